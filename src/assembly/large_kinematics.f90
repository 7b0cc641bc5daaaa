!> The KINEMATICS LARGE element kernels (docs/large-displacements.md): the strains of the current
!> configuration, the forces Bσ(n+1), and the correction force of eq (9) built from a discrete
!> gradient so that the step's internal work is the exact path work of the laws.
module large_kinematics
  use kinds, only: dp
  use scene, only: scene_t
  use assembly, only: system_t
  use element_beam2, only: gauss_legendre, BEAM2_MAX_GAUSS
  use material_law, only: law_step_t
  use element_points, only: model_view_t, point_update
  implicit none
  private
  public :: large_axial_element, large_beam_element

  real(dp), parameter :: TWO_PI = 2.0_dp * acos(-1.0_dp)

contains

  !> KINEMATICS LARGE, BAR2 and SPRING (docs/large-displacements.md): the axial strain of the
  !> current length, eps = (l - L)/s (s = L for BAR2, 1 for SPRING: an elongation; computed
  !> without cancellation), through the law along the straight strain path from eps(n) to
  !> eps(n+1). Bσ(n+1) = w σ(n+1) B(n+1)', with B = [-e, e]/s and e the current unit axis. The
  !> correction of eq (9) makes the step's internal work exact along the large-displacement path:
  !> the step force is the discrete gradient
  !> f̄ = w σ̄ B_d', B_d = [-d, d], d = (x(n) + x(n+1)) / (s (l(n) + l(n+1))), so that B_d Δu = Δeps
  !> exactly and f̄'Δu = w σ̄ Δeps, the law's path work (for the elastic law ½ w E Δ(eps²):
  !> exact energy); f̄ lies along x(n) + x(n+1), so it has no moment about the step's midpoint
  !> configuration and the trapezoidal rule keeps angular momentum. As Bσc of eq (9) (which
  !> enters as ½ Bσc): fc = 2 f̄ - f(n) - f(n+1).
  !> The tangent (TANGENT, AUTO): that of the forces eq (9) carries, positive semi-definite (below).
  !> The current B is kept in the element table, so that the support reactions read the current axis.
  subroutine large_axial_element(scn, sys, mv, e, g0, ng, ue, une, correct, tangent, fe, fc, ke, any_c, wsum, dsum)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(model_view_t), intent(in) :: mv
    integer, intent(in) :: e, g0, ng
    real(dp), intent(in) :: ue(:), une(:)
    logical, intent(in) :: correct, tangent
    real(dp), intent(inout) :: fe(:), fc(:), ke(:, :), wsum, dsum
    logical, intent(inout) :: any_c
    real(dp) :: x0(2), xn(2), x1(2), ln, l1, len0, s, epsn, eps1, deps(1), b1(4), bn(4), bd(4), d(2), ax(2), w, &
      gmat(2, 2), dhat(2), sigbar, g
    type(law_step_t) :: r
    integer :: igp, p
    x0 = scn%mesh%x(:, scn%mesh%conn(2, e)) - scn%mesh%x(:, scn%mesh%conn(1, e))
    len0 = norm2(x0)
    s = 1.0_dp
    if (mv%per_length) s = len0
    xn = x0 + une(3:4) - une(1:2)
    x1 = x0 + ue(3:4) - ue(1:2)
    ln = norm2(xn)
    l1 = norm2(x1)
    ! A member whose axis turns by 90 degrees or more in one step, or whose length vanishes, is
    ! inverted: its strain (from |x|) would not see it. Reported to the step (iterate_eq9).
    if (sys%elems%inverted == 0 .and. (dot_product(xn, x1) <= 0.0_dp .or. l1 <= 1.0e-9_dp * len0)) &
      sys%elems%inverted = e
    ! l - L = (2 X.Δu + Δu.Δu) / (l + L), Δu the relative displacement: no cancellation when
    ! the strain is small (l - L itself would lose it to round-off: 1e-16 of strain is 2e-5 Pa
    ! of a steel bar's stress, and the energy balance would see it).
    epsn = chord_stretch(x0, len0, une(3:4) - une(1:2), ln) / s
    eps1 = chord_stretch(x0, len0, ue(3:4) - ue(1:2), l1) / s
    ax = x1 / max(l1, tiny(1.0_dp))
    b1 = [-ax, ax] / s
    bn = [-xn, xn] / (s * max(ln, tiny(1.0_dp)))
    d = (xn + x1) / (s * max(ln + l1, tiny(1.0_dp)))
    bd = [-d, d]
    fc(1:4) = 0.0_dp
    do igp = g0, g0 + ng - 1
      p = sys%elems%b_ptr(igp)
      w = sys%elems%wt(igp)
      deps(1) = eps1 - epsn
      call point_update(scn, sys, mv, igp, [epsn], deps, r)
      sys%pts%eps_t(1, igp) = eps1
      sys%pts%sig_t(1, igp) = r%sig(1)
      call add_round_floor(sys, w * abs(r%dtan(1, 1)) / s**2, [x0, ue(1:4)])
      sys%elems%bmat(p:p + 3) = b1
      fe(1:4) = fe(1:4) + w * r%sig(1) * b1
      sigbar = r%sigbar(1)
      wsum = wsum + w * sigbar * deps(1)
      dsum = dsum + w * r%dissip
      if (correct) then
        any_c = .true.
        fc(1:4) = fc(1:4) + w * (2.0_dp * sigbar * bd - sys%pts%sig(1, igp) * bn - r%sig(1) * b1)
      end if
      if (tangent) then
        ! With the correction, eq (9) carries f(n+1) + fc = 2 f̄, whose derivative is, to first
        ! order in the step's rotation, w dσ/deps d d' + 2 w σ̄ / (s (l(n) + l(n+1))) (I - d̂ d̂')
        ! (d̂ = d/|d|: the chord of the step, where f̄ acts); without it, f(n+1)'s:
        ! (w dσ/deps / s²) e e' + w σ / (s l) (I - e e'). Both are symmetric and, with compression
        ! and softening left out, positive semi-definite however far an iterate goes (the
        ! residual, not the matrix, sets the answer).
        if (correct) then
          dhat = d / max(norm2(d), tiny(1.0_dp))
          g = 2.0_dp * w * max(sigbar, 0.0_dp) / (s * max(ln + l1, tiny(1.0_dp)))
          gmat = w * max(r%dtan(1, 1), 0.0_dp) * outer2(d, d) - g * outer2(dhat, dhat)
        else
          g = w * max(r%sig(1), 0.0_dp) / (s * max(l1, tiny(1.0_dp)))
          gmat = (w * max(r%dtan(1, 1), 0.0_dp) / s**2 - g) * outer2(ax, ax)
        end if
        gmat(1, 1) = gmat(1, 1) + g
        gmat(2, 2) = gmat(2, 2) + g
        call add_chord_block(ke, gmat, 2)
      end if
    end do
  contains
    pure function outer2(x, y) result(m)
      real(dp), intent(in) :: x(2), y(2)
      real(dp) :: m(2, 2)
      m = spread(x, 2, 2) * spread(y, 1, 2)
    end function outer2
  end subroutine large_axial_element

  !> KINEMATICS LARGE, BEAM2: corotational (docs/large-displacements.md). The chord of the element
  !> turns by α (from the reference chord); in that frame the beam is the small-strain BEAM2, with
  !> the natural deformations q = (e, θ̄1, θ̄2): e = l - L the elongation of the chord (computed
  !> without cancellation), θ̄a = θa - α the nodal rotations relative to the chord. The points see
  !> eps = e/L and kappa = (k1 θ̄1 + k2 θ̄2)/L (k1 = 6r - 4, k2 = 6r - 2: the Hermite curvature with
  !> no transverse displacement in the chord's frame), so the section laws (elastic, fibre
  !> plasticity) work unchanged. Bσ(n+1) = G(n+1)' Q(n+1), G = dq/du and Q = Σ w T' σ the natural
  !> forces (N and the two end moments). Eq (9)'s correction uses a discrete gradient Gd, Gd Δu = Δq
  !> exactly: for e the chord form of the bars; for θ̄a, the chord's exact rotation Δα of the step
  !> and ā = ∇α(c_mid) + (Δα - ∇α(c_mid)·Δc) Δc/|Δc|² (Gonzalez), so ā·Δc = Δα. The step force
  !> f̄ = Gd' Q̄ then does the law's path work: the energy identity holds to round-off at any step.
  !> Linear momentum is kept exactly. A rotation that takes the Cayley update (sys%dofs%cayley:
  !> θ(n+1) = θ(n) + 2 atan(Δw/2)) has the row of cayley_row, without moment about the step's middle
  !> configuration: angular momentum kept. An additive rotation keeps Gonzalez's row, whose moment
  !> (Q̄2 + Q̄3)(Δα - Δα̃)(Δc·J c_mid)/|Δc|² (Δα̃ = ∇α(c_mid)·Δc) is O(h²) (docs/large-displacements.md).
  !> from_n: une is the committed state (else zero, the path from the reference configuration,
  !> rotations additive).
  subroutine large_beam_element(scn, sys, mv, e, g0, ng, ue, une, from_n, correct, tangent, fe, fc, ke, any_c, wsum, &
                                dsum)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(model_view_t), intent(in) :: mv
    integer, intent(in) :: e, g0, ng
    real(dp), intent(in) :: ue(:), une(:)
    logical, intent(in) :: from_n, correct, tangent
    real(dp), intent(inout) :: fe(:), fc(:), ke(:, :), wsum, dsum
    logical, intent(inout) :: any_c
    real(dp) :: x0(2), len0, cn(2), c1(2), dc(2), cm(2), ln, l1, am(2), ab(2), dalpha, d(2), gd(3, 6), gn(3, 6), g1(3, 6), &
      dq(3), qn(3), q1(3), qb(3), kq(3, 3), t(2, 3), en, e1, epsn(2), deps(2), w, r01, xi(BEAM2_MAX_GAUSS), &
      wg(BEAM2_MAX_GAUSS)
    type(law_step_t) :: r
    integer :: igp, p, a, ia
    real(dp) :: acoef, abc(2)
    x0 = scn%mesh%x(:, scn%mesh%conn(2, e)) - scn%mesh%x(:, scn%mesh%conn(1, e))
    len0 = norm2(x0)
    cn = x0 + une(4:5) - une(1:2)
    c1 = x0 + ue(4:5) - ue(1:2)
    ln = norm2(cn)
    l1 = norm2(c1)
    if (sys%elems%inverted == 0 .and. (dot_product(cn, c1) <= 0.0_dp .or. l1 <= 1.0e-9_dp * len0)) sys%elems%inverted = e
    en = chord_stretch(x0, len0, une(4:5) - une(1:2), ln)
    e1 = chord_stretch(x0, len0, ue(4:5) - ue(1:2), l1)
    call natural_gradient(cn, ln, gn)
    call natural_gradient(c1, l1, g1)
    ! The discrete gradient: the chord form for e, the step's exact chord rotation for θ̄.
    ! Δc from the increments, and cn x c1 = cn x Δc: the step's rotation Δα and its midpoint
    ! estimate ∇α(c_mid)·Δc are then both exact to a relative round-off, and so is their difference
    ! (O(Δα³)), which the Gonzalez term divides by |Δc|. (From c1 - cn, a step of 1e-8 rad would
    ! carry 1e-8 of relative error into Δα and the residual would stall at 1e-7 of the moments.)
    dc = (ue(4:5) - une(4:5)) - (ue(1:2) - une(1:2))
    cm = cn + 0.5_dp * dc
    am = [-cm(2), cm(1)] / max(dot_product(cm, cm), tiny(1.0_dp))
    dalpha = atan2(cn(1) * dc(2) - cn(2) * dc(1), ln * ln + dot_product(cn, dc))
    ab = am
    if (dot_product(dc, dc) > 0.0_dp) ab = am + (dalpha - dot_product(am, dc)) * dc / dot_product(dc, dc)
    d = (cn + c1) / max(ln + l1, tiny(1.0_dp))
    gd(1, :) = [-d(1), -d(2), 0.0_dp, d(1), d(2), 0.0_dp]
    gd(2, :) = [ab(1), ab(2), 1.0_dp, -ab(1), -ab(2), 0.0_dp]
    gd(3, :) = [ab(1), ab(2), 0.0_dp, -ab(1), -ab(2), 1.0_dp]
    do a = 1, 2
      if (.not. (from_n .and. allocated(sys%dofs%cayley))) cycle
      ia = sys%dofs%eqn(3, scn%mesh%conn(a, e))
      if (ia <= 0) cycle
      if (.not. sys%dofs%cayley(ia)) cycle
      call cayley_row(cm, dc, ue(3 * a) - une(3 * a), acoef, abc)
      gd(1 + a, :) = [abc(1), abc(2), 0.0_dp, -abc(1), -abc(2), 0.0_dp]
      gd(1 + a, 3 * a) = acoef
    end do
    dq = matmul(gd, ue(1:6) - une(1:6))
    dq(1) = e1 - en
    ! Relative rotations modulo 2 pi: an INITIAL DISPLACEMENT may turn the nodes by whole turns in
    ! one jump from the reference, which Δα (in (-pi, pi]) does not count (a step cannot: STEP_INVERTED).
    dq(2:3) = dq(2:3) - TWO_PI * anint(dq(2:3) / TWO_PI)
    qn = 0.0_dp
    q1 = 0.0_dp
    qb = 0.0_dp
    kq = 0.0_dp
    fc(1:6) = 0.0_dp
    call gauss_legendre(ng, xi, wg)                 ! the points' x'/L, (1 + xi)/2
    do igp = g0, g0 + ng - 1
      p = sys%elems%b_ptr(igp)
      w = sys%elems%wt(igp)
      r01 = 0.5_dp * (1.0_dp + xi(igp - g0 + 1))
      t = 0.0_dp
      t(1, 1) = 1.0_dp / len0
      t(2, 2) = (6.0_dp * r01 - 4.0_dp) / len0
      t(2, 3) = (6.0_dp * r01 - 2.0_dp) / len0
      epsn = [en / len0, 0.0_dp]
      if (from_n) epsn(2) = sys%pts%eps(2, igp)
      deps = matmul(t, dq)
      call point_update(scn, sys, mv, igp, epsn, deps, r)
      sys%pts%eps_t(1:2, igp) = [e1 / len0, epsn(2) + deps(2)]
      call add_round_floor(sys, w * abs(r%dtan(1, 1)) / len0**2, [x0, ue(1:2), ue(4:5)])
      sys%pts%sig_t(1:2, igp) = r%sig(1:2)
      sys%elems%bmat(p:p + 11) = reshape(matmul(t, g1), [12])
      q1 = q1 + w * matmul(r%sig(1:2), t)
      qb = qb + w * matmul(r%sigbar(1:2), t)
      qn = qn + w * matmul(sys%pts%sig(1:2, igp), t)
      wsum = wsum + w * dot_product(r%sigbar(1:2), deps)
      dsum = dsum + w * r%dissip
      if (tangent) kq = kq + w * matmul(transpose(t), matmul(r%dtan(1:2, 1:2), t))
    end do
    fe(1:6) = fe(1:6) + matmul(q1, g1)
    if (correct) then
      any_c = .true.
      fc(1:6) = 2.0_dp * matmul(qb, gd) - matmul(qn, gn) - matmul(q1, g1)
    end if
    if (.not. tangent) return
    if (correct) then
      call beam_tangent(gd, kq, qb, 0.5_dp * (ln + l1), d, cm, ke)
    else
      call beam_tangent(g1, kq, q1, l1, c1, c1, ke)
    end if
  contains
    !> dq/du at the chord c (length l): e along ĉ, θ̄a = θa - α with ∇α = J c/l².
    pure subroutine natural_gradient(c, l, g)
      real(dp), intent(in) :: c(2), l
      real(dp), intent(out) :: g(3, 6)
      real(dp) :: u(2), a(2)
      u = c / max(l, tiny(1.0_dp))
      a = [-c(2), c(1)] / max(l * l, tiny(1.0_dp))
      g(1, :) = [-u(1), -u(2), 0.0_dp, u(1), u(2), 0.0_dp]
      g(2, :) = [a(1), a(2), 1.0_dp, -a(1), -a(2), 0.0_dp]
      g(3, :) = [a(1), a(2), 0.0_dp, -a(1), -a(2), 1.0_dp]
    end subroutine natural_gradient
  end subroutine large_beam_element

  !> The discrete gradient row of θ̄a = θa - α for a node whose rotation turns by the Cayley angle
  !> Θ(Δw) = 2 atan(Δw/2) of its increment (cayley_rotations): g·Δu = Θ(Δw) - Δα exactly, and
  !> g·δ = 0 for the infinitesimal rotation δ about the step's middle (J x_mid on the positions, 1
  !> on the rotations), so f̄ = Gd'Q̄ has no moment: angular momentum is kept. With the chord's
  !> increment Δc = a J c_mid + d c_mid (c_mid the mid-step chord), Δα = Θ(a) + φ(a, d) with
  !> φ = atan2(a d²/4, ...) the stretch's share, and p = Δw - a: g = (ā, A, -ā, 0) (node 1; node 2
  !> mirrored: A on its own rotation), A = (Θ(Δw) - Θ(a))/p, ā = (A J c_mid + (φ/d) c_mid)/|c_mid|², both written without
  !> cancellation (A -> Θ'(a) as p -> 0, φ/d -> 0 as d -> 0). A rigid rotation (p = d = 0) is
  !> then an exact motion of the step with no strain (docs/large-displacements.md).
  pure subroutine cayley_row(cm, dc, dw, acoef, ab)
    real(dp), intent(in) :: cm(2), dc(2), dw
    real(dp), intent(out) :: acoef, ab(2)
    real(dp) :: m2, jc(2), ar, dr, p, dcoef
    m2 = max(dot_product(cm, cm), tiny(1.0_dp))
    jc = [-cm(2), cm(1)]
    ar = dot_product(dc, jc) / m2
    dr = dot_product(dc, cm) / m2
    p = dw - ar
    if (p == 0.0_dp) then
      acoef = 1.0_dp / (1.0_dp + 0.25_dp * ar * ar)
    else
      acoef = 2.0_dp * atan2(0.5_dp * p, 1.0_dp + 0.25_dp * ar * dw) / p
    end if
    dcoef = 0.0_dp
    if (dr /= 0.0_dp) dcoef = atan2(0.25_dp * ar * dr * dr, (1.0_dp - 0.25_dp * ar * ar) * &
      (1.0_dp - 0.25_dp * (ar * ar + dr * dr)) + ar * ar) / dr
    ab = (acoef * jc + dcoef * cm) / m2
  end subroutine cayley_row

  !> The tangent of the forces eq (9) carries for a corotational BEAM2 (2 f̄ with the correction,
  !> f(n+1) without), into ke: the material part G' Kq G (G = Gd, or G(n+1); of the symmetric
  !> forms of 2 f̄'s Jacobian Gd' Kq G(n+1) + ..., Gd' Kq Gd converges best: 13.6 iterations per
  !> step on beam_flying at h = 0.1 where (Gd + G(n+1))/2 needs retries), and the geometric parts
  !> on the translations: the chord's tension N (I - ĉĉ')/l (ĉ along dir; compression left out, as
  !> the bars) and the positive part of the end moments' -(M1 + M2) ∂²α/∂c² at the chord c (trace-
  !> free: its positive part is half of it plus half its eigenvalue). Kept positive semi-definite:
  !> the full geometric terms make K + 4M/h² indefinite on beam_flying at h = 0.1 (CHOLMOD stops).
  pure subroutine beam_tangent(g, kq, q, l, dir, c, ke)
    real(dp), intent(in) :: g(3, 6), kq(3, 3), q(3), l, dir(2), c(2)
    real(dp), intent(inout) :: ke(:, :)
    real(dp) :: ch(2), nax, gm(2, 2), hm(2, 2), lam
    ke(1:6, 1:6) = ke(1:6, 1:6) + matmul(transpose(g), matmul(kq, g))
    nax = max(q(1), 0.0_dp) / max(l, tiny(1.0_dp))
    ch = dir / max(norm2(dir), tiny(1.0_dp))
    gm = -nax * spread(ch, 2, 2) * spread(ch, 1, 2)
    hm = -(q(2) + q(3)) / max(dot_product(c, c)**2, tiny(1.0_dp)) * &
      reshape([2.0_dp * c(1) * c(2), c(2)**2 - c(1)**2, c(2)**2 - c(1)**2, -2.0_dp * c(1) * c(2)], [2, 2])
    lam = sqrt(hm(1, 1)**2 + hm(1, 2)**2)
    gm = gm + 0.5_dp * hm
    gm(1, 1) = gm(1, 1) + nax + 0.5_dp * lam
    gm(2, 2) = gm(2, 2) + nax + 0.5_dp * lam
    call add_chord_block(ke, gm, 3)
  end subroutine beam_tangent

  !> A 2 x 2 stiffness g of a two-node member's chord (x2 - x1) into ke: +g on each node's
  !> translations, -g between them; stride = the DOFs per node (2: BAR2, SPRING; 3: BEAM2).
  pure subroutine add_chord_block(ke, g, stride)
    real(dp), intent(inout) :: ke(:, :)
    real(dp), intent(in) :: g(2, 2)
    integer, intent(in) :: stride
    integer :: a, b
    do a = 0, 1
      do b = 0, 1
        ke(stride * a + 1:stride * a + 2, stride * b + 1:stride * b + 2) = &
          ke(stride * a + 1:stride * a + 2, stride * b + 1:stride * b + 2) + merge(1.0_dp, -1.0_dp, a == b) * g
      end do
    end do
  end subroutine add_chord_block

  !> l - L of a chord X + du of current length l, reference X of length len0, as
  !> (2 X·du + du·du)/(l + L): no cancellation when the strain is small.
  pure real(dp) function chord_stretch(x0, len0, du, l)
    real(dp), intent(in) :: x0(2), len0, du(2), l
    chord_stretch = (2.0_dp * dot_product(x0, du) + dot_product(du, du)) / (l + len0)
  end function chord_stretch

  !> One LARGE axial member's share of the residual's round-off floor: its axial stiffness k times
  !> one ulp of the largest coordinate its chord is computed from (the chord X + u2 - u1 cannot be
  !> known better, so neither can its force: a convergence test below this would never pass).
  pure subroutine add_round_floor(sys, k, x)
    type(system_t), intent(inout) :: sys
    real(dp), intent(in) :: k, x(:)
    sys%elems%round_floor = sys%elems%round_floor + (k * spacing(maxval(abs(x))))**2
  end subroutine add_round_floor
end module large_kinematics
