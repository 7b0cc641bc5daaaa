!> Checkpoint files: the whole state of a run in one HDF5 file, written atomically (a new file
!> under a temporary name, flushed and closed, then renamed over the old one) so that a run
!> killed at any moment leaves either the previous checkpoint or the new one, never half of
!> one. The driver decides what goes in (src/newmark.f90, save_checkpoint); this module only
!> stores named arrays and scalars, and on reading checks every shape.
!> Quadruple-precision arrays are stored bit for bit as pairs of doubles (transfer), so that
!> a restart continues exactly where the run stopped.
module checkpoint
  use, intrinsic :: iso_c_binding, only: c_loc
  use kinds, only: dp, qp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str
  use os_utils, only: os_rename, remove_file, path_exists
  use hdf5, only: hid_t, hsize_t, h5open_f, h5fcreate_f, h5fopen_f, h5fclose_f, h5fflush_f, &
    H5F_ACC_TRUNC_F, H5F_ACC_RDONLY_F, H5F_SCOPE_GLOBAL_F, h5screate_simple_f, h5sclose_f, &
    h5dcreate_f, h5dopen_f, h5dclose_f, h5dwrite_f, h5dread_f, h5dget_space_f, &
    h5sget_simple_extent_ndims_f, h5sget_simple_extent_dims_f, H5T_NATIVE_DOUBLE, H5T_NATIVE_INTEGER, &
    h5lexists_f
  implicit none
  private
  public :: ckpt_file_t

  !> An open checkpoint, for writing (create) or reading (open).
  type :: ckpt_file_t
    integer(hid_t) :: fid = -1
    character(len=:), allocatable :: path, tmp
    logical :: writing = .false.
  contains
    procedure :: create => ck_create
    procedure :: commit => ck_commit
    procedure :: open => ck_open
    procedure :: close => ck_close
    generic :: put => put_r1, put_r2, put_i1, put_r0, put_i0, put_q1
    generic :: get => get_r1, get_r2, get_i1, get_r0, get_i0, get_q1
    procedure, private :: put_r1, put_r2, put_i1, put_r0, put_i0, put_q1
    procedure, private :: get_r1, get_r2, get_i1, get_r0, get_i0, get_q1
  end type ckpt_file_t

