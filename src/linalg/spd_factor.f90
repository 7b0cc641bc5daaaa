!> The direct solver of the scene's symmetric positive definite systems (S = K0 + 4M/h², its
!> tangents, K0 for a preload): CHOLMOD in one process (the default) or MUMPS on the scene's
!> communicator, one process or every rank of an mpirun (docs/input.md, SCHEME SOLVER;
!> docs/parallel.md). spd_factor_t holds either library's factor as a sparse_factor_t, so the time
!> loop, the contact Schur columns and the nonlinear zone see one type, and times its calls.
!>
!> Usage: call f%choose(library, out_of_core) before the first factorize (without it: CHOLMOD);
!> then factorize / solve / destroy as a sparse_factor_t's. Do not copy one; call destroy.
module spd_factor
  use kinds, only: dp
  use errors, only: STAT_RUN
  use sparse_matrix, only: sym_csc_t
  use sparse_factor, only: sparse_factor_t, factor_stats_t
  use cholmod_binding, only: cholmod_factor_t
  use mumps_binding, only: mumps_factor_t
  use parallel, only: parallel_start, scene_comm, scene_ranks
  implicit none
  private
  public :: spd_factor_t, factor_times_t, LIBRARY_AUTO, LIBRARY_CHOLMOD, LIBRARY_MUMPS

  !> SCHEME SOLVER's libraries: AUTO is MUMPS where the scene is shared by more than one rank.
  integer, parameter :: LIBRARY_AUTO = 1, LIBRARY_CHOLMOD = 2, LIBRARY_MUMPS = 3

  !> What the factor's calls cost this process (CPU) and the run (wall, the ranks' calls being
  !> collective): for the run's summary and the benches.
  type :: factor_times_t
    integer(8) :: factorizations = 0, solves = 0
    real(dp) :: factor_cpu = 0.0_dp, factor_wall = 0.0_dp, solve_cpu = 0.0_dp, solve_wall = 0.0_dp
  end type factor_times_t

  type :: spd_factor_t
    private
    class(sparse_factor_t), allocatable :: lib       !< the library's factor (CHOLMOD where not chosen)
    type(factor_times_t), public :: times
  contains
    procedure :: choose
    procedure :: library
    procedure :: ranks
    procedure :: estimates
    procedure :: factorize
    procedure :: solve
    procedure :: is_factored
    procedure :: cost_ratio
    procedure :: solve_flops
    procedure :: stats
    procedure :: destroy
  end type spd_factor_t

