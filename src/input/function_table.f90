!> FUNCTION … TABLE FILE path (docs/input.md, "Functions"): a two-column text table of times and
!> values, read in one pass (time linear in the file's size) through the line reader and the one
!> number reader. Columns separated by blanks, a comma or a semicolon; '#' starts a comment; one
!> header line of words is allowed before the numbers. Times must increase; values within ±1e100.
module function_table
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use array_utils, only: grow
  use line_reader, only: line_reader_t, open_reader, close_reader, raw_line
  use number_text, only: parse_real_text, NUM_OK
  implicit none
  private
  public :: read_function_table

  real(dp), parameter :: MAX_VALUE = 1.0e100_dp

contains

  !> The points of the table at path into t(1:n), f(1:n) (n >= 1). Errors name path:line.
  subroutine read_function_table(path, t, f, stat, errmsg)
    character(len=*), intent(in) :: path
    real(dp), allocatable, intent(out) :: t(:), f(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(line_reader_t) :: g
    real(dp) :: v(2)
    integer :: n, nw
    logical :: ok, header_seen
    call open_reader(g, path, 'table file', stat, errmsg)
    if (stat /= STAT_OK) return
    allocate (t(1024), f(1024))
    n = 0
    header_seen = .false.
    do
      call raw_line(g, ok, stat, errmsg)
      if (stat /= STAT_OK .or. .not. ok) exit
      call two_numbers(g%line, v, nw, ok)
      if (nw == 0) cycle                           ! blank or comment
      if (.not. ok) then
        if (n == 0 .and. .not. header_seen) then   ! one header line of words
          header_seen = .true.
          cycle
        end if
        call set_error(stat, errmsg, STAT_INPUT, path // ':' // str(g%lineno) // ': expected two numbers (time, ' // &
          'value), found "' // trim(g%line(1:min(len(g%line), 60))) // '"')
        exit
      end if
      if (abs(v(2)) > MAX_VALUE) then
        call set_error(stat, errmsg, STAT_INPUT, path // ':' // str(g%lineno) // ': values must be within ±1e100')
        exit
      end if
      if (n > 0) then
        if (v(1) <= t(n)) then
          call set_error(stat, errmsg, STAT_INPUT, path // ':' // str(g%lineno) // ': times must increase (' // &
            str(v(1)) // ' after ' // str(t(n)) // ')')
          exit
        end if
      end if
      n = n + 1
      call grow(t, n)
      call grow(f, n)
      t(n) = v(1)
      f(n) = v(2)
    end do
    call close_reader(g)
    if (stat /= STAT_OK) return
    if (n == 0) then
      call set_error(stat, errmsg, STAT_INPUT, path // ':' // str(g%lineno) // ': no point in the table')
      return
    end if
    t = t(1:n)
    f = f(1:n)
  end subroutine read_function_table

  !> The words of line (blanks, ',' and ';' separate them, '#' ends the line): nw of them; ok when
  !> they are exactly two numbers, into v.
  pure subroutine two_numbers(line, v, nw, ok)
    character(len=*), intent(in) :: line
    real(dp), intent(out) :: v(2)
    integer, intent(out) :: nw
    logical, intent(out) :: ok
    integer :: i, j, ierr
    nw = 0
    ok = .true.
    v = 0.0_dp
    i = 1
    do
      do while (i <= len(line))
        if (index(' ,;' // achar(9) // achar(13), line(i:i)) == 0) exit
        i = i + 1
      end do
      if (i > len(line)) exit
      if (line(i:i) == '#') exit
      j = i
      do while (j <= len(line))
        if (index(' ,;#' // achar(9) // achar(13), line(j:j)) > 0) exit
        j = j + 1
      end do
      nw = nw + 1
      if (nw <= 2) then
        call parse_real_text(line(i:j - 1), v(nw), ierr)
        if (ierr /= NUM_OK) ok = .false.
      end if
      i = j
    end do
    if (nw /= 2) ok = .false.
  end subroutine two_numbers
end module function_table
