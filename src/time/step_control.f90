!> The adaptive step (TIME … ADAPTIVE TOLERANCE tol [MIN hmin] [MAX hmax], docs/input.md and
!> docs/accuracy-speed.md): the local error of each step estimated, the step accepted or taken
!> again at half its length, the next one's length chosen. Every step, whatever its length, is
!> the energy-exact step of eq (9).
!>
!> Estimate (Zienkiewicz and Xie, Earthquake Eng. Struct. Dyn. 20 (1991) 871-887): the local
!> displacement error of Newmark's step is (β − 1/6) h² (a(n+1) − a(n)), h²/12 (a(n+1) − a(n)) for
!> the average acceleration. The accelerations are not carried; the change is taken from the mean
!> accelerations of this step and the last, ā = (v(n+1) − v(n))/h = 2 (Δu/h − v(n))/h (eq 3):
!>     a(n+1) − a(n) ≈ h (ā − ā_prev) / ((h + h_prev)/2),
!>     e = h³ (ā − ā_prev) / (6 (h + h_prev)),   η = ‖e‖_M / max_k ‖u(k)‖_M,
!> in the mass norm ‖x‖_M = √(x'Mx) (displacements and rotations weighed by their inertia), against
!> the largest displacement of the run so far (the current one would make a vibration's steps
!> short at each zero crossing: measured, 1.6 times the steps of a fixed run at its error). For a
!> vibration of frequency ω, η is about (ω h)²/12 times its amplitude's share of the scale: the
!> trapezoid rule's relative period error per step, so TOLERANCE reads as a relative phase error.
!> A step whose contact set changes (an impact or a release, a velocity jump the estimate would
!> take for an error) is not judged, nor is the step after it.
!>
!> Control: steps are STEP × 2^k within [MIN, MAX] (S at each length factorized at its first use
!> and kept: run_state's levels). A step with η > tol is taken again at h/2 while h/2 ≥ MIN;
!> after three accepted steps with η ≤ tol/4 (doubling multiplies η by about 4: the doubled step
!> stays within tol) the step doubles while 2h ≤ MAX; after a contact event it goes
!> back to STEP at most, and after an onset to STEP/32 (contact events are located on a step's end
!> under ADAPTIVE, and the step after an onset holds the contact for its whole length). A step that fails to converge
!> is halved the same way (SCHEME RETRY's sub-steps only below MIN), and its length is not tried
!> again for 50 steps (12 after a rejection by the estimate). The kinks of the scene's
!> functions (table points, a SINE's or SMOOTH_STEP's start and finish) are step ends.
module step_control
  use kinds, only: dp
  use scene, only: scene_t, FN_TABLE
  use assembly, only: system_t, mass_times
  use checkpoint, only: ckpt_file_t
  use array_utils, only: stable_order
  implicit none
  private
  public :: step_controller_t

  integer, parameter :: GROW_AFTER = 3          !< accepted steps with η ≤ GROW_MARGIN tol before doubling
  real(dp), parameter :: GROW_MARGIN = 0.25_dp
  integer, parameter :: HOLD_AFTER_FAIL = 50    !< steps before a length that failed is tried again
  integer, parameter :: HOLD_AFTER_REJECT = 12  !< steps before a length rejected by the estimate is tried again
  !> The step after a located onset, STEP/32 (or MIN): it holds the contact for its whole length,
  !> the onset's error in time; shorter, the closing step's multipliers (~ m v/h) amplify the gap's
  !> round-off in the energy balance (STEP/1024 on inputs/beam_drop_vertical.dat: 1e-10 of E).
  real(dp), parameter :: DWELL_FRACTION = 32.0_dp

  type :: step_controller_t
    private
    logical, public :: on = .false.
    real(dp), public :: tol = 0.0_dp, hmin = 0.0_dp, hmax = 0.0_dp
    real(dp), allocatable :: abar(:), anew(:), anew2(:), e(:), me(:)   !< ā of the last judged step; scratch
    real(dp) :: h_prev = 0.0_dp                 !< its length (0: no ā to compare with)
    real(dp), public :: eta = 0.0_dp            !< the last estimate
    real(dp) :: u_scale = 0.0_dp                !< the largest ‖u‖_M² of the accepted steps (η's scale)
    real(dp) :: u_norm = 0.0_dp                 !< ‖u(n+1)‖_M² of the last judged trial
    logical :: judged = .false.                 !< the last attempt was judged (anew holds its ā)
    logical :: measured = .false.               !< and had a previous ā to be compared with (η computed)
    integer :: streak = 0
    !> After a step failed at length h_fail, no growth to h_fail or beyond for HOLD_AFTER_FAIL steps.
    real(dp) :: h_fail = huge(1.0_dp)
    integer :: hold = 0
    real(dp), allocatable :: kinks(:)           !< the functions' kinks inside the run, increasing
    integer, public :: rejected = 0, grown = 0, shrunk = 0, at_min = 0
  contains
    procedure :: init => ctl_init
    procedure :: judge => ctl_judge
    procedure :: accepted => ctl_accepted
    procedure :: next_length => ctl_next_length
    procedure :: to_kink => ctl_to_kink
    procedure :: failed => ctl_failed
    procedure :: min_length => ctl_min_length
    procedure :: can_halve => ctl_can_halve
    procedure :: save => ctl_save
    procedure :: load => ctl_load
  end type step_controller_t

contains

  !> For n equations, the scene's tolerance, bounds and function kinks.
  subroutine ctl_init(self, scn, n)
    class(step_controller_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    integer, intent(in) :: n
    real(dp), allocatable :: t(:)
    integer :: i
    self%on = scn%adaptive
    if (.not. self%on) return
    self%tol = scn%adapt_tol
    self%hmin = scn%adapt_hmin
    self%hmax = scn%adapt_hmax
    allocate (self%abar(n), self%anew(n), self%anew2(n), self%e(n), self%me(n))
    self%abar = 0.0_dp
    allocate (t(0))
    do i = 1, size(scn%functions)
      associate (f => scn%functions(i))
        if (f%kind == FN_TABLE) then
          t = [t, f%t]
        else
          t = [t, f%start, f%finish]
        end if
      end associate
    end do
    t = pack(t, t > scn%t_start .and. t < scn%t_end)
    call sort_unique(t)
    self%kinks = t
  end subroutine ctl_init

  !> Sorted, duplicates dropped (a few kinks).
  pure subroutine sort_unique(t)
    real(dp), allocatable, intent(inout) :: t(:)
    integer :: i, n
    integer :: idx(size(t))
    idx = [(i, i = 1, size(t))]
    call stable_order(t, idx)
    t = t(idx)
    n = min(size(t), 1)
    do i = 2, size(t)
      if (t(i) > t(n)) then
        n = n + 1
        t(n) = t(i)
      end if
    end do
    t = t(1:n)
  end subroutine sort_unique

  !> The converged trial of a step of length h from velocity v with increment du: η, and whether
  !> it is to be taken again at h/2 (η > tol and h/2 ≥ MIN). judgeable: the step leaves the
  !> contact set as it was (else it is accepted unjudged).
  logical function ctl_judge(self, sys, u, du, v, h, judgeable) result(again)
    class(step_controller_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: u(:), du(:), v(:), h
    logical, intent(in) :: judgeable
    real(dp) :: num, den
    again = .false.
    self%judged = judgeable
    self%measured = .false.
    self%eta = 0.0_dp
    if (.not. judgeable) return
    self%anew = 2.0_dp * (du / h - v) / h
    self%anew2 = u + du
    call mass_times(sys, self%anew2, self%me)
    self%u_norm = dot_product(self%anew2, self%me)
    if (self%h_prev <= 0.0_dp) return
    self%measured = .true.
    self%e = (h**3 / (6.0_dp * (h + self%h_prev))) * (self%anew - self%abar)
    call mass_times(sys, self%e, self%me)
    num = dot_product(self%e, self%me)
    den = max(self%u_norm, self%u_scale)
    if (num > 0.0_dp) self%eta = sqrt(num / max(den, tiny(1.0_dp)))
    again = self%eta > self%tol .and. self%can_halve(h)
    if (again) then
      self%rejected = self%rejected + 1
      ! Not back to h for HOLD_AFTER_REJECT steps (no doubling and rejection in turn).
      self%h_fail = h
      self%hold = max(self%hold, HOLD_AFTER_REJECT)
    end if
  end function ctl_judge

  !> The step of length h was committed; full: at the controller's length (not cut short at a kink
  !> or an event), judged by the last ctl_judge.
  subroutine ctl_accepted(self, h, full)
    class(step_controller_t), intent(inout) :: self
    real(dp), intent(in) :: h
    logical, intent(in) :: full
    if (self%judged) self%u_scale = max(self%u_scale, self%u_norm)
    if (full .and. self%judged) then
      self%abar = self%anew
      self%h_prev = h
      if (self%eta > self%tol) self%at_min = self%at_min + 1
    else
      self%h_prev = 0.0_dp                      ! no mean acceleration to compare the next step with
    end if
    if (full .and. self%judged .and. self%measured .and. self%eta <= GROW_MARGIN * self%tol) then
      self%streak = self%streak + 1
    else
      self%streak = 0
    end if
    self%judged = .false.
  end subroutine ctl_accepted

  !> The length of the next step after one of length h: doubled after GROW_AFTER quiet steps;
  !> after a contact event (the step established or released a contact, or was cut at one) at most
  !> base, TIME STEP, and after a located onset STEP/32 (MIN if larger): the step that closes a
  !> located contact holds it for its whole length (the trapezoid rule's contact step), and that
  !> dwell is the onset's error in time.
  real(dp) function ctl_next_length(self, h, event, onset, base) result(hn)
    class(step_controller_t), intent(inout) :: self
    real(dp), intent(in) :: h, base
    logical, intent(in) :: event, onset
    hn = h
    if (event) then
      self%streak = 0
      if (h > base) hn = base
      if (onset) hn = max(self%min_length(base), base / DWELL_FRACTION)
      if (hn < h) self%shrunk = self%shrunk + 1
      return
    end if
    if (self%hold > 0) self%hold = self%hold - 1
    if (self%hold > 0 .and. 2.0_dp * h >= self%h_fail * (1.0_dp - 1.0e-12_dp)) return
    if (self%streak >= GROW_AFTER .and. 2.0_dp * h <= self%hmax * (1.0_dp + 1.0e-12_dp)) then
      hn = 2.0_dp * h
      self%streak = 0
      self%grown = self%grown + 1
    end if
  end function ctl_next_length

  !> Whether h/2 is still a length of the controller (≥ MIN, to rounding).
  pure logical function ctl_can_halve(self, h)
    class(step_controller_t), intent(in) :: self
    real(dp), intent(in) :: h
    ctl_can_halve = 0.5_dp * h >= self%hmin * (1.0_dp - 1.0e-12_dp)
  end function ctl_can_halve

  !> The shortest step, base 2^k ≥ MIN.
  pure real(dp) function ctl_min_length(self, base) result(h)
    class(step_controller_t), intent(in) :: self
    real(dp), intent(in) :: base
    h = base
    do while (self%can_halve(h))
      h = 0.5_dp * h
    end do
  end function ctl_min_length

  !> A step of length h failed to converge (it is taken again at h/2): h is not tried again for
  !> HOLD_AFTER_FAIL steps (no growth and failure in turn).
  subroutine ctl_failed(self, h)
    class(step_controller_t), intent(inout) :: self
    real(dp), intent(in) :: h
    self%h_fail = h
    self%hold = HOLD_AFTER_FAIL
    self%streak = 0
  end subroutine ctl_failed

  !> The step from t0 of length h cut at the first kink inside it (h itself when none).
  pure real(dp) function ctl_to_kink(self, t0, h) result(hs)
    class(step_controller_t), intent(in) :: self
    real(dp), intent(in) :: t0, h
    integer :: i
    hs = h
    if (.not. allocated(self%kinks)) return
    do i = 1, size(self%kinks)
      if (self%kinks(i) <= t0 + 1.0e-9_dp * h) cycle
      if (self%kinks(i) < t0 + h * (1.0_dp - 1.0e-9_dp)) hs = self%kinks(i) - t0
      return
    end do
  end function ctl_to_kink

  !> The controller's memory into a checkpoint (a restart steps as the run would have).
  subroutine ctl_save(self, ck, h, stat, errmsg)
    class(step_controller_t), intent(in) :: self
    type(ckpt_file_t), intent(inout) :: ck
    real(dp), intent(in) :: h
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    if (.not. self%on) return
    call ck%put('adaptive_h', h, stat, errmsg)
    call ck%put('adaptive_h_prev', self%h_prev, stat, errmsg)
    call ck%put('adaptive_h_fail', self%h_fail, stat, errmsg)
    call ck%put('adaptive_u_scale', self%u_scale, stat, errmsg)
    call ck%put('adaptive_abar', self%abar, stat, errmsg)
    call ck%put('adaptive_counts', [self%streak, self%rejected, self%grown, self%shrunk, self%at_min, self%hold], stat, errmsg)
  end subroutine ctl_save

  !> What ctl_save wrote; h the step to go on with.
  subroutine ctl_load(self, ck, h, stat, errmsg)
    class(step_controller_t), intent(inout) :: self
    type(ckpt_file_t), intent(inout) :: ck
    real(dp), intent(out) :: h
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer :: counts(6)
    h = 0.0_dp
    if (.not. self%on) return
    call ck%get('adaptive_h', h, stat, errmsg)
    call ck%get('adaptive_h_prev', self%h_prev, stat, errmsg)
    call ck%get('adaptive_h_fail', self%h_fail, stat, errmsg)
    call ck%get('adaptive_u_scale', self%u_scale, stat, errmsg)
    call ck%get('adaptive_abar', self%abar, stat, errmsg)
    call ck%get('adaptive_counts', counts, stat, errmsg)
    self%streak = counts(1)
    self%rejected = counts(2)
    self%grown = counts(3)
    self%shrunk = counts(4)
    self%at_min = counts(5)
    self%hold = counts(6)
  end subroutine ctl_load
end module step_control
