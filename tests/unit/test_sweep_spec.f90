!> Sweep files: the cases of a grid, of CASE statements times a grid, of zipped lists; the
!> order of the overrides; the columns; the errors a bad file gives (file:line and the word).
program test_sweep_spec
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT
  use testing, only: check, test_summary
  use sweep_spec, only: sweep_t, parse_sweep, case_dir_name, REF_FINEST, REF_VALUE, MK_APEX, MK_PROBE
  implicit none
  type(sweep_t) :: sw
  integer :: stat
  character(len=:), allocatable :: errmsg
  character(len=32) :: noextra(0)
  character(len=*), parameter :: F = '/tmp/rebond_test_sweep_spec.sweep'
  character(len=*), parameter :: NL = achar(10)

  ! A 3 x 2 grid: 6 cases, the last VARY fastest, global SETs first, command-line overrides last.
  call write_file('SCENE ../x/scene.dat' // NL // 'SET TIME.END=3 OUTPUT.HISTORY=1' // NL // &
    'VARY TIME.STEP 1e-3 5e-4 2.5e-4' // NL // 'VARY SCHEME.IMPACT PAPER "PERSIST"' // NL // &
    'METRIC balance' // NL // 'METRIC apex PROBE ball.UY COUNT 2 SCALE 1' // NL // 'METRIC probe ball.UX AT 0.25' // NL // &
    'METRIC onsets COUNT 2 GAP 1e-3' // NL // 'METRIC contact_duration')
  call parse_sweep(F, ['TIME.START=0'], sw, stat, errmsg)
  call check(stat == STAT_OK, 'grid: parses', errmsg)
  call check(size(sw%cases) == 6, 'grid: 3 x 2 = 6 cases')
  call check(sw%scene == '/tmp/../x/scene.dat', 'grid: SCENE relative to the sweep file', sw%scene)
  call check(sw%outdir == 'results/rebond_test_sweep_spec', 'grid: default OUTPUT results/<sweep name>', sw%outdir)
  call check(size(sw%params) == 2, 'grid: two parameter columns')
  call check(sw%cases(2)%values(1)%s == '1e-3' .and. sw%cases(2)%values(2)%s == 'PERSIST', &
    'grid: case 2 = (first step, second impact)')
  call check(sw%cases(3)%values(1)%s == '5e-4' .and. sw%cases(3)%values(2)%s == 'PAPER', 'grid: case 3 = (second step, PAPER)')
  call check(size(sw%cases(6)%sets) == 5, 'grid: 2 global + 2 varied + 1 command-line overrides')
  call check(sw%cases(6)%sets(1)%s == 'TIME.END=3' .and. sw%cases(6)%sets(3)%s == 'TIME.STEP=2.5e-4' .and. &
    sw%cases(6)%sets(5)%s == 'TIME.START=0', 'grid: overrides in order global, varied, command line')
  call check(size(sw%columns) == 7, 'columns: 2 apexes, 1 probe, impacts + 2 onsets, 1 duration', str_cols())
  call check(sw%columns(1)%s == 'apex1_ball.UY' .and. sw%columns(2)%s == 'apex2_ball.UY' .and. &
    sw%columns(3)%s == 'ball.UX@0.25', 'columns: names of apexes and probe', str_cols())
  call check(sw%metrics(1)%kind == MK_APEX .and. sw%metrics(2)%kind == MK_PROBE, 'metrics: BALANCE adds none')
  call check(sw%col_scale(1) == 1.0_dp .and. sw%col_scale(3) == 0.0_dp, 'columns: SCALE per metric')
  call check(sw%ref_kind == REF_FINEST, 'reference: FINEST by default')

  ! CASE statements times a grid; REFERENCE VALUE.
  call write_file('SCENE s.dat' // NL // 'OUTPUT out/here' // NL // 'CASE a SET SCHEME.IMPACT=PAPER' // NL // &
    'CASE b SET SCHEME.IMPACT=OFF SET SCHEME.TOLERANCE=1e-12' // NL // 'VARY TIME.STEP 1e-3 5e-4' // NL // &
    'METRIC apex PROBE m.UY COUNT 2' // NL // 'REFERENCE VALUE apex2_m.UY=0.5')
  call parse_sweep(F, noextra, sw, stat, errmsg)
  call check(stat == STAT_OK, 'cases: parses', errmsg)
  call check(size(sw%cases) == 4 .and. sw%cases(3)%name == 'b', 'cases: 2 CASEs x 2 steps, CASE outermost')
  call check(size(sw%params) == 3, 'cases: columns TIME.STEP, SCHEME.IMPACT, SCHEME.TOLERANCE')
  call check(sw%cases(1)%values(3)%s == '' .and. sw%cases(4)%values(3)%s == '1e-12', 'cases: a key a CASE does not set is empty')
  call check(sw%outdir == 'out/here', 'cases: OUTPUT', sw%outdir)
  call check(sw%ref_kind == REF_VALUE .and. sw%ref_given(2) .and. .not. sw%ref_given(1) .and. sw%ref_values(2) == 0.5_dp, &
    'reference: VALUE per column')

  ! ZIP pairs the lists.
  call write_file('SCENE s.dat' // NL // 'COMBINE ZIP' // NL // 'VARY TIME.STEP 1e-3 5e-4' // NL // 'VARY TIME.END 1 2')
  call parse_sweep(F, noextra, sw, stat, errmsg)
  call check(stat == STAT_OK .and. size(sw%cases) == 2, 'zip: 2 cases', errmsg)
  call check(sw%cases(2)%values(1)%s == '5e-4' .and. sw%cases(2)%values(2)%s == '2', 'zip: paired values')

  ! Errors name the file, the line and the word.
  call expect_error('VARY TIME.STEP 1 2' // NL // 'METRIC contact_duration', 'no SCENE statement')
  call expect_error('SCENE s.dat' // NL // 'VARY TIME.STEP', 'VARY')
  call expect_error('SCENE s.dat' // NL // 'METRIC speed', ":2: METRIC speed: unknown metric")
  call expect_error('SCENE s.dat' // NL // 'METRIC apex PROBE m.UY AT 3', 'AT does not apply')
  call expect_error('SCENE s.dat' // NL // 'METRIC apex PROBE m.UY' // NL // 'REFERENCE VALUE apex2_m.UY=1', 'no metric column')
  call expect_error('SCENE s.dat' // NL // 'CASE a SET TIME.STEP' // NL, 'STATEMENT.PARAM=VALUE')
  call expect_error('SCENE s.dat' // NL // 'COMBINE ZIP' // NL // 'VARY TIME.STEP 1 2' // NL // 'VARY TIME.END 1', 'equal length')
  call expect_error('SCENE s.dat' // NL // 'REFERENCE CASE zz', 'no CASE of that name')

  call check(case_dir_name(7, 12) == 'case_007' .and. case_dir_name(12, 1500) == 'case_0012', 'case_NNN: at least 3 digits')
  open (newunit=stat, file=F)
  close (stat, status='delete')
  call test_summary('sweep_spec')

contains

  function str_cols() result(s)
    character(len=:), allocatable :: s
    integer :: i
    s = ''
    do i = 1, size(sw%columns)
      s = s // ' ' // sw%columns(i)%s
    end do
  end function str_cols

  subroutine write_file(text)
    character(len=*), intent(in) :: text
    integer :: u
    open (newunit=u, file=F, status='replace', action='write', access='stream')
    write (u) text // achar(10)
    close (u)
  end subroutine write_file

  subroutine expect_error(text, fragment)
    character(len=*), intent(in) :: text, fragment
    call write_file(text)
    call parse_sweep(F, noextra, sw, stat, errmsg)
    call check(stat == STAT_INPUT .and. index(errmsg, fragment) > 0, 'error "' // fragment // '"', errmsg)
  end subroutine expect_error
end program test_sweep_spec
