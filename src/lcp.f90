!> Small dense kernels of the contact algebra (docs/contact.md):
!>   - spsd_solve: a x = b for a symmetric positive SEMI-definite matrix by Cholesky with
!>     diagonal pivoting; dependent rows (zero pivots) are detected and their unknowns set to 0;
!>   - lcp_solve: the linear complementarity problem of unilateral contact
!>         find lam >= 0 with g = q + W lam >= 0 and lam_j g_j = 0,
!>     W symmetric positive (semi)definite, by block principal pivoting (Judice-Pires) with
!>     Murty's least-index rule as the finite fallback.
!> Everything here is pure: the matrices are at most a few hundred wide, so a plain Fortran
!> factorization costs nothing next to the sparse solves and keeps the kernels testable alone.
module lcp
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str
  implicit none
  private
  public :: spsd_solve, lcp_solve, PIVOT_RTOL

  !> A pivot below PIVOT_RTOL * (largest diagonal) marks a row dependent on the previous ones.
  !> Exactly dependent rows give pivots of a few ulps; 1e-12 leaves three decades of margin.
  real(dp), parameter :: PIVOT_RTOL = 1.0e-12_dp
  !> Block pivots tried without reducing the number of violations before falling back to Murty.
  integer, parameter :: BLOCK_TRIES = 3

