!> Scene input: materials, sections and functions (MATERIAL, SECTION, FUNCTION).
!> Their grammar (schema) and their handlers; scene_loader calls them.
module scene_materials
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str, upper
  use section, only: section_t
  use material_law, only: material_t, LAW_ELASTIC, LAW_NONLINEAR_ELASTIC, LAW_ELASTOPLASTIC, LAW_VON_MISES, &
    LAW_HYPERELASTIC
  use statement, only: statement_t, stmt_error, find_param, get_real, get_int, to_real
  use statement_schema, only: schema_t
  use scene, only: scene_t, function_t, MAX_LAYERS, FN_SINE, FN_SMOOTH_STEP, function_prepare
  use scene_helpers, only: get_pair, resolve_path
  use function_table, only: read_function_table
  implicit none
  private
  public :: materials_schema, materials_statement

  !> The largest material or section constant accepted (YOUNG, DENSITY, YIELD, hardening; AREA,
  !> INERTIA, HEIGHT, THICKNESS, MASS): squares, products E I, masses times 4/h² and energies stay
  !> finite (docs/input.md).
  real(dp), parameter :: MAX_MATERIAL = 1.0e100_dp
  !> |B| of NONLINEAR_ELASTIC: its cubic term equals the linear one at a strain of 1e-10 there; past it
  !> the first iterates' strains made E b eps^3 overflow (SIGFPE under make check-debug, seed check 209).
  real(dp), parameter :: MAX_NL_B = 1.0e20_dp

