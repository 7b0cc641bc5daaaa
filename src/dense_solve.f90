!> Dense symmetric linear algebra through LAPACK: generalized eigenproblem (modal analysis of
!> small systems), SPD and symmetric indefinite linear solves. Every LAPACK `info` is checked.
module dense_solve
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str
  implicit none
  private
  public :: generalized_eigen, spd_solve, sym_solve

  !> spd_solve(a, b, stat, errmsg): b(n) or b(n,nrhs).
  interface spd_solve
    module procedure spd_solve_1, spd_solve_2
  end interface spd_solve

  !> sym_solve(a, b, stat, errmsg): b(n) or b(n,nrhs).
  interface sym_solve
    module procedure sym_solve_1, sym_solve_2
  end interface sym_solve

  ! LAPACK (reference interfaces, LP64 default integers).
  interface
    subroutine dsygvd(itype, jobz, uplo, n, a, lda, b, ldb, w, work, lwork, iwork, liwork, info)
      import :: dp
      integer, intent(in) :: itype, n, lda, ldb, lwork, liwork
      character(len=1), intent(in) :: jobz, uplo
      real(dp), intent(inout) :: a(lda, *), b(ldb, *)
      real(dp), intent(out) :: w(*), work(*)
      integer, intent(out) :: iwork(*), info
    end subroutine dsygvd

    subroutine dposv(uplo, n, nrhs, a, lda, b, ldb, info)
      import :: dp
      character(len=1), intent(in) :: uplo
      integer, intent(in) :: n, nrhs, lda, ldb
      real(dp), intent(inout) :: a(lda, *), b(ldb, *)
      integer, intent(out) :: info
    end subroutine dposv

    subroutine dsysv(uplo, n, nrhs, a, lda, ipiv, b, ldb, work, lwork, info)
      import :: dp
      character(len=1), intent(in) :: uplo
      integer, intent(in) :: n, nrhs, lda, ldb, lwork
      real(dp), intent(inout) :: a(lda, *), b(ldb, *)
      integer, intent(out) :: ipiv(*), info
      real(dp), intent(out) :: work(*)
    end subroutine dsysv
  end interface

