!> The KINEMATICS LARGE element kernels (docs/large-displacements.md): the strains of the current
!> configuration, the forces Bσ(n+1), and the correction force of eq (9) built from a discrete
!> gradient so that the step's internal work is the exact path work of the laws.
module large_kinematics
  use kinds, only: dp
  use scene, only: scene_t
  use assembly, only: system_t
  use elements, only: MAX_EDOF
  use element_beam2, only: gauss_legendre, BEAM2_MAX_GAUSS
  use material_law, only: law_step_t
  use element_points, only: model_view_t, point_update
  use law_hyperelastic, only: nh_stress, nh_tangent, nh_discrete_stress
  use log_strain, only: hencky_strain, log_tangent
  implicit none
  private
  public :: large_axial_element, large_plane_element, large_beam_element

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

  !> KINEMATICS LARGE, QUAD4/QUAD8/TRI3/TRI6 with the ELASTIC law: total Lagrangian, St Venant-
  !> Kirchhoff (docs/large-displacements.md); with HYPERELASTIC, neo-Hookean: S = S(E) of
  !> law_hyperelastic and S̄ its discrete stress (S̄·ΔE = Δψ exactly, symmetric), the rest alike;
  !> with VON_MISES, the small-strain J2 law on the pair (E, S) (large rotations, small strains:
  !> code_aster's GROT_GDEP), sub-incremented along the segment [E(n), E(n+1)] by point_update,
  !> S̄ its path-mean stress: S̄·ΔE is the law's path work (stored + dissipated), exactly.
  !> At each point F = I + Σ u_a ⊗ ∇N_a (∇N from the reference B, bref), the Green-Lagrange
  !> strain E = ½(F'F - I) (as xx, yy, zz = 0, 2xy) and the
  !> second Piola-Kirchhoff stress S = D E. Bσ(n+1) = w B_NL(F(n+1))' S(n+1), B_NL(F) the
  !> derivative of E. E is quadratic in u, so B_NL(F_mid) Δu = ΔE exactly (F_mid = (F(n) + F(n+1))/2),
  !> and with S̄ = D (E(n) + E(n+1))/2 the step force f̄ = w B_NL(F_mid)' S̄ does the work
  !> S̄ ΔE = Δψ exactly (Simo and Tarnow's energy-momentum step for this material): Bσc of eq (9)
  !> is 2 f̄ - f(n) - f(n+1). The tangent: w B_NL' D B_NL + the geometric part with the tensile
  !> part of S (positive definite however far an iterate goes). bmat keeps B_NL(F(n+1)) for the
  !> support reactions; the points report E and S. STRAIN_MEASURE LOG: the law on the Hencky strain
  !> and S̄ = G'T̄, G a secant of the log map (secant_stress); bmat then keeps P B_NL and the points report (ℓ, T).
  subroutine large_plane_element(scn, sys, mv, e, g0, ng, ndof, ue, une, correct, tangent, fe, fc, ke, any_c, wsum, dsum)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(model_view_t), intent(in) :: mv
    integer, intent(in) :: e, g0, ng, ndof
    real(dp), intent(in) :: ue(:), une(:)
    logical, intent(in) :: correct, tangent
    real(dp), intent(inout) :: fe(:), fc(:), ke(:, :), wsum, dsum
    logical, intent(inout) :: any_c
    real(dp), parameter :: eye(2, 2) = reshape([1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [2, 2])
    real(dp) :: dn(2, MAX_EDOF / 2), fn(2, 2), f1(2, 2), fm(2, 2), hn(2, 2), h1(2, 2), en(4), e1(4), s1(4), sn(4), sbar(4), &
      bn(4, MAX_EDOF), b1(4, MAX_EDOF), bm(4, MAX_EDOF), w, st(2, 2), g, dm(4, 4), pl(4, 4), wpt, dpt, snoise
    integer :: igp, p, nen, a, b, i
    nen = ndof / 2
    fc(1:ndof) = 0.0_dp
    do igp = g0, g0 + ng - 1
      p = sys%elems%b_ptr(igp)
      w = sys%elems%wt(igp)
      do a = 1, nen
        dn(1, a) = sys%elems%bref(p + (2 * a - 2) * 4)          ! B(1, 2a-1) = dN_a/dX
        dn(2, a) = sys%elems%bref(p + (2 * a - 1) * 4 + 1)      ! B(2, 2a)   = dN_a/dY
      end do
      hn = grad(une)
      h1 = grad(ue)
      fn = hn + eye
      f1 = h1 + eye
      ! An element turned inside out (det F <= 0) has no strain energy of its own to show it:
      ! reported to the step (iterate_eq9), as for the axial members.
      if (sys%elems%inverted == 0 .and. f1(1, 1) * f1(2, 2) - f1(1, 2) * f1(2, 1) <= 0.0_dp) sys%elems%inverted = e
      fm = 0.5_dp * (fn + f1)
      en = green(hn)
      e1 = green(h1)
      call plane_point(scn, sys, mv, igp, en, e1, tangent, correct, sn, s1, sbar, dm, pl, wpt, dpt, snoise)
      ! The attainable residual (iterate_eq9's floor): that stress noise through the point's ∇N.
      if (snoise > 0.0_dp) sys%elems%round_floor = sys%elems%round_floor + (w * snoise)**2 * sum(dn(:, 1:nen)**2)
      call bnl(f1, b1)
      call bnl(fn, bn)
      call bnl(fm, bm)
      do a = 1, ndof                          ! (loops, not reshape/matmul: no temporaries)
        if (mv%log_strain) then               ! the B of the point's strain: P B_NL for ℓ
          do i = 1, 4
            sys%elems%bmat(p + 4 * a - 5 + i) = dot_product(pl(i, :), b1(:, a))
          end do
        else
          sys%elems%bmat(p + 4 * a - 4:p + 4 * a - 1) = b1(:, a)
        end if
        fe(a) = fe(a) + w * s_dot_b(s1, b1, a)
      end do
      wsum = wsum + w * wpt
      dsum = dsum + w * dpt
      if (correct) then
        any_c = .true.
        do a = 1, ndof
          fc(a) = fc(a) + w * (2.0_dp * s_dot_b(sbar, bm, a) - s_dot_b(sn, bn, a) - s_dot_b(s1, b1, a))
        end do
      end if
      if (tangent) then
        call add_btdb(ke, w, b1, dm, ndof)
        ! Geometric part ∇N_a' S ∇N_b on both directions, with the tensile part of S.
        st = reshape([s1(1), s1(4), s1(4), s1(2)], [2, 2])
        call tensile_part(st)
        do a = 1, nen
          do b = 1, nen
            g = w * dot_product(dn(:, a), matmul(st, dn(:, b)))
            do i = 1, 2
              ke(2 * a - 2 + i, 2 * b - 2 + i) = ke(2 * a - 2 + i, 2 * b - 2 + i) + g
            end do
          end do
        end do
      end if
    end do
  contains
    !> The displacement gradient H = Σ u_a ⊗ ∇N_a (F = I + H).
    pure function grad(u) result(f)
      real(dp), intent(in) :: u(:)
      real(dp) :: f(2, 2)
      integer :: k
      f = 0.0_dp
      do k = 1, nen
        f(1, :) = f(1, :) + u(2 * k - 1) * dn(:, k)
        f(2, :) = f(2, :) + u(2 * k) * dn(:, k)
      end do
    end function grad
    !> E = ½(H + H' + H'H) as [Exx, Eyy, 0, 2 Exy] (the engineering shear, as the small strain's
    !> γ), from H: ½(F'F - I) would lose a small strain to round-off.
    pure function green(h) result(e)
      real(dp), intent(in) :: h(2, 2)
      real(dp) :: e(4), c(2, 2)
      c = matmul(transpose(h), h)
      e = [h(1, 1) + 0.5_dp * c(1, 1), h(2, 2) + 0.5_dp * c(2, 2), 0.0_dp, h(1, 2) + h(2, 1) + c(1, 2)]
    end function green
    !> dE = B_NL(F) du (rows as green's; columns u_x, u_y of each node).
    pure subroutine bnl(f, bb)
      real(dp), intent(in) :: f(2, 2)
      real(dp), intent(out) :: bb(:, :)
      integer :: k
      bb = 0.0_dp
      do k = 1, nen
        bb(1, 2 * k - 1) = f(1, 1) * dn(1, k)
        bb(1, 2 * k) = f(2, 1) * dn(1, k)
        bb(2, 2 * k - 1) = f(1, 2) * dn(2, k)
        bb(2, 2 * k) = f(2, 2) * dn(2, k)
        bb(4, 2 * k - 1) = f(1, 1) * dn(2, k) + f(1, 2) * dn(1, k)
        bb(4, 2 * k) = f(2, 1) * dn(2, k) + f(2, 2) * dn(1, k)
      end do
    end subroutine bnl
    !> The symmetric 2 x 2 s replaced by its positive part (eigenvalues below 0 set to 0).
    pure subroutine tensile_part(s)
      real(dp), intent(inout) :: s(2, 2)
      real(dp) :: m, r, v(2), v2(2), l(2)
      m = 0.5_dp * (s(1, 1) + s(2, 2))
      r = sqrt((0.5_dp * (s(1, 1) - s(2, 2)))**2 + s(1, 2)**2)
      l = [m + r, m - r]
      if (r == 0.0_dp) then
        v = [1.0_dp, 0.0_dp]
      else if (abs(s(1, 2)) > 0.0_dp) then
        v = [l(1) - s(2, 2), s(1, 2)]
        v = v / norm2(v)
      else
        v = merge([1.0_dp, 0.0_dp], [0.0_dp, 1.0_dp], s(1, 1) >= s(2, 2))
      end if
      v2 = [-v(2), v(1)]
      s = max(l(1), 0.0_dp) * spread(v, 2, 2) * spread(v, 1, 2) + max(l(2), 0.0_dp) * spread(v2, 2, 2) * spread(v2, 1, 2)
    end subroutine tensile_part
  end subroutine large_plane_element

  !> One point of a LARGE surface element: from the Green-Lagrange strains en, e1 of the step's
  !> ends, the second Piola-Kirchhoff stresses sn, s1, the step's stress sbar with sbar·(e1 - en)
  !> = wpt, the law's path work (dissipated part dpt), and the material tangent dm on E. The point
  !> keeps (and reports) its own pair: (E, S), or with STRAIN_MEASURE LOG (ℓ, T), T conjugate to the
  !> Hencky strain ℓ (log_strain): the law runs on ℓ along the segment [ℓ(n), ℓ(n+1)] (ELASTIC:
  !> the Hencky material, T = D ℓ, path work = Δψ exactly; VON_MISES: J2 additive in ℓ), S = P'T,
  !> and sbar = G'T̄ does that path work on ΔE (secant_stress). pl: P = dℓ/dE (set for the log strain only).
  subroutine plane_point(scn, sys, mv, igp, en, e1, tangent, correct, sn, s1, sbar, dm, pl, wpt, dpt, snoise)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(model_view_t), intent(in) :: mv
    integer, intent(in) :: igp
    real(dp), intent(in) :: en(4), e1(4)
    logical, intent(in) :: tangent, correct   !< correct: the tangent of 2f̄ - f(n) (eq 9), not f(n+1)'s
    real(dp), intent(out) :: sn(4), s1(4), sbar(4), dm(4, 4), pl(4, 4), wpt, dpt
    real(dp), intent(out) :: snoise        !< stress noise of S̄ (secant_stress; 0 off the log strain)
    type(law_step_t) :: r
    real(dp) :: ln(4), l1(4), pn(4, 4), tn(4), t1(4), tbar(4)
    logical :: okn, ok1
    dpt = 0.0_dp
    snoise = 0.0_dp
    if (mv%log_strain) then
      call hencky_strain(en, ln, pn, okn)
      call hencky_strain(e1, l1, pl, ok1)
      ! C singular: det F = 0, which large_plane_element reports as an inversion.
      if (.not. (okn .and. ok1)) l1 = ln
    else
      ln = en
      l1 = e1
    end if
    tn = sys%pts%sig(1:4, igp)
    if (mv%hyper) then
      t1 = nh_stress(mv%lame, e1, mv%pstress)
      tbar = nh_discrete_stress(mv%lame, en, e1, mv%pstress)
      if (tangent) dm = nh_tangent(mv%lame, e1, mv%pstress)
    else if (mv%von_mises) then
      call point_update(scn, sys, mv, igp, ln, l1 - ln, r)
      t1 = r%sig(1:4)
      tbar = r%sigbar(1:4)
      dpt = r%dissip
      if (tangent) dm = r%dtan(1:4, 1:4)
      if (tangent .and. correct .and. r%has_dbar) dm = r%dbar(1:4, 1:4)
    else
      t1 = matmul(sys%elems%dmat(1:4, 1:4, mv%im), l1)
      tbar = 0.5_dp * (tn + t1)
      if (tangent) dm = sys%elems%dmat(1:4, 1:4, mv%im)
    end if
    sys%pts%eps_t(1:4, igp) = l1
    sys%pts%sig_t(1:4, igp) = t1
    wpt = dot_product(tbar, l1 - ln)
    if (.not. mv%log_strain) then
      sn = tn
      s1 = t1
      sbar = tbar
      return
    end if
    sn = matmul(tn, pn)
    s1 = matmul(t1, pl)
    call secant_stress(tbar, ln, l1, en, e1, pn, pl, sbar, snoise)
    if (tangent) call log_tangent(e1, t1, pl, dm)
  end subroutine plane_point

  !> The step's second Piola-Kirchhoff stress of a STRAIN_MEASURE LOG point: S̄ = G'T̄, T̄ the law's
  !> step stress on the Hencky strain (its path mean: T̄·Δℓ is the law's path work) and G a secant
  !> of the map E -> ℓ, G ΔE = Δℓ:
  !>     G = P_m + φ r ⊗ d / (d·ΔE),  P_m = ½(P(n) + P(n+1)),  r = Δℓ - P_m ΔE,  d = ΔE (shear halved),
  !> so that S̄·ΔE = T̄·Δℓ: the step's work is the law's. r is the trapezoid rule's error on the
  !> smooth log map, O(|ΔE|³): the material part stays in T̄ (as σ̄ in small strain) and the term
  !> vanishes with the increment. Its round-off, ν ≈ 64 ε (|ℓ| + |E|), divided by |ΔE| would put
  !> noise in S̄ at small increments of a strained point (Newton then stagnates: the 8 x 40 Taylor
  !> bar at 69 µs); φ, a smooth step of |ΔE|/δ from 0 at δ = ν^(1/3) to 1 at 2δ, leaves it out
  !> there, where it is below |T̄| δ³ in work. snoise = |T̄| δ²: the stress noise left either way,
  !> for the attainable residual (round_floor).
  pure subroutine secant_stress(tbar, ln, l1, en, e1, pn, p1, sbar, snoise)
    real(dp), intent(in) :: tbar(4), ln(4), l1(4), en(4), e1(4), pn(4, 4), p1(4, 4)
    real(dp), intent(out) :: sbar(4), snoise
    real(dp) :: pm(4, 4), de(4), dd(4), r(4), den, delta, x, phi
    integer :: i
    pm = 0.5_dp * (pn + p1)
    de = e1 - en
    dd = [de(1), de(2), de(3), 0.5_dp * de(4)]
    den = dot_product(dd, de)
    sbar = matmul(tbar, pm)
    delta = (64.0_dp * epsilon(1.0_dp) * (sum(abs(l1) + abs(ln)) + sum(abs(e1) + abs(en))))**(1.0_dp / 3.0_dp)
    snoise = norm2(tbar) * delta**2
    x = sqrt(den) / max(delta, tiny(1.0_dp)) - 1.0_dp
    if (x <= 0.0_dp) return
    phi = 1.0_dp
    if (x < 1.0_dp) phi = x * x * (3.0_dp - 2.0_dp * x)
    do i = 1, 4
      r(i) = (l1(i) - ln(i)) - dot_product(pm(i, :), de)
    end do
    sbar = sbar + (phi * dot_product(tbar, r) / den) * dd
  end subroutine secant_stress

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
  !> s'b(:, k), summed in the order of the components (as matmul(s, b) does).
  pure real(dp) function s_dot_b(s, b, k) result(r)
    real(dp), intent(in) :: s(4), b(:, :)
    integer, intent(in) :: k
    integer :: i
    r = 0.0_dp
    do i = 1, 4
      r = r + s(i) * b(i, k)
    end do
  end function s_dot_b

  !> ke(1:ndof, 1:ndof) += w b'D b with b = b(1:4, 1:ndof) (loops on fixed-size work: no temporaries).
  pure subroutine add_btdb(ke, w, b, d, ndof)
    real(dp), intent(inout) :: ke(:, :)
    real(dp), intent(in) :: w, b(:, :), d(4, 4)
    integer, intent(in) :: ndof
    real(dp) :: db(4, MAX_EDOF), t
    integer :: i, j, k, l
    do l = 1, ndof
      do i = 1, 4
        t = 0.0_dp
        do j = 1, 4
          t = t + d(i, j) * b(j, l)
        end do
        db(i, l) = t
      end do
    end do
    do l = 1, ndof
      do k = 1, ndof
        t = 0.0_dp
        do i = 1, 4
          t = t + b(i, k) * db(i, l)
        end do
        ke(k, l) = ke(k, l) + w * t
      end do
    end do
  end subroutine add_btdb
end module large_kinematics
