!> Schema-driven lexer and parser for rebond's keyword files (scene, sweep).
!>
!> A statement is `KEYWORD [lead tokens] (PARAM value*)*` on one logical line (physical lines
!> joined by a trailing `&`). The lexer only knows blanks, comments, quotes and continuations;
!> which token is a parameter name and how many values each parameter takes comes from a
!> schema_t (statement_schema) built by the caller, so the scene never splits text itself.
!> The lexical rules are documented in docs/input.md, section "Lexical rules". Values are read
!> out of the statements by the getters of module statement.
module scene_parser
  use, intrinsic :: iso_fortran_env, only: int64, iostat_end, iostat_eor
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str, upcase => upper
  use kinds, only: dp
  use statement, only: token_t, param_t, statement_t, stmt_error, shown, find_param, count_param, MAX_SHOWN
  use statement_schema, only: schema_t, kwdef_t, pdef_t, find_kw, find_pdef, param_of_token, pdef_list, arity_text, plural
  use number_text, only: parse_real_text, parse_int_text, NUM_MALFORMED
  use words, only: is_blank, word_end
  use line_reader, only: line_reader_t, open_reader, close_reader, raw_line, grow_text
  implicit none
  private
  public :: parse_file, parse_string, read_text, apply_override, check_required

  character(len=*), parameter :: LF = achar(10), CR = achar(13), TAB = achar(9)

