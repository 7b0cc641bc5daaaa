!> x = A⁻¹ b for a fixed SPD matrix A, behind one abstract type: a CHOLMOD factor (owned) or
!> the scene's factor of S (borrowed), a diagonal, or any test double. Used by contact for S⁻¹ (S = K0 + 4M/h²) and M⁻¹.
module inverse_ops
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use cholmod_binding, only: cholmod_factor_t
  use spd_factor, only: spd_factor_t
  implicit none
  private
  public :: inverse_op_t, diag_inverse_t, chol_inverse_t, chol_ref_t

  type, abstract :: inverse_op_t
  contains
    procedure(inverse_apply), deferred :: apply
  end type inverse_op_t

  abstract interface
    subroutine inverse_apply(self, b, x, stat, errmsg)
      import :: inverse_op_t, dp
      class(inverse_op_t), intent(inout) :: self
      real(dp), intent(in), contiguous :: b(:)
      real(dp), intent(out), contiguous :: x(:)
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine inverse_apply
  end interface

  !> Diagonal (lumped) matrix: x = b / d. A zero d_i is allowed where b_i = 0 (massless DOFs
  !> that no contact touches).
  type, extends(inverse_op_t) :: diag_inverse_t
    real(dp), allocatable :: d(:)
  contains
    procedure :: apply => diag_apply
  end type diag_inverse_t

  !> Owns a CHOLMOD factor (used for a consistent mass matrix); call f%destroy() when done.
  type, extends(inverse_op_t) :: chol_inverse_t
    type(cholmod_factor_t) :: f
    !> The mass of the equations whose row of the matrix has no off-diagonal entry (the inverse is
    !> 1/dloc there: the contact nodes' rows IMPACT SYMMETRIC lumps), 0 on the others.
    real(dp), allocatable :: dloc(:)
  contains
    procedure :: apply => chol_apply
  end type chol_inverse_t

  !> Borrows the caller's factor of S (CHOLMOD or MUMPS) for the duration of one call.
  type, extends(inverse_op_t) :: chol_ref_t
    type(spd_factor_t), pointer :: f => null()
  contains
    procedure :: apply => chol_ref_apply
  end type chol_ref_t

contains

  subroutine diag_apply(self, b, x, stat, errmsg)
    class(diag_inverse_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: b(:)
    real(dp), intent(out), contiguous :: x(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: i
    stat = STAT_OK
    if (size(b) /= size(self%d) .or. size(x) /= size(b)) then
      call set_error(stat, errmsg, STAT_INPUT, 'diagonal inverse: size mismatch')
      return
    end if
    do i = 1, size(b)
      if (b(i) == 0.0_dp) then
        x(i) = 0.0_dp
      else if (self%d(i) > 0.0_dp) then
        x(i) = b(i) / self%d(i)
      else
        call set_error(stat, errmsg, STAT_INPUT, 'contact: equation ' // str(i) // &
          ' carries a contact condition but has no mass (lumped mass diagonal ' // str(self%d(i)) // ')')
        return
      end if
    end do
  end subroutine diag_apply

  subroutine chol_apply(self, b, x, stat, errmsg)
    class(chol_inverse_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: b(:)
    real(dp), intent(out), contiguous :: x(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call self%f%solve(b, x, stat, errmsg)
  end subroutine chol_apply

  subroutine chol_ref_apply(self, b, x, stat, errmsg)
    class(chol_ref_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: b(:)
    real(dp), intent(out), contiguous :: x(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call self%f%solve(b, x, stat, errmsg)
  end subroutine chol_ref_apply
end module inverse_ops
