!> Every C function rebond calls, in one place: the few POSIX calls Fortran 2008 lacks (libc),
!> and rebond's own C (src/core/os_shim.c: signals, exit; src/core/file_shim.c: checked
!> writes; src/core/format_shim.c: the digits of ES24.16E3; src/linalg/cholmod_shim.c and
!> umfpack_shim.c: the SuiteSparse handles). The modules that wrap them (os_utils, text_file,
!> text_format, cholmod_binding, sweep) translate their
!> status codes; nothing else calls C.
module c_interfaces
  use, intrinsic :: iso_c_binding, only: c_ptr, c_int, c_double, c_char, c_size_t
  implicit none
  private
  public :: c_rename, c_mkdir, c_access, c_opendir, c_closedir, c_rmdir, c_install_signals, &
    c_signal_received, c_exit, c_remove, rb_format_es, rb_chol_new, rb_chol_free, rb_chol_is_factored, &
    rb_chol_version, rb_blas_threads, rb_chol_cost_ratio, rb_chol_solve_flops, rb_chol_stats, rb_chol_factorize, rb_chol_solve, &
    rb_umf_new, rb_umf_free, &
    rb_umf_is_factored, &
    rb_umf_version, rb_umf_analyze, rb_umf_factorize, rb_umf_solve, c_usleep, &
    rb_file_open, rb_file_write, rb_file_close, rb_strerror, rb_room, c_exit_now, &
    rb_take_errno, rb_unlink_symlink, rb_file_replace_tail, rb_stdout_line

  interface
    ! libc and os_shim.c (os_utils)
    function c_rename(from, to) bind(c, name='rename') result(rc)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: from(*), to(*)
      integer(c_int) :: rc
    end function c_rename

    function c_mkdir(path, mode) bind(c, name='mkdir') result(rc)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: mode   ! mode_t is a 32-bit unsigned int on Linux
      integer(c_int) :: rc
    end function c_mkdir

    function c_access(path, mode) bind(c, name='access') result(rc)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: mode
      integer(c_int) :: rc
    end function c_access

    function c_opendir(path) bind(c, name='opendir') result(dir)
      import :: c_char, c_ptr
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr) :: dir
    end function c_opendir

    function c_closedir(dir) bind(c, name='closedir') result(rc)
      import :: c_ptr, c_int
      type(c_ptr), value :: dir
      integer(c_int) :: rc
    end function c_closedir

    function c_rmdir(path) bind(c, name='rmdir') result(rc)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: rc
    end function c_rmdir

    ! src/os_shim.c: SIGINT/SIGTERM only raise a flag, polled by the time loop.
    function c_install_signals() bind(c, name='rebond_install_signal_handlers') result(rc)
      import :: c_int
      integer(c_int) :: rc
    end function c_install_signals

    function c_signal_received() bind(c, name='rebond_signal_received') result(sig)
      import :: c_int
      integer(c_int) :: sig
    end function c_signal_received

    subroutine c_exit(status) bind(c, name='rebond_exit')
      import :: c_int
      integer(c_int), value :: status
    end subroutine c_exit

    function c_remove(path) bind(c, name='remove') result(rc)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: rc
    end function c_remove
    ! format_shim.c (text_format)
    function rb_format_es(x, out) bind(c, name='rb_format_es') result(n)
      import :: c_double, c_char, c_int
      real(c_double), value :: x
      character(kind=c_char), intent(out) :: out(*)
      integer(c_int) :: n
    end function rb_format_es
    ! cholmod_shim.c and umfpack_shim.c (cholmod_binding)
    function rb_chol_new() bind(c, name='rb_chol_new') result(h)
      import :: c_ptr
      type(c_ptr) :: h
    end function rb_chol_new

    subroutine rb_chol_free(h) bind(c, name='rb_chol_free')
      import :: c_ptr
      type(c_ptr), value :: h
    end subroutine rb_chol_free

    function rb_chol_is_factored(h) bind(c, name='rb_chol_is_factored') result(r)
      import :: c_ptr, c_int
      type(c_ptr), value :: h
      integer(c_int) :: r
    end function rb_chol_is_factored

    function rb_chol_cost_ratio(h) bind(c, name='rb_chol_cost_ratio') result(r)
      import :: c_ptr, c_double
      type(c_ptr), value :: h
      real(c_double) :: r
    end function rb_chol_cost_ratio

    function rb_chol_solve_flops(h) bind(c, name='rb_chol_solve_flops') result(r)
      import :: c_ptr, c_double
      type(c_ptr), value :: h
      real(c_double) :: r
    end function rb_chol_solve_flops

    function rb_chol_stats(h, stats) bind(c, name='rb_chol_stats') result(rc)
      import :: c_ptr, c_double, c_int
      type(c_ptr), value :: h
      real(c_double), intent(out) :: stats(6)
      integer(c_int) :: rc
    end function rb_chol_stats

    subroutine rb_chol_version(v) bind(c, name='rb_chol_version')
      import :: c_int
      integer(c_int), intent(out) :: v(3)
    end subroutine rb_chol_version

    subroutine rb_blas_threads(solve, factorize) bind(c, name='rb_blas_threads')
      import :: c_int
      integer(c_int), intent(out) :: solve, factorize
    end subroutine rb_blas_threads

    function rb_chol_factorize(h, n, nnz, colptr, rowind, values, minor, msg, msglen) &
        bind(c, name='rb_chol_factorize') result(rc)
      import :: c_ptr, c_int, c_double, c_char
      type(c_ptr), value :: h
      integer(c_int), value :: n, nnz
      integer(c_int), intent(in) :: colptr(*), rowind(*)
      real(c_double), intent(in) :: values(*)
      integer(c_int), intent(out) :: minor
      character(kind=c_char), intent(inout) :: msg(*)
      integer(c_int), value :: msglen
      integer(c_int) :: rc
    end function rb_chol_factorize

    function rb_chol_solve(h, n, b, x, msg, msglen) bind(c, name='rb_chol_solve') result(rc)
      import :: c_ptr, c_int, c_double, c_char
      type(c_ptr), value :: h
      integer(c_int), value :: n
      real(c_double), intent(in) :: b(*)
      real(c_double), intent(inout) :: x(*)
      character(kind=c_char), intent(inout) :: msg(*)
      integer(c_int), value :: msglen
      integer(c_int) :: rc
    end function rb_chol_solve

    function rb_umf_new() bind(c, name='rb_umf_new') result(h)
      import :: c_ptr
      type(c_ptr) :: h
    end function rb_umf_new

    subroutine rb_umf_free(h) bind(c, name='rb_umf_free')
      import :: c_ptr
      type(c_ptr), value :: h
    end subroutine rb_umf_free

    function rb_umf_is_factored(h) bind(c, name='rb_umf_is_factored') result(r)
      import :: c_ptr, c_int
      type(c_ptr), value :: h
      integer(c_int) :: r
    end function rb_umf_is_factored

    subroutine rb_umf_version(v) bind(c, name='rb_umf_version')
      import :: c_int
      integer(c_int), intent(out) :: v(3)
    end subroutine rb_umf_version

    function rb_umf_analyze(h, n, nnz, colptr0, rowind0, msg, msglen) bind(c, name='rb_umf_analyze') result(rc)
      import :: c_ptr, c_int, c_char
      type(c_ptr), value :: h
      integer(c_int), value :: n, nnz
      integer(c_int), intent(in) :: colptr0(*), rowind0(*)
      character(kind=c_char), intent(inout) :: msg(*)
      integer(c_int), value :: msglen
      integer(c_int) :: rc
    end function rb_umf_analyze

    function rb_umf_factorize(h, nnz, values, msg, msglen) bind(c, name='rb_umf_factorize') result(rc)
      import :: c_ptr, c_int, c_double, c_char
      type(c_ptr), value :: h
      integer(c_int), value :: nnz
      real(c_double), intent(in) :: values(*)
      character(kind=c_char), intent(inout) :: msg(*)
      integer(c_int), value :: msglen
      integer(c_int) :: rc
    end function rb_umf_factorize

    function rb_umf_solve(h, n, b, x, msg, msglen) bind(c, name='rb_umf_solve') result(rc)
      import :: c_ptr, c_int, c_double, c_char
      type(c_ptr), value :: h
      integer(c_int), value :: n
      real(c_double), intent(in) :: b(*)
      real(c_double), intent(inout) :: x(*)
      character(kind=c_char), intent(inout) :: msg(*)
      integer(c_int), value :: msglen
      integer(c_int) :: rc
    end function rb_umf_solve
    ! libc (sweep)
    function c_usleep(usec) bind(c, name='usleep') result(rc)
      import :: c_int
      integer(c_int), value :: usec
      integer(c_int) :: rc
    end function c_usleep

    ! src/core/file_shim.c: result files written with every write(2) checked (text_file).
    function rb_file_open(path, mode, err) bind(c, name='rebond_file_open') result(h)
      import :: c_char, c_int, c_ptr
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: mode
      integer(c_int), intent(out) :: err
      type(c_ptr) :: h
    end function rb_file_open

    function rb_stdout_line(buf, n) bind(c, name='rebond_stdout_line') result(err)
      import :: c_char, c_int, c_size_t
      character(kind=c_char), intent(in) :: buf(*)
      integer(c_size_t), value :: n
      integer(c_int) :: err
    end function rb_stdout_line

    function rb_file_write(h, buf, n, newline) bind(c, name='rebond_file_write') result(err)
      import :: c_char, c_int, c_ptr, c_size_t
      type(c_ptr), value :: h
      character(kind=c_char), intent(in) :: buf(*)
      integer(c_size_t), value :: n
      integer(c_int), value :: newline
      integer(c_int) :: err
    end function rb_file_write

    function rb_file_replace_tail(h, buf, n, tail) bind(c, name='rebond_file_replace_tail') result(err)
      import :: c_char, c_int, c_ptr, c_size_t
      type(c_ptr), value :: h
      character(kind=c_char), intent(in) :: buf(*)
      integer(c_size_t), value :: n, tail
      integer(c_int) :: err
    end function rb_file_replace_tail

    function rb_file_close(h) bind(c, name='rebond_file_close') result(err)
      import :: c_int, c_ptr
      type(c_ptr), value :: h
      integer(c_int) :: err
    end function rb_file_close

    function rb_room(path, dir) bind(c, name='rebond_room') result(b)
      import :: c_char, c_double
      character(kind=c_char), intent(in) :: path(*), dir(*)
      real(c_double) :: b
    end function rb_room

    function rb_unlink_symlink(path) bind(c, name='rebond_unlink_symlink') result(e)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: e
    end function rb_unlink_symlink

    function rb_take_errno() bind(c, name='rebond_take_errno') result(e)
      import :: c_int
      integer(c_int) :: e
    end function rb_take_errno

    subroutine c_exit_now(status) bind(c, name='rebond_exit_now')
      import :: c_int
      integer(c_int), value :: status
    end subroutine c_exit_now

    subroutine rb_strerror(err, buf, n) bind(c, name='rebond_strerror')
      import :: c_char, c_int
      integer(c_int), value :: err
      character(kind=c_char), intent(out) :: buf(*)
      integer(c_int), value :: n
    end subroutine rb_strerror
  end interface
end module c_interfaces