contains

  !> Parse a scene file. Errors read `<path>:<line>: <KEYWORD>: <what>, at '<word>'`.
  subroutine parse_file(path, sch, stmts, stat, errmsg)
    character(len=*), intent(in) :: path
    type(schema_t), intent(in) :: sch
    type(statement_t), allocatable, intent(out) :: stmts(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: text
    call read_text(path, text, stat, errmsg)
    if (stat /= STAT_OK) then
      allocate (stmts(0))
      return
    end if
    call normalize_lines(text)
    call parse_string(text, path, sch, stmts, stat, errmsg)
  end subroutine parse_file

  !> A UTF-8 byte order mark dropped; a lone CR (old Mac line end) made LF (CR LF stays: the CR
  !> is a blank to the tokenizer). Same length or shorter, in place, linear.
  pure subroutine normalize_lines(text)
    character(len=:), allocatable, intent(inout) :: text
    integer :: i
    if (len(text) >= 3) then
      if (text(1:3) == char(239) // char(187) // char(191)) text = text(4:)
    end if
    do i = 1, len(text)
      if (text(i:i) /= CR) cycle
      if (i < len(text)) then
        if (text(i + 1:i + 1) == LF) cycle
      end if
      text(i:i) = LF
    end do
  end subroutine normalize_lines

  !> Whole file as one string, lines separated by LF. Regular files are read in one unformatted
  !> stream read (O(size), any line length, any byte); files of unknown size (pipes) or
  !> `formatted=.true.` use a non-advancing formatted loop with geometrically grown buffers.
  subroutine read_text(path, text, stat, errmsg, formatted)
    character(len=*), intent(in) :: path
    character(len=:), allocatable, intent(out) :: text
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical, intent(in), optional :: formatted
    integer :: u, ios
    integer(int64) :: sz
    character(len=256) :: iom
    logical :: use_fmt
    stat = STAT_OK
    errmsg = ''
    text = ''
    use_fmt = .false.
    if (present(formatted)) use_fmt = formatted
    if (.not. use_fmt) then
      iom = ''
      open (newunit=u, file=path, access='stream', form='unformatted', status='old', action='read', &
            iostat=ios, iomsg=iom)
      if (ios /= 0) then
        call set_error(stat, errmsg, STAT_INPUT, path // ': cannot open scene file: ' // trim(iom))
        return
      end if
      inquire (unit=u, size=sz)
      if (sz >= 0) then
        deallocate (text)
        allocate (character(len=sz) :: text)
        if (sz > 0) read (u, iostat=ios, iomsg=iom) text
        close (u)
        if (ios /= 0) call set_error(stat, errmsg, STAT_INPUT, path // ': cannot read scene file: ' // trim(iom))
        return
      end if
      close (u)
    end if
    call read_text_formatted(path, text, stat, errmsg)
  end subroutine read_text

  !> The file through line_reader (pipes, devices: no size known), its lines joined by LF.
  subroutine read_text_formatted(path, text, stat, errmsg)
    character(len=*), intent(in) :: path
    character(len=:), allocatable, intent(inout) :: text
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(line_reader_t) :: r
    character(len=:), allocatable :: buf
    integer :: n
    logical :: ok
    call open_reader(r, path, 'scene file', stat, errmsg)
    if (stat /= STAT_OK) return
    allocate (character(len=8192) :: buf)
    n = 0
    do
      call raw_line(r, ok, stat, errmsg)
      if (.not. ok) exit
      if (n + len(r%line) + 1 > len(buf)) call grow_text(buf, n + len(r%line) + 1)
      buf(n + 1:n + len(r%line) + 1) = r%line // LF
      n = n + len(r%line) + 1
    end do
    call close_reader(r)
    if (stat == STAT_OK) text = buf(1:n)
  end subroutine read_text_formatted

  !> Parse scene text (lines separated by LF; CR counts as a blank). `filename` only labels
  !> messages. An empty text gives zero statements and no error.
  subroutine parse_string(text, filename, sch, stmts, stat, errmsg)
    character(len=*), intent(in) :: text, filename
    type(schema_t), intent(in) :: sch
    type(statement_t), allocatable, intent(out) :: stmts(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(token_t), allocatable :: toks(:)
    type(statement_t), allocatable :: buf(:), tmp(:)
    type(statement_t) :: st
    character(len=:), allocatable :: what, word
    integer :: i, k, n, line, ntok, nst, first_on_line, cont_line
    logical :: cont, amp

    stat = STAT_OK
    errmsg = ''
    if (allocated(sch%defect)) then
      allocate (stmts(0))
      call set_error(stat, errmsg, STAT_RUN, 'internal error: scene schema: ' // sch%defect)
      return
    end if
    allocate (toks(16), buf(16))
    nst = 0
    ntok = 0
    n = len(text)
    i = 1
    line = 1
    cont = .false.
    cont_line = 0
    do
      first_on_line = ntok + 1
      call scan_line(text, i, line, toks, ntok, what, word)
      if (allocated(what)) then
        errmsg = lex_error(filename, line, toks, ntok, what, word)
        stat = STAT_INPUT
        allocate (stmts(0))
        return
      end if
      ! i now points at the LF ending this physical line, or past the end of the text
      amp = .false.
      if (ntok >= first_on_line) amp = ends_with_amp(toks(ntok))
      if (amp) then
        cont = .true.
        cont_line = line
        toks(ntok)%text = toks(ntok)%text(1:len(toks(ntok)%text) - 1)
        if (len(toks(ntok)%text) == 0) ntok = ntok - 1
      else if (ntok >= first_on_line .or. .not. cont) then
        ! blank and comment lines inside a continued statement are skipped, elsewhere ignored
        cont = .false.
        if (ntok > 0) then
          call parse_statement(toks(1:ntok), filename, sch, st, stat, errmsg)
          if (stat /= STAT_OK) then
            allocate (stmts(0))
            return
          end if
          if (nst == size(buf)) then
            allocate (tmp(2 * size(buf)))
            do k = 1, nst
              call move_statement(buf(k), tmp(k))
            end do
            call move_alloc(tmp, buf)
          end if
          nst = nst + 1
          call move_statement(st, buf(nst))
          ntok = 0
        end if
      end if
      if (i > n) exit
      i = i + 1
      line = line + 1
    end do
    if (cont) then
      errmsg = lex_error(filename, cont_line, toks, ntok, "line continued with '&' at the end of the file", '&')
      stat = STAT_INPUT
      allocate (stmts(0))
      return
    end if
    allocate (stmts(nst))
    do i = 1, nst
      call move_statement(buf(i), stmts(i))
    end do
    call check_once(stmts, sch, stat, errmsg)
  end subroutine parse_string

  !> Move a statement's allocatable parts without copying them.
  subroutine move_statement(from, to)
    type(statement_t), intent(inout) :: from
    type(statement_t), intent(inout) :: to
    call move_alloc(from%keyword, to%keyword)
    call move_alloc(from%file, to%file)
    to%line = from%line
    to%kwtok = from%kwtok
    call move_alloc(from%lead, to%lead)
    call move_alloc(from%params, to%params)
  end subroutine move_statement

  pure logical function ends_with_amp(t)
    type(token_t), intent(in) :: t
    integer :: m
    m = len(t%text)
    ends_with_amp = .false.
    if (t%quoted .or. m == 0) return
    ends_with_amp = t%text(m:m) == '&'
  end function ends_with_amp

  !> Tokenize one physical line starting at text(i:), appending to toks(1:ntok). On return i is
  !> at the LF that ends the line or past the end. On a lexical error `what` is allocated and
  !> `word` holds the offending text.
  subroutine scan_line(text, i, line, toks, ntok, what, word)
    character(len=*), intent(in) :: text
    integer, intent(inout) :: i
    integer, intent(in) :: line
    type(token_t), allocatable, intent(inout) :: toks(:)
    integer, intent(inout) :: ntok
    character(len=:), allocatable, intent(out) :: what, word
    integer :: n, j, k, ic
    character :: c
    logical :: closed
    n = len(text)
    do while (i <= n)
      c = text(i:i)
      if (c == LF) return
      if (is_blank(c)) then
        i = i + 1
        cycle
      end if
      if (c == '#') then
        ! comment: any printable or non-ASCII byte, but no control characters
        do while (i <= n)
          if (text(i:i) == LF) return
          if (is_bad_control(text(i:i))) then
            call bad_byte(i, i)
            return
          end if
          i = i + 1
        end do
        return
      end if
      if (c == '"') then
        j = i + 1
        do while (j <= n)
          if (text(j:j) == '"' .or. text(j:j) == LF) exit
          if (is_bad_control(text(j:j))) then
            call bad_byte(j, i)
            return
          end if
          j = j + 1
        end do
        closed = .false.
        if (j <= n) closed = text(j:j) == '"'
        if (.not. closed) then            ! reached the end of the line or of the text
          what = 'unterminated quoted string'
          word = text(i:j - 1)
          return
        end if
        call push(text(i + 1:j - 1), .true.)
        i = j + 1
        if (i <= n) then
          c = text(i:i)
          if (.not. (is_blank(c) .or. c == LF .or. c == '#' .or. c == '&')) then
            what = 'a blank must follow a closing quote'
            word = text(j:j) // word_at(i)
            return
          end if
        end if
        cycle
      end if
      ! bare word: up to a blank, a comment or the end of the line, printable ASCII, no quote
      j = word_end(text, i, '#')
      do k = i, j - 1
        ic = iachar(text(k:k))
        if (ic < 32 .or. ic > 126) then
          call bad_byte(k, i)
          return
        end if
        if (text(k:k) == '"') then
          what = 'a quote may only start a word'
          word = word_at(i)
          return
        end if
      end do
      call push(text(i:j - 1), .false.)
      i = j
    end do
  contains
    subroutine push(s, quoted)
      character(len=*), intent(in) :: s
      logical, intent(in) :: quoted
      type(token_t), allocatable :: tmp(:)
      integer :: k
      if (ntok == size(toks)) then
        allocate (tmp(2 * size(toks)))
        do k = 1, ntok
          call move_alloc(toks(k)%text, tmp(k)%text)
          tmp(k)%line = toks(k)%line
          tmp(k)%quoted = toks(k)%quoted
        end do
        call move_alloc(tmp, toks)
      end if
      ntok = ntok + 1
      toks(ntok)%text = s
      toks(ntok)%line = line
      toks(ntok)%quoted = quoted
    end subroutine push

    subroutine bad_byte(pos, wstart)
      integer, intent(in) :: pos, wstart
      what = 'unexpected character (byte 0x' // hex2(iachar(text(pos:pos))) // ')'
      word = word_at(wstart)
    end subroutine bad_byte

    !> The run of text from k to the next blank or end of line (for messages).
    function word_at(k) result(w)
      integer, intent(in) :: k
      character(len=:), allocatable :: w
      integer :: m
      m = word_end(text(1:min(n, k + MAX_SHOWN)), k)
      w = text(k:m - 1)
    end function word_at
  end subroutine scan_line

  !> Control characters other than tab and CR, and DEL.
  pure logical function is_bad_control(c)
    character, intent(in) :: c
    integer :: ic
    ic = iachar(c)
    is_bad_control = (ic < 32 .and. c /= TAB .and. c /= CR) .or. ic == 127
  end function is_bad_control

  pure function hex2(b) result(s)
    integer, intent(in) :: b
    character(len=2) :: s
    character(len=*), parameter :: digits = '0123456789ABCDEF'
    integer :: v
    v = modulo(b, 256)
    s = digits(v / 16 + 1:v / 16 + 1) // digits(mod(v, 16) + 1:mod(v, 16) + 1)
  end function hex2

  !> Message for a lexical error; names the statement's keyword when one was already read.
  function lex_error(filename, line, toks, ntok, what, word) result(s)
    character(len=*), intent(in) :: filename
    integer, intent(in) :: line
    type(token_t), intent(in) :: toks(:)
    integer, intent(in) :: ntok
    character(len=*), intent(in) :: what, word
    character(len=:), allocatable :: s
    s = filename // ':' // str(line) // ': '
    if (ntok > 0) then
      if (.not. toks(1)%quoted) s = s // shown(upcase(toks(1)%text)) // ': '
    end if
    s = s // what // ", at '" // shown(word) // "'"
  end function lex_error

  !> The statements declared `once` are given once at most: the repeat is named.
  subroutine check_once(stmts, sch, stat, errmsg)
    type(statement_t), intent(in) :: stmts(:)
    type(schema_t), intent(in) :: sch
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer :: i, j
    do j = 2, size(stmts)
      if (.not. sch%kws(find_kw(sch, stmts(j)%keyword))%once) cycle
      do i = 1, j - 1
        if (stmts(i)%keyword /= stmts(j)%keyword) cycle
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(stmts(j), 'statement repeated (first at line ' // &
          str(stmts(i)%line) // '); give it once', stmts(j)%kwtok))
        return
      end do
    end do
  end subroutine check_once

  !> Every statement declared `required` is there, else "file:1: no KEYWORD statement (hint)".
  subroutine check_required(stmts, sch, filename, stat, errmsg)
    type(statement_t), intent(in) :: stmts(:)
    type(schema_t), intent(in) :: sch
    character(len=*), intent(in) :: filename
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, i
    logical :: found
    stat = STAT_OK
    do k = 1, sch%nkw
      if (.not. sch%kws(k)%required) cycle
      found = .false.
      do i = 1, size(stmts)
        found = found .or. stmts(i)%keyword == sch%kws(k)%name
      end do
      if (found) cycle
      errmsg = filename // ':1: no ' // sch%kws(k)%name // ' statement'
      if (len(sch%kws(k)%hint) > 0) errmsg = errmsg // ' (' // sch%kws(k)%hint // ')'
      stat = STAT_INPUT
      return
    end do
  end subroutine check_required

  subroutine parse_statement(toks, filename, sch, st, stat, errmsg)
    type(token_t), intent(in) :: toks(:)
    character(len=*), intent(in) :: filename
    type(schema_t), intent(in) :: sch
    type(statement_t), intent(out) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(param_t), allocatable :: params(:)
    integer, allocatable :: first(:)
    integer :: n, k, i, j, nl, np, p, nv, nmax

    stat = STAT_OK
    errmsg = ''
    n = size(toks)
    st%file = filename
    st%kwtok = toks(1)
    st%line = toks(1)%line
    if (toks(1)%quoted) then
      st%keyword = ''
      call fail('a statement must start with a keyword, not a quoted string', toks(1))
      return
    end if
    st%keyword = upcase(toks(1)%text)
    k = find_kw(sch, st%keyword)
    if (k == 0) then
      st%keyword = shown(st%keyword)
      call fail('unknown keyword (expected one of: ' // sch%keyword_names() // ')', toks(1))
      return
    end if
    associate (kd => sch%kws(k))
      ! lead tokens: up to nlead_max tokens that are not parameter names; a required one may be
      ! spelt like a parameter when a parameter follows it (FUNCTION sine SINE …, GROUP box NODES …:
      ! names chosen before the parameter existed stay valid)
      i = 2
      nl = 0
      do while (i <= n .and. nl < kd%nlead_max)
        if (param_of_token(kd, toks(i)) > 0) then
          if (nl >= kd%nlead_min .or. i == n) exit
          if (param_of_token(kd, toks(i + 1)) == 0) exit
        end if
        nl = nl + 1
        i = i + 1
      end do
      st%lead = toks(2:1 + nl)
      if (nl < kd%nlead_min) then
        if (i <= n) then
          call fail('expects ' // lead_text(kd%nlead_min, kd%nlead_max) // ' before its parameters, found ' &
                    // str(nl), toks(i))
        else
          call fail('expects ' // lead_text(kd%nlead_min, kd%nlead_max) // ', found ' // str(nl), toks(1))
        end if
        return
      end if
      ! parameters with their values
      allocate (params(n - i + 1))
      allocate (first(kd%np))
      first = 0
      np = 0
      do while (i <= n)
        p = param_of_token(kd, toks(i))
        if (p == 0) then
          call fail(unknown_param_text(toks(i)), toks(i))
          return
        end if
        associate (pd => kd%params(p))
          if (first(p) > 0 .and. .not. pd%repeatable) then
            call fail('parameter ' // pd%name // ' repeated (first at line ' // str(first(p)) // ')', toks(i))
            return
          end if
          if (first(p) == 0) first(p) = toks(i)%line
          nmax = pd%nmax
          j = i + 1
          nv = 0
          do while (j <= n)
            if (nmax >= 0 .and. nv >= nmax) exit
            if (param_of_token(kd, toks(j)) > 0) exit
            nv = nv + 1
            j = j + 1
          end do
          if (nv < pd%nmin) then
            call fail('parameter ' // pd%name // ' of ' // kd%name // ' expects ' // arity_text(pd%nmin, pd%nmax) &
                      // ', found ' // str(nv), toks(i))
            return
          end if
          np = np + 1
          params(np)%key = pd%name
          params(np)%keytok = toks(i)
          params(np)%values = toks(i + 1:i + nv)
        end associate
        i = j
      end do
      st%params = params(1:np)
    end associate

  contains

    subroutine fail(msg, tok)
      character(len=*), intent(in) :: msg
      type(token_t), intent(in) :: tok
      stat = STAT_INPUT
      errmsg = stmt_error(st, msg, tok)
    end subroutine fail

    function lead_text(lmin, lmax) result(s)
      integer, intent(in) :: lmin, lmax
      character(len=:), allocatable :: s
      if (lmin == lmax) then
        s = str(lmin)
      else
        s = 'at least ' // str(lmin)
      end if
      if (lmin == 1 .and. lmax == 1) then
        s = s // ' name or value'
      else
        s = s // ' names or values'
      end if
    end function lead_text

    !> "unknown parameter 'X' for KW (expected one of: ...)", plus a hint when X is a number
    !> after a full parameter, since the usual cause then is one value too many.
    function unknown_param_text(t) result(s)
      type(token_t), intent(in) :: t
      character(len=:), allocatable :: s
      integer :: q, ierr
      real(dp) :: xdummy
      if (t%quoted) then
        s = 'quoted string where a parameter name was expected (one of: ' // pdef_list(sch%kws(k)) // ')'
      else
        s = "unknown parameter '" // shown(t%text) // "' for " // sch%kws(k)%name // ' (expected one of: ' &
            // pdef_list(sch%kws(k)) // ')'
      end if
      if (np > 0) then
        call parse_real_text(t%text, xdummy, ierr)
        q = find_pdef(sch%kws(k), params(np)%key)
        if (ierr /= NUM_MALFORMED .and. sch%kws(k)%params(q)%nmax > 0) s = s // '; ' // params(np)%key // &
          ' takes ' // arity_text(sch%kws(k)%params(q)%nmin, sch%kws(k)%params(q)%nmax)
      end if
    end function unknown_param_text
  end subroutine parse_statement

  !> Apply "KEYWORD.PARAM=VALUE" or "KEYWORD.NAME.PARAM=VALUE" (NAME = lead(1), exact case; it
  !> may itself contain dots). VALUE follows the lexical rules of a scene line and may hold
  !> several values; it is empty for a flag. The parameter's values are replaced if it is
  !> present, otherwise it is appended. A statement without leading words that the scene
  !> lacks (SCHEME, OUTPUT, GRAVITY, TIME) is created.
  subroutine apply_override(stmts, sch, spec, stat, errmsg)
    type(statement_t), allocatable, intent(inout) :: stmts(:)
    type(schema_t), intent(in) :: sch
    character(len=*), intent(in) :: spec
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: pre, lhs, rhs, kw, pname, name, what, word
    type(token_t), allocatable :: vals(:)
    type(param_t), allocatable :: tmp(:)
    type(statement_t), allocatable :: stmp(:)
    integer :: eq, d1, d2, k, p, i, nv, nmatch, is, nocc, ip, pos
    logical :: named

    stat = STAT_OK
    errmsg = ''
    pre = '--set ' // shown(spec) // ': '
    if (allocated(sch%defect)) then
      call set_error(stat, errmsg, STAT_RUN, 'internal error: scene schema: ' // sch%defect)
      return
    end if
    eq = index(spec, '=')
    if (eq == 0) then
      call bad('expected KEYWORD.PARAM=VALUE or KEYWORD.NAME.PARAM=VALUE')
      return
    end if
    lhs = trim(adjustl(spec(1:eq - 1)))
    rhs = spec(eq + 1:)
    d1 = index(lhs, '.')
    d2 = index(lhs, '.', back=.true.)
    if (d1 <= 1 .or. d2 == len(lhs)) then
      call bad('expected KEYWORD.PARAM=VALUE or KEYWORD.NAME.PARAM=VALUE')
      return
    end if
    kw = upcase(lhs(1:d1 - 1))
    pname = upcase(lhs(d2 + 1:))
    named = d2 > d1
    name = ''
    if (named) name = lhs(d1 + 1:d2 - 1)
    if (named .and. len(name) == 0) then
      call bad('empty NAME in KEYWORD.NAME.PARAM=VALUE')
      return
    end if
    k = find_kw(sch, kw)
    if (k == 0) then
      call bad("unknown keyword '" // shown(kw) // "' (expected one of: " // sch%keyword_names() // ')')
      return
    end if
    associate (kd => sch%kws(k))
      p = find_pdef(kd, pname)
      if (p == 0) then
        call bad("unknown parameter '" // shown(pname) // "' for " // kw // ' (expected one of: ' // pdef_list(kd) // ')')
        return
      end if
      if (named .and. kd%nlead_max == 0) then
        call bad(kw // ' statements have no name; use ' // kw // '.' // pname // '=VALUE')
        return
      end if
      ! values
      allocate (vals(4))
      nv = 0
      pos = 1
      call scan_line(rhs, pos, 0, vals, nv, what, word)
      if (allocated(what)) then
        call bad(what // ", at '" // shown(word) // "'")
        return
      end if
      if (pos <= len(rhs)) then
        call bad('VALUE must be on one line')
        return
      end if
      associate (pd => kd%params(p))
        if (nv < pd%nmin .or. (pd%nmax >= 0 .and. nv > pd%nmax)) then
          call bad('parameter ' // pname // ' of ' // kw // ' expects ' // arity_text(pd%nmin, pd%nmax) // &
                   ', found ' // str(nv))
          return
        end if
      end associate
      ! the one statement it applies to
      nmatch = 0
      is = 0
      do i = 1, size(stmts)
        if (stmts(i)%keyword /= kw .or. len(stmts(i)%keyword) /= len(kw)) cycle
        if (named) then
          if (.not. allocated(stmts(i)%lead)) cycle
          if (size(stmts(i)%lead) == 0) cycle
          if (stmts(i)%lead(1)%text /= name .or. len(stmts(i)%lead(1)%text) /= len(name)) cycle
        end if
        nmatch = nmatch + 1
        if (is == 0) is = i
      end do
      if (nmatch == 0 .and. .not. named .and. kd%nlead_min == 0) then
        ! An optional statement without leading words (SCHEME, OUTPUT, GRAVITY...): create it.
        allocate (stmp(size(stmts) + 1))
        stmp(1:size(stmts)) = stmts
        is = size(stmp)
        stmp(is)%keyword = kw
        stmp(is)%file = '--set'
        stmp(is)%line = 0
        stmp(is)%kwtok = token_t(kw, 0, .false.)
        allocate (stmp(is)%lead(0), stmp(is)%params(0))
        call move_alloc(stmp, stmts)
      else if (nmatch == 0) then
        if (named) then
          call bad('no ' // kw // " statement named '" // shown(name) // "' in the scene")
        else
          call bad('no ' // kw // ' statement in the scene')
        end if
        return
      else if (nmatch > 1) then
        if (named) then
          call bad(str(nmatch) // ' ' // kw // " statements are named '" // shown(name) // "'")
        else if (kd%nlead_max > 0) then
          call bad(kw // ' occurs ' // str(nmatch) // ' times; say which one with --set ' // kw // '.NAME.' &
                   // pname // '=VALUE')
        else
          call bad(kw // ' occurs ' // str(nmatch) // ' times')
        end if
        return
      end if
    end associate
    do i = 1, nv
      vals(i)%line = 0
    end do
    associate (st => stmts(is))
      if (.not. allocated(st%params)) allocate (st%params(0))
      nocc = count_param(st, pname)
      if (nocc > 1) then
        call bad('parameter ' // pname // ' occurs ' // str(nocc) // ' times in the ' // kw // ' statement at line ' &
                 // str(st%line) // '; cannot replace it')
        return
      end if
      ip = find_param(st, pname)
      if (ip == 0) then
        allocate (tmp(size(st%params) + 1))
        tmp(1:size(st%params)) = st%params
        call move_alloc(tmp, st%params)
        ip = size(st%params)
        st%params(ip)%key = pname
        st%params(ip)%keytok = token_t(pname, 0, .false.)
      end if
      st%params(ip)%values = vals(1:nv)
    end associate
  contains
    subroutine bad(msg)
      character(len=*), intent(in) :: msg
      call set_error(stat, errmsg, STAT_INPUT, pre // msg)
    end subroutine bad
  end subroutine apply_override
end module scene_parser
