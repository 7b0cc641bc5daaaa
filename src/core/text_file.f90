!> A text result file whose every write is checked (gfortran's FLUSH does not report a full
!> disk): lines go to the file one write(2) each through src/core/file_shim.c, a failure
!> becomes STAT_RUN with "cannot write <path>: <the system's reason>" and the file is cut back
!> to its last complete line. A symbolic link at the path is replaced, not followed.
module text_file
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_associated, c_int, c_char, c_size_t, c_null_char
  use errors, only: STAT_OK, STAT_RUN, set_error
  use c_interfaces, only: rb_file_open, rb_file_write, rb_file_close, rb_strerror, rb_take_errno, rb_file_replace_tail, &
    rb_stdout_line
  implicit none
  private
  public :: text_file_t, os_reason, clear_os_reason, say, stdout_error

  type :: text_file_t
    private
    type(c_ptr) :: h = c_null_ptr
    character(len=:), allocatable :: path
  contains
    procedure :: create => tf_create
    procedure :: append => tf_append
    procedure :: write_line => tf_write_line
    procedure :: write_text => tf_write_text
    procedure :: write_bytes => tf_write_bytes
    procedure :: replace_tail => tf_replace_tail
    procedure :: close => tf_close
    procedure :: close_keep => tf_close_keep
  end type text_file_t

  !> The first error writing to standard output (say), 0 if none: the run's report is checked
  !> like its files, and a run that could not give it exits 1 (rebond.f90).
  integer, save :: stdout_err = 0

