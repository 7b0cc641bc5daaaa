!> The linear complementarity problem of unilateral contact (docs/contact.md)
!>     find lam >= 0 with g = q + W lam >= 0 and lam_j g_j = 0,
!> W symmetric positive (semi)definite, by block principal pivoting (Judice-Pires) with Murty's
!> least-index rule as the finite fallback. Active subsystems are solved by dense_solve's
!> spsd_solve (LAPACK pivoted Cholesky, dependent rows dropped).
!> The pivoting (lcp_pivot) works on any active_system_t: a dense W here (lcp_solve), the cached
!> Schur columns or the augmented sparse system of contact_multipliers in a run.
module lcp
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str
  use dense_solve, only: spsd_solve
  implicit none
  private
  public :: lcp_solve, lcp_pivot, active_system_t

  !> Block pivots tried without reducing the number of violations before falling back to Murty.
  integer, parameter :: BLOCK_TRIES = 3

  !> What the pivoting needs of W = C S⁻¹C' (or any SPD W): for a trial active set A,
  !> lam_A from W_AA lam_A = -q_A (lam = 0 off A; rows of A dependent on the others leave A with
  !> lam = 0), g = q + W lam, and W_jj of the active j in wdiag (the gap per unit multiplier,
  !> for the tolerance test); gaps recomputes g for a given lam.
  type, abstract :: active_system_t
  contains
    procedure(solve_active_i), deferred :: solve_active
    procedure(gaps_i), deferred :: gaps
  end type active_system_t

  abstract interface
    subroutine solve_active_i(self, q, active, lam, g, wdiag, stat, errmsg)
      import :: active_system_t, dp
      class(active_system_t), intent(inout) :: self
      real(dp), intent(in) :: q(:)
      logical, intent(inout) :: active(:)
      real(dp), intent(out) :: lam(:), g(:)
      real(dp), intent(inout) :: wdiag(:)
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine solve_active_i

    subroutine gaps_i(self, q, lam, g, stat, errmsg)
      import :: active_system_t, dp
      class(active_system_t), intent(inout) :: self
      real(dp), intent(in) :: q(:), lam(:)
      real(dp), intent(out) :: g(:)
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine gaps_i
  end interface

  !> W held dense (tests, small problems).
  type, extends(active_system_t) :: dense_system_t
    real(dp), allocatable :: w(:, :)
  contains
    procedure :: solve_active => dense_solve_active
    procedure :: gaps => dense_gaps
  end type dense_system_t