contains

  subroutine h5check(hdferr, what, path, stat, errmsg)
    integer, intent(in) :: hdferr
    character(len=*), intent(in) :: what, path
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    if (stat /= STAT_OK) return
    if (hdferr < 0) call set_error(stat, errmsg, STAT_RUN, 'checkpoint ' // path // ': cannot ' // what)
  end subroutine h5check

  !> Start a new checkpoint; it becomes `path` only at commit.
  subroutine ck_create(self, path, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: hdferr
    stat = STAT_OK
    self%path = path
    self%tmp = path // '.tmp'
    self%writing = .true.
    call h5open_f(hdferr)
    call h5check(hdferr, 'initialise HDF5', path, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5fcreate_f(self%tmp, H5F_ACC_TRUNC_F, self%fid, hdferr)
    call h5check(hdferr, 'create ' // self%tmp, path, stat, errmsg)
  end subroutine ck_create

  !> Flush, close and rename the new checkpoint over the old one.
  subroutine ck_commit(self, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer :: hdferr
    if (self%fid < 0) return
    if (stat == STAT_OK) then
      call h5fflush_f(self%fid, H5F_SCOPE_GLOBAL_F, hdferr)
      call h5check(hdferr, 'flush', self%tmp, stat, errmsg)
    end if
    call h5fclose_f(self%fid, hdferr)
    self%fid = -1
    call h5check(hdferr, 'close', self%tmp, stat, errmsg)
    if (stat /= STAT_OK) return
    call os_rename(self%tmp, self%path, stat, errmsg)
  end subroutine ck_commit

  !> Open an existing checkpoint for reading.
  subroutine ck_open(self, path, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: hdferr
    stat = STAT_OK
    self%path = path
    self%writing = .false.
    if (.not. path_exists(path)) then
      call set_error(stat, errmsg, STAT_INPUT, 'checkpoint ' // path // ': no such file')
      return
    end if
    call h5open_f(hdferr)
    call h5fopen_f(path, H5F_ACC_RDONLY_F, self%fid, hdferr)
    if (hdferr < 0) then
      self%fid = -1
      call set_error(stat, errmsg, STAT_INPUT, 'checkpoint ' // path // ': not a readable HDF5 file')
    end if
  end subroutine ck_open

  subroutine ck_close(self)
    class(ckpt_file_t), intent(inout) :: self
    integer :: hdferr
    if (self%fid >= 0) call h5fclose_f(self%fid, hdferr)
    self%fid = -1
  end subroutine ck_close

  ! ---- writing ------------------------------------------------------------------------------

  subroutine put_dset(self, name, rank, dims, mtype, ptr_r, ptr_i, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(in) :: rank
    integer(hsize_t), intent(in) :: dims(:)
    integer(hid_t), intent(in) :: mtype
    real(dp), intent(in), optional, target :: ptr_r(*)
    integer, intent(in), optional, target :: ptr_i(*)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer(hid_t) :: space, dset
    integer :: hdferr
    integer(hsize_t) :: d(max(rank, 1))
    if (stat /= STAT_OK) return
    d = 1
    if (rank > 0) d(1:rank) = dims(1:rank)
    call h5screate_simple_f(max(rank, 1), d, space, hdferr)
    call h5check(hdferr, 'create the dataspace of ' // name, self%path, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5dcreate_f(self%fid, name, mtype, space, dset, hdferr)
    call h5check(hdferr, 'create ' // name, self%path, stat, errmsg)
    if (stat == STAT_OK) then
      if (present(ptr_r)) call h5dwrite_f(dset, mtype, c_loc(ptr_r), hdferr)
      if (present(ptr_i)) call h5dwrite_f(dset, mtype, c_loc(ptr_i), hdferr)
      call h5check(hdferr, 'write ' // name, self%path, stat, errmsg)
      call h5dclose_f(dset, hdferr)
    end if
    call h5sclose_f(space, hdferr)
  end subroutine put_dset

  subroutine put_r1(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(dp), intent(in), target, contiguous :: x(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    real(dp), target :: dummy(1)
    if (size(x) == 0) then
      call put_dset(self, name, 1, [0_hsize_t], H5T_NATIVE_DOUBLE, ptr_r=dummy, stat=stat, errmsg=errmsg)
    else
      call put_dset(self, name, 1, [size(x, kind=hsize_t)], H5T_NATIVE_DOUBLE, ptr_r=x, stat=stat, errmsg=errmsg)
    end if
  end subroutine put_r1

  subroutine put_r2(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(dp), intent(in), target, contiguous :: x(:, :)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call put_r1(self, name, reshape(x, [size(x)]), stat, errmsg)
  end subroutine put_r2

  subroutine put_i1(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(in), target, contiguous :: x(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer, target :: dummy(1)
    if (size(x) == 0) then
      call put_dset(self, name, 1, [0_hsize_t], H5T_NATIVE_INTEGER, ptr_i=dummy, stat=stat, errmsg=errmsg)
    else
      call put_dset(self, name, 1, [size(x, kind=hsize_t)], H5T_NATIVE_INTEGER, ptr_i=x, stat=stat, errmsg=errmsg)
    end if
  end subroutine put_i1

  subroutine put_r0(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: x
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call put_r1(self, name, [x], stat, errmsg)
  end subroutine put_r0

  subroutine put_i0(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(in) :: x
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call put_i1(self, name, [x], stat, errmsg)
  end subroutine put_i0

  !> Quadruple precision, bit for bit: each value as the two doubles of its 16 bytes.
  subroutine put_q1(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(qp), intent(in) :: x(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call put_r1(self, name, transfer(x, [0.0_dp], 2 * size(x)), stat, errmsg)
  end subroutine put_q1

  ! ---- reading ------------------------------------------------------------------------------

  !> Read dataset `name` of n values into buf, refusing another size.
  subroutine get_dset(self, name, n, mtype, stat, errmsg, buf_r, buf_i)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(in) :: n
    integer(hid_t), intent(in) :: mtype
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    real(dp), intent(out), optional, target :: buf_r(*)
    integer, intent(out), optional, target :: buf_i(*)
    integer(hid_t) :: dset, space
    integer(hsize_t) :: dims(1), maxdims(1)
    integer :: hdferr, ndims
    logical :: exists
    if (stat /= STAT_OK) return
    call h5lexists_f(self%fid, name, exists, hdferr)
    if (hdferr < 0 .or. .not. exists) then
      call set_error(stat, errmsg, STAT_INPUT, 'checkpoint ' // self%path // ': no dataset ' // name // &
        ' (a checkpoint of another version or scene?)')
      return
    end if
    call h5dopen_f(self%fid, name, dset, hdferr)
    call h5check(hdferr, 'open ' // name, self%path, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5dget_space_f(dset, space, hdferr)
    call h5sget_simple_extent_ndims_f(space, ndims, hdferr)
    dims = 0
    if (ndims == 1) call h5sget_simple_extent_dims_f(space, dims, maxdims, hdferr)
    call h5sclose_f(space, hdferr)
    if (ndims /= 1 .or. dims(1) /= int(max(n, 0), hsize_t)) then
      call set_error(stat, errmsg, STAT_INPUT, 'checkpoint ' // self%path // ': ' // name // ' has ' // &
        str(int(dims(1))) // ' values where this scene needs ' // str(n) // ' (not a checkpoint of this scene)')
    else if (n > 0) then
      if (present(buf_r)) call h5dread_f(dset, mtype, buf_r(1:n), dims, hdferr)
      if (present(buf_i)) call h5dread_f(dset, mtype, buf_i(1:n), dims, hdferr)
      call h5check(hdferr, 'read ' // name, self%path, stat, errmsg)
    end if
    call h5dclose_f(dset, hdferr)
  end subroutine get_dset

  subroutine get_r1(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(dp), intent(out), target, contiguous :: x(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call get_dset(self, name, size(x), H5T_NATIVE_DOUBLE, stat, errmsg, buf_r=x)
  end subroutine get_r1

  subroutine get_r2(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(dp), intent(out), target, contiguous :: x(:, :)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call get_dset(self, name, size(x), H5T_NATIVE_DOUBLE, stat, errmsg, buf_r=x)
  end subroutine get_r2

  subroutine get_i1(self, name, x, stat, errmsg)
    class(ckpt_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(out), target, contiguous :: x(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call get_dset(self, name, size(x), H5T_NATIVE_INTEGER, stat, errmsg, buf_i=x)
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
    real(qp), intent(out) :: x(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    real(dp), allocatable :: b(:)
    allocate (b(2 * size(x)))
    call get_r1(self, name, b, stat, errmsg)
    if (stat == STAT_OK) x = transfer(b, x, size(x))
  end subroutine get_q1
end module checkpoint
