!> The nodal forces of a load statement (docs/input.md, "Conditions and loads"), the one home
!> of how a load is spread on the nodes, for the load vectors and the support reactions:
!>   LOAD      the given force on every node of the group;
!>   PRESSURE  p on the free sides of the group's surface elements (mesh_segments' group_sides),
!>             positive into the body: consistent nodal forces -p t ∫ N_i n ds;
!>   TRACTION  (tx, ty) per unit area on those sides: t ∫ N_i (tx, ty) ds.
!> t is the thickness of the side's element (its MODEL's SECTION THICKNESS), or in an axisymmetric
!> model 2π r(s), the whole ring (r the side's radius at each point). A PRESSURE on the
!> sides of a KINEMATICS LARGE model follows them (follower_loads) unless said DEAD: those sides
!> are left out here. In a DIMENSION 3 scene PRESSURE and TRACTION (tx, ty, tz) act on the free
!> faces of the group's solids (mesh_faces), consistent nodal forces ∫ N_i (-p n + tr) dA.
module loads
  use kinds, only: dp
  use scene, only: scene_t, load_t, LOAD_NODAL, LOAD_PRESSURE, LOAD_TRACTION
  use mesh_segments, only: side_set_t, group_sides
  use mesh_faces, only: face_set_t, group_faces
  use mesh, only: DOF_UX, DOF_UY, DOF_UZ
  use element_iso, only: TWO_PI
  implicit none
  private
  public :: load_nodal_forces, side_forces, side_pressure_stiffness, side_follows, face_forces

contains

  !> fn(1:3, node): the forces (and moment) the load ld puts on every node, at f(t) = 1, but for
  !> the sides that follow the deformation (side_follows).
  subroutine load_nodal_forces(scn, ld, fn)
    type(scene_t), intent(in) :: scn
    type(load_t), intent(in) :: ld
    real(dp), intent(out) :: fn(:, :)
    type(side_set_t) :: sides
    real(dp) :: fs(2, 3), x(2, 3), t
    integer :: i, k, e, stat
    logical :: ring
    character(len=:), allocatable :: msg
    fn = 0.0_dp
    associate (nodes => scn%mesh%ngroups(ld%ngroup)%items)
      if (ld%kind == LOAD_NODAL) then
        do i = 1, size(nodes)
          fn(:, nodes(i)) = fn(:, nodes(i)) + ld%force
        end do
        return
      end if
      if (scn%mesh%ndim == 3) then
        call face_loads(scn, ld, nodes, fn)
        return
      end if
      call group_sides(scn%mesh, nodes, sides, stat, msg)   ! checked when the scene was read
    end associate
    do k = 1, sides%n
      e = sides%elem(k)
      if (scn%elem_model(e) == 0) cycle                     ! no model: no DOFs to load
      if (side_follows(scn, ld, e)) cycle                   ! a follower side (follower_loads)
      t = scn%models(scn%elem_model(e))%sec%thickness
      ring = scn%models(scn%elem_model(e))%sec%axisymmetric
      x(:, 1:sides%nsn(k)) = scn%mesh%x(:, sides%node(1:sides%nsn(k), k))
      if (ld%kind == LOAD_PRESSURE) then
        call side_forces(sides%nsn(k), x, t, ld%force(1), [0.0_dp, 0.0_dp], fs, ring)
      else
        call side_forces(sides%nsn(k), x, t, 0.0_dp, ld%force(1:2), fs, ring)
      end if
      do i = 1, sides%nsn(k)
        fn(1:2, sides%node(i, k)) = fn(1:2, sides%node(i, k)) + fs(:, i)
      end do
    end do
  end subroutine load_nodal_forces

  !> A PRESSURE or TRACTION on the free faces of the solids of a node group (DIMENSION 3).
  subroutine face_loads(scn, ld, nodes, fn)
    type(scene_t), intent(in) :: scn
    type(load_t), intent(in) :: ld
    integer, intent(in) :: nodes(:)
    real(dp), intent(inout) :: fn(:, :)
    type(face_set_t) :: faces
    real(dp) :: x(3, 8), f(3, 8), p, tr(3)
    integer :: k, i, stat
    integer, parameter :: slot(3) = [DOF_UX, DOF_UY, DOF_UZ]
    character(len=:), allocatable :: msg
    call group_faces(scn%mesh, nodes, faces, stat, msg)   ! checked when the scene was read
    p = 0.0_dp
    tr = 0.0_dp
    if (ld%kind == LOAD_PRESSURE) then
      p = ld%force(1)
    else
      tr = ld%force(1:3)
    end if
    do k = 1, faces%n
      if (scn%elem_model(faces%elem(k)) == 0) cycle
      x = 0.0_dp
      x(:, 1:faces%nfn(k)) = scn%mesh%x(:, faces%node(1:faces%nfn(k), k))
      call face_forces(faces%nfn(k), x, p, tr, f)
      do i = 1, faces%nfn(k)
        fn(slot, faces%node(i, k)) = fn(slot, faces%node(i, k)) + f(:, i)
      end do
    end do
  end subroutine face_loads

  !> Consistent nodal forces f(:, 1:nfn) of a face with nodes x(:, 1:nfn) counter-clockwise seen from
  !> outside (the corners, then a quadratic face's mid-edge nodes), under a pressure p (into the body)
  !> and a traction tr per unit area: f_i = ∫ N_i (-p n + tr) dA with n dA = (∂x/∂r × ∂x/∂s) dr ds.
  !> 3-node face (flat): f_i = (-p A n + A tr)/3. 4- and 8-node faces: 2 x 2 and 3 x 3 Gauss on
  !> [-1, 1]²; 6-node faces: a collapsed 3 x 3 Gauss product on the triangle (r = u, s = v (1 - u)).
  !> The pressure's integrand is a polynomial these rules integrate exactly (its total is -p times the
  !> face's vector area, whatever its shape); the traction's is, for a flat face with straight edges.
  pure subroutine face_forces(nfn, x, p, tr, f)
    integer, intent(in) :: nfn
    real(dp), intent(in) :: x(:, :), p, tr(3)
    real(dp), intent(out) :: f(3, 8)
    real(dp), parameter :: g2 = 0.57735026918962576450914878050196_dp
    real(dp), parameter :: g3(3) = [-0.77459666924148337703585307995648_dp, 0.0_dp, 0.77459666924148337703585307995648_dp]
    real(dp), parameter :: w3(3) = [5.0_dp / 9.0_dp, 8.0_dp / 9.0_dp, 5.0_dp / 9.0_dp]
    real(dp) :: na(3), n(8), dn(2, 8), r, s, w, a(3), b(3)
    integer :: ig, i, npt
    f = 0.0_dp
    if (nfn == 3) then
      na = 0.5_dp * cross(x(:, 2) - x(:, 1), x(:, 3) - x(:, 1))
      do i = 1, 3
        f(:, i) = (-p * na + norm2(na) * tr) / 3.0_dp
      end do
      return
    end if
    npt = merge(4, 9, nfn == 4)
    do ig = 1, npt
      if (nfn == 4) then
        r = g2 * merge(1.0_dp, -1.0_dp, mod(ig - 1, 2) == 1)
        s = g2 * merge(1.0_dp, -1.0_dp, (ig - 1) / 2 == 1)
        w = 1.0_dp
      else if (nfn == 8) then
        r = g3(mod(ig - 1, 3) + 1)
        s = g3((ig - 1) / 3 + 1)
        w = w3(mod(ig - 1, 3) + 1) * w3((ig - 1) / 3 + 1)
      else                                      ! the triangle, collapsed from [0, 1]²
        r = 0.5_dp * (1.0_dp + g3(mod(ig - 1, 3) + 1))
        s = 0.5_dp * (1.0_dp + g3((ig - 1) / 3 + 1)) * (1.0_dp - r)
        w = 0.25_dp * w3(mod(ig - 1, 3) + 1) * w3((ig - 1) / 3 + 1) * (1.0_dp - r)
      end if
      call face_shape(nfn, r, s, n, dn)
      a = matmul(x(:, 1:nfn), dn(1, 1:nfn))
      b = matmul(x(:, 1:nfn), dn(2, 1:nfn))
      na = cross(a, b)
      do i = 1, nfn
        f(:, i) = f(:, i) + w * n(i) * (-p * na + norm2(na) * tr)
      end do
    end do
  contains
    pure function cross(u, v) result(c)
      real(dp), intent(in) :: u(3), v(3)
      real(dp) :: c(3)
      c = [u(2) * v(3) - u(3) * v(2), u(3) * v(1) - u(1) * v(3), u(1) * v(2) - u(2) * v(1)]
    end function cross
  end subroutine face_forces

  !> Shape functions of a face: 4-node bilinear and 8-node serendipity quadrangle on [-1, 1]² (corners
  !> (-1,-1), (1,-1), (1,1), (-1,1), then the mid-edge nodes of sides 1-2, 2-3, 3-4, 4-1); 6-node
  !> triangle on r, s >= 0, r + s <= 1 (corners, then sides 1-2, 2-3, 3-1).
  pure subroutine face_shape(nfn, r, s, n, dn)
    integer, intent(in) :: nfn
    real(dp), intent(in) :: r, s
    real(dp), intent(out) :: n(8), dn(2, 8)
    real(dp), parameter :: cr(8) = [-1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, -1.0_dp]
    real(dp), parameter :: cs(8) = [-1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp, 0.0_dp, 1.0_dp, 0.0_dp]
    real(dp) :: l(3), dl(2, 3)
    integer :: i
    integer, parameter :: te(2, 3) = reshape([1, 2, 2, 3, 3, 1], [2, 3])
    n = 0.0_dp
    dn = 0.0_dp
    select case (nfn)
    case (4)
      do i = 1, 4
        n(i) = 0.25_dp * (1.0_dp + cr(i) * r) * (1.0_dp + cs(i) * s)
        dn(1, i) = 0.25_dp * cr(i) * (1.0_dp + cs(i) * s)
        dn(2, i) = 0.25_dp * cs(i) * (1.0_dp + cr(i) * r)
      end do
    case (8)
      do i = 1, 4
        n(i) = 0.25_dp * (1.0_dp + cr(i) * r) * (1.0_dp + cs(i) * s) * (cr(i) * r + cs(i) * s - 1.0_dp)
        dn(1, i) = 0.25_dp * cr(i) * (1.0_dp + cs(i) * s) * (2.0_dp * cr(i) * r + cs(i) * s)
        dn(2, i) = 0.25_dp * cs(i) * (1.0_dp + cr(i) * r) * (cr(i) * r + 2.0_dp * cs(i) * s)
      end do
      do i = 5, 8
        if (cr(i) == 0.0_dp) then
          n(i) = 0.5_dp * (1.0_dp - r * r) * (1.0_dp + cs(i) * s)
          dn(1, i) = -r * (1.0_dp + cs(i) * s)
          dn(2, i) = 0.5_dp * cs(i) * (1.0_dp - r * r)
        else
          n(i) = 0.5_dp * (1.0_dp - s * s) * (1.0_dp + cr(i) * r)
          dn(1, i) = 0.5_dp * cr(i) * (1.0_dp - s * s)
          dn(2, i) = -s * (1.0_dp + cr(i) * r)
        end if
      end do
    case (6)
      l = [1.0_dp - r - s, r, s]
      dl = reshape([-1.0_dp, -1.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [2, 3])
      do i = 1, 3
        n(i) = l(i) * (2.0_dp * l(i) - 1.0_dp)
        dn(:, i) = (4.0_dp * l(i) - 1.0_dp) * dl(:, i)
        n(3 + i) = 4.0_dp * l(te(1, i)) * l(te(2, i))
        dn(:, 3 + i) = 4.0_dp * (l(te(1, i)) * dl(:, te(2, i)) + l(te(2, i)) * dl(:, te(1, i)))
      end do
    end select
  end subroutine face_shape

  !> True when the side of element e under load ld follows the deformation: a PRESSURE not said
  !> DEAD on an element of a KINEMATICS LARGE model (follower_loads takes it).
  pure logical function side_follows(scn, ld, e)
    type(scene_t), intent(in) :: scn
    type(load_t), intent(in) :: ld
    integer, intent(in) :: e
    side_follows = .false.
    if (ld%kind /= LOAD_PRESSURE .or. ld%dead) return
    if (scn%elem_model(e) == 0) return
    side_follows = scn%models(scn%elem_model(e))%large
  end function side_follows

  !> Consistent nodal forces f(:, 1:nsn) of a side with nodes x(:, 1:nsn) (2: straight; 3: end,
  !> mid-side, end: quadratic), thickness t, under a pressure p (into the body: the side runs
  !> counter-clockwise around its element, so its outward normal is the right of its
  !> direction) and a traction tr per unit area. With x(s) = Σ N_k(s) x_k, s in [-1, 1]:
  !>     f_i = t ∫ N_i(s) (-p (y'(s), -x'(s)) + tr |x'(s)|) ds,
  !> by 3-point Gauss: exact for the pressure of any 2- or 3-node side (the integrand is a
  !> polynomial of degree <= 3), and for the traction of a straight side. The pressure's total
  !> is -p t times the chord's normal (Σ N_i = 1: ∫ x' ds is the chord), whatever the mesh.
  !> ring (axisymmetric): t = 2π x(s), the ring's circumference at each point (degree <= 5 for
  !> the pressure: still exact).
  pure subroutine side_forces(nsn, x, t, p, tr, f, ring)
    integer, intent(in) :: nsn
    real(dp), intent(in) :: x(2, 3), t, p, tr(2)
    real(dp), intent(out) :: f(2, 3)
    logical, intent(in), optional :: ring
    real(dp), parameter :: gs(3) = [-sqrt(0.6_dp), 0.0_dp, sqrt(0.6_dp)]
    real(dp), parameter :: gw(3) = [5.0_dp / 9.0_dp, 8.0_dp / 9.0_dp, 5.0_dp / 9.0_dp]
    real(dp) :: n(3), dn(3), dx(2), s, tg
    integer :: g, i
    logical :: axi
    axi = .false.
    if (present(ring)) axi = ring
    f = 0.0_dp
    do g = 1, 3
      s = gs(g)
      if (nsn == 2) then
        n(1:2) = [0.5_dp * (1.0_dp - s), 0.5_dp * (1.0_dp + s)]
        dn(1:2) = [-0.5_dp, 0.5_dp]
      else                                      ! nodes: s = -1, the mid-side node s = 0, s = 1
        n = [0.5_dp * s * (s - 1.0_dp), 1.0_dp - s * s, 0.5_dp * s * (s + 1.0_dp)]
        dn = [s - 0.5_dp, -2.0_dp * s, s + 0.5_dp]
      end if
      dx = matmul(x(:, 1:nsn), dn(1:nsn))
      tg = t
      if (axi) tg = TWO_PI * dot_product(n(1:nsn), x(1, 1:nsn))
      do i = 1, nsn
        f(:, i) = f(:, i) + gw(g) * tg * n(i) * (-p * [dx(2), -dx(1)] + tr * norm2(dx))
      end do
    end do
  end subroutine side_forces

  !> The load stiffness of a pressure P (thickness included) following a side of nsn nodes,
  !> ke = -sym(∂f/∂x) in the order (x1, y1, x2, y2, …). f of side_forces is linear in the nodes:
  !> ∂f_ix/∂y_j = -P c_ij, ∂f_iy/∂x_j = P c_ij, c_ij = ∫ N_i N_j' ds (3-point Gauss: exact), so
  !>     ke(ix, jy) = ½ P (c_ij - c_ji) = -ke(iy, jx),  ke(ix, jx) = ke(iy, jy) = 0,
  !> independent of the configuration. The skew part left out, ½ P [N_i N_j] at the side's ends,
  !> cancels between the sides of a closed or held contour (the load then has the potential P A).
  pure subroutine side_pressure_stiffness(nsn, p, ke)
    integer, intent(in) :: nsn
    real(dp), intent(in) :: p
    real(dp), intent(out) :: ke(6, 6)
    real(dp), parameter :: gs(3) = [-sqrt(0.6_dp), 0.0_dp, sqrt(0.6_dp)]
    real(dp), parameter :: gw(3) = [5.0_dp / 9.0_dp, 8.0_dp / 9.0_dp, 5.0_dp / 9.0_dp]
    real(dp) :: c(3, 3), nn(3), dn(3), q
    integer :: g, i, j
    c = 0.0_dp
    do g = 1, 3
      if (nsn == 2) then
        nn(1:2) = [0.5_dp * (1.0_dp - gs(g)), 0.5_dp * (1.0_dp + gs(g))]
        dn(1:2) = [-0.5_dp, 0.5_dp]
      else
        nn = [0.5_dp * gs(g) * (gs(g) - 1.0_dp), 1.0_dp - gs(g)**2, 0.5_dp * gs(g) * (gs(g) + 1.0_dp)]
        dn = [gs(g) - 0.5_dp, -2.0_dp * gs(g), gs(g) + 0.5_dp]
      end if
      do j = 1, nsn
        do i = 1, nsn
          c(i, j) = c(i, j) + gw(g) * nn(i) * dn(j)
        end do
      end do
    end do
    ke = 0.0_dp
    do j = 1, nsn
      do i = 1, nsn
        q = 0.5_dp * p * (c(i, j) - c(j, i))
        ke(2 * i - 1, 2 * j) = q
        ke(2 * i, 2 * j - 1) = -q
      end do
    end do
  end subroutine side_pressure_stiffness
end module loads
