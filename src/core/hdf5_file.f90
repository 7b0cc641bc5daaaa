!> rebond's one HDF5 layer: an open file (h5_file_t) with typed writes and reads of datasets,
!> attributes and growing per-step series. Every HDF5 status is checked and translated here:
!> the first failure becomes STAT_RUN with "<what> <path>: cannot <operation>", later calls
!> with a failed stat do nothing (sticky stat), and HDF5's own error stack is never printed
!> (the user sees rebond's message only). The library is opened with the first file and
!> closed with the last. Used by fields_hdf5 (fields.h5), checkpoint (checkpoint.h5) and
!> sweep_output (sweep.h5). Do not copy an open h5_file_t: pass it by reference.
module hdf5_file
  use, intrinsic :: iso_c_binding, only: c_char, c_loc, c_null_char, c_ptr, c_null_ptr
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN
  use text_file, only: os_reason, clear_os_reason
  use os_utils, only: drop_symlink
  use hdf5, only: hid_t, hsize_t, size_t, h5open_f, h5close_f, h5eset_auto_f, &
    h5fcreate_f, h5fopen_f, h5fclose_f, h5fflush_f, H5F_ACC_TRUNC_F, H5F_ACC_RDONLY_F, H5F_SCOPE_GLOBAL_F, &
    H5F_ACC_RDWR_F, h5garbage_collect_f, &
    h5gcreate_f, h5gopen_f, h5gclose_f, h5lexists_f, h5oopen_f, h5oclose_f, &
    h5screate_simple_f, h5screate_f, h5sclose_f, h5sselect_hyperslab_f, h5sget_simple_extent_ndims_f, &
    h5sget_simple_extent_dims_f, H5S_SCALAR_F, H5S_UNLIMITED_F, H5S_SELECT_SET_F, &
    h5dcreate_f, h5dopen_f, h5dclose_f, h5dwrite_f, h5dread_f, h5dset_extent_f, h5dget_space_f, &
    h5acreate_f, h5awrite_f, h5aclose_f, h5tcopy_f, h5tset_size_f, h5tset_strpad_f, h5tclose_f, &
    h5pcreate_f, h5pclose_f, h5pset_chunk_f, h5pset_file_locking_f, h5pset_fapl_core_f, h5fget_file_image_f, &
    H5P_FILE_ACCESS_F, H5P_DATASET_CREATE_F, H5T_NATIVE_DOUBLE, H5T_NATIVE_INTEGER, H5T_NATIVE_CHARACTER, &
    H5T_STR_NULLPAD_F
  implicit none
  private
  public :: h5_file_t, hdf5_failed

  integer(hsize_t), parameter :: SERIES_CHUNK = 256   !< chunk length of the per-step series
  integer(size_t), parameter :: MEMORY_INCREMENT = 1048576   !< growth step of an in-memory file

  !> Files open now: the library is opened by the first, closed by the last.
  integer, save :: h5_users = 0
  !> An operation failed: HDF5 may hold a file it cannot close (the program must then end
  !> without HDF5's exit handler, os_utils exit_with now).
  logical, save :: any_failure = .false.

  type :: h5_file_t
    private
    integer(hid_t) :: fid = -1
    character(len=:), allocatable :: path, what
  contains
    procedure :: create => h5_create
    procedure :: open_read => h5_open_read
    procedure :: close => h5_close
    procedure :: reopen => h5_reopen
    procedure :: flush => h5_flush
    procedure :: image => h5_image
    procedure :: is_open => h5_is_open
    procedure :: exists => h5_exists
    procedure :: create_group => h5_create_group
    procedure :: extent => h5_extent
    procedure :: write_attr => h5_write_attr
    procedure :: create_series => h5_create_series
    procedure :: append_series => h5_append_series
    procedure :: write_text => h5_write_text
    generic :: write => write_r1, write_r2, write_i1
    generic :: read => read_r1, read_i1
    procedure, private :: write_r1 => h5_write_r1, write_r2 => h5_write_r2, write_i1 => h5_write_i1
    procedure, private :: read_r1 => h5_read_r1, read_i1 => h5_read_i1
  end type h5_file_t

contains

  !> The first failure (hdferr < 0) as STAT_RUN naming the file and the operation.
  subroutine check(self, hdferr, op, stat, errmsg)
    type(h5_file_t), intent(in) :: self
    integer, intent(in) :: hdferr
    character(len=*), intent(in) :: op
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    character(len=:), allocatable :: why
    if (hdferr >= 0) then
      call clear_os_reason()
    else if (stat == STAT_OK) then
      any_failure = .true.
      stat = STAT_RUN
      errmsg = self%what // ' ' // self%path // ': cannot ' // op
      ! HDF5 does not say why; errno does (No space left on device, File too large, ...).
      why = os_reason()
      if (len(why) > 0) errmsg = errmsg // ': ' // why
    end if
  end subroutine check

  !> True once any HDF5 operation failed in this process.
  logical function hdf5_failed()
    hdf5_failed = any_failure
  end function hdf5_failed

  !> Open the library (first user), with HDF5's automatic error printing off.
  subroutine use_library(self, stat, errmsg)
    type(h5_file_t), intent(in) :: self
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer :: hdferr
    if (h5_users == 0) then
      call h5open_f(hdferr)
      call check(self, hdferr, 'initialise the HDF5 library', stat, errmsg)
      if (stat /= STAT_OK) return
      call h5eset_auto_f(0, hdferr)
      call check(self, hdferr, 'silence the HDF5 error stack', stat, errmsg)
    end if
    h5_users = h5_users + 1
  end subroutine use_library

  subroutine release_library(self, stat, errmsg)
    type(h5_file_t), intent(in) :: self
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer :: hdferr
    h5_users = max(h5_users - 1, 0)
    if (h5_users > 0) return
    call h5close_f(hdferr)
    call check(self, hdferr, 'close the HDF5 library', stat, errmsg)
  end subroutine release_library

  !> A new file at path (an existing one is replaced); what names it in messages ("checkpoint",
  !> "field output", ...). unlocked: without HDF5 file locking (a viewer may read it meanwhile).
  !> in_memory: a file image in memory only (HDF5's core driver, nothing on disk; `image`
  !> gives its bytes), so that the caller writes it with checked writes of its own.
  subroutine h5_create(self, path, what, stat, errmsg, unlocked, in_memory)
    class(h5_file_t), intent(inout) :: self
    character(len=*), intent(in) :: path, what
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical, intent(in), optional :: unlocked, in_memory
    integer(hid_t) :: fapl
    integer :: hdferr
    stat = STAT_OK
    self%path = path
    self%what = what
    call drop_symlink(path, stat, errmsg)
    if (stat /= STAT_OK) return
    call use_library(self, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, hdferr)
    call check(self, hdferr, 'create file access properties', stat, errmsg)
    if (stat == STAT_OK .and. present(unlocked)) then
      if (unlocked) then
        call h5pset_file_locking_f(fapl, .false., .true., hdferr)
        call check(self, hdferr, 'disable file locking', stat, errmsg)
      end if
    end if
    if (stat == STAT_OK .and. present(in_memory)) then
      if (in_memory) then
        call h5pset_fapl_core_f(fapl, MEMORY_INCREMENT, .false., hdferr)
        call check(self, hdferr, 'select the in-memory driver', stat, errmsg)
      end if
    end if
    if (stat == STAT_OK) then
      call h5fcreate_f(path, H5F_ACC_TRUNC_F, self%fid, hdferr, access_prp=fapl)
      call check(self, hdferr, 'create the file', stat, errmsg)
      if (hdferr < 0) self%fid = -1
      call h5pclose_f(fapl, hdferr)
    end if
    if (self%fid < 0) call release_library(self, stat, errmsg)
  end subroutine h5_create

  !> An existing file, read only; stat /= STAT_OK when it is not a readable HDF5 file.
  subroutine h5_open_read(self, path, what, stat, errmsg)
    class(h5_file_t), intent(inout) :: self
    character(len=*), intent(in) :: path, what
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: hdferr
    stat = STAT_OK
    self%path = path
    self%what = what
    call use_library(self, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5fopen_f(path, H5F_ACC_RDONLY_F, self%fid, hdferr)
    call check(self, hdferr, 'open the file (not a readable HDF5 file?)', stat, errmsg)
    if (hdferr < 0) then
      self%fid = -1
      call release_library(self, stat, errmsg)
    end if
  end subroutine h5_open_read

  !> Close the file (sticky stat: a close that fails after an earlier failure keeps the first
  !> message). Closing a file that is not open does nothing.
  subroutine h5_close(self, stat, errmsg)
    class(h5_file_t), intent(inout) :: self
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer :: hdferr
    if (self%fid < 0) return
    call h5fclose_f(self%fid, hdferr)
    call check(self, hdferr, 'close the file', stat, errmsg)
    self%fid = -1
    call release_library(self, stat, errmsg)
  end subroutine h5_close

  !> The file (written by create, unlocked) closed and opened again for writing: HDF5 lets go of
  !> the object headers its metadata cache and free lists hold for every object made since
  !> (fields.h5: ~0.65 kB a written step without it, docs/reliability.md).
  subroutine h5_reopen(self, stat, errmsg)
    class(h5_file_t), intent(inout) :: self
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer(hid_t) :: fapl
    integer :: hdferr
    if (stat /= STAT_OK .or. self%fid < 0) return
    call h5fclose_f(self%fid, hdferr)
    call check(self, hdferr, 'close the file', stat, errmsg)
    self%fid = -1
    if (stat /= STAT_OK) return
    call h5garbage_collect_f(hdferr)
    call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, hdferr)
    call check(self, hdferr, 'create file access properties', stat, errmsg)
    if (stat /= STAT_OK) return
    call h5pset_file_locking_f(fapl, .false., .true., hdferr)
    call check(self, hdferr, 'disable file locking', stat, errmsg)
    if (stat == STAT_OK) then
      call h5fopen_f(self%path, H5F_ACC_RDWR_F, self%fid, hdferr, access_prp=fapl)
      call check(self, hdferr, 'open the file again', stat, errmsg)
      if (hdferr < 0) self%fid = -1
    end if
    call h5pclose_f(fapl, hdferr)
  end subroutine h5_reopen

  !> Everything written so far to the disk.
  subroutine h5_flush(self, stat, errmsg)
    class(h5_file_t), intent(inout) :: self
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer :: hdferr
    if (stat /= STAT_OK) return
    call h5fflush_f(self%fid, H5F_SCOPE_GLOBAL_F, hdferr)
    call check(self, hdferr, 'flush the file', stat, errmsg)
  end subroutine h5_flush

  !> The bytes of the whole file as it stands (an in-memory file: what would be on disk).
  subroutine h5_image(self, bytes, stat, errmsg)
    class(h5_file_t), intent(inout) :: self
    character(kind=c_char, len=1), allocatable, target, intent(out) :: bytes(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer(size_t) :: n
    integer :: hdferr
    type(c_ptr) :: p
    if (stat /= STAT_OK) return
    call h5fflush_f(self%fid, H5F_SCOPE_GLOBAL_F, hdferr)
    call check(self, hdferr, 'flush the file', stat, errmsg)
    if (stat /= STAT_OK) return
    p = c_null_ptr
    call h5fget_file_image_f(self%fid, p, 0_size_t, hdferr, n)
    call check(self, hdferr, 'size the file image', stat, errmsg)
    if (stat /= STAT_OK) return
    allocate (bytes(n))
    p = c_loc(bytes)
    call h5fget_file_image_f(self%fid, p, n, hdferr)
    call check(self, hdferr, 'copy the file image', stat, errmsg)
  end subroutine h5_image

  pure logical function h5_is_open(self)
    class(h5_file_t), intent(in) :: self
    h5_is_open = self%fid >= 0
  end function h5_is_open

  !> Does the link name (a group or a dataset, a path from the root) exist?
  logical function h5_exists(self, name, stat, errmsg) result(exists)
    class(h5_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer :: hdferr
    exists = .false.
    if (stat /= STAT_OK) return
    call h5lexists_f(self%fid, name, exists, hdferr)
    call check(self, hdferr, 'look up ' // name, stat, errmsg)
  end function h5_exists

  subroutine h5_create_group(self, name, stat, errmsg)
    class(h5_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer(hid_t) :: gid
    integer :: hdferr
    if (stat /= STAT_OK) return
    call h5gcreate_f(self%fid, name, gid, hdferr)
    call check(self, hdferr, 'create group /' // name, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5gclose_f(gid, hdferr)
    call check(self, hdferr, 'close group /' // name, stat, errmsg)
  end subroutine h5_create_group

  !> A new dataset name (a path from the root; its groups exist) of type mtype and shape dims
  !> from buf (c_loc of the caller's contiguous data).
  subroutine put(self, name, mtype, dims, buf, stat, errmsg)
    type(h5_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer(hid_t), intent(in) :: mtype
    integer(hsize_t), intent(in) :: dims(:)
    type(c_ptr), intent(in) :: buf
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer(hid_t) :: space, dset
    integer :: hdferr
    if (stat /= STAT_OK) return
    call h5screate_simple_f(size(dims), dims, space, hdferr)
    call check(self, hdferr, 'create the dataspace of ' // name, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5dcreate_f(self%fid, name, mtype, space, dset, hdferr)
    call check(self, hdferr, 'create dataset ' // name, stat, errmsg)
    if (stat == STAT_OK) then
      if (product(dims) > 0) then
        call h5dwrite_f(dset, mtype, buf, hdferr)
        call check(self, hdferr, 'write dataset ' // name, stat, errmsg)
      end if
      call h5dclose_f(dset, hdferr)
      call check(self, hdferr, 'close dataset ' // name, stat, errmsg)
    end if
    call h5sclose_f(space, hdferr)
    call check(self, hdferr, 'close the dataspace of ' // name, stat, errmsg)
  end subroutine put

  subroutine h5_write_r1(self, name, a, stat, errmsg)
    class(h5_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(dp), intent(in), contiguous, target :: a(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call put(self, name, H5T_NATIVE_DOUBLE, [size(a, kind=hsize_t)], c_loc(a), stat, errmsg)
  end subroutine h5_write_r1

  subroutine h5_write_r2(self, name, a, stat, errmsg)
    class(h5_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(dp), intent(in), contiguous, target :: a(:, :)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call put(self, name, H5T_NATIVE_DOUBLE, shape(a, kind=hsize_t), c_loc(a), stat, errmsg)
  end subroutine h5_write_r2

  subroutine h5_write_i1(self, name, a, stat, errmsg)
    class(h5_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(in), contiguous, target :: a(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call put(self, name, H5T_NATIVE_INTEGER, [size(a, kind=hsize_t)], c_loc(a), stat, errmsg)
  end subroutine h5_write_i1

  !> Fixed-length strings as wide as the longest (trailing blanks trimmed), NUL-padded: h5py
  !> reads them back without the padding.
  subroutine h5_write_text(self, name, texts, stat, errmsg)
    class(h5_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    character(len=*), intent(in) :: texts(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer(hid_t) :: stype
    character(kind=c_char, len=1), allocatable, target :: buf(:)
    integer :: w, i, c, hdferr
    if (stat /= STAT_OK) return
    w = 1
    do i = 1, size(texts)
      w = max(w, len_trim(texts(i)))
    end do
    allocate (buf(w * size(texts)))
    buf = c_null_char
    do i = 1, size(texts)
      do c = 1, len_trim(texts(i))
        buf((i - 1) * w + c) = texts(i)(c:c)
      end do
    end do
    call h5tcopy_f(H5T_NATIVE_CHARACTER, stype, hdferr)
    call check(self, hdferr, 'make the string type of ' // name, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5tset_size_f(stype, int(w, size_t), hdferr)
    call check(self, hdferr, 'size the string type of ' // name, stat, errmsg)
    call h5tset_strpad_f(stype, H5T_STR_NULLPAD_F, hdferr)
    call check(self, hdferr, 'pad the string type of ' // name, stat, errmsg)
    call put(self, name, stype, [size(texts, kind=hsize_t)], c_loc(buf), stat, errmsg)
    call h5tclose_f(stype, hdferr)
    call check(self, hdferr, 'close the string type of ' // name, stat, errmsg)
  end subroutine h5_write_text

  !> A scalar attribute of the group or dataset obj: float64 (x), int32 (i) or a string (text).
  subroutine h5_write_attr(self, obj, name, stat, errmsg, x, i, text)
    class(h5_file_t), intent(inout) :: self
    character(len=*), intent(in) :: obj, name
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    real(dp), intent(in), optional :: x
    integer, intent(in), optional :: i
    character(len=*), intent(in), optional :: text
    integer(hid_t) :: space, attr, mtype, oid
    integer(hsize_t), parameter :: dims(1) = [1_hsize_t]
    integer :: hdferr
    if (stat /= STAT_OK) return
    mtype = H5T_NATIVE_INTEGER
    if (present(x)) mtype = H5T_NATIVE_DOUBLE
    if (present(text)) then
      call h5tcopy_f(H5T_NATIVE_CHARACTER, mtype, hdferr)
      call check(self, hdferr, 'make the string type of /' // obj // '@' // name, stat, errmsg)
      if (stat /= STAT_OK) return
      call h5tset_size_f(mtype, int(max(len(text), 1), size_t), hdferr)
      call check(self, hdferr, 'size the string type of /' // obj // '@' // name, stat, errmsg)
    end if
    call h5oopen_f(self%fid, obj, oid, hdferr)
    call check(self, hdferr, 'open /' // obj, stat, errmsg)
    if (stat == STAT_OK) then
      call h5screate_f(H5S_SCALAR_F, space, hdferr)
      call check(self, hdferr, 'create the dataspace of attribute /' // obj // '@' // name, stat, errmsg)
      if (stat == STAT_OK) then
        call h5acreate_f(oid, name, mtype, space, attr, hdferr)
        call check(self, hdferr, 'create attribute /' // obj // '@' // name, stat, errmsg)
        if (stat == STAT_OK) then
          if (present(x)) then
            call h5awrite_f(attr, mtype, x, dims, hdferr)
          else if (present(i)) then
            call h5awrite_f(attr, mtype, i, dims, hdferr)
          else if (present(text)) then
            call h5awrite_f(attr, mtype, text, dims, hdferr)
          end if
          call check(self, hdferr, 'write attribute /' // obj // '@' // name, stat, errmsg)
          call h5aclose_f(attr, hdferr)
          call check(self, hdferr, 'close attribute /' // obj // '@' // name, stat, errmsg)
        end if
        call h5sclose_f(space, hdferr)
      end if
      call h5oclose_f(oid, hdferr)
      call check(self, hdferr, 'close /' // obj, stat, errmsg)
    end if
    if (present(text)) call h5tclose_f(mtype, hdferr)
  end subroutine h5_write_attr

  !> An empty, extendable 1-D dataset (float64, or int32 with integers) for a per-step series.
  subroutine h5_create_series(self, name, integers, stat, errmsg)
    class(h5_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    logical, intent(in) :: integers
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer(hid_t) :: space, dcpl, dset, mtype
    integer :: hdferr
    if (stat /= STAT_OK) return
    mtype = merge(H5T_NATIVE_INTEGER, H5T_NATIVE_DOUBLE, integers)
    call h5screate_simple_f(1, [0_hsize_t], space, hdferr, maxdims=[H5S_UNLIMITED_F])
    call check(self, hdferr, 'create the dataspace of /' // name, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5pcreate_f(H5P_DATASET_CREATE_F, dcpl, hdferr)
    call check(self, hdferr, 'create the creation properties of /' // name, stat, errmsg)
    if (stat == STAT_OK) then
      ! An unlimited dimension requires chunked storage.
      call h5pset_chunk_f(dcpl, 1, [SERIES_CHUNK], hdferr)
      call check(self, hdferr, 'set the chunk size of /' // name, stat, errmsg)
      if (stat == STAT_OK) then
        call h5dcreate_f(self%fid, name, mtype, space, dset, hdferr, dcpl_id=dcpl)
        call check(self, hdferr, 'create dataset /' // name, stat, errmsg)
        if (stat == STAT_OK) then
          call h5dclose_f(dset, hdferr)
          call check(self, hdferr, 'close dataset /' // name, stat, errmsg)
        end if
      end if
      call h5pclose_f(dcpl, hdferr)
    end if
    call h5sclose_f(space, hdferr)
    call check(self, hdferr, 'close the dataspace of /' // name, stat, errmsg)
  end subroutine h5_create_series

  !> Grow the series name to length n and store x (float64) or i (int32) at n.
  subroutine h5_append_series(self, name, n, stat, errmsg, x, i)
    class(h5_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(in) :: n
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    real(dp), intent(in), optional :: x
    integer, intent(in), optional :: i
    integer(hid_t) :: dset, fspace, mspace
    integer(hsize_t), parameter :: one(1) = [1_hsize_t]
    integer :: hdferr
    if (stat /= STAT_OK) return
    call h5dopen_f(self%fid, name, dset, hdferr)
    call check(self, hdferr, 'open dataset /' // name, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5dset_extent_f(dset, [int(n, hsize_t)], hdferr)
    call check(self, hdferr, 'extend dataset /' // name, stat, errmsg)
    if (stat == STAT_OK) then
      call h5dget_space_f(dset, fspace, hdferr)
      call check(self, hdferr, 'get the dataspace of /' // name, stat, errmsg)
      if (stat == STAT_OK) then
        call h5sselect_hyperslab_f(fspace, H5S_SELECT_SET_F, [int(n - 1, hsize_t)], one, hdferr)
        call check(self, hdferr, 'select the last entry of /' // name, stat, errmsg)
        call h5screate_simple_f(1, one, mspace, hdferr)
        call check(self, hdferr, 'create a memory dataspace for /' // name, stat, errmsg)
        if (stat == STAT_OK) then
          if (present(x)) then
            call h5dwrite_f(dset, H5T_NATIVE_DOUBLE, [x], one, hdferr, mem_space_id=mspace, file_space_id=fspace)
          else if (present(i)) then
            call h5dwrite_f(dset, H5T_NATIVE_INTEGER, [i], one, hdferr, mem_space_id=mspace, file_space_id=fspace)
          end if
          call check(self, hdferr, 'append to dataset /' // name, stat, errmsg)
          call h5sclose_f(mspace, hdferr)
        end if
        call h5sclose_f(fspace, hdferr)
      end if
    end if
    call h5dclose_f(dset, hdferr)
    call check(self, hdferr, 'close dataset /' // name, stat, errmsg)
  end subroutine h5_append_series

  !> Rank and length of the dataset name (rank 1 only: n = its length; other ranks: n = -1).
  subroutine h5_extent(self, name, ndims, n, stat, errmsg)
    class(h5_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(out) :: ndims, n
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer(hid_t) :: dset, space
    integer(hsize_t) :: dims(1), maxdims(1)
    integer :: hdferr
    ndims = 0
    n = -1
    if (stat /= STAT_OK) return
    call h5dopen_f(self%fid, name, dset, hdferr)
    call check(self, hdferr, 'open ' // name, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5dget_space_f(dset, space, hdferr)
    call check(self, hdferr, 'get the dataspace of ' // name, stat, errmsg)
    if (stat == STAT_OK) then
      call h5sget_simple_extent_ndims_f(space, ndims, hdferr)
      call check(self, hdferr, 'get the rank of ' // name, stat, errmsg)
      if (stat == STAT_OK .and. ndims == 1) then
        call h5sget_simple_extent_dims_f(space, dims, maxdims, hdferr)
        call check(self, hdferr, 'get the size of ' // name, stat, errmsg)
        n = int(dims(1))
      end if
      call h5sclose_f(space, hdferr)
    end if
    call h5dclose_f(dset, hdferr)
  end subroutine h5_extent

  !> Read the 1-D dataset name into buf (its length is the caller's to check, h5_extent).
  subroutine get(self, name, mtype, buf, n, stat, errmsg)
    type(h5_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer(hid_t), intent(in) :: mtype
    type(c_ptr), intent(in) :: buf
    integer, intent(in) :: n
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer(hid_t) :: dset
    integer :: hdferr
    type(c_ptr) :: p
    if (stat /= STAT_OK .or. n <= 0) return
    p = buf
    call h5dopen_f(self%fid, name, dset, hdferr)
    call check(self, hdferr, 'open ' // name, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5dread_f(dset, mtype, p, hdferr)
    call check(self, hdferr, 'read ' // name, stat, errmsg)
    call h5dclose_f(dset, hdferr)
  end subroutine get

  subroutine h5_read_r1(self, name, a, stat, errmsg)
    class(h5_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    real(dp), intent(inout), contiguous, target :: a(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call get(self, name, H5T_NATIVE_DOUBLE, c_loc(a), size(a), stat, errmsg)
  end subroutine h5_read_r1

  subroutine h5_read_i1(self, name, a, stat, errmsg)
    class(h5_file_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(inout), contiguous, target :: a(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call get(self, name, H5T_NATIVE_INTEGER, c_loc(a), size(a), stat, errmsg)
  end subroutine h5_read_i1
end module hdf5_file
