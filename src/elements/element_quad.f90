!> QUAD4 and QUAD8 isoparametric plane elements, UX, UY per node.
!> Node order (Cast3M QUA4/QUA8, Gmsh): 4 corners counter-clockwise, then for QUAD8 the
!> mid-side nodes of sides 1-2, 2-3, 3-4, 4-1. QUAD8 is the 8-node serendipity element.
!> Strain vector (exx, eyy, ezz, gxy) with engineering shear gxy = du/dy + dv/dx. The ezz row of
!> B is zero: plane strain keeps ezz = 0 and the law recovers szz, plane stress lets the law
!> drop szz; axisymmetric (x = r), it is the hoop strain u_r/r and 2 pi r takes the thickness's
!> place. Full Gauss integration: 2 x 2 (QUAD4), 3 x 3 (QUAD8); point ig = i + n (j - 1),
!> i along xi, j along eta. Weight wt = w_i w_j det J * thickness.
module element_quad
  use kinds, only: dp, zero_tol
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use element_iso, only: iso_cartesian, iso_b, iso_mass, iso_add_mass, iso_ring, TWO_PI
  implicit none
  private
  public :: quad_ngauss, quad_shape, quad_b, quad_mass, quad_check, quad_elastic_d, quad_point_shape

  ! Natural coordinates of the nodes.
  real(dp), parameter :: XI_NODE(8) = [-1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, -1.0_dp]
  real(dp), parameter :: ETA_NODE(8) = [-1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp, 0.0_dp, 1.0_dp, 0.0_dp]