contains

  !> The library of SCHEME SOLVER (LIBRARY_*): MUMPS on the scene's communicator (MPI started for
  !> it in a single process), or CHOLMOD. Any earlier factor is freed.
  subroutine choose(self, library, out_of_core)
    class(spd_factor_t), intent(inout) :: self
    integer, intent(in) :: library
    logical, intent(in) :: out_of_core
    type(mumps_factor_t), allocatable :: mf
    call self%destroy()
    if (allocated(self%lib)) deallocate (self%lib)
    if (library == LIBRARY_MUMPS .or. (library == LIBRARY_AUTO .and. scene_ranks() > 1)) then
      call parallel_start(share=.false.)
      allocate (mf)
      call mf%settings(scene_comm(), out_of_core, '')
      call move_alloc(mf, self%lib)
    else
      allocate (cholmod_factor_t :: self%lib)
    end if
  end subroutine choose

  !> 'CHOLMOD' or 'MUMPS'.
  function library(self) result(s)
    class(spd_factor_t), intent(in) :: self
    character(len=:), allocatable :: s
    s = 'CHOLMOD'
    if (allocated(self%lib)) s = self%lib%name()
  end function library

  !> The processes a factorization and a solve run on.
  integer function ranks(self)
    class(spd_factor_t), intent(in) :: self
    ranks = 1
    if (allocated(self%lib)) ranks = self%lib%ranks()
  end function ranks

  !> The library's estimates (mumps_binding's mf_estimates: flops, factor entries, MB per rank and
  !> in all, in core and out of core); zeros with CHOLMOD.
  function estimates(self) result(e)
    class(spd_factor_t), intent(in) :: self
    real(dp) :: e(6)
    e = 0.0_dp
    if (allocated(self%lib)) e = self%lib%estimates()
  end function estimates

  !> Factorize (pat, values): the first call analyses, later ones with the same pattern only
  !> refactorize. minor: the 1-based column whose pivot failed where the matrix is not positive
  !> definite (MUMPS does not say which: CHOLMOD factorizes the same matrix on this process to
  !> find it, on that failure only), 0 on success.
  subroutine factorize(self, pat, values, stat, errmsg, minor)
    class(spd_factor_t), intent(inout) :: self
    type(sym_csc_t), intent(in) :: pat
    real(dp), intent(in), contiguous :: values(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, intent(out), optional :: minor
    real(dp) :: c0, w0
    if (.not. allocated(self%lib)) allocate (cholmod_factor_t :: self%lib)
    call clocks(c0, w0)
    call self%lib%factorize(pat, values, stat, errmsg, minor)
    call add_clocks(c0, w0, self%times%factor_cpu, self%times%factor_wall)
    self%times%factorizations = self%times%factorizations + 1
    if (stat /= STAT_RUN .or. .not. present(minor)) return
    if (minor /= 0) return
    minor = failing_column(pat, values)
  end subroutine factorize

  !> The column whose pivot fails in CHOLMOD's factorization of (pat, values): the error path of a
  !> library that does not say (a procedure of its own: a local factor with a final procedure costs
  !> gfortran an allocation on every call of the routine that declares it).
  integer function failing_column(pat, values) result(minor)
    type(sym_csc_t), intent(in) :: pat
    real(dp), intent(in), contiguous :: values(:)
    type(cholmod_factor_t) :: diag
    character(len=:), allocatable :: msg
    integer :: st
    call diag%factorize(pat, values, st, msg, minor)
    call diag%destroy()
  end function failing_column

  !> x = A^{-1} b with the current factor.
  subroutine solve(self, b, x, stat, errmsg)
    class(spd_factor_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: b(:)
    real(dp), intent(out), contiguous :: x(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: c0, w0
    if (.not. allocated(self%lib)) allocate (cholmod_factor_t :: self%lib)
    call clocks(c0, w0)
    call self%lib%solve(b, x, stat, errmsg)
    call add_clocks(c0, w0, self%times%solve_cpu, self%times%solve_wall)
    self%times%solves = self%times%solves + 1
  end subroutine solve

  !> This process's CPU seconds and the wall clock's seconds now.
  subroutine clocks(cpu, wall)
    real(dp), intent(out) :: cpu, wall
    integer(8) :: count, rate
    call cpu_time(cpu)
    call system_clock(count, rate)
    wall = real(count, dp) / real(max(rate, 1_8), dp)
  end subroutine clocks

  !> cpu_sum and wall_sum grow by the time since (c0, w0).
  subroutine add_clocks(c0, w0, cpu_sum, wall_sum)
    real(dp), intent(in) :: c0, w0
    real(dp), intent(inout) :: cpu_sum, wall_sum
    real(dp) :: c1, w1
    call clocks(c1, w1)
    cpu_sum = cpu_sum + (c1 - c0)
    wall_sum = wall_sum + (w1 - w0)
  end subroutine add_clocks

  logical function is_factored(self)
    class(spd_factor_t), intent(in) :: self
    is_factored = .false.
    if (allocated(self%lib)) is_factored = self%lib%is_factored()
  end function is_factored

  !> A numeric factorization's cost in solves (the library's flop counts).
  real(dp) function cost_ratio(self)
    class(spd_factor_t), intent(in) :: self
    cost_ratio = 0.0_dp
    if (allocated(self%lib)) cost_ratio = self%lib%cost_ratio()
  end function cost_ratio

  !> The flops of one solve (4 entries of the factor).
  real(dp) function solve_flops(self)
    class(spd_factor_t), intent(in) :: self
    solve_flops = 0.0_dp
    if (allocated(self%lib)) solve_flops = self%lib%solve_flops()
  end function solve_flops

  function stats(self) result(s)
    class(spd_factor_t), intent(in) :: self
    type(factor_stats_t) :: s
    if (allocated(self%lib)) s = self%lib%stats()
  end function stats

  !> The library's factor freed (the choice of library kept for the next factorize).
  subroutine destroy(self)
    class(spd_factor_t), intent(inout) :: self
    if (allocated(self%lib)) call self%lib%destroy()
  end subroutine destroy
end module spd_factor
