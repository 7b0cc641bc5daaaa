!> What the isoparametric plane elements (element_quad, element_tri) share: the Cartesian
!> derivatives of the shape functions, the strain-displacement matrix of (exx, eyy, ezz, gxy)
!> with engineering shear, and the 2-D mass matrix from the scalar one, consistent or HRZ-lumped
!> (the diagonal scaled to the element's mass: every term positive, where row sums would give
!> negative or zero corner masses to the quadratic elements).
module element_iso
  use kinds, only: dp
  implicit none
  private
  public :: iso_cartesian, iso_b, iso_mass, iso_add_mass, iso_ring, TWO_PI

  real(dp), parameter :: TWO_PI = 6.283185307179586476925286766559_dp   !< the axisymmetric ring

contains

  !> Cartesian derivatives dnx(1:2, 1:nen) and det J from the natural ones dn at a point.
  pure subroutine iso_cartesian(nen, x, dn, dnx, detj)
    integer, intent(in) :: nen
    real(dp), intent(in) :: x(:, :), dn(:, :)
    real(dp), intent(out) :: dnx(:, :), detj
    real(dp) :: jac(2, 2)
    ! jac(a, k) = d x_k / d xi_a
    jac = matmul(dn(:, 1:nen), transpose(x(:, 1:nen)))
    detj = jac(1, 1) * jac(2, 2) - jac(1, 2) * jac(2, 1)
    dnx = 0.0_dp
    if (detj == 0.0_dp) return
    dnx(1, 1:nen) = (jac(2, 2) * dn(1, 1:nen) - jac(1, 2) * dn(2, 1:nen)) / detj
    dnx(2, 1:nen) = (-jac(2, 1) * dn(1, 1:nen) + jac(1, 1) * dn(2, 1:nen)) / detj
  end subroutine iso_cartesian

  !> B (4 x 2 nen, UX UY per node) from the Cartesian derivatives: rows exx, eyy, ezz (zero), gxy.
  pure subroutine iso_b(nen, dnx, b)
    integer, intent(in) :: nen
    real(dp), intent(in) :: dnx(:, :)
    real(dp), intent(out) :: b(:, :)
    integer :: i
    b = 0.0_dp
    do i = 1, nen
      b(1, 2 * i - 1) = dnx(1, i)
      b(2, 2 * i) = dnx(2, i)
      b(4, 2 * i - 1) = dnx(2, i)
      b(4, 2 * i) = dnx(1, i)
    end do
  end subroutine iso_b

  !> An axisymmetric point (x = r, y the axis; section's axisymmetric): the hoop strain row
  !> e_tt = u_r / r, B(3, 2a-1) = N_a / r at r = Σ N_a x_a, and the point's ring factor 2π r,
  !> which takes the place of the thickness in its weight (the whole circumference: masses,
  !> forces and energies are those of the full ring). A point on the axis (r = 0) never occurs:
  !> the Gauss points are inside the element and the nodes are at r >= 0 (scene_models).
  pure subroutine iso_ring(nen, n, x, b, ring)
    integer, intent(in) :: nen
    real(dp), intent(in) :: n(:), x(:, :)
    real(dp), intent(inout) :: b(:, :)
    real(dp), intent(out) :: ring
    real(dp) :: r
    integer :: i
    r = dot_product(n(1:nen), x(1, 1:nen))
    do i = 1, nen
      b(3, 2 * i - 1) = n(i) / r
    end do
    ring = TWO_PI * r
  end subroutine iso_ring

  !> One point of the mass rule: ms += dm n n', total += dm (dm = rho t w det J).
  pure subroutine iso_add_mass(nen, n, dm, ms, total)
    integer, intent(in) :: nen
    real(dp), intent(in) :: n(:), dm
    real(dp), intent(inout) :: ms(:, :), total
    integer :: j
    do j = 1, nen
      ms(1:nen, j) = ms(1:nen, j) + dm * n(1:nen) * n(j)
    end do
    total = total + dm
  end subroutine iso_add_mass

  !> The mass matrix me (nd nen x nd nen, the nd = 2 (default) or 3 directions uncoupled) from the
  !> scalar consistent one ms(1:nen, 1:nen) of total mass total: itself (consistent), or its diagonal
  !> scaled to total (HRZ: every term positive).
  pure subroutine iso_mass(nen, ms, total, lumped, me, ndir)
    integer, intent(in) :: nen
    real(dp), intent(in) :: ms(:, :), total
    logical, intent(in) :: lumped
    real(dp), intent(out) :: me(:, :)
    integer, intent(in), optional :: ndir
    real(dp) :: diag
    integer :: i, j, d, nd
    nd = 2
    if (present(ndir)) nd = ndir
    me = 0.0_dp
    if (lumped) then
      diag = 0.0_dp
      do i = 1, nen
        diag = diag + ms(i, i)
      end do
      do i = 1, nen
        do d = 1, nd
          me(nd * i - nd + d, nd * i - nd + d) = ms(i, i) * total / diag
        end do
      end do
    else
      do j = 1, nen
        do i = 1, nen
          do d = 1, nd
            me(nd * i - nd + d, nd * j - nd + d) = ms(i, j)
          end do
        end do
      end do
    end if
  end subroutine iso_mass
end module element_iso
