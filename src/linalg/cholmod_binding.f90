!> SuiteSparse binding: the project's single Fortran module for its C interop with SuiteSparse
!> (src/cholmod_shim.c, src/umfpack_shim.c). C handles stay opaque (type(c_ptr)); 1-based
!> Fortran indices are copied to 0-based ones at the boundary; every library status is checked.
!>
!> cholmod_factor_t: sparse Cholesky of a symmetric positive definite sym_csc_t matrix (CHOLMOD).
!> Usage: call f%factorize(pat, values, stat, errmsg) once (copies the pattern, analyzes,
!> factorizes); later factorize calls with the same pattern and new values only refactorize;
!> call f%solve(b, x, stat, errmsg) as often as needed (allocation-free after the first);
!> call f%destroy() when done.
!>
!> umfpack_factor_t: sparse LU of a general square matrix in full CSC storage (UMFPACK), e.g. the
!> indefinite contact system [S C'; C D]. Usage: call u%analyze(n, colptr, rowind, stat, errmsg)
!> once per pattern; call u%factorize(values, stat, errmsg, singular) for each set of values
!> (singular = .true. on a zero pivot: no factor, the caller falls back); call u%solve(b, x, stat,
!> errmsg) as often as needed (allocation-free); call u%destroy() when done.
!>
!> Do not copy a cholmod_factor_t or an umfpack_factor_t (the copy would share the C handle):
!> pass them by reference. gfortran 12 does not finalize non-allocatable locals at scope exit,
!> so call destroy explicitly.
module cholmod_binding
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_int, c_double, c_char, c_null_char, &
    c_associated
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str
  use sparse_matrix, only: sym_csc_t
  use sparse_factor, only: sparse_factor_t, factor_stats_t, ORDERING_NAMES
  use c_interfaces, only: rb_chol_new, rb_chol_free, rb_chol_is_factored, rb_chol_version, rb_chol_factorize, rb_chol_cost_ratio, &
    rb_chol_solve_flops, rb_chol_stats, rb_blas_threads, &
    rb_chol_solve, rb_umf_new, rb_umf_free, rb_umf_is_factored, rb_umf_version, rb_umf_analyze, rb_umf_factorize, &
    rb_umf_solve
  implicit none
  private
  public :: cholmod_factor_t, cholmod_version, umfpack_factor_t, umfpack_version, factor_stats_t, ORDERING_NAMES, blas_threads

  type, extends(sparse_factor_t) :: cholmod_factor_t
    private
    type(c_ptr) :: handle = c_null_ptr
  contains
    procedure :: name => chol_name
    procedure :: factorize
    procedure :: solve
    procedure :: is_factored
    procedure :: cost_ratio
    procedure :: solve_flops
    procedure :: stats
    procedure :: destroy
    final :: cholmod_factor_final
  end type cholmod_factor_t

  type :: umfpack_factor_t
    private
    type(c_ptr) :: handle = c_null_ptr
  contains
    procedure :: analyze => umf_analyze
    procedure :: factorize => umf_factorize
    procedure :: solve => umf_solve
    procedure :: is_factored => umf_is_factored
    procedure :: destroy => umf_destroy
    final :: umfpack_factor_final
  end type umfpack_factor_t

  ! Return codes of both shims (cholmod_shim.c, umfpack_shim.c), translated by shim_status.
  integer(c_int), parameter :: RB_OK = 0, RB_NOT_POSDEF = 1, RB_SINGULAR = 1, RB_BADARG = 3
  integer, parameter :: MSGLEN = 320

contains

  !> Factorize the SPD matrix (pat, values). The first call copies the pattern and analyzes
  !> (fill-reducing ordering); later calls must pass the same pattern and only refactorize.
  !> Not positive definite: stat = STAT_RUN, errmsg names the 1-based column whose pivot failed,
  !> minor = that column (0 on success).
  subroutine factorize(self, pat, values, stat, errmsg, minor)
    class(cholmod_factor_t), intent(inout) :: self
    type(sym_csc_t), intent(in) :: pat
    real(dp), intent(in), contiguous :: values(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, intent(out), optional :: minor
    character(kind=c_char) :: cmsg(MSGLEN)
    integer(c_int) :: rc, cminor

    stat = STAT_OK
    if (present(minor)) minor = 0
    if (.not. allocated(pat%colptr) .or. .not. allocated(pat%rowind) .or. pat%n < 1) then
      call set_error(stat, errmsg, STAT_INPUT, 'CHOLMOD factorize: empty or unbuilt sparse pattern')
      return
    end if
    if (size(values) /= pat%nnz) then
      call set_error(stat, errmsg, STAT_INPUT, 'CHOLMOD factorize: ' // str(size(values)) // &
                     ' values for a pattern with ' // str(pat%nnz) // ' entries')
      return
    end if
    if (.not. c_associated(self%handle)) then
      self%handle = rb_chol_new()
      if (.not. c_associated(self%handle)) then
        call set_error(stat, errmsg, STAT_RUN, 'CHOLMOD: cannot start (out of memory?)')
        return
      end if
    end if
    cmsg(1) = c_null_char
    rc = rb_chol_factorize(self%handle, int(pat%n, c_int), int(pat%nnz, c_int), pat%colptr, pat%rowind, &
                           values, cminor, cmsg, int(MSGLEN, c_int))
    if (rc == RB_NOT_POSDEF .and. present(minor)) minor = int(cminor)
    call shim_status(rc, cmsg, stat, errmsg)
  end subroutine factorize

  function chol_name(self) result(s)
    class(cholmod_factor_t), intent(in) :: self
    character(len=:), allocatable :: s
    s = 'CHOLMOD'
  end function chol_name

  !> x = A^{-1} b with the current factor. No allocation after the first call on success.
  subroutine solve(self, b, x, stat, errmsg)
    class(cholmod_factor_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: b(:)
    real(dp), intent(out), contiguous :: x(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(kind=c_char) :: cmsg(MSGLEN)
    integer(c_int) :: rc

    call check_solve('CHOLMOD', self%handle, size(b), size(x), stat, errmsg)
    if (stat /= STAT_OK) return
    cmsg(1) = c_null_char
    rc = rb_chol_solve(self%handle, int(size(b), c_int), b, x, cmsg, int(MSGLEN, c_int))
    call shim_status(rc, cmsg, stat, errmsg)
  end subroutine solve

  !> The shims' return code in rebond's terms, in one place: RB_OK nothing, RB_BADARG a caller's
  !> error (STAT_INPUT), anything else (not positive definite, singular, failure) STAT_RUN; the
  !> message is the shim's.
  subroutine shim_status(rc, cmsg, stat, errmsg)
    integer(c_int), intent(in) :: rc
    character(kind=c_char), intent(in) :: cmsg(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (rc == RB_OK) return
    call set_error(stat, errmsg, merge(STAT_INPUT, STAT_RUN, rc == RB_BADARG), c_to_f(cmsg))
  end subroutine shim_status

  !> A solve needs a factor and matching sizes (lib names the library in the message).
  subroutine check_solve(lib, handle, nb, nx, stat, errmsg)
    character(len=*), intent(in) :: lib
    type(c_ptr), intent(in) :: handle
    integer, intent(in) :: nb, nx
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (.not. c_associated(handle)) then
      call set_error(stat, errmsg, STAT_INPUT, lib // ' solve: matrix not factorized')
    else if (nx /= nb) then
      call set_error(stat, errmsg, STAT_INPUT, lib // ' solve: size(x) = ' // str(nx) // ' differs from size(b) = ' // &
                     str(nb))
    end if
  end subroutine check_solve

  !> A numeric factorization's cost in solves (flops of the factorization over those of a solve,
  !> from CHOLMOD's analysis; 0 before the first factorization).
  real(dp) function cost_ratio(self)
    class(cholmod_factor_t), intent(in) :: self
    cost_ratio = 0.0_dp
    if (c_associated(self%handle)) cost_ratio = real(rb_chol_cost_ratio(self%handle), dp)
  end function cost_ratio

  !> The flops of one solve (4 nnz(L), from CHOLMOD's analysis; 0 before the first factorization).
  real(dp) function solve_flops(self)
    class(cholmod_factor_t), intent(in) :: self
    solve_flops = 0.0_dp
    if (c_associated(self%handle)) solve_flops = real(rb_chol_solve_flops(self%handle), dp)
  end function solve_flops

  !> What CHOLMOD's analysis made (sparse_factor's factor_stats_t; zeros before the first factorization).
  function stats(self) result(s)
    class(cholmod_factor_t), intent(in) :: self
    type(factor_stats_t) :: s
    real(c_double) :: cs(6)
    if (.not. c_associated(self%handle)) return
    if (rb_chol_stats(self%handle, cs) == 0) return
    s = factor_stats_t(real(cs(1), dp), real(cs(2), dp), real(cs(3), dp), real(cs(5), dp), nint(cs(4)), cs(6) /= 0.0_c_double)
  end function stats

  !> True when the last factorize succeeded and destroy has not been called since.
  logical function is_factored(self)
    class(cholmod_factor_t), intent(in) :: self
    is_factored = .false.
    if (c_associated(self%handle)) is_factored = rb_chol_is_factored(self%handle) /= 0
  end function is_factored

  !> Free the factor, the matrix copy, the workspaces and the CHOLMOD common. Idempotent.
  subroutine destroy(self)
    class(cholmod_factor_t), intent(inout) :: self
    if (c_associated(self%handle)) call rb_chol_free(self%handle)
    self%handle = c_null_ptr
  end subroutine destroy

  subroutine cholmod_factor_final(self)
    type(cholmod_factor_t), intent(inout) :: self
    call self%destroy()
  end subroutine cholmod_factor_final

  !> The BLAS threads of a solve and of a numeric factorization (cholmod_shim.c: solves on one
  !> thread, factorizations on OpenBLAS's own count; both that count with another BLAS).
  subroutine blas_threads(solve, factorize)
    integer, intent(out) :: solve, factorize
    integer(c_int) :: s, f
    call rb_blas_threads(s, f)
    solve = s
    factorize = f
  end subroutine blas_threads

  !> CHOLMOD version compiled against, e.g. '3.0.14'.
  function cholmod_version() result(s)
    character(len=:), allocatable :: s
    integer(c_int) :: v(3)
    call rb_chol_version(v)
    s = version_text(v)
  end function cholmod_version

  !> Symbolic analysis of the n x n pattern in full CSC storage (both triangles): colptr(n+1),
  !> rowind(nnz), 1-based, rows sorted and distinct within each column. Depends on the pattern
  !> only; replaces any previous pattern and factor. Bad pattern: stat = STAT_INPUT.
  subroutine umf_analyze(self, n, colptr, rowind, stat, errmsg)
    class(umfpack_factor_t), intent(inout) :: self
    integer, intent(in) :: n
    integer, intent(in) :: colptr(:), rowind(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer(c_int), allocatable :: colptr0(:), rowind0(:)
    character(kind=c_char) :: cmsg(MSGLEN)
    integer(c_int) :: rc

    stat = STAT_OK
    if (n < 1 .or. size(colptr) /= n + 1) then
      call set_error(stat, errmsg, STAT_INPUT, 'UMFPACK analyze: order n = ' // str(n) // ' with ' // &
                     str(size(colptr)) // ' column pointers (expected n + 1)')
      return
    end if
    if (colptr(1) /= 1 .or. colptr(n + 1) - 1 /= size(rowind)) then
      call set_error(stat, errmsg, STAT_INPUT, 'UMFPACK analyze: colptr(1) = ' // str(colptr(1)) // &
                     ', colptr(n+1) = ' // str(colptr(n + 1)) // ' for ' // str(size(rowind)) // &
                     ' row indices (expected 1 and nnz + 1)')
      return
    end if
    if (.not. c_associated(self%handle)) then
      self%handle = rb_umf_new()
      if (.not. c_associated(self%handle)) then
        call set_error(stat, errmsg, STAT_RUN, 'UMFPACK: cannot allocate the handle (out of memory?)')
        return
      end if
    end if
    ! 0-based copies for C (once per pattern; the C side keeps its own copy).
    colptr0 = int(colptr - 1, c_int)
    rowind0 = int(rowind - 1, c_int)
    cmsg(1) = c_null_char
    rc = rb_umf_analyze(self%handle, int(n, c_int), int(size(rowind), c_int), colptr0, rowind0, cmsg, &
                        int(MSGLEN, c_int))
    call shim_status(rc, cmsg, stat, errmsg)
  end subroutine umf_analyze

  !> Numeric LU of values(nnz), in the analyzed pattern's order; frees the previous factor.
  !> Singular matrix (zero pivot): singular = .true., stat = STAT_RUN and no usable factor
  !> (solve refuses) until a later factorize succeeds.
  subroutine umf_factorize(self, values, stat, errmsg, singular)
    class(umfpack_factor_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: values(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical, intent(out) :: singular
    character(kind=c_char) :: cmsg(MSGLEN)
    integer(c_int) :: rc

    stat = STAT_OK
    singular = .false.
    if (.not. c_associated(self%handle)) then
      call set_error(stat, errmsg, STAT_INPUT, 'UMFPACK factorize: pattern not analyzed')
      return
    end if
    cmsg(1) = c_null_char
    rc = rb_umf_factorize(self%handle, int(size(values), c_int), values, cmsg, int(MSGLEN, c_int))
    singular = rc == RB_SINGULAR
    call shim_status(rc, cmsg, stat, errmsg)
  end subroutine umf_factorize

  !> x = A^{-1} b with the current LU factor (UMFPACK's iterative refinement included).
  !> Allocation-free: the workspace lives in the C handle.
  subroutine umf_solve(self, b, x, stat, errmsg)
    class(umfpack_factor_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: b(:)
    real(dp), intent(out), contiguous :: x(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(kind=c_char) :: cmsg(MSGLEN)
    integer(c_int) :: rc

    call check_solve('UMFPACK', self%handle, size(b), size(x), stat, errmsg)
    if (stat /= STAT_OK) return
    cmsg(1) = c_null_char
    rc = rb_umf_solve(self%handle, int(size(b), c_int), b, x, cmsg, int(MSGLEN, c_int))
    call shim_status(rc, cmsg, stat, errmsg)
  end subroutine umf_solve

  !> True when the last factorize succeeded (nonsingular) and destroy has not been called since.
  logical function umf_is_factored(self)
    class(umfpack_factor_t), intent(in) :: self
    umf_is_factored = .false.
    if (c_associated(self%handle)) umf_is_factored = rb_umf_is_factored(self%handle) /= 0
  end function umf_is_factored

  !> Free the factor, the analysis, the pattern and value copies and the workspaces. Idempotent.
  subroutine umf_destroy(self)
    class(umfpack_factor_t), intent(inout) :: self
    if (c_associated(self%handle)) call rb_umf_free(self%handle)
    self%handle = c_null_ptr
  end subroutine umf_destroy

  subroutine umfpack_factor_final(self)
    type(umfpack_factor_t), intent(inout) :: self
    call self%destroy()
  end subroutine umfpack_factor_final

  !> UMFPACK version compiled against, e.g. '5.7.9'.
  function umfpack_version() result(s)
    character(len=:), allocatable :: s
    integer(c_int) :: v(3)
    call rb_umf_version(v)
    s = version_text(v)
  end function umfpack_version

  !> "major.minor.patch" of a library version triple.
  pure function version_text(v) result(s)
    integer(c_int), intent(in) :: v(3)
    character(len=:), allocatable :: s
    s = str(int(v(1))) // '.' // str(int(v(2))) // '.' // str(int(v(3)))
  end function version_text

  !> NUL-terminated C string -> Fortran string.
  pure function c_to_f(c) result(s)
    character(kind=c_char), intent(in) :: c(:)
    character(len=:), allocatable :: s
    integer :: i, n
    n = size(c)
    do i = 1, size(c)
      if (c(i) == c_null_char) then
        n = i - 1
        exit
      end if
    end do
    allocate (character(len=n) :: s)
    do i = 1, n
      s(i:i) = c(i)
    end do
  end function c_to_f
end module cholmod_binding
