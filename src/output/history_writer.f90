!> CSV result files (history.csv, probes.csv): a header row, then one line per output, each
!> flushed as soon as it is written so that a run stopped at any moment leaves complete lines.
!> Rows are formatted into a buffer sized at open: nothing is allocated per row (text_format).
module history_writer
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, set_error
  use text_format, only: put_es, put_int, put_text, ES_MAX_LEN
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
    procedure :: resume => csv_resume
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

  !> Reopen a result file after a restart from step `last`: keep the header and the lines of
  !> steps <= last (a killed run may have written lines past its checkpoint), rewritten
  !> atomically, then append. A missing file is created with the header.
  subroutine csv_resume(self, path, header, last, stat, errmsg)
    use os_utils, only: os_rename, path_exists
    class(csv_file_t), intent(inout) :: self
    character(len=*), intent(in) :: path, header
    integer, intent(in) :: last
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: uin, uout, ios, k, step
    character(len=:), allocatable :: line
    character(len=256) :: msg
    stat = STAT_OK
    if (.not. path_exists(path)) then
      call self%open(path, header, stat, errmsg)
      return
    end if
    open (newunit=uin, file=path, status='old', action='read', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call set_error(stat, errmsg, STAT_RUN, 'cannot read ' // path // ': ' // trim(msg))
      return
    end if
    open (newunit=uout, file=path // '.tmp', status='replace', action='write', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      close (uin)
      call set_error(stat, errmsg, STAT_RUN, 'cannot create ' // path // '.tmp: ' // trim(msg))
      return
    end if
    write (uout, '(a)') header
    call read_line(uin, line, ios)   ! the old header
    do
      call read_line(uin, line, ios)
      if (ios /= 0) exit
      k = index(line, ',')
      if (k < 2) cycle
      read (line(1:k - 1), *, iostat=ios) step
      if (ios /= 0) cycle
      if (step <= last) write (uout, '(a)') line
    end do
    close (uin)
    close (uout)
    call os_rename(path // '.tmp', path, stat, errmsg)
    if (stat /= STAT_OK) return
    open (newunit=self%unit, file=path, status='old', position='append', action='write', iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call set_error(stat, errmsg, STAT_RUN, 'cannot append to ' // path // ': ' // trim(msg))
      self%unit = -1
      return
    end if
    self%path = path
    allocate (character(len=32 * (count_commas(header) + 1) + 64) :: self%buf)
  end subroutine csv_resume

  !> One line of any length.
  subroutine read_line(unit, line, ios)
    integer, intent(in) :: unit
    character(len=:), allocatable, intent(out) :: line
    integer, intent(out) :: ios
    character(len=4096) :: chunk
    integer :: n
    line = ''
    do
      read (unit, '(a)', advance='no', iostat=ios, size=n) chunk
      line = line // chunk(1:n)
      if (ios /= 0) exit
    end do
    if (is_iostat_eor(ios)) ios = 0
  end subroutine read_line

  pure integer function count_commas(s)
    character(len=*), intent(in) :: s
    integer :: i
    count_commas = 0
    do i = 1, len(s)
      if (s(i:i) == ',') count_commas = count_commas + 1
    end do
  end function count_commas

  !> One line: step, then reals (17 significant digits), then integers, then more reals.
  !> Built in the buffer by text_format (the characters of I0 and ES24.16E3 without blanks),
  !> not by internal WRITEs, which allocate in the Fortran runtime at every statement.
  subroutine write_row(self, step, reals, ints, stat, errmsg, tail)
    class(csv_file_t), intent(inout) :: self
    integer, intent(in) :: step
    real(dp), intent(in) :: reals(:)
    integer, intent(in) :: ints(:)
    real(dp), intent(in), optional :: tail(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: ios, pos, i, need
    stat = STAT_OK
    need = 12 * (1 + size(ints)) + (ES_MAX_LEN + 1) * size(reals)
    if (present(tail)) need = need + (ES_MAX_LEN + 1) * size(tail)
    if (len(self%buf) < need) then
      ! More values than the header has columns: grow once.
      deallocate (self%buf)
      allocate (character(len=need) :: self%buf)
    end if
    pos = 0
    call put_int(self%buf, pos, step)
    do i = 1, size(reals)
      call put_text(self%buf, pos, ',')
      call put_es(self%buf, pos, reals(i))
    end do
    do i = 1, size(ints)
      call put_text(self%buf, pos, ',')
      call put_int(self%buf, pos, ints(i))
    end do
    if (present(tail)) then
      do i = 1, size(tail)
        call put_text(self%buf, pos, ',')
        call put_es(self%buf, pos, tail(i))
      end do
    end if
    write (self%unit, '(a)', iostat=ios) self%buf(1:pos)
    if (ios == 0) flush (self%unit, iostat=ios)
    if (ios /= 0) call set_error(stat, errmsg, STAT_RUN, 'cannot write ' // self%path)
  end subroutine write_row

  subroutine csv_close(self)
    class(csv_file_t), intent(inout) :: self
    ! newunit= numbers are negative: -1 alone means closed.
    if (self%unit /= -1) close (self%unit)
    self%unit = -1
  end subroutine csv_close
end module history_writer
