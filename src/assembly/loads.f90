!> The nodal forces of a load statement (docs/input.md, "Conditions and loads"), the one home
!> of how a load is spread on the nodes, for the load vectors and the support reactions:
!>   LOAD      the given force on every node of the group;
!>   PRESSURE  p on the free sides of the group's surface elements (mesh_segments' group_sides),
!>             positive into the body: consistent nodal forces -p t ∫ N_i n ds;
!>   TRACTION  (tx, ty) per unit area on those sides: t ∫ N_i (tx, ty) ds.
!> t is the thickness of the side's element (its MODEL's SECTION THICKNESS).
module loads
  use kinds, only: dp
  use scene, only: scene_t, load_t, LOAD_NODAL, LOAD_PRESSURE, LOAD_TRACTION
  use mesh_segments, only: side_set_t, group_sides
  implicit none
  private
  public :: load_nodal_forces, side_forces

contains

  !> fn(1:3, node): the forces (and moment) the load ld puts on every node, at f(t) = 1.
  subroutine load_nodal_forces(scn, ld, fn)
    type(scene_t), intent(in) :: scn
    type(load_t), intent(in) :: ld
    real(dp), intent(out) :: fn(:, :)
    type(side_set_t) :: sides
    real(dp) :: fs(2, 3), x(2, 3), t
    integer :: i, k, e, stat
    character(len=:), allocatable :: msg
    fn = 0.0_dp
    associate (nodes => scn%mesh%ngroups(ld%ngroup)%items)
      if (ld%kind == LOAD_NODAL) then
        do i = 1, size(nodes)
          fn(:, nodes(i)) = fn(:, nodes(i)) + ld%force
        end do
        return
      end if
      call group_sides(scn%mesh, nodes, sides, stat, msg)   ! checked when the scene was read
    end associate
    do k = 1, sides%n
      e = sides%elem(k)
      if (scn%elem_model(e) == 0) cycle                     ! no model: no DOFs to load
      t = scn%models(scn%elem_model(e))%sec%thickness
      x(:, 1:sides%nsn(k)) = scn%mesh%x(:, sides%node(1:sides%nsn(k), k))
      if (ld%kind == LOAD_PRESSURE) then
        call side_forces(sides%nsn(k), x, t, ld%force(1), [0.0_dp, 0.0_dp], fs)
      else
        call side_forces(sides%nsn(k), x, t, 0.0_dp, ld%force(1:2), fs)
      end if
      do i = 1, sides%nsn(k)
        fn(1:2, sides%node(i, k)) = fn(1:2, sides%node(i, k)) + fs(:, i)
      end do
    end do
  end subroutine load_nodal_forces

  !> Consistent nodal forces f(:, 1:nsn) of a side with nodes x(:, 1:nsn) (2: straight; 3: end,
  !> mid-side, end: quadratic), thickness t, under a pressure p (into the body: the side runs
  !> counter-clockwise around its element, so its outward normal is the right of its
  !> direction) and a traction tr per unit area. With x(s) = Σ N_k(s) x_k, s in [-1, 1]:
  !>     f_i = t ∫ N_i(s) (-p (y'(s), -x'(s)) + tr |x'(s)|) ds,
  !> by 3-point Gauss: exact for the pressure of any 2- or 3-node side (the integrand is a
  !> polynomial of degree <= 3), and for the traction of a straight side. The pressure's total
  !> is -p t times the chord's normal (Σ N_i = 1: ∫ x' ds is the chord), whatever the mesh.
  pure subroutine side_forces(nsn, x, t, p, tr, f)
    integer, intent(in) :: nsn
    real(dp), intent(in) :: x(2, 3), t, p, tr(2)
    real(dp), intent(out) :: f(2, 3)
    real(dp), parameter :: gs(3) = [-sqrt(0.6_dp), 0.0_dp, sqrt(0.6_dp)]
    real(dp), parameter :: gw(3) = [5.0_dp / 9.0_dp, 8.0_dp / 9.0_dp, 5.0_dp / 9.0_dp]
    real(dp) :: n(3), dn(3), dx(2), s
    integer :: g, i
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
      do i = 1, nsn
        f(:, i) = f(:, i) + gw(g) * t * n(i) * (-p * [dx(2), -dx(1)] + tr * norm2(dx))
      end do
    end do
  end subroutine side_forces
end module loads
