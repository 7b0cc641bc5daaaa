!> IMPACT SYMMETRIC (docs/contact.md): a release is the impact reversed. An establishment stops
!> the normal velocity of the impacting nodes (PERSIST's projection, the hzero step with gains 1)
!> and the condition holds the kinetic energy the projection took with the step's loss E_j (10);
!> at its release it gives that energy back as an impulse on its nodes. Groups the projection
!> leaves without kinetic energy of their own are returned in fallback for PAPER. Inputs and
!> outputs are arguments; the scratch is the mode's own.
module impact_symmetric
  use kinds, only: dp
  use errors, only: STAT_OK
  use constraint_rows, only: constraint_rows_t
  use impact_report, only: contact_report_t
  use impact_space, only: impact_space_t, MAX_RIGID
  use impact_groups, only: impact_groups_t
  implicit none
  private

  type, public :: symmetric_t
    private
    type(impact_groups_t) :: groups
    integer, allocatable :: idx(:)
    logical, allocatable :: mem(:), rows(:)
    real(dp), allocatable :: ct(:), gain(:), nu(:), share(:), vn(:), mvn(:)
  contains
    procedure :: init => symmetric_init
    procedure :: correct => symmetric_correction
  end type symmetric_t

contains

  !> Scratch for neq equations and nc conditions (before the time loop).
  subroutine symmetric_init(self, neq, nc)
    class(symmetric_t), intent(inout) :: self
    integer, intent(in) :: neq, nc
    if (allocated(self%idx)) deallocate (self%idx, self%mem, self%ct, self%gain, self%nu, self%share, self%rows, self%vn, &
      self%mvn)
    allocate (self%idx(nc), self%mem(nc), self%ct(nc), self%gain(nc), self%nu(nc), self%share(nc), self%rows(neq), &
      self%vn(neq), self%mvn(neq))
    call self%groups%init(neq, nc)
  end subroutine symmetric_init

  !> Released conditions (rel) first: each gives back the energy it held, held_j, as an impulse x
  !> along c_j on its nodes, v <- v + x M⁻¹c_j' with ½ s x² + (c_j v) x = held_j, s = c_j M⁻¹c_j',
  !> x > 0 (repulsive). Then, if conditions are established (est): the velocity projected on zero
  !> normal velocity of every active condition (now), impulses -ν along c_j, and the kinetic energy
  !> it takes, ½ ν'A v, with the step's loss e_j (10) held by the established conditions (the
  !> projection's share of each: ½ ν_j (c_j v) before it, the positive ones), except in the groups
  !> the projection leaves without kinetic energy (fallback). held(:) is the conditions' state;
  !> rep%held: the energy held in the step less the energy given back (history.csv's contact_held,
  !> so that the balance holds exactly). Out: v, mv (= M v), cimp (the impulses along c_j).
  subroutine symmetric_correction(self, sp, c, body, est, rel, now, e, min_fraction, held, v, mv, cimp, fallback, rep, &
    stat, errmsg)
    class(symmetric_t), intent(inout) :: self
    type(impact_space_t), intent(inout) :: sp
    type(constraint_rows_t), intent(in) :: c
    integer, intent(in) :: body(:)
    logical, intent(in) :: est(:), rel(:), now(:)
    real(dp), intent(in) :: e(:), min_fraction
    real(dp), intent(inout) :: held(:), v(:), mv(:), cimp(:)
    logical, intent(out) :: fallback(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: j, k, n, rank, kept
    real(dp) :: b, q, x, dt, wsum, held_now, a1(1, 1)
    stat = STAT_OK
    fallback = .false.
    if (.not. allocated(self%idx)) call self%init(size(v), size(est))
    do j = 1, size(est)
      if (.not. (rel(j) .and. held(j) > 0.0_dp)) cycle
      self%idx(1) = j
      call sp%am_block(c, self%idx(1:1), 1, a1, stat, errmsg)
      if (stat /= STAT_OK) return
      b = c%dot(j, v)
      q = sqrt(b * b + 2.0_dp * a1(1, 1) * held(j))
      if (b >= 0.0_dp) then                      ! (the root without cancellation)
        x = 2.0_dp * held(j) / (q + b)
      else
        x = (q - b) / a1(1, 1)
      end if
      self%nu = 0.0_dp
      self%nu(j) = x
      call sp%add_minv_ct(c, self%nu, 1.0_dp, v, mv, stat, errmsg)
      if (stat /= STAT_OK) return
      cimp(j) = cimp(j) + x
      rep%held = rep%held - held(j)
      held(j) = 0.0_dp
    end do
    if (.not. any(est)) return
    n = 0
    do j = 1, size(est)
      if (.not. now(j)) cycle
      n = n + 1
      self%idx(n) = j
      self%ct(n) = c%dot(j, v)
    end do
    self%vn = v                                  ! (the velocity before the projection)
    self%mvn = mv
    self%gain(1:n) = 1.0_dp
    call sp%hzero_step(c, self%idx(1:n), self%gain(1:n), v, mv, self%nu, rank, stat, errmsg)
    if (stat /= STAT_OK) return
    self%share = 0.0_dp                          ! the established ones' shares, by condition
    do k = 1, n
      j = self%idx(k)
      if (est(j)) self%share(j) = max(0.5_dp * self%nu(j) * self%ct(k), 0.0_dp)
    end do
    call symmetric_fallback(self, sp, c, body, est, now, e, min_fraction, v, mv, fallback, rep, stat, errmsg)
    if (stat /= STAT_OK) return
    dt = 0.5_dp * (dot_product(self%vn, self%mvn) - dot_product(v, mv))
    cimp = cimp - self%nu
    wsum = 0.0_dp
    kept = 0
    do j = 1, size(est)
      if (.not. est(j) .or. fallback(j)) cycle
      wsum = wsum + self%share(j)
      kept = kept + 1
    end do
    held_now = 0.0_dp
    do j = 1, size(est)
      if (.not. est(j) .or. fallback(j)) cycle
      if (wsum > 0.0_dp) then
        held(j) = held(j) + e(j) + dt * self%share(j) / wsum
      else
        held(j) = held(j) + e(j) + dt / real(kept, dp)
      end if
      held_now = held_now + e(j)
    end do
    if (kept > 0) rep%held = rep%held + dt + held_now
  end subroutine symmetric_correction

  !> SYMMETRIC's held energy comes back when the body's elasticity ends the contact. A group (bodies
  !> linked by active conditions) the projection leaves without kinetic energy of its own (a point
  !> mass, a body landing with every node, two rigid-like bodies meeting) has none to end it: under
  !> gravity it would stay down with the energy held. Those groups (PERSIST's test: the projected
  !> energy v, mv, less the group's rigid motion, at most min_fraction of T1 + Σ E_j) get their
  !> velocity before the projection back (vn, mvn), their projection impulses dropped from ν, and
  !> their established conditions in fallback, for PAPER's reflection.
  subroutine symmetric_fallback(self, sp, c, body, est, now, e, min_fraction, v, mv, fallback, rep, stat, errmsg)
    type(symmetric_t), intent(inout) :: self
    type(impact_space_t), intent(inout) :: sp
    type(constraint_rows_t), intent(in) :: c
    integer, intent(in) :: body(:)
    logical, intent(in) :: est(:), now(:)
    real(dp), intent(in) :: e(:), min_fraction
    real(dp), intent(inout) :: v(:), mv(:)
    logical, intent(inout) :: fallback(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: grp, n, j, i, nm, mk(MAX_RIGID)
    real(dp) :: t1, tp, tstar, acm(MAX_RIGID), tcm
    logical :: hit
    call self%groups%build(c, body, now, est, stat, errmsg)
    if (stat /= STAT_OK) return
    associate (mem => self%mem, rows => self%rows)
      do grp = 1, self%groups%n_bodies()
        if (.not. self%groups%is_root(grp)) cycle
        call self%groups%members(grp, mem)
        hit = .false.
        n = 0
        tstar = 0.0_dp
        do j = 1, size(est)
          if (.not. mem(j)) cycle
          if (est(j)) then
            hit = .true.
            tstar = tstar + e(j)
          end if
          if (.not. now(j)) cycle
          n = n + 1
          self%idx(n) = j
        end do
        if (.not. hit) cycle
        call self%groups%rows_of(body, grp, rows)
        t1 = 0.5_dp * sum(self%vn * self%mvn, mask=rows)
        tp = 0.5_dp * sum(v * mv, mask=rows)
        call sp%rigid_motion(c, body, rows, self%idx, n, mv, acm, tcm, nm, mk)
        if (tp - tcm > min_fraction * (t1 + tstar)) cycle
        do i = 1, size(v)
          if (.not. rows(i)) cycle
          v(i) = self%vn(i)
          mv(i) = self%mvn(i)
        end do
        do j = 1, size(est)
          if (.not. mem(j)) cycle
          self%nu(j) = 0.0_dp
          fallback(j) = est(j)
        end do
        rep%persist_fallbacks = rep%persist_fallbacks + 1
      end do
    end associate
  end subroutine symmetric_fallback
end module impact_symmetric
