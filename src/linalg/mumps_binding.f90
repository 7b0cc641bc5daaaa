!> MUMPS binding: the symmetric positive definite factorization of one sparse matrix by MUMPS
!> (Debian's libmumps-dev, its Fortran API: dmumps_struc.h, SYM = 1), on the scene's communicator
!> (module parallel): one process, or every rank of an mpirun.
!>
!> The matrix and the right-hand sides are centralized on the host, rank 0 (ICNTL(18) = 0,
!> ICNTL(20) = ICNTL(21) = 0), which runs the time loop; the factors are distributed over the
!> ranks and each factorization and solve runs on all of them. The other ranks wait in
!> mumps_serve for the host's next call: before every collective MUMPS call the host broadcasts
!> what it does (a command and a slot: the other ranks keep one instance of MUMPS per slot), so
!> every rank calls MUMPS with the same JOB in the same order. mumps_stop_serving ends the wait.
!>
!> mumps_factor_t is a sparse_factor_t (as cholmod_factor_t): settings (the communicator, out of
!> core), then factorize (the first call starts the instance and analyses the pattern, later calls
!> with the same pattern only refactorize), solve, is_factored, cost_ratio, solve_flops, stats,
!> destroy; and its ranks and MUMPS's estimates. Do not copy one (MUMPS keeps its
!> own pointers in it); gfortran 12 does not finalize locals: call destroy.
module mumps_binding
  use mpi_f08, only: MPI_Comm, MPI_Comm_size, MPI_Bcast, MPI_INTEGER, MPI_CHARACTER
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str
  use sparse_matrix, only: sym_csc_t
  use sparse_factor, only: sparse_factor_t, factor_stats_t
  implicit none
  private
  public :: mumps_factor_t, mumps_serve, mumps_stop_serving

  include 'dmumps_struc.h'

  !> The host's calls, as broadcast to the other ranks (header: command, slot, out of core).
  integer, parameter :: CMD_INIT = 1, CMD_ANALYSE = 2, CMD_FACTOR = 3, CMD_SOLVE = 4, CMD_END = 5, CMD_QUIT = 6
  integer, parameter :: MAX_SLOTS = 64           !< MUMPS instances alive at once (S per step length, tangents)
  integer, parameter :: PATH_LEN = 255           !< dmumps_struc's OOC_TMPDIR
  !> The ordering MUMPS used (INFOG(7): 0 AMD, 2 AMF, 3 SCOTCH, 4 PORD, 5 METIS, 6 QAMD) as an index
  !> of cholmod_binding's ORDERING_NAMES; a parallel analysis (INFOG(32) = 2) is its 8th name.
  integer, parameter :: ORDERING_OF(0:6) = [1, 0, 4, 5, 6, 2, 7]

  logical, save :: slot_used(MAX_SLOTS) = .false.   !< the host's slots in use

  type, extends(sparse_factor_t) :: mumps_factor_t
    private
    type(dmumps_struc), allocatable :: id
    type(MPI_Comm) :: comm
    logical :: out_of_core = .false.
    character(len=:), allocatable :: tmpdir
    integer :: nproc = 1
    integer :: slot = 0
    logical :: analysed = .false.
    logical :: factored = .false.
    real(dp) :: analysis_cpu = 0.0_dp
  contains
    procedure :: name => mf_name
    procedure :: settings => mf_settings
    procedure :: factorize => mf_factorize
    procedure :: solve => mf_solve
    procedure :: is_factored => mf_is_factored
    procedure :: cost_ratio => mf_cost_ratio
    procedure :: solve_flops => mf_solve_flops
    procedure :: stats => mf_stats
    procedure :: ranks => mf_ranks
    procedure :: estimates => mf_estimates
    procedure :: destroy => mf_destroy
  end type mumps_factor_t

  !> The other ranks' instances, one per slot.
  type :: slot_t
    type(dmumps_struc), allocatable :: id
  end type slot_t

  external :: dmumps

