!> A statement of rebond's keyword files (scene, sweep) as the parser gives it, and the one
!> place that reads values out of it: typed getters (get: real, integer, word; lists) with
!> defaults and bounds, and the message of an error at a statement or a token (file:line,
!> statement, word).
module statement
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str, upcase => upper
  use number_text, only: parse_real_text, parse_int_text, real_text, NUM_MALFORMED, NUM_RANGE
  implicit none
  private
  public :: token_t, param_t, statement_t, stmt_error, shown, MAX_SHOWN
  public :: get, find_param, count_param, get_real, get_int, get_word, get_real_list, get_int_list, to_real, to_int

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

  !> The typed getter: value `index` (default 1) of the first occurrence of a parameter.
  interface get
    module procedure get_real, get_int, get_word
  end interface get

contains

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

  !> The value `index` (default 1) of the first occurrence of `key`: its parameter ip and value
  !> iv. found = .false. when the parameter (ip = 0) or that value is missing, an error then
  !> unless the getter has a default. One preamble for every getter.
  subroutine find_value(st, key, index, has_default, iv, ip, found, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    integer, intent(in), optional :: index
    logical, intent(in) :: has_default
    integer, intent(out) :: iv, ip
    logical, intent(out) :: found
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    errmsg = ''
    iv = 1
    if (present(index)) iv = index
    ip = find_param(st, key)
    found = .false.
    if (ip > 0) then
      if (allocated(st%params(ip)%values)) found = iv >= 1 .and. iv <= size(st%params(ip)%values)
    end if
    if (.not. (found .or. has_default)) call set_error(stat, errmsg, STAT_INPUT, missing_text(st, key, ip, iv))
  end subroutine find_value

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
    logical :: found
    x = 0.0_dp
    call find_value(st, key, index, present(default), iv, ip, found, stat, errmsg)
    if (.not. found) then
      if (present(default)) x = default
      return
    end if
    associate (t => st%params(ip)%values(iv))
      call to_real(t, st, x, stat, errmsg)
      if (stat /= STAT_OK) return
      if (present(lower)) call check_bound(st, key, t, x < lower, x == lower, lower_inclusive, '>', real_text(lower), &
        stat, errmsg)
      if (present(upper) .and. stat == STAT_OK) call check_bound(st, key, t, x > upper, x == upper, upper_inclusive, &
        '<', real_text(upper), stat, errmsg)
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
    logical :: found
    n = 0
    call find_value(st, key, index, present(default), iv, ip, found, stat, errmsg)
    if (.not. found) then
      if (present(default)) n = default
      return
    end if
    associate (t => st%params(ip)%values(iv))
      call to_int(t, st, n, stat, errmsg)
      if (stat /= STAT_OK) return
      if (present(lower)) call check_bound(st, key, t, n < lower, n == lower, lower_inclusive, '>', str(lower), &
        stat, errmsg)
      if (present(upper) .and. stat == STAT_OK) call check_bound(st, key, t, n > upper, n == upper, upper_inclusive, &
        '<', str(upper), stat, errmsg)
    end associate
  end subroutine get_int

  !> The bound test of the getters: beyond (past the bound) or at it without inclusive (default
  !> .false.) is an error "KEY must be > (or >=, <, <=) bound" at the token.
  subroutine check_bound(st, key, t, beyond, at, inclusive, op, bound, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key, op, bound
    type(token_t), intent(in) :: t
    logical, intent(in) :: beyond, at
    logical, intent(in), optional :: inclusive
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    logical :: incl
    incl = .false.
    if (present(inclusive)) incl = inclusive
    if (beyond .or. (at .and. .not. incl)) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, upcase(key) // &
      ' must be ' // op // trim(merge('= ', '  ', incl)) // ' ' // bound, t))
  end subroutine check_bound

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
    call find_value(st, key, index, present(default), iv, ip, found, stat, errmsg)
    if (found) then
      w = st%params(ip)%values(iv)%text
    else if (present(default)) then
      w = default
    else
      w = ''
    end if
  end subroutine get_word

  !> The first occurrence ip of `key` for the list getters; ip = 0 and an error when missing.
  subroutine list_param(st, key, ip, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    integer, intent(out) :: ip
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    errmsg = ''
    ip = find_param(st, key)
    if (ip == 0) call set_error(stat, errmsg, STAT_INPUT, missing_text(st, key, 0, 1))
  end subroutine list_param

  !> All values of the first occurrence of `key` as reals (error if the parameter is missing).
  subroutine get_real_list(st, key, xs, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    real(dp), allocatable, intent(out) :: xs(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: ip, i
    call list_param(st, key, ip, stat, errmsg)
    if (ip == 0) then
      allocate (xs(0))
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
    call list_param(st, key, ip, stat, errmsg)
    if (ip == 0) then
      allocate (ns(0))
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
end module statement
