!> One step of the scheme (method.md sections 1-3): the iteration of eq (9) with the contact
!> multipliers, then the end of the step in the paper's order, (3), then (12)-(15), then (16)
!> (or PERSIST). The time loop (newmark) calls iterate_eq9 and end_step; it owns the outputs,
!> the checkpoints and the messages.
module newmark_step
  use kinds, only: dp
  use errors, only: STAT_OK
  use scene, only: scene_t
  use assembly, only: system_t, commit_state
  use contact_geometry, only: following_t
  use contact, only: contact_set_t, contact_report_t, contact_prepare, contact_solve_step, contact_end_step, &
    contact_add_force
  use step_state, only: step_state_t
  use iteration_matrix, only: iteration_matrix_t
  use nonlinear_zone, only: zone_t
  implicit none
  private
  public :: residual_history, step_report_t, iterate_eq9, iterate_eq9_zone, end_step, following_rows, STEP_CONVERGED, &
    STEP_DIVERGED, &
    STEP_NOT_CONVERGED, &
    STEP_NONFINITE, &
    STEP_INVERTED, STEP_INDEFINITE

  !> How the iteration of a step ended.
  integer, parameter :: STEP_CONVERGED = 0       !< converged (or a linear step refined to round-off)
  integer, parameter :: STEP_DIVERGED = 1        !< a residual norm is not finite
  integer, parameter :: STEP_NOT_CONVERGED = 2   !< MAX_ITERATIONS reached
  integer, parameter :: STEP_NONFINITE = 3       !< converged on a non-finite du or Bσ
  integer, parameter :: STEP_INVERTED = 4        !< converged on a KINEMATICS LARGE member turned inside out
  integer, parameter :: STEP_INDEFINITE = 5      !< a KINEMATICS LARGE tangent that is not positive definite

  type :: step_report_t
    integer :: outcome = STEP_CONVERGED
    integer :: iterations = 0
    integer :: bad_equation = 0              !< first non-finite entry (STEP_DIVERGED, STEP_NONFINITE)
    integer :: element = 0                   !< the inverted element (STEP_INVERTED)
    real(dp) :: force_scale = 0.0_dp         !< of the convergence test (STEP_NOT_CONVERGED)
    character(len=:), allocatable :: message !< the factorization's (STEP_INDEFINITE)
  end type step_report_t

