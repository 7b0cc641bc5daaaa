!> `rebond sweep FILE`: run every case of a sweep file (module sweep_spec), across MPI ranks,
!> and gather one table (module sweep_output). Grammar and usage: docs/sweep.md.
!>
!> Scheduling: rank 0 loads every case's scene first (bad overrides are recorded as
!> input_error without running), estimates its cost as steps × (nodes + elements) and hands the
!> cases out longest first, one at a time, to whichever worker asks: dynamic, so a few long runs
!> do not leave ranks idle at the end. With one process (no mpirun, or -np 1) rank 0 runs the
!> cases itself in the same order; with N > 1 processes rank 0 only dispatches (it sleeps
!> between polls, so it costs no core) and ranks 1 … N-1 compute: run N = cores + 1.
!> Each case writes its own OUTPUT/case_NNN/; workers send back the summary and the metric
!> values, and rank 0 writes OUTPUT/sweep.csv and OUTPUT/sweep.h5, rows in case order.
module sweep
  use, intrinsic :: iso_c_binding, only: c_int
  use, intrinsic :: iso_fortran_env, only: int64, output_unit, error_unit
  use mpi_f08, only: MPI_Init, MPI_Initialized, MPI_Finalize, MPI_Comm_rank, MPI_Comm_size, MPI_COMM_WORLD, &
                     MPI_Send, MPI_Recv, MPI_Iprobe, MPI_Bcast, MPI_Status, MPI_ANY_SOURCE, &
                     MPI_INTEGER, MPI_DOUBLE_PRECISION, MPI_CHARACTER
  use kinds, only: dp
  use array_utils, only: stable_order
  use errors, only: STAT_OK, STAT_INPUT, str
  use os_utils, only: make_directory
  use scene, only: scene_t
  use scene_loader, only: load_scene
  use assembly, only: system_t, build_system
  use newmark, only: run_options_t, run_summary_t, run_state_t, prepare_run, run_newmark
  use run_state, only: release_matrices
  use contact, only: contact_destroy
  use sweep_spec, only: sweep_t, case_result_t, parse_sweep, case_dir_name, status_name, &
                        MK_APEX, MK_PROBE, CS_OK, CS_INPUT_ERROR, CS_RUN_ERROR, CS_METRIC_ERROR
  use sweep_metrics, only: case_metrics, nan_value
  use sweep_output, only: apply_reference, write_sweep_csv, write_sweep_h5, seconds_text
  use c_interfaces, only: c_usleep
  implicit none
  private
  public :: run_sweep, case_cost_order

  integer, parameter :: TAG_READY = 1, TAG_RESULT = 2, TAG_MESSAGE = 3, TAG_WORK = 4
  !> Longest message sent back from a worker.
  integer, parameter :: MAX_MESSAGE = 2000

