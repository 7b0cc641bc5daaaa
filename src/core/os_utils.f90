!> Thin wrappers over the few POSIX file-system calls Fortran 2008 lacks (rename, mkdir, access,
!> opendir, remove), through iso_c_binding. Paths are passed to C as NUL-terminated copies.
module os_utils
  use, intrinsic :: iso_c_binding, only: c_char, c_int, c_ptr, c_null_char, c_associated
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, set_error
  use c_interfaces, only: c_rename, c_mkdir, c_access, c_opendir, c_closedir, c_rmdir, c_install_signals, &
    c_signal_received, c_exit, c_remove, c_exit_now, rb_room, rb_unlink_symlink
  implicit none
  private
  public :: os_rename, make_directory, path_exists, is_directory, remove_file, remove_directory
  public :: install_signal_handlers, signal_received, path_stem, exit_with, room_for, drop_symlink


  integer(c_int), parameter :: F_OK = 0_c_int
  integer(c_int), parameter :: MODE_0755 = int(o'755', c_int)

contains

  !> NUL-terminated copy of a Fortran string (trailing blanks kept: they are part of the name).
  pure function cstr(s) result(c)
    character(len=*), intent(in) :: s
    character(kind=c_char, len=len(s) + 1) :: c
    c = s // c_null_char
  end function cstr

  !> Rename (atomically, on one file system) from -> to, replacing `to` if it exists.
  subroutine os_rename(from, to, stat, errmsg)
    character(len=*), intent(in) :: from, to
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (c_rename(cstr(from), cstr(to)) /= 0) then
      call set_error(stat, errmsg, STAT_RUN, 'cannot rename "' // from // '" to "' // to // '"')
    end if
  end subroutine os_rename

  !> True when something (file or directory) exists at path.
  logical function path_exists(path)
    character(len=*), intent(in) :: path
    path_exists = c_access(cstr(path), F_OK) == 0
  end function path_exists

  !> True when path is a directory that can be opened.
  logical function is_directory(path)
    character(len=*), intent(in) :: path
    type(c_ptr) :: dir
    integer(c_int) :: rc
    dir = c_opendir(cstr(path))
    is_directory = c_associated(dir)
    if (is_directory) rc = c_closedir(dir)
  end function is_directory

  !> Create directory path and its missing parents (like mkdir -p); an existing directory is fine.
  subroutine make_directory(path, stat, errmsg)
    character(len=*), intent(in) :: path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: i, n
    integer(c_int) :: rc
    stat = STAT_OK
    n = len_trim(path)
    if (n == 0) then
      call set_error(stat, errmsg, STAT_RUN, 'cannot create a directory with an empty name')
      return
    end if
    ! Each prefix ending before a '/' is a parent; the leading '/' of an absolute path is skipped.
    do i = 2, n
      if (path(i:i) == '/' .and. path(i - 1:i - 1) /= '/') then
        if (.not. is_directory(path(1:i - 1))) rc = c_mkdir(cstr(path(1:i - 1)), MODE_0755)
      end if
    end do
    if (.not. is_directory(path(1:n))) rc = c_mkdir(cstr(path(1:n)), MODE_0755)
    ! Judge by the result, not by rc: another process may have created it meanwhile.
    if (.not. is_directory(path(1:n))) then
      if (path_exists(path(1:n))) then
        call set_error(stat, errmsg, STAT_RUN, 'cannot create directory "' // path(1:n) // &
                       '": a file of that name exists')
      else
        call set_error(stat, errmsg, STAT_RUN, 'cannot create directory "' // path(1:n) // '"')
      end if
    end if
  end subroutine make_directory

  !> Delete a file; a missing file is not an error.
  subroutine remove_file(path, stat, errmsg)
    character(len=*), intent(in) :: path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (.not. path_exists(path)) return
    if (c_remove(cstr(path)) /= 0) then
      call set_error(stat, errmsg, STAT_RUN, 'cannot remove "' // path // '"')
    end if
  end subroutine remove_file

  !> Delete an empty directory; a missing one is not an error.
  subroutine remove_directory(path, stat, errmsg)
    character(len=*), intent(in) :: path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (.not. path_exists(path)) return
    if (c_rmdir(cstr(path)) /= 0) then
      call set_error(stat, errmsg, STAT_RUN, 'cannot remove directory "' // path // '" (not empty?)')
    end if
  end subroutine remove_directory
  !> SIGINT and SIGTERM raise a flag instead of killing the process (see signal_received).
  subroutine install_signal_handlers(stat, errmsg)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (c_install_signals() /= 0) call set_error(stat, errmsg, STAT_RUN, 'cannot install the SIGINT/SIGTERM handlers')
  end subroutine install_signal_handlers

  !> The signal received since install_signal_handlers (0: none).
  integer function signal_received()
    signal_received = int(c_signal_received())
  end function signal_received
  !> File name without directory and extension: results/<stem>/ is the default output folder.
  pure function path_stem(path) result(b)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: b
    integer :: k
    b = path(index(path, '/', back=.true.) + 1:)
    k = index(b, '.', back=.true.)
    if (k > 1) b = b(1:k - 1)
  end function path_stem
  !> End the program with a status and no "STOP n" line (top of the program only). now: skip
  !> the libraries' exit handlers (after an HDF5 failure, see os_shim.c).
  subroutine exit_with(status, now)
    integer, intent(in) :: status
    logical, intent(in), optional :: now
    integer :: ios
    flush (6, iostat=ios)                        ! (a failure here is said by the caller, check_stdout)
    flush (0, iostat=ios)
    if (present(now)) then
      if (now) call c_exit_now(int(status, c_int))
    end if
    call c_exit(int(status, c_int))
  end subroutine exit_with

  !> A result file is never written through a symbolic link planted at its path: the link is
  !> removed (its target untouched) and the file created in its place.
  subroutine drop_symlink(path, stat, errmsg)
    character(len=*), intent(in) :: path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (rb_unlink_symlink(cstr(path)) /= 0) call set_error(stat, errmsg, STAT_RUN, 'cannot replace the symbolic link "' &
      // path // '"')
  end subroutine drop_symlink

  !> Bytes that can still be added to the file at path: the space left on its file system,
  !> capped by the file size limit (ulimit -f); -1 when unknown.
  real(dp) function room_for(path)
    character(len=*), intent(in) :: path
    integer :: k
    k = index(path, '/', back=.true.)
    if (k == 0) then
      room_for = real(rb_room(cstr(path), cstr('.')), dp)
    else
      room_for = real(rb_room(cstr(path), cstr(path(1:max(k - 1, 1)))), dp)
    end if
  end function room_for
end module os_utils
