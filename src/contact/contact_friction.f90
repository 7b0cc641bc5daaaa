!> FRICTION on the impulses of the impact corrections (docs/contact.md, "Friction"): the normal
!> impulses a correction gives carry their Coulomb share and a sticking contact's slip rate is
!> brought to zero (friction_impulses), in 2D along the tangent, in 3D on the circle of the cone.
!> What these impulses take from the kinetic energy is the friction's dissipation, booked as such,
!> never restored. A submodule of contact.
submodule (contact) contact_friction
  implicit none

contains

  !> FRICTION on the impulses of the impact correction (docs/contact.md, "Friction"), one condition
  !> after the other; the kinetic energy each changes is the friction's, never restored
  !> (tangential_impulse), I_T kept in cimp(t) for the outputs.
  !> First the corrections: a condition j the correction pushes by I_N = cimp(j) > 0 gets along its
  !> tangential row t the impulse that opposes its slip rate v_t (c_t v, relative to a moving
  !> obstacle), capped by the cone and by what stops the slip: -sign(v_t) min(μ I_N, |v_t| / a_tt),
  !> a_tt = c_t M⁻¹c_t'; one the correction pulls back (I_N < 0: PERSIST's projection of the closing
  !> step's reflection) gives back the friction of that share of the step's impulse F = h/2 Λ_T:
  !> -sign(F) min(μ |I_N|, |F|), so that the step's tangential impulse stays within μ times its net
  !> normal one.
  !> Then the sticking contacts: a stuck condition's slip over the step is 0, Δu_T = (h/2)(v_T(n) +
  !> v_T(n+1)) = 0, so a node that sticks while it slid leaves the step at v_T(n+1) = -v_T(n) and
  !> keeps alternating (the trapezoid rule's signature, as the normal velocity's before eq (16)). A
  !> sticking contact is a tangential impact: its slip rate is brought to 0 by the impulse -v_t / a_tt
  !> along c_t, within what the cone leaves of the step's impulses, μ (h/2 Λ_N + I_N) - |h/2 Λ_T + I_T|.
  !> In 3D both on the circle (friction_impulse_3d).
  module procedure friction_impulses
    integer :: j, jt
    real(dp) :: vt, a(1, 1), f, p, budget
    stat = STAT_OK
    do j = 1, cs%nc                                    ! (cimp(jt) = 0 since contact_end_step began)
      jt = cs%fr%tangent_of(j)
      if (jt == 0 .or. cs%cimp(j) == 0.0_dp) cycle
      if (cs%fr%tangent2_of(j) > 0) then               ! 3D: the circle
        call friction_impulse_3d(cs, j, h, .false., v, mv, rep, stat, errmsg)
        if (stat /= STAT_OK) return
        cycle
      end if
      vt = slip_rate(cs, jt, v)
      f = 0.5_dp * h * cs%st%lambda(jt)                ! the step's tangential impulse
      if (cs%cimp(j) > 0.0_dp .and. vt == 0.0_dp) cycle
      if (cs%cimp(j) < 0.0_dp .and. f == 0.0_dp) cycle
      call cs%sp%am_block(cs%c, [jt], 1, a, stat, errmsg)
      if (stat /= STAT_OK) return
      if (.not. (a(1, 1) > 0.0_dp)) cycle
      if (cs%cimp(j) > 0.0_dp) then                    ! a push: its friction, against the slip rate
        p = -sign(min(cs%fr%mu_of(j) * cs%cimp(j), abs(vt) / a(1, 1)), vt)
      else                                             ! the correction took normal impulse back:
        p = -sign(min(cs%fr%mu_of(j) * abs(cs%cimp(j)), abs(f)), f)   ! the step's friction gives back its share
      end if
      call tangential_impulse(cs, [jt], [p], [vt], a, v, mv, rep, stat, errmsg)
      if (stat /= STAT_OK) return
    end do
    do j = 1, cs%nc                                    ! the sticking contacts' slip rates
      jt = cs%fr%tangent_of(j)
      if (jt == 0) cycle
      if (.not. (cs%now(j) .and. cs%fr%sticks(jt))) cycle
      if (cs%fr%tangent2_of(j) > 0) then               ! 3D: the circle
        call friction_impulse_3d(cs, j, h, .true., v, mv, rep, stat, errmsg)
        if (stat /= STAT_OK) return
        cycle
      end if
      vt = slip_rate(cs, jt, v)
      if (vt == 0.0_dp) cycle
      budget = cs%fr%mu_of(j) * (0.5_dp * h * cs%st%lambda(j) + max(cs%cimp(j), 0.0_dp)) - &
        abs(0.5_dp * h * cs%st%lambda(jt) + cs%cimp(jt))
      if (.not. budget > 0.0_dp) cycle
      call cs%sp%am_block(cs%c, [jt], 1, a, stat, errmsg)
      if (stat /= STAT_OK) return
      if (.not. (a(1, 1) > 0.0_dp)) cycle
      call tangential_impulse(cs, [jt], [-sign(min(budget, abs(vt) / a(1, 1)), vt)], [vt], a, v, mv, rep, stat, &
        errmsg)
      if (stat /= STAT_OK) return
    end do
  end procedure friction_impulses

  !> The slip rate of tangential row jt: c_t v, relative to a moving obstacle (its tangential
  !> velocity wrate(jt)).
  pure real(dp) function slip_rate(cs, jt, v) result(vt)
    type(contact_set_t), intent(in) :: cs
    integer, intent(in) :: jt
    real(dp), intent(in) :: v(:)
    vt = cs%c%dot(jt, v)
    if (cs%moving) vt = vt - cs%wrate(jt)
  end function slip_rate

  !> The impulse p(1:n) along the tangential rows jt(1:n) of a condition (n = 1 in 2D, 2 in 3D;
  !> vt their slip rates, a = C_T M⁻¹C_T'): v <- v + M⁻¹C_T'p, its dissipation -p·(vt + ½ a p) >= 0
  !> booked as the friction's and the rest of the kinetic change, p·(the obstacle's tangential
  !> velocity), as the obstacle's work; p kept in cimp(jt). (Loops: matmul would take a temporary.)
  subroutine tangential_impulse(cs, jt, p, vt, a, v, mv, rep, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: jt(:)
    real(dp), intent(in) :: p(:), vt(:), a(:, :)
    real(dp), intent(inout) :: v(:), mv(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, l
    real(dp) :: ap, dis, ow
    do k = 1, size(jt)
      cs%nu(jt(k)) = p(k)
    end do
    call cs%sp%add_minv_ct(cs%c, cs%nu, 1.0_dp, v, mv, stat, errmsg)
    do k = 1, size(jt)
      cs%nu(jt(k)) = 0.0_dp
    end do
    if (stat /= STAT_OK) return
    dis = 0.0_dp
    ow = 0.0_dp
    do k = 1, size(jt)
      ap = 0.0_dp
      do l = 1, size(jt)
        ap = ap + a(k, l) * p(l)
      end do
      dis = dis + p(k) * (vt(k) + 0.5_dp * ap)
      if (cs%moving) ow = ow + p(k) * cs%wrate(jt(k))
      cs%cimp(jt(k)) = cs%cimp(jt(k)) + p(k)
    end do
    rep%friction_dissipated = rep%friction_dissipated - dis
    if (cs%moving) rep%obstacle_work = rep%obstacle_work + ow
  end subroutine tangential_impulse

  !> The friction impulse of a 3D condition j (tangential rows t1, t2; A = C_T M⁻¹C_T', 2 × 2; v_t
  !> the slip rate). stick = .false., the corrections: a push I_N > 0 gets the impulse p* =
  !> -A⁻¹v_t that stops the slip, brought back to the circle μ I_N if it leaves it; a pull I_N < 0
  !> gives back -F min(1, μ |I_N| / |F|) of the step's tangential impulse F = h/2 Λ_T. stick =
  !> .true., the sticking contacts: p* within what the circle leaves of the step's impulses,
  !> μ (h/2 Λ_N + I_N) - |h/2 Λ_T + I_T|. Each is α p* (0 < α <= 1) and dissipates
  !> α (1 - α/2) p*'A p* >= 0.
  subroutine friction_impulse_3d(cs, j, h, stick, v, mv, rep, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: j
    real(dp), intent(in) :: h
    logical, intent(in) :: stick
    real(dp), intent(inout) :: v(:), mv(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: jt(2)
    real(dp) :: vt(2), a(2, 2), f(2), p(2), cap
    logical :: ok, pull
    stat = STAT_OK
    jt = [cs%fr%tangent_of(j), cs%fr%tangent2_of(j)]
    vt = [slip_rate(cs, jt(1), v), slip_rate(cs, jt(2), v)]
    f = 0.5_dp * h * cs%st%lambda(jt)
    pull = .not. stick .and. cs%cimp(j) < 0.0_dp
    if (stick) then
      cap = cs%fr%mu_of(j) * (0.5_dp * h * cs%st%lambda(j) + cs%cimp(j)) - norm2(f + cs%cimp(jt))
      if (.not. cap > 0.0_dp) return
    else
      cap = cs%fr%mu_of(j) * abs(cs%cimp(j))
    end if
    if (pull) then
      if (all(f == 0.0_dp)) return
      p = -f
    else
      if (all(vt == 0.0_dp)) return
    end if
    call cs%sp%am_block(cs%c, jt, 2, a, stat, errmsg)
    if (stat /= STAT_OK) return
    if (.not. pull) then
      call stop_impulse(a, vt, p, ok)
      if (.not. ok) return
    end if
    if (norm2(p) > cap) p = p * (cap / norm2(p))
    call tangential_impulse(cs, jt, p, vt, a, v, mv, rep, stat, errmsg)
  end subroutine friction_impulse_3d

  !> p = -A⁻¹v_t, the impulse that stops the slip rate v_t (A symmetric 2 × 2; ok = .false. where
  !> A is not positive definite: a tangent the mass does not move).
  pure subroutine stop_impulse(a, vt, p, ok)
    real(dp), intent(in) :: a(2, 2), vt(2)
    real(dp), intent(out) :: p(2)
    logical, intent(out) :: ok
    real(dp) :: det
    det = a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)
    ok = a(1, 1) > 0.0_dp .and. det > epsilon(1.0_dp) * a(1, 1) * a(2, 2)
    p = 0.0_dp
    if (ok) p = -[a(2, 2) * vt(1) - a(1, 2) * vt(2), a(1, 1) * vt(2) - a(2, 1) * vt(1)] / det
  end subroutine stop_impulse
end submodule contact_friction
