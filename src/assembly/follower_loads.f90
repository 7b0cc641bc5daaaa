!> PRESSURE on a KINEMATICS LARGE model: a follower load, normal to the deformed side
!> (docs/input.md, "PRESSURE"; docs/large-displacements.md). On a side with nodes x(u) = X + u,
!>     f_i(u) = -p t ∫ N_i(s) (y'(s), -x'(s)) ds        (loads' side_forces at the current nodes),
!> linear in x: its derivative D, with blocks ∂f_ix/∂y_j = -p t c_ij, ∂f_iy/∂x_j = p t c_ij and
!> c_ij = ∫ N_i N_j' ds, is constant on the side. Its symmetric part is what the tangent
!> takes (-sym D: the iteration matrix is symmetric); the skew part ½ p t [N_i N_j] R sits only
!> at the side's ends and cancels between neighbours of a closed or held contour, where the
!> load has the potential p t A (A the enclosed area). The scheme books its work by the
!> trapezoid rule, ½ du'(F(n) + F(n+1)), the same F as in eq (9): the balance stays exact; on a
!> closed contour the booked work is exactly -p t ΔA (A is quadratic in the nodes).
!> A dead PRESSURE (the word DEAD, or a SMALL model) stays in the load vectors (assembly).
module follower_loads
  use kinds, only: dp
  use scene, only: scene_t, function_value, LOAD_PRESSURE
  use mesh_segments, only: side_set_t, group_sides
  use loads, only: side_forces, side_pressure_stiffness, side_follows
  use sparse_matrix, only: sym_csc_t
  implicit none
  private
  public :: follower_set_t

  !> The sides of every follower PRESSURE, with the equations of their nodes.
  type, public :: follower_set_t
    integer :: n = 0                          !< sides
    integer, allocatable :: nsn(:)            !< (n) 2 or 3 nodes
    integer, allocatable :: node(:, :)        !< (3, n) the side's nodes
    integer, allocatable :: eq(:, :)          !< (6, n) equation of each node's x, y (<= 0: fixed)
    integer, allocatable :: func(:)           !< (n) the load's function (0: constant 1)
    real(dp), allocatable :: tp(:)            !< (n) thickness x pressure
    ! Support reactions: entry k puts component loc (2(i-1) + d) of side side(k) in slot slot(k).
    integer, allocatable :: r_side(:), r_loc(:), r_slot(:)
    real(dp), allocatable :: r_w(:)
  contains
    procedure :: build => follower_build
    procedure :: add_force => follower_add_force
    procedure :: add_tangent => follower_add_tangent
    procedure :: add_reaction => follower_add_reaction
    procedure :: add_reaction_entry => follower_add_reaction_entry
  end type follower_set_t

contains

  !> Collect the following sides of every load; eqn(3, nnode) the equation of each node DOF.
  subroutine follower_build(self, scn, eqn)
    class(follower_set_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    integer, intent(in) :: eqn(:, :)
    type(side_set_t) :: sides
    integer :: il, k, e, i, m, pass, stat
    character(len=:), allocatable :: msg
    do pass = 1, 2
      m = 0
      do il = 1, size(scn%loads)
        if (scn%loads(il)%kind /= LOAD_PRESSURE .or. scn%loads(il)%dead) cycle
        call group_sides(scn%mesh, scn%mesh%ngroups(scn%loads(il)%ngroup)%items, sides, stat, msg) ! checked on reading
        do k = 1, sides%n
          e = sides%elem(k)
          if (.not. side_follows(scn, scn%loads(il), e)) cycle
          m = m + 1
          if (pass == 1) cycle
          self%nsn(m) = sides%nsn(k)
          self%node(:, m) = 0
          self%eq(:, m) = 0
          do i = 1, sides%nsn(k)
            self%node(i, m) = sides%node(i, k)
            self%eq(2 * i - 1:2 * i, m) = eqn(1:2, sides%node(i, k))
          end do
          self%func(m) = scn%loads(il)%func
          self%tp(m) = scn%models(scn%elem_model(e))%sec%thickness * scn%loads(il)%force(1)
        end do
      end do
      if (pass == 1) then
        self%n = m
        allocate (self%nsn(m), self%node(3, m), self%eq(6, m), self%func(m), self%tp(m))
        allocate (self%r_side(0), self%r_loc(0), self%r_slot(0), self%r_w(0))
      end if
    end do
  end subroutine follower_build

  !> The nodes of side k at displacement u (free equations; a fixed DOF stays at X).
  pure subroutine side_nodes(self, scn, k, u, x)
    class(follower_set_t), intent(in) :: self
    type(scene_t), intent(in) :: scn
    integer, intent(in) :: k
    real(dp), intent(in) :: u(:)
    real(dp), intent(out) :: x(2, 3)
    integer :: i, d, j
    x = 0.0_dp
    do i = 1, self%nsn(k)
      do d = 1, 2
        x(d, i) = scn%mesh%x(d, self%node(i, k))
        j = self%eq(2 * (i - 1) + d, k)
        if (j > 0) x(d, i) = x(d, i) + u(j)
      end do
    end do
  end subroutine side_nodes

  !> f += the follower pressures at time t on the configuration X + u.
  subroutine follower_add_force(self, scn, t, u, f)
    class(follower_set_t), intent(in) :: self
    type(scene_t), intent(in) :: scn
    real(dp), intent(in) :: t, u(:)
    real(dp), intent(inout) :: f(:)
    real(dp) :: x(2, 3), fs(2, 3), s
    integer :: k, i, d, j
    do k = 1, self%n
      s = function_value(scn%functions, self%func(k), t)
      if (s == 0.0_dp) cycle
      call side_nodes(self, scn, k, u, x)
      call side_forces(self%nsn(k), x, 1.0_dp, s * self%tp(k), [0.0_dp, 0.0_dp], fs)
      do i = 1, self%nsn(k)
        do d = 1, 2
          j = self%eq(2 * (i - 1) + d, k)
          if (j > 0) f(j) = f(j) + fs(d, i)
        end do
      end do
    end do
  end subroutine follower_add_force

  !> tval += -sym(∂f/∂u) at time t, the load stiffness of every side (loads' side_pressure_stiffness).
  subroutine follower_add_tangent(self, scn, t, pat, tval)
    class(follower_set_t), intent(in) :: self
    type(scene_t), intent(in) :: scn
    real(dp), intent(in) :: t
    type(sym_csc_t), intent(in) :: pat
    real(dp), intent(inout) :: tval(:)
    real(dp) :: ke(6, 6), p
    integer :: k, m
    do k = 1, self%n
      p = function_value(scn%functions, self%func(k), t) * self%tp(k)
      if (p == 0.0_dp) cycle
      m = self%nsn(k)
      call side_pressure_stiffness(m, p, ke)
      call pat%add_element(tval, self%eq(1:2 * m, k), ke(1:2 * m, 1:2 * m))
    end do
  end subroutine follower_add_tangent

  !> Record that component loc of side k's forces lands in support-reaction slot s.
  subroutine follower_add_reaction_entry(self, k, loc, s, w)
    class(follower_set_t), intent(inout) :: self
    integer, intent(in) :: k, loc, s
    real(dp), intent(in), optional :: w     !< weight (default 1; a PROBE MZ ABOUT's arm)
    self%r_side = [self%r_side, k]
    self%r_loc = [self%r_loc, loc]
    self%r_slot = [self%r_slot, s]
    if (present(w)) then
      self%r_w = [self%r_w, w]
    else
      self%r_w = [self%r_w, 1.0_dp]
    end if
  end subroutine follower_add_reaction_entry

  !> fw(slot) += the follower pressures' forces at time t on the fixed DOFs of the reaction
  !> slots, on the configuration X + u.
  subroutine follower_add_reaction(self, scn, t, u, fw)
    class(follower_set_t), intent(in) :: self
    type(scene_t), intent(in) :: scn
    real(dp), intent(in) :: t, u(:)
    real(dp), intent(inout) :: fw(:)
    real(dp) :: x(2, 3), fs(2, 3)
    integer :: e, k
    do e = 1, size(self%r_side)
      k = self%r_side(e)
      call side_nodes(self, scn, k, u, x)
      call side_forces(self%nsn(k), x, 1.0_dp, function_value(scn%functions, self%func(k), t) * self%tp(k), &
        [0.0_dp, 0.0_dp], fs)
      fw(self%r_slot(e)) = fw(self%r_slot(e)) + self%r_w(e) * fs(2 - mod(self%r_loc(e), 2), (self%r_loc(e) + 1) / 2)
    end do
  end subroutine follower_add_reaction
end module follower_loads
