!> Moving rigid obstacles (OBSTACLE … VELOCITY, docs/input.md "Moving obstacles"). The gap of a
!> condition on a moving obstacle depends on time: the driver writes g0 at the step's end and
!> tells the set what the obstacle's motion takes off the gap over the step (its shift), so that
!> g(n) and the multiplier's work split into the contact's and the obstacle's (booked as external
!> work). The impact corrections act in the obstacles' frame: before them each group touching a
!> moving obstacle has its velocity taken relative to a velocity field V with c_j'V = the
!> obstacle's normal velocity on every condition the corrections see (the obstacle's translation,
!> corrected by an hzero projection where the group also touches other obstacles or a support),
!> (IMPACT MASSLESS, without M⁻¹: the translation alone, whose massless contact nodes need no
!> more), so that "normal velocity stopped" or "reversed" means relative to the obstacle, and the
!> kinetic energy a correction restores is the relative one; the rest of the change, V'Δ(Mv),
!> is the obstacle's work. A constant-velocity obstacle then gives the fixed obstacle's solution
!> in its frame. A submodule of contact.
submodule (contact) contact_frame
  implicit none

contains

  !> Condition j's obstacle moves: over the step it takes shift off the gap (g(n+1) = g(n) +
  !> c_j'du - shift), its normal velocity at the end is rate (c_j'v = rate keeps the gap), its
  !> velocity vel. The driver sets g0 at the step's end (contact_set_gap0 or contact_rewrite).
  module procedure cs_move_obstacle
    if (.not. allocated(self%wshift)) then
      allocate (self%wshift(self%nc), self%wrate(self%nc), self%wvel(3, self%nc), self%vframe(self%neq), &
        self%mvframe(self%neq), self%fr_framed(max(self%neq, 1)), self%fr_wb(3, max(self%neq, 1)), &
        self%fr_gain(self%nc), self%fr_target(self%nc), self%fr_conds(self%nc))   ! (bodies <= equations)
      self%wshift = 0.0_dp
      self%wrate = 0.0_dp
      self%wvel = 0.0_dp
      self%fr_gain = 1.0_dp                    ! (the frame's hzero step: a projection)
    end if
    self%moving = .true.
    self%wshift(j) = shift
    self%wrate(j) = rate
    self%wvel(:, j) = 0.0_dp
    self%wvel(1:size(vel), j) = vel             ! (x, y[, z]: a 2D one has z = 0)
  end procedure cs_move_obstacle

  !> enter: v <- v - V, mv <- mv - M V with V the frame of the obstacles of the conditions active
  !> now, established or released (cs%now, est, rel of step_conditions): on every body touching a
  !> moving one, the translation at that obstacle's velocity, then projected (the hzero step with
  !> gain 1 and the obstacles' normal velocities as target) so that c_j'V = wrate(j) on all of the
  !> body's conditions. Not enter: the frame taken back (v <- v + V). Nothing without motion.
  module procedure obstacle_frame
    integer :: j, b, nb, n, rank
    real(dp) :: resid, vmax
    stat = STAT_OK
    if (.not. enter) then
      if (cs%framed) then
        v = v + cs%vframe
        mv = mv + cs%mvframe
      end if
      cs%framed = .false.
      return
    end if
    cs%framed = .false.
    if (.not. cs%moving) return
    associate (framed => cs%fr_framed, wb => cs%fr_wb, gain => cs%fr_gain, target => cs%fr_target, conds => cs%fr_conds)
      nb = max(maxval(body), 1)
      framed(1:nb) = .false.
      wb(:, 1:nb) = 0.0_dp
      do j = 1, cs%nc
        if (cs%bilat(j) .or. .not. (cs%now(j) .or. cs%est(j) .or. cs%rel(j))) cycle
        if (all(cs%wvel(:, j) == 0.0_dp) .and. cs%wrate(j) == 0.0_dp) cycle
        b = row_body(j)
        if (b <= 0) cycle
        if (framed(b)) cycle
        framed(b) = .true.
        wb(:, b) = cs%wvel(:, j)
      end do
      if (.not. any(framed(1:nb))) return
      call cs%sp%translation(body, framed(1:nb), wb(:, 1:nb), cs%vframe, cs%mvframe)
      ! The conditions of the framed bodies the corrections see, and how far the translation is
      ! from their obstacles' normal velocities (a support, a GAP, another obstacle).
      n = 0
      resid = 0.0_dp
      vmax = maxval(abs(wb(:, 1:nb)))
      do j = 1, cs%nc
        if (cs%bilat(j) .or. .not. (cs%now(j) .or. cs%est(j) .or. cs%rel(j))) cycle
        if (.not. touches_framed(j)) cycle
        n = n + 1
        conds(n) = j
        target(n) = cs%wrate(j)
        resid = max(resid, abs(cs%c%dot(j, cs%vframe) - target(n)) / max(sqrt(cs%c%norm2_sq(j)), tiny(1.0_dp)))
      end do
      if (n > 0 .and. resid > 1.0e-13_dp * vmax .and. cs%mass_set) then   ! (MASSLESS has no M⁻¹: the translation)
        call cs%sp%hzero_step(cs%c, conds(1:n), gain(1:n), cs%vframe, cs%mvframe, cs%nu, rank, stat, errmsg, &
          target=target(1:n))
        if (stat /= STAT_OK) return
      end if
      v = v - cs%vframe
      mv = mv - cs%mvframe
      cs%framed = .true.
    end associate
  contains
    integer function row_body(jj) result(bb)
      integer, intent(in) :: jj
      bb = 0
      if (cs%c%last(jj) >= cs%c%first(jj)) bb = body(cs%c%eq_at(cs%c%first(jj)))
    end function row_body
    logical function touches_framed(jj) result(yes)
      integer, intent(in) :: jj
      integer :: p
      yes = .false.
      do p = cs%c%first(jj), cs%c%last(jj)
        if (body(cs%c%eq_at(p)) > 0) yes = yes .or. cs%fr_framed(body(cs%c%eq_at(p)))
      end do
    end function touches_framed
  end procedure obstacle_frame
end submodule contact_frame