contains

  !> Solve the LCP  lam >= 0, g = q + w lam >= 0, lam'g = 0  with a dense w (n,n) symmetric
  !> positive definite (semidefinite tolerated, see spsd_solve): lcp_pivot on a dense_system_t.
  subroutine lcp_solve(w, q, tol, lam, g, active, iterations, stat, errmsg, max_iter)
    real(dp), intent(in) :: w(:, :), q(:), tol
    real(dp), intent(out) :: lam(:), g(:)
    logical, intent(inout) :: active(:)
    integer, intent(out) :: iterations
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, intent(in), optional :: max_iter
    type(dense_system_t) :: sys
    real(dp), allocatable :: wdiag(:)
    logical, allocatable :: viol(:)
    integer :: n
    n = size(q)
    iterations = 0
    if (size(w, 1) /= n .or. size(w, 2) /= n) then
      call set_error(stat, errmsg, STAT_INPUT, 'lcp_solve: inconsistent sizes (n = ' // str(n) // ')')
      return
    end if
    sys%w = w
    allocate (wdiag(n), viol(n))
    call lcp_pivot(sys, q, tol, lam, g, active, wdiag, viol, iterations, stat, errmsg, max_iter)
  end subroutine lcp_solve

  !> Block principal pivoting on any active_system_t: find lam >= 0 with g = q + W lam >= 0 and
  !> lam_j g_j = 0. tol is the gap tolerance (a length): an inactive j violates if g_j < -tol,
  !> an active j if lam_j W_jj < -tol (the gap its negative multiplier would open, so both tests
  !> are in the same units; W_jj as the system reports it in wdiag). active is the warm start
  !> on entry (the previous active set) and the solution set on exit; lam < 0 within tolerance
  !> is returned as 0 (the system then recomputes g). wdiag and viol are workspaces of size n.
  !> Failure (no complementary solution within max_iter pivots: infeasible or inconsistent
  !> dependent constraints) returns stat = STAT_RUN with the violations left. tol_free(j), when
  !> given, replaces tol in the test of an inactive j (g_j < -tol_free(j)): contact passes the
  !> tolerance left to a condition that starts the step already inside it, so that a slow
  !> approach cannot creep in by tol at every step.
  subroutine lcp_pivot(sys, q, tol, lam, g, active, wdiag, viol, iterations, stat, errmsg, max_iter, tol_free, bilateral)
    class(active_system_t), intent(inout) :: sys
    real(dp), intent(in) :: q(:), tol
    real(dp), intent(out) :: lam(:), g(:)
    logical, intent(inout) :: active(:)
    real(dp), intent(inout) :: wdiag(:)
    logical, intent(inout) :: viol(:)
    integer, intent(out) :: iterations
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, intent(in), optional :: max_iter
    real(dp), intent(in), optional :: tol_free(:)
    logical, intent(in), optional :: bilateral(:)   !< equalities: always active, multiplier of any sign
    integer :: n, it, maxit, nv, nbest, tries, j
    logical :: bil

    stat = STAT_OK
    n = size(q)
    iterations = 0
    if (size(lam) /= n .or. size(g) /= n .or. size(active) /= n .or. size(wdiag) /= n .or. size(viol) /= n) then
      call set_error(stat, errmsg, STAT_INPUT, 'lcp_pivot: inconsistent sizes (n = ' // str(n) // ')')
      return
    end if
    maxit = 10 * n + 50
    if (present(max_iter)) maxit = max_iter
    nbest = n + 1
    tries = BLOCK_TRIES
    nv = 0
    if (present(bilateral)) active = active .or. bilateral
    do it = 1, maxit
      iterations = it
      call sys%solve_active(q, active, lam, g, wdiag, stat, errmsg)
      if (stat /= STAT_OK) return
      do j = 1, n
        bil = .false.
        if (present(bilateral)) bil = bilateral(j)
        if (bil) then
          ! an equality dropped as dependent on others must still hold; kept, it never violates
          viol(j) = .not. active(j) .and. abs(g(j)) > tol
        else if (active(j)) then
          viol(j) = lam(j) * wdiag(j) < -tol
        else if (present(tol_free)) then
          viol(j) = g(j) < -tol_free(j)
        else
          viol(j) = g(j) < -tol
        end if
      end do
      nv = count(viol)
      if (nv == 0) then
        if (present(bilateral)) then
          if (any(lam < 0.0_dp .and. .not. bilateral)) then
            where (.not. bilateral) lam = max(lam, 0.0_dp)
            call sys%gaps(q, lam, g, stat, errmsg)
          end if
        else if (any(lam < 0.0_dp)) then
          lam = max(lam, 0.0_dp)
          call sys%gaps(q, lam, g, stat, errmsg)
        end if
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
  end subroutine lcp_pivot

  !> Dense W: lam_A from w_AA lam_A = -q_A, lam_I = 0, g = q + w lam. Rows of A found dependent
  !> on the others are moved out of A (lam = 0), so that their gaps are checked like any
  !> inactive one.
  subroutine dense_solve_active(self, q, active, lam, g, wdiag, stat, errmsg)
    class(dense_system_t), intent(inout) :: self
    real(dp), intent(in) :: q(:)
    logical, intent(inout) :: active(:)
    real(dp), intent(out) :: lam(:), g(:)
    real(dp), intent(inout) :: wdiag(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, allocatable :: ia(:)
    real(dp), allocatable :: xa(:)
    logical, allocatable :: dropped(:)
    integer :: na, rank, i

    stat = STAT_OK
    lam = 0.0_dp
    ia = pack([(i, i = 1, size(q))], active)
    na = size(ia)
    if (na > 0) then
      allocate (xa(na), dropped(na))
      call spsd_solve(self%w(ia, ia), -q(ia), xa, rank, dropped)
      lam(ia) = xa
      if (rank < na) active(pack(ia, dropped)) = .false.
    end if
    g = q + matmul(self%w, lam)
    do i = 1, size(q)
      wdiag(i) = self%w(i, i)
    end do
  end subroutine dense_solve_active

  subroutine dense_gaps(self, q, lam, g, stat, errmsg)
    class(dense_system_t), intent(inout) :: self
    real(dp), intent(in) :: q(:), lam(:)
    real(dp), intent(out) :: g(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    g = q + matmul(self%w, lam)
  end subroutine dense_gaps
end module lcp
