!> The matrix the iteration of eq (9) solves with, and its policy (docs/input.md, SCHEME
!> ITERATION): ELASTIC keeps S = K0 + 4M/h², factorized once per step size (eq (7) for linear
!> elasticity: then the first iterate is exact); TANGENT refactorizes with the consistent
!> tangent Kt + 4M/h² of the latest iterate, and falls back to K0 + 4M/h² for the rest of a step
!> where the tangent stalls (a point switching between plastic loading and elastic unloading
!> from one iterate to the next: two iterates in a row without progress).
module iteration_matrix
  use kinds, only: dp
  use errors, only: STAT_OK
  use assembly, only: system_t
  use cholmod_binding, only: cholmod_factor_t
  implicit none
  private
  public :: iteration_matrix_t

  type :: iteration_matrix_t
    private
    type(cholmod_factor_t), public :: factor     !< CHOLMOD factor of the current S (contact solves with it)
    real(dp), allocatable, public :: sval(:)     !< values of S on the system's pattern (read only)
    real(dp) :: c4 = 0.0_dp                      !< 4/h²
    real(dp) :: h = 0.0_dp                       !< the step
    logical :: tangent = .false.                 !< ITERATION TANGENT
    logical :: fallback = .false.                !< this step went back to K0 + 4M/h²
  contains
    procedure :: setup => mat_setup
    procedure :: step => mat_step
    procedure :: begin_step => mat_begin_step
    procedure :: update => mat_update
    procedure :: check_stall => mat_check_stall
    procedure :: solve => mat_solve
    procedure :: destroy => mat_destroy
  end type iteration_matrix_t

contains

  !> S = K0 + 4M/h² factorized; minor: the failing column when S is singular.
  subroutine mat_setup(self, sys, h, stat, errmsg, minor)
    class(iteration_matrix_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: h
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, intent(out) :: minor
    self%c4 = 4.0_dp / h**2
    self%tangent = allocated(sys%ops%tval)
    self%fallback = .false.
    self%h = h
    call step_matrix(self, sys, sys%ops%kval)
    call self%factor%factorize(sys%ops%pat, self%sval, stat, errmsg, minor)
  end subroutine mat_setup

  !> S = K + 4M/h² + 2C/h on the shared pattern (K: K0 or the tangent; C: Rayleigh damping, whose
  !> trapezoid term ½C (v(n) + v(n+1)) = C du/h enters eq (9), multiplied by 2, as 2C du/h).
  subroutine step_matrix(self, sys, kvals)
    type(iteration_matrix_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: kvals(:)
    if (allocated(sys%ops%cval)) then
      self%sval = kvals + self%c4 * sys%ops%mval + (2.0_dp / self%h) * sys%ops%cval
    else
      self%sval = kvals + self%c4 * sys%ops%mval
    end if
  end subroutine step_matrix

  !> The step h of the current S (0 before setup).
  pure real(dp) function mat_step(self)
    class(iteration_matrix_t), intent(in) :: self
    mat_step = self%h
  end function mat_step

  pure subroutine mat_begin_step(self)
    class(iteration_matrix_t), intent(inout) :: self
    self%fallback = .false.
  end subroutine mat_begin_step

  !> Before each solve: with TANGENT (and no fallback in this step) refactorize with the
  !> tangent of the latest state; refactored tells that S changed.
  subroutine mat_update(self, sys, refactored, stat, errmsg)
    class(iteration_matrix_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    logical, intent(out) :: refactored
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    refactored = self%tangent .and. .not. self%fallback
    if (.not. refactored) return
    call step_matrix(self, sys, sys%ops%tval)
    call self%factor%factorize(sys%ops%pat, self%sval, stat, errmsg)
  end subroutine mat_update

  !> After the residual of iteration iter (res(1:iter) the norms so far): the TANGENT fallback.
  !> One iterate without progress is normal for Newton near a collapse; two in a row, from the
  !> fourth iterate on, switch to K0 + 4M/h², which contracts monotonically, for the rest of the
  !> step (refactored tells that S changed).
  subroutine mat_check_stall(self, sys, res, iter, refactored, stat, errmsg)
    class(iteration_matrix_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: res(:)
    integer, intent(in) :: iter
    logical, intent(out) :: refactored
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    refactored = .false.
    if (.not. self%tangent .or. self%fallback .or. iter < 4) return
    if (res(iter) >= 0.99_dp * res(iter - 1) .and. res(iter - 1) >= 0.99_dp * res(iter - 2)) then
      self%fallback = .true.
      refactored = .true.
      call step_matrix(self, sys, sys%ops%kval)
      call self%factor%factorize(sys%ops%pat, self%sval, stat, errmsg)
    end if
  end subroutine mat_check_stall

  !> x = S⁻¹ b.
  subroutine mat_solve(self, b, x, stat, errmsg)
    class(iteration_matrix_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: b(:)
    real(dp), intent(out), contiguous :: x(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call self%factor%solve(b, x, stat, errmsg)
  end subroutine mat_solve

  subroutine mat_destroy(self)
    class(iteration_matrix_t), intent(inout) :: self
    call self%factor%destroy()
  end subroutine mat_destroy
end module iteration_matrix
