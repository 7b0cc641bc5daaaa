!> Checkpoint files: the whole state of a run in one HDF5 file, written atomically so that a
!> run killed at any moment leaves either the previous checkpoint or the new one, never half
!> of one: the file is built in memory (HDF5's core driver), its bytes written under a
!> temporary name with every write checked (text_file), read back and compared, and only then
!> renamed over the old one. A full disk is an error and leaves the old checkpoint whole.
!> Each owner of state writes its own fields (newmark's save_checkpoint asks them); this
!> module stores named arrays and scalars through hdf5_file and, on reading, checks every
!> shape. Quadruple-precision arrays are stored bit for bit as pairs of doubles (transfer), so
!> that a restart continues exactly where the run stopped. stat and errmsg of put and get are
!> sticky: after a failure the later calls do nothing and the first message stays.
module checkpoint
  use kinds, only: dp, qp
  use errors, only: STAT_OK, STAT_INPUT, STAT_RUN, set_error, str
  use, intrinsic :: iso_c_binding, only: c_char
  use os_utils, only: os_rename, path_exists, remove_file
  use text_file, only: text_file_t
  use hdf5_file, only: h5_file_t
  implicit none
  private
  public :: ckpt_file_t

  !> An open checkpoint, for writing (create) or reading (open).
  type :: ckpt_file_t
    private
    type(h5_file_t) :: f
    character(len=:), allocatable :: path, tmp
  contains
    procedure :: create => ck_create
    procedure :: commit => ck_commit
    procedure :: open => ck_open
    procedure :: close => ck_close
    generic :: put => put_r1, put_r2, put_i1, put_r0, put_i0, put_q1, put_text
    generic :: get => get_r1, get_r2, get_i1, get_r0, get_i0, get_q1, get_text
    procedure, private :: put_r1, put_r2, put_i1, put_r0, put_i0, put_q1, put_text
    procedure, private :: get_r1, get_r2, get_i1, get_r0, get_i0, get_q1, get_text
  end type ckpt_file_t

contains

  !> Start a new checkpoint (in memory); it becomes `path` only at commit.
  subroutine ck_create(self, path, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    self%path = path
    self%tmp = path // '.tmp'
    call self%f%create(self%tmp, 'checkpoint', stat, errmsg, in_memory=.true.)
  end subroutine ck_create

  !> Write the file's bytes to path.tmp, read them back, rename over path. On failure path.tmp
  !> is removed and path (the previous checkpoint) is untouched.
  subroutine ck_commit(self, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    character(kind=c_char, len=1), allocatable :: bytes(:)
    type(text_file_t) :: out
    integer :: st2
    character(len=:), allocatable :: msg2
    if (.not. self%f%is_open()) return
    call self%f%image(bytes, stat, errmsg)
    call self%f%close(stat, errmsg)
    if (stat /= STAT_OK) return
    call out%create(self%tmp, stat, errmsg)
    if (stat /= STAT_OK) return
    call out%write_bytes(bytes, stat, errmsg)
    call out%close_keep(stat, errmsg)
    if (stat == STAT_OK) call read_back(self%tmp, bytes, stat, errmsg)
    if (stat /= STAT_OK) then
      call remove_file(self%tmp, st2, msg2)
      return
    end if
    call os_rename(self%tmp, self%path, stat, errmsg)
  end subroutine ck_commit

  !> The file at path holds exactly bytes.
  subroutine read_back(path, bytes, stat, errmsg)
    character(len=*), intent(in) :: path
    character(kind=c_char, len=1), intent(in) :: bytes(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    character(kind=c_char, len=1), allocatable :: disk(:)
    integer :: u, ios
    integer(8) :: n
    character(len=256) :: msg
    open (newunit=u, file=path, status='old', access='stream', form='unformatted', action='read', &
      iostat=ios, iomsg=msg)
    if (ios /= 0) then
      call set_error(stat, errmsg, STAT_RUN, 'checkpoint ' // path // ': cannot read it back: ' // trim(msg))
      return
    end if
    inquire (unit=u, size=n)
    if (n == size(bytes, kind=8)) then
      allocate (disk(size(bytes)))
      read (u, iostat=ios, iomsg=msg) disk
    end if
    close (u)
    if (n /= size(bytes, kind=8) .or. ios /= 0) then
      call set_error(stat, errmsg, STAT_RUN, 'checkpoint ' // path // ': read back ' // str(int(n)) // ' bytes of ' // &
        str(size(bytes)))
    else if (any(disk /= bytes)) then
      call set_error(stat, errmsg, STAT_RUN, 'checkpoint ' // path // ': the bytes read back differ from those written')
    end if
  end subroutine read_back

  !> Open an existing checkpoint for reading.
  subroutine ck_open(self, path, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    self%path = path
    if (.not. path_exists(path)) then
      call set_error(stat, errmsg, STAT_INPUT, 'checkpoint ' // path // ': no such file')
      return
    end if
    call self%f%open_read(path, 'checkpoint', stat, errmsg)
    if (stat /= STAT_OK) call set_error(stat, errmsg, STAT_INPUT, 'checkpoint ' // path // ': not a readable HDF5 file')
  end subroutine ck_open

  subroutine ck_close(self)
    class(ckpt_file_t), intent(inout) :: self
    integer :: stat
    character(len=:), allocatable :: errmsg
    stat = STAT_OK
    call self%f%close(stat, errmsg)
  end subroutine ck_close

  ! ---- writing ------------------------------------------------------------------------------

  subroutine put_r1(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(dp), intent(in), contiguous :: x(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call self%f%write(name, x, stat, errmsg)
  end subroutine put_r1

  subroutine put_r2(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(dp), intent(in), contiguous :: x(:, :)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call self%f%write(name, reshape(x, [size(x)]), stat, errmsg)
  end subroutine put_r2

  subroutine put_i1(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(in), contiguous :: x(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call self%f%write(name, x, stat, errmsg)
  end subroutine put_i1

  subroutine put_r0(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: x
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call self%f%write(name, [x], stat, errmsg)
  end subroutine put_r0

  subroutine put_i0(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(in) :: x
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call self%f%write(name, [x], stat, errmsg)
  end subroutine put_i0

  !> Quadruple precision, bit for bit: each value as the two doubles of its 16 bytes.
  subroutine put_q1(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(qp), intent(in) :: x(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call self%f%write(name, transfer(x, [0.0_dp], 2 * size(x)), stat, errmsg)
  end subroutine put_q1

  !> Text of any length, as its character codes.
  subroutine put_text(self, name, text, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name, text
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer :: i
    call self%f%write(name, [(ichar(text(i:i)), i = 1, len(text))], stat, errmsg)
  end subroutine put_text

  ! ---- reading ------------------------------------------------------------------------------

  !> Text written by put_text (its length is the dataset's).
  subroutine get_text(self, name, text, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    character(len=:), allocatable, intent(out) :: text
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer, allocatable :: codes(:)
    integer :: ndims, n, i
    text = ''
    if (stat /= STAT_OK) return
    if (.not. self%f%exists(name, stat, errmsg)) then
      if (stat == STAT_OK) call set_error(stat, errmsg, STAT_INPUT, 'checkpoint ' // self%path // ': no dataset ' // &
        name // ' (a checkpoint of another version?)')
      return
    end if
    call self%f%extent(name, ndims, n, stat, errmsg)
    if (stat /= STAT_OK) return
    allocate (codes(max(n, 0)))
    call get_i1(self, name, codes, stat, errmsg)
    if (stat /= STAT_OK) return
    deallocate (text)
    allocate (character(len=size(codes)) :: text)
    do i = 1, size(codes)
      text(i:i) = achar(codes(i))
    end do
  end subroutine get_text

  !> Dataset `name` must exist and hold n values (rank 1).
  subroutine expect(self, name, n, stat, errmsg)
    type(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(in) :: n
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer :: ndims, m
    if (stat /= STAT_OK) return
    if (.not. self%f%exists(name, stat, errmsg)) then
      if (stat == STAT_OK) call set_error(stat, errmsg, STAT_INPUT, 'checkpoint ' // self%path // ': no dataset ' // &
        name // ' (a checkpoint of another version or scene?)')
      return
    end if
    call self%f%extent(name, ndims, m, stat, errmsg)
    if (stat == STAT_OK .and. (ndims /= 1 .or. m /= max(n, 0))) call set_error(stat, errmsg, STAT_INPUT, &
      'checkpoint ' // self%path // ': ' // name // ' has ' // str(max(m, 0)) // ' values where this scene needs ' // &
      str(n) // ' (not a checkpoint of this scene)')
  end subroutine expect

  subroutine get_r1(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(dp), intent(inout), contiguous :: x(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call expect(self, name, size(x), stat, errmsg)
    call self%f%read(name, x, stat, errmsg)
  end subroutine get_r1

  subroutine get_r2(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(dp), intent(inout), contiguous, target :: x(:, :)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    real(dp), pointer, contiguous :: flat(:)
    flat(1:size(x)) => x
    call get_r1(self, name, flat, stat, errmsg)
  end subroutine get_r2

  subroutine get_i1(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(inout), contiguous :: x(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call expect(self, name, size(x), stat, errmsg)
    call self%f%read(name, x, stat, errmsg)
  end subroutine get_i1

  subroutine get_r0(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(dp), intent(out) :: x
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    real(dp) :: b(1)
    b = 0.0_dp
    call get_r1(self, name, b, stat, errmsg)
    x = b(1)
  end subroutine get_r0

  subroutine get_i0(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(out) :: x
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer :: b(1)
    b = 0
    call get_i1(self, name, b, stat, errmsg)
    x = b(1)
  end subroutine get_i0

  subroutine get_q1(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(qp), intent(inout) :: x(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    real(dp), allocatable :: b(:)
    allocate (b(2 * size(x)))
    b = 0.0_dp
    call get_r1(self, name, b, stat, errmsg)
    if (stat == STAT_OK) x = transfer(b, x, size(x))
  end subroutine get_q1
end module checkpoint
