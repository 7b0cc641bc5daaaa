!> Schema-driven lexer and parser for rebond's keyword scene files.
!>
!> A statement is `KEYWORD [lead tokens] (PARAM value*)*` on one logical line (physical lines
!> joined by a trailing `&`). The lexer only knows blanks, comments, quotes and continuations;
!> which token is a parameter name and how many values each parameter takes comes from a
!> schema_t built by the caller, so the scene module never splits text itself.
!> The lexical rules are documented in docs/input.md, section "Lexical rules".
module scene_parser
  use, intrinsic :: iso_fortran_env, only: int64, iostat_end, iostat_eor
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str, upcase => upper
  use number_text, only: parse_real_text, parse_int_text, real_text, NUM_MALFORMED, NUM_RANGE
  implicit none
  private
  public :: token_t, param_t, statement_t, schema_t
  public :: parse_file, parse_string, read_text, apply_override, stmt_error, check_required
  public :: find_param, count_param, get_real, get_int, get_word, get_real_list, get_int_list
  public :: to_real, to_int

  character(len=*), parameter :: LF = achar(10), CR = achar(13), TAB = achar(9)
  !> Longest word quoted verbatim in a message; longer ones are cut (a token may be 50 000 chars).
  integer, parameter :: MAX_SHOWN = 60

  !> One token: a bare word or a quoted string (quotes removed).
  type :: token_t
    character(len=:), allocatable :: text  !< as written (quotes removed)
    integer :: line = 0                    !< physical line in the file; 0 for a --set value
    logical :: quoted = .false.
  end type token_t

  !> One parameter occurrence with its values.
  type :: param_t
    character(len=:), allocatable :: key   !< upper case
    type(token_t) :: keytok
    type(token_t), allocatable :: values(:)
  end type param_t

  !> One statement: keyword, lead tokens, parameters in order of appearance.
  type :: statement_t
    character(len=:), allocatable :: keyword  !< upper case
    character(len=:), allocatable :: file
    integer :: line = 0                       !< line of the keyword
    type(token_t) :: kwtok
    type(token_t), allocatable :: lead(:)
    type(param_t), allocatable :: params(:)   !< in order of appearance
  end type statement_t

  type :: pdef_t
    character(len=:), allocatable :: name
    integer :: nmin = 0, nmax = 0             ! nmax = -1: unbounded
    logical :: repeatable = .false.
  end type pdef_t

  type :: kwdef_t
    character(len=:), allocatable :: name
    character(len=:), allocatable :: hint     !< for a missing required statement, e.g. 'TIME STEP h END t'
    logical :: once = .false.                 !< may be given once at most
    logical :: required = .false.             !< must be given (check_required)
    integer :: nlead_min = 0, nlead_max = 0
    integer :: np = 0
    type(pdef_t), allocatable :: params(:)
  end type kwdef_t

  !> What each keyword accepts. A mistake while building it (duplicate, unknown keyword, bad
  !> counts) is remembered in `defect` and reported by every parse, since add_* has no stat.
  type :: schema_t
    integer, private :: nkw = 0
    type(kwdef_t), allocatable, private :: kws(:)
    character(len=:), allocatable, private :: defect
  contains
    procedure :: add_keyword => schema_add_keyword
    procedure :: add_param => schema_add_param
    procedure :: param_names => schema_param_names
    procedure :: keyword_names => schema_keyword_names
    procedure :: has_keyword => schema_has_keyword
  end type schema_t