contains

  !> One line of the run's report on standard output, written at once and checked (gfortran's
  !> unit 6 drops a write to a full device without a word).
  subroutine say(text)
    character(len=*), intent(in) :: text
    integer(c_int) :: err
    err = rb_stdout_line(text, int(len(text), c_size_t))
    if (err /= 0 .and. stdout_err == 0) stdout_err = err
  end subroutine say

  !> '' when every line of say reached standard output, else the reason of the first failure.
  function stdout_error() result(msg)
    character(len=:), allocatable :: msg
    msg = ''
    if (stdout_err /= 0) msg = strerror_text(stdout_err)
  end function stdout_error

  !> Why the last failed system call failed (strerror of errno), '' if it is not known; errno
  !> is cleared. For libraries that do not say (HDF5).
  function os_reason() result(s)
    character(len=:), allocatable :: s
    integer(c_int) :: err
    err = rb_take_errno()
    s = ''
    if (err /= 0) s = strerror_text(err)
  end function os_reason

  !> Forget errno (after a library call that succeeded).
  subroutine clear_os_reason()
    integer(c_int) :: err
    err = rb_take_errno()
  end subroutine clear_os_reason

  function strerror_text(err) result(s)
    integer(c_int), intent(in) :: err
    character(len=:), allocatable :: s
    character(kind=c_char, len=256) :: buf
    integer :: n
    call rb_strerror(err, buf, len(buf, kind=c_int))
    n = index(buf, c_null_char) - 1
    if (n < 0) n = len_trim(buf)
    s = buf(1:n)
  end function strerror_text

  !> "<what> <path>: <strerror(err)>".
  subroutine os_error(stat, errmsg, what, path, err)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=*), intent(in) :: what, path
    integer(c_int), intent(in) :: err
    call set_error(stat, errmsg, STAT_RUN, what // ' ' // path // ': ' // strerror_text(err))
  end subroutine os_error

  !> A new, empty file at path (an existing file or symbolic link there is replaced).
  subroutine tf_create(self, path, stat, errmsg)
    class(text_file_t), intent(inout) :: self
    character(len=*), intent(in) :: path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call open_mode(self, path, 0_c_int, 'cannot create', stat, errmsg)
  end subroutine tf_create

  !> An existing regular file, written at its end.
  subroutine tf_append(self, path, stat, errmsg)
    class(text_file_t), intent(inout) :: self
    character(len=*), intent(in) :: path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call open_mode(self, path, 1_c_int, 'cannot append to', stat, errmsg)
  end subroutine tf_append

  subroutine open_mode(self, path, mode, what, stat, errmsg)
    type(text_file_t), intent(inout) :: self
    character(len=*), intent(in) :: path, what
    integer(c_int), intent(in) :: mode
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer(c_int) :: err
    stat = STAT_OK
    if (c_associated(self%h)) call tf_close(self, stat, errmsg)
    self%path = path
    self%h = rb_file_open(path // c_null_char, mode, err)
    if (.not. c_associated(self%h)) call os_error(stat, errmsg, what, path, err)
  end subroutine open_mode

  !> One line and its newline, in one write(2): complete in the file when stat is STAT_OK.
  !> Nothing is allocated (it runs in the time loop).
  subroutine tf_write_line(self, line, stat, errmsg)
    class(text_file_t), intent(inout) :: self
    character(len=*), intent(in) :: line
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call put(self, line, 1_c_int, stat, errmsg)
  end subroutine tf_write_line

  !> Text as it is (newlines included), in one write.
  subroutine tf_write_text(self, text, stat, errmsg)
    class(text_file_t), intent(inout) :: self
    character(len=*), intent(in) :: text
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call put(self, text, 0_c_int, stat, errmsg)
  end subroutine tf_write_text

  !> Raw bytes (a binary image), in one write.
  subroutine tf_write_bytes(self, bytes, stat, errmsg)
    class(text_file_t), intent(inout) :: self
    character(kind=c_char, len=1), intent(in) :: bytes(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer(c_int) :: err
    if (not_open(self, stat, errmsg)) return
    err = rb_file_write(self%h, bytes, size(bytes, kind=c_size_t), 0_c_int)
    if (err /= 0) call os_error(stat, errmsg, 'cannot write', self%path, err)
  end subroutine tf_write_bytes

  !> Replace the last tail_len characters of the file by text (which ends with them again), in
  !> one write: the file is a complete document before and after (fields.xmf gains a step).
  subroutine tf_replace_tail(self, text, tail_len, stat, errmsg)
    class(text_file_t), intent(inout) :: self
    character(len=*), intent(in) :: text
    integer, intent(in) :: tail_len
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer(c_int) :: err
    if (not_open(self, stat, errmsg)) return
    err = rb_file_replace_tail(self%h, text, len(text, kind=c_size_t), int(tail_len, c_size_t))
    if (err /= 0) call os_error(stat, errmsg, 'cannot write', self%path, err)
  end subroutine tf_replace_tail

  subroutine put(self, text, newline, stat, errmsg)
    type(text_file_t), intent(inout) :: self
    character(len=*), intent(in) :: text
    integer(c_int), intent(in) :: newline
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer(c_int) :: err
    if (not_open(self, stat, errmsg)) return
    err = rb_file_write(self%h, text, len(text, kind=c_size_t), newline)
    if (err /= 0) call os_error(stat, errmsg, 'cannot write', self%path, err)
  end subroutine put

  !> stat = STAT_OK, or the error of writing to a file that is not open.
  logical function not_open(self, stat, errmsg)
    type(text_file_t), intent(in) :: self
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    not_open = .not. c_associated(self%h)
    if (not_open) call set_error(stat, errmsg, STAT_RUN, 'cannot write ' // tf_name(self) // ': the file is not open')
  end function not_open

  !> Close (a closed file: nothing to do).
  subroutine tf_close(self, stat, errmsg)
    class(text_file_t), intent(inout) :: self
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer(c_int) :: err
    stat = STAT_OK
    if (.not. c_associated(self%h)) return
    err = rb_file_close(self%h)
    self%h = c_null_ptr
    if (err /= 0) call os_error(stat, errmsg, 'cannot close', self%path, err)
  end subroutine tf_close

  !> Close after a sequence of writes whose status is stat (sticky): a failure to close is
  !> reported only when everything before succeeded; the first error is kept.
  subroutine tf_close_keep(self, stat, errmsg)
    class(text_file_t), intent(inout) :: self
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer :: st
    character(len=:), allocatable :: msg
    call tf_close(self, st, msg)
    if (stat == STAT_OK .and. st /= STAT_OK) then
      stat = st
      errmsg = msg
    end if
  end subroutine tf_close_keep

  !> The path, for messages ('' before the first open).
  pure function tf_name(self) result(path)
    type(text_file_t), intent(in) :: self
    character(len=:), allocatable :: path
    path = ''
    if (allocated(self%path)) path = self%path
  end function tf_name
end module text_file
