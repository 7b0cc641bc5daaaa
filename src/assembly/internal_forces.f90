!> The internal forces of eq (9) from the element stresses: Bσ(n+1) of a trial state, the
!> correction force Bσc where the laws were sub-incremented, the consistent tangent on demand,
!> and the work of the increment (returned, never stored in the system). Linear elastic points
!> take σ = D ε in fixed-size kernels; nonlinear points call material_law's law_update
!> (sub-incrementation) and form σc with correction_stress.
module internal_forces
  use kinds, only: dp, qp
  use scene, only: scene_t
  use assembly, only: system_t
  use elements, only: MAX_EDOF, MAX_NSTRAIN
  use element_traits, only: ET_BAR2
  use material_law, only: law_update, law_nstate, law_step_t
  use subincrement, only: correction_stress
  implicit none
  private
  public :: internal_force, work_increment_t

  !> The energies of a trial increment.
  type :: work_increment_t
    real(dp) :: work = 0.0_dp        !< W_N = Σ w σ̄·Δε at the nonlinear points (sub-incremented work)
    real(dp) :: elastic = 0.0_dp     !< strain energy ½ σ·ε of the trial state at the linear elastic points
    real(dp) :: dissipated = 0.0_dp  !< plastic work of the increment
  end type work_increment_t

  !> What the points of one element need to know of their model.
  type :: model_view_t
    integer :: im = 0, mat = 0, nq = 0, nsub = 0
    logical :: linear = .true.
    logical :: large = .false.       !< KINEMATICS LARGE (BAR2, SPRING)
    logical :: per_length = .false.  !< the strain is an elongation over the length (BAR2), not an elongation (SPRING)
  end type model_view_t