contains

  function mf_name(self) result(s)
    class(mumps_factor_t), intent(in) :: self
    character(len=:), allocatable :: s
    s = 'MUMPS'
  end function mf_name

  !> Where the instance will run: comm (every rank of it joins through mumps_serve); out_of_core:
  !> the factors on disk in tmpdir (ICNTL(22) = 1; blank: MUMPS's default). The instance starts at
  !> the first factorization; any earlier one ends here.
  subroutine mf_settings(self, comm, out_of_core, tmpdir)
    class(mumps_factor_t), intent(inout) :: self
    type(MPI_Comm), intent(in) :: comm
    logical, intent(in) :: out_of_core
    character(len=*), intent(in) :: tmpdir
    call self%destroy()
    self%comm = comm
    self%out_of_core = out_of_core
    self%tmpdir = tmpdir
  end subroutine mf_settings

  !> The MUMPS instance started on every rank of the settings' communicator.
  subroutine start(self, stat, errmsg)
    type(mumps_factor_t), intent(inout) :: self
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=PATH_LEN) :: dir
    integer :: k
    stat = STAT_OK
    call MPI_Comm_size(self%comm, self%nproc)
    if (len(self%tmpdir) > PATH_LEN) then
      call set_error(stat, errmsg, STAT_INPUT, 'MUMPS: the out-of-core directory ' // self%tmpdir // ' is longer than ' // &
        str(PATH_LEN) // ' characters')
      return
    end if
    do k = 1, MAX_SLOTS
      if (.not. slot_used(k)) exit
    end do
    if (k > MAX_SLOTS) then
      call set_error(stat, errmsg, STAT_RUN, 'MUMPS: more than ' // str(MAX_SLOTS) // ' factors at once')
      return
    end if
    slot_used(k) = .true.
    self%slot = k
    dir = self%tmpdir
    call command(self, CMD_INIT, merge(1, 0, self%out_of_core))
    if (self%nproc > 1) call MPI_Bcast(dir, PATH_LEN, MPI_CHARACTER, 0, self%comm)
    allocate (self%id)
    call configure(self%id, self%comm, self%out_of_core, dir)
    call check_info(self%id, 'initialization', stat, errmsg)
  end subroutine start

  !> The same instance settings on every rank: SPD (SYM = 1), the host working (PAR = 1),
  !> centralized assembled matrix and right-hand side, no messages (rebond reports INFOG).
  subroutine configure(id, comm, out_of_core, dir)
    type(dmumps_struc), intent(inout) :: id
    type(MPI_Comm), intent(in) :: comm
    logical, intent(in) :: out_of_core
    character(len=*), intent(in) :: dir
    id%comm = comm%MPI_VAL
    id%sym = 1
    id%par = 1
    id%job = -1
    call dmumps(id)
    id%icntl(1:4) = [-1, -1, -1, 0]
    id%icntl(18) = 0
    id%icntl(20) = 0
    id%icntl(21) = 0
    id%icntl(22) = merge(1, 0, out_of_core)
    if (out_of_core) then
      ! (MUMPS's default directory, where dir is blank: $MUMPS_OOC_TMPDIR, else /tmp)
      if (len_trim(dir) > 0) id%ooc_tmpdir = dir
      id%ooc_prefix = 'rebond_'
    end if
  end subroutine configure

  !> Factorize the SPD matrix (pat, values) on every rank (the instance started at the first call).
  !> The first call (or a call with another pattern size) analyses the pattern; later calls
  !> refactorize. Not positive definite or singular: stat = STAT_RUN, with the count of negative
  !> pivots MUMPS met; minor = 0 always (MUMPS does not say which column: spd_factor finds it).
  subroutine mf_factorize(self, pat, values, stat, errmsg, minor)
    class(mumps_factor_t), intent(inout) :: self
    type(sym_csc_t), intent(in) :: pat
    real(dp), intent(in), contiguous :: values(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, intent(out), optional :: minor
    real(dp) :: c0, c1
    stat = STAT_OK
    if (present(minor)) minor = 0
    if (.not. allocated(self%tmpdir)) self%tmpdir = ''
    if (.not. allocated(self%id)) then
      call start(self, stat, errmsg)
      if (stat /= STAT_OK) return
    end if
    if (pat%n < 1 .or. size(values) /= pat%nnz) then
      call set_error(stat, errmsg, STAT_INPUT, 'MUMPS factorize: ' // str(size(values)) // ' values for a pattern of ' // &
        str(pat%nnz) // ' entries on ' // str(pat%n) // ' equations')
      return
    end if
    self%factored = .false.
    if (.not. self%analysed .or. pat%n /= self%id%n .or. int(pat%nnz, 8) /= self%id%nnz) then
      call cpu_time(c0)
      call set_pattern(self, pat)
      call command(self, CMD_ANALYSE, 0)
      self%id%job = 1
      call dmumps(self%id)
      call cpu_time(c1)
      self%analysis_cpu = c1 - c0
      call check_info(self%id, 'analysis', stat, errmsg)
      if (stat /= STAT_OK) return
      self%analysed = .true.
    end if
    self%id%a(1:pat%nnz) = values
    call command(self, CMD_FACTOR, 0)
    call factor_job(self%id)
    call check_info(self%id, 'factorization', stat, errmsg)
    if (stat /= STAT_OK) return
    if (self%id%infog(12) > 0) then
      call set_error(stat, errmsg, STAT_RUN, 'MUMPS: matrix not positive definite (' // str(self%id%infog(12)) // &
        ' negative pivots)')
      return
    end if
    self%factored = .true.
  end subroutine mf_factorize

  !> The host's copy of the pattern as MUMPS's coordinates (the upper triangle, 1-based).
  subroutine set_pattern(self, pat)
    type(mumps_factor_t), intent(inout) :: self
    type(sym_csc_t), intent(in) :: pat
    integer :: j, p
    if (associated(self%id%irn)) deallocate (self%id%irn, self%id%jcn, self%id%a, self%id%rhs)
    allocate (self%id%irn(pat%nnz), self%id%jcn(pat%nnz), self%id%a(pat%nnz), self%id%rhs(pat%n))
    do j = 1, pat%n
      do p = pat%colptr(j), pat%colptr(j + 1) - 1
        self%id%irn(p) = pat%rowind(p)
        self%id%jcn(p) = j
      end do
    end do
    self%id%n = pat%n
    self%id%nnz = int(pat%nnz, 8)
    self%id%nrhs = 1
    self%id%lrhs = pat%n
  end subroutine set_pattern

  !> JOB = 2, the workspace doubled (ICNTL(14)) and the factorization taken again while MUMPS
  !> reports it too small (INFOG(1) = -8, -9): the same on every rank (INFOG is global).
  subroutine factor_job(id)
    type(dmumps_struc), intent(inout) :: id
    integer :: k
    do k = 1, 5
      id%job = 2
      call dmumps(id)
      if (id%infog(1) /= -8 .and. id%infog(1) /= -9) return
      id%icntl(14) = 2 * max(id%icntl(14), 20)
    end do
  end subroutine factor_job

  !> x = A^{-1} b on every rank (b and x on the host). None of ours is allocated here; MUMPS
  !> allocates inside each call (docs/parallel.md, "Allocations").
  subroutine mf_solve(self, b, x, stat, errmsg)
    class(mumps_factor_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: b(:)
    real(dp), intent(out), contiguous :: x(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (.not. self%factored) then
      call set_error(stat, errmsg, STAT_INPUT, 'MUMPS solve: matrix not factorized')
      return
    end if
    if (size(b) /= self%id%n .or. size(x) /= self%id%n) then
      call set_error(stat, errmsg, STAT_INPUT, 'MUMPS solve: sizes ' // str(size(b)) // ' and ' // str(size(x)) // &
        ' for ' // str(self%id%n) // ' equations')
      return
    end if
    self%id%rhs(1:self%id%n) = b
    call command(self, CMD_SOLVE, 0)
    self%id%job = 3
    call dmumps(self%id)
    call check_info(self%id, 'solve', stat, errmsg)
    if (stat /= STAT_OK) return
    x = self%id%rhs(1:self%id%n)
  end subroutine mf_solve

  logical function mf_is_factored(self)
    class(mumps_factor_t), intent(in) :: self
    mf_is_factored = self%factored
  end function mf_is_factored

  !> The flops of one solve: a forward and a backward sweep over the factor's entries (INFOG(29)).
  real(dp) function mf_solve_flops(self)
    class(mumps_factor_t), intent(in) :: self
    mf_solve_flops = 0.0_dp
    if (self%factored) mf_solve_flops = 4.0_dp * factor_entries(self%id)
  end function mf_solve_flops

  !> A factorization's cost in solves: MUMPS's elimination flops (RINFOG(3)) over a solve's.
  real(dp) function mf_cost_ratio(self)
    class(mumps_factor_t), intent(in) :: self
    mf_cost_ratio = 0.0_dp
    if (self%factored) mf_cost_ratio = self%id%rinfog(3) / max(4.0_dp * factor_entries(self%id), 1.0_dp)
  end function mf_cost_ratio

  !> The factor's entries: INFOG(29), or -INFOG(29) millions when negative (MUMPS's convention).
  real(dp) function factor_entries(id)
    type(dmumps_struc), intent(in) :: id
    factor_entries = real(id%infog(29), dp)
    if (id%infog(29) < 0) factor_entries = -1.0e6_dp * real(id%infog(29), dp)
  end function factor_entries

  !> What the analysis and the factorization made (cholmod_binding's factor_stats_t).
  function mf_stats(self) result(s)
    class(mumps_factor_t), intent(in) :: self
    type(factor_stats_t) :: s
    integer :: o
    if (.not. self%factored) return
    o = self%id%infog(7)
    s%nnz = factor_entries(self%id)
    s%stored = s%nnz
    s%flops = self%id%rinfog(3)
    s%analysis_cpu = self%analysis_cpu
    s%ordering = 8
    if (self%id%infog(32) /= 2 .and. o >= 0 .and. o <= 6) s%ordering = ORDERING_OF(o)
    s%supernodal = .true.
  end function mf_stats

  !> MUMPS's own estimates after the analysis, for reports and projections: [flops of the
  !> elimination (RINFOG(1)), entries of the factors (INFOG(3)), working memory in core in MB of the
  !> busiest rank and of all (INFOG(16), INFOG(17)), the same out of core (INFOG(26), INFOG(27))];
  !> zeros before the analysis.
  function mf_estimates(self) result(e)
    class(mumps_factor_t), intent(in) :: self
    real(dp) :: e(6)
    e = 0.0_dp
    if (.not. self%analysed) return
    e(1) = self%id%rinfog(1)
    e(2) = real(self%id%infog(3), dp)
    if (self%id%infog(3) < 0) e(2) = -1.0e6_dp * real(self%id%infog(3), dp)
    e(3:6) = real([self%id%infog(16), self%id%infog(17), self%id%infog(26), self%id%infog(27)], dp)
  end function mf_estimates

  !> The ranks the factor is distributed over (0 before start).
  integer function mf_ranks(self)
    class(mumps_factor_t), intent(in) :: self
    mf_ranks = 0
    if (allocated(self%id)) mf_ranks = self%nproc
  end function mf_ranks

  !> The instance ended on every rank, the host's arrays freed. Idempotent.
  subroutine mf_destroy(self)
    class(mumps_factor_t), intent(inout) :: self
    if (.not. allocated(self%id)) return
    call command(self, CMD_END, 0)
    if (associated(self%id%irn)) deallocate (self%id%irn, self%id%jcn, self%id%a, self%id%rhs)
    self%id%job = -2
    call dmumps(self%id)
    deallocate (self%id)
    slot_used(self%slot) = .false.
    self%slot = 0
    self%analysed = .false.
    self%factored = .false.
  end subroutine mf_destroy

  !> The host tells the other ranks what it calls next (nothing on one rank).
  subroutine command(self, cmd, arg)
    type(mumps_factor_t), intent(in) :: self
    integer, intent(in) :: cmd, arg
    integer :: hdr(3)
    if (self%nproc <= 1) return
    hdr = [cmd, self%slot, arg]
    call MPI_Bcast(hdr, 3, MPI_INTEGER, 0, self%comm)
  end subroutine command

  !> A rank other than the host: make the host's MUMPS calls with it until mumps_stop_serving.
  subroutine mumps_serve(comm)
    type(MPI_Comm), intent(in) :: comm
    type(slot_t), allocatable :: slots(:)
    character(len=PATH_LEN) :: dir
    integer :: hdr(3)
    allocate (slots(MAX_SLOTS))
    do
      call MPI_Bcast(hdr, 3, MPI_INTEGER, 0, comm)
      if (hdr(1) == CMD_QUIT) exit
      if (hdr(2) < 1 .or. hdr(2) > MAX_SLOTS) cycle
      associate (s => slots(hdr(2)))
        select case (hdr(1))
        case (CMD_INIT)
          call MPI_Bcast(dir, PATH_LEN, MPI_CHARACTER, 0, comm)
          if (allocated(s%id)) deallocate (s%id)
          allocate (s%id)
          call configure(s%id, comm, hdr(3) == 1, dir)
        case (CMD_ANALYSE)
          s%id%job = 1
          call dmumps(s%id)
        case (CMD_FACTOR)
          call factor_job(s%id)
        case (CMD_SOLVE)
          s%id%job = 3
          call dmumps(s%id)
        case (CMD_END)
          s%id%job = -2
          call dmumps(s%id)
          deallocate (s%id)
        end select
      end associate
    end do
  end subroutine mumps_serve

  !> The host releases the other ranks from mumps_serve (collective on comm; nothing on one rank).
  subroutine mumps_stop_serving(comm)
    type(MPI_Comm), intent(in) :: comm
    integer :: hdr(3), nproc
    call MPI_Comm_size(comm, nproc)
    if (nproc <= 1) return
    hdr = [CMD_QUIT, 0, 0]
    call MPI_Bcast(hdr, 3, MPI_INTEGER, 0, comm)
  end subroutine mumps_stop_serving

  !> MUMPS's status (INFOG(1) < 0: an error on some rank) as stat and message.
  subroutine check_info(id, what, stat, errmsg)
    type(dmumps_struc), intent(in) :: id
    character(len=*), intent(in) :: what
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (id%infog(1) >= 0) return
    select case (id%infog(1))
    case (-10, -40)
      call set_error(stat, errmsg, STAT_RUN, 'MUMPS ' // what // ': matrix singular or not positive definite ' // &
        '(INFOG(1) = ' // str(id%infog(1)) // ')')
    case (-13)
      call set_error(stat, errmsg, STAT_RUN, 'MUMPS ' // what // ': out of memory (INFOG(2) = ' // str(id%infog(2)) // ')')
    case default
      call set_error(stat, errmsg, STAT_RUN, 'MUMPS ' // what // ' failed: INFOG(1) = ' // str(id%infog(1)) // &
        ', INFOG(2) = ' // str(id%infog(2)) // ' (MUMPS users'' guide, chapter on error diagnostics)')
    end select
  end subroutine check_info
end module mumps_binding
