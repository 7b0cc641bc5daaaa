!> Coulomb's law in 3D on the circular cone (docs/contact.md, "Friction in 3D"). A frictional
!> condition k has a normal row N and two tangential rows t1, t2 (an orthonormal basis of the
!> tangent plane: scene's condition_tangent); on the step multipliers Λ and the step's slip
!> s = (g_t1, g_t2) = C_T Δu,
!>   stick   s = 0                          and |Λ_T| <= μ Λ_N,
!>   slip    Λ_T = -μ Λ_N d,  s = σ d,  σ >= 0,  d = (cos θ, sin θ):
!> the force on the circle, opposite to the slip. The cone is not faceted: the slip's direction θ
!> is an unknown, so the friction's work ½ Λ_T·s = -½ μ Λ_N σ is never positive to round-off.
!>
!> cone_solve keeps the primal-dual active set of coulomb_solve over the states (contact open or
!> closed; stick or slip); for given states the unknowns are the multipliers of the active,
!> sticking and bilateral rows and, per slipping condition, (θ, σ). The equations
!>   g_I = q_I + W Λ = 0,   g_t1 - σ cos θ = 0,   g_t2 - σ sin θ = 0
!> are linear in every unknown but θ (Λ_T of a slipping condition is -μ Λ_N d(θ)), and are solved
!> by Newton's method on the dense block of W = C S⁻¹C' over those rows (the Schur columns of the
!> multiplier system, LAPACK dgesv): quadratic in θ, exact in the rest at every iterate. Then a
!> state that violates its law changes, as in 2D: a stick force outside the circle slips opposite
!> to it, a slip whose length σ turned negative sticks. Large zones (MULTIPLIERS AUGMENTED, or AUTO
!> where the dense block would pass AUGMENTED_ABOVE rows) solve each pass on the augmented sparse
!> system instead, by a fixed point (cone_fixed_point: the slipping forces as known loads on the
!> kept factor, each θ taking its slip's direction), the Schur block's Newton serving where that
!> does not settle. A submodule of coulomb.
submodule (coulomb) coulomb_cone
  implicit none

  integer, parameter :: NEWTON_MAX = 40
  integer, parameter :: FP_MAX = 60                   !< sparse solves of the augmented fixed point
  integer, parameter :: FX_MAX = 60                   !< its solves with the slipping forces known
  real(dp), parameter :: FORCE_RTOL = 1.0e-14_dp      !< their change (relative) at convergence
  real(dp), parameter :: THETA_TOL = 1.0e-14_dp       !< |Δθ| (rad) below which θ has converged
  !> |Δθ| still accepted after NEWTON_MAX steps (round-off on a direction whose condition has almost
  !> no normal force nor slip); above it the pass's states are wrong (a contact that opens: its Λ_N
  !> turns negative) and change, or, if they violate nothing, the step fails (retried as sub-steps).
  real(dp), parameter :: THETA_ACCEPT = 1.0e-8_dp
  real(dp), parameter :: THETA_STEP = 0.5_dp          !< largest |Δθ| of one Newton step (rad)

contains

  module procedure cone_solve
    integer :: pass, k, j, j2, nv, nbest, tries
    logical :: converged
    stat = STAT_OK
    iterations = 0
    call cone_open(self, active, q, tol)
    nbest = huge(1)
    tries = BLOCK_TRIES
    do pass = 1, MAX_PASSES
      iterations = pass
      call cone_states(self, ms, q, bilateral, active, lam, g, wdiag, converged, stat, errmsg)
      if (stat /= STAT_OK) return
      call unilateral_violations(bilateral, active, lam, g, wdiag, tol, tol_free, viol)
      do k = 1, self%n
        j = self%trow(k)
        j2 = self%trow2(k)
        if (.not. active(self%nrow(k))) cycle
        select case (self%state(k))
        case (FRICTION_STICK)
          viol(j) = hypot(lam(j), lam(j2)) > self%mu(k) * max(lam(self%nrow(k)), 0.0_dp) * (1.0_dp + THRESHOLD_RTOL)
        case (FRICTION_SLIP_POS)
          viol(j) = self%sig(k) < -tol
        end select
      end do
      nv = count(viol)
      if (nv == 0 .and. .not. converged) then  ! (states that violate nothing, directions not found)
        call set_error(stat, errmsg, STAT_RUN, 'friction: the slip directions of the contact zone did not converge ' // &
          'in ' // str(NEWTON_MAX) // ' Newton steps')
        return
      end if
      if (nv == 0) return
      call limit_changes(viol, nv, nbest, tries)
      where (viol .and. .not. bilateral) active = .not. active
      call cone_open(self, active, g, tol)
      do k = 1, self%n
        j = self%trow(k)
        if (.not. viol(j)) cycle
        if (self%state(k) == FRICTION_STICK) then   ! slip opposite to the force that left the circle
          self%state(k) = FRICTION_SLIP_POS
          self%theta(k) = atan2(-lam(self%trow2(k)), -lam(j))
          self%sig(k) = 0.0_dp
        else
          self%state(k) = FRICTION_STICK
        end if
      end do
    end do
    call set_error(stat, errmsg, STAT_RUN, 'friction: no consistent contact, stick and slip states after ' // &
      str(MAX_PASSES) // ' passes (' // str(nv) // ' conditions still violated)')
  end procedure cone_solve

  !> The conditions whose contact closes (state FREE, the contact active): slipping the way their
  !> slip s = (s_t1, s_t2) goes where |s| > tol, stuck otherwise.
  pure subroutine cone_open(self, active, s, tol)
    class(coulomb_t), intent(inout) :: self
    logical, intent(in) :: active(:)
    real(dp), intent(in) :: s(:), tol
    integer :: k
    real(dp) :: s1, s2
    do k = 1, self%n
      if (self%state(k) /= FRICTION_FREE .or. .not. active(self%nrow(k))) cycle
      s1 = s(self%trow(k))
      s2 = s(self%trow2(k))
      self%state(k) = FRICTION_STICK
      if (hypot(s1, s2) > tol) then
        self%state(k) = FRICTION_SLIP_POS
        self%theta(k) = atan2(s2, s1)
        self%sig(k) = hypot(s1, s2)
      end if
    end do
  end subroutine cone_open

  !> One pass of cone_solve: the rows of the states (I: active, bilateral, sticking tangential;
  !> then each slipping condition's t1, t2, whose unknowns are θ and σ), Newton's iteration on
  !> them, then lam, g = q + W lam and wdiag.
  subroutine cone_states(self, ms, q, bilateral, active, lam, g, wdiag, converged, stat, errmsg)
    class(coulomb_t), intent(inout) :: self
    type(multiplier_system_t), intent(inout) :: ms
    real(dp), intent(in) :: q(:)
    logical, intent(in) :: bilateral(:)
    logical, intent(in) :: active(:)
    real(dp), intent(inout) :: lam(:)
    real(dp), intent(out) :: g(:)
    real(dp), intent(inout) :: wdiag(:)
    logical, intent(out) :: converged
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, l, ni, nl, it
    real(dp) :: dmax
    stat = STAT_OK
    call fixed_rows(self%kof, self%nrow, bilateral, active, self%state, self%rows, ni)
    nl = ni
    do k = 1, self%n
      if (self%state(k) /= FRICTION_SLIP_POS) cycle
      self%rows(nl + 1:nl + 2) = [self%trow(k), self%trow2(k)]
      nl = nl + 2
    end do
    ! A large zone (MULTIPLIERS AUGMENTED, or AUTO where the dense block's order nl, 3 rows a
    ! slipping node, passes AUGMENTED_ABOVE): the augmented sparse system by a fixed point; the
    ! Schur block's Newton where that does not settle.
    if (ms%kkt_built .and. (ms%mode == SOLVER_AUGMENTED .or. (ms%mode == SOLVER_AUTO .and. nl > ms%switch_size))) then
      call cone_fixed_point(self, ms, q, ni, lam, g, converged, stat, errmsg)
      if (stat /= STAT_OK .or. converged) then
        if (converged) wdiag = ms%wlow
        return
      end if
    end if
    self%keep = .false.
    do l = 1, nl
      self%keep(self%rows(l)) = .true.
      self%pos(self%rows(l)) = l
    end do
    call ms%ensure(self%rows, nl, self%keep, stat, errmsg)
    if (stat /= STAT_OK) return
    if (size(self%m, 1) < nl) then             ! grow past the high-water mark
      deallocate (self%m, self%wb)
      allocate (self%m(2 * nl, 2 * nl), self%wb(2 * nl, 2 * nl))
    end if
    call ms%w_block(self%rows, nl, self%rows, nl, self%wb)
    ! The unknowns in place: Λ of the rows of I (from the last pass: a slipping condition's Λ_N
    ! starts where it was, not at 0 where its direction would be undetermined), then (θ, σ) at a
    ! slipping condition's t1, t2.
    do l = 1, ni
      self%lr(l) = lam(self%rows(l))
    end do
    do k = 1, self%n
      if (self%state(k) /= FRICTION_SLIP_POS) cycle
      l = self%pos(self%trow(k))
      self%lr(l:l + 1) = [self%theta(k), self%sig(k)]
    end do
    do it = 1, NEWTON_MAX
      call cone_newton_step(self, q, ni, nl, dmax, stat, errmsg)
      if (stat /= STAT_OK) return
      if (dmax <= THETA_TOL) exit
    end do
    converged = dmax <= THETA_ACCEPT
    do k = 1, self%n
      if (self%state(k) /= FRICTION_SLIP_POS) cycle
      l = self%pos(self%trow(k))
      self%theta(k) = self%lr(l)
      self%sig(k) = self%lr(l + 1)
    end do
    lam = 0.0_dp
    call cone_multipliers(self, ni, nl, lam)
    g = q
    call ms%add_columns(self%rows, nl, lam, g)
    do l = 1, nl
      wdiag(self%rows(l)) = self%wb(l, l)
    end do
  end subroutine cone_states

  !> cone_states on the augmented sparse system (ms%solve_coulomb), the rows I (rows(1:ni)) holding
  !> g = 0. First the slipping conditions' forces as known loads, -μ Λ_N d(θ) from the last iterate,
  !> on the factor of the rows I alone (kept from solve to solve and step to step), each θ taking the
  !> direction of its slip, until neither the forces (1e-14 relative) nor any θ (THETA_TOL) move
  !> (FX_MAX solves); where that does not settle, their rows Λ_t1 = -μ cos θ Λ_N, Λ_t2 = -μ sin θ Λ_N
  !> in the system (refactorized at each θ), the same update (FP_MAX solves). converged = .false.:
  !> neither settled, or the system is singular. σ = s·d(θ).
  subroutine cone_fixed_point(self, ms, q, ni, lam, g, converged, stat, errmsg)
    class(coulomb_t), intent(inout) :: self
    type(multiplier_system_t), intent(inout) :: ms
    real(dp), intent(in) :: q(:)
    integer, intent(in) :: ni
    real(dp), intent(inout) :: lam(:)
    real(dp), intent(out) :: g(:)
    logical, intent(out) :: converged
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: it, k, l
    real(dp) :: dmax
    logical :: singular
    converged = .false.
    self%on = .false.
    do l = 1, ni
      self%on(self%rows(l)) = .true.
    end do
    call cone_known_forces(self, ms, q, lam, g, converged, stat, errmsg)
    if (stat /= STAT_OK .or. converged) return
    do it = 1, FP_MAX
      self%rho = 0.0_dp
      do k = 1, self%n
        if (self%state(k) /= FRICTION_SLIP_POS) cycle
        self%rho(self%trow(k)) = -self%mu(k) * cos(self%theta(k))
        self%rho(self%trow2(k)) = -self%mu(k) * sin(self%theta(k))
      end do
      call ms%solve_coulomb(q, self%on, self%rho, lam, g, singular, stat, errmsg)
      if (stat /= STAT_OK .or. singular) return
      call follow_slips(self, g, dmax)
      if (dmax <= THETA_TOL) then
        converged = slips_forward(self)
        return
      end if
    end do
  end subroutine cone_fixed_point

  !> cone_fixed_point's first stage: the slipping forces known (lam_rows), the factor of on kept.
  subroutine cone_known_forces(self, ms, q, lam, g, converged, stat, errmsg)
    class(coulomb_t), intent(inout) :: self
    type(multiplier_system_t), intent(inout) :: ms
    real(dp), intent(in) :: q(:)
    real(dp), intent(inout) :: lam(:)
    real(dp), intent(out) :: g(:)
    logical, intent(out) :: converged
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: it, k, t1, t2
    real(dp) :: dmax, df, fmax, f1, f2
    logical :: singular
    converged = .false.
    stat = STAT_OK
    self%rho = 0.0_dp
    self%lam_rows = 0.0_dp
    do k = 1, self%n
      if (self%state(k) /= FRICTION_SLIP_POS) cycle
      self%lam_rows(self%trow(k)) = -self%mu(k) * lam(self%nrow(k)) * cos(self%theta(k))
      self%lam_rows(self%trow2(k)) = -self%mu(k) * lam(self%nrow(k)) * sin(self%theta(k))
    end do
    do it = 1, FX_MAX
      call ms%solve_coulomb(q, self%on, self%rho, lam, g, singular, stat, errmsg, force=self%lam_rows)
      if (stat /= STAT_OK .or. singular) return
      call follow_slips(self, g, dmax)
      df = 0.0_dp
      fmax = 0.0_dp
      do k = 1, self%n
        if (self%state(k) /= FRICTION_SLIP_POS) cycle
        t1 = self%trow(k)
        t2 = self%trow2(k)
        f1 = -self%mu(k) * lam(self%nrow(k)) * cos(self%theta(k))
        f2 = -self%mu(k) * lam(self%nrow(k)) * sin(self%theta(k))
        df = max(df, hypot(f1 - self%lam_rows(t1), f2 - self%lam_rows(t2)))
        fmax = max(fmax, hypot(f1, f2))
        self%lam_rows(t1) = f1
        self%lam_rows(t2) = f2
      end do
      if (dmax <= THETA_TOL .and. df <= FORCE_RTOL * fmax) then
        converged = slips_forward(self)
        return
      end if
    end do
  end subroutine cone_known_forces

  !> The fixed point's update from the slips g of its last solve: each slipping condition's σ = s·d(θ)
  !> and, where σ > 0, θ the slip's direction; dmax the largest change of θ. (σ <= 0, slipping
  !> against its force: θ stays, and slips_forward hands the pass to the Newton.)
  pure subroutine follow_slips(self, g, dmax)
    class(coulomb_t), intent(inout) :: self
    real(dp), intent(in) :: g(:)
    real(dp), intent(out) :: dmax
    integer :: k
    real(dp) :: s1, s2, th
    dmax = 0.0_dp
    do k = 1, self%n
      if (self%state(k) /= FRICTION_SLIP_POS) cycle
      s1 = g(self%trow(k))
      s2 = g(self%trow2(k))
      self%sig(k) = s1 * cos(self%theta(k)) + s2 * sin(self%theta(k))
      if (.not. self%sig(k) > 0.0_dp) cycle
      th = atan2(s2, s1)
      dmax = max(dmax, abs(atan2(sin(th - self%theta(k)), cos(th - self%theta(k)))))
      self%theta(k) = th
    end do
  end subroutine follow_slips

  !> Whether every slipping condition slips along its force's opposite (σ > 0). A fixed point that
  !> settles with one slipping against its force (σ <= 0, where θ is not updated) is not the pass's
  !> answer: the Schur block's Newton, which solves θ and σ together, decides that pass.
  pure logical function slips_forward(self) result(ok)
    class(coulomb_t), intent(in) :: self
    integer :: k
    ok = .true.
    do k = 1, self%n
      if (self%state(k) == FRICTION_SLIP_POS) ok = ok .and. self%sig(k) > 0.0_dp
    end do
  end function slips_forward

  !> The multipliers of the rows from the unknowns lr: Λ of I as they are, a slipping condition's
  !> Λ_T = -μ Λ_N (cos θ, sin θ); into lam (over every row).
  pure subroutine cone_multipliers(self, ni, nl, lam)
    class(coulomb_t), intent(in) :: self
    integer, intent(in) :: ni, nl
    real(dp), intent(inout) :: lam(:)
    integer :: k, l
    real(dp) :: f
    do l = 1, ni
      lam(self%rows(l)) = self%lr(l)
    end do
    do k = 1, self%n
      if (self%state(k) /= FRICTION_SLIP_POS) cycle
      l = self%pos(self%trow(k))
      if (l > nl) cycle
      f = -self%mu(k) * self%lr(self%pos(self%nrow(k)))
      lam(self%trow(k)) = f * cos(self%lr(l))
      lam(self%trow2(k)) = f * sin(self%lr(l))
    end do
  end subroutine cone_multipliers

  !> One Newton step on the unknowns lr(1:nl): the residual r = (g_I, g_t - σ d) and its Jacobian
  !> from W's block wb, J Δ = -r by dgesv (|Δθ| capped at THETA_STEP), then lr <- lr + t Δ with t
  !> halved from 1 until |r| falls (Armijo, down to 1/64); dmax the largest |t Δθ| (0 without a
  !> slipping condition: the system is then linear, solved at once).
  subroutine cone_newton_step(self, q, ni, nl, dmax, stat, errmsg)
    class(coulomb_t), intent(inout) :: self
    real(dp), intent(in) :: q(:)
    integer, intent(in) :: ni, nl
    real(dp), intent(out) :: dmax
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, l, ln, info
    real(dp) :: c, s, sig, lamn, r0, rt, t
    stat = STAT_OK
    dmax = 0.0_dp
    call cone_residual(self, q, ni, nl, self%lr, self%col(:, 1))
    r0 = norm2(self%col(1:nl, 1))
    ! The Jacobian: W's columns for Λ of I; a slipping condition adds to its Λ_N's column
    ! -μ (c W_t1 + s W_t2), and its θ and σ columns.
    self%m(1:nl, 1:ni) = self%wb(1:nl, 1:ni)
    do k = 1, self%n
      if (self%state(k) /= FRICTION_SLIP_POS) cycle
      l = self%pos(self%trow(k))
      ln = self%pos(self%nrow(k))
      c = cos(self%lr(l))
      s = sin(self%lr(l))
      sig = self%lr(l + 1)
      lamn = self%lr(ln)
      self%m(1:nl, ln) = self%m(1:nl, ln) - self%mu(k) * (c * self%wb(1:nl, l) + s * self%wb(1:nl, l + 1))
      self%m(1:nl, l) = -self%mu(k) * lamn * (-s * self%wb(1:nl, l) + c * self%wb(1:nl, l + 1))
      self%m(l, l) = self%m(l, l) + sig * s
      self%m(l + 1, l) = self%m(l + 1, l) - sig * c
      self%m(1:nl, l + 1) = 0.0_dp
      self%m(l:l + 1, l + 1) = [-c, -s]
    end do
    self%rhs(1:nl) = -self%col(1:nl, 1)
    info = 0
    if (nl > 0) call dgesv(nl, 1, self%m, size(self%m, 1), self%ipiv, self%rhs, size(self%rhs), info)
    if (info /= 0) then
      call set_error(stat, errmsg, STAT_RUN, 'friction: the conditions of the contact zone are dependent (a ' // &
        'FRICTION contact on a DOF an IMPOSE or another contact also holds, or a slipping contact without ' // &
        'normal force nor slip)')
      return
    end if
    do k = 1, self%n
      if (self%state(k) /= FRICTION_SLIP_POS) cycle
      l = self%pos(self%trow(k))
      self%rhs(l) = max(-THETA_STEP, min(THETA_STEP, self%rhs(l)))
      dmax = max(dmax, abs(self%rhs(l)))
    end do
    t = 1.0_dp
    do                                         ! (rho: the trial unknowns)
      self%rho(1:nl) = self%lr(1:nl) + t * self%rhs(1:nl)
      if (dmax == 0.0_dp) exit                 ! (linear: the full step is the solution)
      call cone_residual(self, q, ni, nl, self%rho, self%col(:, 1))
      rt = norm2(self%col(1:nl, 1))
      if (rt <= (1.0_dp - 1.0e-4_dp * t) * r0 .or. t <= 1.0_dp / 64) exit
      t = 0.5_dp * t
    end do
    dmax = t * dmax
    self%lr(1:nl) = self%rho(1:nl)
  end subroutine cone_newton_step

  !> r(1:nl) = (g_I, g_t1 - σ cos θ, g_t2 - σ sin θ) at the unknowns x(1:nl), g = q + W Λ(x)
  !> (self%keep's rows as they are; the multipliers of the rows in the scratch on).
  subroutine cone_residual(self, q, ni, nl, x, r)
    class(coulomb_t), intent(inout) :: self
    real(dp), intent(in) :: q(:), x(:)
    integer, intent(in) :: ni, nl
    real(dp), intent(inout) :: r(:)
    integer :: k, l
    real(dp) :: f
    self%lam_rows(1:ni) = x(1:ni)
    do k = 1, self%n
      if (self%state(k) /= FRICTION_SLIP_POS) cycle
      l = self%pos(self%trow(k))
      f = -self%mu(k) * x(self%pos(self%nrow(k)))
      self%lam_rows(l:l + 1) = f * [cos(x(l)), sin(x(l))]
    end do
    do l = 1, nl
      r(l) = q(self%rows(l))
    end do
    do k = 1, nl                               ! (loops: matmul may take a temporary)
      r(1:nl) = r(1:nl) + self%lam_rows(k) * self%wb(1:nl, k)
    end do
    do k = 1, self%n
      if (self%state(k) /= FRICTION_SLIP_POS) cycle
      l = self%pos(self%trow(k))
      r(l:l + 1) = r(l:l + 1) - x(l + 1) * [cos(x(l)), sin(x(l))]
    end do
  end subroutine cone_residual
end submodule coulomb_cone
