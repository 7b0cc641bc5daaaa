!> Contact events located inside a step (SCHEME EVENTS LOCATE, docs/contact.md "Contact events
!> located"). A step whose last iterate establishes a contact at the onset of an impact (no
!> condition between the same two bodies held at its start), or releases one, is not committed: the instant of
!> the first event is estimated and the step is cut there, so that the event falls on a step's
!> end; the run's steps go on from it (the time grid shifts, newmark).
!>
!> Onset: each closing condition's gap over the step, from its start,
!>     g(s) = g(n) + ġ(n) s + ½ a s²,   ġ(n) = c_j'v(n) (less an obstacle's normal velocity),
!> with a the gap's mean acceleration over the previous step, (ġ(n) − ġ(n−1))/h(n−1), when the
!> condition was open through it (0 otherwise). Between impacts the trapezoid rule integrates a
!> constant acceleration exactly, so the instant is exact for a point mass under gravity and for a
!> body in uniform motion; otherwise its error is O(h³). The smallest root in (0, h], by the form
!>     s = 2 g(n) / (−ġ(n) + √(ġ(n)² − 2 a g(n)))
!> (no cancellation for either sign of ġ(n)).
!> Release: the step multiplier Λ_j = R(n) + R(n+1) is twice the contact force's mean over the
!> step, its value at the step's middle to O(h²) (R itself alternates about it: the trapezoid
!> rule's split of Λ). A held condition whose force falls is released where the line through the
!> last two midpoints' forces, the previous step's Λ_p/2 at −h(n−1)/2 and this step's trial
!> Λ/2 at h/2, reaches zero:
!>     s = h/2 + Λ (h(n−1) + h)/2 / (Λ_p − Λ),
!> when that lies inside the step (the trial, held on average, would release at the next step a
!> condition whose force is already negative: the release then falls on the step's end where the
!> force vanishes). A flat force, as on a bar whose wave the lattice carries exactly, predicts no
!> zero: the release stays on the grid. Not under IMPACT MASSLESS (its Λ is R(n+1)).
!> A cut is made when s/h lies in [SPLIT_MIN, 1 − SPLIT_MIN]: closer to a step's end the event
!> already is on the grid.
module event_location
  use kinds, only: dp
  use contact, only: contact_set_t
  use checkpoint, only: ckpt_file_t
  implicit none
  private
  public :: event_locator_t

  !> Fraction of the step below which (or above 1 − which) an event is not cut off.
  real(dp), parameter :: SPLIT_MIN = 1.0e-3_dp

  type :: event_locator_t
    private
    !> ġ and R at the start of this step and of the previous one; open (unilateral, inactive) and
    !> active then.
    real(dp), allocatable :: rate(:), rate_prev(:), lam(:)
    logical, allocatable :: open_now(:), open_prev(:), held_now(:), held_prev(:)
    !> The bodies (mesh-connected components) of each condition's two nodes (0: an obstacle, or a
    !> node without a free DOF): an onset is located when no condition between the same two bodies
    !> is held (pair_held).
    integer, allocatable :: cbody(:, :)
    real(dp) :: h_prev = 0.0_dp, h_now = 0.0_dp
    logical :: started = .false.
    integer, public :: located = 0                  !< steps cut at an event
  contains
    procedure :: init => locator_init
    procedure :: begin_step => locator_begin_step
    procedure :: event_fraction => locator_event_fraction
    procedure :: save => locator_save
    procedure :: load => locator_load
  end type event_locator_t