contains

  !> Number of Gauss points of a quad with nen nodes.
  pure integer function quad_ngauss(nen)
    integer, intent(in) :: nen
    if (nen == 8) then
      quad_ngauss = 9
    else
      quad_ngauss = 4
    end if
  end function quad_ngauss

  !> Natural coordinates and weight of Gauss point ig.
  pure subroutine quad_gauss_point(nen, ig, xi, eta, w)
    integer, intent(in) :: nen, ig
    real(dp), intent(out) :: xi, eta, w
    real(dp) :: p(3), q(3)
    integer :: n, i, j
    if (nen == 8) then
      n = 3
      p = [-sqrt(0.6_dp), 0.0_dp, sqrt(0.6_dp)]
      q = [5.0_dp, 8.0_dp, 5.0_dp] / 9.0_dp
    else
      n = 2
      p = [-1.0_dp / sqrt(3.0_dp), 1.0_dp / sqrt(3.0_dp), 0.0_dp]
      q = [1.0_dp, 1.0_dp, 0.0_dp]
    end if
    i = mod(ig - 1, n) + 1
    j = (ig - 1) / n + 1
    xi = p(i)
    eta = p(j)
    w = q(i) * q(j)
  end subroutine quad_gauss_point

  !> Shape functions n(1:nen) and their natural derivatives dn(1:2, 1:nen) at (xi, eta).
  pure subroutine quad_shape(nen, xi, eta, n, dn)
    integer, intent(in) :: nen
    real(dp), intent(in) :: xi, eta
    real(dp), intent(out) :: n(8), dn(2, 8)
    real(dp) :: a, b
    integer :: i
    n = 0.0_dp
    dn = 0.0_dp
    if (nen == 4) then
      do i = 1, 4
        a = XI_NODE(i)
        b = ETA_NODE(i)
        n(i) = 0.25_dp * (1.0_dp + a * xi) * (1.0_dp + b * eta)
        dn(1, i) = 0.25_dp * a * (1.0_dp + b * eta)
        dn(2, i) = 0.25_dp * b * (1.0_dp + a * xi)
      end do
      return
    end if
    do i = 1, 4
      a = XI_NODE(i)
      b = ETA_NODE(i)
      n(i) = 0.25_dp * (1.0_dp + a * xi) * (1.0_dp + b * eta) * (a * xi + b * eta - 1.0_dp)
      dn(1, i) = 0.25_dp * a * (1.0_dp + b * eta) * (2.0_dp * a * xi + b * eta)
      dn(2, i) = 0.25_dp * b * (1.0_dp + a * xi) * (a * xi + 2.0_dp * b * eta)
    end do
    do i = 5, 7, 2  ! mid-sides on eta = -1, +1
      b = ETA_NODE(i)
      n(i) = 0.5_dp * (1.0_dp - xi**2) * (1.0_dp + b * eta)
      dn(1, i) = -xi * (1.0_dp + b * eta)
      dn(2, i) = 0.5_dp * (1.0_dp - xi**2) * b
    end do
    do i = 6, 8, 2  ! mid-sides on xi = +1, -1
      a = XI_NODE(i)
      n(i) = 0.5_dp * (1.0_dp + a * xi) * (1.0_dp - eta**2)
      dn(1, i) = 0.5_dp * a * (1.0_dp - eta**2)
      dn(2, i) = -eta * (1.0_dp + a * xi)
    end do
  end subroutine quad_shape

  !> The shape functions n(1:nen) at Gauss point ig (stress recovery).
  pure subroutine quad_point_shape(nen, ig, n)
    integer, intent(in) :: nen, ig
    real(dp), intent(out) :: n(8)
    real(dp) :: xi, eta, w, dn(2, 8)
    call quad_gauss_point(nen, ig, xi, eta, w)
    call quad_shape(nen, xi, eta, n, dn)
  end subroutine quad_point_shape

  !> B (4 x 2 nen) and weight at Gauss point ig; x(2, 1:nen) used.
  pure subroutine quad_b(nen, x, thickness, axisym, ig, b, wt)
    integer, intent(in) :: nen, ig
    real(dp), intent(in) :: x(2, 8), thickness
    logical, intent(in) :: axisym
    real(dp), intent(out) :: b(4, 16), wt
    real(dp) :: xi, eta, w, n(8), dn(2, 8), dnx(2, 8), detj, ring
    call quad_gauss_point(nen, ig, xi, eta, w)
    call quad_shape(nen, xi, eta, n, dn)
    call iso_cartesian(nen, x, dn, dnx, detj)
    call iso_b(nen, dnx, b)
    wt = w * detj * thickness
    if (axisym) then
      call iso_ring(nen, n, x, b, ring)
      wt = w * detj * ring
    end if
  end subroutine quad_b

  !> Mass matrix (2 nen x 2 nen), same Gauss rule as the stiffness (exact for straight sides).
  !> Lumped: HRZ, the diagonal of the consistent matrix scaled to the element mass; every term
  !> is positive (row sums would give negative QUAD8 corner masses).
  pure subroutine quad_mass(nen, x, thickness, axisym, rho, lumped, me)
    integer, intent(in) :: nen
    real(dp), intent(in) :: x(2, 8), thickness, rho
    logical, intent(in) :: axisym, lumped
    real(dp), intent(out) :: me(16, 16)
    real(dp) :: ms(8, 8), xi, eta, w, n(8), dn(2, 8), dnx(2, 8), detj, total, t
    integer :: ig
    ms = 0.0_dp
    total = 0.0_dp
    do ig = 1, quad_ngauss(nen)
      call quad_gauss_point(nen, ig, xi, eta, w)
      call quad_shape(nen, xi, eta, n, dn)
      call iso_cartesian(nen, x, dn, dnx, detj)
      t = thickness
      if (axisym) t = TWO_PI * dot_product(n(1:nen), x(1, 1:nen))     ! the whole ring
      call iso_add_mass(nen, n, rho * t * w * detj, ms, total)
    end do
    call iso_mass(nen, ms, total, lumped, me)
  end subroutine quad_mass

  !> Reject a degenerate or inverted quad: det J <= zero_tol * ref^2 at a Gauss point or at a
  !> corner (clockwise nodes, crossed sides, collapsed side, misplaced mid-side node).
  pure subroutine quad_check(nen, x, ref, stat, errmsg)
    integer, intent(in) :: nen
    real(dp), intent(in) :: x(2, 8), ref
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: xi, eta, w, n(8), dn(2, 8), dnx(2, 8), detj, tol
    character(len=:), allocatable :: name
    integer :: ig, k
    stat = STAT_OK
    tol = zero_tol * ref**2
    name = 'QUAD4'
    if (nen == 8) name = 'QUAD8'
    do k = 1, 4
      call quad_shape(nen, XI_NODE(k), ETA_NODE(k), n, dn)
      call iso_cartesian(nen, x, dn, dnx, detj)
      if (detj <= tol) then
        call set_error(stat, errmsg, STAT_INPUT, 'degenerate or inverted ' // name // ': det J = ' // &
          str(detj) // ' <= 0 at corner node ' // str(k) // &
          ' (corners must be counter-clockwise, sides must not cross or collapse)')
        return
      end if
    end do
    do ig = 1, quad_ngauss(nen)
      call quad_gauss_point(nen, ig, xi, eta, w)
      call quad_shape(nen, xi, eta, n, dn)
      call iso_cartesian(nen, x, dn, dnx, detj)
      if (detj <= tol) then
        call set_error(stat, errmsg, STAT_INPUT, 'degenerate or inverted ' // name // ': det J = ' // &
          str(detj) // ' <= 0 at Gauss point ' // str(ig) // &
          ' (corners must be counter-clockwise, sides must not cross or collapse)')
        return
      end if
    end do
  end subroutine quad_check

  !> Elastic D (4 x 4) on (xx, yy, zz, xy), engineering shear.
  !> Plane strain: the isotropic 3D law restricted to these components; with ezz = 0 it gives
  !> szz = lambda (exx + eyy) = nu (sxx + syy). Plane stress: szz = 0 with the reduced
  !> E/(1 - nu^2) law in-plane; row and column zz are zero.
  pure subroutine quad_elastic_d(young, poisson, plane_stress, d)
    real(dp), intent(in) :: young, poisson
    logical, intent(in) :: plane_stress
    real(dp), intent(out) :: d(4, 4)
    real(dp) :: lam, mu, f
    d = 0.0_dp
    mu = young / (2.0_dp * (1.0_dp + poisson))
    if (plane_stress) then
      f = young / (1.0_dp - poisson**2)
      d(1, 1) = f
      d(2, 2) = f
      d(1, 2) = f * poisson
      d(2, 1) = f * poisson
    else
      lam = young * poisson / ((1.0_dp + poisson) * (1.0_dp - 2.0_dp * poisson))
      d(1:3, 1:3) = lam
      d(1, 1) = lam + 2.0_dp * mu
      d(2, 2) = lam + 2.0_dp * mu
      d(3, 3) = lam + 2.0_dp * mu
    end if
    d(4, 4) = mu
  end subroutine quad_elastic_d
end module element_quad
