!> Reading a data file line by line (Gmsh meshes): the next non-blank line, read in time linear
!> in its length and bounded (MAX_LINE), split into blank-separated words (tok), and the typed
!> reads of a word through the one number reader (number_text), with messages that name the
!> file and the line. Extended by the readers (gmsh_reader's gmsh_t), which add their state.
module line_reader
  use, intrinsic :: iso_fortran_env, only: int64, iostat_end, iostat_eor
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str, shown
  use array_utils, only: grow
  use words, only: is_blank, word_end
  use number_text, only: parse_real_text, parse_int64_text, NUM_OK, NUM_MALFORMED, NUM_RANGE
  implicit none
  private
  public :: line_reader_t, open_reader, close_reader, raw_line, next_line, grow_text
  public :: get_int, get_reals, get_real_tok, fail, tok, clip, MAX_LINE

  !> Longest line accepted. Data lines are short (a Gmsh element line holds at most 9 numbers);
  !> without a bound, a file with no newline that never ends (FILE /dev/zero) grew the line until
  !> memory ran out (found by tests/fuzz/fuzz.py).
  integer, parameter :: MAX_LINE = 1048576

  !> The open file, the current line (line, lineno) and its words: tok(k) = line(tb(k):te(k)).
  type :: line_reader_t
    character(len=:), allocatable :: path
    integer :: unit = -1
    integer :: lineno = 0
    character(len=:), allocatable :: line
    integer :: ntok = 0
    integer, allocatable :: tb(:), te(:)
    character(len=:), allocatable :: buf      !< the line being read (grows by doubling)
    character(len=:), allocatable :: pending  !< the rest of a record after a lone CR
    logical :: pending_eor = .false.          !< that rest ends its record
  end type line_reader_t

  character(len=*), parameter :: CR = achar(13), BOM = char(239) // char(187) // char(191)

contains

  !> Open path for reading (what names the file in the message: 'scene file', 'mesh file'...).
  subroutine open_reader(g, path, what, stat, errmsg)
    class(line_reader_t), intent(inout) :: g
    character(len=*), intent(in) :: path, what
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=256) :: iomsg
    integer :: ios
    stat = STAT_OK
    g%path = path
    g%lineno = 0
    if (.not. allocated(g%tb)) allocate (g%tb(32), g%te(32))
    iomsg = ''
    open (newunit=g%unit, file=path, status='old', action='read', form='formatted', access='sequential', &
          iostat=ios, iomsg=iomsg)
    if (ios /= 0) then
      g%unit = -1
      call set_error(stat, errmsg, STAT_INPUT, path // ':0: cannot open the ' // what // ': ' // trim(iomsg))
    end if
  end subroutine open_reader

  subroutine close_reader(g)
    class(line_reader_t), intent(inout) :: g
    if (g%unit /= -1) close (g%unit)
    g%unit = -1
  end subroutine close_reader

  !> The next physical line as it is (blank lines too, no words split) into g%line; ok = .false.
  !> at the end of the file. Lines end at LF, CR LF or a lone CR (old Mac files); a UTF-8 byte
  !> order mark is dropped.
  subroutine raw_line(g, ok, stat, errmsg)
    class(line_reader_t), intent(inout) :: g
    logical, intent(out) :: ok
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: nl
    stat = STAT_OK
    if (.not. allocated(g%buf)) allocate (character(len=4096) :: g%buf)
    if (.not. allocated(g%pending)) g%pending = ''
    call physical_piece(g, nl, ok, stat, errmsg)
    if (stat /= STAT_OK .or. .not. ok) then
      ok = .false.
      return
    end if
    g%lineno = g%lineno + 1
    g%line = g%buf(1:nl)
    if (g%lineno == 1 .and. nl >= 3) then
      if (g%line(1:3) == BOM) g%line = g%line(4:)
    end if
  end subroutine raw_line

  !> The next non-blank line (raw_line) split into words; ok = .false. at the end of the file.
  subroutine next_line(g, ok, stat, errmsg)
    class(line_reader_t), intent(inout) :: g
    logical, intent(out) :: ok
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    do
      call raw_line(g, ok, stat, errmsg)
      if (.not. ok) return
      call tokenize(g)
      if (g%ntok > 0) return
    end do
  end subroutine next_line

  !> The next line into buf(1:nl): what is left of a record after a lone CR (pending), then the
  !> record read on, up to its end or the next CR. got = .false. at the end of the file.
  subroutine physical_piece(g, nl, got, stat, errmsg)
    type(line_reader_t), intent(inout) :: g
    integer, intent(out) :: nl
    logical, intent(out) :: got
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=4096) :: chunk
    integer :: ios, n, c
    logical :: done
    stat = STAT_OK
    nl = 0
    got = .false.
    done = .false.
    if (len(g%pending) > 0 .or. g%pending_eor) then
      got = .true.
      c = index(g%pending, CR)
      if (c > 0) then
        call take(g%pending(1:c - 1))
        g%pending = g%pending(c + 1:)
        return
      end if
      call take(g%pending)
      g%pending = ''
      if (g%pending_eor) then
        g%pending_eor = .false.
        return
      end if
    end if
    do while (.not. done)
      read (g%unit, '(a)', advance='no', iostat=ios, size=n) chunk
      if (ios == iostat_end) return   ! got: the last line had no newline
      if (ios /= 0 .and. ios /= iostat_eor) then
        g%lineno = g%lineno + 1
        call fail(g, stat, errmsg, 'read error (not a text file?)')
        return
      end if
      got = .true.
      done = ios == iostat_eor
      c = index(chunk(1:n), CR)
      if (c > 0 .and. c < n) then
        ! A lone CR ends the line; the rest of the chunk waits for the next call.
        g%pending = chunk(c + 1:n)
        g%pending_eor = done
        n = c - 1
        done = .true.
      else if (c == n .and. c > 0) then
        n = c - 1                     ! CR LF, or a CR at the end of a chunk
        if (.not. done) done = .true.
      end if
      call take(chunk(1:n))
      if (stat /= STAT_OK) return
    end do
  contains
    subroutine take(piece)
      character(len=*), intent(in) :: piece
      if (nl + len(piece) > MAX_LINE) then
        g%lineno = g%lineno + 1
        call fail(g, stat, errmsg, 'line longer than ' // str(MAX_LINE) // ' characters (not a text file?)')
        return
      end if
      ! The line grows in a buffer that doubles: reading is linear in the line's length.
      if (nl + len(piece) > len(g%buf)) call grow_text(g%buf, nl + len(piece))
      g%buf(nl + 1:nl + len(piece)) = piece
      nl = nl + len(piece)
    end subroutine take
  end subroutine physical_piece

  !> Token k of the current line as an integer in [lo, hi].
  subroutine get_int(g, k, lo, hi, what, val, stat, errmsg)
    class(line_reader_t), intent(inout) :: g
    integer, intent(in) :: k, lo, hi
    character(len=*), intent(in) :: what
    integer, intent(out) :: val
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer(int64) :: v
    integer :: ierr
    stat = STAT_OK
    val = 0
    call parse_int64_text(tok(g, k), v, ierr)
    if (ierr == NUM_MALFORMED) then
      call fail(g, stat, errmsg, 'expected ' // what // ', found "' // clip(tok(g, k)) // '"')
    else if (ierr /= NUM_OK .or. v < lo .or. v > hi) then
      call fail(g, stat, errmsg, 'expected ' // what // ', found ' // clip(tok(g, k)) // ' (out of range)')
    else
      val = int(v)
    end if
  end subroutine get_int

  !> Tokens 1..n of the current line as reals.
  subroutine get_reals(g, n, what, val, stat, errmsg)
    class(line_reader_t), intent(inout) :: g
    integer, intent(in) :: n
    character(len=*), intent(in) :: what
    real(dp), intent(out) :: val(n)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, ierr
    stat = STAT_OK
    do k = 1, n
      call parse_real_text(tok(g, k), val(k), ierr)
      if (ierr /= NUM_OK) then
        call fail(g, stat, errmsg, 'expected ' // what // ' (a finite real number), found "' // clip(tok(g, k)) // '"' // &
          trim(merge(' (out of range)', '               ', ierr == NUM_RANGE)))
        return
      end if
    end do
  end subroutine get_reals

  !> Token k must be a real number (value unused).
  subroutine get_real_tok(g, k, what, stat, errmsg)
    class(line_reader_t), intent(inout) :: g
    integer, intent(in) :: k
    character(len=*), intent(in) :: what
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: v
    integer :: ierr
    stat = STAT_OK
    call parse_real_text(tok(g, k), v, ierr)
    if (ierr /= NUM_OK) call fail(g, stat, errmsg, 'expected ' // what // ' (a real number), found "' // clip(tok(g, k)) // '"')
  end subroutine get_real_tok

  !> Error at the current line.
  subroutine fail(g, stat, errmsg, msg)
    class(line_reader_t), intent(in) :: g
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=*), intent(in) :: msg
    call set_error(stat, errmsg, STAT_INPUT, g%path // ':' // str(g%lineno) // ': ' // msg)
  end subroutine fail

  !> Split the current line into words (words' blanks: space, tab, CR).
  pure subroutine tokenize(g)
    class(line_reader_t), intent(inout) :: g
    integer :: i, j, n
    n = len(g%line)
    g%ntok = 0
    i = 1
    do while (i <= n)
      if (is_blank(g%line(i:i))) then
        i = i + 1
        cycle
      end if
      j = word_end(g%line, i)
      if (g%ntok == size(g%tb)) then
        call grow(g%tb, 2 * g%ntok)
        call grow(g%te, 2 * g%ntok)
      end if
      g%ntok = g%ntok + 1
      g%tb(g%ntok) = i
      g%te(g%ntok) = j - 1
      i = j
    end do
  end subroutine tokenize

  !> Token k of the current line ('' past the last one).
  pure function tok(g, k) result(s)
    class(line_reader_t), intent(in) :: g
    integer, intent(in) :: k
    character(len=:), allocatable :: s
    if (k >= 1 .and. k <= g%ntok) then
      s = g%line(g%tb(k):g%te(k))
    else
      s = ''
    end if
  end function tok

  !> A line or a word for messages: shortened, and described instead of quoted when it is not
  !> text (a binary file is never echoed).
  pure function clip(s) result(c)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: c
    c = shown(s)
    if (c /= s) return
    if (len_trim(s) > 60) then
      c = s(1:57) // '...'
    else
      c = trim(s)
    end if
  end function clip

  !> Room for n characters in a (doubling), the content kept.
  pure subroutine grow_text(a, n)
    character(len=:), allocatable, intent(inout) :: a
    integer, intent(in) :: n
    character(len=:), allocatable :: tmp
    allocate (character(len=max(n, 2 * len(a))) :: tmp)
    tmp(1:len(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_text
end module line_reader