contains

  !> Run the sweep file `path`; `extra` are --set overrides for every case, `outdir` (if not
  !> empty) replaces OUTPUT. code: 0 every case ok, 1 some case failed or the table could not be
  !> written, 2 bad sweep file. Initializes and finalizes MPI (once per process).
  subroutine run_sweep(path, extra, outdir, quiet, code)
    character(len=*), intent(in) :: path
    character(len=*), intent(in) :: extra(:)
    character(len=*), intent(in) :: outdir
    logical, intent(in) :: quiet
    integer, intent(out) :: code
    type(sweep_t) :: sw
    type(case_result_t), allocatable :: res(:)
    integer, allocatable :: order(:)
    character(len=:), allocatable :: errmsg
    integer :: rank, nproc, stat, iref, k
    logical :: inited
    integer(int64) :: c0, c1, crate

    call MPI_Initialized(inited)
    if (.not. inited) call MPI_Init()
    call MPI_Comm_rank(MPI_COMM_WORLD, rank)
    call MPI_Comm_size(MPI_COMM_WORLD, nproc)
    call system_clock(c0, crate)
    code = 0

    call parse_sweep(path, extra, sw, stat, errmsg)
    if (stat /= STAT_OK) then
      if (rank == 0) write (error_unit, '(a)') 'rebond sweep: error: ' // errmsg
      code = 2
      call MPI_Finalize()
      return
    end if
    if (len(outdir) > 0) sw%outdir = outdir

    allocate (res(size(sw%cases)))
    allocate (order(0))
    if (rank == 0) then
      call make_directory(sw%outdir, stat, errmsg)
      if (stat /= STAT_OK) then
        write (error_unit, '(a)') 'rebond sweep: error: ' // errmsg
        code = 1
      else
        call estimate(sw, res, order)
        if (.not. quiet) then
          write (output_unit, '(a)') 'rebond sweep ' // path // ': ' // str(size(sw%cases)) // ' cases, scene ' // &
            sw%scene // ', ' // str(nproc) // ' process' // trim(merge('es', '  ', nproc > 1)) // &
            trim(merge(' (rank 0 dispatches)', '                    ', nproc > 1))
          do k = 1, size(res)
            if (res(k)%status == CS_INPUT_ERROR) write (output_unit, '(a)') '  ' // case_dir_name(k, size(res)) // &
              ' input_error: ' // res(k)%message
          end do
        end if
      end if
    end if

    if (nproc == 1) then
      do k = 1, size(order)
        call run_case(sw, order(k), res(order(k)))
        if (.not. quiet) call progress(k)
      end do
    else if (rank == 0) then
      call master(sw, order, res, quiet)
    else
      call worker(sw)
    end if

    if (rank == 0 .and. code == 0) then
      call apply_reference(sw, res, iref)
      call write_sweep_csv(sw%outdir // '/sweep.csv', sw, res, iref, stat, errmsg)
      if (stat == STAT_OK) call write_sweep_h5(sw%outdir // '/sweep.h5', sw, res, iref, stat, errmsg)
      if (stat /= STAT_OK) then
        write (error_unit, '(a)') 'rebond sweep: error: ' // errmsg
        code = 1
      end if
      if (any(res%status /= CS_OK)) code = 1
      call system_clock(c1)
      if (.not. quiet) then
        write (output_unit, '(a)') '  ' // str(count(res%status == CS_OK)) // ' of ' // str(size(res)) // &
          ' cases ok in ' // seconds_text(real(c1 - c0, dp) / real(crate, dp)) // &
          ' s; table in ' // sw%outdir // '/sweep.csv and sweep.h5'
        if (iref > 0) write (output_unit, '(a)') '  reference: ' // case_dir_name(iref, size(res))
      end if
    end if
    call MPI_Bcast(code, 1, MPI_INTEGER, 0, MPI_COMM_WORLD)
    call MPI_Finalize()

  contains

    subroutine progress(i)
      integer, intent(in) :: i
      write (output_unit, '(a)') '  [' // str(i) // '/' // str(size(order)) // '] ' // &
        case_dir_name(order(i), size(res)) // ' ' // status_name(res(order(i))%status) // ', ' // &
        seconds_text(res(order(i))%wall) // ' s'
      flush (output_unit)
    end subroutine progress
  end subroutine run_sweep

  !> Load every case's scene (rank 0): time step, cost estimate, input errors; `order` lists the
  !> cases to run, costliest first.
  subroutine estimate(sw, res, order)
    type(sweep_t), intent(in) :: sw
    type(case_result_t), intent(inout) :: res(:)
    integer, allocatable, intent(out) :: order(:)
    type(scene_t) :: scn
    integer :: k, stat, nsteps
    character(len=:), allocatable :: errmsg, missing
    real(dp), allocatable :: cost(:)
    logical, allocatable :: run(:)
    allocate (cost(size(res)), run(size(res)))
    do k = 1, size(res)
      call load_scene(sw%scene, overrides(sw, k), scn, stat, errmsg)
      run(k) = stat == STAT_OK
      if (stat /= STAT_OK) then
        res(k)%status = CS_INPUT_ERROR
        res(k)%message = errmsg
        call blank(sw, res(k))
        cycle
      end if
      res(k)%dt = scn%dt
      nsteps = max(1, nint((scn%t_end - scn%t_start) / scn%dt))
      cost(k) = real(nsteps, dp) * real(scn%mesh%nnode + scn%mesh%nelem, dp)
      res(k)%cost = cost(k)
      missing = missing_probe(sw, scn)
      if (len(missing) > 0) then
        run(k) = .false.
        res(k)%status = CS_INPUT_ERROR
        res(k)%message = 'metric probe ' // missing // ' is not an OUTPUT PROBE of the scene'
        call blank(sw, res(k))
      end if
    end do
    order = case_cost_order(cost, run)
  end subroutine estimate

  !> Indices k with run(k), by decreasing cost (ties: increasing k).
  pure function case_cost_order(cost, run) result(order)
    real(dp), intent(in) :: cost(:)
    logical, intent(in) :: run(:)
    integer, allocatable :: order(:)
    integer :: i
    order = pack([(i, i = 1, size(cost))], run)
    call stable_order(-cost, order)          ! the dearest first, ties in their order
  end function case_cost_order

  !> The first metric probe that the scene does not write, '' if none.
  function missing_probe(sw, scn) result(s)
    type(sweep_t), intent(in) :: sw
    type(scene_t), intent(in) :: scn
    character(len=:), allocatable :: s
    integer :: i, j
    logical :: found
    s = ''
    do i = 1, size(sw%metrics)
      if (sw%metrics(i)%kind /= MK_APEX .and. sw%metrics(i)%kind /= MK_PROBE) cycle
      found = .false.
      do j = 1, size(scn%probes)
        if (scn%probes(j)%label == sw%metrics(i)%probe) found = .true.
      end do
      if (.not. found) then
        s = sw%metrics(i)%probe
        return
      end if
    end do
  end function missing_probe

  subroutine blank(sw, r)
    type(sweep_t), intent(in) :: sw
    type(case_result_t), intent(inout) :: r
    if (allocated(r%values)) deallocate (r%values)
    allocate (r%values(size(sw%columns)))
    r%values = nan_value()
    r%wall = nan_value()
    r%max_rel_balance = nan_value()
  end subroutine blank

  !> The overrides of case k as the character array load_scene takes.
  function overrides(sw, k) result(o)
    type(sweep_t), intent(in) :: sw
    integer, intent(in) :: k
    character(len=:), allocatable :: o(:)
    integer :: i, l
    l = 1
    do i = 1, size(sw%cases(k)%sets)
      l = max(l, len(sw%cases(k)%sets(i)%s))
    end do
    allocate (character(len=l) :: o(size(sw%cases(k)%sets)))
    do i = 1, size(o)
      o(i) = sw%cases(k)%sets(i)%s
    end do
  end function overrides

  !> One case, start to finish, in this process; failures are recorded in r, never fatal.
  subroutine run_case(sw, k, r)
    type(sweep_t), intent(in) :: sw
    integer, intent(in) :: k
    type(case_result_t), intent(inout) :: r
    type(scene_t) :: scn
    type(system_t) :: sys
    type(run_state_t) :: rs
    type(run_options_t) :: opts
    type(run_summary_t) :: summary
    integer :: stat
    character(len=:), allocatable :: errmsg
    integer(int64) :: c0, c1, crate
    logical :: factored

    call system_clock(c0, crate)
    call blank(sw, r)
    r%status = CS_OK
    r%message = ''
    factored = .false.
    call load_scene(sw%scene, overrides(sw, k), scn, stat, errmsg)
    if (stat == STAT_OK) then
      r%dt = scn%dt
      call build_system(scn, sys, stat, errmsg)
    end if
    if (stat == STAT_OK) then
      call prepare_run(scn, sys, rs, stat, errmsg)
      factored = .true.
    end if
    if (stat /= STAT_OK) then
      r%status = merge(CS_INPUT_ERROR, CS_RUN_ERROR, stat == STAT_INPUT)
      r%message = errmsg
    else
      opts%outdir = sw%outdir // '/' // case_dir_name(k, size(sw%cases))
      opts%quiet = .true.
      call run_newmark(scn, sys, rs, opts, summary, stat, errmsg)
      r%steps = summary%steps
      r%iterations = summary%iterations
      r%max_rel_balance = summary%max_rel_balance
      if (stat /= STAT_OK) then
        r%status = CS_RUN_ERROR
        r%message = errmsg
      else
        call case_metrics(sw, opts%outdir, scn%dt, r%values, stat, errmsg)
        if (stat /= STAT_OK) then
          r%status = CS_METRIC_ERROR
          r%message = errmsg
        end if
      end if
    end if
    if (factored) then
      ! gfortran does not finalize these locals: free the CHOLMOD factors explicitly.
      call release_matrices(rs)
      if (rs%has_contact) call contact_destroy(rs%cs)
    end if
    call system_clock(c1)
    r%wall = real(c1 - c0, dp) / real(crate, dp)
  end subroutine run_case

  !> Rank 0 with workers: answer each worker's request with the next case (or 0: stop),
  !> storing the result it brings back.
  subroutine master(sw, order, res, quiet)
    type(sweep_t), intent(in) :: sw
    integer, intent(in) :: order(:)
    type(case_result_t), intent(inout) :: res(:)
    logical, intent(in) :: quiet
    type(MPI_Status) :: st
    integer :: nproc, next, stopped, src, hdr(5), k, done, work(1)
    real(dp), allocatable :: vals(:)
    character(len=MAX_MESSAGE) :: msg
    logical :: flag
    integer(c_int) :: rc

    call MPI_Comm_size(MPI_COMM_WORLD, nproc)
    allocate (vals(4 + size(sw%columns)))
    next = 1
    stopped = 0
    done = 0
    do while (stopped < nproc - 1)
      call MPI_Iprobe(MPI_ANY_SOURCE, TAG_READY, MPI_COMM_WORLD, flag, st)
      if (.not. flag) then
        rc = c_usleep(2000_c_int)      ! poll without spinning a core
        cycle
      end if
      src = st%MPI_SOURCE
      call MPI_Recv(hdr, 5, MPI_INTEGER, src, TAG_READY, MPI_COMM_WORLD, st)
      k = hdr(1)
      if (k > 0) then
        call MPI_Recv(vals, size(vals), MPI_DOUBLE_PRECISION, src, TAG_RESULT, MPI_COMM_WORLD, st)
        if (hdr(5) > 0) call MPI_Recv(msg, hdr(5), MPI_CHARACTER, src, TAG_MESSAGE, MPI_COMM_WORLD, st)
        call unpack_result(sw, hdr, vals, msg, res(k))
        done = done + 1
        if (.not. quiet) then
          write (output_unit, '(a)') '  [' // str(done) // '/' // str(size(order)) // '] ' // &
            case_dir_name(k, size(res)) // ' ' // status_name(res(k)%status) // ', ' // &
            seconds_text(res(k)%wall) // ' s (rank ' // str(src) // ')'
          flush (output_unit)
        end if
      end if
      if (next <= size(order)) then
        work(1) = order(next)
        next = next + 1
      else
        work(1) = 0
        stopped = stopped + 1
      end if
      call MPI_Send(work, 1, MPI_INTEGER, src, TAG_WORK, MPI_COMM_WORLD)
    end do
  end subroutine master

  !> Ranks > 0: ask for a case, run it, send the result with the next request, until told to stop.
  subroutine worker(sw)
    type(sweep_t), intent(in) :: sw
    type(case_result_t) :: r
    type(MPI_Status) :: st
    integer :: hdr(5), work(1), k, lm
    real(dp), allocatable :: vals(:)
    character(len=MAX_MESSAGE) :: msg
    allocate (vals(4 + size(sw%columns)))
    hdr = 0
    do
      call MPI_Send(hdr, 5, MPI_INTEGER, 0, TAG_READY, MPI_COMM_WORLD)
      if (hdr(1) > 0) then
        call MPI_Send(vals, size(vals), MPI_DOUBLE_PRECISION, 0, TAG_RESULT, MPI_COMM_WORLD)
        if (hdr(5) > 0) call MPI_Send(msg, hdr(5), MPI_CHARACTER, 0, TAG_MESSAGE, MPI_COMM_WORLD)
      end if
      call MPI_Recv(work, 1, MPI_INTEGER, 0, TAG_WORK, MPI_COMM_WORLD, st)
      k = work(1)
      if (k == 0) exit
      r = case_result_t()
      call run_case(sw, k, r)
      lm = min(len(r%message), MAX_MESSAGE)
      msg = r%message(1:lm)
      hdr = [k, r%status, r%steps, r%iterations, lm]
      vals(1:4) = [r%dt, r%wall, r%max_rel_balance, r%cost]
      vals(5:) = r%values
    end do
  end subroutine worker

  subroutine unpack_result(sw, hdr, vals, msg, r)
    type(sweep_t), intent(in) :: sw
    integer, intent(in) :: hdr(5)
    real(dp), intent(in) :: vals(:)
    character(len=*), intent(in) :: msg
    type(case_result_t), intent(inout) :: r
    r%status = hdr(2)
    r%steps = hdr(3)
    r%iterations = hdr(4)
    r%message = msg(1:hdr(5))
    r%dt = vals(1)
    r%wall = vals(2)
    r%max_rel_balance = vals(3)
    r%values = vals(5:4 + size(sw%columns))
  end subroutine unpack_result

end module sweep
