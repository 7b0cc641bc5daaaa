!> The pure kernels of the impact correction (method.md section 3): the energy error (10), the
!> root of the quadratic (13), the coupled impulses (14)-(15), the multiplier ν of the hzero
!> step (16), the PERSIST scale (section 6). The run calls them from contact; the dense forms
!> of (16) and of the PERSIST projection (hzero_reflection_dense, persist_projection_dense) are
!> the test oracles of contact's sparse hzero_reflection, which is the one the run calls.
module impact_kernels
  use kinds, only: dp
  use dense_solve, only: spsd_solve, gen_solve
  implicit none
  private
  public :: impact_energy_error, lambda_root, impulse_fixed_point, normal_multiplier, hzero_reflection_dense, &
    persist_projection_dense, persist_scale

  !> The fixed point (14) tries Newton every NEWTON_AFTER iterations once it is slow.
  integer, parameter :: NEWTON_AFTER = 30

contains

  !> (10) Energy lost by the scheme when a condition closes from the gap g_start under the
  !> multiplier lambda: E = ½ Λ g(n).
  elemental real(dp) function impact_energy_error(lambda, g_start) result(e)
    real(dp), intent(in) :: lambda, g_start
    e = 0.5_dp * lambda * g_start
  end function impact_energy_error

  !> Negative root of ½ a y² + b y - e = 0 (a > 0, e >= 0; the roots have opposite signs, their
  !> product is -2e/a). No cancellation for either sign of b: for b >= 0 the root is
  !> -(b + s)/a, for b < 0 it is -2e/(s - b), s = sqrt(b² + 2ae). e = 0 gives 0 (b < 0) or
  !> -2b/a (b >= 0). a <= 0 (no impulse possible) degrades to the linear root e/b if b < 0, else 0.
  elemental real(dp) function lambda_root(a, b, e) result(y)
    real(dp), intent(in) :: a, b, e
    real(dp) :: s
    if (a <= 0.0_dp) then
      y = 0.0_dp
      if (b < 0.0_dp) y = e / b
      return
    end if
    s = hypot(b, sqrt(2.0_dp * a * max(e, 0.0_dp)))
    if (b >= 0.0_dp) then
      y = -(b + s) / a
    else
      y = -2.0_dp * max(e, 0.0_dp) / (s - b)
    end if
  end function lambda_root

  !> (14)-(15) Coupled impulses of the n points entering contact in the same step:
  !>   ½ y_j (G y)_j + b_j y_j - e_j = 0,  G_jk = Λ_j Λ_k c_j'M⁻¹c_k,  b_j = Λ_j c_j'v(n+1),  e_j = E_j.
  !> Fixed point: each y_j is the negative root of its quadratic with the cross terms k /= j
  !> frozen at the previous iterate; the step is halved (down to 1/64) whenever the change grows
  !> (oscillation), and every NEWTON_AFTER iterations a damped Newton solve of (14) is tried.
  !> Converged when the fixed-point change max|Δy| <= tol max|y|. Finally y is scaled by the
  !> positive root t of ½ t² y'Gy + t b'y - Σe = 0, so that the total kinetic energy added,
  !> ½ y'Gy + b'y (the sum of (14) over j), is Σ e_j to round-off (t - 1 = O(change)).
  !> Strongly coupled data may have no solution with all y_j <= 0: then converged = .false.
  !> and y is the decoupled roots (13) scaled by t (total energy still exact, the split
  !> between the points is not): the caller reports it.
  pure subroutine impulse_fixed_point(g, b, e, y, iterations, change, converged, tol, max_iter, work)
    real(dp), intent(in) :: g(:, :), b(:), e(:)
    real(dp), intent(out) :: y(:)
    integer, intent(out) :: iterations
    real(dp), intent(out) :: change
    logical, intent(out) :: converged
    real(dp), intent(in), optional :: tol
    integer, intent(in), optional :: max_iter
    real(dp), intent(inout), optional :: work(:)   !< 2 n reals; without it they are allocated
    real(dp), allocatable :: w(:)
    real(dp) :: rtol
    integer :: n, maxit

    n = size(b)
    rtol = 1.0e-14_dp
    if (present(tol)) rtol = tol
    maxit = 500
    if (present(max_iter)) maxit = max_iter
    iterations = 0
    change = 0.0_dp
    converged = .true.
    y = 0.0_dp
    if (n == 0) return
    if (present(work)) then
      call iterate(y, work(1:n), work(n + 1:2 * n), iterations, change, converged)
    else
      allocate (w(2 * n))
      call iterate(y, w(1:n), w(n + 1:2 * n), iterations, change, converged)
    end if

  contains

    pure subroutine iterate(y, ynew, gy, iterations, change, converged)
      real(dp), intent(inout) :: y(:)
      real(dp), intent(out) :: ynew(:), gy(:), change
      integer, intent(out) :: iterations
      logical, intent(out) :: converged
      real(dp) :: omega, prev, qa, qb, qe, t
      integer :: it, j
      do j = 1, n                                  ! decoupled start: (13) for each point
        y(j) = lambda_root(g(j, j), b(j), e(j))
      end do
      omega = 1.0_dp
      prev = huge(1.0_dp)
      converged = .false.
      do it = 1, maxit
        iterations = it
        call sweep(y, ynew, gy, change, converged)
        if (converged) exit
        if (change > prev) omega = max(0.5_dp * omega, 1.0_dp / 64.0_dp)
        prev = change
        y = y + omega * (ynew - y)
        ! Slow (strong coupling): Newton on (14) from here, judged by the same fixed-point change.
        if (it >= NEWTON_AFTER .and. mod(it, NEWTON_AFTER) == 0) then
          call newton_14(g, b, e, y)
          call sweep(y, ynew, gy, change, converged)
          if (converged) exit
        end if
      end do
      ! (14) may have no solution with every y_j < 0 (strongly coupled points, some already
      ! separating): keep an all-negative direction, the last iterate or the decoupled roots (13).
      if (.not. converged .and. any(y > 0.0_dp)) then
        do j = 1, n
          y(j) = lambda_root(g(j, j), b(j), e(j))
        end do
      end if
      ! Exact total energy: root of ½ qa t² + qb t - qe = 0 nearest to 1 (the positive one).
      gy = matmul(g, y)
      qa = dot_product(y, gy)
      qb = dot_product(b, y)
      qe = sum(e)
      if (qa > 0.0_dp) then
        t = nearest_root(qa, qb, qe)
        y = t * y
      end if
    end subroutine iterate

    !> One Jacobi sweep of (14): each point's quadratic (13) with the others' impulses frozen
    !> at y; change = largest relative update; converged (y takes the sweep) below rtol.
    pure subroutine sweep(y, ynew, gy, change, converged)
      real(dp), intent(inout) :: y(:)
      real(dp), intent(out) :: ynew(:), gy(:), change
      logical, intent(out) :: converged
      integer :: k
      gy = matmul(g, y)
      do k = 1, n
        ynew(k) = lambda_root(g(k, k), b(k) + 0.5_dp * (gy(k) - g(k, k) * y(k)), e(k))
      end do
      change = maxval(abs(ynew - y)) / max(maxval(abs(ynew)), tiny(1.0_dp))
      converged = change <= rtol
      if (converged) y = ynew
    end subroutine sweep
  end subroutine impulse_fixed_point

  !> A few damped Newton steps on F_j(y) = ½ y_j (G y)_j + b_j y_j - e_j = 0, Jacobian
  !> J = diag(½ G y + b) + ½ diag(y) G. Leaves y unchanged where J is singular.
  pure subroutine newton_14(g, b, e, y)
    real(dp), intent(in) :: g(:, :), b(:), e(:)
    real(dp), intent(inout) :: y(:)
    real(dp), allocatable :: jac(:, :), f(:), d(:), yt(:)
    real(dp) :: fn, t
    integer :: it, j, n
    logical :: ok
    n = size(y)
    allocate (jac(n, n), d(n))
    f = residual_14(g, b, e, y)
    do it = 1, 20
      fn = norm2(f)
      if (fn == 0.0_dp) return
      do j = 1, n
        jac(j, :) = 0.5_dp * y(j) * g(j, :)
      end do
      f = matmul(g, y)
      do j = 1, n
        jac(j, j) = jac(j, j) + 0.5_dp * f(j) + b(j)
      end do
      f = residual_14(g, b, e, y)
      call gen_solve(jac, -f, d, ok)
      if (.not. ok) return
      t = 1.0_dp
      do
        yt = y + t * d
        if (norm2(residual_14(g, b, e, yt)) < (1.0_dp - 1.0e-4_dp * t) * fn .or. t < 1.0e-3_dp) exit
        t = 0.5_dp * t
      end do
      if (t < 1.0e-3_dp) return
      y = yt
      f = residual_14(g, b, e, y)
      if (maxval(abs(t * d)) <= epsilon(1.0_dp) * maxval(abs(y))) return
    end do
  end subroutine newton_14

  pure function residual_14(g, b, e, y) result(f)
    real(dp), intent(in) :: g(:, :), b(:), e(:), y(:)
    real(dp) :: f(size(y))
    f = 0.5_dp * y * matmul(g, y) + b * y - e
  end function residual_14

  !> Root of ½ a t² + b t - e = 0 (a > 0) closest to 1, computed without cancellation.
  pure real(dp) function nearest_root(a, b, e) result(t)
    real(dp), intent(in) :: a, b, e
    real(dp) :: d, q, t1, t2
    d = b * b + 2.0_dp * a * e
    if (d < 0.0_dp) then                         ! no real root (e < 0): keep the iterate
      t = 1.0_dp
      return
    end if
    q = -(b + sign(sqrt(d), b))                  ! roots: q/a and -2e/q
    if (q == 0.0_dp) then
      t = 0.0_dp
      return
    end if
    t1 = q / a
    t2 = -2.0_dp * e / q
    t = t1
    if (abs(t2 - 1.0_dp) < abs(t1 - 1.0_dp)) t = t2
  end function nearest_root

  !> ν solving (A M⁻¹A') ν = A v (amat = A M⁻¹A', av = A v): the multiplier of the hzero step
  !> (16) and of the projection of PERSIST. Dependent rows of A (duplicated conditions) are
  !> detected by the pivoted Cholesky of spsd_solve and get ν = 0; rank = independent rows.
  pure subroutine normal_multiplier(amat, av, nu, rank)
    real(dp), intent(in) :: amat(:, :), av(:)
    real(dp), intent(out) :: nu(:)
    integer, intent(out) :: rank
    call spsd_solve(amat, av, nu, rank)
  end subroutine normal_multiplier

  !> (16), dense (test oracle of contact's hzero_reflection): v <- [I - 2 M⁻¹A'(A M⁻¹A')⁻¹A] v,
  !> the M-orthogonal reflection of v about the tangent space of the conditions A, given
  !> minv_at = M⁻¹A' (n, p), amat = A M⁻¹A' (p, p), av = A v.
  pure subroutine hzero_reflection_dense(minv_at, amat, av, v, rank)
    real(dp), intent(in) :: minv_at(:, :), amat(:, :), av(:)
    real(dp), intent(inout) :: v(:)
    integer, intent(out), optional :: rank
    call normal_update_dense(2.0_dp, minv_at, amat, av, v, rank)
  end subroutine hzero_reflection_dense

  !> PERSIST step 3, dense (test oracle): v <- [I - M⁻¹A'(A M⁻¹A')⁻¹A] v, the M-orthogonal
  !> projection on zero normal velocity A v = 0 (same arguments as hzero_reflection_dense).
  pure subroutine persist_projection_dense(minv_at, amat, av, v, rank)
    real(dp), intent(in) :: minv_at(:, :), amat(:, :), av(:)
    real(dp), intent(inout) :: v(:)
    integer, intent(out), optional :: rank
    call normal_update_dense(1.0_dp, minv_at, amat, av, v, rank)
  end subroutine persist_projection_dense

  !> v <- v - factor M⁻¹A'(A M⁻¹A')⁻¹A v: factor 2 reflects (16), factor 1 projects (PERSIST).
  pure subroutine normal_update_dense(factor, minv_at, amat, av, v, rank)
    real(dp), intent(in) :: factor, minv_at(:, :), amat(:, :), av(:)
    real(dp), intent(inout) :: v(:)
    integer, intent(out), optional :: rank
    real(dp), allocatable :: nu(:)
    integer :: r
    allocate (nu(size(av)))
    call normal_multiplier(amat, av, nu, r)
    v = v - factor * matmul(minv_at, nu)
    if (present(rank)) rank = r
  end subroutine normal_update_dense

  !> PERSIST step 4: s = sqrt((T* - T_other) / T_body), the factor on the body's velocity that
  !> brings the total kinetic energy to T*. Returns 0 if T_body <= 0 or T* < T_other.
  elemental real(dp) function persist_scale(t_star, t_other, t_body) result(s)
    real(dp), intent(in) :: t_star, t_other, t_body
    s = 0.0_dp
    if (t_body > 0.0_dp .and. t_star >= t_other) s = sqrt((t_star - t_other) / t_body)
  end function persist_scale

end module impact_kernels
