!> Unilateral contact with one Lagrange multiplier per step and the impact energy corrections
!> of method.md sections 3 and 6 (user documentation: docs/contact.md).
!>
!> A condition j is a gap g_j(u) = g0_j + c_j'u >= 0 over the free equations, c_j sparse. Per step:
!>   contact_solve_step  (every iteration) g_free = g0 + C(u_n + du_free); LCP for the step
!>                       multiplier Λ >= 0 with g = g_free + W Λ >= 0, Λ'g = 0; du = du_free + Z Λ
!>                       where Z = S⁻¹C', W = C S⁻¹ C' (S the iteration matrix K0 + 4M/h²);
!>   contact_end_step    (after eq (3)) events, E_j = ½ Λ_j g_j(n) (10), then IMPACT PAPER:
!>                       impulses (12)-(15) and the hzero reflection (16), or IMPACT PERSIST:
!>                       projection on zero normal velocity and scaling of the body; reactions
!>                       R(n+1) = Λ - R(n), reported only.
!> The pure kernels (impact_energy_error, lambda_root, impulse_fixed_point, normal_multiplier,
!> hzero_reflection, persist_projection, persist_scale) carry the equations; the rest is
!> bookkeeping around them and the linear solves.
!>
!> Linear solves go through inverse_op_t (x = A⁻¹ b): CHOLMOD factors, a diagonal, or any test
!> double; the multipliers of the LCP come from contact_multipliers (Schur columns of the active
!> conditions, or the augmented sparse system for large active sets). Do not copy a
!> contact_set_t (it may own a CHOLMOD factor of M and an UMFPACK factor): pass it by reference
!> and call contact_destroy when done. Nothing is allocated per step once the workspaces have
!> reached the largest active set of the run.
module contact
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str
  use sparse_matrix, only: sym_csc_t
  use cholmod_binding, only: cholmod_factor_t
  use inverse_ops, only: inverse_op_t, diag_inverse_t, chol_inverse_t, chol_ref_t
  use lcp, only: lcp_pivot
  use dense_solve, only: spsd_solve, spsd_solve_ws, gen_solve
  use contact_multipliers, only: multiplier_system_t, SOLVER_AUTO, SOLVER_SCHUR, SOLVER_AUGMENTED, SWITCH_DEFAULT
  implicit none
  private
  public :: IMPACT_OFF, IMPACT_PAPER, IMPACT_PERSIST, EVENT_ESTABLISH, EVENT_RELEASE, LABEL_LEN
  public :: inverse_op_t, diag_inverse_t, chol_inverse_t
  public :: SOLVER_AUTO, SOLVER_SCHUR, SOLVER_AUGMENTED, SWITCH_DEFAULT
  public :: contact_set_t, contact_event_t, contact_report_t
  public :: contact_add, contact_finalize, contact_set_mass, contact_prepare, contact_solve_step, &
    contact_end_step, contact_add_force, contact_gaps, contact_destroy, contact_w_matrix, contact_am_block, &
    contact_set_rigid_modes
  public :: impact_energy_error, lambda_root, impulse_fixed_point, normal_multiplier, hzero_reflection, &
    persist_projection, persist_scale

  !> Impact treatment (same values as scene's SCHEME IMPACT).
  integer, parameter :: IMPACT_OFF = 0, IMPACT_PAPER = 1, IMPACT_PERSIST = 2
  integer, parameter :: EVENT_ESTABLISH = 1, EVENT_RELEASE = 2
  integer, parameter :: LABEL_LEN = 48
  !> The fixed point (14) tries Newton every NEWTON_AFTER iterations once it is slow.
  integer, parameter :: NEWTON_AFTER = 30

  !> One line of events.csv.
  type :: contact_event_t
    integer :: index = 0                     !< condition
    integer :: kind = 0                      !< EVENT_ESTABLISH or EVENT_RELEASE
    real(dp) :: gap_start = 0.0_dp           !< g_j(n)
    real(dp) :: gap_end = 0.0_dp             !< g_j(n+1)
    real(dp) :: multiplier = 0.0_dp          !< Λ_j
    real(dp) :: reaction = 0.0_dp            !< R_j(n+1)
    real(dp) :: energy = 0.0_dp              !< E_j (10), restored by the correction
    real(dp) :: y = 0.0_dp                   !< impulse factor y_j = λ_j h of (13)-(14) (PAPER)
  end type contact_event_t

  !> The candidate conditions, their state and the cached operators.
  type :: contact_set_t
    integer :: nc = 0                        !< number of candidate conditions
    integer :: neq = 0                       !< free equations
    ! c_j = sum over p in ptr(j):ptr(j+1)-1 of coef(p) e_eq(p)  (CSR rows of C)
    integer, allocatable :: ptr(:), eq(:)
    real(dp), allocatable :: coef(:), g0(:)
    integer, allocatable :: nodes(:, :)      !< (2, nc) node_a, node_b (0: rigid obstacle)
    character(len=LABEL_LEN), allocatable :: label(:)
    ! State.
    logical, allocatable :: active(:)        !< active at the end of the last step
    logical, allocatable :: active_iter(:)   !< active set of the last LCP (warm start of the next)
    real(dp), allocatable :: lambda(:)       !< step multiplier Λ of the last LCP
    real(dp), allocatable :: r_prev(:)       !< physical reaction R(n) at the end of the last step
    real(dp), allocatable :: gap_n(:)        !< g(n) = g0 + C u_n of the last solve
    real(dp), allocatable :: gap(:)          !< g(n+1) of the last LCP
    integer :: lcp_iterations = 0            !< pivots of the last LCP
    ! Multipliers and operators.
    logical :: finalized = .false., prepared = .false., mass_set = .false.
    type(multiplier_system_t) :: ms          !< W = C S⁻¹C' for the LCP (Schur columns or augmented)
    class(inverse_op_t), allocatable :: minv !< M⁻¹
    ! Events of the last contact_end_step: events(1:n_events).
    type(contact_event_t), allocatable :: events(:)
    integer :: n_events = 0
    ! Workspaces (sized at contact_finalize; the dense ones grow with the largest active set).
    real(dp), allocatable :: wq(:), wdiag(:), gn(:), gend(:), e(:), y(:), r(:), mu(:)
    logical, allocatable :: viol(:), now(:), est(:), rel(:), fallback(:), rows(:)
    integer, allocatable :: idx(:), cgroup(:), parent(:)
    real(dp), allocatable :: f(:), xw(:), vp(:), mvp(:), ct(:)
    real(dp), allocatable :: amat(:, :), gmat(:, :), sv(:), work2(:)
    ! Rigid translations t_k (neq, 2) on the free equations and M t_k (contact_set_rigid_modes):
    ! PERSIST scales node-to-node groups about their centre-of-mass velocity.
    logical :: has_rigid = .false.
    real(dp), allocatable :: rig(:, :), mrig(:, :)
    integer, allocatable :: ipiv(:)
    ! Settings (set before contact_finalize / contact_prepare to change them).
    real(dp) :: length_scale = 1.0_dp        !< model size; gap tolerance = gap_rtol * length_scale
    real(dp) :: gap_rtol = 1.0e-12_dp
    real(dp) :: fp_tol = 1.0e-14_dp          !< relative change ending the impulse fixed point
    integer :: fp_max_iter = 500
    real(dp) :: persist_min_fraction = 1.0e-6_dp  !< PERSIST falls back to PAPER below this T_body/T*
    integer :: solver = SOLVER_AUTO          !< multipliers: SOLVER_AUTO, SOLVER_SCHUR or SOLVER_AUGMENTED
    integer :: switch_size = SWITCH_DEFAULT  !< AUTO: augmented above this many active conditions
    integer(8) :: z_max_entries = 8388608_8  !< 64 MB: initial size of the Schur column cache
  end type contact_set_t

  !> Summary of one contact_end_step.
  type :: contact_report_t
    integer :: n_active = 0, n_establish = 0, n_release = 0
    real(dp) :: energy_error = 0.0_dp        !< Σ E_j over the established conditions
    real(dp) :: energy_restored = 0.0_dp     !< kinetic energy added, measured
    real(dp) :: scheme_work = 0.0_dp         !< ½ Λ'C du: the work the scheme counts for the multiplier
    integer :: fp_iterations = 0             !< impulse fixed point (14)
    real(dp) :: fp_change = 0.0_dp           !< its final relative change
    integer :: fp_failures = 0               !< 1 if (14) had no all-negative solution (see impulse_fixed_point)
    integer :: persist_groups = 0, persist_fallbacks = 0
    integer :: reflection_rank = 0           !< rank of A M⁻¹A' in (16) (< rows: dependent rows)
  end type contact_report_t

  interface contact_set_mass
    module procedure set_mass_diag, set_mass_chol, set_mass_op
  end interface contact_set_mass

  interface contact_prepare
    module procedure prepare_chol, prepare_op
  end interface contact_prepare

  interface contact_solve_step
    module procedure solve_step_chol, solve_step_op
  end interface contact_solve_step

contains

  ! ---------------------------------------------------------------------------------------
  ! Kernels
  ! ---------------------------------------------------------------------------------------

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

  !> (16) v <- [I - 2 M⁻¹A'(A M⁻¹A')⁻¹A] v, the M-orthogonal reflection of v about the tangent
  !> space of the conditions A, given minv_at = M⁻¹A' (n, p), amat = A M⁻¹A' (p, p), av = A v.
  pure subroutine hzero_reflection(minv_at, amat, av, v, rank)
    real(dp), intent(in) :: minv_at(:, :), amat(:, :), av(:)
    real(dp), intent(inout) :: v(:)
    integer, intent(out), optional :: rank
    real(dp), allocatable :: nu(:)
    integer :: r
    allocate (nu(size(av)))
    call normal_multiplier(amat, av, nu, r)
    v = v - 2.0_dp * matmul(minv_at, nu)
    if (present(rank)) rank = r
  end subroutine hzero_reflection

  !> PERSIST step 3: v <- [I - M⁻¹A'(A M⁻¹A')⁻¹A] v, the M-orthogonal projection on zero normal
  !> velocity A v = 0 (same arguments as hzero_reflection).
  pure subroutine persist_projection(minv_at, amat, av, v, rank)
    real(dp), intent(in) :: minv_at(:, :), amat(:, :), av(:)
    real(dp), intent(inout) :: v(:)
    integer, intent(out), optional :: rank
    real(dp), allocatable :: nu(:)
    integer :: r
    allocate (nu(size(av)))
    call normal_multiplier(amat, av, nu, r)
    v = v - matmul(minv_at, nu)
    if (present(rank)) rank = r
  end subroutine persist_projection

  !> PERSIST step 4: s = sqrt((T* - T_other) / T_body), the factor on the body's velocity that
  !> brings the total kinetic energy to T*. Returns 0 if T_body <= 0 or T* < T_other.
  elemental real(dp) function persist_scale(t_star, t_other, t_body) result(s)
    real(dp), intent(in) :: t_star, t_other, t_body
    s = 0.0_dp
    if (t_body > 0.0_dp .and. t_star >= t_other) s = sqrt((t_star - t_other) / t_body)
  end function persist_scale

  ! ---------------------------------------------------------------------------------------
  ! Building the set
  ! ---------------------------------------------------------------------------------------

  !> Append the condition g0 + Σ coefs(k) u(eqs(k)) >= 0. Entries with eqs(k) <= 0 (supported
  !> or absent DOFs) are skipped. nodes = [node_a, node_b] (0 for a rigid obstacle) and label
  !> name it in messages and events. Storage grows geometrically (tens of thousands of
  !> candidates are added in linear time).
  pure subroutine contact_add(cs, g0, eqs, coefs, nodes, label)
    type(contact_set_t), intent(inout) :: cs
    real(dp), intent(in) :: g0
    integer, intent(in) :: eqs(:)
    real(dp), intent(in) :: coefs(:)
    integer, intent(in), optional :: nodes(2)
    character(len=*), intent(in), optional :: label
    integer :: k, nz, nc

    if (.not. allocated(cs%ptr)) call reserve(cs, 16, 64)
    nc = cs%nc + 1
    nz = cs%ptr(cs%nc + 1)
    call reserve(cs, nc, nz - 1 + size(eqs))
    do k = 1, min(size(eqs), size(coefs))
      if (eqs(k) > 0 .and. coefs(k) /= 0.0_dp) then
        cs%eq(nz) = eqs(k)
        cs%coef(nz) = coefs(k)
        nz = nz + 1
      end if
    end do
    cs%nc = nc
    cs%ptr(nc + 1) = nz
    cs%g0(nc) = g0
    cs%nodes(:, nc) = 0
    if (present(nodes)) cs%nodes(:, nc) = nodes
    cs%label(nc) = 'condition ' // str(nc)
    if (present(label)) cs%label(nc) = label
  end subroutine contact_add

  !> Room for nc conditions and nz entries of C (doubling).
  pure subroutine reserve(cs, nc, nz)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: nc, nz
    integer, allocatable :: i1(:), i2(:, :)
    real(dp), allocatable :: r1(:)
    character(len=LABEL_LEN), allocatable :: l1(:)
    integer :: m
    if (.not. allocated(cs%ptr)) then
      allocate (cs%ptr(nc + 1), cs%g0(nc), cs%nodes(2, nc), cs%label(nc), cs%eq(nz), cs%coef(nz))
      cs%ptr(1) = 1
      return
    end if
    if (size(cs%g0) < nc) then
      m = max(nc, 2 * size(cs%g0))
      allocate (i1(m + 1), r1(m), i2(2, m), l1(m))
      i1(1:cs%nc + 1) = cs%ptr(1:cs%nc + 1)
      r1(1:cs%nc) = cs%g0(1:cs%nc)
      i2(:, 1:cs%nc) = cs%nodes(:, 1:cs%nc)
      l1(1:cs%nc) = cs%label(1:cs%nc)
      call move_alloc(i1, cs%ptr)
      call move_alloc(r1, cs%g0)
      call move_alloc(i2, cs%nodes)
      call move_alloc(l1, cs%label)
    end if
    if (size(cs%eq) < nz) then
      m = max(nz, 2 * size(cs%eq))
      allocate (i1(m), r1(m))
      i1(1:size(cs%eq)) = cs%eq
      r1(1:size(cs%coef)) = cs%coef
      call move_alloc(i1, cs%eq)
      call move_alloc(r1, cs%coef)
    end if
  end subroutine reserve

  !> Check the conditions against neq free equations, set the model size (length_scale > 0,
  !> e.g. the bounding-box diagonal; tolerances are relative to it) and allocate the state and
  !> the workspaces: nothing active, no reaction. The initial gaps are the driver's (scene)
  !> business. cs%solver and cs%switch_size are read here.
  subroutine contact_finalize(cs, neq, length_scale, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: neq
    real(dp), intent(in) :: length_scale
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: j, nc, nz
    stat = STAT_OK
    if (.not. allocated(cs%ptr)) call reserve(cs, 0, 0)
    nc = cs%nc
    nz = cs%ptr(nc + 1) - 1
    ! Trim the growth reserve.
    cs%ptr = cs%ptr(1:nc + 1)
    cs%g0 = cs%g0(1:nc)
    cs%nodes = cs%nodes(:, 1:nc)
    cs%label = cs%label(1:nc)
    cs%eq = cs%eq(1:nz)
    cs%coef = cs%coef(1:nz)
    if (.not. (length_scale > 0.0_dp)) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact: the model size must be positive, got ' // str(length_scale))
      return
    end if
    do j = 1, nc
      if (any(cs%eq(cs%ptr(j):cs%ptr(j + 1) - 1) > neq)) then
        call set_error(stat, errmsg, STAT_INPUT, 'contact: ' // trim(cs%label(j)) // ' refers to an equation beyond ' &
          // str(neq))
        return
      end if
    end do
    cs%neq = neq
    cs%length_scale = length_scale
    if (allocated(cs%active)) deallocate (cs%active, cs%active_iter, cs%lambda, cs%r_prev, cs%gap_n, cs%gap)
    allocate (cs%active(nc), cs%active_iter(nc), cs%lambda(nc), cs%r_prev(nc), cs%gap_n(nc), cs%gap(nc))
    cs%active = .false.
    cs%active_iter = .false.
    cs%lambda = 0.0_dp
    cs%r_prev = 0.0_dp
    cs%gap_n = cs%g0
    cs%gap = cs%g0
    if (allocated(cs%wq)) deallocate (cs%wq, cs%wdiag, cs%gn, cs%gend, cs%e, cs%y, cs%r, cs%mu, cs%viol, cs%now, &
      cs%est, cs%rel, cs%fallback, cs%idx, cs%cgroup, cs%f, cs%xw, cs%vp, cs%mvp, cs%rows, cs%events, cs%sv, cs%ct, &
      cs%work2, cs%ipiv)
    allocate (cs%wq(nc), cs%wdiag(nc), cs%gn(nc), cs%gend(nc), cs%e(nc), cs%y(nc), cs%r(nc), cs%mu(nc), cs%viol(nc), &
      cs%now(nc), cs%est(nc), cs%rel(nc), cs%fallback(nc), cs%idx(nc), cs%cgroup(nc), cs%events(nc), cs%sv(nc), &
      cs%ct(nc), cs%work2(2 * nc), cs%ipiv(nc))
    if (allocated(cs%parent)) deallocate (cs%parent)
    cs%has_rigid = .false.
    allocate (cs%f(neq), cs%xw(neq), cs%vp(neq), cs%mvp(neq), cs%rows(neq), cs%parent(neq))  ! bodies <= neq
    if (allocated(cs%amat)) deallocate (cs%amat, cs%gmat)
    ! Dense blocks for up to 64 conditions established together; they grow beyond (rarely).
    allocate (cs%amat(min(nc, 64), min(nc, 64)), cs%gmat(min(nc, 64), min(nc, 64)))
    cs%wdiag = 1.0_dp
    cs%n_events = 0
    cs%ms%mode = cs%solver
    cs%ms%switch_size = cs%switch_size
    call cs%ms%init(nc, neq, cs%ptr, cs%eq, cs%coef, &
      int(min(int(max(nc, 1), 8), max(8_8, min(int(cs%switch_size, 8), cs%z_max_entries / max(neq, 1))))))
    cs%finalized = .true.
    cs%prepared = .false.
  end subroutine contact_finalize

  !> Free the caches and the factors.
  subroutine contact_destroy(cs)
    type(contact_set_t), intent(inout) :: cs
    if (allocated(cs%minv)) call contact_destroy_mass(cs)
    call cs%ms%destroy()
    cs%prepared = .false.
    cs%mass_set = .false.
  end subroutine contact_destroy

  ! ---------------------------------------------------------------------------------------
  ! Sparse rows of C
  ! ---------------------------------------------------------------------------------------

  !> g = g0 + C u.
  pure subroutine contact_gaps(cs, u, g)
    type(contact_set_t), intent(in) :: cs
    real(dp), intent(in) :: u(:)
    real(dp), intent(out) :: g(:)
    integer :: j
    do j = 1, cs%nc
      g(j) = cs%g0(j) + row_dot(cs, j, u)
    end do
  end subroutine contact_gaps

  !> f <- f + C'Λ with the multiplier of the last contact_solve_step: the contact force on the
  !> right of (5)/(9), for the driver's residual.
  pure subroutine contact_add_force(cs, f)
    type(contact_set_t), intent(in) :: cs
    real(dp), intent(inout) :: f(:)
    if (cs%nc == 0 .or. .not. allocated(cs%lambda)) return
    call ct_add(cs, cs%lambda, f)
  end subroutine contact_add_force

  !> cx = C x (all rows).
  pure subroutine c_times(cs, x, cx)
    type(contact_set_t), intent(in) :: cs
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: cx(:)
    integer :: j
    do j = 1, cs%nc
      cx(j) = row_dot(cs, j, x)
    end do
  end subroutine c_times

  pure real(dp) function row_dot(cs, j, x)
    type(contact_set_t), intent(in) :: cs
    integer, intent(in) :: j
    real(dp), intent(in) :: x(:)
    integer :: p
    row_dot = 0.0_dp
    do p = cs%ptr(j), cs%ptr(j + 1) - 1
      row_dot = row_dot + cs%coef(p) * x(cs%eq(p))
    end do
  end function row_dot

  !> f <- f + C' mu  (mu over all nc conditions).
  pure subroutine ct_add(cs, mu, f)
    type(contact_set_t), intent(in) :: cs
    real(dp), intent(in) :: mu(:)
    real(dp), intent(inout) :: f(:)
    integer :: j, p
    do j = 1, cs%nc
      if (mu(j) == 0.0_dp) cycle
      do p = cs%ptr(j), cs%ptr(j + 1) - 1
        f(cs%eq(p)) = f(cs%eq(p)) + cs%coef(p) * mu(j)
      end do
    end do
  end subroutine ct_add

  !> a(1:n, 1:n) = C_idx M⁻¹ C_idx' for the conditions idx(1:n): the blocks of A M⁻¹A' that the
  !> impulse (14) and the reflection (16) need. Lumped mass: from the sparse rows directly;
  !> otherwise one solve with M per condition. Symmetrized.
  subroutine contact_am_block(cs, idx, n, a, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: idx(:), n
    real(dp), intent(out) :: a(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, l, p, q
    stat = STAT_OK
    select type (op => cs%minv)
    type is (diag_inverse_t)
      do l = 1, n
        do k = 1, l
          a(k, l) = 0.0_dp
          do p = cs%ptr(idx(k)), cs%ptr(idx(k) + 1) - 1
            do q = cs%ptr(idx(l)), cs%ptr(idx(l) + 1) - 1
              if (cs%eq(p) /= cs%eq(q)) cycle
              if (.not. (op%d(cs%eq(p)) > 0.0_dp)) then
                call set_error(stat, errmsg, STAT_INPUT, 'contact: equation ' // str(cs%eq(p)) // &
                  ' carries a contact condition but has no mass (lumped mass diagonal ' // str(op%d(cs%eq(p))) // ')')
                return
              end if
              a(k, l) = a(k, l) + cs%coef(p) * cs%coef(q) / op%d(cs%eq(p))
            end do
          end do
          a(l, k) = a(k, l)
        end do
      end do
    class default
      do l = 1, n
        cs%f = 0.0_dp
        do p = cs%ptr(idx(l)), cs%ptr(idx(l) + 1) - 1
          cs%f(cs%eq(p)) = cs%f(cs%eq(p)) + cs%coef(p)
        end do
        call cs%minv%apply(cs%f, cs%xw, stat, errmsg)
        if (stat /= STAT_OK) return
        do k = 1, n
          a(k, l) = row_dot(cs, idx(k), cs%xw)
        end do
      end do
      do l = 1, n
        do k = 1, l - 1
          a(k, l) = 0.5_dp * (a(k, l) + a(l, k))
          a(l, k) = a(k, l)
        end do
      end do
    end select
  end subroutine contact_am_block

  !> W = C S⁻¹ C' over every candidate (nc solves; diagnostics and tests, not the run).
  subroutine contact_w_matrix(cs, s, w, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    class(inverse_op_t), intent(inout), target :: s
    real(dp), intent(out) :: w(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: j
    stat = STAT_OK
    cs%ms%s => s
    do j = 1, cs%nc
      call cs%ms%column(j, cs%xw, stat, errmsg)
      if (stat /= STAT_OK) exit
      call c_times(cs, cs%xw, w(:, j))
    end do
    nullify (cs%ms%s)
    w = 0.5_dp * (w + transpose(w))
  end subroutine contact_w_matrix

  ! ---------------------------------------------------------------------------------------
  ! Mass and iteration-matrix operators
  ! ---------------------------------------------------------------------------------------

  !> Lumped mass: M = diag(mdiag).
  subroutine set_mass_diag(cs, mdiag, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    real(dp), intent(in) :: mdiag(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(diag_inverse_t) :: op
    allocate (op%d, source=mdiag)
    call set_mass_op(cs, op, stat, errmsg)
  end subroutine set_mass_diag

  !> Consistent mass (pattern, values): factorized with CHOLMOD and kept in cs; M must be
  !> positive definite on every free equation.
  subroutine set_mass_chol(cs, pat, mval, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    type(sym_csc_t), intent(in) :: pat
    real(dp), intent(in), contiguous :: mval(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: minor
    if (allocated(cs%minv)) call contact_destroy_mass(cs)
    allocate (chol_inverse_t :: cs%minv)
    select type (op => cs%minv)
    type is (chol_inverse_t)
      call op%f%factorize(pat, mval, stat, errmsg, minor)
      if (stat /= STAT_OK) then
        call set_error(stat, errmsg, STAT_INPUT, 'contact with a consistent mass needs M positive definite: ' // &
          'zero or negative mass pivot at equation ' // str(minor) // ' (' // errmsg // ')')
        return
      end if
    end select
    call finish_mass(cs, stat, errmsg)
  end subroutine set_mass_chol

  !> Any M⁻¹ operator (tests, special masses); op is copied into cs.
  subroutine set_mass_op(cs, op, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    class(inverse_op_t), intent(in) :: op
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    if (allocated(cs%minv)) call contact_destroy_mass(cs)
    allocate (cs%minv, source=op)
    call finish_mass(cs, stat, errmsg)
  end subroutine set_mass_op

  subroutine contact_destroy_mass(cs)
    type(contact_set_t), intent(inout) :: cs
    select type (op => cs%minv)
    type is (chol_inverse_t)
      call op%f%destroy()
    end select
    deallocate (cs%minv)
    cs%mass_set = .false.
  end subroutine contact_destroy_mass

  !> Every condition must see a mass: check the diagonal of A M⁻¹A' (n solves with a
  !> consistent mass, once per run).
  subroutine finish_mass(cs, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: a(1, 1)
    integer :: j
    stat = STAT_OK
    if (.not. cs%finalized) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_set_mass: call contact_finalize first')
      return
    end if
    select type (op => cs%minv)
    type is (diag_inverse_t)
      do j = 1, cs%nc
        call contact_am_block(cs, [j], 1, a, stat, errmsg)
        if (stat /= STAT_OK) return
      end do
    end select
    cs%mass_set = .true.
  end subroutine finish_mass

  !> A new iteration matrix S = K0 + 4M/h² (per step size, or per iteration with TANGENT), the
  !> driver's CHOLMOD factor: the cached Schur columns are dropped. pat and sval (the pattern
  !> and values of S) enable the augmented system; without them only SOLVER_SCHUR works.
  subroutine prepare_chol(cs, s, stat, errmsg, pat, sval)
    type(contact_set_t), intent(inout) :: cs
    type(cholmod_factor_t), intent(inout), target :: s
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(sym_csc_t), intent(in), optional :: pat
    real(dp), intent(in), optional :: sval(:)
    type(chol_ref_t) :: op
    op%f => s
    call prepare_op(cs, op, stat, errmsg, pat, sval)
  end subroutine prepare_chol

  !> Same with any S⁻¹ operator.
  subroutine prepare_op(cs, s, stat, errmsg, pat, sval)
    type(contact_set_t), intent(inout) :: cs
    class(inverse_op_t), intent(inout) :: s
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(sym_csc_t), intent(in), optional :: pat
    real(dp), intent(in), optional :: sval(:)
    stat = STAT_OK
    if (.not. cs%finalized) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_prepare: call contact_finalize first')
      return
    end if
    cs%prepared = .false.
    if (cs%nc > 0) then
      call cs%ms%prepare(stat, errmsg, pat, sval)
      if (stat /= STAT_OK) return
    end if
    cs%prepared = .true.
  end subroutine prepare_op

  !> The rigid translations of the model on the free equations, t (neq, 2) (1 on the UX, resp.
  !> UY, equation of every node, 0 elsewhere) and mt = M t. With them PERSIST scales a group
  !> linked only by node-to-node conditions about its centre-of-mass velocity, which keeps its
  !> momentum (docs/contact.md).
  subroutine contact_set_rigid_modes(cs, t, mt, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    real(dp), intent(in) :: t(:, :), mt(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (.not. cs%finalized .or. size(t, 1) /= cs%neq .or. any(shape(mt) /= shape(t)) .or. size(t, 2) /= 2) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_set_rigid_modes: call contact_finalize first; t and M t ' // &
        'must be (neq, 2)')
      return
    end if
    cs%rig = t
    cs%mrig = mt
    cs%has_rigid = .true.
  end subroutine contact_set_rigid_modes

  ! ---------------------------------------------------------------------------------------
  ! The step
  ! ---------------------------------------------------------------------------------------

  !> One iteration of the step: with u_n the displacement at the start of the step and du_free
  !> the update without contact forces, find the step multiplier lambda (LCP) and the constrained
  !> update du = du_free + S⁻¹C'Λ; s is the factor of the S given to contact_prepare.
  subroutine solve_step_chol(cs, s, u_n, du_free, du, lambda, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    type(cholmod_factor_t), intent(inout), target :: s
    real(dp), intent(in) :: u_n(:), du_free(:)
    real(dp), intent(out) :: du(:)
    real(dp), intent(out) :: lambda(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(chol_ref_t), target :: op
    op%f => s
    call solve_step_op(cs, op, u_n, du_free, du, lambda, stat, errmsg)
  end subroutine solve_step_chol

  subroutine solve_step_op(cs, s, u_n, du_free, du, lambda, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    class(inverse_op_t), intent(inout), target :: s
    real(dp), intent(in) :: u_n(:), du_free(:)
    real(dp), intent(out) :: du(:)
    real(dp), intent(out) :: lambda(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: j

    stat = STAT_OK
    du = du_free
    if (.not. cs%prepared) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_solve_step: call contact_prepare first')
      return
    end if
    if (size(lambda) /= cs%nc .or. size(u_n) /= cs%neq .or. size(du_free) /= cs%neq .or. size(du) /= cs%neq) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_solve_step: size mismatch (' // str(cs%neq) // &
        ' equations, ' // str(cs%nc) // ' conditions)')
      return
    end if
    lambda = 0.0_dp
    if (cs%nc == 0) return
    call contact_gaps(cs, u_n, cs%gap_n)
    ! A condition that starts the step slightly penetrated (within the input tolerance, or by
    ! the LCP tolerance at an earlier release) is held where it is, not pushed out: its target
    ! is g(n+1) >= g(n). Pushing it out would let the multiplier do the work ½ Λ |g(n)|, which
    ! E_j = ½ Λ max(g(n), 0) of eq (10) cannot take back: energy created.
    do j = 1, cs%nc
      cs%wq(j) = max(cs%gap_n(j), 0.0_dp) + row_dot(cs, j, du_free)
    end do
    cs%ms%s => s
    call lcp_pivot(cs%ms, cs%wq, cs%gap_rtol * cs%length_scale, cs%lambda, cs%gap, cs%active_iter, cs%wdiag, &
      cs%viol, cs%lcp_iterations, stat, errmsg)
    if (stat /= STAT_OK) then
      nullify (cs%ms%s)
      errmsg = errmsg // ' (' // str(count(cs%active_iter)) // ' conditions in the last active set)'
      return
    end if
    lambda = cs%lambda
    if (any(cs%lambda > 0.0_dp)) then
      call cs%ms%correction(cs%lambda, cs%xw, stat, errmsg)
      if (stat == STAT_OK) du = du + cs%xw
    end if
    nullify (cs%ms%s)
  end subroutine solve_step_op

  !> End of a converged step, after eq (3) gave v = v(n+1) and mv = M v(n+1):
  !>   events (established: active now and not at the end of the last step; released: the
  !>   reverse), E_j = ½ Λ_j max(g_j(n), 0) (10) for the established ones, then the correction
  !>   of the mode (IMPACT_OFF: none; IMPACT_PAPER: (12)-(15) then (16); IMPACT_PERSIST: section 6,
  !>   falling back to PAPER for bodies left without kinetic energy), reactions R(n+1) = Λ - R(n)
  !>   (0 for inactive conditions), new state. v and mv are updated together (mv stays M v).
  !>   body(i) is the mesh-connected component of equation i (0: none), required by PERSIST.
  !>   energy_restored = kinetic energy added, measured (= Σ E_j to round-off). The events of
  !>   the step are cs%events(1:cs%n_events).
  subroutine contact_end_step(cs, mode, u_n, du, v, mv, energy_restored, stat, errmsg, body, report)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: mode
    real(dp), intent(in) :: u_n(:), du(:)
    real(dp), intent(inout) :: v(:), mv(:)
    real(dp), intent(out) :: energy_restored
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, intent(in), optional :: body(:)
    type(contact_report_t), intent(out), optional :: report
    type(contact_report_t) :: rep
    real(dp) :: t_before
    integer :: j, k

    stat = STAT_OK
    energy_restored = 0.0_dp
    cs%n_events = 0
    if (.not. cs%finalized) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_end_step: call contact_finalize first')
      return
    end if
    if (cs%nc == 0) then
      if (present(report)) report = rep
      return
    end if
    if (mode /= IMPACT_OFF .and. .not. cs%mass_set) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_end_step: call contact_set_mass first')
      return
    end if
    associate (gn => cs%gn, gend => cs%gend, now => cs%now, est => cs%est, rel => cs%rel, e => cs%e, y => cs%y)
      call contact_gaps(cs, u_n, gn)
      do j = 1, cs%nc
        gend(j) = gn(j) + row_dot(cs, j, du)
      end do
      now = cs%active_iter
      est = now .and. .not. cs%active
      rel = cs%active .and. .not. now
      y = 0.0_dp
      e = 0.0_dp
      where (est) e = impact_energy_error(cs%lambda, max(gn, 0.0_dp))
      rep%n_active = count(now)
      rep%n_establish = count(est)
      rep%n_release = count(rel)
      rep%energy_error = sum(e)
      rep%scheme_work = 0.5_dp * dot_product(cs%lambda, gend - gn)
      t_before = 0.5_dp * dot_product(v, mv)

      if (rep%n_establish > 0) then
        select case (mode)
        case (IMPACT_PAPER)
          call paper_correction(cs, est, v, mv, rep, stat, errmsg)
        case (IMPACT_PERSIST)
          if (.not. present(body)) then
            call set_error(stat, errmsg, STAT_INPUT, 'contact_end_step: IMPACT PERSIST needs body(:)')
            return
          end if
          call persist_correction(cs, body, v, mv, rep, stat, errmsg)
          if (stat == STAT_OK .and. any(cs%fallback)) then
            cs%est = cs%fallback
            call paper_correction(cs, cs%est, v, mv, rep, stat, errmsg)
            cs%est = now .and. .not. cs%active
          end if
        case (IMPACT_OFF)
        case default
          call set_error(stat, errmsg, STAT_INPUT, 'contact_end_step: unknown impact mode ' // str(mode))
        end select
        if (stat /= STAT_OK) return
        if (mode /= IMPACT_OFF) energy_restored = 0.5_dp * dot_product(v, mv) - t_before
      end if
      rep%energy_restored = energy_restored

      ! Reactions (reported only) and the new state.
      cs%r = merge(cs%lambda - cs%r_prev, 0.0_dp, now)
      k = 0
      do j = 1, cs%nc
        if (.not. (est(j) .or. rel(j))) cycle
        k = k + 1
        cs%events(k) = contact_event_t(j, merge(EVENT_ESTABLISH, EVENT_RELEASE, est(j)), gn(j), gend(j), &
          cs%lambda(j), cs%r(j), e(j), y(j))
      end do
      cs%n_events = k
      cs%r_prev = cs%r
      cs%active = now
      cs%gap_n = gend
    end associate
    if (present(report)) report = rep
  end subroutine contact_end_step

  !> Dense workspaces amat and gmat at least n x n (they only grow).
  subroutine reserve_dense(cs, n)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: n
    integer :: m
    if (size(cs%amat, 1) >= n) return
    m = max(n, 2 * size(cs%amat, 1))
    deallocate (cs%amat, cs%gmat)
    allocate (cs%amat(m, m), cs%gmat(m, m))
  end subroutine reserve_dense

  !> (12)-(16) for the conditions sel (all established in the step): impulses by the fixed
  !> point (14)-(15) for those with Λ_j > 0, Δv = M⁻¹ Σ y_j Λ_j c_j, then the hzero reflection
  !> about all of them. Uses cs%e (E_j) and sets cs%y (y_j).
  subroutine paper_correction(cs, sel, v, mv, rep, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    logical, intent(in) :: sel(:)
    real(dp), intent(inout) :: v(:), mv(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: change
    integer :: j, k, n, iters, rank
    logical :: conv

    stat = STAT_OK
    n = 0
    do j = 1, cs%nc
      if (.not. (sel(j) .and. cs%lambda(j) > 0.0_dp)) cycle
      n = n + 1
      cs%idx(n) = j
    end do
    call reserve_dense(cs, n)
    if (n > 0) then
      associate (ip => cs%idx(1:n), g => cs%gmat(1:n, 1:n))
        call contact_am_block(cs, ip, n, g, stat, errmsg)
        if (stat /= STAT_OK) return
        do k = 1, n
          g(:, k) = g(:, k) * cs%lambda(ip) * cs%lambda(ip(k))
          cs%sv(k) = cs%lambda(ip(k)) * row_dot(cs, ip(k), v)
          cs%ct(k) = cs%e(ip(k))
        end do
        call impulse_fixed_point(g, cs%sv(1:n), cs%ct(1:n), cs%wq(1:n), iters, change, conv, cs%fp_tol, &
          cs%fp_max_iter, cs%work2)
        rep%fp_iterations = rep%fp_iterations + iters
        rep%fp_change = max(rep%fp_change, change)
        if (.not. conv) rep%fp_failures = rep%fp_failures + 1     ! reported, energy still exact
        cs%mu = 0.0_dp
        do k = 1, n
          cs%y(ip(k)) = cs%wq(k)
          cs%mu(ip(k)) = cs%wq(k) * cs%lambda(ip(k))
        end do
      end associate
      call add_minv_ct(cs, cs%mu, 1.0_dp, v, mv, stat, errmsg)          ! (12)
      if (stat /= STAT_OK) return
    end if
    ! (16) hzero reflection about every condition established in the step.
    n = 0
    do j = 1, cs%nc
      if (.not. sel(j)) cycle
      n = n + 1
      cs%idx(n) = j
    end do
    call normal_multiplier_ws(cs, n, v, rank, stat, errmsg)
    if (stat /= STAT_OK) return
    rep%reflection_rank = rank
    call add_minv_ct(cs, cs%mu, -2.0_dp, v, mv, stat, errmsg)
  end subroutine paper_correction

  !> ν with (A M⁻¹A') ν = A v for the conditions A = cs%idx(1:n), into cs%mu (0 elsewhere): the
  !> multiplier of the hzero step (16) and of the PERSIST projection. normal_multiplier in the
  !> workspaces of cs (no allocation), with A M⁻¹A' from contact_am_block.
  subroutine normal_multiplier_ws(cs, n, v, rank, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: n
    real(dp), intent(in) :: v(:)
    integer, intent(out) :: rank
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k
    rank = 0
    call reserve_dense(cs, n)
    call contact_am_block(cs, cs%idx(1:n), n, cs%amat(1:n, 1:n), stat, errmsg)
    if (stat /= STAT_OK) return
    do k = 1, n
      cs%sv(k) = row_dot(cs, cs%idx(k), v)
    end do
    call spsd_solve_ws(n, cs%amat, cs%sv, rank, cs%ipiv, cs%work2)
    cs%mu = 0.0_dp
    do k = 1, n
      cs%mu(cs%idx(k)) = cs%sv(k)
    end do
  end subroutine normal_multiplier_ws

  !> Section 6. Groups: bodies linked by active conditions. For each group holding an
  !> established condition: project on zero normal velocity of all its active conditions, then
  !> scale its velocity so that its kinetic energy is T1_group + Σ E_j. Groups whose projected
  !> kinetic energy is below persist_min_fraction of that target, or conditions on equations
  !> without body, are left untouched and returned in cs%fallback (their established conditions).
  subroutine persist_correction(cs, body, v, mv, rep, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: body(:)
    real(dp), intent(inout) :: v(:), mv(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: nb, j, p, bj, i, grp, rank, n
    real(dp) :: t1, tp, tstar, s, acm(2), tcm, vcm, mvcm

    stat = STAT_OK
    cs%fallback = .false.
    if (size(body) /= cs%neq) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_end_step: body(:) must have one entry per equation')
      return
    end if
    nb = 0
    if (cs%neq > 0) nb = max(maxval(body), 0)
    if (size(cs%parent) < nb) then                 ! sized neq at contact_finalize: never
      deallocate (cs%parent)
      allocate (cs%parent(nb))
    end if
    associate (parent => cs%parent, cgroup => cs%cgroup, now => cs%now, est => cs%est, rows => cs%rows)
      do i = 1, nb
        parent(i) = i
      end do
      ! Union of the bodies touched by each active condition; cgroup = representative body (0: none).
      cgroup = 0
      do j = 1, cs%nc
        if (.not. now(j)) cycle
        do p = cs%ptr(j), cs%ptr(j + 1) - 1
          bj = body(cs%eq(p))
          if (bj <= 0) then
            cgroup(j) = -1
            exit
          end if
          if (cgroup(j) == 0) then
            cgroup(j) = bj
          else
            call union(parent, cgroup(j), bj)
          end if
        end do
      end do
      do j = 1, cs%nc
        if (cgroup(j) > 0) cgroup(j) = find(parent, cgroup(j))
      end do
      where (est .and. cgroup <= 0) cs%fallback = .true.
      do grp = 1, nb
        if (find(parent, grp) /= grp) cycle
        if (.not. any(est .and. cgroup == grp)) cycle
        rep%persist_groups = rep%persist_groups + 1
        do i = 1, cs%neq
          rows(i) = body(i) > 0
          if (rows(i)) rows(i) = find(parent, body(i)) == grp
        end do
        n = 0
        do j = 1, cs%nc
          if (.not. (now(j) .and. cgroup(j) == grp)) cycle
          n = n + 1
          cs%idx(n) = j
        end do
        call normal_multiplier_ws(cs, n, v, rank, stat, errmsg)
        if (stat /= STAT_OK) return
        cs%vp = v
        cs%mvp = mv
        call add_minv_ct(cs, cs%mu, -1.0_dp, cs%vp, cs%mvp, stat, errmsg)
        if (stat /= STAT_OK) return
        t1 = 0.5_dp * sum(v * mv, mask=rows)
        tp = 0.5_dp * sum(cs%vp * cs%mvp, mask=rows)
        tstar = t1 + sum(cs%e, mask=est .and. cgroup == grp)
        ! Scale about the centre-of-mass velocity a_k t_k when the group's conditions are all
        ! invariant under its translations (node-to-node, no obstacle, no support): momentum and
        ! the zero normal velocities are kept; otherwise about zero.
        call group_translation(cs, rows, n, acm, tcm)
        if (.not. (tp - tcm > cs%persist_min_fraction * tstar)) then
          where (est .and. cgroup == grp) cs%fallback = .true.
          rep%persist_fallbacks = rep%persist_fallbacks + 1
          cycle
        end if
        s = persist_scale(tstar, tcm, tp - tcm)
        do i = 1, cs%neq                           ! (a loop: a WHERE block allocates its mask)
          if (.not. rows(i)) cycle
          if (cs%has_rigid) then
            vcm = acm(1) * cs%rig(i, 1) + acm(2) * cs%rig(i, 2)
            mvcm = acm(1) * cs%mrig(i, 1) + acm(2) * cs%mrig(i, 2)
          else
            vcm = 0.0_dp
            mvcm = 0.0_dp
          end if
          v(i) = vcm + s * (cs%vp(i) - vcm)
          mv(i) = mvcm + s * (cs%mvp(i) - mvcm)
        end do
      end do
    end associate
  end subroutine persist_correction

  !> The centre-of-mass velocity v_cm = a_1 t_1 + a_2 t_2 of the group (rows) after the
  !> projection (cs%vp, cs%mvp): the M-orthogonal projection on its translations, G a = P with
  !> G_kl = t_k'M t_l and P_k = t_k'M v over the group, and its kinetic energy tcm = ½ a'P.
  !> a = 0, tcm = 0 (scale about zero) without rigid modes, when an active condition of the
  !> group, cs%idx(1:n), is not invariant under the translations (c_j't_k /= 0: an obstacle
  !> or a supported node), or when G is singular.
  subroutine group_translation(cs, rows, n, a, tcm)
    type(contact_set_t), intent(in) :: cs
    logical, intent(in) :: rows(:)
    integer, intent(in) :: n
    real(dp), intent(out) :: a(2), tcm
    real(dp) :: g(2, 2), pk(2), det
    integer :: k, l, j
    a = 0.0_dp
    tcm = 0.0_dp
    if (.not. cs%has_rigid) return
    do j = 1, n
      do k = 1, 2
        if (row_dot(cs, cs%idx(j), cs%rig(:, k)) /= 0.0_dp) return
      end do
    end do
    do k = 1, 2
      pk(k) = sum(cs%rig(:, k) * cs%mvp, mask=rows)
      do l = 1, 2
        g(k, l) = sum(cs%rig(:, k) * cs%mrig(:, l), mask=rows)
      end do
    end do
    det = g(1, 1) * g(2, 2) - g(1, 2) * g(2, 1)
    if (.not. (det > 0.0_dp)) return
    a(1) = (g(2, 2) * pk(1) - g(1, 2) * pk(2)) / det     ! 2 x 2 by Cramer's rule
    a(2) = (g(1, 1) * pk(2) - g(2, 1) * pk(1)) / det
    tcm = 0.5_dp * (a(1) * pk(1) + a(2) * pk(2))
  end subroutine group_translation

  pure recursive integer function find(parent, i) result(r)
    integer, intent(in) :: parent(:), i
    r = i
    if (parent(i) /= i) r = find(parent, parent(i))
  end function find

  pure subroutine union(parent, a, b)
    integer, intent(inout) :: parent(:)
    integer, intent(in) :: a, b
    integer :: ra, rb
    ra = find(parent, a)
    rb = find(parent, b)
    if (ra /= rb) parent(max(ra, rb)) = min(ra, rb)
  end subroutine union

  !> v <- v + alpha M⁻¹C'mu and mv <- mv + alpha C'mu (mv stays M v without a product by M).
  subroutine add_minv_ct(cs, mu, alpha, v, mv, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    real(dp), intent(in) :: mu(:), alpha
    real(dp), intent(inout) :: v(:), mv(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    cs%f = 0.0_dp
    call ct_add(cs, mu, cs%f)
    call cs%minv%apply(cs%f, cs%xw, stat, errmsg)
    if (stat /= STAT_OK) return
    v = v + alpha * cs%xw
    mv = mv + alpha * cs%f
  end subroutine add_minv_ct
end module contact