contains

  !> Solve K x = w M x (K symmetric, M symmetric positive definite; upper triangles used) with
  !> dsygvd. w(n) receives the eigenvalues in ascending order (omega^2 for K, M stiffness and
  !> mass); vecs, when present, is allocated to (n,n) with the M-orthonormal eigenvectors
  !> (vecs^T M vecs = I) in the same order. k and m are not modified.
  subroutine generalized_eigen(k, m, w, vecs, stat, errmsg)
    real(dp), intent(in) :: k(:, :), m(:, :)
    real(dp), intent(out) :: w(:)
    real(dp), allocatable, intent(out), optional :: vecs(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), allocatable :: a(:, :), b(:, :), work(:)
    integer, allocatable :: iwork(:)
    real(dp) :: wq(1)
    integer :: n, info, iq(1), lwork, liwork
    character(len=1) :: jobz

    stat = STAT_OK
    n = size(k, 1)
    if (size(k, 2) /= n .or. size(m, 1) /= n .or. size(m, 2) /= n .or. size(w) /= n) then
      call set_error(stat, errmsg, STAT_INPUT, 'generalized_eigen: K, M must be n x n and w of size n (n = ' &
                     // str(n) // ')')
      return
    end if
    jobz = 'N'
    if (present(vecs)) jobz = 'V'
    if (n == 0) then
      if (present(vecs)) allocate (vecs(0, 0))
      return
    end if
    a = k
    b = m
    call dsygvd(1, jobz, 'U', n, a, n, b, n, w, wq, -1, iq, -1, info)   ! workspace query
    if (info /= 0) then
      call set_error(stat, errmsg, STAT_RUN, 'generalized_eigen: dsygvd workspace query info = ' // str(info))
      return
    end if
    lwork = max(1, int(wq(1)))
    liwork = max(1, iq(1))
    allocate (work(lwork), iwork(liwork))
    call dsygvd(1, jobz, 'U', n, a, n, b, n, w, work, lwork, iwork, liwork, info)
    if (info < 0) then
      call set_error(stat, errmsg, STAT_INPUT, 'generalized_eigen: dsygvd argument ' // str(-info) // ' invalid')
    else if (info > n) then
      call set_error(stat, errmsg, STAT_RUN, 'generalized_eigen: mass matrix not positive definite (leading ' // &
                     'minor of order ' // str(info - n) // ')')
    else if (info > 0) then
      call set_error(stat, errmsg, STAT_RUN, 'generalized_eigen: dsygvd did not converge (info = ' // &
                     str(info) // ')')
    end if
    if (info /= 0) return
    if (present(vecs)) call move_alloc(a, vecs)
  end subroutine generalized_eigen

  !> a x = b for a(n,n) SPD (upper triangle used; overwritten by its Cholesky factor);
  !> b(n) is overwritten by x.
  subroutine spd_solve_1(a, b, stat, errmsg)
    real(dp), intent(inout) :: a(:, :)
    real(dp), intent(inout), contiguous :: b(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call spd_solve_core(a, b, size(b), 1, stat, errmsg)
  end subroutine spd_solve_1

  !> a X = B for a(n,n) SPD; b(n,nrhs) is overwritten by X.
  subroutine spd_solve_2(a, b, stat, errmsg)
    real(dp), intent(inout) :: a(:, :)
    real(dp), intent(inout), contiguous :: b(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call spd_solve_core(a, b, size(b, 1), size(b, 2), stat, errmsg)
  end subroutine spd_solve_2

  subroutine spd_solve_core(a, b, nb, nrhs, stat, errmsg)
    real(dp), intent(inout) :: a(:, :)
    integer, intent(in) :: nb, nrhs
    real(dp), intent(inout) :: b(nb, nrhs)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: n, info

    stat = STAT_OK
    n = size(a, 1)
    if (size(a, 2) /= n .or. nb /= n) then
      call set_error(stat, errmsg, STAT_INPUT, 'spd_solve: a must be n x n and b have n rows (n = ' // str(n) // ')')
      return
    end if
    if (n == 0 .or. nrhs == 0) return
    call dposv('U', n, nrhs, a, n, b, n, info)
    if (info < 0) then
      call set_error(stat, errmsg, STAT_INPUT, 'spd_solve: dposv argument ' // str(-info) // ' invalid')
    else if (info > 0) then
      call set_error(stat, errmsg, STAT_RUN, 'spd_solve: matrix not positive definite (leading minor of order ' // &
                     str(info) // ')')
    end if
  end subroutine spd_solve_core

  !> a x = b for a(n,n) symmetric, possibly indefinite (upper triangle used; overwritten by its
  !> Bunch-Kaufman factor); b(n) is overwritten by x.
  subroutine sym_solve_1(a, b, stat, errmsg)
    real(dp), intent(inout) :: a(:, :)
    real(dp), intent(inout), contiguous :: b(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call sym_solve_core(a, b, size(b), 1, stat, errmsg)
  end subroutine sym_solve_1

  !> a X = B for a(n,n) symmetric indefinite; b(n,nrhs) is overwritten by X.
  subroutine sym_solve_2(a, b, stat, errmsg)
    real(dp), intent(inout) :: a(:, :)
    real(dp), intent(inout), contiguous :: b(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call sym_solve_core(a, b, size(b, 1), size(b, 2), stat, errmsg)
  end subroutine sym_solve_2

  subroutine sym_solve_core(a, b, nb, nrhs, stat, errmsg)
    real(dp), intent(inout) :: a(:, :)
    integer, intent(in) :: nb, nrhs
    real(dp), intent(inout) :: b(nb, nrhs)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), allocatable :: work(:)
    integer, allocatable :: ipiv(:)
    real(dp) :: wq(1)
    integer :: n, info, lwork

    stat = STAT_OK
    n = size(a, 1)
    if (size(a, 2) /= n .or. nb /= n) then
      call set_error(stat, errmsg, STAT_INPUT, 'sym_solve: a must be n x n and b have n rows (n = ' // str(n) // ')')
      return
    end if
    if (n == 0 .or. nrhs == 0) return
    allocate (ipiv(n))
    call dsysv('U', n, nrhs, a, n, ipiv, b, n, wq, -1, info)     ! workspace query
    if (info /= 0) then
      call set_error(stat, errmsg, STAT_RUN, 'sym_solve: dsysv workspace query info = ' // str(info))
      return
    end if
    lwork = max(1, int(wq(1)))
    allocate (work(lwork))
    call dsysv('U', n, nrhs, a, n, ipiv, b, n, work, lwork, info)
    if (info < 0) then
      call set_error(stat, errmsg, STAT_INPUT, 'sym_solve: dsysv argument ' // str(-info) // ' invalid')
    else if (info > 0) then
      call set_error(stat, errmsg, STAT_RUN, 'sym_solve: matrix is singular (zero pivot D(' // str(info) // ',' // &
                     str(info) // '))')
    end if
  end subroutine sym_solve_core
end module dense_solve
