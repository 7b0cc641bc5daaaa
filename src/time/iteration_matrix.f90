!> The matrix the iteration of eq (9) solves with, and its policy (docs/input.md, SCHEME
!> ITERATION): ELASTIC keeps S = K0 + 4M/h², factorized once per step size (eq (7) for linear
!> elasticity: then the first iterate is exact); TANGENT refactorizes with the consistent
!> tangent Kt + 4M/h² of the latest iterate, and falls back to K0 + 4M/h² for the rest of a step
!> where the tangent stalls (a point switching between plastic loading and elastic unloading
!> from one iterate to the next: two iterates in a row without progress). AUTO keeps the S it
!> has (K0 + 4M/h² at first) while it contracts fast enough, and refactorizes with the tangent
!> of the latest iterate when the iterations it predicts cost more than a factorization and
!> the few Newton iterations after it (the factorization's cost in solves is CHOLMOD's flop
!> count over a solve's: deterministic, no clock); the new S is kept for the steps after. Where a
!> factorization costs at most one solve, AUTO is TANGENT.
module iteration_matrix
  use kinds, only: dp
  use errors, only: STAT_OK
  use assembly, only: system_t
  use spd_factor, only: spd_factor_t
  use checkpoint, only: ckpt_file_t
  implicit none
  private
  public :: iteration_matrix_t

  type :: iteration_matrix_t
    private
    type(spd_factor_t), public :: factor     !< CHOLMOD factor of the current S (contact solves with it)
    real(dp), allocatable, public :: sval(:)     !< values of S on the system's pattern (read only)
    real(dp) :: c4 = 0.0_dp                      !< 4/h²
    real(dp) :: h = 0.0_dp                       !< the step
    logical :: tangent = .false.                 !< ITERATION TANGENT
    logical :: fallback = .false.                !< this step went back to K0 + 4M/h²
    logical :: auto = .false.                    !< ITERATION AUTO
    logical :: refactor_next = .false.           !< AUTO: refactorize with the tangent at the next update
    logical :: on_tangent = .false.              !< AUTO: S is a tangent (not K0 + 4M/h²)
    integer :: since = 0                         !< AUTO: iterations since S changed in this step
    logical :: switched = .false.                !< AUTO: S became a tangent in this step
    real(dp) :: ratio = 0.0_dp                   !< AUTO: a factorization's cost in solves
    integer(8), public :: n_factor = 0           !< factorizations made (setup included)
    integer(8), public :: n_geometric_dropped = 0 !< tangents factorized again without their compressive geometric part
  contains
    procedure :: setup => mat_setup
    procedure :: begin_step => mat_begin_step
    procedure :: update => mat_update
    procedure :: after_residual => mat_after_residual
    procedure :: wants_tangent => mat_wants_tangent
    procedure :: on_tangent_now => mat_on_tangent
    procedure :: solve => mat_solve
    procedure :: save => mat_save
    procedure :: load => mat_load
    procedure :: destroy => mat_destroy
  end type iteration_matrix_t

contains

  !> S = K0 + 4M/h² factorized; minor: the failing column when S is singular. auto: ITERATION
  !> AUTO (with a tangent assembled; otherwise TANGENT when there is one).
  subroutine mat_setup(self, sys, h, stat, errmsg, minor, auto)
    class(iteration_matrix_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: h
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, intent(out) :: minor
    logical, intent(in), optional :: auto
    self%c4 = 4.0_dp / h**2
    self%auto = .false.
    if (present(auto)) self%auto = auto .and. allocated(sys%ops%tval)
    self%tangent = allocated(sys%ops%tval) .and. .not. self%auto
    self%fallback = .false.
    self%refactor_next = .false.
    self%on_tangent = .false.
    self%h = h
    call step_matrix(self, sys, sys%ops%kval)
    call self%factor%factorize(sys%ops%pat, self%sval, stat, errmsg, minor)
    self%n_factor = self%n_factor + 1
    if (stat == STAT_OK) self%ratio = self%factor%cost_ratio()
    ! A factorization that costs at most one solve (a system of a few equations): Newton's
    ! iterations save more than their refactorizations cost, so AUTO is TANGENT there (measured on
    ! spring_nonlinear: 8662 iterations at 7e-13 of E against 12108 at 6e-11 on K0 + 4M/h²).
    if (self%auto .and. self%ratio <= 1.0_dp) then
      self%auto = .false.
      self%tangent = .true.
    end if
  end subroutine mat_setup

  !> S = K + 4M/h² + 2C/h on the shared pattern (K: K0 or the tangent; C: Rayleigh damping, whose
  !> trapezoid term ½C (v(n) + v(n+1)) = C du/h enters eq (9), multiplied by 2, as 2C du/h).
  subroutine step_matrix(self, sys, kvals, gvals)
    type(iteration_matrix_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: kvals(:)
    real(dp), intent(in), optional :: gvals(:)    !< added to K (the compressive geometric stiffness)
    if (allocated(sys%ops%cval)) then
      self%sval = kvals + self%c4 * sys%ops%mval + (2.0_dp / self%h) * sys%ops%cval
    else
      self%sval = kvals + self%c4 * sys%ops%mval
    end if
    if (present(gvals)) self%sval = self%sval + gvals
  end subroutine step_matrix

  pure subroutine mat_begin_step(self)
    class(iteration_matrix_t), intent(inout) :: self
    self%fallback = .false.
    self%since = 0
    self%switched = .false.
  end subroutine mat_begin_step

  !> Whether the next trial state should assemble the tangent: TANGENT, or AUTO about to
  !> refactorize.
  pure logical function mat_wants_tangent(self)
    class(iteration_matrix_t), intent(in) :: self
    mat_wants_tangent = self%tangent .or. self%refactor_next
  end function mat_wants_tangent

  !> Whether the S of the last solve was a tangent (TANGENT, or AUTO after a switch), not K0 + 4M/h².
  pure logical function mat_on_tangent(self)
    class(iteration_matrix_t), intent(in) :: self
    mat_on_tangent = (self%tangent .or. self%on_tangent) .and. .not. self%fallback
  end function mat_on_tangent

  !> ITERATION AUTO, after the residual res(iter) of an iterate that did not converge (target:
  !> the converged residual): refactorize with the tangent when the contraction of the last two
  !> residuals predicts more iterations than a factorization and 3 Newton iterations cost
  !> (a divergence predicts infinitely many). A tangent factorized in this step whose first
  !> iterate does not lower the residual (a point switching between plastic loading and elastic
  !> unloading makes Newton cycle) sends the step back to K0 + 4M/h², which contracts
  !> monotonically (as TANGENT's fallback). switch: the caller assembles the tangent at this
  !> iterate (the next update factorizes it).
  subroutine mat_consider(self, sys, res, iter, target, switch, refactored, stat, errmsg)
    type(iteration_matrix_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: res(:), target
    integer, intent(in) :: iter
    logical, intent(out) :: switch, refactored
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: rho, predicted
    stat = STAT_OK
    switch = .false.
    refactored = .false.
    if (.not. self%auto .or. self%fallback .or. iter < 2) return
    self%since = self%since + 1
    rho = res(iter) / max(res(iter - 1), tiny(1.0_dp))
    if (self%switched .and. self%since == 1 .and. rho >= 0.99_dp .and. .not. sys%elems%any_large) then
      refactored = .true.
      call fall_back(self, sys, stat, errmsg)
      return
    end if
    if (self%since < 2) return
    if (rho >= 1.0_dp) then
      predicted = huge(1.0_dp)
    else
      predicted = log(target / res(iter)) / log(rho)
    end if
    if (predicted > 3.0_dp + self%ratio) then
      switch = .true.
      self%refactor_next = .true.
    end if
  end subroutine mat_consider

  !> Before each solve: with TANGENT (and no fallback in this step) refactorize with the
  !> tangent of the latest state; refactored tells that S changed.
  subroutine mat_update(self, sys, refactored, stat, errmsg)
    class(iteration_matrix_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    logical, intent(out) :: refactored
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    refactored = (self%tangent .and. .not. self%fallback) .or. self%refactor_next
    if (.not. refactored) return
    call step_matrix(self, sys, sys%ops%tval, sys%ops%gval)
    call self%factor%factorize(sys%ops%pat, self%sval, stat, errmsg)
    self%n_factor = self%n_factor + 1
    if (stat /= STAT_OK .and. allocated(sys%ops%gval)) then
      ! The compressive geometric stiffness made S indefinite (a far iterate, a buckling member):
      ! the tangent without it, positive definite.
      self%n_geometric_dropped = self%n_geometric_dropped + 1
      call step_matrix(self, sys, sys%ops%tval)
      call self%factor%factorize(sys%ops%pat, self%sval, stat, errmsg)
      self%n_factor = self%n_factor + 1
    end if
    if (self%refactor_next) then
      self%refactor_next = .false.
      self%on_tangent = .true.
      self%switched = .true.
      self%since = 0
      if (stat /= STAT_OK .and. .not. sys%elems%any_large) then
        ! AUTO: a tangent that is not positive definite (a far iterate, a member in compression)
        ! is not used: K0 + 4M/h² for the rest of the step.
        call fall_back(self, sys, stat, errmsg)
      end if
    end if
  end subroutine mat_update

  !> After the residual of iteration iter (res(1:iter) the norms so far): the TANGENT fallback.
  !> One iterate without progress is normal for Newton near a collapse; two in a row, from the
  !> fourth iterate on, switch to K0 + 4M/h², which contracts monotonically, for the rest of the
  !> step (refactored tells that S changed).
  subroutine mat_check_stall(self, sys, res, iter, refactored, stat, errmsg)
    type(iteration_matrix_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: res(:)
    integer, intent(in) :: iter
    logical, intent(out) :: refactored
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    refactored = .false.
    ! (KINEMATICS LARGE: K0 + 4M/h² holds the reference axes, which a rotated member has left:
    ! no fallback; a stalled step ends in MAX_ITERATIONS and SCHEME RETRY.)
    if (.not. self%tangent .or. self%fallback .or. iter < 4 .or. sys%elems%any_large) return
    if (res(iter) >= 0.99_dp * res(iter - 1) .and. res(iter - 1) >= 0.99_dp * res(iter - 2)) then
      refactored = .true.
      call fall_back(self, sys, stat, errmsg)
    end if
  end subroutine mat_check_stall

  !> After the residual res(iter) of an iterate that did not converge (target: the converged
  !> residual): the policy's reaction, TANGENT's stall fallback or AUTO's choice (refactored: S
  !> changed; switch: the caller assembles the tangent at this iterate for the next update).
  subroutine mat_after_residual(self, sys, res, iter, target, switch, refactored, stat, errmsg)
    class(iteration_matrix_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: res(:), target
    integer, intent(in) :: iter
    logical, intent(out) :: switch, refactored
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    switch = .false.
    if (self%auto) then
      call mat_consider(self, sys, res, iter, target, switch, refactored, stat, errmsg)
    else
      call mat_check_stall(self, sys, res, iter, refactored, stat, errmsg)
    end if
  end subroutine mat_after_residual

  !> TANGENT's and AUTO's fallback: K0 + 4M/h² factorized for the rest of the step.
  subroutine fall_back(self, sys, stat, errmsg)
    type(iteration_matrix_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    self%fallback = .true.
    self%on_tangent = .false.
    call step_matrix(self, sys, sys%ops%kval)
    call self%factor%factorize(sys%ops%pat, self%sval, stat, errmsg)
    self%n_factor = self%n_factor + 1
  end subroutine fall_back

  !> x = S⁻¹ b.
  subroutine mat_solve(self, b, x, stat, errmsg)
    class(iteration_matrix_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: b(:)
    real(dp), intent(out), contiguous :: x(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call self%factor%solve(b, x, stat, errmsg)
  end subroutine mat_solve

  !> AUTO carries S from step to step: a tangent S goes to the checkpoint (its values), so that
  !> a restart iterates with the same matrix (bit for bit). ELASTIC and TANGENT need nothing.
  subroutine mat_save(self, ck, stat, errmsg)
    class(iteration_matrix_t), intent(in) :: self
    type(ckpt_file_t), intent(inout) :: ck
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    if (.not. self%auto) return
    call ck%put('iteration_on_tangent', merge(1, 0, self%on_tangent), stat, errmsg)
    if (self%on_tangent) call ck%put('iteration_s', self%sval, stat, errmsg)
  end subroutine mat_save

  !> After setup: the S of mat_save factorized again when it was a tangent.
  subroutine mat_load(self, sys, ck, stat, errmsg)
    class(iteration_matrix_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    type(ckpt_file_t), intent(inout) :: ck
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer :: flag
    if (.not. self%auto .or. stat /= STAT_OK) return
    call ck%get('iteration_on_tangent', flag, stat, errmsg)
    if (stat /= STAT_OK .or. flag == 0) return
    call ck%get('iteration_s', self%sval, stat, errmsg)
    if (stat /= STAT_OK) return
    call self%factor%factorize(sys%ops%pat, self%sval, stat, errmsg)
    self%n_factor = self%n_factor + 1
    self%on_tangent = stat == STAT_OK
  end subroutine mat_load

  subroutine mat_destroy(self)
    class(iteration_matrix_t), intent(inout) :: self
    call self%factor%destroy()
  end subroutine mat_destroy
end module iteration_matrix
