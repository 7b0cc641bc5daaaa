!> BEAM2 element: two-node Euler-Bernoulli beam, UX, UY, RZ per node, small displacements.
!> Local axes: x' from node 1 to node 2 (c = cos, s = sin of its angle), y' = z ^ x'.
!> Local DOFs (u, v, theta) = R (ux, uy, rz), R = [c s 0; -s c 0; 0 0 1], per node.
!> Generalized strains, at Gauss-Legendre points along the element:
!>   axial strain eps = du/dx' (linear u), curvature kappa = d2v/dx'2 (Hermite cubic v),
!> conjugate to the resultants (N, M); elastic D = diag(E A, E I). kappa is linear, so the
!> default 2 points integrate the elastic stiffness exactly. A layer at height y' sees the
!> strain eps - y' kappa. B is returned in global DOFs (B_local R).
module element_beam2
  use kinds, only: dp
  use section, only: section_t
  implicit none
  private
  public :: beam2_ngauss, beam2_b, beam2_mass, gauss_legendre, BEAM2_MAX_GAUSS

  integer, parameter :: BEAM2_MAX_GAUSS = 5  !< largest accepted sec%gauss
  integer, parameter :: BEAM2_DEFAULT_GAUSS = 2

contains

  !> Number of Gauss points: sec%gauss when set (clamped to 1..5; elem_check_geometry rejects
  !> values above 5), else 2.
  pure integer function beam2_ngauss(sec)
    type(section_t), intent(in) :: sec
    beam2_ngauss = BEAM2_DEFAULT_GAUSS
    if (sec%gauss >= 1) beam2_ngauss = min(sec%gauss, BEAM2_MAX_GAUSS)
  end function beam2_ngauss

  !> Gauss-Legendre rule on [-1, 1] with n = 1..5 points (abscissae increasing).
  pure subroutine gauss_legendre(n, xi, w)
    integer, intent(in) :: n
    real(dp), intent(out) :: xi(:), w(:)
    real(dp) :: a, b
    select case (n)
    case (1)
      xi(1) = 0.0_dp
      w(1) = 2.0_dp
    case (2)
      a = 1.0_dp / sqrt(3.0_dp)
      xi(1:2) = [-a, a]
      w(1:2) = 1.0_dp
    case (3)
      a = sqrt(0.6_dp)
      xi(1:3) = [-a, 0.0_dp, a]
      w(1:3) = [5.0_dp, 8.0_dp, 5.0_dp] / 9.0_dp
    case (4)
      a = sqrt(3.0_dp / 7.0_dp - 2.0_dp / 7.0_dp * sqrt(1.2_dp))
      b = sqrt(3.0_dp / 7.0_dp + 2.0_dp / 7.0_dp * sqrt(1.2_dp))
      xi(1:4) = [-b, -a, a, b]
      w(1:4) = [18.0_dp - sqrt(30.0_dp), 18.0_dp + sqrt(30.0_dp), 18.0_dp + sqrt(30.0_dp), &
        18.0_dp - sqrt(30.0_dp)] / 36.0_dp
    case (5)
      a = sqrt(5.0_dp - 2.0_dp * sqrt(10.0_dp / 7.0_dp)) / 3.0_dp
      b = sqrt(5.0_dp + 2.0_dp * sqrt(10.0_dp / 7.0_dp)) / 3.0_dp
      xi(1:5) = [-b, -a, 0.0_dp, a, b]
      w(1:5) = [322.0_dp - 13.0_dp * sqrt(70.0_dp), 322.0_dp + 13.0_dp * sqrt(70.0_dp), 512.0_dp, &
        322.0_dp + 13.0_dp * sqrt(70.0_dp), 322.0_dp - 13.0_dp * sqrt(70.0_dp)] / 900.0_dp
    case default
      xi = 0.0_dp
      w = 0.0_dp
    end select
  end subroutine gauss_legendre

  !> Length and direction cosines of the element axis.
  pure subroutine beam2_axis(x, len, c, s)
    real(dp), intent(in) :: x(2, 2)
    real(dp), intent(out) :: len, c, s
    len = norm2(x(:, 2) - x(:, 1))
    if (len > 0.0_dp) then
      c = (x(1, 2) - x(1, 1)) / len
      s = (x(2, 2) - x(2, 1)) / len
    else
      c = 1.0_dp
      s = 0.0_dp
    end if
  end subroutine beam2_axis

  !> B (2 x 6, rows eps and kappa, global DOFs) and weight w_g L/2 at Gauss point ig.
  pure subroutine beam2_b(x, sec, ig, b, wt)
    real(dp), intent(in) :: x(2, 2)
    type(section_t), intent(in) :: sec
    integer, intent(in) :: ig
    real(dp), intent(out) :: b(2, 6), wt
    real(dp) :: xi(BEAM2_MAX_GAUSS), w(BEAM2_MAX_GAUSS), bl(2, 6), len, c, s, r
    integer :: a, k
    call gauss_legendre(beam2_ngauss(sec), xi, w)
    call beam2_axis(x, len, c, s)
    b = 0.0_dp
    wt = 0.0_dp
    if (len <= 0.0_dp) return
    r = 0.5_dp * (1.0_dp + xi(ig))  ! x'/L in [0, 1]
    bl = 0.0_dp
    bl(1, 1) = -1.0_dp / len
    bl(1, 4) = 1.0_dp / len
    ! Second derivatives of the Hermite cubics (v1, theta1, v2, theta2).
    bl(2, 2) = (-6.0_dp + 12.0_dp * r) / len**2
    bl(2, 3) = (-4.0_dp + 6.0_dp * r) / len
    bl(2, 5) = (6.0_dp - 12.0_dp * r) / len**2
    bl(2, 6) = (-2.0_dp + 6.0_dp * r) / len
    do a = 0, 3, 3  ! u = c ux + s uy, v = -s ux + c uy
      do k = 1, 2
        b(k, a + 1) = c * bl(k, a + 1) - s * bl(k, a + 2)
        b(k, a + 2) = s * bl(k, a + 1) + c * bl(k, a + 2)
        b(k, a + 3) = bl(k, a + 3)
      end do
    end do
    wt = w(ig) * 0.5_dp * len
  end subroutine beam2_b

  !> Mass matrix (6 x 6, global). Consistent: axial rho A L/6 [2 1; 1 2] on (u1, u2) plus the
  !> Hermite bending matrix rho A L/420 [...] on (v1, th1, v2, th2), rotated to global.
  !> Lumped (HRZ): rho A L/2 per translation, rho A L^3/78 per rotation.
  !> Isotropic (KINEMATICS LARGE, consistent): rho A L/6 [2 1; 1 2] on both translations and the
  !> lumped rotations: the Hermite matrix couples the translations to the element's axis, which
  !> turns in large rotations; this one is the same in every frame (and exact for a rigid motion).
  pure subroutine beam2_mass(x, area, rho, lumped, me, isotropic)
    real(dp), intent(in) :: x(2, 2), area, rho
    logical, intent(in) :: lumped
    real(dp), intent(out) :: me(6, 6)
    logical, intent(in), optional :: isotropic
    real(dp) :: ml(6, 6), t(6, 6), len, c, s, m
    integer :: i
    call beam2_axis(x, len, c, s)
    m = rho * area * len
    me = 0.0_dp
    if (lumped) then
      do i = 0, 3, 3
        me(i + 1, i + 1) = 0.5_dp * m
        me(i + 2, i + 2) = 0.5_dp * m
        me(i + 3, i + 3) = m * len**2 / 78.0_dp
      end do
      return
    end if
    if (present(isotropic)) then
      if (isotropic) then
        do i = 1, 2
          me([i, i + 3], [i, i + 3]) = m / 6.0_dp * reshape([2.0_dp, 1.0_dp, 1.0_dp, 2.0_dp], [2, 2])
        end do
        me(3, 3) = m * len**2 / 78.0_dp
        me(6, 6) = m * len**2 / 78.0_dp
        return
      end if
    end if
    ml = 0.0_dp
    ml(1, 1) = 2.0_dp * m / 6.0_dp
    ml(4, 4) = 2.0_dp * m / 6.0_dp
    ml(1, 4) = m / 6.0_dp
    ml(4, 1) = m / 6.0_dp
    ml([2, 3, 5, 6], [2, 3, 5, 6]) = m / 420.0_dp * reshape([ &
      156.0_dp, 22.0_dp * len, 54.0_dp, -13.0_dp * len, &
      22.0_dp * len, 4.0_dp * len**2, 13.0_dp * len, -3.0_dp * len**2, &
      54.0_dp, 13.0_dp * len, 156.0_dp, -22.0_dp * len, &
      -13.0_dp * len, -3.0_dp * len**2, -22.0_dp * len, 4.0_dp * len**2], [4, 4])
    t = 0.0_dp
    do i = 0, 3, 3
      t(i + 1, i + 1:i + 2) = [c, s]
      t(i + 2, i + 1:i + 2) = [-s, c]
      t(i + 3, i + 3) = 1.0_dp
    end do
    me = matmul(transpose(t), matmul(ml, t))
  end subroutine beam2_mass
end module element_beam2
