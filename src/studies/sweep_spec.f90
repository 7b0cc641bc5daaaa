!> Sweep files (`rebond sweep FILE`): the list of runs of a parameter study and what to measure.
!>
!> A sweep file uses the lexical rules of scene files (module scene_parser) with its own
!> keywords; the grammar is documented in docs/sweep.md. parse_sweep turns it into a sweep_t:
!> the scene, the cases (each a list of `KEY=VALUE` overrides, as `--set` takes them), the
!> table's parameter columns, the metric columns and the reference. Nothing here runs a scene.
module sweep_spec
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str, upper
  use os_utils, only: path_exists, path_stem
  use statement, only: statement_t, token_t, stmt_error, find_param, count_param, get_int, get_real, get_word
  use statement_schema, only: schema_t
  use scene_parser, only: parse_file, check_required
  use number_text, only: parse_real_text, NUM_OK
  implicit none
  private
  public :: text_t, metric_t, sweep_case_t, sweep_t, case_result_t
  public :: parse_sweep, sweep_schema, case_dir_name, metric_kind_name, push
  public :: MK_APEX, MK_CONTACT_DURATION, MK_ONSETS, MK_PROBE
  public :: REF_FINEST, REF_CASE, REF_VALUE
  public :: CS_PENDING, CS_OK, CS_INPUT_ERROR, CS_RUN_ERROR, CS_METRIC_ERROR, status_name

  !> Metric kinds (METRIC statement).
  integer, parameter :: MK_APEX = 1, MK_CONTACT_DURATION = 2, MK_ONSETS = 3, MK_PROBE = 4
  !> Reference kinds (REFERENCE statement).
  integer, parameter :: REF_FINEST = 1, REF_CASE = 2, REF_VALUE = 3
  !> Case status in the table.
  integer, parameter :: CS_PENDING = 0, CS_OK = 1, CS_INPUT_ERROR = 2, CS_RUN_ERROR = 3, CS_METRIC_ERROR = 4

  !> A string in an array of strings of different lengths.
  type :: text_t
    character(len=:), allocatable :: s
  end type text_t

  !> One METRIC statement; it fills columns first_col .. first_col + ncol - 1 of the table.
  type :: metric_t
    integer :: kind = 0
    character(len=:), allocatable :: probe    !< `group.DOF` (APEX, PROBE)
    integer :: count = 1                      !< APEX: apexes; ONSETS: impacts reported
    real(dp) :: at = 0.0_dp                   !< PROBE: time
    character(len=:), allocatable :: at_text  !< PROBE: the time as written (column name)
    real(dp) :: gap = -1.0_dp                 !< ONSETS: cluster gap (s); < 0: 10 steps of the case
    real(dp) :: scale = 0.0_dp                !< error scale; 0: relative to |reference|
    integer :: first_col = 0, ncol = 0
  end type metric_t

  !> One run: overrides in the order they are applied, and its value of each parameter column.
  type :: sweep_case_t
    character(len=:), allocatable :: name     !< CASE name, '' for a pure grid
    type(text_t), allocatable :: sets(:)      !< `KEY=VALUE`
    type(text_t), allocatable :: values(:)    !< one per parameter column, '' when not set
  end type sweep_case_t

  type :: sweep_t
    character(len=:), allocatable :: path     !< the sweep file
    character(len=:), allocatable :: name     !< its base name without extension
    character(len=:), allocatable :: scene    !< the scene path, resolved against the sweep file's folder
    character(len=:), allocatable :: outdir   !< OUTPUT, default results/<name>
    type(text_t), allocatable :: params(:)    !< parameter columns (VARY keys, then CASE keys)
    type(sweep_case_t), allocatable :: cases(:)
    type(metric_t), allocatable :: metrics(:)
    type(text_t), allocatable :: columns(:)   !< metric columns, over all metrics
    real(dp), allocatable :: col_scale(:)     !< error scale of each metric column (0: relative)
    integer :: ref_kind = REF_FINEST
    character(len=:), allocatable :: ref_case !< REFERENCE CASE name
    real(dp), allocatable :: ref_values(:)    !< REFERENCE VALUE, per metric column (NaN: not given)
    logical, allocatable :: ref_given(:)
  end type sweep_t

  !> What a run gave; errors are filled by the master once the reference is known.
  type :: case_result_t
    integer :: status = CS_PENDING
    character(len=:), allocatable :: message
    real(dp) :: dt = 0.0_dp, wall = 0.0_dp, max_rel_balance = 0.0_dp, cost = 0.0_dp
    integer :: steps = 0, iterations = 0
    real(dp), allocatable :: values(:), errors(:)
  end type case_result_t

