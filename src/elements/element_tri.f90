!> TRI3 and TRI6 isoparametric plane elements, UX, UY per node (Cast3M TRI3/TRI6, Gmsh 3- and
!> 6-node triangles). Node order: 3 corners counter-clockwise, then for TRI6 the mid-side nodes
!> of sides 1-2, 2-3, 3-1. Natural coordinates (xi, eta) on the triangle (0,0) (1,0) (0,1), area
!> coordinates L1 = 1 - xi - eta, L2 = xi, L3 = eta. Strains and D as the quads (element_quad):
!> (exx, eyy, ezz, gxy), plane strain or plane stress. Stiffness: 1 point (TRI3, constant
!> strain), 3 points of degree 2 (TRI6: exact for straight sides); mass: 3 points (TRI3) and 6
!> points of degree 4 (TRI6, Dunavant), exact for straight sides. Weight wt = w det J thickness.
!> Lumped mass: HRZ, the diagonal of the consistent matrix scaled to the element mass: TRI3 1/3
!> per node, TRI6 3/57 per corner and 16/57 per mid-side node (all positive; row sums would give
!> the TRI6 corners zero mass).
module element_tri
  use kinds, only: dp, zero_tol
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use element_iso, only: iso_cartesian, iso_b, iso_mass, iso_add_mass, iso_ring, TWO_PI
  implicit none
  private
  public :: tri_ngauss, tri_shape, tri_b, tri_mass, tri_check, tri_point_shape

  real(dp), parameter :: XI_NODE(6) = [0.0_dp, 1.0_dp, 0.0_dp, 0.5_dp, 0.5_dp, 0.0_dp]
  real(dp), parameter :: ETA_NODE(6) = [0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.5_dp, 0.5_dp]
  ! Dunavant's degree-4 rule (6 points): weights on the reference triangle (area 1/2).
  real(dp), parameter :: D4A = 0.445948490915965_dp, D4B = 0.091576213509771_dp
  real(dp), parameter :: D4WA = 0.5_dp * 0.223381589678011_dp, D4WB = 0.5_dp * 0.109951743655322_dp

