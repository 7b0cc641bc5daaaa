!> The end of a step with contact (method.md sections 3 and 6): events, the energy error (10),
!> IMPACT PAPER's impulses (12)-(15) and hzero reflection (16), IMPACT PERSIST's projection and
!> scaling. A submodule of contact: it works on the set's private state.
submodule (contact) contact_impact
  implicit none

contains

  !> End of a converged step, after eq (3) gave v = v(n+1) and mv = M v(n+1):
  !>   events (established: active now and not at the end of the last step; released: the
  !>   reverse), E_j = ½ Λ_j max(g_j(n), 0) (10) for the established ones, then the correction
  !>   of the mode (IMPACT_OFF: none; IMPACT_PAPER: (12)-(15) then (16); IMPACT_PERSIST: section 6,
  !>   falling back to PAPER for bodies left without kinetic energy; rows that follow the
  !>   geometry: the rest of their multiplier's work given back by scaling), reactions R(n+1) = Λ - R(n)
  !>   (0 for inactive conditions), new state. v and mv are updated together (mv stays M v).
  !>   body(i) is the mesh-connected component of equation i (0: none), required by PERSIST.
  !>   energy_restored = kinetic energy added, measured (= Σ E_j to round-off). The events of
  !>   the step are cs%events(1:cs%n_events).
  module procedure contact_end_step
    type(contact_report_t) :: rep, geo
    real(dp) :: t_before
    integer :: j, k

    stat = STAT_OK
    energy_restored = 0.0_dp
    cs%n_ev = 0
    if (.not. cs%finalized) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_end_step: call contact_finalize first')
      return
    end if
    if (cs%nc == 0) then
      if (present(report)) report = rep
      return
    end if
    if ((mode == IMPACT_PAPER .or. mode == IMPACT_PERSIST .or. mode == IMPACT_SYMMETRIC) .and. .not. cs%mass_set .and. &
      cs%first_bilateral > 1) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_end_step: call contact_set_mass first')
      return
    end if
    associate (gn => cs%gn, gend => cs%gend, now => cs%now, est => cs%est, rel => cs%rel, e => cs%e, y => cs%y)
      call step_conditions(cs, mode, u_n, du, rep)
      cs%gaps_kept = .false.
      t_before = 0.5_dp * dot_product(v, mv)
      cs%cimp = 0.0_dp
      cs%bimp = 0.0_dp

      if (rep%n_establish > 0 .or. ((mode == IMPACT_MASSLESS .or. mode == IMPACT_SYMMETRIC) .and. rep%n_release > 0)) then
        if ((mode == IMPACT_PERSIST .or. mode == IMPACT_MASSLESS .or. mode == IMPACT_SYMMETRIC) .and. &
          .not. present(body)) then
          call set_error(stat, errmsg, STAT_INPUT, 'contact_end_step: IMPACT PERSIST, MASSLESS and SYMMETRIC need body(:)')
          return
        end if
        select case (mode)
        case (IMPACT_PAPER)
          call paper_correction(cs, est, v, mv, rep, stat, errmsg)
        case (IMPACT_PERSIST)
          call persist_correction(cs, body, v, mv, rep, stat, errmsg)
        case (IMPACT_MASSLESS)
          ! Massless contact nodes: no velocity to reflect or project; the energy the step lost
          ! at establishment, or counted at a release, goes to (comes from) the body by scaling
          ! (groups without kinetic energy are left, reported in persist_fallbacks: the balance
          ! shows it).
          call persist_correction(cs, body, v, mv, rep, stat, errmsg, project=.false.)
        case (IMPACT_SYMMETRIC)
          call symmetric_correction(cs, body, v, mv, rep, stat, errmsg)
        case (IMPACT_OFF)
        case default
          call set_error(stat, errmsg, STAT_INPUT, 'contact_end_step: unknown impact mode ' // str(mode))
        end select
        if (stat /= STAT_OK) return
        ! PERSIST's and SYMMETRIC's groups left without kinetic energy (cs%fallback): PAPER.
        ! (Nested: Fortran's .and. may read both sides, and other modes leave cs%fallback as it was.)
        if (mode == IMPACT_PERSIST .or. mode == IMPACT_SYMMETRIC) then
          if (any(cs%fallback)) then
            cs%est = cs%fallback
            call paper_correction(cs, cs%est, v, mv, rep, stat, errmsg)
            cs%est = now .and. .not. cs%st%active
            if (stat /= STAT_OK) return
          end if
        end if
        if (mode /= IMPACT_OFF) energy_restored = 0.5_dp * dot_product(v, mv) - t_before
      end if
      ! Rows that follow the geometry (contact_rewrite) start each step at the gap of the new
      ! configuration, which is not the end gap of the last step's row (they differ to second
      ! order in the motion), and close it to zero. The multiplier's work ½ Λ_j (g_j(n+1) - g_j(n))
      ! would be work of a frictionless contact: what eq (10) does not take back (all of it for a
      ! held contact) is given back by scaling the group, momentum kept.
      if (mode /= IMPACT_OFF .and. any(cs%follow .and. now)) then
        if (.not. present(body)) then
          call set_error(stat, errmsg, STAT_INPUT, 'contact_end_step: rows that follow the geometry need body(:)')
          return
        end if
        do j = 1, cs%nc
          cs%xg(j) = 0.0_dp
          if (cs%follow(j) .and. now(j)) cs%xg(j) = 0.5_dp * cs%lam_step(j) * (gn(j) - gend(j)) - e(j)
        end do
        call persist_correction(cs, body, v, mv, geo, stat, errmsg, project=.false., geometry=cs%xg)   ! (geo: scratch)
        if (stat /= STAT_OK) return
        energy_restored = 0.5_dp * dot_product(v, mv) - t_before
      end if
      rep%energy_restored = energy_restored

      ! Reactions (reported only) and the new state.
      if (mode == IMPACT_MASSLESS) then
        cs%r = merge(cs%st%lambda, 0.0_dp, now)
      else
        cs%r = merge(cs%st%lambda - cs%st%r_prev, 0.0_dp, now)
      end if
      k = 0
      do j = 1, cs%nc
        if (.not. (est(j) .or. rel(j))) cycle
        k = k + 1
        cs%ev(k) = contact_event_t(j, merge(EVENT_ESTABLISH, EVENT_RELEASE, est(j)), gn(j), gend(j), &
          cs%lam_step(j), cs%r(j), e(j), y(j))
      end do
      cs%n_ev = k
      cs%st%r_prev = cs%r
      cs%st%active = now
      cs%st%gap_n = gend
    end associate
    if (present(report)) report = rep
  end procedure contact_end_step

  !> The conditions of the step that just converged: gaps g(n), g(n+1); active now, established,
  !> released; E_j (10) of the established ones and, under MASSLESS, -½ R(n) g(n+1) of the released
  !> ones (docs/contact.md); the step's multiplier; counts and works into rep. Work arrays of cs
  !> only: contact_shortfall may call it before contact_end_step does.
  subroutine step_conditions(cs, mode, u_n, du, rep)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: mode
    real(dp), intent(in) :: u_n(:), du(:)
    type(contact_report_t), intent(inout) :: rep
    integer :: j
    associate (gn => cs%gn, gend => cs%gend, now => cs%now, est => cs%est, rel => cs%rel, e => cs%e, y => cs%y)
      if (.not. cs%gaps_kept) then             ! (else kept with the rows of the step: contact_step_gaps)
        call cs%c%gaps(u_n, gn)
        do j = 1, cs%nc
          gend(j) = gn(j) + cs%c%dot(j, du)
        end do
      end if
      ! Bilateral rows (IMPOSE) are no contacts: no events, no correction; their multipliers'
      ! work is the work of the imposed motion, for the driver's external work.
      now = cs%st%active_iter .and. .not. cs%bilat
      rep%imposed_work = 0.5_dp * sum(cs%st%lambda * (gend - gn), mask=cs%bilat)
      est = now .and. .not. cs%st%active
      rel = cs%st%active .and. .not. now
      y = 0.0_dp
      e = 0.0_dp
      where (est) e = impact_energy_error(cs%st%lambda, max(gn, 0.0_dp))
      ! MASSLESS: Λ is R(n+1) (the massless rows are equilibrium at n+1), the step's multiplier
      ! R(n) + R(n+1); a release gives back ½ R(n) g(n+1) the scheme counted (docs/contact.md).
      cs%lam_step = cs%st%lambda
      if (mode == IMPACT_MASSLESS) then
        cs%lam_step = cs%st%lambda + cs%st%r_prev
        where (rel) e = -impact_energy_error(cs%st%r_prev, max(gend, 0.0_dp))
        rep%reaction_work = 0.5_dp * dot_product(cs%st%r_prev, gend - gn)
      end if
      rep%n_active = count(now)
      rep%n_establish = count(est)
      rep%n_release = count(rel)
      rep%energy_error = sum(e)
      rep%scheme_work = 0.5_dp * dot_product(cs%lam_step, gend - gn)
    end associate
  end subroutine step_conditions

  !> What the impact correction of the step that just converged would leave in the energy balance
  !> (contact_end_step's report%unrestored), found before anything is committed, so that the
  !> driver can take the step again as sub-steps (SCHEME RETRY) rather than leave it: under
  !> MASSLESS a release's ½ R(n) g(n+1) that the body's kinetic energy cannot give (a step about as
  !> long as the contact). v, mv: v(n+1) and M v(n+1) of eq (3), scratch (changed). 0 in the
  !> other modes and on steps where no condition changes.
  module procedure contact_shortfall
    type(contact_report_t) :: rep
    stat = STAT_OK
    shortfall = 0.0_dp
    if (.not. cs%finalized .or. cs%nc == 0 .or. mode /= IMPACT_MASSLESS) return
    call step_conditions(cs, mode, u_n, du, rep)
    if (rep%n_establish == 0 .and. rep%n_release == 0) return
    call persist_correction(cs, body, v, mv, rep, stat, errmsg, project=.false.)
    shortfall = rep%unrestored
  end procedure contact_shortfall

  !> IMPACT SYMMETRIC (docs/contact.md): a release is the impact reversed. Released conditions
  !> first: each gives back the energy it held, held_j, as an impulse x along c_j on its nodes,
  !> v <- v + x M⁻¹c_j' with ½ s x² + (c_j v) x = held_j, s = c_j M⁻¹c_j', x > 0 (repulsive).
  !> Then, if conditions are established: the velocity projected on zero normal velocity of every
  !> active condition (the hzero step with gains 1: PERSIST's projection, impulses -ν along c_j),
  !> and the kinetic energy it takes, ½ ν'A v, with the step's loss E_j (10) held by the
  !> established conditions (the projection's share of each: ½ ν_j (c_j v) before it, the positive
  !> ones), except in the groups the projection leaves without kinetic energy (symmetric_fallback:
  !> returned in cs%fallback for PAPER). rep%held: the energy held in the step less the energy
  !> given back (the driver books it in history.csv's contact_held, so the balance holds exactly;
  !> impact_dissipated stays for energy that never comes back).
  subroutine symmetric_correction(cs, body, v, mv, rep, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: body(:)
    real(dp), intent(inout) :: v(:), mv(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: j, k, n, rank, kept
    real(dp) :: b, q, x, dt, wsum, held_now
    stat = STAT_OK
    cs%fallback = .false.
    associate (held => cs%st%held, est => cs%est, rel => cs%rel, now => cs%now, share => cs%sv)
      do j = 1, cs%nc
        if (.not. (rel(j) .and. held(j) > 0.0_dp)) cycle
        cs%idx(1) = j
        call contact_am_block(cs, cs%idx(1:1), 1, cs%amat(1:1, 1:1), stat, errmsg)
        if (stat /= STAT_OK) return
        b = cs%c%dot(j, v)
        q = sqrt(b * b + 2.0_dp * cs%amat(1, 1) * held(j))
        if (b >= 0.0_dp) then                    ! (the root without cancellation)
          x = 2.0_dp * held(j) / (q + b)
        else
          x = (q - b) / cs%amat(1, 1)
        end if
        cs%mu = 0.0_dp
        cs%mu(j) = x
        call add_minv_ct(cs, cs%mu, 1.0_dp, v, mv, stat, errmsg)
        if (stat /= STAT_OK) return
        cs%cimp(j) = cs%cimp(j) + x
        rep%held = rep%held - held(j)
        held(j) = 0.0_dp
      end do
      if (.not. any(est)) return
      n = 0
      do j = 1, cs%nc
        if (.not. now(j)) cycle
        n = n + 1
        cs%idx(n) = j
        cs%ct(n) = cs%c%dot(j, v)
      end do
      cs%vn = v                                  ! (the velocity before the projection)
      cs%mvn = mv
      cs%gain(1:n) = 1.0_dp
      call hzero_reflection(cs, cs%idx(1:n), cs%gain(1:n), v, mv, rank, stat, errmsg)
      if (stat /= STAT_OK) return
      share = 0.0_dp                             ! the established ones' shares, by condition
      do k = 1, n
        j = cs%idx(k)
        if (est(j)) share(j) = max(0.5_dp * cs%mu(j) * cs%ct(k), 0.0_dp)
      end do
      call symmetric_fallback(cs, body, v, mv, rep, stat, errmsg)
      if (stat /= STAT_OK) return
      dt = 0.5_dp * (dot_product(cs%vn, cs%mvn) - dot_product(v, mv))
      cs%cimp = cs%cimp - cs%mu
      wsum = 0.0_dp
      kept = 0
      do j = 1, cs%nc
        if (.not. est(j) .or. cs%fallback(j)) cycle
        wsum = wsum + share(j)
        kept = kept + 1
      end do
      held_now = 0.0_dp
      do j = 1, cs%nc
        if (.not. est(j) .or. cs%fallback(j)) cycle
        if (wsum > 0.0_dp) then
          held(j) = held(j) + cs%e(j) + dt * share(j) / wsum
        else
          held(j) = held(j) + cs%e(j) + dt / real(kept, dp)
        end if
        held_now = held_now + cs%e(j)
      end do
      if (kept > 0) rep%held = rep%held + dt + held_now
    end associate
  end subroutine symmetric_correction

  !> a(1:n, 1:n) = C_idx M⁻¹ C_idx' for the conditions idx(1:n): the blocks of A M⁻¹A' that the
  !> impulse (14) and the reflection (16) need. From the sparse rows directly where M⁻¹ is 1/m on
  !> every equation of the conditions (a lumped mass; the contact rows SYMMETRIC lumps in a
  !> consistent one: no solve, the cost of the contact zone); otherwise one solve with M per
  !> condition, symmetrized.
  module procedure contact_am_block
    integer :: k, l
    stat = STAT_OK
    select type (op => cs%minv)
    type is (diag_inverse_t)
      call local_block(cs, idx, n, op%d, a, stat, errmsg)
      return
    type is (chol_inverse_t)
      if (rows_local(cs, idx(1:n), op%dloc)) then
        call local_block(cs, idx, n, op%dloc, a, stat, errmsg)
        return
      end if
    end select
    do l = 1, n
      cs%f = 0.0_dp
      call cs%c%scatter(idx(l), 1.0_dp, cs%f)
      call cs%minv%apply(cs%f, cs%xw, stat, errmsg)
      if (stat /= STAT_OK) return
      do k = 1, n
        a(k, l) = cs%c%dot(idx(k), cs%xw)
      end do
    end do
    do l = 1, n
      do k = 1, l - 1
        a(k, l) = 0.5_dp * (a(k, l) + a(l, k))
        a(l, k) = a(k, l)
      end do
    end do
  end procedure contact_am_block

  !> contact_am_block where M⁻¹ is 1/d(eq) on every equation the conditions idx(1:n) touch.
  subroutine local_block(cs, idx, n, d, a, stat, errmsg)
    type(contact_set_t), intent(in) :: cs
    integer, intent(in) :: idx(:), n
    real(dp), intent(in) :: d(:)
    real(dp), intent(out) :: a(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, l, p, q, ep
    stat = STAT_OK
    do l = 1, n
      do k = 1, l
        a(k, l) = 0.0_dp
        do p = cs%c%first(idx(k)), cs%c%last(idx(k))
          ep = cs%c%eq_at(p)
          do q = cs%c%first(idx(l)), cs%c%last(idx(l))
            if (ep /= cs%c%eq_at(q)) cycle
            if (.not. (d(ep) > 0.0_dp)) then
              call set_error(stat, errmsg, STAT_INPUT, 'contact: equation ' // str(ep) // &
                ' carries a contact condition but has no mass (lumped mass diagonal ' // str(d(ep)) // ')')
              return
            end if
            a(k, l) = a(k, l) + cs%c%coef_at(p) * cs%c%coef_at(q) / d(ep)
          end do
        end do
        a(l, k) = a(k, l)
      end do
    end do
  end subroutine local_block

  !> Whether every equation of the conditions conds has a local inverse (d > 0: no coupling in M).
  pure logical function rows_local(cs, conds, d) result(ok)
    type(contact_set_t), intent(in) :: cs
    integer, intent(in) :: conds(:)
    real(dp), intent(in) :: d(:)
    integer :: k
    ok = .false.
    do k = 1, size(conds)
      if (.not. row_local(cs, conds(k), d)) return
    end do
    ok = .true.
  end function rows_local

  pure logical function row_local(cs, j, d) result(ok)
    type(contact_set_t), intent(in) :: cs
    integer, intent(in) :: j
    real(dp), intent(in) :: d(:)
    integer :: p
    ok = .false.
    do p = cs%c%first(j), cs%c%last(j)
      if (.not. (d(cs%c%eq_at(p)) > 0.0_dp)) return
    end do
    ok = .true.
  end function row_local

  !> SYMMETRIC's held energy comes back when the body's elasticity ends the contact. A group (bodies
  !> linked by active conditions) the projection leaves without kinetic energy of its own (a point
  !> mass, a body landing with every node, two rigid-like bodies meeting) has none to end it: under
  !> gravity it would stay down with the energy held. Those groups (PERSIST's test: the projected
  !> energy, less the group's rigid translation, at most persist_min_fraction of T1 + Σ E_j) get
  !> their velocity before the projection back (cs%vn, cs%mvn), their projection impulses dropped,
  !> and their established conditions in cs%fallback, for PAPER's reflection.
  subroutine symmetric_fallback(cs, body, v, mv, rep, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: body(:)
    real(dp), intent(inout) :: v(:), mv(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: nb, grp, n, j, i, nm, mk(3)
    real(dp) :: t1, tp, tstar, acm(3), tcm
    logical :: hit
    cs%changing = cs%est
    call group_conditions(cs, body, nb, stat, errmsg)
    if (stat /= STAT_OK) return
    cs%vp = v                                    ! (the projected velocity, for group_rigid_motion)
    cs%mvp = mv
    associate (cgroup => cs%cgroup, rows => cs%rows)
      do grp = 1, nb
        if (find(cs%parent, grp) /= grp) cycle
        hit = .false.
        n = 0
        tstar = 0.0_dp
        do j = 1, cs%nc
          if (cgroup(j) /= grp) cycle
          if (cs%est(j)) then
            hit = .true.
            tstar = tstar + cs%e(j)
          end if
          if (.not. cs%now(j)) cycle
          n = n + 1
          cs%idx(n) = j
        end do
        if (.not. hit) cycle
        call group_rows(cs, body, grp)
        t1 = 0.5_dp * sum(cs%vn * cs%mvn, mask=rows)
        tp = 0.5_dp * sum(v * mv, mask=rows)
        call group_rigid_motion(cs, body, rows, n, acm, tcm, nm, mk)
        if (tp - tcm > cs%settings%persist_min_fraction * (t1 + tstar)) cycle
        do i = 1, cs%neq
          if (.not. rows(i)) cycle
          v(i) = cs%vn(i)
          mv(i) = cs%mvn(i)
        end do
        do j = 1, cs%nc
          if (cgroup(j) /= grp) cycle
          cs%mu(j) = 0.0_dp
          cs%fallback(j) = cs%est(j)
        end do
        rep%persist_fallbacks = rep%persist_fallbacks + 1
      end do
    end associate
  end subroutine symmetric_fallback

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

  !> IMPACT PAPER for the conditions sel (all established in the step): the impulses of
  !> (12)-(15) (impulse_eq12_15), then the hzero reflection (16) about all of them.
  subroutine paper_correction(cs, sel, v, mv, rep, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    logical, intent(in) :: sel(:)
    real(dp), intent(inout) :: v(:), mv(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: j, n, rank
    real(dp) :: t_elastic
    logical :: inelastic
    call impulse_eq12_15(cs, sel, v, mv, rep, stat, errmsg)
    if (stat /= STAT_OK) return
    n = 0
    inelastic = .false.
    do j = 1, cs%nc
      if (.not. sel(j)) cycle
      n = n + 1
      cs%idx(n) = j
      cs%gain(n) = 1.0_dp + cs%c%restitution(j)
      inelastic = inelastic .or. cs%c%restitution(j) < 1.0_dp
    end do
    if (inelastic) t_elastic = 0.5_dp * dot_product(v, mv)
    call hzero_reflection(cs, cs%idx(1:n), cs%gain(1:n), v, mv, rank, stat, errmsg)
    if (stat /= STAT_OK) return
    rep%reflection_rank = rank
    cs%cimp = cs%cimp - cs%mu
    ! RESTITUTION e < 1: Newton's law took (1 - e²) of the normal kinetic energy (measured).
    if (inelastic) rep%impact_dissipated = rep%impact_dissipated + (t_elastic - 0.5_dp * dot_product(v, mv))
  end subroutine paper_correction

  !> (12)-(15) for the conditions sel established in the step with Λ_j > 0: E_j (cs%e, eq 10)
  !> given back as kinetic energy by the impulses y_j Λ_j c_j, y from the coupled quadratics
  !> (14) (impulse_fixed_point; (13) for one point), then (12) v <- v + M⁻¹ Σ y_j Λ_j c_j.
  !> Sets cs%y (y_j).
  subroutine impulse_eq12_15(cs, sel, v, mv, rep, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    logical, intent(in) :: sel(:)
    real(dp), intent(inout) :: v(:), mv(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: change
    integer :: j, k, n, iters
    logical :: conv

    stat = STAT_OK
    n = 0
    do j = 1, cs%nc
      if (.not. (sel(j) .and. cs%st%lambda(j) > 0.0_dp)) cycle
      n = n + 1
      cs%idx(n) = j
    end do
    call reserve_dense(cs, n)
    if (n > 0) then
      associate (ip => cs%idx(1:n), g => cs%gmat(1:n, 1:n))
        call contact_am_block(cs, ip, n, g, stat, errmsg)
        if (stat /= STAT_OK) return
        do k = 1, n
          g(:, k) = g(:, k) * cs%st%lambda(ip) * cs%st%lambda(ip(k))
          cs%sv(k) = cs%st%lambda(ip(k)) * cs%c%dot(ip(k), v)
          cs%ct(k) = cs%e(ip(k))
        end do
        call impulse_fixed_point(g, cs%sv(1:n), cs%ct(1:n), cs%wq(1:n), iters, change, conv, cs%settings%fp_tol, &
          cs%settings%fp_max_iter, cs%work2)
        rep%fp_iterations = rep%fp_iterations + iters
        rep%fp_change = max(rep%fp_change, change)
        if (.not. conv) rep%fp_failures = rep%fp_failures + 1     ! reported, energy still exact
        cs%mu = 0.0_dp
        do k = 1, n
          cs%y(ip(k)) = cs%wq(k)
          cs%mu(ip(k)) = cs%wq(k) * cs%st%lambda(ip(k))
        end do
      end associate
      call add_minv_ct(cs, cs%mu, 1.0_dp, v, mv, stat, errmsg)          ! (12)
      cs%cimp = cs%cimp + cs%mu
    end if
  end subroutine impulse_eq12_15

  !> (16) The hzero step about the conditions A = conds: one Newmark step of length
  !> h0 -> 0 with A held as equalities leaves only the mass terms,
  !>     M w + A'ν = M v,  A w = 0,   then v <- 2 w - v by (3),
  !> i.e. v <- v - 2 M⁻¹A'ν with (A M⁻¹A') ν = A v: the M-orthogonal reflection of v about the
  !> tangent space of A (normal velocities reversed, v'Mv kept). With the gains g_k = 1 + e_k,
  !> (A M⁻¹A') ν = diag(g) A v and v <- v - M⁻¹A'ν give A v <- -diag(e) A v: g = 2 (e = 1) is
  !> (16); g = 1 (e = 0) stops at w, the M-orthogonal projection on A v = 0 that PERSIST uses
  !> (method.md section 6); 0 <= e < 1 is Newton's law of restitution (RESTITUTION e) in the
  !> M-metric. mv is updated with v (mv <- mv - A'ν). rank: independent rows of A (dependent
  !> ones, e.g. duplicated conditions, get ν = 0). The dense hzero_reflection_dense of
  !> impact_kernels is its test oracle.
  module procedure hzero_reflection
    call normal_multiplier_ws(cs, conds, gain, v, rank, stat, errmsg)
    if (stat /= STAT_OK) return
    call add_minv_ct(cs, cs%mu, -1.0_dp, v, mv, stat, errmsg)
  end procedure hzero_reflection

  !> ν with (A M⁻¹A') ν = diag(gain) A v for the conditions A = conds, into cs%mu (0 elsewhere): the
  !> multiplier of the hzero step (16) and of the PERSIST projection. normal_multiplier in the
  !> workspaces of cs (no allocation), with A M⁻¹A' from contact_am_block.
  subroutine normal_multiplier_ws(cs, conds, gain, v, rank, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: conds(:)
    real(dp), intent(in) :: gain(:)
    real(dp), intent(in) :: v(:)
    integer, intent(out) :: rank
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, n
    rank = 0
    n = size(conds)
    call reserve_dense(cs, n)
    call contact_am_block(cs, conds, n, cs%amat(1:n, 1:n), stat, errmsg)
    if (stat /= STAT_OK) return
    do k = 1, n
      cs%sv(k) = gain(k) * cs%c%dot(conds(k), v)
    end do
    call spsd_solve_ws(n, cs%amat, cs%sv, rank, cs%ipiv, cs%work2)
    cs%mu = 0.0_dp
    do k = 1, n
      cs%mu(conds(k)) = cs%sv(k)
    end do
  end subroutine normal_multiplier_ws

  !> Section 6. Groups: bodies linked by active conditions. For each group holding an
  !> established condition: project on zero normal velocity of all its active conditions, then
  !> scale its velocity so that its kinetic energy is T1_group + Σ E_j. Groups whose projected
  !> kinetic energy is below persist_min_fraction of that target (massless_min_fraction without the
  !> projection, MASSLESS), or conditions on equations
  !> without body, are left untouched and returned in cs%fallback (their established conditions).
  subroutine persist_correction(cs, body, v, mv, rep, stat, errmsg, project, geometry)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: body(:)
    real(dp), intent(inout) :: v(:), mv(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical, intent(in), optional :: project     !< .false.: scale only (IMPACT MASSLESS)
    real(dp), intent(in), optional :: geometry(:)   !< the active conditions that follow the geometry, these energies
    integer :: nb, j, i, grp, rank, n, k, nm, mk(3)
    real(dp) :: t1, tp, tstar, s, acm(3), tcm, vcm, mvcm, dis, dm(3), pb(2)
    logical :: proj

    stat = STAT_OK
    cs%fallback = .false.
    proj = .true.
    if (present(project)) proj = project
    ! The conditions that change the energy: established ones, and under MASSLESS (no
    ! projection) released ones too; the maintained ones join the groups.
    cs%changing = cs%est
    if (.not. proj) cs%changing = cs%est .or. cs%rel
    if (present(geometry)) cs%changing = cs%follow .and. cs%now
    call group_conditions(cs, body, nb, stat, errmsg)
    if (stat /= STAT_OK) return
    associate (parent => cs%parent, cgroup => cs%cgroup, now => cs%now, est => cs%changing, rows => cs%rows)
      where (est .and. cgroup <= 0) cs%fallback = .true.
      do grp = 1, nb
        if (find(parent, grp) /= grp) cycle
        if (.not. any(est .and. cgroup == grp)) cycle
        rep%persist_groups = rep%persist_groups + 1
        call group_rows(cs, body, grp)
        n = 0
        do j = 1, cs%nc
          if (.not. (now(j) .and. cgroup(j) == grp)) cycle
          n = n + 1
          cs%idx(n) = j
        end do
        t1 = 0.5_dp * sum(v * mv, mask=rows)
        dis = 0.0_dp
        cs%vp = v
        cs%mvp = mv
        cs%mu = 0.0_dp
        if (proj) then                           ! (massless contact nodes: nothing to project)
          ! RESTITUTION e < 1 on established conditions: Newton's law (gains 1 + e, maintained
          ! contacts 1) tells the kinetic energy the impact keeps; the rest is dissipated.
          if (cs%inelastic) then
            do k = 1, n
              cs%gain(k) = 1.0_dp
              if (est(cs%idx(k))) cs%gain(k) = 1.0_dp + cs%c%restitution(cs%idx(k))
            end do
            if (any(cs%gain(1:n) < 2.0_dp .and. est(cs%idx(1:n)))) then
              cs%vn = v
              cs%mvn = mv
              call hzero_reflection(cs, cs%idx(1:n), cs%gain(1:n), cs%vn, cs%mvn, rank, stat, errmsg)
              if (stat /= STAT_OK) return
              dis = t1 - 0.5_dp * sum(cs%vn * cs%mvn, mask=rows)
            end if
          end if
          cs%gain(1:n) = 1.0_dp
          call hzero_reflection(cs, cs%idx(1:n), cs%gain(1:n), cs%vp, cs%mvp, rank, stat, errmsg)
          if (stat /= STAT_OK) return
        end if
        tp = 0.5_dp * sum(cs%vp * cs%mvp, mask=rows)
        if (present(geometry)) then
          tstar = t1 + sum(geometry, mask=est .and. cgroup == grp)
        else
          tstar = t1 + sum(cs%e, mask=est .and. cgroup == grp) - dis
        end if
        ! Scale about the group's rigid motion that its conditions leave invariant (a rigid
        ! motion the contact cannot change: the tangential translation and the rotation about
        ! the contact normal against a wall, every translation between free bodies): the momenta
        ! the contact cannot change and the zero normal velocities are kept.
        call group_rigid_motion(cs, body, rows, n, acm, tcm, nm, mk)
        if (.not. (tp - tcm > merge(cs%settings%persist_min_fraction, cs%settings%massless_min_fraction, proj) * tstar)) then
          where (est .and. cgroup == grp) cs%fallback = .true.
          rep%persist_fallbacks = rep%persist_fallbacks + 1
          if (.not. proj) rep%unrestored = rep%unrestored + abs(tstar - t1)   ! (PERSIST: PAPER takes over)
          cycle
        end if
        s = persist_scale(tstar, tcm, tp - tcm)
        ! A target below the rigid motion's energy cannot be reached by scaling (s = 0): the rest
        ! stays in the balance, and the driver says so.
        if (tstar < tcm) rep%unrestored = rep%unrestored + (tcm - tstar)
        cs%cimp = cs%cimp - cs%mu                  ! the projection's impulses along c_j
        rep%impact_dissipated = rep%impact_dissipated + dis
        dm = 0.0_dp
        pb = 0.0_dp
        do i = 1, cs%neq                           ! (a loop: a WHERE block allocates its mask)
          if (.not. rows(i)) cycle
          vcm = 0.0_dp
          mvcm = 0.0_dp
          if (cs%has_rigid) then
            do k = 1, size(cs%rig, 2)
              if (acm(k) == 0.0_dp) cycle
              vcm = vcm + acm(k) * cs%rig(i, k)
              mvcm = mvcm + acm(k) * cs%mrig(i, k)
            end do
          end if
          v(i) = vcm + s * (cs%vp(i) - vcm)
          mv(i) = mvcm + s * (cs%mvp(i) - mvcm)
          do k = 1, nm                             ! the momenta the scaling gave, by free mode
            dm(k) = dm(k) + cs%rig(i, mk(k)) * (mv(i) - cs%mvp(i))
          end do
          if (cs%has_rigid) pb = pb + cs%rig(i, 1:2) * (mv(i) - cs%mvp(i))
        end do
        call book_scaling(cs, n, nm, dm, pb, findloc(est .and. cgroup == grp, .true., 1))
      end do
    end associate
  end subroutine persist_correction

  !> The momentum a scaling gave a group, as impulses: dm(1:nm) along its free rigid modes
  !> (group_rigid_motion's mk, rows cs%erig(1:n, 1:nm) of its active conditions cs%idx(1:n)) lies
  !> in what normal impulses at those rows can give; their least-norm impulses z (normal_impulses)
  !> join cs%cimp along c_j, so that contacts.csv and the reaction count them where they act. A
  !> group without a free mode (held by supports, whose reactions take any momentum) books the
  !> momentum pb (x, y) on its first established condition j0, as a body impulse (cs%bimp).
  subroutine book_scaling(cs, n, nm, dm, pb, j0)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: n, nm, j0
    real(dp), intent(in) :: dm(3), pb(2)
    real(dp) :: resid
    integer :: j
    if (nm > 0 .and. n > 0) then
      call normal_impulses(cs%erig(1:n, 1:nm), dm(1:nm), maxval(cs%cnorm(1:n)) * cs%rig_scale, cs%sv(1:n), resid)
      if (resid <= 1.0e-8_dp) then
        do j = 1, n
          cs%cimp(cs%idx(j)) = cs%cimp(cs%idx(j)) + cs%sv(j)
        end do
        return
      end if
    end if
    if (j0 > 0) cs%bimp(:, j0) = cs%bimp(:, j0) + pb
  end subroutine book_scaling

  !> The groups of section 6: the bodies (body(:), per equation) linked by the active conditions
  !> and by cs%changing; cs%cgroup(j) = the representative body of condition j's group (0: not
  !> active, -1: on an equation without body), cs%parent the union-find forest over nb bodies.
  subroutine group_conditions(cs, body, nb, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: body(:)
    integer, intent(out) :: nb
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: i, j, p, bj
    stat = STAT_OK
    nb = 0
    if (size(body) /= cs%neq) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_end_step: body(:) must have one entry per equation')
      return
    end if
    if (cs%neq > 0) nb = max(maxval(body), 0)
    if (size(cs%parent) < nb) then                 ! sized neq at contact_finalize: never
      deallocate (cs%parent)
      allocate (cs%parent(nb))
    end if
    associate (parent => cs%parent, cgroup => cs%cgroup)
      do i = 1, nb
        parent(i) = i
      end do
      cgroup = 0
      do j = 1, cs%nc
        if (.not. (cs%now(j) .or. cs%changing(j))) cycle
        do p = cs%c%first(j), cs%c%last(j)
          bj = body(cs%c%eq_at(p))
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
    end associate
  end subroutine group_conditions

  !> cs%rows = the equations of group grp (group_conditions).
  subroutine group_rows(cs, body, grp)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: body(:), grp
    integer :: i
    do i = 1, cs%neq
      cs%rows(i) = body(i) > 0
      if (cs%rows(i)) cs%rows(i) = find(cs%parent, body(i)) == grp
    end do
  end subroutine group_rows

  !> The rigid motion v_r = Σ a_k t_k of the group (rows) after the projection (cs%vp, cs%mvp)
  !> that a scaling must leave alone: its M-orthogonal projection on the free rigid modes of the
  !> group (translations, rotation about the origin; cs%body_free: no support moves them) that
  !> its active conditions cs%idx(1:n) leave invariant (c_j't = 0), and its kinetic energy
  !> tcm (invariant_rigid_motion). Scaling about v_r keeps every momentum the contact cannot
  !> change (the tangential one against a wall, the angular one about the contact normal) and
  !> the zero normal velocities; node-to-node groups keep all their momenta. nm, mk(1:nm): the
  !> free modes, cs%erig(1:n, 1:nm) their c_j't_k, for normal_impulses. a = 0 without free mode.
  subroutine group_rigid_motion(cs, body, rows, n, a, tcm, nm, mk)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: body(:)
    logical, intent(in) :: rows(:)
    integer, intent(in) :: n
    real(dp), intent(out) :: a(3), tcm
    integer, intent(out) :: nm, mk(3)
    real(dp) :: g(3, 3), pk(3), rmax(3), am(3)
    logical :: free(3)
    integer :: k, l, i, j
    a = 0.0_dp
    tcm = 0.0_dp
    nm = 0
    if (.not. cs%has_rigid) return
    free = .false.
    free(1:size(cs%rig, 2)) = .true.
    if (allocated(cs%body_free)) then
      do i = 1, cs%neq
        if (rows(i) .and. body(i) > 0) free = free .and. cs%body_free(:, body(i))
      end do
    end if
    do k = 1, 3
      if (.not. free(k)) cycle
      nm = nm + 1
      mk(nm) = k
    end do
    if (nm == 0) return
    cs%rig_scale = 0.0_dp
    do k = 1, nm
      pk(k) = sum(cs%rig(:, mk(k)) * cs%mvp, mask=rows)
      rmax(k) = maxval(abs(cs%rig(:, mk(k))), mask=rows)
      cs%rig_scale = max(cs%rig_scale, rmax(k))
      do l = 1, nm
        g(k, l) = sum(cs%rig(:, mk(k)) * cs%mrig(:, mk(l)), mask=rows)
      end do
    end do
    do j = 1, n
      cs%cnorm(j) = sqrt(cs%c%norm2_sq(cs%idx(j)))
      do k = 1, nm
        cs%erig(j, k) = cs%c%dot(cs%idx(j), cs%rig(:, mk(k)))
      end do
    end do
    call invariant_rigid_motion(g(1:nm, 1:nm), pk(1:nm), cs%erig(1:n, 1:nm), cs%cnorm(1:n), rmax(1:nm), am(1:nm), tcm)
    do k = 1, nm
      a(mk(k)) = am(k)
    end do
  end subroutine group_rigid_motion

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
    integer :: j, p, ep
    logical :: local
    stat = STAT_OK
    select type (op => cs%minv)
    type is (chol_inverse_t)                     ! rows with a local inverse: no solve (contact_am_block)
      local = .true.
      do j = 1, cs%nc
        if (mu(j) /= 0.0_dp) local = local .and. row_local(cs, j, op%dloc)
      end do
      if (local) then
        do j = 1, cs%nc
          if (mu(j) == 0.0_dp) cycle
          do p = cs%c%first(j), cs%c%last(j)
            ep = cs%c%eq_at(p)
            v(ep) = v(ep) + alpha * mu(j) * cs%c%coef_at(p) / op%dloc(ep)
            mv(ep) = mv(ep) + alpha * mu(j) * cs%c%coef_at(p)
          end do
        end do
        return
      end if
    end select
    cs%f = 0.0_dp
    call cs%c%add_transpose(mu, cs%f)
    call cs%minv%apply(cs%f, cs%xw, stat, errmsg)
    if (stat /= STAT_OK) return
    v = v + alpha * cs%xw
    mv = mv + alpha * cs%f
  end subroutine add_minv_ct
end submodule contact_impact
