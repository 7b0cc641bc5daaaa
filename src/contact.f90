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
!> double. Do not copy a contact_set_t (it may own a CHOLMOD factor of M): pass it by reference
!> and call contact_destroy when done.
module contact
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str
  use sparse_matrix, only: sym_csc_t
  use cholmod_binding, only: cholmod_factor_t
  use lcp, only: spsd_solve, lcp_solve
  implicit none
  private
  public :: IMPACT_OFF, IMPACT_PAPER, IMPACT_PERSIST, EVENT_ESTABLISH, EVENT_RELEASE, LABEL_LEN
  public :: inverse_op_t, diag_inverse_t, chol_inverse_t
  public :: contact_set_t, contact_event_t, contact_report_t
  public :: contact_add, contact_finalize, contact_set_mass, contact_prepare, contact_solve_step, &
    contact_end_step, contact_add_force, contact_gaps, contact_destroy
  public :: impact_energy_error, lambda_root, impulse_fixed_point, normal_multiplier, hzero_reflection, &
    persist_projection, persist_scale

  !> Impact treatment (same values as scene's SCHEME IMPACT).
  integer, parameter :: IMPACT_OFF = 0, IMPACT_PAPER = 1, IMPACT_PERSIST = 2
  integer, parameter :: EVENT_ESTABLISH = 1, EVENT_RELEASE = 2
  integer, parameter :: LABEL_LEN = 48
  !> The fixed point (14) tries Newton every NEWTON_AFTER iterations once it is slow.
  integer, parameter :: NEWTON_AFTER = 30

  !> x = A⁻¹ b for a fixed SPD matrix A.
  type, abstract :: inverse_op_t
  contains
    procedure(inverse_apply), deferred :: apply
  end type inverse_op_t

  abstract interface
    subroutine inverse_apply(self, b, x, stat, errmsg)
      import :: inverse_op_t, dp
      class(inverse_op_t), intent(inout) :: self
      real(dp), intent(in), contiguous :: b(:)
      real(dp), intent(out), contiguous :: x(:)
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine inverse_apply
  end interface

  !> Diagonal (lumped) matrix: x = b / d. A zero d_i is allowed where b_i = 0 (massless DOFs
  !> that no contact touches).
  type, extends(inverse_op_t) :: diag_inverse_t
    real(dp), allocatable :: d(:)
  contains
    procedure :: apply => diag_apply
  end type diag_inverse_t

  !> Owns a CHOLMOD factor (used for a consistent mass matrix).
  type, extends(inverse_op_t) :: chol_inverse_t
    type(cholmod_factor_t) :: f
  contains
    procedure :: apply => chol_apply
  end type chol_inverse_t

  !> Borrows the caller's CHOLMOD factor for the duration of one call.
  type, extends(inverse_op_t) :: chol_ref_t
    type(cholmod_factor_t), pointer :: f => null()
  contains
    procedure :: apply => chol_ref_apply
  end type chol_ref_t

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
    ! Caches.
    logical :: finalized = .false., prepared = .false., mass_set = .false.
    logical :: z_stored = .false.            !< Z = S⁻¹C' kept (neq*nc <= z_max_entries)
    real(dp), allocatable :: z(:, :)         !< (neq, nc) when z_stored
    real(dp), allocatable :: w(:, :)         !< (nc, nc) C S⁻¹ C'
    real(dp), allocatable :: am(:, :)        !< (nc, nc) C M⁻¹ C'
    class(inverse_op_t), allocatable :: minv !< M⁻¹
    ! Settings (set before contact_finalize / contact_prepare to change them).
    real(dp) :: length_scale = 1.0_dp        !< model size; gap tolerance = gap_rtol * length_scale
    real(dp) :: gap_rtol = 1.0e-12_dp
    real(dp) :: fp_tol = 1.0e-14_dp          !< relative change ending the impulse fixed point
    integer :: fp_max_iter = 500
    real(dp) :: persist_min_fraction = 1.0e-6_dp  !< PERSIST falls back to PAPER below this T_body/T*
    integer(8) :: z_max_entries = 8388608_8  !< 64 MB of Z at most; beyond, one extra solve per iteration
  end type contact_set_t

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
  pure subroutine impulse_fixed_point(g, b, e, y, iterations, change, converged, tol, max_iter)
    real(dp), intent(in) :: g(:, :), b(:), e(:)
    real(dp), intent(out) :: y(:)
    integer, intent(out) :: iterations
    real(dp), intent(out) :: change
    logical, intent(out) :: converged
    real(dp), intent(in), optional :: tol
    integer, intent(in), optional :: max_iter
    real(dp), allocatable :: ynew(:)
    real(dp) :: rtol, omega, prev, qa, qb, qe, t
    integer :: n, it, maxit, j

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
    do j = 1, n                                  ! decoupled start: (13) for each point
      y(j) = lambda_root(g(j, j), b(j), e(j))
    end do
    omega = 1.0_dp
    prev = huge(1.0_dp)
    converged = .false.
    allocate (ynew(n))
    do it = 1, maxit
      iterations = it
      call sweep(y, ynew, change, converged)
      if (converged) exit
      if (change > prev) omega = max(0.5_dp * omega, 1.0_dp / 64.0_dp)
      prev = change
      y = y + omega * (ynew - y)
      ! Slow (strong coupling): Newton on (14) from here, judged by the same fixed-point change.
      if (it >= NEWTON_AFTER .and. mod(it, NEWTON_AFTER) == 0) then
        call newton_14(g, b, e, y)
        call sweep(y, ynew, change, converged)
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
    qa = dot_product(y, matmul(g, y))
    qb = dot_product(b, y)
    qe = sum(e)
    if (qa > 0.0_dp) then
      t = nearest_root(qa, qb, qe)
      y = t * y
    end if

  contains

    !> One Jacobi sweep of (14): each point's quadratic (13) with the others' impulses frozen
    !> at y; change = largest relative update; converged (y takes the sweep) below rtol.
    pure subroutine sweep(y, ynew, change, converged)
      real(dp), intent(inout) :: y(:)
      real(dp), intent(out) :: ynew(:), change
      logical, intent(out) :: converged
      real(dp) :: gy(size(y))
      integer :: k
      gy = matmul(g, y)
      do k = 1, size(y)
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
      call lu_solve(jac, -f, d, ok)
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

  !> x = a⁻¹ r by Gaussian elimination with partial pivoting (small dense, nonsymmetric).
  pure subroutine lu_solve(a, r, x, ok)
    real(dp), intent(in) :: a(:, :), r(:)
    real(dp), intent(out) :: x(:)
    logical, intent(out) :: ok
    real(dp), allocatable :: w(:, :), row(:)
    real(dp) :: piv, tmp
    integer :: n, k, i, p
    n = size(r)
    allocate (w, source=a)
    x = r
    allocate (row(n))
    ok = .false.
    do k = 1, n
      p = k - 1 + maxloc(abs(w(k:n, k)), 1)
      piv = w(p, k)
      if (.not. (abs(piv) > epsilon(1.0_dp) * maxval(abs(a)))) return
      if (p /= k) then
        row = w(k, :); w(k, :) = w(p, :); w(p, :) = row
        tmp = x(k); x(k) = x(p); x(p) = tmp
      end if
      do i = k + 1, n
        w(i, k) = w(i, k) / piv
        w(i, k + 1:n) = w(i, k + 1:n) - w(i, k) * w(k, k + 1:n)
        x(i) = x(i) - w(i, k) * x(k)
      end do
    end do
    do k = n, 1, -1
      x(k) = (x(k) - dot_product(w(k, k + 1:n), x(k + 1:n))) / w(k, k)
    end do
    ok = .true.
  end subroutine lu_solve

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
  ! Linear operators
  ! ---------------------------------------------------------------------------------------

  subroutine diag_apply(self, b, x, stat, errmsg)
    class(diag_inverse_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: b(:)
    real(dp), intent(out), contiguous :: x(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: i
    stat = STAT_OK
    if (size(b) /= size(self%d) .or. size(x) /= size(b)) then
      call set_error(stat, errmsg, STAT_INPUT, 'diagonal inverse: size mismatch')
      return
    end if
    do i = 1, size(b)
      if (b(i) == 0.0_dp) then
        x(i) = 0.0_dp
      else if (self%d(i) > 0.0_dp) then
        x(i) = b(i) / self%d(i)
      else
        call set_error(stat, errmsg, STAT_INPUT, 'contact: equation ' // str(i) // &
          ' carries a contact condition but has no mass (lumped mass diagonal ' // str(self%d(i)) // ')')
        return
      end if
    end do
  end subroutine diag_apply

  subroutine chol_apply(self, b, x, stat, errmsg)
    class(chol_inverse_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: b(:)
    real(dp), intent(out), contiguous :: x(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call self%f%solve(b, x, stat, errmsg)
  end subroutine chol_apply

  subroutine chol_ref_apply(self, b, x, stat, errmsg)
    class(chol_ref_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: b(:)
    real(dp), intent(out), contiguous :: x(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call self%f%solve(b, x, stat, errmsg)
  end subroutine chol_ref_apply

  ! ---------------------------------------------------------------------------------------
  ! Building the set
  ! ---------------------------------------------------------------------------------------

  !> Append the condition g0 + Σ coefs(k) u(eqs(k)) >= 0. Entries with eqs(k) <= 0 (supported
  !> or absent DOFs) are skipped. nodes = [node_a, node_b] (0 for a rigid obstacle) and label
  !> name it in messages and events.
  pure subroutine contact_add(cs, g0, eqs, coefs, nodes, label)
    type(contact_set_t), intent(inout) :: cs
    real(dp), intent(in) :: g0
    integer, intent(in) :: eqs(:)
    real(dp), intent(in) :: coefs(:)
    integer, intent(in), optional :: nodes(2)
    character(len=*), intent(in), optional :: label
    integer :: k, nz
    integer, allocatable :: itmp(:, :)
    character(len=LABEL_LEN), allocatable :: ltmp(:)

    if (.not. allocated(cs%ptr)) then
      cs%ptr = [1]
      allocate (cs%eq(0), cs%coef(0), cs%g0(0), cs%nodes(2, 0), cs%label(0))
    end if
    nz = cs%ptr(cs%nc + 1)
    do k = 1, min(size(eqs), size(coefs))
      if (eqs(k) > 0 .and. coefs(k) /= 0.0_dp) then
        cs%eq = [cs%eq, eqs(k)]
        cs%coef = [cs%coef, coefs(k)]
        nz = nz + 1
      end if
    end do
    cs%nc = cs%nc + 1
    cs%ptr = [cs%ptr, nz]
    cs%g0 = [cs%g0, g0]
    allocate (itmp(2, cs%nc))
    itmp(:, 1:cs%nc - 1) = cs%nodes
    itmp(:, cs%nc) = 0
    if (present(nodes)) itmp(:, cs%nc) = nodes
    call move_alloc(itmp, cs%nodes)
    allocate (ltmp(cs%nc))
    ltmp(1:cs%nc - 1) = cs%label
    ltmp(cs%nc) = 'condition ' // str(cs%nc)
    if (present(label)) ltmp(cs%nc) = label
    call move_alloc(ltmp, cs%label)
  end subroutine contact_add

  !> Check the conditions against neq free equations, set the model size (length_scale > 0,
  !> e.g. the bounding-box diagonal; tolerances are relative to it) and allocate the state:
  !> nothing active, no reaction. The initial gaps are the driver's (scene) business.
  pure subroutine contact_finalize(cs, neq, length_scale, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: neq
    real(dp), intent(in) :: length_scale
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: j, nc
    stat = STAT_OK
    if (.not. allocated(cs%ptr)) then
      cs%ptr = [1]
      allocate (cs%eq(0), cs%coef(0), cs%g0(0), cs%nodes(2, 0), cs%label(0))
    end if
    nc = cs%nc
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
    cs%finalized = .true.
    cs%prepared = .false.
  end subroutine contact_finalize

  !> Free the caches and the mass factor.
  subroutine contact_destroy(cs)
    type(contact_set_t), intent(inout) :: cs
    if (allocated(cs%minv)) then
      select type (op => cs%minv)
      type is (chol_inverse_t)
        call op%f%destroy()
      end select
      deallocate (cs%minv)
    end if
    if (allocated(cs%z)) deallocate (cs%z)
    if (allocated(cs%w)) deallocate (cs%w)
    if (allocated(cs%am)) deallocate (cs%am)
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
    g = cs%g0 + c_times(cs, u)
  end subroutine contact_gaps

  !> f <- f + C'Λ with the multiplier of the last contact_solve_step: the contact force on the
  !> right of (5)/(9), for the driver's residual.
  pure subroutine contact_add_force(cs, f)
    type(contact_set_t), intent(in) :: cs
    real(dp), intent(inout) :: f(:)
    if (cs%nc == 0 .or. .not. allocated(cs%lambda)) return
    call ct_add(cs, cs%lambda, f)
  end subroutine contact_add_force

  !> C x (all rows).
  pure function c_times(cs, x) result(cx)
    type(contact_set_t), intent(in) :: cs
    real(dp), intent(in) :: x(:)
    real(dp) :: cx(cs%nc)
    integer :: j
    do j = 1, cs%nc
      cx(j) = row_dot(cs, j, x)
    end do
  end function c_times

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

  !> Y = C X⁻¹ C' column by column with the operator op (nc solves); symmetrized.
  subroutine schur_columns(cs, op, y, z, stat, errmsg)
    type(contact_set_t), intent(in) :: cs
    class(inverse_op_t), intent(inout) :: op
    real(dp), intent(out) :: y(:, :)
    real(dp), intent(inout), optional :: z(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), allocatable :: b(:), x(:), e(:)
    integer :: j
    stat = STAT_OK
    allocate (b(cs%neq), x(cs%neq), e(cs%nc))
    b = 0.0_dp
    do j = 1, cs%nc
      e = 0.0_dp
      e(j) = 1.0_dp
      b = 0.0_dp
      call ct_add(cs, e, b)
      call op%apply(b, x, stat, errmsg)
      if (stat /= STAT_OK) then
        errmsg = 'contact: solve for ' // trim(cs%label(j)) // ': ' // errmsg
        return
      end if
      y(:, j) = c_times(cs, x)
      if (present(z)) z(:, j) = x
    end do
    y = 0.5_dp * (y + transpose(y))
  end subroutine schur_columns

  ! ---------------------------------------------------------------------------------------
  ! Mass and iteration-matrix operators
  ! ---------------------------------------------------------------------------------------

  !> Lumped mass: M = diag(mdiag). Computes A_M = C M⁻¹ C' (once per run).
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

  subroutine finish_mass(cs, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (.not. cs%finalized) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_set_mass: call contact_finalize first')
      return
    end if
    if (allocated(cs%am)) deallocate (cs%am)
    allocate (cs%am(cs%nc, cs%nc))
    call schur_columns(cs, cs%minv, cs%am, stat=stat, errmsg=errmsg)
    if (stat /= STAT_OK) return
    cs%mass_set = .true.
  end subroutine finish_mass

  !> Per step size: W = C S⁻¹ C' and, if neq*nc <= z_max_entries, Z = S⁻¹C', with the driver's
  !> CHOLMOD factor of S = K0 + 4M/h².
  subroutine prepare_chol(cs, s, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    type(cholmod_factor_t), intent(inout), target :: s
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(chol_ref_t) :: op
    op%f => s
    call prepare_op(cs, op, stat, errmsg)
  end subroutine prepare_chol

  !> Same with any S⁻¹ operator.
  subroutine prepare_op(cs, s, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    class(inverse_op_t), intent(inout) :: s
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (.not. cs%finalized) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_prepare: call contact_finalize first')
      return
    end if
    cs%prepared = .false.
    if (allocated(cs%w)) deallocate (cs%w)
    if (allocated(cs%z)) deallocate (cs%z)
    allocate (cs%w(cs%nc, cs%nc))
    cs%z_stored = int(cs%neq, 8) * int(cs%nc, 8) <= cs%z_max_entries
    if (cs%z_stored) then
      allocate (cs%z(cs%neq, cs%nc))
      call schur_columns(cs, s, cs%w, cs%z, stat, errmsg)
    else
      call schur_columns(cs, s, cs%w, stat=stat, errmsg=errmsg)
    end if
    if (stat /= STAT_OK) return
    cs%prepared = .true.
  end subroutine prepare_op

  ! ---------------------------------------------------------------------------------------
  ! The step
  ! ---------------------------------------------------------------------------------------

  !> One iteration of the step: with u_n the displacement at the start of the step and du_free
  !> the update without contact forces, find the step multiplier lambda (LCP) and the constrained
  !> update du = du_free + S⁻¹C'Λ. The solve with s is only used when Z is not stored.
  subroutine solve_step_chol(cs, s, u_n, du_free, du, lambda, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    type(cholmod_factor_t), intent(inout), target :: s
    real(dp), intent(in) :: u_n(:), du_free(:)
    real(dp), intent(out) :: du(:)
    real(dp), intent(out) :: lambda(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(chol_ref_t) :: op
    op%f => s
    call solve_step_op(cs, op, u_n, du_free, du, lambda, stat, errmsg)
  end subroutine solve_step_chol

  subroutine solve_step_op(cs, s, u_n, du_free, du, lambda, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    class(inverse_op_t), intent(inout) :: s
    real(dp), intent(in) :: u_n(:), du_free(:)
    real(dp), intent(out) :: du(:)
    real(dp), intent(out) :: lambda(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), allocatable :: q(:), b(:), x(:)
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
    cs%gap_n = cs%g0 + c_times(cs, u_n)
    ! A condition that starts the step slightly penetrated (within the input tolerance, or by
    ! the LCP tolerance at an earlier release) is held where it is, not pushed out: its target
    ! is g(n+1) >= g(n). Pushing it out would let the multiplier do the work ½ Λ |g(n)|, which
    ! E_j = ½ Λ max(g(n), 0) of eq (10) cannot take back: energy created.
    q = max(cs%gap_n, 0.0_dp) + c_times(cs, du_free)
    call lcp_solve(cs%w, q, cs%gap_rtol * cs%length_scale, cs%lambda, cs%gap, cs%active_iter, cs%lcp_iterations, &
      stat, errmsg)
    if (stat /= STAT_OK) then
      errmsg = errmsg // ' (' // str(count(cs%active_iter)) // ' conditions in the last active set)'
      return
    end if
    lambda = cs%lambda
    if (.not. any(cs%lambda > 0.0_dp)) return
    if (cs%z_stored) then
      do j = 1, cs%nc
        if (cs%lambda(j) > 0.0_dp) du = du + cs%lambda(j) * cs%z(:, j)
      end do
    else
      allocate (b(cs%neq), x(cs%neq))
      b = 0.0_dp
      call ct_add(cs, cs%lambda, b)
      call s%apply(b, x, stat, errmsg)
      if (stat /= STAT_OK) return
      du = du + x
    end if
  end subroutine solve_step_op

  !> End of a converged step, after eq (3) gave v = v(n+1) and mv = M v(n+1):
  !>   events (established: active now and not at the end of the last step; released: the
  !>   reverse), E_j = ½ Λ_j max(g_j(n), 0) (10) for the established ones, then the correction
  !>   of the mode (IMPACT_OFF: none; IMPACT_PAPER: (12)-(15) then (16); IMPACT_PERSIST: section 6,
  !>   falling back to PAPER for bodies left without kinetic energy), reactions R(n+1) = Λ - R(n)
  !>   (0 for inactive conditions), new state. v and mv are updated together (mv stays M v).
  !>   body(i) is the mesh-connected component of equation i (0: none), required by PERSIST.
  !>   energy_restored = kinetic energy added, measured (= Σ E_j to round-off).
  subroutine contact_end_step(cs, mode, u_n, du, v, mv, energy_restored, events, stat, errmsg, body, report)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: mode
    real(dp), intent(in) :: u_n(:), du(:)
    real(dp), intent(inout) :: v(:), mv(:)
    real(dp), intent(out) :: energy_restored
    type(contact_event_t), allocatable, intent(out) :: events(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, intent(in), optional :: body(:)
    type(contact_report_t), intent(out), optional :: report
    type(contact_report_t) :: rep
    logical, allocatable :: now(:), est(:), rel(:), fallback(:)
    real(dp), allocatable :: gn(:), gend(:), e(:), y(:), r(:)
    real(dp) :: t_before
    integer :: j, k, nev

    stat = STAT_OK
    energy_restored = 0.0_dp
    allocate (events(0))
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
    gn = cs%g0 + c_times(cs, u_n)
    gend = gn + c_times(cs, du)
    now = cs%active_iter .and. .true.
    est = now .and. .not. cs%active
    rel = cs%active .and. .not. now
    allocate (e(cs%nc), y(cs%nc))
    y = 0.0_dp
    e = 0.0_dp
    where (est) e = impact_energy_error(cs%lambda, max(gn, 0.0_dp))
    rep%n_active = count(now)
    rep%n_establish = count(est)
    rep%n_release = count(rel)
    rep%energy_error = sum(e)
    rep%scheme_work = 0.5_dp * dot_product(cs%lambda, c_times(cs, du))
    t_before = 0.5_dp * dot_product(v, mv)

    if (rep%n_establish > 0) then
      select case (mode)
      case (IMPACT_PAPER)
        call paper_correction(cs, est, e, v, mv, y, rep, stat, errmsg)
      case (IMPACT_PERSIST)
        if (.not. present(body)) then
          call set_error(stat, errmsg, STAT_INPUT, 'contact_end_step: IMPACT PERSIST needs body(:)')
          return
        end if
        call persist_correction(cs, now, est, e, body, v, mv, fallback, rep, stat, errmsg)
        if (stat == STAT_OK .and. any(fallback)) call paper_correction(cs, fallback, e, v, mv, y, rep, stat, errmsg)
      case (IMPACT_OFF)
      case default
        call set_error(stat, errmsg, STAT_INPUT, 'contact_end_step: unknown impact mode ' // str(mode))
      end select
      if (stat /= STAT_OK) return
      if (mode /= IMPACT_OFF) energy_restored = 0.5_dp * dot_product(v, mv) - t_before
    end if
    rep%energy_restored = energy_restored

    ! Reactions (reported only) and the new state.
    r = merge(cs%lambda - cs%r_prev, 0.0_dp, now)
    nev = count(est) + count(rel)
    deallocate (events)
    allocate (events(nev))
    k = 0
    do j = 1, cs%nc
      if (.not. (est(j) .or. rel(j))) cycle
      k = k + 1
      events(k) = contact_event_t(j, merge(EVENT_ESTABLISH, EVENT_RELEASE, est(j)), gn(j), gend(j), cs%lambda(j), &
        r(j), e(j), y(j))
    end do
    cs%r_prev = r
    cs%active = now
    cs%gap_n = gend
    if (present(report)) report = rep
  end subroutine contact_end_step

  !> (12)-(16) for the conditions sel (all established in the step): impulses by the fixed
  !> point (14)-(15) for those with Λ_j > 0, Δv = M⁻¹ Σ y_j Λ_j c_j, then the hzero reflection
  !> about all of them.
  subroutine paper_correction(cs, sel, e, v, mv, y, rep, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    logical, intent(in) :: sel(:)
    real(dp), intent(in) :: e(:)
    real(dp), intent(inout) :: v(:), mv(:), y(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, allocatable :: ip(:), ia(:)
    real(dp), allocatable :: g(:, :), b(:), yp(:), mu(:), av(:), nu(:)
    real(dp) :: change
    integer :: i, k, iters, rank
    logical :: conv

    stat = STAT_OK
    ip = pack([(i, i = 1, cs%nc)], sel .and. cs%lambda > 0.0_dp)
    if (size(ip) > 0) then
      g = cs%am(ip, ip)
      do k = 1, size(ip)
        g(:, k) = g(:, k) * cs%lambda(ip) * cs%lambda(ip(k))
      end do
      b = cs%lambda(ip) * c_rows(cs, ip, v)
      allocate (yp(size(ip)))
      call impulse_fixed_point(g, b, e(ip), yp, iters, change, conv, cs%fp_tol, cs%fp_max_iter)
      rep%fp_iterations = rep%fp_iterations + iters
      rep%fp_change = max(rep%fp_change, change)
      if (.not. conv) rep%fp_failures = rep%fp_failures + 1     ! reported, energy still exact
      y(ip) = yp
      allocate (mu(cs%nc))
      mu = 0.0_dp
      mu(ip) = yp * cs%lambda(ip)
      call add_minv_ct(cs, mu, 1.0_dp, v, mv, stat, errmsg)          ! (12)
      if (stat /= STAT_OK) return
    end if
    ! (16) hzero reflection about every condition established in the step.
    ia = pack([(i, i = 1, cs%nc)], sel)
    av = c_rows(cs, ia, v)
    allocate (nu(size(ia)))
    call normal_multiplier(cs%am(ia, ia), av, nu, rank)
    rep%reflection_rank = rank
    if (.not. allocated(mu)) allocate (mu(cs%nc))
    mu = 0.0_dp
    mu(ia) = nu
    call add_minv_ct(cs, mu, -2.0_dp, v, mv, stat, errmsg)
  end subroutine paper_correction

  !> Section 6. Groups: bodies linked by active conditions. For each group holding an
  !> established condition: project on zero normal velocity of all its active conditions, then
  !> scale its velocity so that its kinetic energy is T1_group + Σ E_j. Groups whose projected
  !> kinetic energy is below persist_min_fraction of that target, or conditions on equations
  !> without body, are left untouched and returned in fallback (their established conditions).
  subroutine persist_correction(cs, now, est, e, body, v, mv, fallback, rep, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    logical, intent(in) :: now(:), est(:)
    real(dp), intent(in) :: e(:)
    integer, intent(in) :: body(:)
    real(dp), intent(inout) :: v(:), mv(:)
    logical, allocatable, intent(out) :: fallback(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, allocatable :: parent(:), cgroup(:), ia(:)
    logical, allocatable :: rows(:)
    real(dp), allocatable :: vp(:), mvp(:), mu(:), nu(:)
    integer :: nb, j, p, bj, i, grp, rank
    real(dp) :: t1, tp, tstar, s

    stat = STAT_OK
    allocate (fallback(cs%nc))
    fallback = .false.
    if (size(body) /= cs%neq) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_end_step: body(:) must have one entry per equation')
      return
    end if
    nb = 0
    if (cs%neq > 0) nb = max(maxval(body), 0)
    parent = [(i, i = 1, nb)]
    ! Union of the bodies touched by each active condition; cgroup = representative body (0: none).
    allocate (cgroup(cs%nc))
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
    where (est .and. cgroup <= 0) fallback = .true.
    allocate (rows(cs%neq), mu(cs%nc))
    do grp = 1, nb
      if (find(parent, grp) /= grp) cycle
      if (.not. any(est .and. cgroup == grp)) cycle
      rep%persist_groups = rep%persist_groups + 1
      do i = 1, cs%neq
        rows(i) = body(i) > 0
        if (rows(i)) rows(i) = find(parent, body(i)) == grp
      end do
      ia = pack([(i, i = 1, cs%nc)], now .and. cgroup == grp)
      allocate (nu(size(ia)))
      call normal_multiplier(cs%am(ia, ia), c_rows(cs, ia, v), nu, rank)
      mu = 0.0_dp
      mu(ia) = nu
      vp = v
      mvp = mv
      call add_minv_ct(cs, mu, -1.0_dp, vp, mvp, stat, errmsg)
      if (stat /= STAT_OK) return
      deallocate (nu)
      t1 = 0.5_dp * sum(v * mv, mask=rows)
      tp = 0.5_dp * sum(vp * mvp, mask=rows)
      tstar = t1 + sum(e, mask=est .and. cgroup == grp)
      if (.not. (tp > cs%persist_min_fraction * tstar)) then
        where (est .and. cgroup == grp) fallback = .true.
        rep%persist_fallbacks = rep%persist_fallbacks + 1
        cycle
      end if
      s = persist_scale(tstar, 0.0_dp, tp)
      where (rows)
        v = s * vp
        mv = s * mvp
      end where
    end do
  end subroutine persist_correction

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

  !> c_j'x for the conditions idx.
  pure function c_rows(cs, idx, x) result(cx)
    type(contact_set_t), intent(in) :: cs
    integer, intent(in) :: idx(:)
    real(dp), intent(in) :: x(:)
    real(dp) :: cx(size(idx))
    integer :: k
    do k = 1, size(idx)
      cx(k) = row_dot(cs, idx(k), x)
    end do
  end function c_rows

  !> v <- v + alpha M⁻¹C'mu and mv <- mv + alpha C'mu (mv stays M v without a product by M).
  subroutine add_minv_ct(cs, mu, alpha, v, mv, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    real(dp), intent(in) :: mu(:), alpha
    real(dp), intent(inout) :: v(:), mv(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), allocatable :: f(:), x(:)
    stat = STAT_OK
    allocate (f(cs%neq), x(cs%neq))
    f = 0.0_dp
    call ct_add(cs, mu, f)
    call cs%minv%apply(f, x, stat, errmsg)
    if (stat /= STAT_OK) return
    v = v + alpha * x
    mv = mv + alpha * f
  end subroutine add_minv_ct
end module contact
