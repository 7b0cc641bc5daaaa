!> Status codes and message helpers, in the Truchas/toml-f style: a procedure that can fail
!> returns `stat` and an allocatable `errmsg`; its caller returns early on `stat /= 0`.
module errors
  implicit none
  private
  public :: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str, upper, shown, check_alloc

  integer, parameter :: STAT_OK = 0     !< success
  integer, parameter :: STAT_RUN = 1    !< failure while running (solver, I/O)
  integer, parameter :: STAT_INPUT = 2  !< bad input (scene, mesh file, command line)

  interface str
    module procedure str_int, str_real
  end interface str

contains

  !> Set a failure status and its message.
  pure subroutine set_error(stat, errmsg, code, msg)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, intent(in) :: code
    character(len=*), intent(in) :: msg
    stat = code
    errmsg = msg
  end subroutine set_error

  !> After `allocate (..., stat=ast)` of the arrays of `what` (nbytes in all): out of memory
  !> becomes STAT_RUN with one message instead of the runtime's abort and backtrace.
  pure subroutine check_alloc(ast, what, nbytes, stat, errmsg)
    integer, intent(in) :: ast
    character(len=*), intent(in) :: what
    real(kind(1.0d0)), intent(in) :: nbytes
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    character(len=24) :: buf
    if (ast == 0 .or. stat /= STAT_OK) return
    write (buf, '(f0.1)') nbytes / 1048576.0d0
    stat = STAT_RUN
    errmsg = 'out of memory: cannot allocate ' // trim(buf) // ' MiB for ' // what // &
      ' (a smaller mesh, or more memory: ulimit -v, free memory)'
  end subroutine check_alloc

  !> An integer as text, without blanks.
  pure function str_int(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(len=24) :: buf
    write (buf, '(i0)') i
    s = trim(buf)
  end function str_int

  !> A real as text in the shortest form that reads back (es format, 17 digits trimmed).
  pure function str_real(x) result(s)
    use kinds, only: dp
    real(dp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: buf
    write (buf, '(g0)') x
    s = trim(adjustl(buf))
  end function str_real

  !> Text from a file, fit to be quoted in a message: itself when it is text (printable ASCII,
  !> tabs, well-formed UTF-8), else a description, so that raw bytes never reach the terminal.
  pure function shown(s) result(t)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: t
    integer :: i, c, k, more
    character(len=16), parameter :: HEX = '0123456789ABCDEF'
    i = 1
    do while (i <= len(s))
      c = iachar(s(i:i))
      more = -1
      if (c == 9 .or. (c >= 32 .and. c <= 126)) then
        more = 0
      else if (c >= 194 .and. c <= 223) then
        more = 1
      else if (c >= 224 .and. c <= 239) then
        more = 2
      else if (c >= 240 .and. c <= 244) then
        more = 3
      end if
      if (more >= 0 .and. i + more <= len(s)) then
        do k = i + 1, i + more
          if (iachar(s(k:k)) < 128 .or. iachar(s(k:k)) > 191) more = -1
        end do
      else
        more = -1
      end if
      if (more < 0) then
        t = 'binary data (byte 0x' // HEX(c / 16 + 1:c / 16 + 1) // HEX(mod(c, 16) + 1:mod(c, 16) + 1) // &
          ' at character ' // str_int(i) // ')'
        return
      end if
      i = i + 1 + more
    end do
    t = s
  end function shown

  !> Upper-case copy of an ASCII string.
  pure function upper(s) result(u)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: u
    integer :: i, c
    u = s
    do i = 1, len(s)
      c = iachar(s(i:i))
      if (c >= iachar('a') .and. c <= iachar('z')) u(i:i) = achar(c - 32)
    end do
  end function upper
end module errors
