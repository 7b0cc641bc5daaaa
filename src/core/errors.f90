!> Status codes and message helpers, in the Truchas/toml-f style: a procedure that can fail
!> returns `stat` and an allocatable `errmsg`; its caller returns early on `stat /= 0`.
module errors
  implicit none
  private
  public :: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str, upper

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