contains

  ! ---------------------------------------------------------------------------------------------
  ! Schema
  ! ---------------------------------------------------------------------------------------------

  !> Declare a keyword taking between nlead_min and nlead_max lead tokens (both default 0).
  !> once: the statement may be given once at most (parse_string refuses a repeat); required:
  !> it must be given (check_required, hint: what it looks like, for the message).
  subroutine schema_add_keyword(self, name, nlead_min, nlead_max, once, required, hint)
    class(schema_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(in), optional :: nlead_min, nlead_max
    logical, intent(in), optional :: once, required
    character(len=*), intent(in), optional :: hint
    type(kwdef_t), allocatable :: tmp(:)
    character(len=:), allocatable :: u
    u = upcase(trim(adjustl(name)))
    if (.not. allocated(self%kws)) allocate (self%kws(16))
    if (len(u) == 0) then
      call note_defect(self, 'empty keyword name')
      return
    end if
    if (find_kw(self, u) > 0) then
      call note_defect(self, 'keyword ' // u // ' declared twice')
      return
    end if
    if (self%nkw == size(self%kws)) then
      allocate (tmp(2 * size(self%kws)))
      tmp(1:self%nkw) = self%kws(1:self%nkw)
      call move_alloc(tmp, self%kws)
    end if
    self%nkw = self%nkw + 1
    associate (k => self%kws(self%nkw))
      k%name = u
      k%nlead_min = 0
      k%nlead_max = 0
      if (present(nlead_min)) k%nlead_min = nlead_min
      if (present(nlead_max)) k%nlead_max = nlead_max
      if (present(nlead_min) .and. .not. present(nlead_max)) k%nlead_max = k%nlead_min
      k%np = 0
      if (present(once)) k%once = once
      if (present(required)) k%required = required
      k%hint = ''
      if (present(hint)) k%hint = hint
      allocate (k%params(8))
      if (k%nlead_min < 0 .or. k%nlead_max < k%nlead_min) &
        call note_defect(self, 'keyword ' // u // ': bad nlead_min/nlead_max')
    end associate
  end subroutine schema_add_keyword

  !> Declare parameter `name` of `keyword` taking nmin..nmax values (nmax = -1: unbounded;
  !> both default 0, a flag). A non-repeatable parameter may appear once per statement.
  subroutine schema_add_param(self, keyword, name, nmin, nmax, repeatable)
    class(schema_t), intent(inout) :: self
    character(len=*), intent(in) :: keyword, name
    integer, intent(in), optional :: nmin, nmax
    logical, intent(in), optional :: repeatable
    type(pdef_t), allocatable :: tmp(:)
    character(len=:), allocatable :: u
    integer :: k
    k = find_kw(self, upcase(trim(adjustl(keyword))))
    if (k == 0) then
      call note_defect(self, 'parameter ' // trim(name) // ' added to undeclared keyword ' // trim(keyword))
      return
    end if
    u = upcase(trim(adjustl(name)))
    associate (kd => self%kws(k))
      if (len(u) == 0) then
        call note_defect(self, 'empty parameter name for ' // kd%name)
        return
      end if
      if (find_pdef(kd, u) > 0) then
        call note_defect(self, 'parameter ' // u // ' of ' // kd%name // ' declared twice')
        return
      end if
      if (kd%np == size(kd%params)) then
        allocate (tmp(2 * size(kd%params)))
        tmp(1:kd%np) = kd%params(1:kd%np)
        call move_alloc(tmp, kd%params)
      end if
      kd%np = kd%np + 1
      kd%params(kd%np)%name = u
      kd%params(kd%np)%nmin = 0
      kd%params(kd%np)%nmax = 0
      if (present(nmin)) kd%params(kd%np)%nmin = nmin
      if (present(nmax)) kd%params(kd%np)%nmax = nmax
      if (present(nmin) .and. .not. present(nmax)) kd%params(kd%np)%nmax = nmin
      kd%params(kd%np)%repeatable = .false.
      if (present(repeatable)) kd%params(kd%np)%repeatable = repeatable
      associate (pd => kd%params(kd%np))
        if (pd%nmin < 0 .or. (pd%nmax >= 0 .and. pd%nmax < pd%nmin) .or. pd%nmax < -1) &
          call note_defect(self, 'parameter ' // u // ' of ' // kd%name // ': bad nmin/nmax')
      end associate
    end associate
  end subroutine schema_add_param

  !> Comma-separated parameter names of a keyword, in declaration order ('' if none or unknown).
  function schema_param_names(self, keyword) result(s)
    class(schema_t), intent(in) :: self
    character(len=*), intent(in) :: keyword
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    k = find_kw(self, upcase(keyword))
    if (k > 0) s = pdef_list(self%kws(k))
  end function schema_param_names

  !> Comma-separated keyword names, in declaration order.
  function schema_keyword_names(self) result(s)
    class(schema_t), intent(in) :: self
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, self%nkw
      if (k > 1) s = s // ', '
      s = s // self%kws(k)%name
    end do
  end function schema_keyword_names

  !> Whether a keyword (any case) is declared.
  logical function schema_has_keyword(self, keyword)
    class(schema_t), intent(in) :: self
    character(len=*), intent(in) :: keyword
    schema_has_keyword = find_kw(self, upcase(keyword)) > 0
  end function schema_has_keyword

  subroutine note_defect(self, msg)
    type(schema_t), intent(inout) :: self
    character(len=*), intent(in) :: msg
    if (.not. allocated(self%defect)) self%defect = msg   ! keep the first: later ones may follow from it
  end subroutine note_defect

  pure integer function find_kw(sch, uname)
    type(schema_t), intent(in) :: sch
    character(len=*), intent(in) :: uname
    integer :: k
    find_kw = 0
    do k = 1, sch%nkw
      if (sch%kws(k)%name == uname .and. len(sch%kws(k)%name) == len(uname)) then
        find_kw = k
        return
      end if
    end do
  end function find_kw

  pure integer function find_pdef(kd, uname)
    type(kwdef_t), intent(in) :: kd
    character(len=*), intent(in) :: uname
    integer :: p
    find_pdef = 0
    do p = 1, kd%np
      if (kd%params(p)%name == uname .and. len(kd%params(p)%name) == len(uname)) then
        find_pdef = p
        return
      end if
    end do
  end function find_pdef

  !> Index of the parameter named by token `t`, 0 if `t` is not one (quoted tokens never are).
  !> Lengths are compared first so long value tokens are never upper-cased.
  pure integer function param_of_token(kd, t)
    type(kwdef_t), intent(in) :: kd
    type(token_t), intent(in) :: t
    integer :: p
    param_of_token = 0
    if (t%quoted) return
    do p = 1, kd%np
      if (len(kd%params(p)%name) /= len(t%text)) cycle
      if (kd%params(p)%name == upcase(t%text)) then
        param_of_token = p
        return
      end if
    end do
  end function param_of_token

  pure function pdef_list(kd) result(s)
    type(kwdef_t), intent(in) :: kd
    character(len=:), allocatable :: s
    integer :: p
    s = ''
    do p = 1, kd%np
      if (p > 1) s = s // ', '
      s = s // kd%params(p)%name
    end do
  end function pdef_list

  !> "2 values", "at least 1 value", "1 to 3 values", "no value".
  pure function arity_text(nmin, nmax) result(s)
    integer, intent(in) :: nmin, nmax
    character(len=:), allocatable :: s
    if (nmax == nmin) then
      if (nmin == 0) then
        s = 'no value'
      else
        s = str(nmin) // plural(nmin)
      end if
    else if (nmax < 0) then
      s = 'at least ' // str(nmin) // plural(nmin)
    else
      s = str(nmin) // ' to ' // str(nmax) // ' values'
    end if
  end function arity_text

  pure function plural(n) result(s)
    integer, intent(in) :: n
    character(len=:), allocatable :: s
    if (n == 1) then
      s = ' value'
    else
      s = ' values'
    end if
  end function plural

  ! ---------------------------------------------------------------------------------------------
  ! Reading and lexing
  ! ---------------------------------------------------------------------------------------------

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
    call parse_string(text, path, sch, stmts, stat, errmsg)
  end subroutine parse_file

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

  subroutine read_text_formatted(path, text, stat, errmsg)
    character(len=*), intent(in) :: path
    character(len=:), allocatable, intent(inout) :: text
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=4096) :: chunk
    character(len=:), allocatable :: buf
    character(len=256) :: iom
    integer :: u, ios, nread, n
    stat = STAT_OK
    errmsg = ''
    iom = ''
    open (newunit=u, file=path, access='sequential', form='formatted', status='old', action='read', &
          iostat=ios, iomsg=iom)
    if (ios /= 0) then
      call set_error(stat, errmsg, STAT_INPUT, path // ': cannot open scene file: ' // trim(iom))
      return
    end if
    allocate (character(len=8192) :: buf)
    n = 0
    do
      nread = 0
      read (u, '(a)', advance='no', size=nread, iostat=ios, iomsg=iom) chunk
      if (ios /= 0 .and. ios /= iostat_eor .and. ios /= iostat_end) then
        call set_error(stat, errmsg, STAT_INPUT, path // ': cannot read scene file: ' // trim(iom))
        close (u)
        return
      end if
      call append(chunk(1:nread))
      if (ios == iostat_eor) call append(LF)
      if (ios == iostat_end) exit
    end do
    close (u)
    text = buf(1:n)
  contains
    subroutine append(s)
      character(len=*), intent(in) :: s
      character(len=:), allocatable :: tmp
      if (n + len(s) > len(buf)) then
        allocate (character(len=max(2 * len(buf), n + len(s))) :: tmp)
        tmp(1:n) = buf(1:n)
        call move_alloc(tmp, buf)
      end if
      buf(n + 1:n + len(s)) = s
      n = n + len(s)
    end subroutine append
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
    integer :: n, j, ic
    character :: c
    logical :: closed
    n = len(text)
    do while (i <= n)
      c = text(i:i)
      if (c == LF) return
      if (c == ' ' .or. c == TAB .or. c == CR) then
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
          if (.not. (c == ' ' .or. c == TAB .or. c == CR .or. c == LF .or. c == '#' .or. c == '&')) then
            what = 'a blank must follow a closing quote'
            word = text(j:j) // word_at(i)
            return
          end if
        end if
        cycle
      end if
      ! bare word: up to a blank, a comment or the end of the line
      j = i
      do while (j <= n)
        c = text(j:j)
        if (c == ' ' .or. c == TAB .or. c == CR .or. c == LF .or. c == '#') exit
        ic = iachar(c)
        if (ic < 32 .or. ic > 126) then
          call bad_byte(j, i)
          return
        end if
        if (c == '"') then
          what = 'a quote may only start a word'
          word = word_at(i)
          return
        end if
        j = j + 1
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
      m = k
      do while (m <= n .and. m - k < MAX_SHOWN + 1)
        if (text(m:m) == ' ' .or. text(m:m) == TAB .or. text(m:m) == LF .or. text(m:m) == CR) exit
        m = m + 1
      end do
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

  !> A word made safe and short for a message: non-printable bytes as '?', cut at MAX_SHOWN.
  pure function shown(w) result(s)
    character(len=*), intent(in) :: w
    character(len=:), allocatable :: s
    integer :: k, ic
    if (len(w) > MAX_SHOWN) then
      s = w(1:MAX_SHOWN) // '...'
    else
      s = w
    end if
    do k = 1, min(len(w), MAX_SHOWN)
      ic = iachar(s(k:k))
      if (ic < 32 .or. ic > 126) s(k:k) = '?'
    end do
  end function shown

  ! ---------------------------------------------------------------------------------------------
  ! Splitting a statement with the schema
  ! ---------------------------------------------------------------------------------------------

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
      ! lead tokens: up to nlead_max tokens that are not parameter names
      i = 2
      nl = 0
      do while (i <= n .and. nl < kd%nlead_max)
        if (param_of_token(kd, toks(i)) > 0) exit
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

  !> "<file>:<line>: <KEYWORD>[ <lead(1)>]: <msg>[, at '<word>']". The line is the token's
  !> (the keyword's if the token has none); a token from --set (line 0) is marked as such.
  function stmt_error(st, msg, tok) result(s)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: msg
    type(token_t), intent(in), optional :: tok
    character(len=:), allocatable :: s
    integer :: line
    line = st%line
    if (present(tok)) then
      if (tok%line > 0) line = tok%line
    end if
    if (allocated(st%file)) then
      s = st%file // ':' // str(line) // ': '
    else
      s = '?:' // str(line) // ': '
    end if
    if (allocated(st%keyword)) then
      if (len(st%keyword) > 0) then
        s = s // st%keyword
        if (allocated(st%lead)) then
          if (size(st%lead) > 0) s = s // ' ' // shown(st%lead(1)%text)
        end if
        s = s // ': '
      end if
    end if
    s = s // msg
    if (present(tok)) then
      if (allocated(tok%text)) then
        s = s // ", at '" // shown(tok%text) // "'"
      else
        s = s // ", at ''"
      end if
      if (tok%line == 0) s = s // ' (given with --set)'
    end if
  end function stmt_error

  ! ---------------------------------------------------------------------------------------------
  ! Command-line overrides
  ! ---------------------------------------------------------------------------------------------

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

  ! ---------------------------------------------------------------------------------------------
  ! Queries
  ! ---------------------------------------------------------------------------------------------

  !> Index in st%params of the occurrence-th (default first) parameter `key` (any case), or 0.
  integer function find_param(st, key, occurrence)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    integer, intent(in), optional :: occurrence
    integer :: i, want, seen
    character(len=:), allocatable :: u
    find_param = 0
    if (.not. allocated(st%params)) return
    want = 1
    if (present(occurrence)) want = occurrence
    u = upcase(key)
    seen = 0
    do i = 1, size(st%params)
      if (st%params(i)%key == u .and. len(st%params(i)%key) == len(u)) then
        seen = seen + 1
        if (seen == want) then
          find_param = i
          return
        end if
      end if
    end do
  end function find_param

  !> How many times parameter `key` (any case) occurs in the statement.
  integer function count_param(st, key)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    integer :: i
    character(len=:), allocatable :: u
    count_param = 0
    if (.not. allocated(st%params)) return
    u = upcase(key)
    do i = 1, size(st%params)
      if (st%params(i)%key == u .and. len(st%params(i)%key) == len(u)) count_param = count_param + 1
    end do
  end function count_param

  !> Locate value `iv` of the first occurrence of `key`. found = .false. when the parameter or
  !> that value is missing (ip tells which: 0 = parameter missing).
  subroutine locate(st, key, iv, ip, found)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    integer, intent(in) :: iv
    integer, intent(out) :: ip
    logical, intent(out) :: found
    ip = find_param(st, key)
    found = .false.
    if (ip == 0) return
    if (.not. allocated(st%params(ip)%values)) return
    found = iv >= 1 .and. iv <= size(st%params(ip)%values)
  end subroutine locate

  !> Error for a missing parameter or value (no default given).
  function missing_text(st, key, ip, iv) result(s)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    integer, intent(in) :: ip, iv
    character(len=:), allocatable :: s
    if (ip == 0) then
      s = stmt_error(st, 'missing parameter ' // upcase(key), st%kwtok)
    else
      s = stmt_error(st, 'parameter ' // upcase(key) // ' has no value number ' // str(iv), st%params(ip)%keytok)
    end if
  end function missing_text

  !> Real value `index` (default 1) of the first occurrence of `key`. Bounds are exclusive
  !> unless lower_inclusive / upper_inclusive is .true.
  subroutine get_real(st, key, x, stat, errmsg, default, index, lower, lower_inclusive, upper, upper_inclusive)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    real(dp), intent(out) :: x
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), intent(in), optional :: default, lower, upper
    integer, intent(in), optional :: index
    logical, intent(in), optional :: lower_inclusive, upper_inclusive
    integer :: iv, ip
    logical :: found, incl
    stat = STAT_OK
    errmsg = ''
    x = 0.0_dp
    iv = 1
    if (present(index)) iv = index
    call locate(st, key, iv, ip, found)
    if (.not. found) then
      if (present(default)) then
        x = default
      else
        call set_error(stat, errmsg, STAT_INPUT, missing_text(st, key, ip, iv))
      end if
      return
    end if
    associate (t => st%params(ip)%values(iv))
      call to_real(t, st, x, stat, errmsg)
      if (stat /= STAT_OK) return
      if (present(lower)) then
        incl = .false.
        if (present(lower_inclusive)) incl = lower_inclusive
        if ((incl .and. x < lower) .or. (.not. incl .and. .not. x > lower)) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, upcase(key) // ' must be ' // &
                         trim(merge('>=', '> ', incl)) // ' ' // real_text(lower), t))
          return
        end if
      end if
      if (present(upper)) then
        incl = .false.
        if (present(upper_inclusive)) incl = upper_inclusive
        if ((incl .and. x > upper) .or. (.not. incl .and. .not. x < upper)) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, upcase(key) // ' must be ' // &
                         trim(merge('<=', '< ', incl)) // ' ' // real_text(upper), t))
          return
        end if
      end if
    end associate
  end subroutine get_real

  !> Integer value `index` (default 1) of the first occurrence of `key`; bounds as get_real.
  subroutine get_int(st, key, n, stat, errmsg, default, index, lower, lower_inclusive, upper, upper_inclusive)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    integer, intent(out) :: n
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, intent(in), optional :: default, index, lower, upper
    logical, intent(in), optional :: lower_inclusive, upper_inclusive
    integer :: iv, ip
    logical :: found, incl
    stat = STAT_OK
    errmsg = ''
    n = 0
    iv = 1
    if (present(index)) iv = index
    call locate(st, key, iv, ip, found)
    if (.not. found) then
      if (present(default)) then
        n = default
      else
        call set_error(stat, errmsg, STAT_INPUT, missing_text(st, key, ip, iv))
      end if
      return
    end if
    associate (t => st%params(ip)%values(iv))
      call to_int(t, st, n, stat, errmsg)
      if (stat /= STAT_OK) return
      if (present(lower)) then
        incl = .false.
        if (present(lower_inclusive)) incl = lower_inclusive
        if (n < lower .or. (n == lower .and. .not. incl)) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, upcase(key) // ' must be ' // &
                         trim(merge('>=', '> ', incl)) // ' ' // str(lower), t))
          return
        end if
      end if
      if (present(upper)) then
        incl = .false.
        if (present(upper_inclusive)) incl = upper_inclusive
        if (n > upper .or. (n == upper .and. .not. incl)) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, upcase(key) // ' must be ' // &
                         trim(merge('<=', '< ', incl)) // ' ' // str(upper), t))
          return
        end if
      end if
    end associate
  end subroutine get_int

  !> Text of value `index` (default 1) of the first occurrence of `key`, case kept.
  subroutine get_word(st, key, w, stat, errmsg, default, index)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    character(len=:), allocatable, intent(out) :: w
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=*), intent(in), optional :: default
    integer, intent(in), optional :: index
    integer :: iv, ip
    logical :: found
    stat = STAT_OK
    errmsg = ''
    iv = 1
    if (present(index)) iv = index
    call locate(st, key, iv, ip, found)
    if (found) then
      w = st%params(ip)%values(iv)%text
    else if (present(default)) then
      w = default
    else
      w = ''
      call set_error(stat, errmsg, STAT_INPUT, missing_text(st, key, ip, iv))
    end if
  end subroutine get_word

  !> All values of the first occurrence of `key` as reals (error if the parameter is missing).
  subroutine get_real_list(st, key, xs, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    real(dp), allocatable, intent(out) :: xs(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: ip, i
    stat = STAT_OK
    errmsg = ''
    ip = find_param(st, key)
    if (ip == 0) then
      allocate (xs(0))
      call set_error(stat, errmsg, STAT_INPUT, missing_text(st, key, 0, 1))
      return
    end if
    allocate (xs(size(st%params(ip)%values)))
    do i = 1, size(xs)
      call to_real(st%params(ip)%values(i), st, xs(i), stat, errmsg)
      if (stat /= STAT_OK) return
    end do
  end subroutine get_real_list

  !> All values of the first occurrence of `key` as integers (error if the parameter is missing).
  subroutine get_int_list(st, key, ns, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    integer, allocatable, intent(out) :: ns(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: ip, i
    stat = STAT_OK
    errmsg = ''
    ip = find_param(st, key)
    if (ip == 0) then
      allocate (ns(0))
      call set_error(stat, errmsg, STAT_INPUT, missing_text(st, key, 0, 1))
      return
    end if
    allocate (ns(size(st%params(ip)%values)))
    do i = 1, size(ns)
      call to_int(st%params(ip)%values(i), st, ns(i), stat, errmsg)
      if (stat /= STAT_OK) return
    end do
  end subroutine get_int_list

  !> Strict real from one token; messages name the statement and the token.
  subroutine to_real(tok, st, x, stat, errmsg)
    type(token_t), intent(in) :: tok
    type(statement_t), intent(in) :: st
    real(dp), intent(out) :: x
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: ierr
    stat = STAT_OK
    errmsg = ''
    call parse_real_text(tok%text, x, ierr)
    if (ierr == NUM_MALFORMED) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected a number', tok))
    else if (ierr == NUM_RANGE) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'number out of range', tok))
    end if
  end subroutine to_real

  !> Strict integer from one token.
  subroutine to_int(tok, st, n, stat, errmsg)
    type(token_t), intent(in) :: tok
    type(statement_t), intent(in) :: st
    integer, intent(out) :: n
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: ierr
    stat = STAT_OK
    errmsg = ''
    call parse_int_text(tok%text, n, ierr)
    if (ierr == NUM_MALFORMED) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected an integer', tok))
    else if (ierr == NUM_RANGE) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'integer out of range', tok))
    end if
  end subroutine to_int

end module scene_parser