contains

  !> Integration points of the stiffness (the stress points): 1 (TRI3) or 3 (TRI6).
  pure integer function tri_ngauss(nen)
    integer, intent(in) :: nen
    tri_ngauss = merge(3, 1, nen == 6)
  end function tri_ngauss

  !> Point ig of the rule with npt points (1, 3 or 6): natural coordinates and weight.
  pure subroutine tri_point(npt, ig, xi, eta, w)
    integer, intent(in) :: npt, ig
    real(dp), intent(out) :: xi, eta, w
    real(dp) :: a, c
    select case (npt)
    case (1)
      xi = 1.0_dp / 3.0_dp
      eta = xi
      w = 0.5_dp
    case (3)
      xi = 1.0_dp / 6.0_dp
      eta = xi
      if (ig == 2) xi = 2.0_dp / 3.0_dp
      if (ig == 3) eta = 2.0_dp / 3.0_dp
      w = 1.0_dp / 6.0_dp
    case default
      a = merge(D4A, D4B, ig <= 3)
      w = merge(D4WA, D4WB, ig <= 3)
      c = 1.0_dp - 2.0_dp * a
      select case (mod(ig - 1, 3))
      case (0)
        xi = a
        eta = a
      case (1)
        xi = c
        eta = a
      case default
        xi = a
        eta = c
      end select
    end select
  end subroutine tri_point

  !> Shape functions n(1:nen) and their natural derivatives dn(1:2, 1:nen) at (xi, eta).
  pure subroutine tri_shape(nen, xi, eta, n, dn)
    integer, intent(in) :: nen
    real(dp), intent(in) :: xi, eta
    real(dp), intent(out) :: n(6), dn(2, 6)
    real(dp) :: l1, l2, l3
    l1 = 1.0_dp - xi - eta
    l2 = xi
    l3 = eta
    n = 0.0_dp
    dn = 0.0_dp
    if (nen == 3) then
      n(1:3) = [l1, l2, l3]
      dn(:, 1) = [-1.0_dp, -1.0_dp]
      dn(:, 2) = [1.0_dp, 0.0_dp]
      dn(:, 3) = [0.0_dp, 1.0_dp]
      return
    end if
    n = [l1 * (2.0_dp * l1 - 1.0_dp), l2 * (2.0_dp * l2 - 1.0_dp), l3 * (2.0_dp * l3 - 1.0_dp), &
         4.0_dp * l1 * l2, 4.0_dp * l2 * l3, 4.0_dp * l3 * l1]
    dn(:, 1) = [-(4.0_dp * l1 - 1.0_dp), -(4.0_dp * l1 - 1.0_dp)]
    dn(:, 2) = [4.0_dp * l2 - 1.0_dp, 0.0_dp]
    dn(:, 3) = [0.0_dp, 4.0_dp * l3 - 1.0_dp]
    dn(:, 4) = [4.0_dp * (l1 - l2), -4.0_dp * l2]
    dn(:, 5) = [4.0_dp * l3, 4.0_dp * l2]
    dn(:, 6) = [-4.0_dp * l3, 4.0_dp * (l1 - l3)]
  end subroutine tri_shape

  !> B (4 x 2 nen) and weight at stress point ig; x(2, 1:nen) used.
  !> The shape functions n(1:nen) at Gauss point ig (stress recovery).
  pure subroutine tri_point_shape(nen, ig, n)
    integer, intent(in) :: nen, ig
    real(dp), intent(out) :: n(6)
    real(dp) :: xi, eta, w, dn(2, 6)
    call tri_point(tri_ngauss(nen), ig, xi, eta, w)
    call tri_shape(nen, xi, eta, n, dn)
  end subroutine tri_point_shape

  pure subroutine tri_b(nen, x, thickness, axisym, ig, b, wt)
    integer, intent(in) :: nen, ig
    real(dp), intent(in) :: x(2, 6), thickness
    logical, intent(in) :: axisym
    real(dp), intent(out) :: b(4, 12), wt
    real(dp) :: xi, eta, w, n(6), dn(2, 6), dnx(2, 6), detj, ring
    call tri_point(tri_ngauss(nen), ig, xi, eta, w)
    call tri_shape(nen, xi, eta, n, dn)
    call iso_cartesian(nen, x, dn, dnx, detj)
    call iso_b(nen, dnx, b)
    wt = w * detj * thickness
    if (axisym) then
      call iso_ring(nen, n, x, b, ring)
      wt = w * detj * ring
    end if
  end subroutine tri_b

  !> Mass matrix (2 nen x 2 nen), consistent (exact for straight sides) or HRZ-lumped.
  pure subroutine tri_mass(nen, x, thickness, axisym, rho, lumped, me)
    integer, intent(in) :: nen
    real(dp), intent(in) :: x(2, 6), thickness, rho
    logical, intent(in) :: axisym, lumped
    real(dp), intent(out) :: me(12, 12)
    real(dp) :: ms(6, 6), xi, eta, w, n(6), dn(2, 6), dnx(2, 6), detj, total, t
    integer :: ig, npt
    ms = 0.0_dp
    total = 0.0_dp
    npt = merge(6, 3, nen == 6)
    do ig = 1, npt
      call tri_point(npt, ig, xi, eta, w)
      call tri_shape(nen, xi, eta, n, dn)
      call iso_cartesian(nen, x, dn, dnx, detj)
      t = thickness
      if (axisym) t = TWO_PI * dot_product(n(1:nen), x(1, 1:nen))     ! the whole ring
      call iso_add_mass(nen, n, rho * t * w * detj, ms, total)
    end do
    call iso_mass(nen, ms, total, lumped, me)
  end subroutine tri_mass

  !> Reject a degenerate or inverted triangle: det J <= zero_tol * ref^2 at a node or at a
  !> point of the mass rule (clockwise corners, collapsed side, misplaced mid-side node).
  pure subroutine tri_check(nen, x, ref, stat, errmsg)
    integer, intent(in) :: nen
    real(dp), intent(in) :: x(2, 6), ref
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: xi, eta, w, n(6), dn(2, 6), dnx(2, 6), detj, tol
    character(len=:), allocatable :: name
    integer :: k
    stat = STAT_OK
    tol = zero_tol * ref**2
    name = merge('TRI6', 'TRI3', nen == 6)
    do k = 1, nen + 6
      if (k <= nen) then
        xi = XI_NODE(k)
        eta = ETA_NODE(k)
      else
        call tri_point(6, k - nen, xi, eta, w)
      end if
      call tri_shape(nen, xi, eta, n, dn)
      call iso_cartesian(nen, x, dn, dnx, detj)
      if (detj <= tol) then
        call set_error(stat, errmsg, STAT_INPUT, 'degenerate or inverted ' // name // ': det J = ' // &
          str(detj) // ' <= 0 ' // trim(merge('at node        ', 'at mass point  ', k <= nen)) // ' ' // &
          str(merge(k, k - nen, k <= nen)) // ' (corners must be counter-clockwise, sides must not collapse)')
        return
      end if
    end do
  end subroutine tri_check
end module element_tri
