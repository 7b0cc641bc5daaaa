!> HEX8 and TET4 isoparametric solid elements (DIMENSION 3), UX, UY, UZ per node.
!> Node order (Gmsh, VTK, Cast3M CUB8/TET4): HEX8 the four corners of the face zeta = -1
!> counter-clockwise seen from +zeta, then those of zeta = +1 above them; TET4 corners 1, 2, 3
!> counter-clockwise seen from corner 4 (a positive volume (x2-x1)·((x3-x1)×(x4-x1)) > 0).
!> Strain vector (exx, eyy, ezz, gxy, gyz, gxz), engineering shears; stresses (sxx, syy, szz,
!> sxy, syz, sxz). Integration: HEX8 2 x 2 x 2 Gauss (point ig = i + 2 (j - 1) + 4 (k - 1)),
!> TET4 one point at the centroid (the strain is constant). Weight wt = w det J. Mass: consistent
!> (HEX8 on its 2 x 2 x 2 points, exact for a parallelepiped; TET4 exact: rho V (1 + δij)/20) or
!> HRZ-lumped (the diagonal scaled to the element's mass; a TET4 gets rho V/4 at each corner).
module element_solid
  use kinds, only: dp, zero_tol
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  implicit none
  private
  public :: solid_ngauss, solid_b, solid_mass, solid_check, solid_elastic_d, solid_point_shape

  ! Natural coordinates of the HEX8 corners.
  real(dp), parameter :: HX(8) = [-1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp]
  real(dp), parameter :: HY(8) = [-1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp]
  real(dp), parameter :: HZ(8) = [-1.0_dp, -1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp]

contains

  !> Number of integration points of a solid with nen nodes (8: HEX8, 4: TET4).
  pure integer function solid_ngauss(nen)
    integer, intent(in) :: nen
    solid_ngauss = merge(8, 1, nen == 8)
  end function solid_ngauss

  !> Natural coordinates and weight of point ig.
  pure subroutine solid_point(nen, ig, xi, w)
    integer, intent(in) :: nen, ig
    real(dp), intent(out) :: xi(3), w
    real(dp), parameter :: g = 0.57735026918962576450914878050196_dp   ! 1/sqrt(3)
    if (nen == 8) then
      xi(1) = merge(g, -g, mod(ig - 1, 2) == 1)
      xi(2) = merge(g, -g, mod((ig - 1) / 2, 2) == 1)
      xi(3) = merge(g, -g, (ig - 1) / 4 == 1)
      w = 1.0_dp
    else
      xi = 0.25_dp
      w = 1.0_dp / 6.0_dp
    end if
  end subroutine solid_point

  !> Shape functions n(1:nen) and natural derivatives dn(1:3, 1:nen) at xi.
  pure subroutine solid_shape(nen, xi, n, dn)
    integer, intent(in) :: nen
    real(dp), intent(in) :: xi(3)
    real(dp), intent(out) :: n(8), dn(3, 8)
    integer :: i
    n = 0.0_dp
    dn = 0.0_dp
    if (nen == 8) then
      do i = 1, 8
        n(i) = 0.125_dp * (1.0_dp + HX(i) * xi(1)) * (1.0_dp + HY(i) * xi(2)) * (1.0_dp + HZ(i) * xi(3))
        dn(1, i) = 0.125_dp * HX(i) * (1.0_dp + HY(i) * xi(2)) * (1.0_dp + HZ(i) * xi(3))
        dn(2, i) = 0.125_dp * HY(i) * (1.0_dp + HX(i) * xi(1)) * (1.0_dp + HZ(i) * xi(3))
        dn(3, i) = 0.125_dp * HZ(i) * (1.0_dp + HX(i) * xi(1)) * (1.0_dp + HY(i) * xi(2))
      end do
    else
      n(1:4) = [1.0_dp - xi(1) - xi(2) - xi(3), xi(1), xi(2), xi(3)]
      dn(:, 1) = -1.0_dp
      dn(1, 2) = 1.0_dp
      dn(2, 3) = 1.0_dp
      dn(3, 4) = 1.0_dp
    end if
  end subroutine solid_shape

  !> The shape functions n(1:nen) at integration point ig (stress recovery).
  pure subroutine solid_point_shape(nen, ig, n)
    integer, intent(in) :: nen, ig
    real(dp), intent(out) :: n(8)
    real(dp) :: xi(3), w, dn(3, 8)
    call solid_point(nen, ig, xi, w)
    call solid_shape(nen, xi, n, dn)
  end subroutine solid_point_shape

  !> Cartesian derivatives dnx(1:3, 1:nen) and det J at xi (x(1:3, 1:nen) the node coordinates).
  pure subroutine solid_cartesian(nen, x, xi, n, dnx, detj)
    integer, intent(in) :: nen
    real(dp), intent(in) :: x(:, :), xi(3)
    real(dp), intent(out) :: n(8), dnx(3, 8), detj
    real(dp) :: dn(3, 8), jac(3, 3), inv(3, 3)
    call solid_shape(nen, xi, n, dn)
    jac = matmul(dn(:, 1:nen), transpose(x(1:3, 1:nen)))       ! jac(a, k) = d x_k / d xi_a
    inv(1, 1) = jac(2, 2) * jac(3, 3) - jac(2, 3) * jac(3, 2)
    inv(1, 2) = jac(1, 3) * jac(3, 2) - jac(1, 2) * jac(3, 3)
    inv(1, 3) = jac(1, 2) * jac(2, 3) - jac(1, 3) * jac(2, 2)
    inv(2, 1) = jac(2, 3) * jac(3, 1) - jac(2, 1) * jac(3, 3)
    inv(2, 2) = jac(1, 1) * jac(3, 3) - jac(1, 3) * jac(3, 1)
    inv(2, 3) = jac(1, 3) * jac(2, 1) - jac(1, 1) * jac(2, 3)
    inv(3, 1) = jac(2, 1) * jac(3, 2) - jac(2, 2) * jac(3, 1)
    inv(3, 2) = jac(1, 2) * jac(3, 1) - jac(1, 1) * jac(3, 2)
    inv(3, 3) = jac(1, 1) * jac(2, 2) - jac(1, 2) * jac(2, 1)
    detj = jac(1, 1) * inv(1, 1) + jac(1, 2) * inv(2, 1) + jac(1, 3) * inv(3, 1)
    dnx = 0.0_dp
    if (detj == 0.0_dp) return
    ! d N / d x_k = Σ_a (J^-1)(k, a) d N / d xi_a
    dnx(:, 1:nen) = matmul(inv, dn(:, 1:nen)) / detj
  end subroutine solid_cartesian

  !> B (6 x 3 nen, UX UY UZ per node) and weight at point ig.
  pure subroutine solid_b(nen, x, ig, b, wt)
    integer, intent(in) :: nen, ig
    real(dp), intent(in) :: x(:, :)
    real(dp), intent(out) :: b(:, :), wt
    real(dp) :: xi(3), w, n(8), dnx(3, 8), detj
    integer :: i, c
    call solid_point(nen, ig, xi, w)
    call solid_cartesian(nen, x, xi, n, dnx, detj)
    b = 0.0_dp
    do i = 1, nen
      c = 3 * (i - 1)
      b(1, c + 1) = dnx(1, i)
      b(2, c + 2) = dnx(2, i)
      b(3, c + 3) = dnx(3, i)
      b(4, c + 1) = dnx(2, i)
      b(4, c + 2) = dnx(1, i)
      b(5, c + 2) = dnx(3, i)
      b(5, c + 3) = dnx(2, i)
      b(6, c + 1) = dnx(3, i)
      b(6, c + 3) = dnx(1, i)
    end do
    wt = w * detj
  end subroutine solid_b

  !> Mass matrix me (3 nen x 3 nen, the three directions uncoupled), consistent or HRZ-lumped.
  pure subroutine solid_mass(nen, x, rho, lumped, me)
    integer, intent(in) :: nen
    real(dp), intent(in) :: x(:, :), rho
    logical, intent(in) :: lumped
    real(dp), intent(out) :: me(:, :)
    real(dp) :: ms(8, 8), total, diag, xi(3), w, n(8), dnx(3, 8), detj, dm
    integer :: ig, i, j, d
    ms = 0.0_dp
    total = 0.0_dp
    if (nen == 8) then
      do ig = 1, 8
        call solid_point(nen, ig, xi, w)
        call solid_cartesian(nen, x, xi, n, dnx, detj)
        dm = rho * w * detj
        do j = 1, nen
          ms(1:nen, j) = ms(1:nen, j) + dm * n(1:nen) * n(j)
        end do
        total = total + dm
      end do
    else
      call solid_point(nen, 1, xi, w)
      call solid_cartesian(nen, x, xi, n, dnx, detj)
      total = rho * w * detj
      ms(1:4, 1:4) = total / 20.0_dp
      do i = 1, 4
        ms(i, i) = total / 10.0_dp
      end do
    end if
    me = 0.0_dp
    if (lumped) then
      diag = 0.0_dp
      do i = 1, nen
        diag = diag + ms(i, i)
      end do
      do i = 1, nen
        do d = 1, 3
          me(3 * i - 3 + d, 3 * i - 3 + d) = ms(i, i) * total / diag
        end do
      end do
    else
      do j = 1, nen
        do i = 1, nen
          do d = 1, 3
            me(3 * i - 3 + d, 3 * j - 3 + d) = ms(i, j)
          end do
        end do
      end do
    end if
  end subroutine solid_mass

  !> Reject a zero-volume or inverted solid: det J <= zero_tol ref^3 at an integration point or
  !> (HEX8) at a corner, ref the model size.
  pure subroutine solid_check(nen, x, ref, stat, errmsg)
    integer, intent(in) :: nen
    real(dp), intent(in) :: x(:, :), ref
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: xi(3), w, n(8), dnx(3, 8), detj, dmin
    integer :: k
    stat = STAT_OK
    dmin = huge(1.0_dp)
    do k = 1, solid_ngauss(nen)
      call solid_point(nen, k, xi, w)
      call solid_cartesian(nen, x, xi, n, dnx, detj)
      dmin = min(dmin, detj)
    end do
    if (nen == 8) then
      do k = 1, 8
        xi = [HX(k), HY(k), HZ(k)]
        call solid_cartesian(nen, x, xi, n, dnx, detj)
        dmin = min(dmin, detj)
      end do
    end if
    if (.not. dmin > zero_tol * ref**3) then
      call set_error(stat, errmsg, STAT_INPUT, merge('HEX8', 'TET4', nen == 8) // ' of zero volume or inverted ' // &
        '(det J = ' // str(dmin) // '; check its node order)')
    end if
  end subroutine solid_check

  !> Isotropic elasticity on (exx, eyy, ezz, gxy, gyz, gxz).
  pure subroutine solid_elastic_d(young, poisson, d)
    real(dp), intent(in) :: young, poisson
    real(dp), intent(out) :: d(6, 6)
    real(dp) :: lam, mu
    integer :: i
    mu = young / (2.0_dp * (1.0_dp + poisson))
    lam = young * poisson / ((1.0_dp + poisson) * (1.0_dp - 2.0_dp * poisson))
    d = 0.0_dp
    d(1:3, 1:3) = lam
    do i = 1, 3
      d(i, i) = lam + 2.0_dp * mu
      d(i + 3, i + 3) = mu
    end do
  end subroutine solid_elastic_d
end module element_solid
