!> The isoparametric solid elements (DIMENSION 3), UX, UY, UZ per node: HEX8, HEX20 (serendipity),
!> TET4, TET10 and WEDGE6 (a prism), told apart by their node count nen (8, 20, 4, 10, 6).
!> Node order (Gmsh's): HEX8 the four corners of the face zeta = -1 counter-clockwise seen from
!> +zeta, then those of zeta = +1 above them; HEX20 these, then the mid-edge nodes of the edges
!> (1,2), (1,4), (1,5), (2,3), (2,6), (3,4), (3,7), (4,8), (5,6), (5,8), (6,7), (7,8); TET4 corners
!> 1, 2, 3 counter-clockwise seen from corner 4 (a positive volume (x2-x1)·((x3-x1)×(x4-x1)) > 0);
!> TET10 these, then the mid-edge nodes of (1,2), (2,3), (3,1), (4,1), (4,3), (4,2); WEDGE6 the triangle
!> 1 2 3 (natural xi, eta at zeta = -1) counter-clockwise seen from the triangle 4 5 6 above it.
!> Strain vector (exx, eyy, ezz, gxy, gyz, gxz), engineering shears; stresses (sxx, syy, szz,
!> sxy, syz, sxz). Integration (point ig, weight wt = w det J): HEX8 2 x 2 x 2 Gauss, HEX20 3 x 3 x 3
!> (i along xi fastest), TET4 one point at the centroid (the strain is constant), TET10 the
!> four-point rule of degree 2, WEDGE6 the three-point triangle rule of degree 2 times 2 Gauss points
!> along zeta (exact for its mass on a right prism). Mass: consistent (HEX on their points, exact for a parallelepiped;
!> TET4 exact, rho V (1 + δij)/20; TET10 on a collapsed 4 x 4 x 4 Gauss product, exact for a
!> straight-sided one) or HRZ-lumped (the diagonal scaled to the element's mass: every term
!> positive, where row sums would give the quadratic elements' corners negative masses).
module element_solid
  use kinds, only: dp, zero_tol
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use small_matrix, only: adjugate3
  use element_iso, only: iso_mass, iso_add_mass
  implicit none
  private
  public :: solid_ngauss, solid_b, solid_mass, solid_check, solid_point_shape, SOLID_MAX_NEN

  integer, parameter :: SOLID_MAX_NEN = 20
  ! Natural coordinates of the HEX corners, then of HEX20's mid-edge nodes (Gmsh's edges).
  real(dp), parameter :: HX(20) = [-1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp, &
    0.0_dp, -1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp, 0.0_dp, 1.0_dp, -1.0_dp, 0.0_dp, -1.0_dp, 1.0_dp, 0.0_dp]
  real(dp), parameter :: HY(20) = [-1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp, &
    -1.0_dp, 0.0_dp, -1.0_dp, 0.0_dp, -1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp]
  real(dp), parameter :: HZ(20) = [-1.0_dp, -1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, &
    -1.0_dp, -1.0_dp, 0.0_dp, -1.0_dp, 0.0_dp, -1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp]
  !> TET10's mid-edge nodes: the corners of each edge (Gmsh's order).
  integer, parameter :: TEDGE(2, 6) = reshape([1, 2, 2, 3, 3, 1, 4, 1, 4, 3, 4, 2], [2, 6])

