!> Node-to-segment contact whose geometry follows the configuration (GAP … SEGMENTS on a
!> KINEMATICS LARGE model; docs/contact.md, "Pairing that follows the configuration"). At the
!> start of every step each following condition (node b of the statement's NODES group) is
!> paired anew in the configuration x = X + u(n): the closest segment b projects onto, or past the
!> ends the nearest corner (mesh_segments' pair_segment), and its row of C is rewritten as the
!> gradient of that gap at x:
!>     g(u) = g0 + n.(u_b - (1 - ξ) u_a - ξ u_c),   g0 = n.(X_b - (1 - ξ) X_a - ξ X_c),
!> so that g(u(n)) is the gap of the current configuration (the rotation terms of the gradient
!> vanish at the foot of the perpendicular). During the iteration of eq (9) the row is the
!> gradient at the midpoint of the step (fg_update). A pairing is a function of u(n) only: a restart
!> continues bit for bit without saving rows. The multiplier's work across the change of
!> linearization of a held contact is given back at the end of the step (contact_end_step).
module contact_geometry
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use mesh_segments, only: segment_set_t, segment_pair_t, pair_segment, pair_on, NO_PARTNER
  use contact, only: contact_set_t, contact_rewrite, row_geometry_t
  implicit none
  private
  public :: following_t

  !> The following conditions of a contact set and their segment sets.
  type :: following_t
    private
    integer :: n = 0
    integer, allocatable :: row(:)            !< the condition's row in the contact set
    integer, allocatable :: node(:)           !< its node b
    integer, allocatable :: set(:)            !< its segments, sets(set)
    integer, allocatable :: side(:)           !< its side of a chain of line elements (pair_segment)
    real(dp), allocatable :: circle(:, :)     !< (4, n) a rigid circle (set 0): centre x, y, radius, +1 outside / -1 inside
    ! A moving circle (move): its centre's displacement at the step's start and end, its velocity
    ! at the end; the gap the step's motion takes off (set at each pairing); krow: k of a row.
    real(dp), allocatable :: w0(:, :), w1(:, :), wv(:, :), shift(:)
    integer, allocatable :: krow(:)
    integer, allocatable :: sptr(:), star(:)  !< the nodes of b's elements, star(sptr(k):sptr(k+1)-1): no partners
    logical, allocatable :: skip(:)           !< workspace: one star marked (nnode)
    integer, allocatable :: seg(:)            !< the segment it is paired with now (0: none this step, -1: not yet)
    integer, allocatable :: vnode(:)          !< paired with that segment's end node vnode (0: its line)
    real(dp), allocatable :: gstart(:)        !< the gap at the start of the step, g(n)
    type(segment_set_t), allocatable :: sets(:)
    real(dp), allocatable :: x(:, :)          !< workspace: the configuration X + u (2, nnode)
    integer(8) :: repairings = 0              !< changes of segment or of corner since the start
  contains
    procedure :: init => fg_init
    procedure :: count => fg_count
    procedure :: changes => fg_changes
    procedure :: update => fg_update
    procedure :: move => fg_move
  end type following_t

contains

  !> Conditions rows(k), of nodes(k), on segment sets sets(set(k)), on side(k) of a chain of line
  !> elements, the nodes of their elements star(sptr(k):sptr(k+1)-1) (mesh_segments' node_stars: a
  !> node touches no side of its own elements); nnode nodes in the mesh.
  subroutine fg_init(self, rows, nodes, set, side, sets, sptr, star, nnode, circle)
    class(following_t), intent(inout) :: self
    integer, intent(in) :: rows(:), nodes(:), set(:), side(:), sptr(:), star(:)
    type(segment_set_t), intent(in) :: sets(:)
    integer, intent(in) :: nnode
    real(dp), intent(in), optional :: circle(:, :)   !< (4, n): the rigid circle of the conditions of set 0
    integer :: i
    self%n = size(rows)
    allocate (self%circle(4, self%n))
    self%circle = 0.0_dp
    if (present(circle)) self%circle = circle
    self%row = rows
    self%node = nodes
    self%set = set
    self%side = side
    self%sets = sets
    self%sptr = sptr
    self%star = star
    allocate (self%skip(merge(nnode, 0, self%n > 0)))
    self%skip = .false.
    allocate (self%seg(self%n), self%vnode(self%n), self%gstart(self%n), self%x(2, merge(nnode, 0, self%n > 0)))
    allocate (self%w0(2, self%n), self%w1(2, self%n), self%wv(2, self%n), self%shift(self%n), &
      self%krow(merge(maxval(rows), 0, self%n > 0)))
    self%w0 = 0.0_dp
    self%w1 = 0.0_dp
    self%wv = 0.0_dp
    self%shift = 0.0_dp
    self%krow = 0
    self%krow(rows) = [(i, i = 1, self%n)]
    self%seg = -1                              ! (not paired yet)
    self%gstart = 0.0_dp
    self%vnode = 0
    self%repairings = 0
  end subroutine fg_init

  pure integer function fg_count(self)
    class(following_t), intent(in) :: self
    fg_count = self%n
  end function fg_count

  !> Changes of partner (segment, or segment and corner) since init, the first pairing excluded.
  pure integer(8) function fg_changes(self)
    class(following_t), intent(in) :: self
    fg_changes = self%repairings
  end function fg_changes

  !> Row j's circle moves over the next step: its centre displaced by w0 at the start, w1 at
  !> the end (from its place at t = 0), velocity vel at the end (OBSTACLE … SPHERE … VELOCITY).
  pure subroutine fg_move(self, j, w0, w1, vel)
    class(following_t), intent(inout) :: self
    integer, intent(in) :: j
    real(dp), intent(in) :: w0(2), w1(2), vel(2)
    integer :: k
    k = self%krow(j)
    self%w0(:, k) = w0
    self%w1(:, k) = w1
    self%wv(:, k) = vel
  end subroutine fg_move

  !> Pair every following condition and rewrite its row in cs: at the start of the step (du
  !> absent) in the configuration x0 + u, where the gap found, g(n), is kept; during the
  !> iteration of eq (9) with the same partner (segment or corner: the row stays a smooth function
  !> of du) at the midpoint x0 + u + du/2 of the iterate du, with g0 such that the
  !> row still gives g(n) at u: the row is then the gap's gradient at the middle of the step, so
  !> that g(n+1) = g(n) + c'du to third order in du (the step's contact force is normal to the
  !> midpoint configuration, as the internal forces of LARGE members are). x0: the mesh
  !> coordinates; u, du on the free equations eqn(1:2, node) (<= 0: a supported DOF). The
  !> caller prepares cs again (contact_prepare) before the next solve.
  !> With at_end, the same partner at the end configuration x0 + u + du (g(n+1) kept: the gaps of
  !> the step were taken by contact_step_gaps): the impact corrections act along the gradient at
  !> the configuration they act in, which makes them torque-free.
  subroutine fg_update(self, x0, eqn, u, cs, stat, errmsg, du, at_end)
    class(following_t), intent(inout) :: self
    real(dp), intent(in) :: x0(:, :)
    integer, intent(in) :: eqn(:, :)
    real(dp), intent(in) :: u(:)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), intent(in), optional :: du(:)
    logical, intent(in), optional :: at_end
    type(segment_pair_t) :: pr
    integer :: k, i, d, j, eqs(6)
    real(dp) :: coefs(6), g0, f, fw, delta(2), cc(4)
    stat = STAT_OK
    if (self%n == 0) return
    f = 0.5_dp
    if (present(at_end)) then
      if (at_end) f = 1.0_dp
    end if
    do i = 1, size(self%x, 2)
      do d = 1, 2
        j = eqn(d, i)
        self%x(d, i) = x0(d, i)
        if (j <= 0) cycle
        self%x(d, i) = x0(d, i) + u(j)
        if (present(du)) self%x(d, i) = x0(d, i) + (u(j) + f * du(j))
      end do
    end do
    do k = 1, self%n
      if (self%set(k) == 0) then               ! a rigid circle (OBSTACLE … SPHERE): always its partner
        ! (its centre where it is at the start, the midpoint or the end of the step: move)
        fw = merge(f, 0.0_dp, present(du))
        cc = self%circle(:, k)
        cc(1:2) = cc(1:2) + (1.0_dp - fw) * self%w0(:, k) + fw * self%w1(:, k)
        if (present(du) .and. f == 0.5_dp) then
          ! during the iteration: the discrete gradient between x(n) and x(n) + du relative to the
          ! circle (pair_circle), whose motion takes n̄.(w1 - w0) off the gap
          do d = 1, 2
            j = eqn(d, self%node(k))
            delta(d) = self%w0(d, k) - self%w1(d, k)
            if (j > 0) delta(d) = delta(d) + du(j)
          end do
          call pair_circle(self%x(:, self%node(k)), cc, self%node(k), pr, delta)
        else
          call pair_circle(self%x(:, self%node(k)), cc, self%node(k), pr)
        end if
        if (f /= 1.0_dp) self%shift(k) = dot_product(pr%normal, self%w1(:, k) - self%w0(:, k))
        if (any(self%wv(:, k) /= 0.0_dp) .or. self%shift(k) /= 0.0_dp) call cs%move_obstacle(self%row(k), &
          self%shift(k), dot_product(pr%normal, self%wv(:, k)), self%wv(:, k))
        if (.not. present(du)) then
          self%seg(k) = 1
          self%gstart(k) = pr%gap
        end if
      else if (present(du)) then               ! the step's partner, at the midpoint
        if (self%seg(k) == 0) cycle            ! (none: the row stays empty)
        call pair_on(self%x, self%sets(self%set(k)), self%node(k), self%seg(k), self%vnode(k), pr, self%side(k))
      else
        associate (st => self%star(self%sptr(k):self%sptr(k + 1) - 1))
          self%skip(st) = .true.
          call pair_segment(self%x, self%sets(self%set(k)), self%node(k), pr, self%side(k), self%skip)
          self%skip(st) = .false.
        end associate
        if (self%seg(k) >= 0 .and. (pr%seg /= self%seg(k) .or. (pr%vertex .neqv. self%vnode(k) > 0))) &
          self%repairings = self%repairings + 1
        if (pr%seg == 0) then                  ! no partner this step: an empty row, never active
          self%seg(k) = 0
          self%vnode(k) = 0
          self%gstart(k) = NO_PARTNER
          call contact_rewrite(cs, self%row(k), NO_PARTNER, [integer ::], [real(dp) ::], &
            row_geometry_t([self%node(k), 0, 0], 0.0_dp, 0.0_dp), stat, errmsg)
          if (stat /= STAT_OK) return
          cycle
        end if
        self%seg(k) = pr%seg
        self%vnode(k) = merge(pr%nodes(2), 0, pr%vertex)
        self%gstart(k) = pr%gap
      end if
      eqs = 0
      g0 = self%gstart(k)                      ! g(u_n) = g(n)
      if (self%set(k) == 0 .and. f /= 1.0_dp) g0 = g0 - self%shift(k)   ! (g0: the step end's)
      if (f == 1.0_dp) g0 = cs%gap_end(self%row(k))   ! g(u_n + du) = g(n+1)
      do i = 1, 3
        coefs(2 * i - 1:2 * i) = pr%w(i) * pr%normal
        if (pr%nodes(i) == 0) cycle
        eqs(2 * i - 1:2 * i) = max(eqn(1:2, pr%nodes(i)), 0)
        do d = 1, 2
          j = eqs(2 * i - 2 + d)
          if (j <= 0) cycle
          g0 = g0 - coefs(2 * i - 2 + d) * u(j)
          if (f == 1.0_dp) g0 = g0 - coefs(2 * i - 2 + d) * du(j)
        end do
      end do
      call contact_rewrite(cs, self%row(k), g0, eqs, coefs, row_geometry_t(pr%nodes, pr%w, pr%normal), stat, errmsg)
      if (stat /= STAT_OK) return
    end do
  end subroutine fg_update

  !> Node b at x facing the rigid circle c = (centre x, y, radius, side): the normal through the
  !> centre (outward for side +1, inward for -1), the gap side (|x - centre| - radius), the row
  !> on b alone. At the centre (no normal) the last normal is kept: a node never gets there
  !> from outside, nor from inside farther than the radius. With delta (x the midpoint of the
  !> step's move delta of b): the discrete gradient of the gap between x - delta/2 and x + delta/2,
  !>     n̄ = n(x) + (g(x + delta/2) - g(x - delta/2) - n(x).delta) delta / |delta|²,
  !> so that n̄.delta is the gap's change exactly: a contact held along the circle does no work
  !> (the multiplier's work Λ n̄.delta = Λ (g(n+1) - g(n)) = 0), and the energy stays exact.
  pure subroutine pair_circle(x, c, b, pr, delta)
    real(dp), intent(in) :: x(2), c(4)
    integer, intent(in) :: b
    type(segment_pair_t), intent(inout) :: pr
    real(dp), intent(in), optional :: delta(2)
    real(dp) :: d(2), r, dd
    d = x - c(1:2)
    r = norm2(d)
    if (r > 0.0_dp) pr%normal = c(4) * d / r
    pr%gap = c(4) * (r - c(3))
    if (present(delta)) then
      dd = dot_product(delta, delta)
      if (dd > 0.0_dp) pr%normal = pr%normal + (c(4) * (norm2(x + 0.5_dp * delta - c(1:2)) - &
        norm2(x - 0.5_dp * delta - c(1:2))) - dot_product(pr%normal, delta)) * delta / dd
    end if
    pr%nodes = [b, 0, 0]
    pr%w = [1.0_dp, 0.0_dp, 0.0_dp]
    pr%seg = 1
    pr%vertex = .false.
  end subroutine pair_circle
end module contact_geometry
