!> The end of a step with contact (method.md sections 3 and 6): the events and the energy error
!> (10) of the step's conditions, then the correction of the impact mode, each in its own module
!> with explicit inputs and outputs: impact_paper ((12)-(15) and (16)), impact_persist,
!> impact_massless, impact_symmetric; impact_scaling for the rows that follow the geometry.
!> A submodule of contact: it hands them the set's rows, state and M⁻¹ (impact_space).
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
    real(dp) :: t_before, t_lab
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
      ! Moving obstacles: the corrections in their frame (contact_frame); t_lab the lab kinetic energy.
      ! (only where a correction will act: v - V + V is v to round-off only)
      t_lab = 0.5_dp * dot_product(v, mv)
      if (cs%moving .and. present(body) .and. mode /= IMPACT_OFF .and. (rep%n_establish > 0 .or. rep%n_release > 0 .or. &
        any(cs%follow .and. now))) then
        call obstacle_frame(cs, .true., body, v, mv, stat, errmsg)
        if (stat /= STAT_OK) return
      end if
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
          call cs%paper%correct(cs%sp, cs%c, est, cs%st%lambda, e, cs%settings%fp_tol, cs%settings%fp_max_iter, v, mv, &
            y, cs%cimp, rep, stat, errmsg)
        case (IMPACT_PERSIST)
          call cs%persist%correct(cs%sp, cs%c, body, est, now, e, cs%inelastic, cs%settings%persist_min_fraction, v, mv, &
            cs%cimp, cs%bimp, cs%fallback, rep, stat, errmsg)
        case (IMPACT_MASSLESS)
          call cs%massless%correct(cs%sp, cs%c, body, est, rel, now, e, cs%settings%massless_min_fraction, v, mv, &
            cs%cimp, cs%bimp, cs%fallback, rep, stat, errmsg)
        case (IMPACT_SYMMETRIC)
          call cs%symmetric%correct(cs%sp, cs%c, body, est, rel, now, e, cs%settings%persist_min_fraction, cs%st%held, &
            v, mv, cs%cimp, cs%fallback, rep, stat, errmsg)
        case (IMPACT_OFF)
        case default
          call set_error(stat, errmsg, STAT_INPUT, 'contact_end_step: unknown impact mode ' // str(mode))
        end select
        if (stat /= STAT_OK) return
        ! PERSIST's and SYMMETRIC's groups left without kinetic energy (their fallback): PAPER.
        if (mode == IMPACT_PERSIST .or. mode == IMPACT_SYMMETRIC) then
          if (any(cs%fallback)) then
            call cs%paper%correct(cs%sp, cs%c, cs%fallback, cs%st%lambda, e, cs%settings%fp_tol, &
              cs%settings%fp_max_iter, v, mv, y, cs%cimp, rep, stat, errmsg)
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
          cs%changing(j) = cs%follow(j) .and. now(j)
          if (cs%changing(j)) cs%xg(j) = 0.5_dp * cs%lam_step(j) * (gn(j) - gend(j)) - e(j)
        end do
        call cs%following%correct(cs%sp, cs%c, body, cs%changing, now, cs%xg, cs%settings%massless_min_fraction, v, mv, &
          cs%cimp, cs%bimp, cs%fallback, geo, stat, errmsg)           ! (geo and fallback: not reported)
        if (stat /= STAT_OK) return
        energy_restored = 0.5_dp * dot_product(v, mv) - t_before
      end if
      rep%energy_restored = energy_restored
      if (cs%framed) then                      ! back to the lab: the rest of the change is the obstacles' work
        call obstacle_frame(cs, .false., body, v, mv, stat, errmsg)
        rep%obstacle_work = rep%obstacle_work + (0.5_dp * dot_product(v, mv) - t_lab - energy_restored)
      end if
      ! FRICTION: the normal impulses of the correction carry their Coulomb share, and a sticking
      ! contact's slip rate goes to 0 (after the energy restored is measured, in the lab frame:
      ! what the friction takes is dissipation, never restored).
      if (cs%fr%count() > 0 .and. mode /= IMPACT_OFF .and. present(step)) then
        cs%nu = 0.0_dp                          ! (tangential_impulse's one-entry impulse vector)
        call friction_impulses(cs, step, v, mv, rep, stat, errmsg)
        if (stat /= STAT_OK) return
      end if

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
        if (cs%moving) gn = gn + cs%wshift      ! (the rows hold g0 at the step's end)
      end if
      ! Bilateral rows (IMPOSE) are no contacts: no events, no correction; their multipliers'
      ! work is the work of the imposed motion, for the driver's external work.
      now = cs%st%active_iter .and. .not. cs%bilat
      rep%imposed_work = 0.5_dp * sum(cs%st%lambda * (gend - gn), mask=cs%bilat .and. .not. cs%tangent)
      ! FRICTION: the tangential rows' work ½ Λ_T s (s = c_T du, the slip), never positive.
      rep%friction_dissipated = -0.5_dp * sum(cs%st%lambda * (gend - gn), mask=cs%tangent)
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
        if (cs%moving) rep%reaction_work = rep%reaction_work + 0.5_dp * dot_product(cs%st%r_prev, cs%wshift)   ! (½ R(n)'C du)
      end if
      rep%n_active = count(now)
      rep%n_establish = count(est)
      rep%n_release = count(rel)
      rep%energy_error = sum(e)
      rep%scheme_work = 0.5_dp * dot_product(cs%lam_step, gend - gn)
      ! A moving obstacle's work over the step: the multiplier's work ½ Λ c'du = ½ Λ (g(n+1) - g(n)
      ! + shift) on the structure, less the contact's share.
      if (cs%moving) rep%obstacle_work = 0.5_dp * sum(cs%lam_step * cs%wshift, mask=.not. cs%bilat .or. cs%tangent)
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
    call obstacle_frame(cs, .true., body, v, mv, stat, errmsg)   ! (v, mv: scratch)
    if (stat /= STAT_OK) return
    call cs%massless%correct(cs%sp, cs%c, body, cs%est, cs%rel, cs%now, cs%e, cs%settings%massless_min_fraction, v, mv, &
      cs%cimp, cs%bimp, cs%fallback, rep, stat, errmsg)
    shortfall = rep%unrestored
    if (stat == STAT_OK) call obstacle_frame(cs, .false., body, v, mv, stat, errmsg)
  end procedure contact_shortfall

  !> a(1:n, 1:n) = C_idx M⁻¹ C_idx' for the conditions idx(1:n) (impact_space's am_block).
  module procedure contact_am_block
    call cs%sp%am_block(cs%c, idx, n, a, stat, errmsg)
  end procedure contact_am_block

  !> (16) The hzero step about the conditions conds with the gains (impact_space's hzero_step,
  !> the one every mode calls); its multiplier ν stays in cs%nu, read by nothing else.
  module procedure hzero_reflection
    call cs%sp%hzero_step(cs%c, conds, gain, v, mv, cs%nu, rank, stat, errmsg)
  end procedure hzero_reflection
end submodule contact_impact
