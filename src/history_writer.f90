!> CSV result files (history.csv, probes.csv): a header row, then one line per output, each
!> flushed as soon as it is written so that a run stopped at any moment leaves complete lines.
!> Rows are formatted into a buffer sized at open: nothing is allocated per row.
module history_writer
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, set_error
  implicit none
  private
  public :: csv_file_t

  type :: csv_file_t
    integer :: unit = -1
    character(len=:), allocatable :: path
    character(len=:), allocatable :: buf
  contains
    procedure :: open => csv_open
    procedure :: write_row
    procedure :: close => csv_close
  end type csv_file_t

contains

  !> Create the file and write its header (comma-separated column names).
  subroutine csv_open(self, path, header, stat, errmsg)
    class(csv_file_t), intent(inout) :: self
    character(len=*), intent(in) :: path, header
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: ios, ncol
    character(len=256) :: msg
    stat = STAT_OK
    open (newunit=self%unit, file=path, status='replace', action='write', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call set_error(stat, errmsg, STAT_RUN, 'cannot create ' // path // ': ' // trim(msg))
      self%unit = -1
      return
    end if
    self%path = path
    ncol = count_commas(header) + 1
    allocate (character(len=32 * ncol + 64) :: self%buf)
    write (self%unit, '(a)') header
    flush (self%unit)
  end subroutine csv_open

  pure integer function count_commas(s)
    character(len=*), intent(in) :: s
    integer :: i
    count_commas = 0
    do i = 1, len(s)
      if (s(i:i) == ',') count_commas = count_commas + 1
    end do
  end function count_commas

  !> One line: step, then reals (17 significant digits), then integers, then more reals.
  subroutine write_row(self, step, reals, ints, stat, errmsg, tail)
    class(csv_file_t), intent(inout) :: self
    integer, intent(in) :: step
    real(dp), intent(in) :: reals(:)
    integer, intent(in) :: ints(:)
    real(dp), intent(in), optional :: tail(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: ios, pos, i
    stat = STAT_OK
    write (self%buf, '(i0)') step
    pos = len_trim(self%buf)
    do i = 1, size(reals)
      write (self%buf(pos + 1:), '(",",es24.16e3)') reals(i)
      pos = len_trim(self%buf)
    end do
    do i = 1, size(ints)
      write (self%buf(pos + 1:), '(",",i0)') ints(i)
      pos = len_trim(self%buf)
    end do
    if (present(tail)) then
      do i = 1, size(tail)
        write (self%buf(pos + 1:), '(",",es24.16e3)') tail(i)
        pos = len_trim(self%buf)
      end do
    end if
    write (self%unit, '(a)', iostat=ios) trim(squeeze(self%buf(1:pos)))
    if (ios == 0) flush (self%unit, iostat=ios)
    if (ios /= 0) call set_error(stat, errmsg, STAT_RUN, 'cannot write ' // self%path)
  end subroutine write_row

  !> The row without the blanks the E format pads with.
  pure function squeeze(s) result(r)
    character(len=*), intent(in) :: s
    character(len=len(s)) :: r
    integer :: i, k
    r = ' '
    k = 0
    do i = 1, len(s)
      if (s(i:i) /= ' ') then
        k = k + 1
        r(k:k) = s(i:i)
      end if
    end do
    r = r(1:k)
  end function squeeze

  subroutine csv_close(self)
    class(csv_file_t), intent(inout) :: self
    ! newunit= numbers are negative: -1 alone means closed.
    if (self%unit /= -1) close (self%unit)
    self%unit = -1
  end subroutine csv_close
end module history_writer
