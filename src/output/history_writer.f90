!> CSV result files (history.csv, probes.csv, events.csv, contacts.csv): a header row, then
!> one line per output, each in the file as soon as it is written (text_file: one checked
!> write(2) per line) so that a run stopped at any moment leaves complete lines, and a full
!> disk stops the run with a message. Rows are formatted into a buffer sized at open: nothing
!> is allocated per row (text_format).
module history_writer
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, set_error
  use text_format, only: put_es, put_int, put_text, ES_MAX_LEN
  use text_file, only: text_file_t
  use line_reader, only: line_reader_t, open_reader, close_reader, raw_line
  use number_text, only: parse_int_text, NUM_OK
  implicit none
  private
  public :: csv_file_t

  type :: csv_file_t
    private
    type(text_file_t) :: f
    character(len=:), allocatable :: buf
  contains
    procedure :: open => csv_open
    procedure :: write_row
    procedure :: write_line => csv_write_line
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
    call self%f%create(path, stat, errmsg)
    if (stat /= STAT_OK) return
    call size_buffer(self, header)
    call self%f%write_line(header, stat, errmsg)
  end subroutine csv_open

  subroutine size_buffer(self, header)
    type(csv_file_t), intent(inout) :: self
    character(len=*), intent(in) :: header
    if (allocated(self%buf)) deallocate (self%buf)
    allocate (character(len=32 * (count_commas(header) + 1) + 64) :: self%buf)
  end subroutine size_buffer

  !> Reopen a result file after a restart from step `last`: keep the header and the lines of
  !> steps <= last (a killed run may have written lines past its checkpoint), rewritten
  !> atomically, then append. A missing file is created with the header.
  subroutine csv_resume(self, path, header, last, stat, errmsg)
    use os_utils, only: os_rename, path_exists, remove_file
    class(csv_file_t), intent(inout) :: self
    character(len=*), intent(in) :: path, header
    integer, intent(in) :: last
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(text_file_t) :: out
    type(line_reader_t) :: old
    integer :: k, step, ierr, st2
    logical :: ok
    character(len=:), allocatable :: msg2
    stat = STAT_OK
    if (.not. path_exists(path)) then
      call self%open(path, header, stat, errmsg)
      return
    end if
    call open_reader(old, path, 'result file', stat, errmsg)
    if (stat /= STAT_OK) then
      stat = STAT_RUN
      return
    end if
    ! The kept lines go to path.tmp, which replaces path only once complete: a failure
    ! (a full disk) leaves the old file whole.
    call out%create(path // '.tmp', stat, errmsg)
    if (stat == STAT_OK) call out%write_line(header, stat, errmsg)
    if (stat == STAT_OK) call raw_line(old, ok, stat, errmsg)   ! the old header
    do while (stat == STAT_OK .and. ok)
      call raw_line(old, ok, stat, errmsg)
      if (stat /= STAT_OK .or. .not. ok) exit
      k = index(old%line, ',')
      if (k < 2) cycle
      call parse_int_text(old%line(1:k - 1), step, ierr)
      if (ierr /= NUM_OK) cycle
      if (step <= last) call out%write_line(old%line, stat, errmsg)
    end do
    call close_reader(old)
    if (stat /= STAT_OK) stat = STAT_RUN   ! a read error of the old file stops the restart too
    call out%close_keep(stat, errmsg)
    if (stat /= STAT_OK) then
      call remove_file(path // '.tmp', st2, msg2)
      return
    end if
    call os_rename(path // '.tmp', path, stat, errmsg)
    if (stat /= STAT_OK) return
    call self%f%append(path, stat, errmsg)
    if (stat /= STAT_OK) return
    call size_buffer(self, header)
  end subroutine csv_resume

  pure integer function count_commas(s)
    character(len=*), intent(in) :: s
    integer :: i
    count_commas = 0
    do i = 1, len(s)
      if (s(i:i) == ',') count_commas = count_commas + 1
    end do
  end function count_commas

  !> One line: step, then reals (17 significant digits), then integers, then more reals, then
  !> more integers.
  !> Built in the buffer by text_format (the characters of I0 and ES24.16E3 without blanks),
  !> not by internal WRITEs, which allocate in the Fortran runtime at every statement.
  subroutine write_row(self, step, reals, ints, stat, errmsg, tail, tail_ints, tail2)
    class(csv_file_t), intent(inout) :: self
    integer, intent(in) :: step
    real(dp), intent(in) :: reals(:)
    integer, intent(in) :: ints(:)
    real(dp), intent(in), optional :: tail(:)
    integer, intent(in), optional :: tail_ints(:)
    real(dp), intent(in), optional :: tail2(:)     !< reals after tail_ints (columns added later)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: pos, i, need
    stat = STAT_OK
    need = 12 * (1 + size(ints)) + (ES_MAX_LEN + 1) * size(reals)
    if (present(tail)) need = need + (ES_MAX_LEN + 1) * size(tail)
    if (present(tail_ints)) need = need + 12 * size(tail_ints)
    if (present(tail2)) need = need + (ES_MAX_LEN + 1) * size(tail2)
    if (len(self%buf) < need) then
      ! More values than the header has columns: grow once.
      deallocate (self%buf)
      allocate (character(len=need) :: self%buf)
    end if
    pos = 0
    call put_int(self%buf, pos, step)
    call put_reals(self%buf, pos, reals)
    do i = 1, size(ints)
      call put_text(self%buf, pos, ',')
      call put_int(self%buf, pos, ints(i))
    end do
    if (present(tail)) call put_reals(self%buf, pos, tail)
    if (present(tail_ints)) then
      do i = 1, size(tail_ints)
        call put_text(self%buf, pos, ',')
        call put_int(self%buf, pos, tail_ints(i))
      end do
    end if
    if (present(tail2)) call put_reals(self%buf, pos, tail2)
    call self%f%write_line(self%buf(1:pos), stat, errmsg)
  end subroutine write_row

  !> ",x1,x2,…" appended to buf at pos.
  subroutine put_reals(buf, pos, x)
    character(len=*), intent(inout) :: buf
    integer, intent(inout) :: pos
    real(dp), intent(in) :: x(:)
    integer :: i
    do i = 1, size(x)
      call put_text(buf, pos, ',')
      call put_es(buf, pos, x(i))
    end do
  end subroutine put_reals

  !> A line built by the caller (events.csv, contacts.csv).
  subroutine csv_write_line(self, line, stat, errmsg)
    class(csv_file_t), intent(inout) :: self
    character(len=*), intent(in) :: line
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call self%f%write_line(line, stat, errmsg)
  end subroutine csv_write_line

  !> Close; a failure to close (the last bytes not stored) is reported like a failed write.
  subroutine csv_close(self, stat, errmsg)
    class(csv_file_t), intent(inout) :: self
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call self%f%close(stat, errmsg)
  end subroutine csv_close
end module history_writer