contains

  !> Room for the conditions of cs (before the time loop: no allocation in it), with the bodies of
  !> their nodes: body(eq) of the first free equation eqn(:, node) (dof_map's equation_bodies).
  subroutine locator_init(self, cs, eqn, body)
    class(event_locator_t), intent(inout) :: self
    type(contact_set_t), intent(in) :: cs
    integer, intent(in) :: eqn(:, :), body(:)
    integer :: nc, j, k, d, nodes(2)
    if (allocated(self%rate)) return
    nc = cs%n_conditions()
    allocate (self%rate(nc), self%rate_prev(nc), self%lam(nc), self%open_now(nc), &
      self%open_prev(nc), self%held_now(nc), self%held_prev(nc), self%cbody(2, nc))
    self%cbody = 0
    do j = 1, nc
      nodes = cs%nodes(j)
      do k = 1, 2
        if (nodes(k) <= 0) cycle
        do d = 1, size(eqn, 1)
          if (eqn(d, nodes(k)) > 0) then
            self%cbody(k, j) = body(eqn(d, nodes(k)))
            exit
          end if
        end do
      end do
    end do
    self%rate = 0.0_dp
    self%lam = 0.0_dp
    self%open_now = .false.
    self%held_now = .false.
  end subroutine locator_init

  !> The start of a step of length h from velocity v: the conditions' normal velocities,
  !> reactions and states now, those of the previous step kept.
  subroutine locator_begin_step(self, cs, v, h)
    class(event_locator_t), intent(inout) :: self
    type(contact_set_t), intent(in) :: cs
    real(dp), intent(in) :: v(:), h
    integer :: j
    logical :: unilateral, active, trial
    real(dp) :: lambda
    self%rate_prev = self%rate
    self%open_prev = self%open_now
    self%held_prev = self%held_now
    do j = 1, cs%n_conditions()
      call cs%row_state(j, unilateral, active, trial, lambda, v, self%rate(j))
      self%open_now(j) = unilateral .and. .not. active
      self%held_now(j) = unilateral .and. active
      self%lam(j) = cs%multiplier(j)
    end do
    if (self%started) then
      self%h_prev = self%h_now
    else
      self%open_prev = .false.
      self%held_prev = .false.
    end if
    self%h_now = h
    self%started = .true.
  end subroutine locator_begin_step

  !> The fraction θ of the step (length h) at which its first contact event happened, 0 when the
  !> step is not to be cut: no onset (a condition closing between two bodies already in contact is
  !> the contact spreading) or release in it, or θ within SPLIT_MIN of its ends.
  real(dp) function locator_event_fraction(self, cs, h, massless, is_onset) result(theta)
    class(event_locator_t), intent(in) :: self
    type(contact_set_t), intent(in) :: cs
    real(dp), intent(in) :: h
    logical, intent(in) :: massless
    logical, intent(out) :: is_onset               !< the first event is an onset (else a release)
    integer :: j
    logical :: unilateral, active, trial, onset
    real(dp) :: smin, lambda, s
    theta = 0.0_dp
    is_onset = .false.
    smin = huge(1.0_dp)
    do j = 1, cs%n_conditions()
      call cs%row_state(j, unilateral, active, trial, lambda)
      if (.not. unilateral) cycle
      onset = .false.
      if (trial .and. .not. active) onset = .not. pair_held(self, j)
      if (onset) then
        s = onset_time(self, j, cs%gap(j), h)
        if (s < smin) is_onset = .true.
        smin = min(smin, s)
      end if
      if (trial .and. active .and. self%held_prev(j) .and. .not. massless) then
        s = release_time(self, j, lambda, h)
        if (s < smin) is_onset = .false.
        smin = min(smin, s)
      end if
    end do
    if (smin > h) return
    theta = smin / h
    if (theta < SPLIT_MIN .or. theta > 1.0_dp - SPLIT_MIN) theta = 0.0_dp
  end function locator_event_fraction

  !> Whether a condition between the same two bodies as condition j (an obstacle counting as body
  !> 0) was held at the step's start: j closing is then the contact spreading, not an onset.
  pure logical function pair_held(self, j) result(held)
    type(event_locator_t), intent(in) :: self
    integer, intent(in) :: j
    integer :: k, a, b
    a = minval(self%cbody(:, j))
    b = maxval(self%cbody(:, j))
    held = .false.
    do k = 1, size(self%held_now)
      if (.not. self%held_now(k)) cycle
      if (minval(self%cbody(:, k)) == a .and. maxval(self%cbody(:, k)) == b) then
        held = .true.
        return
      end if
    end do
  end function pair_held

  !> The first root in (0, h] of condition j's gap g(s) (huge: none).
  pure real(dp) function onset_time(self, j, g, h) result(s)
    type(event_locator_t), intent(in) :: self
    integer, intent(in) :: j
    real(dp), intent(in) :: g, h
    real(dp) :: r, a, disc, den
    s = huge(1.0_dp)
    if (.not. (g > 0.0_dp)) return                   ! closed at the start: nothing to locate
    r = self%rate(j)
    a = 0.0_dp
    if (self%open_prev(j) .and. self%h_prev > 0.0_dp) a = (self%rate(j) - self%rate_prev(j)) / self%h_prev
    disc = r * r - 2.0_dp * a * g
    if (disc < 0.0_dp) return
    den = -r + sqrt(disc)
    if (.not. (den > 0.0_dp)) return
    s = 2.0_dp * g / den
    if (.not. (s > 0.0_dp .and. s <= h)) s = huge(1.0_dp)
  end function onset_time

  !> The zero in (0, h) of held condition j's force, extrapolated from the previous step's
  !> multiplier and this step's trial lambda (huge: none).
  pure real(dp) function release_time(self, j, lambda, h) result(s)
    type(event_locator_t), intent(in) :: self
    integer, intent(in) :: j
    real(dp), intent(in) :: lambda, h
    real(dp) :: lp
    s = huge(1.0_dp)
    lp = self%lam(j)
    if (.not. (lambda > 0.0_dp .and. lp > lambda .and. self%h_prev > 0.0_dp)) return
    s = 0.5_dp * h + lambda * 0.5_dp * (self%h_prev + h) / (lp - lambda)
    if (.not. (s > 0.0_dp .and. s < h)) s = huge(1.0_dp)
  end function release_time

  !> The histories into a checkpoint (a restart locates as the run would have).
  subroutine locator_save(self, ck, stat, errmsg)
    class(event_locator_t), intent(in) :: self
    type(ckpt_file_t), intent(inout) :: ck
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call ck%put('events_started', merge(1, 0, self%started), stat, errmsg)
    call ck%put('events_located', self%located, stat, errmsg)
    if (.not. self%started) return
    call ck%put('events_rate', self%rate, stat, errmsg)
    call ck%put('events_multiplier', self%lam, stat, errmsg)
    call ck%put('events_open', merge(1, 0, self%open_now), stat, errmsg)
    call ck%put('events_held', merge(1, 0, self%held_now), stat, errmsg)
    call ck%put('events_h', self%h_now, stat, errmsg)
  end subroutine locator_save

  !> What locator_save wrote, for nc conditions.
  subroutine locator_load(self, ck, nc, stat, errmsg)
    class(event_locator_t), intent(inout) :: self
    type(ckpt_file_t), intent(inout) :: ck
    integer, intent(in) :: nc
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer :: flags(nc), started
    started = 0
    call ck%get('events_started', started, stat, errmsg)
    call ck%get('events_located', self%located, stat, errmsg)
    self%started = started == 1 .and. allocated(self%rate)
    if (self%started) self%started = size(self%rate) == nc   ! (no size of an unallocated array: -fcheck)
    if (.not. self%started) return
    call ck%get('events_rate', self%rate, stat, errmsg)
    call ck%get('events_multiplier', self%lam, stat, errmsg)
    call ck%get('events_open', flags, stat, errmsg)
    self%open_now = flags == 1
    call ck%get('events_held', flags, stat, errmsg)
    self%held_now = flags == 1
    call ck%get('events_h', self%h_now, stat, errmsg)
  end subroutine locator_load
end module event_location