contains

  !> Iterate eq (9) on du from du = 0 (F(n+1) already in st%f_np1): solve with the iteration
  !> matrix, add the contact multipliers (cs present: du = du_free + S⁻¹C'Λ, the LCP of the
  !> active set), evaluate the laws along the step, the residual; until the residual (with C'Λ
  !> on the right) is below SCHEME TOLERANCE x the step's force scale. Linear steps: one iterate,
  !> or with contact or EXTENDED refinement until the residual stops falling. stat reports
  !> a failed factorization or contact solve; the other endings are rep%outcome.
  subroutine iterate_eq9(scn, sys, st, mat, rep, stat, errmsg, cs, lam, follow)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(step_state_t), intent(inout) :: st
    type(iteration_matrix_t), intent(inout), target :: mat
    type(step_report_t), intent(out) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(contact_set_t), intent(inout), optional :: cs
    real(dp), intent(inout), optional :: lam(:)
    type(following_t), intent(inout), optional :: follow
    integer :: iter
    real(dp) :: rwork, target, fscale, dun(3)
    logical :: refactored, switch, relax, relaxed
    dun = 0.0_dp
    relax = .false.
    call st%begin_step()
    call mat%begin_step()
    do iter = 1, scn%max_iterations
      rep%iterations = iter
      call mat%update(sys, refactored, stat, errmsg)
      if (stat /= STAT_OK .and. sys%elems%any_large) then
        ! A LARGE tangent that does not factorize even without its compressive part: the iterate has
        ! gone where no element should (an element inverted, a point past its law's range). A step
        ! failure, which SCHEME RETRY takes again as sub-steps, not the end of the run.
        rep%outcome = STEP_INDEFINITE
        rep%element = sys%elems%inverted
        rep%message = errmsg
        stat = STAT_OK
        return
      end if
      if (stat /= STAT_OK) errmsg = 'tangent matrix: ' // errmsg
      if (stat == STAT_OK .and. refactored .and. present(cs)) &
        call contact_prepare(cs, mat%factor, stat, errmsg, sys%ops%pat, mat%sval)
      if (stat /= STAT_OK) return
      call mat%solve(st%r, st%ddu, stat, errmsg)
      if (stat == STAT_OK .and. allocated(sys%ops%aval) .and. mat%on_tangent_now()) &
        call anti_sweep(sys, mat, st, stat, errmsg, cs)
      if (stat /= STAT_OK) return
      ! On a tangent, an iterate whose residual rose after a fall, or that oscillates (|du| up and
      ! down) with its residual not halved in two iterates (Newton cycling: a point switching between
      ! plastic loading and elastic unloading, contacts chattering; measured on the axisymmetric
      ! Taylor bar at 5e-7 s) is followed by a relaxed one, halfway from the last du to the new iterate (the
      ! contact solve's: its multipliers balance the whole residual; relaxing the free iterate
      ! before it left half the contact residual for ever). A relaxed iterate, whose gaps and
      ! multipliers need not be complementary, never ends the step.
      relaxed = relax
      if (relax) st%du_prev = st%du
      if (present(cs)) then
        ! Multipliers: the unconstrained iterate, then du = du_free + S^-1 C' Lambda with the
        ! active set of the LCP (gaps >= 0, Lambda >= 0, complementarity).
        st%ddu = st%du + st%ddu
        if (present(follow) .and. iter > 1) call following_rows(scn, sys, st, mat, cs, follow, .true., stat, errmsg)
        if (stat /= STAT_OK) return
        call contact_solve_step(cs, mat%factor, st%u, st%ddu, st%du, lam, stat, errmsg)
        if (stat /= STAT_OK) then
          errmsg = 'contact: ' // errmsg
          return
        end if
      else
        st%du = st%du + st%ddu
      end if
      if (relax) st%du = st%du_prev + 0.5_dp * (st%du - st%du_prev)
      call st%trial(scn, sys, scn%energy_correction, mat%wants_tangent())
      ! (Rows that follow the geometry are re-linearized at the midpoint of the iterate: a linear
      ! model iterates too, until the residual stops falling.)
      if (sys%elems%linear .and. .not. st%extended .and. .not. following(follow)) exit
      call st%residual(sys)
      ! st%r is the residual without the contact forces: the next unconstrained iterate is
      ! du + S^-1 r and contact_solve_step adds S^-1 C' Lambda with the total multiplier.
      ! Convergence is judged on the full residual, with C' Lambda on the right of eq (9).
      if (present(cs)) then
        st%ddu = st%r
        call contact_add_force(cs, st%ddu)
        st%res_hist(iter) = norm2(st%ddu)
        rwork = abs(dot_product(st%ddu, st%du))
      else
        st%res_hist(iter) = norm2(st%r)
        rwork = abs(dot_product(st%r, st%du))
      end if
      if (.not. (st%res_hist(iter) <= huge(1.0_dp))) then
        rep%outcome = STEP_DIVERGED
        rep%bad_equation = max(first_nonfinite(st%r), 1)
        return
      end if
      dun(1) = dun(2)                          ! |du| of the last three iterates
      dun(2) = dun(3)
      dun(3) = norm2(st%du)
      if (sys%elems%linear .and. following(follow)) then
        ! Rows re-linearized at the iterate's midpoint (a curved obstacle's discrete gradient): on
        ! until the iterate settles (|du| to 1e-12: the row is then the one of its own du).
        if (iter >= 2 .and. abs(dun(3) - dun(2)) <= 1.0e-12_dp * dun(3)) exit
        if (iter == scn%max_iterations) exit
        cycle
      else if (sys%elems%linear) then
        ! Refinement of a linear step: on until the residual stops falling (round-off).
        if (iter >= 2) then
          if (st%res_hist(iter) >= 0.5_dp * st%res_hist(iter - 1)) exit
        end if
        ! (An absolute floor such as 16 eps x force scale stops too early: at small steps the
        ! scale is 4Mv/h and the first iterate passes it unrefined.)
        if (st%res_hist(iter) == 0.0_dp .or. iter == min(scn%max_iterations, 6)) exit
        cycle
      end if
      fscale = force_scale(st)
      relax = .not. relaxed .and. mat%on_tangent_now() .and. cycling(st%res_hist(1:iter), dun)
      if (.not. relaxed .and. converged(scn, sys, st%res_hist(1:iter), rwork, fscale, step_work(st), norm2(st%du), &
        st%energy_share, target)) exit
      ! The iteration matrix's policy after a residual: TANGENT's fallback on a stall; AUTO's
      ! tangent where it pays (assembled at this iterate, factorized by the next update).
      call mat%after_residual(sys, st%res_hist, iter, target, switch, refactored, stat, errmsg)
      if (stat == STAT_OK .and. refactored .and. present(cs)) &
        call contact_prepare(cs, mat%factor, stat, errmsg, sys%ops%pat, mat%sval)
      if (stat /= STAT_OK) return
      if (switch) call st%trial(scn, sys, scn%energy_correction, .true.)
      if (iter == scn%max_iterations) then
        rep%outcome = STEP_NOT_CONVERGED
        rep%force_scale = fscale
        return
      end if
    end do
    call end_checks(sys, st, rep)
  end subroutine iterate_eq9

  !> The rows of the contacts that follow the geometry (contact_geometry), paired at the start of
  !> the step in u(n), or (midpoint) at the midpoint of the iterate du with the step's partners, and
  !> the multipliers' S data for them.
  subroutine following_rows(scn, sys, st, mat, cs, follow, midpoint, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    type(step_state_t), intent(in) :: st
    type(iteration_matrix_t), intent(inout) :: mat
    type(contact_set_t), intent(inout) :: cs
    type(following_t), intent(inout) :: follow
    logical, intent(in) :: midpoint
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (follow%count() == 0) return
    if (midpoint) then
      call follow%update(scn%mesh%x, sys%dofs%eqn, st%u, cs, stat, errmsg, st%du)
    else
      call follow%update(scn%mesh%x, sys%dofs%eqn, st%u, cs, stat, errmsg)
    end if
    if (stat == STAT_OK) call contact_prepare(cs, mat%factor, stat, errmsg, sys%ops%pat, mat%sval)
  end subroutine following_rows

  !> End of a converged step: the points' state committed, the works of the step (external
  !> ½ du'(F(n) + F(n+1)), correction ½ du'Bσc), eq (3), then with contact the impact
  !> correction of SCHEME IMPACT (energy restored in e_rest, report in crep), then the new state.
  subroutine end_step(scn, sys, st, dw_ext, dw_corr, e_rest, stat, errmsg, cs, body, crep)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(step_state_t), intent(inout) :: st
    real(dp), intent(out) :: dw_ext, dw_corr, e_rest
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(contact_set_t), intent(inout), optional :: cs
    integer, intent(in), optional :: body(:)
    type(contact_report_t), intent(out), optional :: crep
    real(dp) :: w_massless
    stat = STAT_OK
    call commit_state(sys)
    dw_ext = 0.5_dp * dot_product(st%du, st%f_n + st%f_np1)
    dw_corr = 0.5_dp * dot_product(st%du, st%fcorr)
    w_massless = st%massless_work()
    call st%velocity(sys)
    e_rest = 0.0_dp
    if (present(cs)) then
      ! Order at the end of a step: (3), then (12)-(15), then (16) (or PERSIST).
      call contact_end_step(cs, scn%impact, st%u, st%du, st%v, st%mv, e_rest, stat, errmsg, body=body, report=crep, &
        step=st%h)
      if (stat /= STAT_OK) then
        errmsg = 'impact correction: ' // errmsg
        return
      end if
      call st%absorb_velocity_change()
      ! MASSLESS: of the massless rows' extra work, the start reactions' share went to the
      ! impact correction (releases); the rest is a node out of equilibrium at n snapping to it,
      ! energy the massless model dissipates (docs/contact.md).
      if (present(crep) .and. allocated(st%massless)) crep%snap_dissipated = crep%reaction_work - w_massless
    end if
    call st%commit(sys)
  end subroutine end_step

  !> Newton's step with the Jacobian's antisymmetric part A (sys%ops%aval: LARGE surface and volume
  !> elements under eq (9), whose force 2 B_NL(F_mid)' S̄ and the laws' path mean have a Jacobian that
  !> is not symmetric, and small-strain VON_MISES points; S, factorized by CHOLMOD, holds its
  !> symmetric part): one sweep of (S + A) x = r_t,
  !>     ddu <- S⁻¹ r - S⁻¹ A S⁻¹ r_t,
  !> r_t the whole residual (with the contact forces C'Λ of the iterate; the contact solve then adds
  !> S⁻¹C'Λ to the free iterate, so its fixed point stays r_t = 0). |S⁻¹A| is about 1/50 on the
  !> Taylor bar: the sweep leaves about 1/2500 of the step's error where S alone left 1/50 (Newton's
  !> contraction changes, not the converged state). One solve more, two with contact rows.
  subroutine anti_sweep(sys, mat, st, stat, errmsg, cs)
    type(system_t), intent(in) :: sys
    type(iteration_matrix_t), intent(inout) :: mat
    type(step_state_t), intent(inout) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(contact_set_t), intent(in), optional :: cs
    stat = STAT_OK
    if (present(cs)) then
      st%aw = st%r
      call contact_add_force(cs, st%aw)
      call mat%solve(st%aw, st%ay, stat, errmsg)
      if (stat /= STAT_OK) return
    else
      st%ay = st%ddu
    end if
    call sys%ops%pat%anti_matvec(sys%ops%aval, st%ay, st%aw)
    call mat%solve(st%aw, st%ay, stat, errmsg)
    if (stat == STAT_OK) st%ddu = st%ddu - st%ay
  end subroutine anti_sweep

  !> Whether the iteration cycles (iterate_eq9's relaxed iterate), from the third iterate on: the
  !> residual res rose after a fall, or |du| (dun: the last three iterates) went up and down while
  !> the residual did not halve in two iterates.
  pure logical function cycling(res, dun)
    real(dp), intent(in) :: res(:), dun(3)
    integer :: n
    n = size(res)
    cycling = .false.
    if (n < 3) return
    cycling = (res(n) > res(n - 1) .and. res(n - 1) <= res(n - 2)) .or. &
      ((dun(3) - dun(2)) * (dun(2) - dun(1)) < 0.0_dp .and. res(n) > 0.5_dp * res(n - 2))
  end function cycling

  !> The convergence test of eq (9) after the residual norms res(1:iter), the residual's work
  !> rwork = |r·Δu|, the force scale, the work the step exchanges and ‖Δu‖ (docs/input.md, SCHEME
  !> TOLERANCE): ‖r‖ ≤ TOLERANCE x the force scale; below the round-off floor of the LARGE members
  !> (a stiff member's force moves by k ulp(|x|) when its nodes move by one ulp), on until the
  !> residual stagnates: the floor itself would leave r·Δu in the balance (1e-12 J per step on
  !> beam_drop_inclined_large, docs/large-displacements.md). And the energy: r·Δu is what the
  !> step's energy balance misses, so it must stay within TOLERANCE x the work the step exchanges,
  !> or at the round-off of that product; past the force test, a residual that stagnates ends the
  !> step all the same. target: the residual AUTO aims at (the force test's, or the energy
  !> budget's if that is lower).
  logical function converged(scn, sys, res, rwork, fscale, work, dunorm, share, target)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: res(:), rwork, fscale, work, dunorm
    real(dp), intent(in) :: share          !< the run's TOLERANCE x energy scale per step (step_state)
    real(dp), intent(out) :: target
    real(dp) :: limit, budget
    logical :: stagnant
    integer :: iter
    iter = size(res)
    limit = max(scn%tolerance * fscale, 4.0_dp * sys%elems%round_floor)
    budget = huge(1.0_dp)
    if (scn%energy_test) budget = max(scn%tolerance * work, 64.0_dp * epsilon(1.0_dp) * dunorm * fscale)
    stagnant = .false.
    if (iter >= 2) stagnant = res(iter) >= 0.5_dp * res(iter - 1)
    converged = .false.
    if (res(iter) <= scn%tolerance * fscale) converged = rwork <= budget .or. stagnant
    ! Past the force test, a stagnating iterate below the attainable residual (round_floor) ends the
    ! step only if its residual's work passes the energy test: the balance stays within TOLERANCE of
    ! the step's work, or of the run's energy (its share per step: the run's |balance| then stays
    ! below TOLERANCE x E). (The 16 x 80 Taylor bar's corner element, crushed to 1.6 %, leaves 0.1 to
    ! 0.3 N of noise, 5e-9 J of residual work against 1.3e-10 J of TOLERANCE x the step's work: its
    ! steps of 75-78 us stopped there.)
    if (res(iter) <= limit .and. stagnant .and. (res(iter) <= scn%tolerance * fscale .or. &
      rwork <= max(budget, share))) converged = .true.
    target = min(limit, budget / max(dunorm, tiny(1.0_dp)))
  end function converged

  !> iterate_eq9 on the nonlinear zone (nonlinear_zone): du = a + W y with a = S⁻¹ r(0), the one
  !> solve of the step (with cs: du = a + W y + S⁻¹C'Λ, the multipliers of the contact solve at
  !> each iterate); the elements touching Z evaluated at each iterate, the residual's Z rows (with
  !> C'Λ on the right: zero elsewhere), y updated by S's iteration or (no contact rows) by Newton
  !> through Woodbury; then du on every equation and the whole trial state once. The convergence test is
  !> iterate_eq9's, with the step's exchanged work and ‖Δu‖ taken on Z (the residual's work
  !> r·Δu is exact: r is zero off Z) and ‖Bσ(n+1)‖ from ‖Bσ(n)‖ and Z's rows.
  !> The tangent fallback is TANGENT's: two iterates in a row without progress from the fourth
  !> on, or I + D W_Z singular, and S's iteration for the rest of the step. (Where G's LU is
  !> costly it is kept over the iterates while they contract: zone_t%uses_tangent.)
  subroutine iterate_eq9_zone(scn, sys, st, mat, zone, rep, stat, errmsg, cs, lam, follow)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(step_state_t), intent(inout) :: st
    type(iteration_matrix_t), intent(inout) :: mat
    type(zone_t), intent(inout) :: zone
    type(step_report_t), intent(out) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(contact_set_t), intent(inout), optional :: cs
    real(dp), intent(inout), optional :: lam(:)
    type(following_t), intent(inout), optional :: follow
    integer :: iter
    real(dp) :: rwork, work, dunorm, dfint2, fext, fn, fm, fscale, target
    logical :: fallback, tangent, newton, newton_ok
    call st%begin_step()
    call zone%begin_step()
    call mat%solve(st%r, st%ddu, stat, errmsg)
    if (stat /= STAT_OK) return
    fext = norm2(st%f_np1 + st%f_n)
    fn = norm2(st%fint_n)
    fm = norm2((4.0_dp / st%h) * st%mv)
    fallback = .false.
    do iter = 1, scn%max_iterations
      rep%iterations = iter
      tangent = zone%uses_tangent(fallback, st%res_hist(1:iter), iter)
      if (present(cs)) then
        ! The multipliers as in iterate_eq9: du = du_free + S⁻¹C'Λ on every equation, and C'Λ
        ! (in mdu, unused by the zone) on the right of Z's rows.
        call zone%free_du(st)
        if (present(follow) .and. iter > 1) call following_rows(scn, sys, st, mat, cs, follow, .true., stat, errmsg)
        if (stat /= STAT_OK) return
        call contact_solve_step(cs, mat%factor, st%u, zone%dfree, st%du, lam, stat, errmsg)
        if (stat /= STAT_OK) then
          errmsg = 'contact: ' // errmsg
          return
        end if
        st%mdu = 0.0_dp
        call contact_add_force(cs, st%mdu)
      end if
      call zone%trial(scn, sys, st, tangent)
      if (present(cs)) then
        call zone%residual(sys, st, st%res_hist(iter), rwork, work, dunorm, dfint2, st%mdu)
      else
        call zone%residual(sys, st, st%res_hist(iter), rwork, work, dunorm, dfint2)
      end if
      if (.not. (st%res_hist(iter) <= huge(1.0_dp))) then
        rep%outcome = STEP_DIVERGED
        rep%bad_equation = max(first_nonfinite(st%r), 1)
        return
      end if
      fscale = max(fext, fn, sqrt(max(fn**2 + dfint2, 0.0_dp)), fm, tiny(1.0_dp))
      if (converged(scn, sys, st%res_hist(1:iter), rwork, fscale, work, dunorm, st%energy_share, target)) exit
      if (iter == scn%max_iterations) then
        rep%outcome = STEP_NOT_CONVERGED
        rep%force_scale = fscale
        return
      end if
      if (zone%newton_on(fallback) .and. iter >= 4 .and. .not. sys%elems%any_large) then
        fallback = st%res_hist(iter) >= 0.99_dp * st%res_hist(iter - 1) .and. &
          st%res_hist(iter - 1) >= 0.99_dp * st%res_hist(iter - 2)
      end if
      newton = zone%newton_on(fallback)
      call zone%update(sys, newton, tangent .and. newton, newton_ok)
      if (newton .and. .not. newton_ok) fallback = .true.
    end do
    if (.not. present(cs)) call zone%full_du(st)
    call st%trial(scn, sys, scn%energy_correction, .false.)
    call end_checks(sys, st, rep)
  end subroutine iterate_eq9_zone

  !> After a converged iteration: a non-finite du or Bσ, or an inverted LARGE member.
  subroutine end_checks(sys, st, rep)
    type(system_t), intent(in) :: sys
    type(step_state_t), intent(in) :: st
    type(step_report_t), intent(inout) :: rep
    rep%bad_equation = first_nonfinite(st%du)
    if (rep%bad_equation == 0) rep%bad_equation = first_nonfinite(st%fint)
    if (rep%bad_equation > 0) rep%outcome = STEP_NONFINITE
    if (rep%outcome == STEP_CONVERGED .and. sys%elems%inverted > 0) then
      rep%outcome = STEP_INVERTED
      rep%element = sys%elems%inverted
    end if
  end subroutine end_checks

  !> Force scale of the step for the convergence test (docs/input.md, SCHEME TOLERANCE).
  real(dp) function force_scale(st)
    type(step_state_t), intent(in) :: st
    force_scale = max(norm2(st%f_np1 + st%f_n), norm2(st%fint_n), norm2(st%fint), norm2((4.0_dp / st%h) * st%mv), &
      tiny(1.0_dp))
  end function force_scale

  !> The work the step exchanges at the current iterate: |Δu·F̄| + |Δu·(Bσ(n) + Bσ(n+1) + Bσc)/2|.
  real(dp) function step_work(st)
    type(step_state_t), intent(in) :: st
    step_work = 0.5_dp * (abs(dot_product(st%du, st%f_n + st%f_np1)) + abs(dot_product(st%du, st%fint_n + st%fint + &
      st%fcorr)))
  end function step_work

  !> Index of the first NaN or infinite entry, 0 if none.
  !> Residual norms as text, for the non-convergence reports (a step's, a STATIC increment's).
  function residual_history(res) result(txt)
    real(dp), intent(in) :: res(:)
    character(len=:), allocatable :: txt
    integer :: k
    character(len=16) :: buf
    txt = ''
    do k = 1, size(res)
      write (buf, '(es10.3)') res(k)
      txt = txt // trim(adjustl(buf)) // merge(', ', '  ', k < size(res))
    end do
    txt = trim(txt)
  end function residual_history

  !> There are rows that follow the geometry (contact_geometry).
  logical function following(follow)
    type(following_t), intent(in), optional :: follow
    following = .false.
    if (present(follow)) following = follow%count() > 0
  end function following

  pure integer function first_nonfinite(x)
    real(dp), intent(in) :: x(:)
    integer :: i
    first_nonfinite = 0
    do i = 1, size(x)
      if (.not. (abs(x(i)) <= huge(1.0_dp))) then
        first_nonfinite = i
        return
      end if
    end do
  end function first_nonfinite
end module newmark_step
