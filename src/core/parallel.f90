!> MPI for one scene (docs/input.md, SCHEME SOLVER; docs/parallel.md). rebond starts MPI only
!> where a scene needs it: under mpirun with more than one rank (the ranks share the scene's
!> linear solves), or for SCHEME SOLVER MUMPS in one process (MUMPS is an MPI library). A run
!> without either never touches MPI. `rebond sweep` starts MPI itself (sweep.f90): there every
!> case is solved in its own process, on MPI_COMM_SELF.
!>
!> The scene's communicator: MPI_COMM_WORLD when the single-scene mode shares the scene with the
!> other ranks (parallel_start(share=.true.)), MPI_COMM_SELF otherwise.
module parallel
  use mpi_f08, only: MPI_Comm, MPI_COMM_WORLD, MPI_COMM_SELF, MPI_Init, MPI_Initialized, MPI_Finalized, &
    MPI_Finalize, MPI_Comm_rank, MPI_Comm_size
  implicit none
  private
  public :: launched_ranks, parallel_start, parallel_stop, scene_comm, scene_ranks, scene_rank

  type(MPI_Comm), save :: comm = MPI_COMM_SELF
  logical, save :: shared = .false.
  integer, save :: nranks = 1, myrank = 0        !< of comm, set when it becomes MPI_COMM_WORLD

contains

  !> The ranks mpirun launched this process among, from the launcher's environment (Open MPI's
  !> OMPI_COMM_WORLD_SIZE, else PMI_SIZE), without starting MPI: 1 outside mpirun.
  integer function launched_ranks()
    character(len=32) :: v
    integer :: l, st, ios
    launched_ranks = 1
    call get_environment_variable('OMPI_COMM_WORLD_SIZE', v, l, st)
    if (st /= 0 .or. l == 0) call get_environment_variable('PMI_SIZE', v, l, st)
    if (st /= 0 .or. l == 0) return
    read (v(1:l), *, iostat=ios) launched_ranks
    if (ios /= 0 .or. launched_ranks < 1) launched_ranks = 1
  end function launched_ranks

  !> MPI started (once per process); share: the scene's communicator becomes MPI_COMM_WORLD.
  subroutine parallel_start(share)
    logical, intent(in) :: share
    logical :: inited
    call MPI_Initialized(inited)
    if (.not. inited) call MPI_Init()
    if (share .and. .not. shared) then
      comm = MPI_COMM_WORLD
      shared = .true.
      call MPI_Comm_size(comm, nranks)
      call MPI_Comm_rank(comm, myrank)
    end if
  end subroutine parallel_start

  !> MPI finalized if it was started and is not yet (idempotent; every exit of the program).
  subroutine parallel_stop()
    logical :: inited, done
    call MPI_Initialized(inited)
    if (.not. inited) return
    call MPI_Finalized(done)
    if (.not. done) call MPI_Finalize()
  end subroutine parallel_stop

  !> The communicator the scene's linear solves run on.
  function scene_comm() result(c)
    type(MPI_Comm) :: c
    c = comm
  end function scene_comm

  !> The ranks sharing the scene (1 without MPI or on MPI_COMM_SELF).
  integer function scene_ranks()
    scene_ranks = nranks
  end function scene_ranks

  !> This process's rank among those sharing the scene (0 without MPI).
  integer function scene_rank()
    scene_rank = myrank
  end function scene_rank
end module parallel
