!> Scene input: the run: time, scheme and outputs (TIME, SCHEME, OUTPUT).
!> Their grammar (schema) and their handlers; scene_loader calls them.
module scene_run
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str, upper
  use mesh, only: DOF_UX, DOF_UY, DOF_RZ, DOF_UZ
  use statement, only: statement_t, token_t, stmt_error, find_param, count_param, get_real, get_int, to_int, to_real
  use statement_schema, only: schema_t
  use contact_modes, only: IMPACT_OFF, IMPACT_PAPER, IMPACT_PERSIST, IMPACT_MASSLESS, IMPACT_AUTO, IMPACT_SYMMETRIC, &
    SOLVER_AUTO, SOLVER_SCHUR, SOLVER_AUGMENTED, SWITCH_DEFAULT
  use scene, only: scene_t, probe_t
  use spd_factor, only: LIBRARY_AUTO, LIBRARY_CHOLMOD, LIBRARY_MUMPS
  use scene_helpers, only: node_group, get_choice
  implicit none
  private
  public :: run_schema, run_statement

  !> SCHEME IMPACT and MULTIPLIERS: the codes of each word, in the words' order.
  integer, parameter :: IMPACT_MODES(6) = [IMPACT_AUTO, IMPACT_PAPER, IMPACT_PERSIST, IMPACT_OFF, IMPACT_MASSLESS, &
    IMPACT_SYMMETRIC]
  integer, parameter :: SOLVERS(3) = [SOLVER_AUTO, SOLVER_SCHUR, SOLVER_AUGMENTED]
  integer, parameter :: LIBRARIES(3) = [LIBRARY_AUTO, LIBRARY_CHOLMOD, LIBRARY_MUMPS]
  integer, parameter :: MAX_MODES = 10000         !< MODES n at most (each mode a vector of the model's size)

contains

  subroutine run_schema(sch)
    type(schema_t), intent(inout) :: sch
    call sch%add_keyword('TIME', 0, 0, once=.true., required=.true., hint='TIME STEP h END t')
    call sch%add_param('TIME', 'STEP', 1, 1)
    call sch%add_param('TIME', 'END', 1, 1)
    call sch%add_param('TIME', 'START', 1, 1)
    call sch%add_param('TIME', 'ADAPTIVE', 0, 0)
    call sch%add_param('TIME', 'TOLERANCE', 1, 1)
    call sch%add_param('TIME', 'MIN', 1, 1)
    call sch%add_param('TIME', 'MAX', 1, 1)
    call sch%add_keyword('SCHEME', 0, 0, once=.true.)
    call sch%add_param('SCHEME', 'NEWMARK', 0, 0)
    call sch%add_param('SCHEME', 'TOLERANCE', 1, 1)
    call sch%add_param('SCHEME', 'MAX_ITERATIONS', 1, 1)
    call sch%add_param('SCHEME', 'ENERGY_CORRECTION', 1, 1)
    call sch%add_param('SCHEME', 'ENERGY_TEST', 1, 1)
    call sch%add_param('SCHEME', 'ITERATION', 1, 1)
    call sch%add_param('SCHEME', 'IMPACT', 1, 1)
    call sch%add_param('SCHEME', 'PRECISION', 1, 1)
    call sch%add_param('SCHEME', 'MULTIPLIERS', 1, 1)
    call sch%add_param('SCHEME', 'AUGMENTED_ABOVE', 1, 1)
    call sch%add_param('SCHEME', 'RETRY', 1, 1)
    call sch%add_param('SCHEME', 'ZONE', 1, 1)
    call sch%add_param('SCHEME', 'FORCES', 1, 1)
    call sch%add_param('SCHEME', 'EVENTS', 1, 1)
    call sch%add_param('SCHEME', 'SOLVER', 1, 2)
    call sch%add_keyword('OUTPUT', 0, 0, once=.true.)
    call sch%add_param('OUTPUT', 'HISTORY', 1, 2)
    call sch%add_param('OUTPUT', 'FIELDS', 1, 2)
    call sch%add_param('OUTPUT', 'PROBE', 2, -1, repeatable=.true.)
    call sch%add_param('OUTPUT', 'CHECKPOINT', 1, 2)
    call sch%add_keyword('MODES', 1, 1, once=.true., hint='MODES n [ABOVE f0]')
    call sch%add_param('MODES', 'ABOVE', 1, 1)
    call sch%add_keyword('STATIC', 0, 0, once=.true., hint='STATIC [STEPS n] [TOLERANCE r] [MAX_ITERATIONS k]')
    call sch%add_param('STATIC', 'STEPS', 1, 1)
    call sch%add_param('STATIC', 'TOLERANCE', 1, 1)
    call sch%add_param('STATIC', 'MAX_ITERATIONS', 1, 1)
  end subroutine run_schema

  !> One run statement (pass 2 of load_scene).
  subroutine run_statement(scn, st, path, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    select case (st%keyword)
    case ('TIME')
      call do_time(scn, st, stat, errmsg)
    case ('SCHEME')
      call do_scheme(scn, st, stat, errmsg)
    case ('OUTPUT')
      call do_output(scn, st, stat, errmsg)
    case ('MODES')
      call do_modes(scn, st, stat, errmsg)
    case ('STATIC')
      call do_static(scn, st, stat, errmsg)
    end select
  end subroutine run_statement

  !> MODES n [ABOVE f0] (docs/input.md, "Modes"): the n lowest natural frequencies of the supported
  !> structure (above f0 Hz), computed before the dynamics (alone with TIME END equal to START).
  subroutine do_modes(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call to_int(st%lead(1), st, scn%modes, stat, errmsg)
    if (stat /= STAT_OK) return
    if (scn%modes < 1 .or. scn%modes > MAX_MODES) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'the number of modes must be 1 to ' // str(MAX_MODES), &
        st%lead(1)))
      return
    end if
    scn%modes_line = st%line
    scn%modes_above = -1.0_dp
    if (find_param(st, 'ABOVE') > 0) call get_real(st, 'ABOVE', scn%modes_above, stat, errmsg, lower=0.0_dp, &
      lower_inclusive=.true., upper=1.0e30_dp, upper_inclusive=.true.)
  end subroutine do_modes

  !> STATIC [STEPS n] [TOLERANCE r] [MAX_ITERATIONS k] (docs/input.md, "Static preload"): the
  !> loads and gravity at the start time applied in n equal increments, each solved by Newton to
  !> r x the force scale, before the dynamics (static_preload).
  subroutine do_static(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    scn%static_line = st%line
    call get_int(st, 'STEPS', scn%static_steps, stat, errmsg, default=1, lower=1, lower_inclusive=.true., &
      upper=100000, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_int(st, 'MAX_ITERATIONS', scn%static_max_iter, stat, errmsg, default=50, lower=1, lower_inclusive=.true., &
      upper=100000, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_real(st, 'TOLERANCE', scn%static_tol, stat, errmsg, default=1.0e-10_dp, lower=0.0_dp, &
      upper=1.0e-2_dp, upper_inclusive=.true.)
  end subroutine do_static

  subroutine do_time(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: half_span
    ! 4M/h² must be a number: h at most 1e150 (any physical step is far below).
    call get_real(st, 'STEP', scn%dt, stat, errmsg, lower=0.0_dp, lower_inclusive=.false., upper=1.0e150_dp, &
      upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_real(st, 'START', scn%t_start, stat, errmsg, default=0.0_dp)
    if (stat /= STAT_OK) return
    call get_real(st, 'END', scn%t_end, stat, errmsg)
    if (stat /= STAT_OK) return
    ! Halves and products that cannot overflow (END 1e308, START -1e308, STEP 4.9e-324).
    half_span = 0.5_dp * scn%t_end - 0.5_dp * scn%t_start
    if (scn%t_end < scn%t_start) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'END must be after START (' // str(scn%t_start) // ')', &
        st%params(find_param(st, 'END'))%values(1)))
      return
    end if
    ! END = START: a run of MODES alone (scene_loader checks that there is a MODES statement).
    if (scn%t_end == scn%t_start) scn%time_zero_line = st%line
    call do_adaptive(scn, st, stat, errmsg)
    if (stat /= STAT_OK) return
    if (scn%dt >= huge(1.0_dp) / 2.0e9_dp) return
    if (half_span > 1.0e9_dp * max(scn%dt, scn%adapt_hmin)) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'more than 2e9 steps', &
        st%params(find_param(st, 'STEP'))%values(1)))
    end if
  end subroutine do_time

  !> TIME … ADAPTIVE TOLERANCE tol [MIN hmin] [MAX hmax] (step_control): steps STEP 2^k within
  !> [MIN, MAX] (defaults STEP/1024, 256 STEP), STEP the first.
  subroutine do_adaptive(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=9), parameter :: keys(3) = ['TOLERANCE', 'MIN      ', 'MAX      ']
    integer :: k
    stat = STAT_OK
    scn%adaptive = find_param(st, 'ADAPTIVE') > 0
    if (.not. scn%adaptive) then
      do k = 1, size(keys)
        if (find_param(st, trim(keys(k))) > 0) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, trim(keys(k)) // ' is a parameter of the ' // &
            'adaptive step: TIME STEP h END t ADAPTIVE TOLERANCE tol [MIN hmin] [MAX hmax]', &
            st%params(find_param(st, trim(keys(k))))%keytok))
          return
        end if
      end do
      return
    end if
    if (find_param(st, 'TOLERANCE') == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'ADAPTIVE needs TOLERANCE tol (the local error per ' // &
        'step, relative: docs/input.md)', st%params(find_param(st, 'ADAPTIVE'))%keytok))
      return
    end if
    call get_real(st, 'TOLERANCE', scn%adapt_tol, stat, errmsg, lower=0.0_dp, lower_inclusive=.false., upper=1.0_dp, &
      upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_real(st, 'MIN', scn%adapt_hmin, stat, errmsg, default=scn%dt / 1024.0_dp, lower=0.0_dp, &
      lower_inclusive=.false., upper=scn%dt, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_real(st, 'MAX', scn%adapt_hmax, stat, errmsg, default=scn%dt * 256.0_dp, lower=scn%dt, &
      lower_inclusive=.true., upper=1.0e150_dp, upper_inclusive=.true.)
  end subroutine do_adaptive

  subroutine do_scheme(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k
    call get_real(st, 'TOLERANCE', scn%tolerance, stat, errmsg, default=1.0e-10_dp, lower=0.0_dp, &
      lower_inclusive=.false.)
    if (stat /= STAT_OK) return
    call get_int(st, 'MAX_ITERATIONS', scn%max_iterations, stat, errmsg, default=25, lower=1, lower_inclusive=.true.)
    if (stat /= STAT_OK) return
    ! RETRY n: a step whose iteration fails is taken again as 2, 4, ..., 2^n sub-steps (0: stop).
    call get_int(st, 'RETRY', scn%retry, stat, errmsg, default=4, lower=0, lower_inclusive=.true., upper=20, &
      upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_choice(st, 'ENERGY_CORRECTION', ['ON ', 'OFF'], 'ON', k, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%energy_correction = k == 1
    ! ENERGY_TEST ON: eq (9) converges when the residual's work on the step is also within
    ! TOLERANCE x the step's exchanged work (newmark_step); OFF: the force test alone.
    call get_choice(st, 'ENERGY_TEST', ['ON ', 'OFF'], 'ON', k, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%energy_test = k == 1
    call get_choice(st, 'ITERATION', ['ELASTIC', 'TANGENT', 'AUTO   '], 'AUTO', k, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%tangent = k >= 2
    scn%iter_auto = k == 3
    scn%iteration_given = find_param(st, 'ITERATION') > 0
    ! ZONE: iterate eq (9) on the equations of the nonlinear elements only (nonlinear_zone).
    call get_choice(st, 'ZONE', ['AUTO', 'ON  ', 'OFF '], 'AUTO', scn%zone, stat, errmsg)
    if (stat /= STAT_OK) return
    ! FORCES: Bσ of linear elastic small-strain models as K0 u (AUTO) or by the element loop.
    call get_choice(st, 'FORCES', ['AUTO  ', 'POINTS'], 'AUTO', k, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%forces_points = k == 2
    ! EVENTS: contact onsets and releases on a step's end (event_location); AUTO resolved with
    ! IMPACT (scene_contacts).
    call get_choice(st, 'EVENTS', ['AUTO  ', 'LOCATE', 'OFF   '], 'AUTO', scn%events, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_choice(st, 'IMPACT', ['AUTO     ', 'PAPER    ', 'PERSIST  ', 'OFF      ', 'MASSLESS ', &
      'SYMMETRIC'], 'AUTO', k, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%impact = IMPACT_MODES(k)
    call get_choice(st, 'PRECISION', ['DOUBLE  ', 'EXTENDED'], 'DOUBLE', k, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%extended = k == 2
    call get_choice(st, 'MULTIPLIERS', ['AUTO     ', 'SCHUR    ', 'AUGMENTED'], 'AUTO', k, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%multipliers = SOLVERS(k)
    call get_int(st, 'AUGMENTED_ABOVE', scn%augmented_above, stat, errmsg, default=SWITCH_DEFAULT, lower=0, &
      lower_inclusive=.true.)
    if (stat /= STAT_OK) return
    call do_solver(scn, st, stat, errmsg)
  end subroutine do_scheme

  !> SOLVER AUTO|CHOLMOD|MUMPS [OUT_OF_CORE]: the library of the SPD factorizations; OUT_OF_CORE
  !> (MUMPS's factors on disk) only with MUMPS.
  subroutine do_solver(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k
    call get_choice(st, 'SOLVER', ['AUTO   ', 'CHOLMOD', 'MUMPS  '], 'AUTO', k, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%linear_solver = LIBRARIES(k)
    k = find_param(st, 'SOLVER')
    if (k == 0) return
    if (size(st%params(k)%values) < 2) return
    associate (w => st%params(k)%values(2))
      if (upper(w%text) /= 'OUT_OF_CORE') then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected OUT_OF_CORE after the library', w))
      else if (scn%linear_solver /= LIBRARY_MUMPS) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'OUT_OF_CORE is MUMPS''s (SOLVER MUMPS OUT_OF_CORE)', w))
      else
        scn%out_of_core = .true.
      end if
    end associate
  end subroutine do_solver

  !> "[EVERY] k" of OUTPUT HISTORY / FIELDS.
  subroutine get_every(st, key, every, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    integer, intent(inout) :: every
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, n
    stat = STAT_OK
    k = find_param(st, key)
    if (k == 0) return
    n = size(st%params(k)%values)
    if (n == 2) then
      if (upper(st%params(k)%values(1)%text) /= 'EVERY') then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected EVERY k', st%params(k)%values(1)))
        return
      end if
    end if
    call to_int(st%params(k)%values(n), st, every, stat, errmsg)
    if (stat /= STAT_OK) return
    if (every < 0) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'must be >= 0 (0: never)', &
      st%params(k)%values(n)))
  end subroutine get_every

  subroutine do_output(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, occ, i, ig
    type(probe_t) :: pr
    call get_every(st, 'HISTORY', scn%history_every, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_every(st, 'FIELDS', scn%fields_every, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_every(st, 'CHECKPOINT', scn%checkpoint_every, stat, errmsg)
    if (stat /= STAT_OK) return
    do occ = 1, count_param(st, 'PROBE')
      k = find_param(st, 'PROBE', occ)
      associate (vals => st%params(k)%values)
        i = 1
        do while (i <= size(vals))
          if (i == size(vals)) then
            call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'PROBE takes pairs: group DOF [ABOUT x y]', &
              st%params(k)%keytok))
            return
          end if
          call node_group(scn, st, vals(i), ig, stat, errmsg)
          if (stat /= STAT_OK) return
          call probe_dof(st, vals(i + 1), pr, scn%mesh%ndim, stat, errmsg)
          if (stat /= STAT_OK) return
          if (size(scn%mesh%ngroups(ig)%items) /= 1 .and. .not. pr%reaction) then
            call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'a probe of a displacement or a velocity needs a ' // &
              'one-node group; this one has ' // str(size(scn%mesh%ngroups(ig)%items)) // ' nodes', vals(i)))
            return
          end if
          pr%ngroup = ig
          pr%node = scn%mesh%ngroups(ig)%items(1)
          pr%label = vals(i)%text // '.' // upper(vals(i + 1)%text)
          pr%line = st%line
          pr%about = .false.
          i = i + 2
          if (i <= size(vals)) then
            if (upper(vals(i)%text) == 'ABOUT') then
              call probe_about(st, vals, i, pr, stat, errmsg)
              if (stat /= STAT_OK) return
            end if
          end if
          scn%probes = [scn%probes, pr]
        end do
      end associate
    end do
  end subroutine do_output

  !> PROBE group MZ ABOUT x y: the moment of the group's support reactions about (x, y); vals(i)
  !> is ABOUT, i moves past y.
  subroutine probe_about(st, vals, i, pr, stat, errmsg)
    type(statement_t), intent(in) :: st
    type(token_t), intent(in) :: vals(:)
    integer, intent(inout) :: i
    type(probe_t), intent(inout) :: pr
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k
    stat = STAT_OK
    if (upper(vals(i - 1)%text) /= 'MZ') then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'ABOUT goes with MZ (the moment of the reactions about ' // &
        'a point)', vals(i)))
      return
    end if
    if (i + 2 > size(vals)) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'ABOUT needs the point: x y', vals(i)))
      return
    end if
    do k = 1, 2
      call to_real(vals(i + k), st, pr%x0(k), stat, errmsg)
      if (stat /= STAT_OK) return
    end do
    pr%about = .true.
    i = i + 3
  end subroutine probe_about

  !> The quantity of a PROBE pair: UX UY RZ (displacement), VX VY VRZ (velocity), RX RY RZ
  !> (support reaction; RZ is a rotation when displaced, a moment as a reaction: the reaction
  !> is spelled MZ); in a DIMENSION 3 scene UX UY UZ, VX VY VZ, RX RY.
  subroutine probe_dof(st, tok, pr, ndim, stat, errmsg)
    type(statement_t), intent(in) :: st
    type(token_t), intent(in) :: tok
    type(probe_t), intent(inout) :: pr
    integer, intent(in) :: ndim
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    pr%velocity = .false.
    pr%reaction = .false.
    if (ndim == 2 .and. any(upper(tok%text) == ['UZ', 'VZ'])) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, upper(tok%text) // ' needs DIMENSION 3', tok))
      return
    else if (ndim == 3 .and. upper(tok%text) == 'RZ') then   ! (3D: no rotation DOF; RZ is the reaction along z)
      pr%dof = DOF_UZ
      pr%reaction = .true.
      return
    else if (ndim == 3 .and. any(upper(tok%text) == ['VRZ', 'MZ '])) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'a DIMENSION 3 scene probes UX, UY, UZ (displacements), ' // &
        'VX, VY, VZ (velocities) or RX, RY, RZ (support reactions)', tok))
      return
    end if
    if (any(upper(tok%text) == ['UZ', 'VZ'])) then
      pr%dof = DOF_UZ
      pr%velocity = upper(tok%text(1:1)) == 'V'
      return
    end if
    select case (upper(tok%text))
    case ('UX', 'VX', 'RX')
      pr%dof = DOF_UX
    case ('UY', 'VY', 'RY')
      pr%dof = DOF_UY
    case ('RZ', 'VRZ', 'MZ')
      pr%dof = DOF_RZ
    case default
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected a DOF: UX, UY, RZ (displacements), VX, VY, ' // &
        'VRZ (velocities) or RX, RY, MZ (support reactions)', tok))
      return
    end select
    pr%velocity = upper(tok%text(1:1)) == 'V'
    pr%reaction = any(upper(tok%text) == ['RX', 'RY', 'MZ'])
  end subroutine probe_dof

end module scene_run
