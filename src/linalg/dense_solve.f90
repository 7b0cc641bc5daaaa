!> Dense linear algebra through LAPACK (interfaces in lapack_pure): generalized eigenproblem
!> (modal analysis of small systems), SPD and symmetric indefinite linear solves, and the pure
!> kernels of the contact algebra: spsd_solve (semidefinite, rank-revealing pivoted Cholesky)
!> and gen_solve (small general square systems). Every LAPACK `info` is checked.
module dense_solve
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str
  use lapack_pure, only: dsygvd, dposv, dsysv, dpstrf, dpotrs, dgesv
  implicit none
  private
  public :: generalized_eigen, spd_solve, sym_solve, spsd_solve, spsd_solve_ws, gen_solve, PIVOT_RTOL

  !> spd_solve(a, b, stat, errmsg): b(n) or b(n,nrhs).
  interface spd_solve
    module procedure spd_solve_1, spd_solve_2
  end interface spd_solve

  !> sym_solve(a, b, stat, errmsg): b(n) or b(n,nrhs).
  interface sym_solve
    module procedure sym_solve_1, sym_solve_2
  end interface sym_solve

  !> Default relative pivot tolerance of spsd_solve: a pivot <= PIVOT_RTOL * max(diag) marks a
  !> row dependent on the kept ones. Exactly dependent rows give pivots of a few ulps (relative);
  !> 1e-12 leaves three decades of margin.
  real(dp), parameter :: PIVOT_RTOL = 1.0e-12_dp

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

  !> Solve a x = b, a(n,n) symmetric positive semidefinite (full storage, lower triangle used),
  !> by Cholesky with diagonal pivoting (dpstrf): P' a P = L L' on the leading rank rows.
  !> Pivoting stops at the first pivot <= rtol * max(diag(a)) (dpstrf's TOL test): the remaining
  !> rows are dependent (to that tolerance) on the kept ones, their unknowns are set to zero and
  !> the kept block is solved exactly (dpotrs). rank = number of kept rows; dropped(j) marks the
  !> others. For a consistent right-hand side this is a solution of the full system.
  !> rtol defaults to PIVOT_RTOL; a negative rtol is taken as 0 (stop only at pivots <= 0).
  !> rank = 0, x = 0 and every row dropped when: n = 0; a has a NaN or Inf entry; max(diag(a))
  !> is not positive; or a size mismatch / LAPACK argument error (info < 0), which can only
  !> be a programming error and, the routine being pure without stat, is reported this way.
  pure subroutine spsd_solve(a, b, x, rank, dropped, rtol)
    real(dp), intent(in) :: a(:, :), b(:)
    real(dp), intent(out) :: x(:)
    integer, intent(out) :: rank
    logical, intent(out), optional :: dropped(:)
    real(dp), intent(in), optional :: rtol
    real(dp), allocatable :: l(:, :), work(:)
    integer, allocatable :: piv(:)
    integer :: n

    n = size(b)
    x = 0.0_dp
    rank = 0
    if (present(dropped)) dropped = .true.
    if (n == 0 .or. size(a, 1) /= n .or. size(a, 2) /= n .or. size(x) /= n) return
    if (present(dropped)) then
      if (size(dropped) /= n) return
    end if
    allocate (l, source=a)
    allocate (piv(n), work(2 * n))
    x = b
    call spsd_solve_ws(n, l, x, rank, piv, work, dropped, rtol)
  end subroutine spsd_solve

  !> spsd_solve in place, for callers that must not allocate (the contact multipliers, every
  !> iteration): a(1:n, 1:n) (leading dimension size(a, 1) >= n) is overwritten by the factor,
  !> b(1:n) by the solution x; piv(n) and work(2n) are workspaces. Same results as spsd_solve.
  pure subroutine spsd_solve_ws(n, a, b, rank, piv, work, dropped, rtol)
    integer, intent(in) :: n
    real(dp), intent(inout), contiguous :: a(:, :)
    real(dp), intent(inout) :: b(:)
    integer, intent(out) :: rank
    integer, intent(inout), contiguous :: piv(:)
    real(dp), intent(inout), contiguous :: work(:)
    logical, intent(out), optional :: dropped(:)
    real(dp), intent(in), optional :: rtol
    integer :: i, r, info, lda
    real(dp) :: rt, dmax

    rt = PIVOT_RTOL
    if (present(rtol)) rt = max(rtol, 0.0_dp)
    rank = 0
    if (present(dropped)) dropped(1:n) = .true.
    lda = size(a, 1)
    if (n == 0 .or. lda < n .or. size(a, 2) < n .or. size(b) < n .or. size(piv) < n .or. size(work) < 2 * n) then
      b(1:min(n, size(b))) = 0.0_dp
      return
    end if
    if (.not. finite_matrix(a(1:n, 1:n))) then         ! NaN/Inf: no meaningful rank (tested quietly first)
      b(1:n) = 0.0_dp
      return
    end if
    dmax = 0.0_dp
    do i = 1, n
      dmax = max(dmax, a(i, i))
    end do
    if (.not. (dmax > 0.0_dp)) then
      b(1:n) = 0.0_dp
      return
    end if
    ! TOL >= 0 here, so dpstrf uses it as given (a negative TOL would select n eps max(diag)).
    call dpstrf('L', n, a, lda, piv, r, rt * dmax, work, info)
    if (info < 0 .or. r <= 0 .or. r > n) then          ! info = 1 only says rank < n
      b(1:n) = 0.0_dp
      return
    end if
    do i = 1, r                                        ! the kept unknowns, in pivot order
      work(i) = b(piv(i))
    end do
    call dpotrs('L', r, 1, a, lda, work, r, info)      ! leading r x r block of L
    b(1:n) = 0.0_dp
    if (info /= 0) return
    do i = 1, r
      b(piv(i)) = work(i)
    end do
    rank = r
    if (present(dropped)) then
      do i = 1, r
        dropped(piv(i)) = .false.
      end do
    end if
  end subroutine spsd_solve_ws

  !> x = a^-1 b for a small general square a(n,n) (LU with partial pivoting, dgesv). ok = .false.
  !> (and x = 0) when a is singular: an exactly zero pivot (info > 0) or, as the hand-written LU
  !> it replaces, a pivot |U(k,k)| <= eps * max|a| (numerically singular); a NaN or Inf entry;
  !> or a size mismatch. n = 0 is ok.
  pure subroutine gen_solve(a, b, x, ok)
    real(dp), intent(in) :: a(:, :), b(:)
    real(dp), intent(out) :: x(:)
    logical, intent(out) :: ok
    real(dp), allocatable :: lu(:, :), y(:)
    integer, allocatable :: ipiv(:)
    real(dp) :: amax
    integer :: n, k, info

    n = size(b)
    x = 0.0_dp
    ok = .false.
    if (size(a, 1) /= n .or. size(a, 2) /= n .or. size(x) /= n) return
    ok = .true.
    if (n == 0) return
    ok = .false.
    if (.not. finite_matrix(a)) return
    amax = maxval(abs(a))
    allocate (lu, source=a)
    allocate (y, source=b)
    allocate (ipiv(n))
    call dgesv(n, 1, lu, n, ipiv, y, n, info)
    if (info /= 0) return
    do k = 1, n
      if (.not. (abs(lu(k, k)) > epsilon(1.0_dp) * amax)) return
    end do
    x = y
    ok = .true.
  end subroutine gen_solve

  !> All entries finite. NaN is tested first with the quiet /= so that the ordered comparison
  !> never sees one (no invalid-operation flag under FPE traps); LAPACK never gets NaN or Inf.
  pure logical function finite_matrix(a)
    real(dp), intent(in) :: a(:, :)
    finite_matrix = .not. any(a /= a)
    if (finite_matrix) finite_matrix = .not. any(abs(a) > huge(1.0_dp))
  end function finite_matrix
end module dense_solve
