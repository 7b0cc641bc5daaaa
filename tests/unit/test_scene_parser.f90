!> Tests of scene_parser: lexing, schema-driven splitting, every error path (file:line, keyword
!> and offending word), --set overrides, strict numbers, long lines, binary garbage, empty input.
program test_scene_parser
  use, intrinsic :: iso_fortran_env, only: int64
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, STAT_RUN, shown
  use testing, only: check, check_close, test_summary
  use statement, only: token_t, statement_t, stmt_error, find_param, count_param, get_real, get_int, get_word, &
    get_real_list, get_int_list, to_real, to_int
  use statement_schema, only: schema_t
  use scene_parser, only: parse_file, parse_string, read_text, apply_override
  use number_text, only: parse_real_text, parse_int_text, real_text, NUM_OK, NUM_MALFORMED, NUM_RANGE
  implicit none

  character(len=*), parameter :: NL = new_line('a')
  type(schema_t) :: sch
  character(len=:), allocatable :: tmpdir

  tmpdir = scratch_dir()
  call execute_command_line('mkdir -p ' // tmpdir)
  call build_schema(sch)

  call test_schema()
  call test_lexing()
  call test_splitting()
  call test_errors()
  call test_lexical_errors()
  call test_overrides()
  call test_numbers()
  call test_getters()
  call test_long_lines()
  call test_garbage()
  call test_files()
  call test_number_texts()
  call execute_command_line('rm -rf ' // tmpdir)
  call test_summary('scene_parser')

contains

  !> $TMPDIR/rebond_test_scene_parser (default /tmp) for the generated scene files.
  function scratch_dir() result(d)
    character(len=:), allocatable :: d
    character(len=1024) :: t
    integer :: n, st
    call get_environment_variable('TMPDIR', t, n, st)
    if (st /= 0 .or. n == 0) t = '/tmp'
    d = trim(t) // '/rebond_test_scene_parser'
  end function scratch_dir

  subroutine build_schema(s)
    type(schema_t), intent(inout) :: s
    call s%add_keyword('MATERIAL', nlead_min=1, nlead_max=1)
    call s%add_param('MATERIAL', 'YOUNG', nmin=1, nmax=1)
    call s%add_param('MATERIAL', 'POISSON', nmin=1, nmax=1)
    call s%add_param('MATERIAL', 'DENSITY', nmin=1, nmax=1)
    call s%add_keyword('LINE', nlead_min=1, nlead_max=1)
    call s%add_param('LINE', 'FROM', nmin=2, nmax=2)
    call s%add_param('LINE', 'TO', nmin=2, nmax=2)
    call s%add_param('LINE', 'DIV', nmin=1, nmax=1)
    call s%add_keyword('GROUP', nlead_min=1, nlead_max=3)
    call s%add_param('GROUP', 'NODES', nmin=1, nmax=-1)
    call s%add_param('GROUP', 'FLAG', nmin=0, nmax=0)
    call s%add_param('GROUP', 'RANGE', nmin=1, nmax=2)
    call s%add_keyword('LOAD', nlead_min=1, nlead_max=1)
    call s%add_param('LOAD', 'NODES', nmin=1, nmax=-1, repeatable=.true.)
    call s%add_param('LOAD', 'FORCE', nmin=2, nmax=2)
    call s%add_keyword('GRAVITY')
    call s%add_param('GRAVITY', 'G', nmin=2, nmax=2)
    call s%add_keyword('SCHEME')
    call s%add_param('SCHEME', 'DT', nmin=1, nmax=1)
    call s%add_param('SCHEME', 'STEPS', nmin=1, nmax=1)
    call s%add_param('SCHEME', 'LUMPED')
    call s%add_param('SCHEME', 'TITLE', nmin=1, nmax=1)
  end subroutine build_schema

  !> Parse text expected to be valid.
  subroutine parse_ok(text, stmts, name)
    character(len=*), intent(in) :: text, name
    type(statement_t), allocatable, intent(out) :: stmts(:)
    integer :: stat
    character(len=:), allocatable :: errmsg
    call parse_string(text, 't.dat', sch, stmts, stat, errmsg)
    call check(stat == STAT_OK, name // ' parses', errmsg)
  end subroutine parse_ok

  !> Parse text expected to fail with a message "t.dat:<prefix>...<suffix>" containing `middle`.
  subroutine parse_bad(text, prefix, middle, suffix, name)
    character(len=*), intent(in) :: text, prefix, middle, suffix, name
    type(statement_t), allocatable :: stmts(:)
    integer :: stat
    character(len=:), allocatable :: errmsg
    call parse_string(text, 't.dat', sch, stmts, stat, errmsg)
    call check(stat == STAT_INPUT, name // ': stat = STAT_INPUT')
    call check_msg(errmsg, 't.dat:' // prefix, middle, suffix, name)
    call check(size(stmts) == 0, name // ': no statements returned')
  end subroutine parse_bad

  subroutine check_msg(msg, prefix, middle, suffix, name)
    character(len=*), intent(in) :: msg, prefix, middle, suffix, name
    logical :: ok
    ok = len(msg) >= len(prefix) + len(suffix)
    if (ok) ok = msg(1:len(prefix)) == prefix .and. msg(len(msg) - len(suffix) + 1:) == suffix
    if (ok) ok = index(msg, middle) > 0
    call check(ok, name // ': message', 'got "' // msg // '"; want "' // prefix // '...' // middle // '...' // suffix // '"')
  end subroutine check_msg

  subroutine test_schema()
    type(schema_t) :: bad
    type(statement_t), allocatable :: stmts(:)
    integer :: stat
    character(len=:), allocatable :: errmsg
    call check(sch%param_names('line') == 'FROM, TO, DIV', 'param_names lists in declaration order')
    call check(sch%param_names('NOPE') == '', 'param_names of unknown keyword is empty')
    call check(sch%has_keyword('Gravity') .and. .not. sch%has_keyword('GRAV'), 'has_keyword is case-insensitive')
    call bad%add_keyword('A')
    call bad%add_param('B', 'X', nmin=1, nmax=1)
    call parse_string('A', 'x', bad, stmts, stat, errmsg)
    call check(stat == STAT_RUN .and. index(errmsg, 'undeclared keyword B') > 0, 'schema defect reported by parse', errmsg)
  end subroutine test_schema

  subroutine test_lexing()
    type(statement_t), allocatable :: s(:)
    character(len=:), allocatable :: text
    text = '# header comment' // NL // &
           '' // NL // &
           'material Steel  Young 210e9 poisson 0.3   # trailing comment' // NL // &   ! line 3
           achar(9) // 'LINE "my beam # not a comment" fRoM 0 0 &' // NL // &      ! line 4
           '   # a comment line inside the continuation' // NL // &
           '' // NL // &
           '   TO 1.5 "-2"&' // NL // &                                              ! line 7
           '   DIV 4' // achar(13) // NL // &                                        ! line 8 (CRLF)
           'line b from 1 2 to 3 4 # &  (a comment hides the ampersand)' // NL // &  ! line 9
           'gravity G 0 -9.81'                                                         ! line 10, no final LF
    call parse_ok(text, s, 'lexing')
    if (size(s) /= 4) then
      call check(.false., 'lexing: 4 statements', 'got ' // achar(48 + min(size(s), 9)))
      return
    end if
    call check(s(1)%keyword == 'MATERIAL' .and. s(1)%line == 3 .and. s(1)%kwtok%text == 'material', &
               'keyword upper-cased, kwtok as written, line counted over comments and blanks')
    call check(s(1)%lead(1)%text == 'Steel', 'lead keeps its case')
    call check(s(1)%params(1)%key == 'YOUNG' .and. s(1)%params(1)%keytok%text == 'Young', 'parameter upper-cased')
    call check(s(1)%params(2)%values(1)%text == '0.3' .and. size(s(1)%params) == 2, 'trailing comment removed')
    call check(s(2)%keyword == 'LINE' .and. s(2)%line == 4, 'tab before keyword')
    call check(s(2)%lead(1)%text == 'my beam # not a comment' .and. s(2)%lead(1)%quoted, 'quoted token keeps # and blanks')
    call check(size(s(2)%params) == 3, 'continuation joins 3 physical lines across comment and blank lines')
    call check(s(2)%params(1)%key == 'FROM' .and. s(2)%params(1)%keytok%line == 4, 'FROM on line 4')
    call check(s(2)%params(2)%key == 'TO' .and. s(2)%params(2)%keytok%line == 7, 'TO on line 7')
    call check(s(2)%params(2)%values(2)%text == '-2' .and. s(2)%params(2)%values(2)%quoted, &
               'quoted value directly followed by &')
    call check(s(2)%params(3)%values(1)%text == '4' .and. s(2)%params(3)%values(1)%line == 8, 'CR is a blank')
    call check(s(3)%lead(1)%text == 'b' .and. size(s(3)%params) == 2 .and. s(3)%line == 9, &
               '& inside a comment does not continue')
    call check(s(4)%keyword == 'GRAVITY' .and. size(s(4)%lead) == 0 .and. s(4)%params(1)%values(2)%text == '-9.81', &
               'last line without newline')
    call check(s(2)%file == 't.dat', 'file name recorded')

    ! 'value&' at end of line: the & is removed from the word
    call parse_ok('LINE a FROM 1 2&' // NL // 'TO 3 4', s, 'word&')
    call check(size(s) == 1, 'word& continues')
    if (size(s) == 1) call check(s(1)%params(1)%values(2)%text == '2' .and. s(1)%params(2)%keytok%line == 2, &
                                 'word& keeps the word')
    ! a lone & not at the end of a line is an ordinary token; a quoted "&" does not continue
    call parse_ok('GROUP g NODES 1 & 2' // NL // 'GROUP h NODES "&"' // NL // 'SCHEME', s, 'inner &')
    call check(size(s) == 3, 'inner & and quoted & do not continue')
    if (size(s) == 3) then
      call check(size(s(1)%params(1)%values) == 3 .and. s(1)%params(1)%values(2)%text == '&', 'inner & is a value')
      call check(s(2)%params(1)%values(1)%text == '&' .and. s(2)%params(1)%values(1)%quoted, 'quoted & is a value')
    end if
    ! empty quoted string; non-ASCII inside quotes and comments is fine
    call parse_ok('SCHEME TITLE "" # caf' // char(195) // char(169) // NL // &
                  'MATERIAL "b' // char(195) // char(169) // 'ton"', s, 'quotes')
    call check(size(s) == 2, 'quotes: 2 statements')
    if (size(s) == 2) then
      call check(len(s(1)%params(1)%values(1)%text) == 0 .and. s(1)%params(1)%values(1)%quoted, 'empty quoted string')
      call check(s(2)%lead(1)%text == 'b' // char(195) // char(169) // 'ton', 'UTF-8 inside quotes kept')
    end if
    ! only blanks and comments: no statements
    call parse_ok('   ' // NL // '# x' // NL // achar(9) // NL, s, 'blank lines')
    call check(size(s) == 0, 'blank and comment lines give no statement')
    call parse_ok('', s, 'empty text')
    call check(size(s) == 0, 'empty text gives no statement')
  end subroutine test_lexing

  subroutine test_splitting()
    type(statement_t), allocatable :: s(:)
    call parse_ok('GROUP a b NODES 1 2 3 4 5 FLAG RANGE 7' // NL // &
                  'GROUP x y z RANGE 1 2 NODES 9' // NL // &
                  'GROUP q FROM' // NL // &
                  'GROUP "nodes" NODES "flag" Flag' // NL // &
                  'LOAD p NODES 1 2 FORCE 0 -1 nodes 3', s, 'splitting')
    if (size(s) /= 5) then
      call check(.false., 'splitting: 5 statements')
      return
    end if
    call check(size(s(1)%lead) == 2 .and. s(1)%lead(2)%text == 'b', 'lead stops at the first parameter name')
    call check(size(s(1)%params) == 3, '3 parameters')
    call check(size(s(1)%params(1)%values) == 5, 'unbounded NODES takes all 5 values')
    call check(s(1)%params(2)%key == 'FLAG' .and. size(s(1)%params(2)%values) == 0, 'flag has no value')
    call check(size(s(1)%params(3)%values) == 1, 'RANGE 1..2 with 1 value')
    call check(size(s(2)%lead) == 3 .and. size(s(2)%params(1)%values) == 2 .and. s(2)%params(2)%key == 'NODES', &
               'lead of 3, RANGE with 2, then NODES')
    call check(size(s(3)%lead) == 2 .and. s(3)%lead(2)%text == 'FROM', 'a parameter name of another keyword is a lead')
    call check(s(4)%lead(1)%text == 'nodes' .and. s(4)%params(1)%values(1)%text == 'flag' .and. &
               s(4)%params(2)%key == 'FLAG', 'quoted tokens are never parameter names')
    call check(count_param(s(5), 'nodes') == 2 .and. find_param(s(5), 'NODES', 2) == 3 .and. &
               find_param(s(5), 'Force') == 2 .and. find_param(s(5), 'NODES', 3) == 0, &
               'repeatable parameter: count_param and find_param occurrence')
  end subroutine test_splitting

  subroutine test_errors()
    call parse_bad('SCHEME' // NL // 'FOO 1 2', '2: FOO: ', &
                   'unknown keyword (expected one of: MATERIAL, LINE, GROUP, LOAD, GRAVITY, SCHEME)', ", at 'FOO'", &
                   'unknown keyword')
    call parse_bad(NL // 'LINE a FROM 1 TO 1 2', '2: LINE a: ', 'parameter FROM of LINE expects 2 values, found 1', &
                   ", at 'FROM'", 'too few values before the next parameter')
    call parse_bad('LINE a TO 1 2 &' // NL // ' from 1', '2: LINE a: ', 'parameter FROM of LINE expects 2 values, found 1', &
                   ", at 'from'", 'too few values at the end of the statement')
    call parse_bad('GROUP a NODES', '1: GROUP a: ', 'parameter NODES of GROUP expects at least 1 value, found 0', &
                   ", at 'NODES'", 'unbounded parameter with no value')
    call parse_bad(NL // NL // 'MATERIAL steel YOUNGS 1', '3: MATERIAL steel: ', &
                   "unknown parameter 'YOUNGS' for MATERIAL (expected one of: YOUNG, POISSON, DENSITY)", &
                   ", at 'YOUNGS'", 'unknown parameter')
    call parse_bad('MATERIAL steel YOUNG 1 2', '1: MATERIAL steel: ', "unknown parameter '2' for MATERIAL", &
                   ", at '2'", 'value after nmax values')
    call parse_bad('MATERIAL steel YOUNG 1 2', '1: MATERIAL steel: ', 'YOUNG takes 1 value', ", at '2'", &
                   'hint names the full parameter')
    call parse_bad('GROUP a b c d NODES 1', '1: GROUP a: ', "unknown parameter 'd'", ", at 'd'", 'too many lead tokens')
    call parse_bad('MATERIAL steel YOUNG 1 "x"', '1: MATERIAL steel: ', 'quoted string where a parameter name', &
                   ", at 'x'", 'quoted token where a parameter is expected')
    call parse_bad('SCHEME' // NL // NL // 'MATERIAL s YOUNG 1 POISSON 0.3 &' // NL // '  young 2', &
                   '4: MATERIAL s: ', 'parameter YOUNG repeated (first at line 3)', ", at 'young'", 'repeated parameter')
    call parse_bad('SCHEME LUMPED DT 1 LUMPED', '1: SCHEME: ', 'parameter LUMPED repeated (first at line 1)', &
                   ", at 'LUMPED'", 'repeated flag')
    call parse_bad('LINE FROM 0 0 TO 1 1', '1: LINE: ', 'expects 1 name or value before its parameters, found 0', &
                   ", at 'FROM'", 'missing lead before a parameter')
    call parse_bad('SCHEME' // NL // 'MATERIAL', '2: MATERIAL: ', 'expects 1 name or value, found 0', &
                   ", at 'MATERIAL'", 'missing lead at the end')
    call parse_bad('"LINE" a', '1: ', 'a statement must start with a keyword', ", at 'LINE'", 'quoted keyword')
    call parse_bad('SCHEME' // NL // 'LINE a FROM 0 0 &', '2: LINE: ', "continued with '&' at the end of the file", &
                   ", at '&'", 'continuation at end of file')
    call parse_bad('LINE a FROM 0 0 &' // NL // '# only a comment follows' // NL, '1: LINE: ', &
                   "continued with '&' at the end of the file", ", at '&'", 'continuation then comment at end of file')
  end subroutine test_errors

  subroutine test_lexical_errors()
    call parse_bad('SCHEME TITLE "abc' // NL // 'SCHEME', '1: SCHEME: ', 'unterminated quoted string', &
                   ", at '" // '"abc' // "'", 'unterminated quote')
    call parse_bad(NL // 'LINE "a', '2: LINE: ', 'unterminated quoted string', ", at '" // '"a' // "'", &
                   'unterminated quote at end of text')
    call parse_bad('SCHEME TITLE a"b"', '1: SCHEME: ', 'a quote may only start a word', ", at 'a" // '"b"' // "'", &
                   'quote inside a word')
    call parse_bad('SCHEME TITLE "a"b', '1: SCHEME: ', 'a blank must follow a closing quote', &
                   ", at '" // '"b' // "'", 'text after a closing quote')
    call parse_bad('SCHEME DT 1' // achar(0) // '0', '1: SCHEME: ', 'unexpected character (byte 0x00)', ", at '1?0'", &
                   'NUL byte')
    call parse_bad('SCHEME' // NL // 'MATERIAL caf' // char(195) // char(169), '2: MATERIAL: ', &
                   'unexpected character (byte 0xC3)', ", at 'caf??'", 'UTF-8 outside quotes')
    call parse_bad(achar(127) // 'LINE', '1: ', 'unexpected character (byte 0x7F)', ", at '?LINE'", 'DEL before keyword')
    call parse_bad('SCHEME # bell ' // achar(7), '1: SCHEME: ', 'unexpected character (byte 0x07)', ", at '?'", &
                   'control character in a comment')
    call parse_bad('SCHEME TITLE "x' // achar(27) // '"', '1: SCHEME: ', 'unexpected character (byte 0x1B)', &
                   ", at '" // '"x?"' // "'", 'control character in quotes')
  end subroutine test_lexical_errors

  subroutine test_overrides()
    type(statement_t), allocatable :: s(:)
    integer :: stat, ip
    character(len=:), allocatable :: errmsg
    real(dp) :: x
    call parse_ok('MATERIAL steel YOUNG 210e9 POISSON 0.3' // NL // &
                  'MATERIAL alu.6061 YOUNG 70e9' // NL // &
                  'GRAVITY G 0 -9.81' // NL // &
                  'SCHEME DT 1e-3' // NL // &
                  'LOAD p NODES 1 NODES 2 FORCE 0 1', s, 'override scene')
    if (size(s) /= 5) return

    call apply_override(s, sch, 'material.steel.young=1e9', stat, errmsg)
    call check(stat == STAT_OK, 'override: replace named', errmsg)
    ip = find_param(s(1), 'YOUNG')
    call check(ip == 1 .and. size(s(1)%params) == 2, 'replace keeps position and count')
    call check(s(1)%params(ip)%values(1)%text == '1e9' .and. s(1)%params(ip)%values(1)%line == 0, &
               'replaced value with line 0')
    call check(s(2)%params(1)%values(1)%text == '70e9', 'other MATERIAL untouched')

    call apply_override(s, sch, 'MATERIAL.alu.6061.DENSITY=2700', stat, errmsg)
    call check(stat == STAT_OK, 'override: append to a name containing dots', errmsg)
    call check(size(s(2)%params) == 2 .and. s(2)%params(2)%key == 'DENSITY' .and. &
               s(2)%params(2)%values(1)%text == '2700' .and. s(2)%params(2)%keytok%line == 0, 'appended parameter')

    call apply_override(s, sch, 'gravity.g=1.5 -3', stat, errmsg)
    call check(stat == STAT_OK, 'override: multi-value', errmsg)
    call get_real(s(3), 'G', x, stat, errmsg, index=2)
    call check(stat == STAT_OK .and. x == -3.0_dp .and. size(s(3)%params(1)%values) == 2, 'multi-value replaced')

    call apply_override(s, sch, 'SCHEME.LUMPED=', stat, errmsg)
    call check(stat == STAT_OK .and. count_param(s(4), 'LUMPED') == 1, 'override: flag appended with empty value', errmsg)
    call apply_override(s, sch, 'SCHEME.TITLE="two words"', stat, errmsg)
    call check(stat == STAT_OK, 'override: quoted value', errmsg)
    call check(s(4)%params(find_param(s(4), 'TITLE'))%values(1)%text == 'two words', 'quoted value kept whole')

    call apply_override(s, sch, 'MATERIAL.YOUNG=1', stat, errmsg)
    call check(stat == STAT_INPUT, 'ambiguous keyword: stat')
    call check_msg(errmsg, '--set MATERIAL.YOUNG=1: ', 'MATERIAL occurs 2 times', 'MATERIAL.NAME.YOUNG=VALUE', 'ambiguous')

    call apply_override(s, sch, 'LINE.FROM=0 0', stat, errmsg)
    call check_msg(errmsg, '--set LINE.FROM=0 0: ', 'no LINE statement', '', 'keyword absent from the scene')
    call apply_override(s, sch, 'MATERIAL.Steel.YOUNG=1', stat, errmsg)
    call check_msg(errmsg, '--set MATERIAL.Steel.YOUNG=1: ', "no MATERIAL statement named 'Steel'", '', &
                   'NAME is case-sensitive')
    call apply_override(s, sch, 'FOO.X=1', stat, errmsg)
    call check(stat == STAT_INPUT, 'unknown keyword: stat')
    call check_msg(errmsg, '--set FOO.X=1: ', "unknown keyword 'FOO' (expected one of: MATERIAL", '', 'unknown keyword')
    call apply_override(s, sch, 'SCHEME.DTT=1', stat, errmsg)
    call check_msg(errmsg, '--set SCHEME.DTT=1: ', "unknown parameter 'DTT' for SCHEME (expected one of: DT, STEPS", '', &
                   'unknown parameter')
    call apply_override(s, sch, 'GRAVITY.G=1', stat, errmsg)
    call check_msg(errmsg, '--set GRAVITY.G=1: ', 'parameter G of GRAVITY expects 2 values, found 1', '', &
                   'too few override values')
    call apply_override(s, sch, 'SCHEME.DT=1 2', stat, errmsg)
    call check_msg(errmsg, '--set SCHEME.DT=1 2: ', 'expects 1 value, found 2', '', 'too many override values')
    call apply_override(s, sch, 'SCHEME.LUMPED=yes', stat, errmsg)
    call check_msg(errmsg, '--set SCHEME.LUMPED=yes: ', 'expects no value, found 1', '', 'flag takes no value')
    call apply_override(s, sch, 'SCHEME.x.DT=1', stat, errmsg)
    call check_msg(errmsg, '--set SCHEME.x.DT=1: ', 'SCHEME statements have no name', '', 'NAME for an unnamed keyword')
    call apply_override(s, sch, 'SCHEME.DT', stat, errmsg)
    call check_msg(errmsg, '--set SCHEME.DT: ', 'expected KEYWORD.PARAM=VALUE', '', 'no =')
    call apply_override(s, sch, 'SCHEME=1', stat, errmsg)
    call check_msg(errmsg, '--set SCHEME=1: ', 'expected KEYWORD.PARAM=VALUE', '', 'no parameter')
    call apply_override(s, sch, 'LOAD.NODES=5', stat, errmsg)
    call check_msg(errmsg, '--set LOAD.NODES=5: ', 'parameter NODES occurs 2 times', '', 'repeated parameter not replaced')
    call apply_override(s, sch, 'SCHEME.TITLE="x', stat, errmsg)
    call check_msg(errmsg, '--set SCHEME.TITLE="x: ', 'unterminated quoted string', '', 'lexical error in VALUE')

    ! a bad value given with --set is reported against the statement, marked as such
    call apply_override(s, sch, 'SCHEME.DT=abc', stat, errmsg)
    call check(stat == STAT_OK, 'override values are not interpreted')
    call get_real(s(4), 'DT', x, stat, errmsg)
    call check(stat == STAT_INPUT, 'bad --set value: stat')
    call check_msg(errmsg, 't.dat:4: SCHEME: ', 'expected a number', ", at 'abc' (given with --set)", 'bad --set value')
  end subroutine test_overrides

  subroutine test_numbers()
    character(len=16), parameter :: good(*) = [character(len=16) :: '1', '+1', '-1', '1.', '1.5', '.5', '-.5', &
      '+.25', '1e3', '1E-3', '1d3', '1.5D+2', '0', '007', '1.e5', '-0.0', '2.5e-1']
    real(dp), parameter :: goodv(*) = [1.0_dp, 1.0_dp, -1.0_dp, 1.0_dp, 1.5_dp, 0.5_dp, -0.5_dp, &
      0.25_dp, 1000.0_dp, 1.0e-3_dp, 1000.0_dp, 150.0_dp, 0.0_dp, 7.0_dp, 1.0e5_dp, 0.0_dp, 0.25_dp]
    character(len=16), parameter :: bad(*) = [character(len=16) :: '', '+', '-', '.', 'e3', '1e', '1e+', &
      '1.5.2', '1,2', 'T', 'F', 'NaN', 'nan', 'Inf', '-Infinity', '0x10', ' 1', '1f', '1e3.5', '++1', '1_dp', &
      '--1', '1/', '1d', '.e1', '1e 3', '1.0q0', '+-1', '(1,2)', '1*2', '2*1']
    character(len=24), parameter :: igood(*) = [character(len=24) :: '0', '-0', '+42', '2147483647', &
      '-2147483648', '000000000000012', '-7']
    integer, parameter :: igoodv(*) = [0, 0, 42, 2147483647, -2147483647 - 1, 12, -7]
    character(len=24), parameter :: ibad(*) = [character(len=24) :: '', '+', '-', '1.5', '1e3', '1.', '12a', &
      '0x1', ' 1', '1 2', '1,2', 'T']
    character(len=40), parameter :: irange(*) = [character(len=40) :: '2147483648', '-2147483649', &
      '99999999999999999999', '-00000000000000000000099999999999']
    !> 2**1024 - 2**970 written out in full (309 digits)
    character(len=*), parameter :: THRESH = '1797693134862315807937289714053034150799341327100378269361737789804449' // &
      '68292764750946649017977587207096330286416692887910946555547851940402630657488671505820681908902000708383676' // &
      '273854845817711531764475730270069855571366959622842914819860834936475292719074168444365510704342711559699508' // &
      '093042880177904174497792'
    real(dp) :: x
    integer :: i, ierr, n
    logical :: ok
    ! Exact comparisons on purpose: READ rounds correctly, and every expected value is either exact
    ! in binary or the compiler's own correctly rounded literal of the same decimal.
    ok = .true.
    do i = 1, size(good)
      call parse_real_text(trim(good(i)), x, ierr)
      if (ierr /= NUM_OK .or. x /= goodv(i)) then
        ok = .false.
        call check(.false., 'accept real ' // trim(good(i)))
      end if
    end do
    ! decimal literals that are exact in binary (or equal to the same literal in source) compare exactly
    call check(ok, 'real accept table')
    ok = .true.
    do i = 1, size(bad)
      call parse_real_text(trim(bad(i)), x, ierr)
      if (ierr /= NUM_MALFORMED) then
        ok = .false.
        call check(.false., 'reject real "' // trim(bad(i)) // '"')
      end if
    end do
    call check(ok, 'real reject table')
    call parse_real_text('1 ', x, ierr)
    call check(ierr == NUM_MALFORMED, 'trailing blank rejected')
    call parse_real_text('1e309', x, ierr)
    call check(ierr == NUM_RANGE, '1e309 out of range')
    call parse_real_text('-1.8e308', x, ierr)
    call check(ierr == NUM_RANGE, '-1.8e308 out of range')
    call parse_real_text('1.7976931348623157e308', x, ierr)
    call check(ierr == NUM_OK .and. x == huge(x), 'huge(dp) accepted')
    ! the overflow threshold is (2 - 2**-53) * 2**1023 = 1.797693134862315807937...e308 (round-to-nearest-even)
    call parse_real_text('1.7976931348623158e308', x, ierr)
    call check(ierr == NUM_OK .and. x == huge(x), 'just below the overflow threshold rounds to huge')
    call parse_real_text('1.797693134862315808e308', x, ierr)
    call check(ierr == NUM_RANGE, 'just above the overflow threshold')
    call parse_real_text(THRESH, x, ierr)
    call check(ierr == NUM_RANGE, 'exact overflow threshold (a tie, rounds to Inf)')
    call parse_real_text(THRESH(1:len(THRESH) - 1) // '1', x, ierr)
    call check(ierr == NUM_OK .and. x == huge(x), 'threshold - 1 rounds to huge')
    call parse_real_text('0.001e311', x, ierr)
    call check(ierr == NUM_OK .and. x == 1.0e308_dp, 'leading zeros count in the exponent')
    call parse_real_text('1e99999999999', x, ierr)
    call check(ierr == NUM_RANGE, 'huge exponent out of range')
    call parse_real_text('-1e-99999999999', x, ierr)
    call check(ierr == NUM_OK .and. x == 0.0_dp, 'huge negative exponent gives 0')
    call parse_real_text('0e999999', x, ierr)
    call check(ierr == NUM_OK .and. x == 0.0_dp, 'zero with a huge exponent is 0')
    call parse_real_text('1e-400', x, ierr)
    call check(ierr == NUM_OK .and. x == 0.0_dp, 'underflow gives 0')
    call parse_real_text('0.1', x, ierr)
    call check(x == 0.1_dp, '0.1 correctly rounded (same as the compiler literal)')
    call parse_real_text('3.14159265358979323846264338327950288', x, ierr)
    call check_close(x, 4.0_dp * atan(1.0_dp), epsilon(x), 'long mantissa pi within 1 ulp of 4*atan(1)')

    ok = .true.
    do i = 1, size(igood)
      call parse_int_text(trim(igood(i)), n, ierr)
      if (ierr /= NUM_OK .or. n /= igoodv(i)) then
        ok = .false.
        call check(.false., 'accept integer ' // trim(igood(i)))
      end if
    end do
    call check(ok, 'integer accept table')
    ok = .true.
    do i = 1, size(ibad)
      call parse_int_text(trim(ibad(i)), n, ierr)
      if (ierr /= NUM_MALFORMED) then
        ok = .false.
        call check(.false., 'reject integer "' // trim(ibad(i)) // '"')
      end if
    end do
    call check(ok, 'integer reject table')
    ok = .true.
    do i = 1, size(irange)
      call parse_int_text(trim(irange(i)), n, ierr)
      if (ierr /= NUM_RANGE) then
        ok = .false.
        call check(.false., 'integer out of range "' // trim(irange(i)) // '"')
      end if
    end do
    call check(ok, 'integer range table')
  end subroutine test_numbers

  subroutine test_getters()
    type(statement_t), allocatable :: s(:)
    integer :: stat, n
    integer, allocatable :: ns(:)
    real(dp), allocatable :: xs(:)
    character(len=:), allocatable :: errmsg, w
    real(dp) :: x
    call parse_ok('MATERIAL steel YOUNG -1 POISSON 0.5' // NL // &
                  'SCHEME DT 1e-3 STEPS 0 TITLE Cantilever' // NL // &
                  'GROUP g NODES 1 2 -3 RANGE 1.5' // NL // &
                  'GRAVITY G 0 1e999' // NL // &
                  'LOAD p NODES 4 FORCE x 1', s, 'getters scene')
    if (size(s) /= 5) return
    call get_real(s(2), 'dt', x, stat, errmsg, lower=0.0_dp)
    call check(stat == STAT_OK .and. x == 1.0e-3_dp, 'get_real value, key case-insensitive', errmsg)
    call get_real(s(1), 'YOUNG', x, stat, errmsg, lower=0.0_dp)
    call check(stat == STAT_INPUT, 'get_real lower bound: stat')
    call check_msg(errmsg, 't.dat:1: MATERIAL steel: ', 'YOUNG must be > 0', ", at '-1'", 'get_real lower bound')
    call get_real(s(1), 'POISSON', x, stat, errmsg, lower=-1.0_dp, upper=0.5_dp)
    call check_msg(errmsg, 't.dat:1: MATERIAL steel: ', 'POISSON must be < 0.5', ", at '0.5'", 'get_real upper bound')
    call get_real(s(1), 'POISSON', x, stat, errmsg, upper=0.5_dp, upper_inclusive=.true.)
    call check(stat == STAT_OK .and. x == 0.5_dp, 'get_real inclusive upper bound', errmsg)
    call get_real(s(1), 'DENSITY', x, stat, errmsg)
    call check_msg(errmsg, 't.dat:1: MATERIAL steel: ', 'missing parameter DENSITY', ", at 'MATERIAL'", 'missing parameter')
    call get_real(s(1), 'DENSITY', x, stat, errmsg, default=7800.0_dp)
    call check(stat == STAT_OK .and. x == 7800.0_dp, 'default when missing')
    call get_real(s(4), 'G', x, stat, errmsg, index=2)
    call check_msg(errmsg, 't.dat:4: GRAVITY: ', 'number out of range', ", at '1e999'", 'out of range value')
    call get_real(s(5), 'FORCE', x, stat, errmsg)
    call check_msg(errmsg, 't.dat:5: LOAD p: ', 'expected a number', ", at 'x'", 'malformed value')
    call get_real(s(3), 'RANGE', x, stat, errmsg, index=2)
    call check_msg(errmsg, 't.dat:3: GROUP g: ', 'parameter RANGE has no value number 2', ", at 'RANGE'", 'missing index')
    call get_real(s(3), 'RANGE', x, stat, errmsg, index=2, default=-1.0_dp)
    call check(stat == STAT_OK .and. x == -1.0_dp, 'default for a missing optional value')

    call get_int(s(2), 'STEPS', n, stat, errmsg, lower=0, lower_inclusive=.true.)
    call check(stat == STAT_OK .and. n == 0, 'get_int inclusive lower bound', errmsg)
    call get_int(s(2), 'STEPS', n, stat, errmsg, lower=0)
    call check_msg(errmsg, 't.dat:2: SCHEME: ', 'STEPS must be > 0', ", at '0'", 'get_int exclusive lower bound')
    call get_int(s(3), 'RANGE', n, stat, errmsg)
    call check_msg(errmsg, 't.dat:3: GROUP g: ', 'expected an integer', ", at '1.5'", 'get_int rejects 1.5')
    call get_int_list(s(3), 'NODES', ns, stat, errmsg)
    call check(stat == STAT_OK .and. size(ns) == 3, 'get_int_list', errmsg)
    if (size(ns) == 3) call check(all(ns == [1, 2, -3]), 'get_int_list values')
    call get_real_list(s(4), 'G', xs, stat, errmsg)
    call check(stat == STAT_INPUT .and. index(errmsg, "at '1e999'") > 0, 'get_real_list reports the bad value')
    call get_real_list(s(3), 'FLAG', xs, stat, errmsg)
    call check(stat == STAT_INPUT .and. index(errmsg, 'missing parameter FLAG') > 0, 'get_real_list missing')

    call get_word(s(2), 'TITLE', w, stat, errmsg)
    call check(stat == STAT_OK .and. w == 'Cantilever', 'get_word keeps case')
    call get_word(s(2), 'LUMPED', w, stat, errmsg, default='no')
    call check(stat == STAT_OK .and. w == 'no', 'get_word default')
    call get_word(s(2), 'LUMPED', w, stat, errmsg)
    call check(stat == STAT_INPUT .and. index(errmsg, 'missing parameter LUMPED') > 0, 'get_word missing')

    ! stmt_error without token, with a token on a continuation line
    call check(stmt_error(s(1), 'boom') == 't.dat:1: MATERIAL steel: boom', 'stmt_error without token')
    call check(stmt_error(s(3), 'bad', s(3)%params(1)%values(3)) == "t.dat:3: GROUP g: bad, at '-3'", &
               'stmt_error with token')
  end subroutine test_getters

  subroutine test_long_lines()
    type(statement_t), allocatable :: s(:)
    character(len=:), allocatable :: text, big
    integer :: i, nvals, u
    ! one token of 50 000 characters
    allocate (character(len=50000) :: big)
    do i = 1, len(big)
      big(i:i) = achar(iachar('a') + mod(i, 26))
    end do
    call parse_ok('SCHEME TITLE ' // big // ' DT 1', s, '50 000-character token')
    if (size(s) == 1) call check(s(1)%params(1)%values(1)%text == big .and. s(1)%params(2)%key == 'DT', &
                                 'long token intact')
    ! a 50 000+ character line of values, in a file (read as one stream)
    nvals = 10000
    text = 'GROUP g NODES'
    do i = 1, nvals
      text = text // ' ' // achar(48 + mod(i, 10)) // achar(48 + mod(i / 10, 10)) // achar(48 + mod(i / 100, 10)) &
             // achar(48 + mod(i / 1000, 10))
    end do
    call check(len(text) > 50000, 'long line is longer than 50 000 characters')
    open (newunit=u, file=tmpdir // '/long.dat', status='replace', action='write')
    write (u, '(a)') 'SCHEME DT 1'
    write (u, '(a)') text
    write (u, '(a)') 'SCHEME STEPS 3'
    close (u)
    call file_ok(tmpdir // '/long.dat', s, 'long line file')
    call check(size(s) == 3, 'long line file: 3 statements')
    if (size(s) == 3) then
      call check(size(s(2)%params(1)%values) == nvals, 'all 10 000 values read')
      call check(s(2)%params(1)%values(nvals)%text == '0000' .and. s(3)%line == 3, 'last value and next line number')
    end if
    ! the message for an error on a long token is cut
    call parse_bad('SCHEME ' // big, '1: SCHEME: ', "unknown parameter '" // big(1:60) // "...'", &
                   ", at '" // big(1:60) // "...'", 'long word cut in messages')
  end subroutine test_long_lines

  subroutine test_garbage()
    type(statement_t), allocatable :: s(:)
    character(len=4096) :: junk
    integer :: i, stat, trial
    integer(int64) :: seed
    character(len=:), allocatable :: errmsg
    logical :: ok
    ok = .true.
    seed = 12345
    do trial = 1, 20
      do i = 1, len(junk)
        seed = modulo(1103515245_int64 * seed + 12345_int64, 2147483648_int64)   ! no int64 overflow
        junk(i:i) = achar(int(modulo(seed / 65536_int64, 256_int64)))
      end do
      call parse_string(junk, 'junk.bin', sch, s, stat, errmsg)
      ! 4096 uniform bytes contain control and non-ASCII bytes outside any comment with overwhelming probability
      if (stat /= STAT_INPUT .or. index(errmsg, 'junk.bin:') /= 1 .or. size(s) /= 0) ok = .false.
    end do
    call check(ok, 'random binary garbage: clean STAT_INPUT error, no crash')
    call parse_string(repeat(achar(0), 100), 'z', sch, s, stat, errmsg)
    call check(stat == STAT_INPUT .and. index(errmsg, 'byte 0x00') > 0, 'NUL bytes rejected')
  end subroutine test_garbage

  subroutine file_ok(path, s, name)
    character(len=*), intent(in) :: path, name
    type(statement_t), allocatable, intent(out) :: s(:)
    integer :: stat
    character(len=:), allocatable :: errmsg
    call parse_file(path, sch, s, stat, errmsg)
    call check(stat == STAT_OK, name // ' parses', errmsg)
  end subroutine file_ok

  subroutine test_files()
    type(statement_t), allocatable :: s(:)
    character(len=:), allocatable :: errmsg, t1, t2
    integer :: u, stat
    real :: t0, t_small, t_big
    ! empty file
    open (newunit=u, file=tmpdir // '/empty.dat', status='replace', action='write')
    close (u)
    call file_ok(tmpdir // '/empty.dat', s, 'empty file')
    call check(size(s) == 0, 'empty file: zero statements')
    ! missing file
    call parse_file(tmpdir // '/nope.dat', sch, s, stat, errmsg)
    call check(stat == STAT_INPUT .and. index(errmsg, 'nope.dat') > 0 .and. size(s) == 0, 'missing file: STAT_INPUT')
    ! error messages name the path
    open (newunit=u, file=tmpdir // '/err.dat', status='replace', action='write')
    write (u, '(a)') '# comment'
    write (u, '(a)') 'MATERIAL m YOUNG 1 YOUNGS 2'
    close (u)
    call parse_file(tmpdir // '/err.dat', sch, s, stat, errmsg)
    call check_msg(errmsg, tmpdir // '/err.dat:2: MATERIAL m: ', "unknown parameter 'YOUNGS'", ", at 'YOUNGS'", &
                   'file error message')
    ! stream and formatted reading give the same text
    call read_text(tmpdir // '/long.dat', t1, stat, errmsg)
    call read_text(tmpdir // '/long.dat', t2, stat, errmsg, formatted=.true.)
    call check(t1 == t2 .and. len(t1) == len(t2) .and. len(t1) > 50000, 'stream and formatted reads agree')
    ! linear cost: 4x the statements should not cost anywhere near 16x (timing printed, loose bound)
    call write_many(tmpdir // '/small.dat', 20000)
    call write_many(tmpdir // '/big.dat', 80000)
    call cpu_time(t0)
    call file_ok(tmpdir // '/small.dat', s, 'small generated file')
    call cpu_time(t_small)
    t_small = t_small - t0
    call cpu_time(t0)
    call file_ok(tmpdir // '/big.dat', s, 'big generated file')
    call cpu_time(t_big)
    t_big = t_big - t0
    call check(size(s) == 80000, 'big file: 80 000 statements')
    if (size(s) == 80000) call check(s(80000)%line == 159999 .and. s(80000)%lead(1)%text == 'p80000', &
                                     'big file: last statement line and name')
    write (*, '(a,f8.3,a,f8.3,a)') '# parse time 20k statements ', t_small, ' s, 80k statements ', t_big, ' s'
    ! 4x input: linear ~4x; quadratic would be ~16x. 10x leaves room for timer noise.
    call check(t_big <= 10.0 * max(t_small, 0.02), 'parse time grows linearly')
  end subroutine test_files

  subroutine write_many(path, n)
    character(len=*), intent(in) :: path
    integer, intent(in) :: n
    integer :: u, i
    open (newunit=u, file=path, status='replace', action='write')
    do i = 1, n
      write (u, '(a,i0,a)') 'LOAD p', i, ' NODES 1 2 3 &   # comment'
      write (u, '(a)') '  FORCE 0.0 -1.5e3'
    end do
    close (u)
  end subroutine write_many
  !> real_text: the shortest text that reads back exactly (messages, checkpoint fingerprints);
  !> shown: text quoted, binary described.
  subroutine test_number_texts()
    real(dp), parameter :: xs(12) = [0.0_dp, 0.5_dp, -12.25_dp, 1.3e-3_dp, 1.0e100_dp, 1.0e150_dp, 0.1_dp, &
      1.0_dp / 3.0_dp, huge(1.0_dp), tiny(1.0_dp), 4.9e-324_dp, -2.0e-5_dp]
    character(len=*), parameter :: want(5) = [character(len=8) :: '0', '0.5', '-12.25', '0.0013', '1E+100']
    real(dp) :: y
    integer :: i, ierr
    do i = 1, size(xs)
      call parse_real_text(real_text(xs(i)), y, ierr)
      call check(ierr == NUM_OK .and. y == xs(i), 'real_text reads back exactly: ' // real_text(xs(i)))
    end do
    do i = 1, size(want)
      call check(real_text(xs(i)) == trim(want(i)), 'real_text form ' // trim(want(i)), real_text(xs(i)))
    end do
    call check(shown('beam.end UX') == 'beam.end UX', 'shown: text as it is')
    call check(shown('Young ' // char(195) // char(169)) == 'Young ' // char(195) // char(169), 'shown: UTF-8 kept')
    call check(shown('ab' // char(0) // 'c') == 'binary data (byte 0x00 at character 3)', 'shown: a NUL described', &
      shown('ab' // char(0) // 'c'))
    call check(shown(char(255) // 'x') == 'binary data (byte 0xFF at character 1)', 'shown: an invalid UTF-8 byte')
  end subroutine test_number_texts
end program test_scene_parser
