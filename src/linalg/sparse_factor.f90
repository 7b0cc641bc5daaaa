!> What every sparse SPD factorization offers the code above linalg (cholmod_binding's
!> cholmod_factor_t, mumps_binding's mumps_factor_t; spd_factor holds one of them): the abstract
!> type sparse_factor_t, the report of its analysis (factor_stats_t) and the orderings' names.
module sparse_factor
  use kinds, only: dp
  use sparse_matrix, only: sym_csc_t
  implicit none
  private
  public :: sparse_factor_t, factor_stats_t, ORDERING_NAMES

  !> The fill-reducing orderings a factor's analysis may use (factor_stats_t%ordering): CHOLMOD's
  !> (1-3), MUMPS's (1, 2, 4-7) and a parallel analysis of MUMPS (8).
  character(len=*), parameter :: ORDERING_NAMES(8) = [character(len=35) :: 'AMD', 'METIS', &
    'nested dissection of supervariables', 'AMF', 'SCOTCH', 'PORD', 'QAMD', 'parallel (PT-Scotch or ParMETIS)']

  !> What a factor's analysis made, for reports (zeros before the first factorization).
  type :: factor_stats_t
    real(dp) :: nnz = 0.0_dp                 !< nonzeros of L
    real(dp) :: stored = 0.0_dp              !< entries stored (supernodal blocks)
    real(dp) :: flops = 0.0_dp               !< of a numeric factorization
    real(dp) :: analysis_cpu = 0.0_dp        !< CPU seconds of the ordering and symbolic analysis
    integer :: ordering = 0                  !< index in ORDERING_NAMES
    logical :: supernodal = .false.
  end type factor_stats_t

  !> A factorization of a symmetric positive definite sym_csc_t matrix: factorize (the first call
  !> analyses the pattern, later ones with the same pattern refactorize; not positive definite:
  !> stat = STAT_RUN, minor the failing column where the library says it, else 0), solve (no
  !> allocation of ours after the first), the costs of a factorization and a solve, destroy; the
  !> library's name, the processes it runs on (1 unless it says) and its own estimates of its cost
  !> (none unless it has them).
  type, abstract :: sparse_factor_t
  contains
    procedure(name_i), deferred :: name
    procedure :: ranks => one_rank
    procedure :: estimates => no_estimates
    procedure(factorize_i), deferred :: factorize
    procedure(solve_i), deferred :: solve
    procedure(logical_i), deferred :: is_factored
    procedure(real_i), deferred :: cost_ratio
    procedure(real_i), deferred :: solve_flops
    procedure(stats_i), deferred :: stats
    procedure(destroy_i), deferred :: destroy
  end type sparse_factor_t

  abstract interface
    function name_i(self) result(s)
      import :: sparse_factor_t
      class(sparse_factor_t), intent(in) :: self
      character(len=:), allocatable :: s
    end function name_i
    subroutine factorize_i(self, pat, values, stat, errmsg, minor)
      import :: sparse_factor_t, sym_csc_t, dp
      class(sparse_factor_t), intent(inout) :: self
      type(sym_csc_t), intent(in) :: pat
      real(dp), intent(in), contiguous :: values(:)
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
      integer, intent(out), optional :: minor
    end subroutine factorize_i
    subroutine solve_i(self, b, x, stat, errmsg)
      import :: sparse_factor_t, dp
      class(sparse_factor_t), intent(inout) :: self
      real(dp), intent(in), contiguous :: b(:)
      real(dp), intent(out), contiguous :: x(:)
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine solve_i
    logical function logical_i(self)
      import :: sparse_factor_t
      class(sparse_factor_t), intent(in) :: self
    end function logical_i
    real(dp) function real_i(self)
      import :: sparse_factor_t, dp
      class(sparse_factor_t), intent(in) :: self
    end function real_i
    function stats_i(self) result(s)
      import :: sparse_factor_t, factor_stats_t
      class(sparse_factor_t), intent(in) :: self
      type(factor_stats_t) :: s
    end function stats_i
    subroutine destroy_i(self)
      import :: sparse_factor_t
      class(sparse_factor_t), intent(inout) :: self
    end subroutine destroy_i
  end interface

contains

  !> A library that runs in this process alone.
  integer function one_rank(self)
    class(sparse_factor_t), intent(in) :: self
    one_rank = 1
  end function one_rank

  !> A library without estimates of its own (mumps_binding's mf_estimates lists what they are).
  function no_estimates(self) result(e)
    class(sparse_factor_t), intent(in) :: self
    real(dp) :: e(6)
    e = 0.0_dp
  end function no_estimates
end module sparse_factor