contains

  !> Solve a x = b, a (n,n) symmetric positive semidefinite (full storage), by Cholesky with
  !> diagonal pivoting. Pivoting stops at the first pivot <= rtol * max(diag(a)): the remaining
  !> rows are dependent (to that tolerance) on the kept ones, their unknowns are set to zero and
  !> the kept block is solved exactly. rank = number of kept rows; dropped(j) marks the others.
  !> For a consistent right-hand side this is a solution of the full system.
  pure subroutine spsd_solve(a, b, x, rank, dropped, rtol)
    real(dp), intent(in) :: a(:, :), b(:)
    real(dp), intent(out) :: x(:)
    integer, intent(out) :: rank
    logical, intent(out), optional :: dropped(:)
    real(dp), intent(in), optional :: rtol
    real(dp), allocatable :: l(:, :), y(:), row(:)
    integer, allocatable :: p(:)
    integer :: n, k, j, i, jmax, itmp
    real(dp) :: tol, dmax

    n = size(b)
    tol = PIVOT_RTOL
    if (present(rtol)) tol = rtol
    x = 0.0_dp
    rank = 0
    if (present(dropped)) dropped = .true.
    if (n == 0) return
    l = a
    allocate (row(n))
    p = [(i, i = 1, n)]
    dmax = 0.0_dp
    do i = 1, n
      dmax = max(dmax, l(i, i))
    end do
    if (dmax <= 0.0_dp) return
    do k = 1, n
      jmax = k
      do j = k + 1, n
        if (l(j, j) > l(jmax, jmax)) jmax = j
      end do
      if (.not. (l(jmax, jmax) > tol * dmax)) exit     ! also catches NaN
      if (jmax /= k) then                              ! symmetric swap of k and jmax
        row = l(k, :)
        l(k, :) = l(jmax, :)
        l(jmax, :) = row
        row = l(:, k)
        l(:, k) = l(:, jmax)
        l(:, jmax) = row
        itmp = p(k); p(k) = p(jmax); p(jmax) = itmp
      end if
      l(k, k) = sqrt(l(k, k))
      l(k + 1:n, k) = l(k + 1:n, k) / l(k, k)
      do j = k + 1, n                                  ! Schur complement, lower triangle and diagonal
        l(j:n, j) = l(j:n, j) - l(j:n, k) * l(j, k)
        l(j, j + 1:n) = l(j + 1:n, j)                  ! keep it symmetric for the swaps above
      end do
      rank = k
    end do
    ! Forward and back substitution on the kept block (permuted order).
    y = b(p(1:rank))
    do k = 1, rank
      y(k) = (y(k) - dot_product(l(k, 1:k - 1), y(1:k - 1))) / l(k, k)
    end do
    do k = rank, 1, -1
      y(k) = (y(k) - dot_product(l(k + 1:rank, k), y(k + 1:rank))) / l(k, k)
    end do
    x(p(1:rank)) = y
    if (present(dropped)) then
      dropped = .true.
      dropped(p(1:rank)) = .false.
    end if
  end subroutine spsd_solve

  !> Solve the LCP  lam >= 0, g = q + w lam >= 0, lam'g = 0  with w (n,n) symmetric positive
  !> definite (semidefinite tolerated, see spsd_solve). tol is the gap tolerance (a length): an
  !> inactive j violates if g_j < -tol, an active j if lam_j w_jj < -tol (the gap its negative
  !> multiplier would open, so both tests are in the same units). active is the warm start on
  !> entry (the previous active set) and the solution set on exit; lam < 0 within tolerance is
  !> returned as 0. Failure (no complementary solution within max_iter pivots: infeasible or
  !> inconsistent dependent constraints) returns stat = STAT_RUN with the violations left.
  pure subroutine lcp_solve(w, q, tol, lam, g, active, iterations, stat, errmsg, max_iter)
    real(dp), intent(in) :: w(:, :), q(:), tol
    real(dp), intent(out) :: lam(:), g(:)
    logical, intent(inout) :: active(:)
    integer, intent(out) :: iterations
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, intent(in), optional :: max_iter
    logical, allocatable :: viol(:)
    integer :: n, it, maxit, nv, nbest, tries, j

    stat = STAT_OK
    n = size(q)
    iterations = 0
    if (size(w, 1) /= n .or. size(w, 2) /= n .or. size(lam) /= n .or. size(g) /= n .or. size(active) /= n) then
      call set_error(stat, errmsg, STAT_INPUT, 'lcp_solve: inconsistent sizes (n = ' // str(n) // ')')
      return
    end if
    maxit = 10 * n + 50
    if (present(max_iter)) maxit = max_iter
    allocate (viol(n))
    nbest = n + 1
    tries = BLOCK_TRIES
    do it = 1, maxit
      iterations = it
      call solve_active(w, q, active, lam, g)
      do j = 1, n
        if (active(j)) then
          viol(j) = lam(j) * w(j, j) < -tol
        else
          viol(j) = g(j) < -tol
        end if
      end do
      nv = count(viol)
      if (nv == 0) then
        lam = max(lam, 0.0_dp)
        g = q + matmul(w, lam)
        return
      end if
      if (nv < nbest) then             ! progress: exchange every violating index at once
        nbest = nv
        tries = BLOCK_TRIES
        active = active .neqv. viol
      else if (tries > 0) then
        tries = tries - 1
        active = active .neqv. viol
      else                             ! Murty: exchange the least violating index only
        j = findloc(viol, .true., 1)
        active(j) = .not. active(j)
      end if
    end do
    call set_error(stat, errmsg, STAT_RUN, 'contact LCP: no complementary solution after ' // str(maxit) // &
      ' pivots (' // str(nv) // ' conditions still violated, worst gap ' // str(minval(g)) // &
      '): infeasible or inconsistent dependent conditions')
  end subroutine lcp_solve

  !> lam_A from w_AA lam_A = -q_A, lam_I = 0, g = q + w lam. Rows of A found dependent on the
  !> others are moved out of A (lam = 0), so that their gaps are checked like any inactive one.
  pure subroutine solve_active(w, q, active, lam, g)
    real(dp), intent(in) :: w(:, :), q(:)
    logical, intent(inout) :: active(:)
    real(dp), intent(out) :: lam(:), g(:)
    integer, allocatable :: ia(:)
    real(dp), allocatable :: xa(:)
    logical, allocatable :: dropped(:)
    integer :: na, rank, i

    lam = 0.0_dp
    ia = pack([(i, i = 1, size(q))], active)
    na = size(ia)
    if (na > 0) then
      allocate (xa(na), dropped(na))
      call spsd_solve(w(ia, ia), -q(ia), xa, rank, dropped)
      lam(ia) = xa
      if (rank < na) active(pack(ia, dropped)) = .false.
    end if
    g = q + matmul(w, lam)
  end subroutine solve_active
end module lcp
