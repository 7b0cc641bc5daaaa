!> rebond — implicit structural dynamics with impacts, energy-exact Newmark.
!> Command line only: bin/rebond SCENE [-o OUTDIR] [--set STATEMENT.PARAM=VALUE]... [--quiet] [--restart FILE]
!>                or bin/rebond sweep FILE [-o OUTDIR] [--set STATEMENT.PARAM=VALUE]... [--quiet]
!> Exit codes: 0 success, 2 bad input (scene, mesh, sweep file, command line), 1 failure during
!> the run (sweep: some case failed; the table is written all the same).
program rebond
  use, intrinsic :: iso_fortran_env, only: error_unit
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, STAT_RUN, str
  use scene, only: scene_t
  use contact_modes, only: IMPACT_NAMES
  use cholmod_binding, only: ORDERING_NAMES
  use spd_factor, only: LIBRARY_AUTO
  use scene_loader, only: load_scene
  use assembly, only: system_t, build_system
  use newmark, only: run_options_t, run_summary_t, run_state_t, prepare_run, run_newmark
  use run_state, only: release_matrices
  use sweep, only: run_sweep
  use os_utils, only: path_stem, exit_with, make_directory, install_signal_handlers
  use hdf5_file, only: hdf5_failed
  use text_file, only: say, stdout_error
  use scene_report, only: report_t, measure_scene, say_report, report_warnings
  use modes, only: modes_t, compute_modes, write_modes
  use parallel, only: launched_ranks, parallel_start, parallel_stop, scene_comm, scene_ranks, scene_rank
  use mumps_binding, only: mumps_serve, mumps_stop_serving
  implicit none

  character(len=*), parameter :: VERSION = '0.1.0'
  character(len=:), allocatable :: scene_path, outdir, errmsg, arg, restart
  character(len=:), allocatable :: overrides(:)   !< --set values, as long as the longest
  type(scene_t) :: scn
  type(system_t) :: sys
  type(run_state_t) :: rs
  type(run_options_t) :: opts
  type(run_summary_t) :: summary
  type(modes_t) :: md
  integer :: i, n, stat, first, w, l, nset
  logical :: quiet, sweep_mode
  ! Static storage, as the standard implies for main-program variables: gfortran keeps these
  ! on the stack of MAIN__, and the strings they hold at exit show up as leaks in valgrind.
  save

  ! --set values: at most one per argument, none longer than the longest argument.
  n = command_argument_count()
  w = 1
  do i = 1, n
    call get_command_argument(i, length=l)
    w = max(w, l)
  end do
  allocate (character(len=w) :: overrides(n))
  nset = 0
  scene_path = ''
  outdir = ''
  restart = ''
  quiet = .false.
  n = command_argument_count()
  ! `rebond sweep FILE …` selects the sweep mode (docs/sweep.md); the options are the same.
  sweep_mode = .false.
  first = 1
  if (n >= 1) then
    if (get_arg(1) == 'sweep') then
      sweep_mode = .true.
      first = 2
    end if
  end if
  i = first
  do while (i <= n)
    arg = get_arg(i)
    select case (arg)
    case ('-h', '--help')
      call usage()
      stop
    case ('--version')
      write (*, '(a)') 'rebond ' // VERSION
      stop
    case ('-o', '--output')
      if (i == n) call fail_usage('option ' // arg // ' needs a directory')
      i = i + 1
      outdir = get_arg(i)
    case ('--set')
      if (i == n) call fail_usage('option --set needs STATEMENT.PARAM=VALUE')
      i = i + 1
      call push_override(get_arg(i))
    case ('--quiet', '-q')
      quiet = .true.
    case ('--restart')
      if (i == n) call fail_usage('option --restart needs a checkpoint file (OUTDIR/checkpoint.h5)')
      i = i + 1
      restart = get_arg(i)
    case default
      if (len(arg) > 6) then
        if (arg(1:6) == '--set=') then
          call push_override(arg(7:))
          i = i + 1
          cycle
        end if
      end if
      if (len(arg) > 0) then
        if (arg(1:1) == '-') call fail_usage('unknown option ' // arg)
      end if
      if (len(scene_path) > 0) call fail_usage('more than one ' // trim(merge('sweep file', 'scene     ', sweep_mode)) // &
        ' given: ' // scene_path // ' and ' // arg)
      scene_path = arg
    end select
    i = i + 1
  end do
  if (sweep_mode) then
    if (len(scene_path) == 0) call fail_usage('no sweep file given')
    if (len(restart) > 0) call fail_usage('--restart applies to a single scene, not to a sweep')
    call run_sweep(scene_path, overrides(1:nset), outdir, quiet, stat)
    if (stat == STAT_INPUT) call exit_with(2)
    if (stat /= STAT_OK) call exit_with(1)
  else
    call run_scene()
  end if
  call finish_parallel()

contains

  !> The single-scene mode.
  subroutine run_scene()
    integer :: im, nmod
    if (len(scene_path) == 0) call fail_usage('no scene file given')
    if (len(outdir) == 0) outdir = 'results/' // path_stem(scene_path)
    ! Under mpirun with more than one rank, the ranks share the scene's linear solves (SCHEME
    ! SOLVER, docs/parallel.md): rank 0 runs the scene, the others take part in its MUMPS calls.
    if (launched_ranks() > 1) then
      call parallel_start(share=.true.)
      if (scene_rank() > 0) then
        ! (SIGINT/SIGTERM, which mpirun forwards to every rank, only noted: rank 0 ends the step,
        ! writes its checkpoint and releases this rank; Open MPI's SIGKILL follows after
        ! odls_base_sigkill_timeout, 1 s by default)
        call install_signal_handlers(stat, errmsg)
        call mumps_serve(scene_comm())
        return
      end if
    end if

    call load_scene(scene_path, overrides(1:nset), scn, stat, errmsg)
    if (stat /= STAT_OK) call fail(stat, errmsg)
    call build_system(scn, sys, stat, errmsg)
    if (stat /= STAT_OK) call fail(stat, errmsg)
    call prepare_run(scn, sys, rs, stat, errmsg)
    if (stat /= STAT_OK) call fail(stat, errmsg)

    opts%outdir = outdir
    opts%quiet = quiet
    if (len(restart) > 0) opts%restart = restart
    if (.not. quiet) then
      if (len(scn%title) > 0) then
        call say('rebond ' // VERSION // ': ' // scene_path // ' — ' // scn%title)
      else
        call say('rebond ' // VERSION // ': ' // scene_path)
      end if
      ! The elements of the models (a Gmsh mesh also brings its boundary lines and points, which no
      ! MODEL takes: counted apart).
      nmod = count(scn%elem_model > 0)
      if (nmod == scn%mesh%nelem) then
        call say('  ' // str(scn%mesh%nnode) // ' nodes, ' // str(nmod) // ' elements, ' // str(sys%dofs%neq) // ' equations')
      else
        call say('  ' // str(scn%mesh%nnode) // ' nodes, ' // str(nmod) // ' elements, ' // str(sys%dofs%neq) // &
          ' equations (and ' // str(scn%mesh%nelem - nmod) // ' mesh elements in no MODEL, not modelled)')
      end if
      if (size(scn%conditions) > 0) call say('  contact conditions: ' // str(size(scn%conditions)) // ', IMPACT ' // &
        trim(IMPACT_NAMES(scn%impact)) // trim(merge(' (AUTO)', '       ', scn%impact_auto)) // &
        trim(merge(', events located on a step''s end', '                                ', scn%locate_events)))
      do im = 1, size(scn%models)
        if (scn%models(im)%tuned .and. .not. scn%models(im)%mass_said) call say('  MODEL ' // &
          scn%models(im)%group // ': mass tuned to the step (BAR2 default at c h/dx <= 1; MASS CONSISTENT for the classic)')
      end do
      if (said_solver()) call say('  linear solves: ' // &
        rs%mat%factor%library() // ' on ' // str(rs%mat%factor%ranks()) // ' rank(s) of ' // str(scene_ranks()) // &
        trim(merge(' (SCHEME SOLVER AUTO)', '                     ', scn%linear_solver == LIBRARY_AUTO)))
      if (scn%static_steps > 0) call say_static()
      if (.not. sys%elems%linear) call say('  nonlinear zone: ' // rs%zone%why)
      if (sys%ops%k0u%active()) call say('  internal forces: K0 u (linear elastic model; SCHEME FORCES POINTS for the ' // &
        'element loop)')
    end if
    if (scn%modes > 0) call run_modes()
    call scene_report_out()
    if (scn%time_zero_line > 0 .and. scn%static_steps == 0) then   ! MODES alone (TIME END = START)
      if (.not. quiet) call say('  no time steps (TIME END = START): the modes only; results in ' // outdir // '/')
      call check_stdout()
      return
    end if
    call run_newmark(scn, sys, rs, opts, summary, stat, errmsg)
    if (stat /= STAT_OK) then
      ! Interrupted (SIGINT/SIGTERM) or failed: the summary of what was done, then the cause.
      if (.not. quiet .and. summary%steps > 0) call print_summary()
      call fail(stat, errmsg)
    end if
    if (.not. quiet) call print_summary()
    call check_stdout()
  end subroutine run_scene

  !> STATIC (static_preload): what the preload did.
  subroutine say_static()
    character(len=200) :: line
    write (line, '(a,i0,a,i0,a,i0,a,es9.2,a,es10.3,a,es10.3,a)') '  static preload: ', rs%pre%increments, &
      ' increment(s), ', rs%pre%iterations, ' iterations, ', rs%pre%factorizations, ' factorizations; residual ', &
      rs%pre%residual, ' of the force scale; loads'' work ', rs%pre%work_loads, ' J, laws'' work ', &
      rs%pre%work_internal, ' J'
    call say(trim(line))
    if (rs%has_contact) then
      write (line, '(a,es12.5,a)') '    contact conditions hold it with a total force of ', rs%pre%contact_force, ' N'
      call say(trim(line))
    end if
  end subroutine say_static

  !> MODES (modes): computed, written to OUTDIR/modes.csv and modes.h5, the first ten on stdout.
  subroutine run_modes()
    character(len=64) :: line
    integer :: k
    real(dp) :: c0, c1
    call cpu_time(c0)
    call compute_modes(scn, sys, md, stat, errmsg)
    call cpu_time(c1)
    if (stat /= STAT_OK) call fail(stat, errmsg)
    call make_directory(outdir, stat, errmsg)
    if (stat == STAT_OK) call write_modes(scn, sys, md, outdir, stat, errmsg)
    if (stat /= STAT_OK) call fail(stat, errmsg)
    if (md%n < scn%modes) write (error_unit, '(a)') 'rebond: warning: ' // scene_path // ': MODES: ' // str(md%n) // &
      ' of the ' // str(scn%modes) // ' modes asked for converged (modes.csv has those)'
    if (quiet) return
    write (line, '(f0.3,a,es8.1)') c1 - c0, ' s CPU, largest relative residual ', md%residual
    call say('  modes: ' // str(md%n) // ' by ' // md%method // ' in ' // trim(line) // '; ' // outdir // '/modes.csv')
    do k = 1, min(md%n, 10)
      write (line, '(a,i0,a,es12.5,a)') '    mode ', k, ': ', md%frequency(k), ' Hz'
      call say(trim(line))
    end do
    if (md%n > 10) call say('    …')
  end subroutine run_modes

  !> The report of the scene (scene_report): its lines on stdout, its warnings on stderr (also
  !> with --quiet). With MODES, the lowest natural frequency is the first mode's that is not rigid.
  subroutine scene_report_out()
    type(report_t) :: rep
    character(len=:), allocatable :: w
    integer :: p, k
    call measure_scene(scn, sys, rs%mat%factor, rs%nsteps, rs%rig, rep, stat, errmsg)
    if (stat /= STAT_OK) call fail(stat, errmsg)
    if (scn%modes > 0 .and. scn%modes_above <= 0.0_dp) then
      do k = 1, md%n
        if (md%frequency(k) <= 1.0e-6_dp * md%frequency(md%n)) cycle
        rep%f_low = md%frequency(k)
        rep%low_converged = .true.
        exit
      end do
    end if
    if (.not. quiet) call say_report(scn, rep)
    w = report_warnings(scn, rep)
    do while (len(w) > 0)
      p = index(w, new_line('a'))
      write (error_unit, '(a)') 'rebond: warning: ' // scene_path // ': ' // w(1:p - 1)
      w = w(p + 1:)
    end do
  end subroutine scene_report_out

  !> The run's report reached standard output, or the run says so and exits 1 (its results are
  !> written and kept): a full disk or a closed pipe there is no success.
  subroutine check_stdout()
    character(len=:), allocatable :: why
    why = stdout_error()
    if (len(why) > 0) then
      write (error_unit, '(a)') 'rebond: error: cannot write the run''s report to standard output: ' // why // &
        ' (the results in ' // outdir // '/ are complete)'
      call finish_parallel()
      call exit_with(1)
    end if
  end subroutine check_stdout

  !> The summary of the run on standard output (say: every line checked).
  subroutine print_summary()
    character(len=256) :: line
    write (line, '(a,i0,a,f0.3,a)') '  ', summary%steps, ' steps in ', summary%wall, ' s'
    call say(trim(line))
    write (line, '(a,es10.3)') '  max |balance| / max(kinetic + internal) = ', summary%max_rel_balance
    call say(trim(line))
    if (summary%factor%ordering > 0) then
      write (line, '(a,i0,a,f0.3,a)') '  factor of S: nnz(L) = ', nint(summary%factor%nnz, 8), ', ' // &
        trim(ORDERING_NAMES(summary%factor%ordering)) // ' ordering (analysis ', summary%factor%analysis_cpu, ' s CPU)'
      call say(trim(line))
    end if
    if (said_solver()) then
      associate (t => rs%mat%factor%times)
        write (line, '(a,i0,a,f0.3,a,f0.3,a,i0,a,f0.3,a,f0.3,a)') '  linear solves (' // rs%mat%factor%library() // &
          '): ', t%factorizations, ' factorizations in ', t%factor_cpu, ' s CPU (', t%factor_wall, ' s wall), ', &
          t%solves, ' solves in ', t%solve_cpu, ' s CPU (', t%solve_wall, ' s wall) on rank 0'
      end associate
      call say(trim(line))
      if (rs%mat%factor%library() == 'MUMPS') then
        associate (e => rs%mat%factor%estimates())
          write (line, '(a,es9.2,a,es9.2,a,i0,a,i0,a,i0,a,i0,a)') '  MUMPS''s estimates: ', e(1), ' flops, ', e(2), &
            ' factor entries; in core ', nint(e(3)), ' MB on the busiest rank (', nint(e(4)), ' MB in all), out of core ', &
            nint(e(5)), ' MB (', nint(e(6)), ' MB)'
        end associate
        call say(trim(line))
      end if
    end if
    if (summary%factorizations > 1) call say('  iteration matrix factorized ' // str8(int(summary%factorizations, 8)) // &
      ' times (ITERATION TANGENT or AUTO, SCHEME RETRY, EVENTS)')
    if (summary%geometric_dropped > 0) call say('  ' // str8(summary%geometric_dropped) // ' of them again without ' // &
      'the compressive geometric stiffness (the tangent with it was not positive definite)')
    if (summary%retried > summary%impact_retried) call say('  ' // str(summary%retried - summary%impact_retried) // &
      ' steps did not converge and were taken again as sub-steps (SCHEME RETRY; up to ' // str(summary%max_substeps) // &
      ' per step)')
    if (summary%impact_retried > 0) call say('  ' // str(summary%impact_retried) // ' steps were taken again as ' // &
      'sub-steps: the impact correction of the whole step could not restore the energy (SCHEME RETRY; up to ' // &
      str(summary%max_substeps) // ' per step)')
    if (summary%adapt_rejected + summary%adapt_grown + summary%adapt_shrunk > 0) then
      write (line, '(a,es10.3,a,es10.3,a)') '  adaptive step: from ', summary%h_min_used, ' to ', summary%h_max_used, ' s'
      call say(trim(line) // '; ' // str(summary%adapt_rejected) // ' steps taken again at half their length ' // &
        '(error above TOLERANCE), ' // str(summary%adapt_grown) // ' doublings, ' // str(summary%adapt_shrunk) // &
        ' halvings or returns to STEP')
      if (summary%adapt_at_min > 0) call say('  ' // str(summary%adapt_at_min) // ' steps kept at MIN with ' // &
        'their error above TOLERANCE')
    end if
    if (summary%located > 0) call say('  ' // str(summary%located) // ' steps were cut at a contact event, which ' // &
      'then fell on a step''s end (SCHEME EVENTS)')
    if (summary%schur_solves + summary%augmented_solves > 0) call say('  contact multipliers: ' // &
      str8(summary%schur_solves) // ' Schur solves (' // str8(summary%schur_columns) // ' columns), ' // &
      str8(summary%augmented_solves) // ' augmented solves (' // str8(summary%augmented_factorizations) // ' LU)')
    if (summary%following > 0) call say('  contact pairing: ' // str(summary%following) // ' conditions ' // &
      'linearized anew at every step (GAP … SEGMENTS PAIRING STEP, curved OBSTACLE), ' // str8(summary%repairings) // &
      ' changes of partner')
    call say('  results in ' // outdir // '/')
  end subroutine print_summary

  !> Whether stdout names the linear solver: SCHEME SOLVER given, MUMPS, or more than one rank.
  logical function said_solver()
    said_solver = rs%mat%factor%library() == 'MUMPS' .or. scene_ranks() > 1 .or. scn%linear_solver /= LIBRARY_AUTO
  end function said_solver

  !> An integer of any kind as I0 (the summary's counters are 8-byte).
  function str8(i) result(t)
    integer(8), intent(in) :: i
    character(len=:), allocatable :: t
    character(len=24) :: buf
    write (buf, '(i0)') i
    t = trim(buf)
  end function str8

  function get_arg(k) result(a)
    integer, intent(in) :: k
    character(len=:), allocatable :: a
    integer :: l
    call get_command_argument(k, length=l)
    allocate (character(len=l) :: a)
    call get_command_argument(k, a)
  end function get_arg


  subroutine usage()
    write (*, '(a)') 'usage: rebond SCENE [-o OUTDIR] [--set STATEMENT.PARAM=VALUE]... [--quiet]'
    write (*, '(a)') '       rebond sweep FILE [-o OUTDIR] [--set STATEMENT.PARAM=VALUE]... [--quiet]'
    write (*, '(a)') ''
    write (*, '(a)') 'Runs the keyword scene file SCENE (grammar: docs/input.md) and writes history.csv,'
    write (*, '(a)') 'probes.csv, fields.h5 and fields.xmf into OUTDIR (default results/<scene name>/).'
    write (*, '(a)') 'With sweep, runs every case of the sweep file FILE (docs/sweep.md), under mpirun'
    write (*, '(a)') 'across ranks, into OUTDIR/case_NNN/ and writes the table OUTDIR/sweep.csv and sweep.h5'
    write (*, '(a)') '(OUTDIR default: the OUTPUT of FILE, else results/<sweep name>/).'
    write (*, '(a)') ''
    write (*, '(a)') '  -o, --output DIR     output directory'
    write (*, '(a)') '  --set KEY.PARAM=V    override a parameter of a statement that occurs once'
    write (*, '(a)') '                       (KEY.NAME.PARAM=V for a named one), e.g. --set TIME.STEP=2e-4;'
    write (*, '(a)') '                       with sweep: for every case, after the sweep file''s own'
    write (*, '(a)') '  -q, --quiet          no progress line and no summary'
    write (*, '(a)') '  --restart FILE       continue the run saved in FILE (OUTDIR/checkpoint.h5, written by'
    write (*, '(a)') '                       OUTPUT CHECKPOINT EVERY k, on SIGINT/SIGTERM or before a blow-up);'
    write (*, '(a)') '                       give the same scene, -o and --set as the first run'
    write (*, '(a)') '  -h, --help           this text'
    write (*, '(a)') '  --version            the version'
    write (*, '(a)') ''
    write (*, '(a)') 'Exit status: 0 success, 2 bad input, 1 failure during the run (sweep: a case failed).'
  end subroutine usage

  !> overrides(nset) = s (the array is as wide as the longest argument: nothing is cut).
  subroutine push_override(s)
    character(len=*), intent(in) :: s
    nset = nset + 1
    overrides(nset) = s
  end subroutine push_override

  subroutine fail_usage(msg)
    character(len=*), intent(in) :: msg
    write (0, '(a)') 'rebond: ' // msg
    write (0, '(a)') 'usage: rebond SCENE [-o OUTDIR] [--set STATEMENT.PARAM=VALUE]... [--quiet]  (--help for more)'
    call exit_with(2)
  end subroutine fail_usage

  !> The factors of S freed (MUMPS's on every rank, its out-of-core files removed), the other ranks
  !> released and MPI finalized where this run started it (every exit of rank 0).
  subroutine finish_parallel()
    if (scene_rank() == 0) call release_matrices(rs)
    if (scene_ranks() > 1 .and. scene_rank() == 0) call mumps_stop_serving(scene_comm())
    call parallel_stop()
  end subroutine finish_parallel

  subroutine fail(code, msg)
    integer, intent(in) :: code
    character(len=*), intent(in) :: msg
    write (0, '(a)') 'rebond: error: ' // msg
    call finish_parallel()
    if (code == STAT_INPUT) call exit_with(2, now=hdf5_failed())
    call exit_with(1, now=hdf5_failed())
  end subroutine fail
end program rebond