contains

  !> Trial state for the total displacement u: strains, then the stresses the laws give along
  !> the step's straight strain path from the committed state, in the model's sub-increments.
  !> Returns fint = sum B'sigma(n+1) w and the correction force fcorr = sum B'sigma_c w of
  !> eq (9), sigma_c = 2 sigma_bar - (sigma(n) + sigma(n+1)); with correct = .false., or at
  !> points whose step stayed elastic, sigma_c is not formed (it is exactly zero), and the
  !> energies of the increment in inc. With tangent = .true. the consistent tangent is
  !> assembled into sys%ops%tval. Every trial point (eps_t, sig_t, q_t) is written before it is
  !> read, so commit_state may swap the trial and committed arrays. uq: u unrounded
  !> (PRECISION EXTENDED: the linear elastic points are then evaluated in quadruple precision).
  !> un: the committed displacements u(n), which KINEMATICS LARGE elements need (absent: zero,
  !> the path from the reference configuration).
  subroutine internal_force(scn, sys, u, fint, fcorr, correct, tangent, inc, uq, un)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    real(dp), intent(in) :: u(:)
    real(dp), intent(out) :: fint(:), fcorr(:)
    logical, intent(in) :: correct, tangent
    type(work_increment_t), intent(out) :: inc
    real(qp), intent(in), optional :: uq(:)
    real(dp), intent(in), optional :: un(:)
    type(model_view_t) :: mv
    integer :: e, ndof, nstr, ng, g0, k, j, e0
    real(dp) :: ue(MAX_EDOF), une(MAX_EDOF), fe(MAX_EDOF), fc(MAX_EDOF), ke(MAX_EDOF, MAX_EDOF), wsum, dsum, esum
    real(qp) :: esumq
    logical :: any_c
    fint = 0.0_dp
    esumq = 0.0_qp
    if (sys%extended) sys%fint_q = 0.0_qp
    fcorr = 0.0_dp
    wsum = 0.0_dp
    esum = 0.0_dp
    dsum = 0.0_dp
    if (tangent) sys%ops%tval = 0.0_dp
    if (sys%react%nslot > 0) sys%react%fc_t = 0.0_dp
    sys%elems%inverted = 0
    do e = 1, scn%mesh%nelem
      if (scn%elem_model(e) == 0) cycle
      g0 = sys%elems%gp_ptr(e)
      ng = sys%elems%gp_ptr(e + 1) - g0
      if (ng == 0) cycle
      e0 = sys%elems%edof_ptr(e)
      ndof = sys%elems%edof_ptr(e + 1) - e0
      nstr = (sys%elems%b_ptr(g0 + 1) - sys%elems%b_ptr(g0)) / ndof
      ! Per-model data, looked up once per run of elements of the same model.
      if (scn%elem_model(e) /= mv%im) call view_model(scn, sys, scn%elem_model(e), mv)
      do k = 1, ndof
        j = sys%elems%edof(e0 + k - 1)
        ue(k) = 0.0_dp
        if (j > 0) ue(k) = u(j)
      end do
      fe(1:ndof) = 0.0_dp
      any_c = .false.
      if (mv%linear .and. sys%extended .and. .not. tangent) then
        call linear_element_q(sys, e, mv%im, ue, esumq, uq)
        cycle
      end if
      if (tangent) ke(1:ndof, 1:ndof) = 0.0_dp
      if (mv%large) then
        une(1:ndof) = 0.0_dp
        if (present(un)) then
          do k = 1, ndof
            j = sys%elems%edof(e0 + k - 1)
            if (j > 0) une(k) = un(j)
          end do
        end if
        if (mv%per_length .or. nstr == 1) then
          call large_axial_element(scn, sys, mv, e, g0, ng, ue, une, correct, tangent, fe, fc, ke, any_c, wsum, dsum)
        else
          call large_plane_element(sys, mv, e, g0, ng, ndof, ue, une, correct, tangent, fe, fc, ke, any_c, wsum)
        end if
      else if (mv%linear .and. (nstr == 4 .or. nstr == 2 .or. nstr == 1)) then
        call linear_element(sys, g0, ng, ndof, nstr, mv%im, ue, tangent, fe, ke, esum)
      else
        call nonlinear_element(scn, sys, mv, g0, ng, ndof, nstr, ue, correct, tangent, fe, fc, ke, any_c, wsum, dsum, &
          esum)
      end if
      associate (dofs => sys%elems%edof(e0:e0 + ndof - 1))
        do k = 1, ndof
          j = dofs(k)
          if (j <= 0) cycle
          if (sys%extended) then
            sys%fint_q(j) = sys%fint_q(j) + real(fe(k), qp)
          else
            fint(j) = fint(j) + fe(k)
          end if
          if (any_c) fcorr(j) = fcorr(j) + fc(k)
        end do
        if (tangent) call sys%ops%pat%add_element(sys%ops%tval, dofs, ke(1:ndof, 1:ndof))
      end associate
      ! Support reactions (PROBE … RX|RY|MZ) take the correction force of eq (9) on their rows.
      if (any_c .and. sys%react%nslot > 0) call sys%react%add_correction(e, fc)
    end do
    if (sys%extended) then
      fint = real(sys%fint_q, dp)
      esum = real(esumq + real(esum, qp), dp)
    end if
    inc = work_increment_t(wsum, esum, dsum)
  end subroutine internal_force

  subroutine view_model(scn, sys, im, mv)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    integer, intent(in) :: im
    type(model_view_t), intent(out) :: mv
    mv%im = im
    mv%linear = sys%elems%model_linear(im)
    mv%nsub = scn%models(im)%substeps
    mv%large = scn%models(im)%large
    mv%per_length = scn%models(im)%etype == ET_BAR2
    mv%mat = scn%models(im)%material
    mv%nq = 0
    if (mv%mat > 0) mv%nq = law_nstate(scn%materials(mv%mat), sys%elems%pk(im), scn%models(im)%sec)
  end subroutine view_model

  !> Linear elastic points of one element: fixed-size kernels over the element's points (B,
  !> w, eps_t and sig_t of consecutive points are contiguous; passed by sequence association,
  !> no copies), and B'DB w into ke with the tangent.
  subroutine linear_element(sys, g0, ng, ndof, nstr, im, ue, tangent, fe, ke, esum)
    type(system_t), intent(inout) :: sys
    integer, intent(in) :: g0, ng, ndof, nstr, im
    real(dp), intent(in) :: ue(:)
    logical, intent(in) :: tangent
    real(dp), intent(inout) :: fe(:), ke(:, :), esum
    integer :: p, igp
    p = sys%elems%b_ptr(g0)
    select case (nstr)
    case (4)
      call linear_points_4(ndof, ng, sys%elems%bmat(p), sys%elems%wt(g0), ue, sys%elems%dmat(1, 1, im), &
        sys%pts%eps_t(1, g0), sys%pts%sig_t(1, g0), fe, esum)
    case (2)
      call linear_points_2(ndof, ng, sys%elems%bmat(p), sys%elems%wt(g0), ue, sys%elems%dmat(1, 1, im), &
        sys%pts%eps_t(1, g0), sys%pts%sig_t(1, g0), fe, esum)
    case default
      call linear_points_1(ndof, ng, sys%elems%bmat(p), sys%elems%wt(g0), ue, sys%elems%dmat(1, 1, im), &
        sys%pts%eps_t(1, g0), sys%pts%sig_t(1, g0), fe, esum)
    end select
    if (tangent) then
      do igp = g0, g0 + ng - 1
        call add_btdb(nstr, ndof, sys%elems%bmat(sys%elems%b_ptr(igp)), sys%elems%dmat(1, 1, im), sys%elems%wt(igp), ke)
      end do
    end if
  end subroutine linear_element

  !> Linear elastic points of element e in quadruple precision (PRECISION EXTENDED): strains of
  !> smooth fields and the nodal balance of element forces cancel heavily; rounding them in
  !> double injects energy (docs/precision.md). Explicit loops (software quad arithmetic: every
  !> operation counts); the products by B are exact in quad (double x double), only the sums
  !> round, at 1e-34. The element forces go to sys%fint_q, its strain energy to esumq.
  subroutine linear_element_q(sys, e, im, ue, esumq, uq)
    type(system_t), intent(inout) :: sys
    integer, intent(in) :: e, im
    real(dp), intent(in) :: ue(:)
    real(qp), intent(inout) :: esumq
    real(qp), intent(in), optional :: uq(:)
    real(qp) :: ueq(MAX_EDOF), feq(MAX_EDOF), epsq(MAX_NSTRAIN), sigq(MAX_NSTRAIN), dq(MAX_NSTRAIN, MAX_NSTRAIN), wq
    integer :: e0, g0, ng, ndof, nstr, k, j, a, b2, igp, p
    g0 = sys%elems%gp_ptr(e)
    ng = sys%elems%gp_ptr(e + 1) - g0
    e0 = sys%elems%edof_ptr(e)
    ndof = sys%elems%edof_ptr(e + 1) - e0
    nstr = (sys%elems%b_ptr(g0 + 1) - sys%elems%b_ptr(g0)) / ndof
    if (present(uq)) then
      do k = 1, ndof
        j = sys%elems%edof(e0 + k - 1)
        ueq(k) = 0.0_qp
        if (j > 0) ueq(k) = uq(j)
      end do
    else
      ueq(1:ndof) = real(ue(1:ndof), qp)
    end if
    feq(1:ndof) = 0.0_qp
    do a = 1, nstr
      do b2 = 1, nstr
        dq(a, b2) = real(sys%elems%dmat(a, b2, im), qp)
      end do
    end do
    do igp = g0, g0 + ng - 1
      p = sys%elems%b_ptr(igp) - 1
      wq = real(sys%elems%wt(igp), qp)
      epsq(1:nstr) = 0.0_qp
      do k = 1, ndof
        if (ueq(k) == 0.0_qp) cycle
        do a = 1, nstr
          if (sys%elems%bmat(p + (k - 1) * nstr + a) /= 0.0_dp) &
            epsq(a) = epsq(a) + real(sys%elems%bmat(p + (k - 1) * nstr + a), qp) * ueq(k)
        end do
      end do
      do a = 1, nstr
        sigq(a) = 0.0_qp
        do b2 = 1, nstr
          if (dq(a, b2) /= 0.0_qp) sigq(a) = sigq(a) + dq(a, b2) * epsq(b2)
        end do
      end do
      do k = 1, ndof
        do a = 1, nstr
          if (sys%elems%bmat(p + (k - 1) * nstr + a) /= 0.0_dp) &
            feq(k) = feq(k) + wq * (real(sys%elems%bmat(p + (k - 1) * nstr + a), qp) * sigq(a))
        end do
      end do
      esumq = esumq + 0.5_qp * wq * sum(sigq(1:nstr) * epsq(1:nstr))
      sys%pts%eps_t(1:nstr, igp) = real(epsq(1:nstr), dp)
      sys%pts%sig_t(1:nstr, igp) = real(sigq(1:nstr), dp)
    end do
    do k = 1, ndof
      j = sys%elems%edof(e0 + k - 1)
      if (j > 0) sys%fint_q(j) = sys%fint_q(j) + feq(k)
    end do
  end subroutine linear_element_q

  !> The points of one element through their law (material_law's law_update: sub-incremented
  !> along the step), the element forces fe, with correct the correction forces fc of eq (9)
  !> (any_c: some point was sub-incremented), the tangent into ke, the works of the increment.
  subroutine nonlinear_element(scn, sys, mv, g0, ng, ndof, nstr, ue, correct, tangent, fe, fc, ke, any_c, wsum, dsum, &
                               esum)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(model_view_t), intent(in) :: mv
    integer, intent(in) :: g0, ng, ndof, nstr
    real(dp), intent(in) :: ue(:)
    logical, intent(in) :: correct, tangent
    real(dp), intent(inout) :: fe(:), fc(:), ke(:, :), wsum, dsum, esum
    logical, intent(inout) :: any_c
    real(dp) :: deps(MAX_NSTRAIN), sc(MAX_NSTRAIN), w
    type(law_step_t) :: r
    integer :: igp, p
    fc(1:ndof) = 0.0_dp
    do igp = g0, g0 + ng - 1
      p = sys%elems%b_ptr(igp)
      w = sys%elems%wt(igp)
      ! eps = B ue (B stored column-major, nstr x ndof)
      call b_times(nstr, ndof, sys%elems%bmat(p), ue, sys%pts%eps_t(1, igp))
      deps(1:nstr) = sys%pts%eps_t(1:nstr, igp) - sys%pts%eps(1:nstr, igp)
      call point_update(scn, sys, mv, igp, sys%pts%eps(1:nstr, igp), deps(1:nstr), r)
      sys%pts%sig_t(1:nstr, igp) = r%sig(1:nstr)
      if (tangent) call add_btdb(nstr, ndof, sys%elems%bmat(p), r%dtan, w, ke)
      if (mv%linear) then
        esum = esum + 0.5_dp * w * dot_product(sys%pts%sig_t(1:nstr, igp), sys%pts%eps_t(1:nstr, igp))
      else
        wsum = wsum + w * r%work
        dsum = dsum + w * r%dissip
      end if
      call add_btsig(nstr, ndof, sys%elems%bmat(p), sys%pts%sig_t(1, igp), w, fe)
      ! Eq (9): the correction stress, only where the law was sub-incremented.
      if (r%nused > 0 .and. correct) then
        any_c = .true.
        call correction_stress(r%sigbar(1:nstr), sys%pts%sig(1:nstr, igp), sys%pts%sig_t(1:nstr, igp), sc(1:nstr))
        call add_btsig(nstr, ndof, sys%elems%bmat(p), sc, w, fc)
      end if
    end do

  end subroutine nonlinear_element

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
    integer :: igp, p, a, b
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
    epsn = stretch(une(3:4) - une(1:2), ln) / s
    eps1 = stretch(ue(3:4) - ue(1:2), l1) / s
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
        do a = 0, 1
          do b = 0, 1
            ke(2 * a + 1:2 * a + 2, 2 * b + 1:2 * b + 2) = ke(2 * a + 1:2 * a + 2, 2 * b + 1:2 * b + 2) + &
              merge(1.0_dp, -1.0_dp, a == b) * gmat
          end do
        end do
      end if
    end do
  contains
    pure real(dp) function stretch(du, l)
      real(dp), intent(in) :: du(2), l
      stretch = (2.0_dp * dot_product(x0, du) + dot_product(du, du)) / (l + len0)
    end function stretch
    pure function outer2(x, y) result(m)
      real(dp), intent(in) :: x(2), y(2)
      real(dp) :: m(2, 2)
      m = spread(x, 2, 2) * spread(y, 1, 2)
    end function outer2
  end subroutine large_axial_element

  !> KINEMATICS LARGE, QUAD4/QUAD8/TRI3/TRI6 with the ELASTIC law: total Lagrangian, St Venant-
  !> Kirchhoff (docs/large-displacements.md). At each point F = I + Σ u_a ⊗ ∇N_a (∇N from the
  !> reference B, bref), the Green-Lagrange strain E = ½(F'F - I) (as xx, yy, zz = 0, 2xy) and the
  !> second Piola-Kirchhoff stress S = D E. Bσ(n+1) = w B_NL(F(n+1))' S(n+1), B_NL(F) the
  !> derivative of E. E is quadratic in u, so B_NL(F_mid) Δu = ΔE exactly (F_mid = (F(n) + F(n+1))/2),
  !> and with S̄ = D (E(n) + E(n+1))/2 the step force f̄ = w B_NL(F_mid)' S̄ does the work
  !> S̄ ΔE = Δψ exactly (Simo and Tarnow's energy-momentum step for this material): Bσc of eq (9)
  !> is 2 f̄ - f(n) - f(n+1). The tangent: w B_NL' D B_NL + the geometric part with the tensile
  !> part of S (positive definite however far an iterate goes). bmat keeps B_NL(F(n+1)) for the
  !> support reactions; the points report E and S.
  subroutine large_plane_element(sys, mv, e, g0, ng, ndof, ue, une, correct, tangent, fe, fc, ke, any_c, wsum)
    type(system_t), intent(inout) :: sys
    type(model_view_t), intent(in) :: mv
    integer, intent(in) :: e, g0, ng, ndof
    real(dp), intent(in) :: ue(:), une(:)
    logical, intent(in) :: correct, tangent
    real(dp), intent(inout) :: fe(:), fc(:), ke(:, :), wsum
    logical, intent(inout) :: any_c
    real(dp), parameter :: eye(2, 2) = reshape([1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [2, 2])
    real(dp) :: dn(2, MAX_EDOF / 2), fn(2, 2), f1(2, 2), fm(2, 2), hn(2, 2), h1(2, 2), en(4), e1(4), s1(4), sn(4), sbar(4), &
      bn(4, MAX_EDOF), b1(4, MAX_EDOF), bm(4, MAX_EDOF), w, st(2, 2), g
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
      sn = sys%pts%sig(1:4, igp)
      s1 = matmul(sys%elems%dmat(1:4, 1:4, mv%im), e1)
      sys%pts%eps_t(1:4, igp) = e1
      sys%pts%sig_t(1:4, igp) = s1
      call bnl(f1, b1)
      call bnl(fn, bn)
      call bnl(fm, bm)
      sys%elems%bmat(p:p + 4 * ndof - 1) = reshape(b1(:, 1:ndof), [4 * ndof])
      fe(1:ndof) = fe(1:ndof) + w * matmul(s1, b1(:, 1:ndof))
      sbar = 0.5_dp * (sn + s1)
      wsum = wsum + w * dot_product(sbar, e1 - en)
      if (correct) then
        any_c = .true.
        fc(1:ndof) = fc(1:ndof) + w * (2.0_dp * matmul(sbar, bm(:, 1:ndof)) - matmul(sn, bn(:, 1:ndof)) - &
          matmul(s1, b1(:, 1:ndof)))
      end if
      if (tangent) then
        ke(1:ndof, 1:ndof) = ke(1:ndof, 1:ndof) + w * matmul(transpose(b1(:, 1:ndof)), &
          matmul(sys%elems%dmat(1:4, 1:4, mv%im), b1(:, 1:ndof)))
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

  !> One point through its law (material_law's law_update, sub-incremented along the step from
  !> the committed state eps_n with the increment deps). SUBSTEPS AUTO (nsub <= 0): the count may
  !> only grow during the iterations of a step; a count that changes back and forth makes the
  !> residual of eq (9) jump and cycle. So a point that asks for fewer sub-increments than before
  !> in this step is redone with them.
  subroutine point_update(scn, sys, mv, igp, eps_n, deps, r)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(model_view_t), intent(in) :: mv
    integer, intent(in) :: igp
    real(dp), intent(in) :: eps_n(:), deps(:)
    type(law_step_t), intent(out) :: r
    integer :: n, pass, nstr
    nstr = size(deps)
    n = mv%nsub
    do pass = 1, 2
      call law_update(scn%materials(mv%mat), scn%models(mv%im)%sec, sys%elems%pk(mv%im), &
        sys%elems%dmat(1:nstr, 1:nstr, mv%im), n, eps_n, deps, sys%pts%sig(1:nstr, igp), &
        sys%pts%q(1:mv%nq, igp), sys%pts%q_t(1:mv%nq, igp), r)
      if (mv%nsub > 0 .or. pass == 2) exit
      if (r%nused >= sys%pts%nsub_pt(igp)) then
        sys%pts%nsub_pt(igp) = r%nused
        exit
      end if
      n = sys%pts%nsub_pt(igp)
    end do
  end subroutine point_update

  !> Linear elastic QUAD points of one element: eps = B ue, sigma = D eps, fe += w B'sigma,
  !> esum += w sigma.eps / 2. b: the ng consecutive B (4 x ndof); eps, sig: trial state columns.
  pure subroutine linear_points_4(ndof, ng, b, w, ue, d, eps, sig, fe, esum)
    integer, intent(in) :: ndof, ng
    real(dp), intent(in) :: b(4, ndof, ng), w(ng), ue(ndof), d(MAX_NSTRAIN, MAX_NSTRAIN)
    real(dp), intent(inout) :: eps(MAX_NSTRAIN, ng), sig(MAX_NSTRAIN, ng), fe(ndof), esum
    integer :: ig, k
    real(dp) :: e1, e2, e3, e4, s1, s2, s3, s4
    do ig = 1, ng
      e1 = 0.0_dp
      e2 = 0.0_dp
      e3 = 0.0_dp
      e4 = 0.0_dp
      do k = 1, ndof
        e1 = e1 + b(1, k, ig) * ue(k)
        e2 = e2 + b(2, k, ig) * ue(k)
        e3 = e3 + b(3, k, ig) * ue(k)
        e4 = e4 + b(4, k, ig) * ue(k)
      end do
      s1 = d(1, 1) * e1 + d(1, 2) * e2 + d(1, 3) * e3 + d(1, 4) * e4
      s2 = d(2, 1) * e1 + d(2, 2) * e2 + d(2, 3) * e3 + d(2, 4) * e4
      s3 = d(3, 1) * e1 + d(3, 2) * e2 + d(3, 3) * e3 + d(3, 4) * e4
      s4 = d(4, 1) * e1 + d(4, 2) * e2 + d(4, 3) * e3 + d(4, 4) * e4
      eps(1, ig) = e1
      eps(2, ig) = e2
      eps(3, ig) = e3
      eps(4, ig) = e4
      sig(1, ig) = s1
      sig(2, ig) = s2
      sig(3, ig) = s3
      sig(4, ig) = s4
      esum = esum + 0.5_dp * w(ig) * (s1 * e1 + s2 * e2 + s3 * e3 + s4 * e4)
      s1 = w(ig) * s1
      s2 = w(ig) * s2
      s3 = w(ig) * s3
      s4 = w(ig) * s4
      do k = 1, ndof
        fe(k) = fe(k) + (b(1, k, ig) * s1 + b(2, k, ig) * s2 + b(3, k, ig) * s3 + b(4, k, ig) * s4)
      end do
    end do
  end subroutine linear_points_4

  !> linear_points_4 for beams (axial strain, curvature).
  pure subroutine linear_points_2(ndof, ng, b, w, ue, d, eps, sig, fe, esum)
    integer, intent(in) :: ndof, ng
    real(dp), intent(in) :: b(2, ndof, ng), w(ng), ue(ndof), d(MAX_NSTRAIN, MAX_NSTRAIN)
    real(dp), intent(inout) :: eps(MAX_NSTRAIN, ng), sig(MAX_NSTRAIN, ng), fe(ndof), esum
    integer :: ig, k
    real(dp) :: e1, e2, s1, s2
    do ig = 1, ng
      e1 = 0.0_dp
      e2 = 0.0_dp
      do k = 1, ndof
        e1 = e1 + b(1, k, ig) * ue(k)
        e2 = e2 + b(2, k, ig) * ue(k)
      end do
      s1 = d(1, 1) * e1 + d(1, 2) * e2
      s2 = d(2, 1) * e1 + d(2, 2) * e2
      eps(1, ig) = e1
      eps(2, ig) = e2
      sig(1, ig) = s1
      sig(2, ig) = s2
      esum = esum + 0.5_dp * w(ig) * (s1 * e1 + s2 * e2)
      s1 = w(ig) * s1
      s2 = w(ig) * s2
      do k = 1, ndof
        fe(k) = fe(k) + (b(1, k, ig) * s1 + b(2, k, ig) * s2)
      end do
    end do
  end subroutine linear_points_2

  !> linear_points_4 for springs and bars (one strain component).
  pure subroutine linear_points_1(ndof, ng, b, w, ue, d, eps, sig, fe, esum)
    integer, intent(in) :: ndof, ng
    real(dp), intent(in) :: b(ndof, ng), w(ng), ue(ndof), d(MAX_NSTRAIN, MAX_NSTRAIN)
    real(dp), intent(inout) :: eps(MAX_NSTRAIN, ng), sig(MAX_NSTRAIN, ng), fe(ndof), esum
    integer :: ig, k
    real(dp) :: e1, s1
    do ig = 1, ng
      e1 = 0.0_dp
      do k = 1, ndof
        e1 = e1 + b(k, ig) * ue(k)
      end do
      s1 = d(1, 1) * e1
      eps(1, ig) = e1
      sig(1, ig) = s1
      esum = esum + 0.5_dp * w(ig) * (s1 * e1)
      s1 = w(ig) * s1
      do k = 1, ndof
        fe(k) = fe(k) + b(k, ig) * s1
      end do
    end do
  end subroutine linear_points_1

  !> eps(1:nstr) = B ue, B nstr x ndof.
  pure subroutine b_times(nstr, ndof, b, ue, eps)
    integer, intent(in) :: nstr, ndof
    real(dp), intent(in) :: b(nstr, ndof), ue(ndof)
    real(dp), intent(out) :: eps(nstr)
    integer :: k
    eps = 0.0_dp
    do k = 1, ndof
      eps = eps + b(:, k) * ue(k)
    end do
  end subroutine b_times

  !> fe += w B's, B nstr x ndof.
  pure subroutine add_btsig(nstr, ndof, b, s, w, fe)
    integer, intent(in) :: nstr, ndof
    real(dp), intent(in) :: b(nstr, ndof), s(nstr), w
    real(dp), intent(inout) :: fe(ndof)
    integer :: k
    do k = 1, ndof
      fe(k) = fe(k) + w * dot_product(b(:, k), s)
    end do
  end subroutine add_btsig

  !> ke(1:ndof, 1:ndof) += w B' D B, B nstr x ndof, D the leading nstr x nstr block of d.
  pure subroutine add_btdb(nstr, ndof, b, d, w, ke)
    integer, intent(in) :: nstr, ndof
    real(dp), intent(in) :: b(nstr, ndof), d(MAX_NSTRAIN, MAX_NSTRAIN), w
    real(dp), intent(inout) :: ke(MAX_EDOF, MAX_EDOF)
    real(dp) :: db(MAX_NSTRAIN, MAX_EDOF)
    integer :: k, m
    do k = 1, ndof
      db(1:nstr, k) = matmul(d(1:nstr, 1:nstr), b(:, k))
    end do
    do k = 1, ndof
      do m = 1, ndof
        ke(m, k) = ke(m, k) + w * dot_product(b(:, m), db(1:nstr, k))
      end do
    end do
  end subroutine add_btdb
end module internal_forces