contains

  !> The keywords of a sweep file.
  subroutine sweep_schema(sch)
    type(schema_t), intent(out) :: sch
    integer, parameter :: MANY = 1000000
    call sch%add_keyword('SCENE', 1, 1, once=.true., required=.true., hint='SCENE path')
    call sch%add_keyword('OUTPUT', 1, 1, once=.true.)
    call sch%add_keyword('SET', 1, MANY)
    call sch%add_keyword('VARY', 2, MANY)
    call sch%add_keyword('COMBINE', 1, 1, once=.true.)
    call sch%add_keyword('CASE', 1, 1)
    call sch%add_param('CASE', 'SET', 1, 1, repeatable=.true.)
    call sch%add_keyword('METRIC', 0, 1)
    call sch%add_param('METRIC', 'PROBE', 1, 1)
    call sch%add_param('METRIC', 'COUNT', 1, 1)
    call sch%add_param('METRIC', 'AT', 1, 1)
    call sch%add_param('METRIC', 'GAP', 1, 1)
    call sch%add_param('METRIC', 'SCALE', 1, 1)
    call sch%add_keyword('REFERENCE', 1, MANY, once=.true.)
  end subroutine sweep_schema

  pure function status_name(code) result(s)
    integer, intent(in) :: code
    character(len=:), allocatable :: s
    select case (code)
    case (CS_OK)
      s = 'ok'
    case (CS_INPUT_ERROR)
      s = 'input_error'
    case (CS_RUN_ERROR)
      s = 'run_error'
    case (CS_METRIC_ERROR)
      s = 'metric_error'
    case default
      s = 'not_run'
    end select
  end function status_name

  pure function metric_kind_name(kind) result(s)
    integer, intent(in) :: kind
    character(len=:), allocatable :: s
    select case (kind)
    case (MK_APEX)
      s = 'APEX'
    case (MK_CONTACT_DURATION)
      s = 'CONTACT_DURATION'
    case (MK_ONSETS)
      s = 'ONSETS'
    case (MK_PROBE)
      s = 'PROBE'
    case default
      s = '?'
    end select
  end function metric_kind_name

  !> Directory of case k of n, relative to the sweep's OUTPUT: case_001 … (at least 3 digits).
  pure function case_dir_name(k, n) result(s)
    integer, intent(in) :: k, n
    character(len=:), allocatable :: s
    character(len=16) :: buf, fmt
    integer :: w
    w = max(3, len(str(n)))
    write (fmt, '(a,i0,a,i0,a)') '(i', w, '.', w, ')'
    write (buf, fmt) k
    s = 'case_' // trim(buf)
  end function case_dir_name

  !> Read and check a sweep file. `extra` are command-line overrides applied to every case last.
  subroutine parse_sweep(path, extra, sw, stat, errmsg)
    character(len=*), intent(in) :: path
    character(len=*), intent(in) :: extra(:)
    type(sweep_t), intent(out) :: sw
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(schema_t) :: sch
    type(statement_t), allocatable :: st(:)
    type(text_t), allocatable :: gsets(:), vkeys(:), grid(:, :)
    type(sweep_case_t), allocatable :: named(:)
    type(text_t), allocatable :: vvals(:, :)
    integer, allocatable :: nvals(:)
    integer :: i
    logical :: zip

    if (.not. path_exists(path)) then
      call set_error(stat, errmsg, STAT_INPUT, 'cannot open sweep file ' // path)
      return
    end if
    call sweep_schema(sch)
    call parse_file(path, sch, st, stat, errmsg)
    if (stat /= STAT_OK) return
    sw%path = path
    sw%name = path_stem(path)
    allocate (gsets(0), vkeys(0), named(0), nvals(0), sw%metrics(0))
    allocate (vvals(0, 0))
    zip = .false.
    sw%outdir = 'results/' // sw%name
    do i = 1, size(st)
      call sweep_statement(st(i), path(1:index(path, '/', back=.true.)), sw, gsets, vkeys, vvals, nvals, named, zip, &
        stat, errmsg)
      if (stat /= STAT_OK) return
    end do
    call check_required(st, sch, path, stat, errmsg)
    if (stat /= STAT_OK) return
    call vary_grid(path, zip, vvals, nvals, grid, stat, errmsg)
    if (stat /= STAT_OK) return
    if (size(named) == 0) then
      deallocate (named)
      allocate (named(1))
      named(1)%name = ''
      allocate (named(1)%sets(0))
    end if
    call build_cases(sw, named, gsets, vkeys, grid, extra)
    call metric_columns(sw)
    allocate (sw%ref_values(size(sw%columns)), sw%ref_given(size(sw%columns)))
    sw%ref_values = 0.0_dp
    sw%ref_given = .false.
    do i = 1, size(st)
      if (st(i)%keyword == 'REFERENCE') then
        call read_reference(sw, st(i), stat, errmsg)
        if (stat /= STAT_OK) return
      end if
    end do
  end subroutine parse_sweep

  !> One statement of the sweep file, in file order (REFERENCE is read last, parse_sweep).
  subroutine sweep_statement(st, dir, sw, gsets, vkeys, vvals, nvals, named, zip, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: dir
    type(sweep_t), intent(inout) :: sw
    type(text_t), allocatable, intent(inout) :: gsets(:), vkeys(:), vvals(:, :)
    integer, allocatable, intent(inout) :: nvals(:)
    type(sweep_case_t), allocatable, intent(inout) :: named(:)
    logical, intent(inout) :: zip
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: w
    integer :: j, nv
    stat = STAT_OK
    select case (st%keyword)
    case ('SCENE')
      w = st%lead(1)%text
      if (len(w) == 0) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'empty scene path', st%lead(1)))
      else if (w(1:1) == '/') then
        sw%scene = w
      else
        sw%scene = dir // w
      end if
    case ('OUTPUT')
      sw%outdir = st%lead(1)%text
      if (len(sw%outdir) == 0) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'empty output directory', &
        st%lead(1)))
    case ('SET')
      do j = 1, size(st%lead)
        call check_assignment(st, st%lead(j), stat, errmsg)
        if (stat /= STAT_OK) return
        call push(gsets, st%lead(j)%text)
      end do
    case ('VARY')
      associate (key => st%lead(1))
        if (index(key%text, '.') < 2 .or. index(key%text, '=') > 0) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected STATEMENT.PARAM (no value) as the first ' // &
            'word', key))
          return
        end if
        if (find_text(vkeys, key%text) > 0) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'parameter varied twice', key))
          return
        end if
        call push(vkeys, key%text)
      end associate
      nv = size(st%lead) - 1
      call grow_values(vvals, nvals, nv)
      do j = 1, nv
        vvals(j, size(nvals))%s = st%lead(j + 1)%text
      end do
    case ('COMBINE')
      select case (upper(st%lead(1)%text))
      case ('GRID')
        zip = .false.
      case ('ZIP')
        zip = .true.
      case default
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected GRID or ZIP', st%lead(1)))
      end select
    case ('CASE')
      call add_named_case(named, st, stat, errmsg)
    case ('METRIC')
      call add_metric(sw, st, stat, errmsg)
    end select
  end subroutine sweep_statement

  !> A new column of VARY values (nnew of them).
  subroutine grow_values(vv, nn, nnew)
    type(text_t), allocatable, intent(inout) :: vv(:, :)
    integer, allocatable, intent(inout) :: nn(:)
    integer, intent(in) :: nnew
    type(text_t), allocatable :: tmp(:, :)
    integer :: a, b
    allocate (tmp(max(size(vv, 1), nnew), size(nn) + 1))
    do b = 1, size(nn)
      do a = 1, nn(b)
        tmp(a, b) = vv(a, b)
      end do
    end do
    call move_alloc(tmp, vv)
    nn = [nn, nnew]
  end subroutine grow_values

  !> The points of the VARY grid, grid(param, point): every combination (the last VARY
  !> varying fastest) or, COMBINE ZIP, the lists side by side.
  subroutine vary_grid(path, zip, vvals, nvals, grid, stat, errmsg)
    character(len=*), intent(in) :: path
    logical, intent(in) :: zip
    type(text_t), intent(in) :: vvals(:, :)
    integer, intent(in) :: nvals(:)
    type(text_t), allocatable, intent(out) :: grid(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, j, ng, r, q, a
    stat = STAT_OK
    if (zip .and. size(nvals) > 0) then
      if (any(nvals /= nvals(1))) then
        call set_error(stat, errmsg, STAT_INPUT, path // ': COMBINE ZIP needs VARY lists of equal length')
        return
      end if
      ng = nvals(1)
      allocate (grid(size(nvals), ng))
      do k = 1, ng
        do j = 1, size(nvals)
          grid(j, k) = vvals(k, j)
        end do
      end do
    else
      ng = product(nvals)
      allocate (grid(size(nvals), ng))
      do k = 1, ng
        r = k - 1
        do a = size(nvals), 1, -1
          q = mod(r, nvals(a))
          r = r / nvals(a)
          grid(a, k) = vvals(q + 1, a)
        end do
      end do
    end if
  end subroutine vary_grid

  !> The parameter columns (VARY keys, then the keys the CASE statements set) and the cases:
  !> CASE statements (outer) times the grid (first VARY outermost), each with its assignments
  !> (global SET, the case's SET, the grid point's, the command line's).
  subroutine build_cases(sw, named, gsets, vkeys, grid, extra)
    type(sweep_t), intent(inout) :: sw
    type(sweep_case_t), intent(in) :: named(:)
    type(text_t), intent(in) :: gsets(:), vkeys(:), grid(:, :)
    character(len=*), intent(in) :: extra(:)
    character(len=:), allocatable :: w
    integer :: i, j, k, nv, ip, ng
    ng = size(grid, 2)
    allocate (sw%params(0))
    do i = 1, size(vkeys)
      call push(sw%params, vkeys(i)%s)
    end do
    do i = 1, size(named)
      do j = 1, size(named(i)%sets)
        w = key_of(named(i)%sets(j)%s)
        if (find_text(sw%params, w) == 0) call push(sw%params, w)
      end do
    end do
    allocate (sw%cases(size(named) * ng))
    k = 0
    do i = 1, size(named)
      do j = 1, ng
        k = k + 1
        sw%cases(k)%name = named(i)%name
        allocate (sw%cases(k)%sets(0))
        do nv = 1, size(gsets)
          call push(sw%cases(k)%sets, gsets(nv)%s)
        end do
        do nv = 1, size(named(i)%sets)
          call push(sw%cases(k)%sets, named(i)%sets(nv)%s)
        end do
        allocate (sw%cases(k)%values(size(sw%params)))
        do nv = 1, size(sw%params)
          sw%cases(k)%values(nv)%s = ''
        end do
        do nv = 1, size(named(i)%sets)
          w = named(i)%sets(nv)%s
          ip = find_text(sw%params, key_of(w))
          w = value_of(w)
          sw%cases(k)%values(ip)%s = w
        end do
        do nv = 1, size(vkeys)
          call push(sw%cases(k)%sets, vkeys(nv)%s // '=' // grid(nv, j)%s)
          sw%cases(k)%values(nv)%s = grid(nv, j)%s
        end do
        do nv = 1, size(extra)
          call push(sw%cases(k)%sets, trim(extra(nv)))
        end do
      end do
    end do
  end subroutine build_cases

  !> A CASE statement: a named variant with its SET assignments.
  subroutine add_named_case(named, s, stat2, msg2)
    type(sweep_case_t), allocatable, intent(inout) :: named(:)
    type(statement_t), intent(in) :: s
    integer, intent(out) :: stat2
    character(len=:), allocatable, intent(out) :: msg2
    type(sweep_case_t) :: c
    integer :: p, m
    stat2 = STAT_OK
    msg2 = ''
    c%name = s%lead(1)%text
    do p = 1, size(named)
      if (named(p)%name == c%name) then
        call set_error(stat2, msg2, STAT_INPUT, stmt_error(s, 'case name used twice', s%lead(1)))
        return
      end if
    end do
    allocate (c%sets(0))
    do m = 1, count_param(s, 'SET')
      p = find_param(s, 'SET', m)
      call check_assignment(s, s%params(p)%values(1), stat2, msg2)
      if (stat2 /= STAT_OK) return
      call push(c%sets, s%params(p)%values(1)%text)
    end do
    block
      type(sweep_case_t), allocatable :: tmp(:)
      allocate (tmp(size(named) + 1))
      do p = 1, size(named)
        call move_alloc(named(p)%name, tmp(p)%name)
        call move_alloc(named(p)%sets, tmp(p)%sets)
      end do
      call move_alloc(c%name, tmp(size(tmp))%name)
      call move_alloc(c%sets, tmp(size(tmp))%sets)
      call move_alloc(tmp, named)
    end block
  end subroutine add_named_case

  !> A METRIC statement.
  subroutine add_metric(sw, s, stat2, msg2)
    type(sweep_t), intent(inout) :: sw
    type(statement_t), intent(in) :: s
    integer, intent(out) :: stat2
    character(len=:), allocatable, intent(out) :: msg2
    type(metric_t) :: m
    character(len=:), allocatable :: kind
    stat2 = STAT_OK
    msg2 = ''
    ! `METRIC probe g.DOF AT t` reads as the parameter PROBE without a lead word.
    if (size(s%lead) > 0) then
      kind = upper(s%lead(1)%text)
    else if (find_param(s, 'PROBE') > 0) then
      kind = 'PROBE'
    else
      call set_error(stat2, msg2, STAT_INPUT, stmt_error(s, &
        'expected BALANCE, APEX, CONTACT_DURATION, ONSETS or PROBE', s%kwtok))
      return
    end if
    call get_real(s, 'SCALE', m%scale, stat2, msg2, default=0.0_dp, lower=0.0_dp)
    if (stat2 /= STAT_OK) return
    select case (kind)
    case ('BALANCE')
      if (size(s%params) > 0) then
        call set_error(stat2, msg2, STAT_INPUT, stmt_error(s, 'BALANCE takes no parameter', s%params(1)%keytok))
      end if
      return               ! max_rel_balance is always a column
    case ('APEX')
      m%kind = MK_APEX
      call get_word(s, 'PROBE', m%probe, stat2, msg2)
      if (stat2 /= STAT_OK) return
      call get_int(s, 'COUNT', m%count, stat2, msg2, default=1, lower=1, lower_inclusive=.true.)
      if (stat2 /= STAT_OK) return
      call only(s, ['PROBE', 'COUNT', 'SCALE'], stat2, msg2)
    case ('CONTACT_DURATION', 'ONSETS')
      if (kind == 'ONSETS') then
        m%kind = MK_ONSETS
        call get_int(s, 'COUNT', m%count, stat2, msg2, default=1, lower=1, lower_inclusive=.true.)
        if (stat2 /= STAT_OK) return
        call only(s, ['COUNT', 'GAP  ', 'SCALE'], stat2, msg2)
      else
        m%kind = MK_CONTACT_DURATION
        call only(s, ['GAP  ', 'SCALE'], stat2, msg2)
      end if
      if (stat2 /= STAT_OK) return
      call get_real(s, 'GAP', m%gap, stat2, msg2, default=-1.0_dp)
      if (stat2 /= STAT_OK) return
      if (find_param(s, 'GAP') > 0 .and. m%gap <= 0.0_dp) then
        call set_error(stat2, msg2, STAT_INPUT, stmt_error(s, 'GAP must be > 0', s%params(find_param(s, 'GAP'))%keytok))
        return
      end if
    case ('PROBE')
      m%kind = MK_PROBE
      if (size(s%lead) > 0) then
        call set_error(stat2, msg2, STAT_INPUT, stmt_error(s, 'write METRIC PROBE group.DOF AT t', s%lead(1)))
        return
      end if
      call get_word(s, 'PROBE', m%probe, stat2, msg2)
      if (stat2 /= STAT_OK) return
      call get_real(s, 'AT', m%at, stat2, msg2)
      if (stat2 /= STAT_OK) return
      call get_word(s, 'AT', m%at_text, stat2, msg2)
      if (stat2 /= STAT_OK) return
      call only(s, ['PROBE', 'AT   ', 'SCALE'], stat2, msg2)
    case default
      call set_error(stat2, msg2, STAT_INPUT, stmt_error(s, &
        'unknown metric (BALANCE, APEX, CONTACT_DURATION, ONSETS, PROBE)', s%lead(1)))
      return
    end select
    if (stat2 /= STAT_OK) return
    if (m%kind == MK_APEX .or. m%kind == MK_PROBE) then
      if (index(m%probe, '.') < 2) then
        call set_error(stat2, msg2, STAT_INPUT, stmt_error(s, 'expected a probe group.DOF', &
          s%params(find_param(s, 'PROBE'))%values(1)))
        return
      end if
    end if
    block
      type(metric_t), allocatable :: tmp(:)
      allocate (tmp(size(sw%metrics) + 1))
      tmp(1:size(sw%metrics)) = sw%metrics
      tmp(size(tmp)) = m
      call move_alloc(tmp, sw%metrics)
    end block
  end subroutine add_metric

  !> Error on any parameter of s not in `allowed`.
  subroutine only(s, allowed, stat2, msg2)
    type(statement_t), intent(in) :: s
    character(len=*), intent(in) :: allowed(:)
    integer, intent(out) :: stat2
    character(len=:), allocatable, intent(out) :: msg2
    integer :: p
    stat2 = STAT_OK
    msg2 = ''
    do p = 1, size(s%params)
      if (.not. any(allowed == s%params(p)%key)) then
        call set_error(stat2, msg2, STAT_INPUT, stmt_error(s, s%params(p)%key // ' does not apply to this METRIC', &
          s%params(p)%keytok))
        return
      end if
    end do
  end subroutine only

  !> The REFERENCE statement: FINEST, CASE name or VALUE column=value...
  subroutine read_reference(sw, s, stat2, msg2)
    type(sweep_t), intent(inout) :: sw
    type(statement_t), intent(in) :: s
    integer, intent(out) :: stat2
    character(len=:), allocatable, intent(out) :: msg2
    integer :: p, c, ierr, eq
    real(dp) :: x
    stat2 = STAT_OK
    msg2 = ''
    select case (upper(s%lead(1)%text))
    case ('FINEST')
      sw%ref_kind = REF_FINEST
      if (size(s%lead) > 1) call set_error(stat2, msg2, STAT_INPUT, stmt_error(s, 'FINEST takes nothing', s%lead(2)))
    case ('CASE')
      sw%ref_kind = REF_CASE
      if (size(s%lead) /= 2) then
        call set_error(stat2, msg2, STAT_INPUT, stmt_error(s, 'expected REFERENCE CASE name', s%lead(1)))
        return
      end if
      sw%ref_case = s%lead(2)%text
      do p = 1, size(sw%cases)
        if (sw%cases(p)%name == sw%ref_case) return
      end do
      call set_error(stat2, msg2, STAT_INPUT, stmt_error(s, 'no CASE of that name', s%lead(2)))
    case ('VALUE')
      sw%ref_kind = REF_VALUE
      if (size(s%lead) < 2) then
        call set_error(stat2, msg2, STAT_INPUT, stmt_error(s, 'expected column=value after VALUE', s%lead(1)))
        return
      end if
      do p = 2, size(s%lead)
        associate (t => s%lead(p))
          eq = index(t%text, '=')
          if (eq < 2) then
            call set_error(stat2, msg2, STAT_INPUT, stmt_error(s, 'expected column=value', t))
            return
          end if
          c = find_text(sw%columns, t%text(1:eq - 1))
          if (c == 0) then
            call set_error(stat2, msg2, STAT_INPUT, stmt_error(s, 'no metric column ' // t%text(1:eq - 1) // &
              ' (columns: ' // join(sw%columns) // ')', t))
            return
          end if
          call parse_real_text(t%text(eq + 1:), x, ierr)
          if (ierr /= NUM_OK) then
            call set_error(stat2, msg2, STAT_INPUT, stmt_error(s, 'expected a number after =', t))
            return
          end if
          sw%ref_values(c) = x
          sw%ref_given(c) = .true.
        end associate
      end do
    case default
      call set_error(stat2, msg2, STAT_INPUT, stmt_error(s, 'expected FINEST, CASE or VALUE', s%lead(1)))
    end select
  end subroutine read_reference

  !> A `KEY=VALUE` override: KEY has a dot and comes before '='.
  subroutine check_assignment(s, t, stat, errmsg)
    type(statement_t), intent(in) :: s
    type(token_t), intent(in) :: t
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: eq
    stat = STAT_OK
    errmsg = ''
    eq = index(t%text, '=')
    if (eq < 2) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(s, 'expected STATEMENT.PARAM=VALUE', t))
    else if (index(t%text(1:eq - 1), '.') < 2) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(s, 'expected STATEMENT.PARAM=VALUE', t))
    end if
  end subroutine check_assignment

  !> Names of the metric columns and their error scales.
  subroutine metric_columns(sw)
    type(sweep_t), intent(inout) :: sw
    integer :: i, k
    allocate (sw%columns(0), sw%col_scale(0))
    do i = 1, size(sw%metrics)
      associate (m => sw%metrics(i))
        m%first_col = size(sw%columns) + 1
        select case (m%kind)
        case (MK_APEX)
          do k = 1, m%count
            call push(sw%columns, 'apex' // str(k) // '_' // m%probe)
          end do
        case (MK_CONTACT_DURATION)
          call push(sw%columns, 'contact_duration')
        case (MK_ONSETS)
          call push(sw%columns, 'impacts')
          do k = 1, m%count
            call push(sw%columns, 'onsets' // str(k))
          end do
        case (MK_PROBE)
          call push(sw%columns, m%probe // '@' // m%at_text)
        end select
        m%ncol = size(sw%columns) - m%first_col + 1
        sw%col_scale = [sw%col_scale, spread(m%scale, 1, m%ncol)]
      end associate
    end do
  end subroutine metric_columns

  !> Append s to a list of strings.
  subroutine push(list, s)
    type(text_t), allocatable, intent(inout) :: list(:)
    character(len=*), intent(in) :: s
    type(text_t), allocatable :: tmp(:)
    integer :: i
    if (.not. allocated(list)) allocate (list(0))
    allocate (tmp(size(list) + 1))
    do i = 1, size(list)
      call move_alloc(list(i)%s, tmp(i)%s)
    end do
    tmp(size(tmp))%s = s
    call move_alloc(tmp, list)
  end subroutine push

  pure integer function find_text(list, s)
    type(text_t), intent(in) :: list(:)
    character(len=*), intent(in) :: s
    integer :: i
    find_text = 0
    do i = 1, size(list)
      if (list(i)%s == s .and. len(list(i)%s) == len(s)) then
        find_text = i
        return
      end if
    end do
  end function find_text

  pure function join(list) result(s)
    type(text_t), intent(in) :: list(:)
    character(len=:), allocatable :: s
    integer :: i
    s = ''
    do i = 1, size(list)
      if (i > 1) s = s // ', '
      s = s // list(i)%s
    end do
  end function join

  pure function key_of(a) result(k)
    character(len=*), intent(in) :: a
    character(len=:), allocatable :: k
    k = a(1:index(a, '=') - 1)
  end function key_of

  pure function value_of(a) result(v)
    character(len=*), intent(in) :: a
    character(len=:), allocatable :: v
    v = a(index(a, '=') + 1:)
  end function value_of


end module sweep_spec
