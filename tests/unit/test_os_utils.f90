!> os_utils: directory creation (with parents), existence tests, rename, removal.
program test_os_utils
  use errors, only: STAT_OK
  use testing, only: check, test_summary
  use os_utils, only: os_rename, make_directory, path_exists, is_directory, remove_file, remove_directory
  implicit none
  character(len=:), allocatable :: root, errmsg
  character(len=32) :: buf
  integer :: stat, cnt, u

  call system_clock(cnt)
  write (buf, '(i0)') cnt
  root = '/tmp/rebond_test_os_utils_' // trim(buf)
  call check(.not. path_exists(root), 'fresh scratch name does not exist')

  call make_directory(root // '/a/b/', stat, errmsg)
  call check(stat == STAT_OK .and. is_directory(root // '/a/b'), 'make_directory creates parents')
  call make_directory(root // '/a/b', stat, errmsg)
  call check(stat == STAT_OK, 'make_directory on an existing directory is fine')

  open (newunit=u, file=root // '/a/f1', status='replace', action='write')
  write (u, '(a)') 'x'
  close (u)
  call check(path_exists(root // '/a/f1') .and. .not. is_directory(root // '/a/f1'), 'a file exists, not a directory')
  call make_directory(root // '/a/f1', stat, errmsg)
  call check(stat /= STAT_OK, 'make_directory over a file fails')

  call os_rename(root // '/a/f1', root // '/a/b/f2', stat, errmsg)
  call check(stat == STAT_OK .and. path_exists(root // '/a/b/f2') .and. .not. path_exists(root // '/a/f1'), &
             'os_rename moves the file')
  call os_rename(root // '/a/f1', root // '/a/f3', stat, errmsg)
  call check(stat /= STAT_OK .and. index(errmsg, '/a/f1') > 0, 'renaming a missing file fails, naming it')

  call remove_directory(root // '/a/b', stat, errmsg)
  call check(stat /= STAT_OK, 'remove_directory refuses a non-empty directory')
  call remove_file(root // '/a/b/f2', stat, errmsg)
  call check(stat == STAT_OK .and. .not. path_exists(root // '/a/b/f2'), 'remove_file')
  call remove_file(root // '/a/b/f2', stat, errmsg)
  call check(stat == STAT_OK, 'remove_file of a missing file is fine')
  call remove_directory(root // '/a/b', stat, errmsg)
  call remove_directory(root // '/a', stat, errmsg)
  call remove_directory(root, stat, errmsg)
  call check(stat == STAT_OK .and. .not. path_exists(root), 'remove_directory')
  call test_summary('os_utils')
end program test_os_utils