contains

  !> Number of integration points of a solid with nen nodes.
  pure integer function solid_ngauss(nen)
    integer, intent(in) :: nen
    select case (nen)
    case (8)
      solid_ngauss = 8
    case (20)
      solid_ngauss = 27
    case (10)
      solid_ngauss = 4
    case (6)
      solid_ngauss = 6
    case default
      solid_ngauss = 1
    end select
  end function solid_ngauss

  !> Natural coordinates and weight of point ig.
  pure subroutine solid_point(nen, ig, xi, w)
    integer, intent(in) :: nen, ig
    real(dp), intent(out) :: xi(3), w
    real(dp), parameter :: g = 0.57735026918962576450914878050196_dp   ! 1/sqrt(3)
    real(dp), parameter :: p3(3) = [-0.77459666924148337703585307995648_dp, 0.0_dp, &
      0.77459666924148337703585307995648_dp]                          ! ±sqrt(3/5), 0
    real(dp), parameter :: w3(3) = [5.0_dp / 9.0_dp, 8.0_dp / 9.0_dp, 5.0_dp / 9.0_dp]
    real(dp), parameter :: ta = 0.58541019662496845446137605030969_dp, tb = 0.13819660112501051517954131656344_dp
    integer :: i, j, k
    select case (nen)
    case (8)
      xi(1) = merge(g, -g, mod(ig - 1, 2) == 1)
      xi(2) = merge(g, -g, mod((ig - 1) / 2, 2) == 1)
      xi(3) = merge(g, -g, (ig - 1) / 4 == 1)
      w = 1.0_dp
    case (20)
      i = mod(ig - 1, 3) + 1
      j = mod((ig - 1) / 3, 3) + 1
      k = (ig - 1) / 9 + 1
      xi = [p3(i), p3(j), p3(k)]
      w = w3(i) * w3(j) * w3(k)
    case (10)                                   ! ta at one barycentric coordinate, tb at the others
      xi = tb
      if (ig > 1) xi(ig - 1) = ta
      w = 1.0_dp / 24.0_dp
    case (6)                                    ! (1/6, 1/6), (2/3, 1/6), (1/6, 2/3) at zeta = -g, then +g
      i = mod(ig - 1, 3)
      xi(1:2) = 1.0_dp / 6.0_dp
      if (i > 0) xi(i) = 2.0_dp / 3.0_dp
      xi(3) = merge(g, -g, ig > 3)
      w = 1.0_dp / 6.0_dp
    case default
      xi = 0.25_dp
      w = 1.0_dp / 6.0_dp
    end select
  end subroutine solid_point

  !> Shape functions n(1:nen) and natural derivatives dn(1:3, 1:nen) at xi.
  pure subroutine solid_shape(nen, xi, n, dn)
    integer, intent(in) :: nen
    real(dp), intent(in) :: xi(3)
    real(dp), intent(out) :: n(SOLID_MAX_NEN), dn(3, SOLID_MAX_NEN)
    n = 0.0_dp
    dn = 0.0_dp
    if (nen == 8 .or. nen == 20) then
      call hex_shape(nen, xi, n, dn)
    else if (nen == 6) then
      call wedge_shape(xi, n, dn)
    else
      call tet_shape(nen, xi, n, dn)
    end if
  end subroutine solid_shape

  !> WEDGE6 (linear prism): the triangle's L1 = 1 - xi - eta, L2 = xi, L3 = eta times (1 -+ zeta)/2.
  pure subroutine wedge_shape(xi, n, dn)
    real(dp), intent(in) :: xi(3)
    real(dp), intent(inout) :: n(:), dn(:, :)
    real(dp), parameter :: dlx(3) = [-1.0_dp, 1.0_dp, 0.0_dp], dly(3) = [-1.0_dp, 0.0_dp, 1.0_dp]
    real(dp) :: l(3), z(2)
    integer :: a, h
    l = [1.0_dp - xi(1) - xi(2), xi(1), xi(2)]
    z = 0.5_dp * [1.0_dp - xi(3), 1.0_dp + xi(3)]
    do h = 1, 2
      do a = 1, 3
        n(3 * h - 3 + a) = l(a) * z(h)
        dn(1, 3 * h - 3 + a) = dlx(a) * z(h)
        dn(2, 3 * h - 3 + a) = dly(a) * z(h)
        dn(3, 3 * h - 3 + a) = merge(-0.5_dp, 0.5_dp, h == 1) * l(a)
      end do
    end do
  end subroutine wedge_shape

  !> HEX8 (trilinear) and HEX20 (serendipity) shape functions.
  pure subroutine hex_shape(nen, xi, n, dn)
    integer, intent(in) :: nen
    real(dp), intent(in) :: xi(3)
    real(dp), intent(inout) :: n(:), dn(:, :)
    real(dp) :: c(3), f(3), s
    integer :: i, k, j
    do i = 1, nen
      c = [HX(i), HY(i), HZ(i)]
      f = 1.0_dp + c * xi                       ! (1 + c_j x_j)
      if (nen == 8) then
        n(i) = 0.125_dp * f(1) * f(2) * f(3)
        dn(1, i) = 0.125_dp * c(1) * f(2) * f(3)
        dn(2, i) = 0.125_dp * c(2) * f(1) * f(3)
        dn(3, i) = 0.125_dp * c(3) * f(1) * f(2)
      else if (i <= 8) then                     ! corner: 1/8 Π(1 + c x) (Σ c x - 2)
        s = sum(c * xi) - 2.0_dp
        n(i) = 0.125_dp * f(1) * f(2) * f(3) * s
        dn(1, i) = 0.125_dp * c(1) * (f(2) * f(3) * s + f(1) * f(2) * f(3))
        dn(2, i) = 0.125_dp * c(2) * (f(1) * f(3) * s + f(1) * f(2) * f(3))
        dn(3, i) = 0.125_dp * c(3) * (f(1) * f(2) * s + f(1) * f(2) * f(3))
      else                                      ! mid-edge, c_k = 0: 1/4 (1 - x_k^2) Π_{j /= k}(1 + c x)
        k = minloc(abs(c), 1)
        f(k) = 1.0_dp - xi(k)**2
        n(i) = 0.25_dp * f(1) * f(2) * f(3)
        do j = 1, 3
          if (j == k) then
            dn(j, i) = 0.25_dp * (-2.0_dp * xi(k)) * product(f, mask=[1, 2, 3] /= k)
          else
            dn(j, i) = 0.25_dp * c(j) * product(f, mask=[1, 2, 3] /= j)
          end if
        end do
      end if
    end do
  end subroutine hex_shape

  !> TET4 (linear) and TET10 (quadratic) shape functions, L1 = 1 - xi - eta - zeta, L2..L4 = xi, eta, zeta.
  pure subroutine tet_shape(nen, xi, n, dn)
    integer, intent(in) :: nen
    real(dp), intent(in) :: xi(3)
    real(dp), intent(inout) :: n(:), dn(:, :)
    real(dp) :: l(4), dl(3, 4)
    integer :: i, a, b
    l = [1.0_dp - xi(1) - xi(2) - xi(3), xi(1), xi(2), xi(3)]
    dl = 0.0_dp
    dl(:, 1) = -1.0_dp
    dl(1, 2) = 1.0_dp
    dl(2, 3) = 1.0_dp
    dl(3, 4) = 1.0_dp
    if (nen == 4) then
      n(1:4) = l
      dn(:, 1:4) = dl
      return
    end if
    do i = 1, 4
      n(i) = l(i) * (2.0_dp * l(i) - 1.0_dp)
      dn(:, i) = (4.0_dp * l(i) - 1.0_dp) * dl(:, i)
    end do
    do i = 1, 6
      a = TEDGE(1, i)
      b = TEDGE(2, i)
      n(4 + i) = 4.0_dp * l(a) * l(b)
      dn(:, 4 + i) = 4.0_dp * (l(a) * dl(:, b) + l(b) * dl(:, a))
    end do
  end subroutine tet_shape

  !> The shape functions n(1:nen) at integration point ig (stress recovery).
  pure subroutine solid_point_shape(nen, ig, n)
    integer, intent(in) :: nen, ig
    real(dp), intent(out) :: n(SOLID_MAX_NEN)
    real(dp) :: xi(3), w, dn(3, SOLID_MAX_NEN)
    call solid_point(nen, ig, xi, w)
    call solid_shape(nen, xi, n, dn)
  end subroutine solid_point_shape

  !> Cartesian derivatives dnx(1:3, 1:nen) and det J at xi (x(1:3, 1:nen) the node coordinates).
  pure subroutine solid_cartesian(nen, x, xi, n, dnx, detj)
    integer, intent(in) :: nen
    real(dp), intent(in) :: x(:, :), xi(3)
    real(dp), intent(out) :: n(SOLID_MAX_NEN), dnx(3, SOLID_MAX_NEN), detj
    real(dp) :: dn(3, SOLID_MAX_NEN), jac(3, 3), inv(3, 3)
    call solid_shape(nen, xi, n, dn)
    jac = matmul(dn(:, 1:nen), transpose(x(1:3, 1:nen)))       ! jac(a, k) = d x_k / d xi_a
    inv = adjugate3(jac)
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
    real(dp) :: xi(3), w, n(SOLID_MAX_NEN), dnx(3, SOLID_MAX_NEN), detj
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

  !> Point k of the mass rule: natural coordinates and weight. HEX: the stiffness points; TET10: a
  !> collapsed 4 x 4 x 4 Gauss product (xi = u, eta = v (1 - u), zeta = w (1 - u)(1 - v), weight
  !> (1 - u)^2 (1 - v): exact to degree 7 in each of u, v, w, so for N_i N_j det J of a straight tet).
  pure subroutine mass_point(nen, k, xi, w)
    integer, intent(in) :: nen, k
    real(dp), intent(out) :: xi(3), w
    real(dp), parameter :: gp(4) = 0.5_dp * (1.0_dp + [-0.86113631159405257522394648889281_dp, &
      -0.33998104358485626480266575910324_dp, 0.33998104358485626480266575910324_dp, &
      0.86113631159405257522394648889281_dp])
    real(dp), parameter :: gw(4) = 0.5_dp * [0.34785484513745385737306394922200_dp, &
      0.65214515486254614262693605077800_dp, 0.65214515486254614262693605077800_dp, &
      0.34785484513745385737306394922200_dp]
    real(dp) :: u, v, t
    if (nen /= 10) then
      call solid_point(nen, k, xi, w)
      return
    end if
    u = gp(mod(k - 1, 4) + 1)
    v = gp(mod((k - 1) / 4, 4) + 1)
    t = gp((k - 1) / 16 + 1)
    xi = [u, v * (1.0_dp - u), t * (1.0_dp - u) * (1.0_dp - v)]
    w = gw(mod(k - 1, 4) + 1) * gw(mod((k - 1) / 4, 4) + 1) * gw((k - 1) / 16 + 1) * (1.0_dp - u)**2 * (1.0_dp - v)
  end subroutine mass_point

  !> Mass matrix me (3 nen x 3 nen, the three directions uncoupled), consistent or HRZ-lumped.
  pure subroutine solid_mass(nen, x, rho, lumped, me)
    integer, intent(in) :: nen
    real(dp), intent(in) :: x(:, :), rho
    logical, intent(in) :: lumped
    real(dp), intent(out) :: me(:, :)
    real(dp) :: ms(SOLID_MAX_NEN, SOLID_MAX_NEN), total, xi(3), w, n(SOLID_MAX_NEN), dnx(3, SOLID_MAX_NEN), detj
    integer :: ig, i, npt
    ms = 0.0_dp
    total = 0.0_dp
    if (nen == 4) then
      call solid_point(nen, 1, xi, w)
      call solid_cartesian(nen, x, xi, n, dnx, detj)
      total = rho * w * detj
      ms(1:4, 1:4) = total / 20.0_dp
      do i = 1, 4
        ms(i, i) = total / 10.0_dp
      end do
    else
      npt = solid_ngauss(nen)
      if (nen == 10) npt = 64
      do ig = 1, npt
        call mass_point(nen, ig, xi, w)
        call solid_cartesian(nen, x, xi, n, dnx, detj)
        call iso_add_mass(nen, n, rho * w * detj, ms, total)
      end do
    end if
    call iso_mass(nen, ms, total, lumped, me, 3)
  end subroutine solid_mass

  !> Reject a zero-volume or inverted solid: det J <= zero_tol ref^3 at an integration point or at a
  !> corner, ref the model size. Its name: HEX8, HEX20, TET4, TET10 or WEDGE6.
  pure subroutine solid_check(nen, x, ref, stat, errmsg)
    integer, intent(in) :: nen
    real(dp), intent(in) :: x(:, :), ref
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), parameter :: tc(3, 4) = reshape([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1], [3, 4]) * 1.0_dp
    real(dp), parameter :: wc(3, 6) = reshape([0, 0, -1, 1, 0, -1, 0, 1, -1, 0, 0, 1, 1, 0, 1, 0, 1, 1], [3, 6]) * 1.0_dp
    real(dp) :: xi(3), w, n(SOLID_MAX_NEN), dnx(3, SOLID_MAX_NEN), detj, dmin
    integer :: k
    stat = STAT_OK
    dmin = huge(1.0_dp)
    do k = 1, solid_ngauss(nen)
      call solid_point(nen, k, xi, w)
      call solid_cartesian(nen, x, xi, n, dnx, detj)
      dmin = min(dmin, detj)
    end do
    do k = 1, merge(8, merge(6, 4, nen == 6), nen == 8 .or. nen == 20)
      if (nen == 8 .or. nen == 20) then
        xi = [HX(k), HY(k), HZ(k)]
      else if (nen == 6) then
        xi = wc(:, k)
      else
        xi = tc(:, k)
      end if
      call solid_cartesian(nen, x, xi, n, dnx, detj)
      dmin = min(dmin, detj)
    end do
    if (.not. dmin > zero_tol * ref**3) then
      call set_error(stat, errmsg, STAT_INPUT, solid_name(nen) // ' of zero volume or inverted (det J = ' // &
        str(dmin) // '; check its node order)')
    end if
  end subroutine solid_check

  pure function solid_name(nen) result(s)
    integer, intent(in) :: nen
    character(len=:), allocatable :: s
    select case (nen)
    case (8)
      s = 'HEX8'
    case (20)
      s = 'HEX20'
    case (10)
      s = 'TET10'
    case (6)
      s = 'WEDGE6'
    case default
      s = 'TET4'
    end select
  end function solid_name
end module element_solid
