!> Explicit interfaces to the LAPACK routines rebond calls (reference interfaces, LP64 default
!> integers), declared PURE so that pure kernels (contact, LCP) can call them.
!> Why PURE is legitimate: these routines touch nothing but their arguments (no SAVE state, no
!> I/O, no globals); the only exception is XERBLA on an invalid argument (info < 0), which every
!> caller here rules out by checking dimensions first. Declaring the external interface PURE is
!> the established way to call LAPACK from pure Fortran (the compiler cannot see the Fortran 77
!> definition, so purity is our promise, not something it checks).
module lapack_pure
  use kinds, only: dp
  implicit none
  private
  public :: dsygvd, dsyev, dposv, dsysv, dpstrf, dpotrf, dpotrs, dgesv, dgetrf, dgetrs

  interface
    !> Generalized symmetric-definite eigenproblem, divide and conquer.
    pure subroutine dsygvd(itype, jobz, uplo, n, a, lda, b, ldb, w, work, lwork, iwork, liwork, info)
      import :: dp
      integer, intent(in) :: itype, n, lda, ldb, lwork, liwork
      character(len=1), intent(in) :: jobz, uplo
      real(dp), intent(inout) :: a(lda, *), b(ldb, *)
      real(dp), intent(out) :: w(*), work(*)
      integer, intent(out) :: iwork(*), info
    end subroutine dsygvd

    !> Symmetric eigenproblem (QR iteration).
    pure subroutine dsyev(jobz, uplo, n, a, lda, w, work, lwork, info)
      import :: dp
      character(len=1), intent(in) :: jobz, uplo
      integer, intent(in) :: n, lda, lwork
      real(dp), intent(inout) :: a(lda, *)
      real(dp), intent(out) :: w(*), work(*)
      integer, intent(out) :: info
    end subroutine dsyev

    !> SPD solve (Cholesky factor + solve).
    pure subroutine dposv(uplo, n, nrhs, a, lda, b, ldb, info)
      import :: dp
      character(len=1), intent(in) :: uplo
      integer, intent(in) :: n, nrhs, lda, ldb
      real(dp), intent(inout) :: a(lda, *), b(ldb, *)
      integer, intent(out) :: info
    end subroutine dposv

    !> Symmetric indefinite solve (Bunch-Kaufman).
    pure subroutine dsysv(uplo, n, nrhs, a, lda, ipiv, b, ldb, work, lwork, info)
      import :: dp
      character(len=1), intent(in) :: uplo
      integer, intent(in) :: n, nrhs, lda, ldb, lwork
      real(dp), intent(inout) :: a(lda, *), b(ldb, *)
      integer, intent(out) :: ipiv(*), info
      real(dp), intent(out) :: work(*)
    end subroutine dsysv

    !> Cholesky with complete (diagonal) pivoting of a PSD matrix: P' A P = L L' on the leading
    !> rank rows. Stops at the first pivot <= tol (or NaN); tol < 0 means n eps max(diag).
    !> info = 1 when rank < n (not an error).
    pure subroutine dpstrf(uplo, n, a, lda, piv, rank, tol, work, info)
      import :: dp
      character(len=1), intent(in) :: uplo
      integer, intent(in) :: n, lda
      real(dp), intent(inout) :: a(lda, *)
      integer, intent(out) :: piv(*), rank, info
      real(dp), intent(in) :: tol
      real(dp), intent(out) :: work(*)
    end subroutine dpstrf

    !> Cholesky factorization; info > 0 when a is not positive definite (the leading minor of that
    !> order is not positive): a cheap definiteness test.
    pure subroutine dpotrf(uplo, n, a, lda, info)
      import :: dp
      character(len=1), intent(in) :: uplo
      integer, intent(in) :: n, lda
      real(dp), intent(inout) :: a(lda, *)
      integer, intent(out) :: info
    end subroutine dpotrf

    !> Solve with a Cholesky factor from dpotrf/dposv (or the leading block of dpstrf's).
    pure subroutine dpotrs(uplo, n, nrhs, a, lda, b, ldb, info)
      import :: dp
      character(len=1), intent(in) :: uplo
      integer, intent(in) :: n, nrhs, lda, ldb
      real(dp), intent(in) :: a(lda, *)
      real(dp), intent(inout) :: b(ldb, *)
      integer, intent(out) :: info
    end subroutine dpotrs

    !> General square solve, LU with partial pivoting; info = i > 0 when U(i,i) is exactly 0.
    pure subroutine dgesv(n, nrhs, a, lda, ipiv, b, ldb, info)
      import :: dp
      integer, intent(in) :: n, nrhs, lda, ldb
      real(dp), intent(inout) :: a(lda, *), b(ldb, *)
      integer, intent(out) :: ipiv(*), info
    end subroutine dgesv

    !> LU with partial pivoting of a general matrix (dgesv's factorization); info as dgesv.
    pure subroutine dgetrf(m, n, a, lda, ipiv, info)
      import :: dp
      integer, intent(in) :: m, n, lda
      real(dp), intent(inout) :: a(lda, *)
      integer, intent(out) :: ipiv(*), info
    end subroutine dgetrf

    !> Solve with dgetrf's factors (dgesv's solve).
    pure subroutine dgetrs(trans, n, nrhs, a, lda, ipiv, b, ldb, info)
      import :: dp
      character(len=1), intent(in) :: trans
      integer, intent(in) :: n, nrhs, lda, ldb
      real(dp), intent(in) :: a(lda, *)
      integer, intent(in) :: ipiv(*)
      real(dp), intent(inout) :: b(ldb, *)
      integer, intent(out) :: info
    end subroutine dgetrs
  end interface
end module lapack_pure