contains

  subroutine materials_schema(sch)
    type(schema_t), intent(inout) :: sch
    call sch%add_keyword('MATERIAL', 1, 1)
    call sch%add_param('MATERIAL', 'ELASTIC', 0, 0)
    call sch%add_param('MATERIAL', 'NONLINEAR_ELASTIC', 0, 0)
    call sch%add_param('MATERIAL', 'ELASTOPLASTIC', 0, 0)
    call sch%add_param('MATERIAL', 'VON_MISES', 0, 0)
    call sch%add_param('MATERIAL', 'HYPERELASTIC', 0, 0)
    call sch%add_param('MATERIAL', 'B', 1, 1)
    call sch%add_param('MATERIAL', 'YIELD', 1, 1)
    call sch%add_param('MATERIAL', 'H_ISO', 1, 1)
    call sch%add_param('MATERIAL', 'H_KIN', 1, 1)
    call sch%add_param('MATERIAL', 'YOUNG', 1, 1)
    call sch%add_param('MATERIAL', 'POISSON', 1, 1)
    call sch%add_param('MATERIAL', 'DENSITY', 1, 1)
    call sch%add_keyword('SECTION', 1, 1)
    call sch%add_param('SECTION', 'AREA', 1, 1)
    call sch%add_param('SECTION', 'INERTIA', 1, 1)
    call sch%add_param('SECTION', 'HEIGHT', 1, 1)
    call sch%add_param('SECTION', 'THICKNESS', 1, 1)
    call sch%add_param('SECTION', 'MASS', 1, 1)
    call sch%add_param('SECTION', 'DIRECTION', 2, 2)
    call sch%add_param('SECTION', 'GAUSS', 1, 1)
    call sch%add_param('SECTION', 'LAYERS', 1, 1)
    call sch%add_keyword('FUNCTION', 1, 1)
    call sch%add_param('FUNCTION', 'POINTS', 2, -1)
    call sch%add_param('FUNCTION', 'SINE', 0, 0)
    call sch%add_param('FUNCTION', 'AMPLITUDE', 1, 1)
    call sch%add_param('FUNCTION', 'FREQUENCY', 1, 1)
    call sch%add_param('FUNCTION', 'PHASE', 1, 1)
    call sch%add_param('FUNCTION', 'START', 1, 1)
    call sch%add_param('FUNCTION', 'END', 1, 1)
    call sch%add_param('FUNCTION', 'SMOOTH_STEP', 0, 0)
    call sch%add_param('FUNCTION', 'T', 1, 1)
    call sch%add_param('FUNCTION', 'TABLE', 0, 0)
    call sch%add_param('FUNCTION', 'FILE', 1, 1)
  end subroutine materials_schema

  !> One materials statement (pass 1 of load_scene).
  subroutine materials_statement(scn, st, path, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    select case (st%keyword)
    case ('MATERIAL')
      call do_material(scn, st, stat, errmsg)
    case ('SECTION')
      call do_section(scn, st, stat, errmsg)
    case ('FUNCTION')
      call do_function(scn, st, path, stat, errmsg)
    end select
  end subroutine materials_statement

  subroutine do_material(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(material_t) :: mat
    integer :: i, nlaw
    do i = 1, size(scn%materials)
      if (scn%materials(i)%name == st%lead(1)%text) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'material defined twice', st%lead(1)))
        return
      end if
    end do
    mat%name = st%lead(1)%text
    nlaw = count([find_param(st, 'ELASTIC') > 0, find_param(st, 'NONLINEAR_ELASTIC') > 0, &
      find_param(st, 'ELASTOPLASTIC') > 0, find_param(st, 'VON_MISES') > 0, find_param(st, 'HYPERELASTIC') > 0])
    if (nlaw /= 1) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'give exactly one law (ELASTIC, NONLINEAR_ELASTIC, ' // &
        'ELASTOPLASTIC, VON_MISES or HYPERELASTIC)', st%lead(1)))
      return
    end if
    mat%law = LAW_ELASTIC
    if (find_param(st, 'NONLINEAR_ELASTIC') > 0) mat%law = LAW_NONLINEAR_ELASTIC
    if (find_param(st, 'ELASTOPLASTIC') > 0) mat%law = LAW_ELASTOPLASTIC
    if (find_param(st, 'VON_MISES') > 0) mat%law = LAW_VON_MISES
    if (find_param(st, 'HYPERELASTIC') > 0) mat%law = LAW_HYPERELASTIC
    call check_law_params(st, mat%law, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_real(st, 'B', mat%nl_b, stat, errmsg, default=0.0_dp, lower=-MAX_NL_B, lower_inclusive=.true., &
      upper=MAX_NL_B, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    if (mat%law == LAW_ELASTOPLASTIC .or. mat%law == LAW_VON_MISES) then
      call get_real(st, 'YIELD', mat%yield, stat, errmsg, lower=0.0_dp, lower_inclusive=.false., &
      upper=MAX_MATERIAL, upper_inclusive=.true.)
      if (stat /= STAT_OK) return
    end if
    call get_real(st, 'H_ISO', mat%h_iso, stat, errmsg, default=0.0_dp, lower=0.0_dp, lower_inclusive=.true., &
      upper=MAX_MATERIAL, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_real(st, 'H_KIN', mat%h_kin, stat, errmsg, default=0.0_dp, lower=0.0_dp, lower_inclusive=.true., &
      upper=MAX_MATERIAL, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_real(st, 'YOUNG', mat%young, stat, errmsg, lower=0.0_dp, lower_inclusive=.false., &
      upper=MAX_MATERIAL, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_real(st, 'POISSON', mat%poisson, stat, errmsg, default=0.0_dp, lower=-1.0_dp, lower_inclusive=.false.)
    if (stat /= STAT_OK) return
    if (mat%poisson >= 0.5_dp) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'POISSON must be < 0.5', &
        st%params(find_param(st, 'POISSON'))%values(1)))
      return
    end if
    call get_real(st, 'DENSITY', mat%density, stat, errmsg, default=0.0_dp, lower=0.0_dp, lower_inclusive=.true., &
      upper=MAX_MATERIAL, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    scn%materials = [scn%materials, mat]
  end subroutine do_material

  subroutine do_section(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(section_t) :: sec
    integer :: i
    do i = 1, size(scn%sections)
      if (scn%sections(i)%name == st%lead(1)%text) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'section defined twice', st%lead(1)))
        return
      end if
    end do
    sec%name = st%lead(1)%text
    call get_real(st, 'AREA', sec%area, stat, errmsg, default=0.0_dp, lower=0.0_dp, lower_inclusive=.false., &
      upper=MAX_MATERIAL, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_real(st, 'INERTIA', sec%inertia, stat, errmsg, default=0.0_dp, lower=0.0_dp, lower_inclusive=.false., &
      upper=MAX_MATERIAL, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_real(st, 'HEIGHT', sec%height, stat, errmsg, default=0.0_dp, lower=0.0_dp, lower_inclusive=.false., &
      upper=MAX_MATERIAL, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_real(st, 'THICKNESS', sec%thickness, stat, errmsg, default=1.0_dp, lower=0.0_dp, lower_inclusive=.false., &
      upper=MAX_MATERIAL, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    sec%has_thickness = find_param(st, 'THICKNESS') > 0
    call get_real(st, 'MASS', sec%mass, stat, errmsg, default=0.0_dp, lower=0.0_dp, lower_inclusive=.true., &
      upper=MAX_MATERIAL, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    if (find_param(st, 'DIRECTION') > 0) then
      call get_pair(st, 'DIRECTION', sec%direction, stat, errmsg)
      if (stat /= STAT_OK) return
      if (norm2(sec%direction) <= 0.0_dp) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'DIRECTION must be a non-zero vector', &
          st%params(find_param(st, 'DIRECTION'))%keytok))
        return
      end if
      sec%direction = sec%direction / norm2(sec%direction)
      sec%has_direction = .true.
    end if
    call get_int(st, 'GAUSS', sec%gauss, stat, errmsg, default=0, lower=1, lower_inclusive=.true.)
    if (stat /= STAT_OK) return
    ! LAYERS <= MAX_LAYERS: each layer carries state at every Gauss point of every element, and a
    ! count near 2**31 failed to allocate or ran for hours (found by tests/fuzz/fuzz.py).
    call get_int(st, 'LAYERS', sec%layers, stat, errmsg, default=0, lower=1, lower_inclusive=.true., &
      upper=MAX_LAYERS, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    if (sec%gauss > 5) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'GAUSS must be between 1 and 5', &
        st%params(find_param(st, 'GAUSS'))%values(1)))
      return
    end if
    scn%sections = [scn%sections, sec]
  end subroutine do_section

  !> FUNCTION name POINTS t1 f1 t2 f2 … | SINE AMPLITUDE a FREQUENCY hz [PHASE deg] [START t0] [END t1]
  !> | SMOOTH_STEP T t1 [START t0] | TABLE FILE path (docs/input.md, "Functions"): one kind, the
  !> parameters of another refused.
  subroutine do_function(scn, st, path, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=11), parameter :: KINDS(4) = [character(len=11) :: 'POINTS', 'SINE', 'SMOOTH_STEP', 'TABLE']
    character(len=9), parameter :: OWN(7) = [character(len=9) :: 'AMPLITUDE', 'FREQUENCY', 'PHASE', 'START', 'END', 'T', &
      'FILE']
    ! which kinds take each of OWN (POINTS, SINE, SMOOTH_STEP, TABLE)
    logical, parameter :: TAKES(4, 7) = reshape([.false., .true., .false., .false., .false., .true., .false., .false., &
      .false., .true., .false., .false., .false., .true., .true., .false., .false., .true., .false., .false., &
      .false., .false., .true., .false., .false., .false., .false., .true.], [4, 7])
    type(function_t) :: fn
    integer :: i, k, nk, kind
    character(len=:), allocatable :: file, msg
    stat = STAT_OK
    do i = 1, size(scn%functions)
      if (scn%functions(i)%name == st%lead(1)%text) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'function defined twice', st%lead(1)))
        return
      end if
    end do
    fn%name = st%lead(1)%text
    nk = 0
    kind = 0
    do i = 1, size(KINDS)
      if (find_param(st, trim(KINDS(i))) > 0) then
        nk = nk + 1
        if (nk == 2) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'one of POINTS, SINE, SMOOTH_STEP, TABLE: ' // &
            trim(KINDS(kind)) // ' and ' // trim(KINDS(i)) // ' given', st%params(find_param(st, trim(KINDS(i))))%keytok))
          return
        end if
        kind = i
      end if
    end do
    if (kind == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'missing POINTS, SINE, SMOOTH_STEP or TABLE', st%lead(1)))
      return
    end if
    do i = 1, size(OWN)
      k = find_param(st, trim(OWN(i)))
      if (k > 0 .and. .not. TAKES(kind, i)) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, trim(OWN(i)) // ' does not belong to a ' // &
          trim(KINDS(kind)) // ' function', st%params(k)%keytok))
        return
      end if
    end do
    select case (kind)
    case (1)
      call get_points(st, fn, stat, errmsg)
    case (2)
      fn%kind = FN_SINE
      call get_real(st, 'AMPLITUDE', fn%amplitude, stat, errmsg, lower=-MAX_MATERIAL, lower_inclusive=.true., &
        upper=MAX_MATERIAL, upper_inclusive=.true.)
      if (stat == STAT_OK) call get_real(st, 'FREQUENCY', fn%frequency, stat, errmsg, lower=0.0_dp, &
        lower_inclusive=.false., upper=MAX_MATERIAL, upper_inclusive=.true.)
      if (stat == STAT_OK) call get_real(st, 'PHASE', fn%phase, stat, errmsg, default=0.0_dp, lower=-1.0e6_dp, &
        lower_inclusive=.true., upper=1.0e6_dp, upper_inclusive=.true.)
      fn%phase = fn%phase * atan(1.0_dp) / 45.0_dp
      if (stat == STAT_OK) call get_interval(st, .false., fn, stat, errmsg)
    case (3)
      fn%kind = FN_SMOOTH_STEP
      call get_real(st, 'T', fn%finish, stat, errmsg)
      if (stat == STAT_OK) call get_interval(st, .true., fn, stat, errmsg)
    case (4)
      k = find_param(st, 'FILE')
      if (k == 0) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'TABLE needs FILE path (two columns: time, value)', &
          st%params(find_param(st, 'TABLE'))%keytok))
        return
      end if
      file = st%params(k)%values(1)%text
      call read_function_table(resolve_path(path, file), fn%t, fn%f, stat, msg)
      if (stat /= STAT_OK) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, msg, st%params(k)%values(1)))
    end select
    if (stat /= STAT_OK) return
    call function_prepare(fn)
    scn%functions = [scn%functions, fn]
  end subroutine do_function

  !> FUNCTION … SINE or SMOOTH_STEP: START (default 0) before the end (SINE: END, default none;
  !> SMOOTH_STEP: T, in fn%finish), both finite.
  subroutine get_interval(st, step, fn, stat, errmsg)
    type(statement_t), intent(in) :: st
    logical, intent(in) :: step
    type(function_t), intent(inout) :: fn
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: key
    call get_real(st, 'START', fn%start, stat, errmsg, default=0.0_dp, lower=-MAX_MATERIAL, lower_inclusive=.true., &
      upper=MAX_MATERIAL, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    key = 'T'
    if (.not. step) then
      key = 'END'
      if (find_param(st, 'END') == 0) return
      call get_real(st, 'END', fn%finish, stat, errmsg)
      if (stat /= STAT_OK) return
    end if
    if (.not. (fn%finish > fn%start .and. fn%finish <= MAX_MATERIAL)) call set_error(stat, errmsg, STAT_INPUT, &
      stmt_error(st, key // ' must be after START (' // str(fn%start) // ') and within 1e100', &
      st%params(find_param(st, key))%values(1)))
  end subroutine get_interval

  !> FUNCTION … POINTS t1 f1 t2 f2 …: times increasing, values within ±1e100.
  subroutine get_points(st, fn, stat, errmsg)
    type(statement_t), intent(in) :: st
    type(function_t), intent(inout) :: fn
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, n, i
    stat = STAT_OK
    k = find_param(st, 'POINTS')
    n = size(st%params(k)%values)
    if (mod(n, 2) /= 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'POINTS needs pairs of time and value, found ' // &
        str(n) // ' numbers', st%params(k)%keytok))
      return
    end if
    allocate (fn%t(n / 2), fn%f(n / 2))
    do i = 1, n / 2
      call to_real(st%params(k)%values(2 * i - 1), st, fn%t(i), stat, errmsg)
      if (stat /= STAT_OK) return
      call to_real(st%params(k)%values(2 * i), st, fn%f(i), stat, errmsg)
      if (stat /= STAT_OK) return
      ! A function scales loads, imposed motions and gravity (themselves within ±1e100): its values
      ! are held to the same bound (a value of 1e300 overflowed a pressure, fuzz seed s9dbg2 5635).
      if (abs(fn%f(i)) > MAX_MATERIAL) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'POINTS values must be within ±1e100', &
          st%params(k)%values(2 * i)))
        return
      end if
      if (i > 1) then
        if (fn%t(i) <= fn%t(i - 1)) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'times must increase', &
            st%params(k)%values(2 * i - 1)))
          return
        end if
      end if
    end do
  end subroutine get_points

  !> Parameters that the chosen law does not use are refused rather than ignored.
  subroutine check_law_params(st, law, stat, errmsg)
    type(statement_t), intent(in) :: st
    integer, intent(in) :: law
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=5), parameter :: keys(4) = [character(len=5) :: 'B', 'YIELD', 'H_ISO', 'H_KIN']
    logical :: allowed(4)
    integer :: i, k
    stat = STAT_OK
    select case (law)
    case (LAW_NONLINEAR_ELASTIC)
      allowed = [.true., .false., .false., .false.]
    case (LAW_ELASTOPLASTIC, LAW_VON_MISES)
      allowed = [.false., .true., .true., .true.]
    case default
      allowed = .false.
    end select
    do i = 1, size(keys)
      k = find_param(st, trim(keys(i)))
      if (k > 0 .and. .not. allowed(i)) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'parameter ' // trim(keys(i)) // &
          ' does not belong to this law', st%params(k)%keytok))
        return
      end if
    end do
  end subroutine check_law_params
end module scene_materials
