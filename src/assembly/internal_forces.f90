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
  use material_law, only: law_step_t
  use element_points, only: model_view_t, view_model, point_update
  use element_table, only: element_table_t, add_btdb, add_anti
  use large_kinematics, only: large_axial_element, large_beam_element
  use large_plane, only: large_plane_element
  use large_solid, only: large_solid_element
  use small_matrix, only: sym_part
  use subincrement, only: correction_stress
  implicit none
  private
  public :: internal_force, work_increment_t, refresh_points, check_k0_product, linear_strain_energy

  !> The energies of a trial increment.
  type :: work_increment_t
    real(dp) :: work = 0.0_dp        !< W_N = Σ w σ̄·Δε at the nonlinear points (sub-incremented work)
    real(dp) :: elastic = 0.0_dp     !< strain energy ½ σ·ε of the trial state at the linear elastic points
    real(dp) :: dissipated = 0.0_dp  !< plastic work of the increment
  end type work_increment_t

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
  !> the path from the reference configuration). elist: only these elements (the nonlinear zone's
  !> iterates): fint, fcorr and the tangent are then added to, their rows zeroed by the caller,
  !> and the support reactions' correction is left to the next whole evaluation.
  subroutine internal_force(scn, sys, u, fint, fcorr, correct, tangent, inc, uq, un, elist)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    real(dp), intent(in) :: u(:)
    real(dp), intent(out) :: fint(:), fcorr(:)
    logical, intent(in) :: correct, tangent
    type(work_increment_t), intent(out) :: inc
    real(qp), intent(in), optional :: uq(:)
    real(dp), intent(in), optional :: un(:)
    integer, intent(in), optional :: elist(:)
    type(model_view_t) :: mv
    integer :: e, ndof, nstr, ng, g0, k, j, e0, ie, nel
    real(dp) :: ue(MAX_EDOF), une(MAX_EDOF), fe(MAX_EDOF), fc(MAX_EDOF), ke(MAX_EDOF, MAX_EDOF), kg(MAX_EDOF, MAX_EDOF), &
      ka(MAX_EDOF, MAX_EDOF), wsum, dsum, esum
    real(qp) :: esumq
    logical :: any_c, keeps_a
    if (sys%ops%k0u%active() .and. .not. (tangent .or. present(elist) .or. sys%extended)) then
      ! A linear elastic small-strain model: Bσ(u) = K0 u (stiffness_product), σc = 0 (no law is
      ! sub-incremented); the points are evaluated where they are read (refresh_points).
      call sys%ops%k0u%apply(sys%ops%pat, sys%ops%kval, u, fint, esum)
      fcorr = 0.0_dp
      if (sys%react%nslot > 0) sys%react%fc_t = 0.0_dp
      sys%elems%inverted = 0
      sys%elems%round_floor = 0.0_dp
      sys%pts%trial_current = .false.
      inc = work_increment_t(0.0_dp, esum, 0.0_dp)
      return
    end if
    esumq = 0.0_qp
    wsum = 0.0_dp
    esum = 0.0_dp
    dsum = 0.0_dp
    nel = scn%mesh%nelem
    if (present(elist)) then
      nel = size(elist)
    else
      sys%pts%trial_current = .true.
      fint = 0.0_dp
      if (sys%extended) sys%fint_q = 0.0_qp
      fcorr = 0.0_dp
      if (tangent) sys%ops%tval = 0.0_dp
      if (tangent .and. allocated(sys%ops%gval)) sys%ops%gval = 0.0_dp
      if (tangent .and. allocated(sys%ops%aval)) sys%ops%aval = 0.0_dp
      if (sys%react%nslot > 0) sys%react%fc_t = 0.0_dp
    end if
    sys%elems%inverted = 0
    sys%elems%round_floor = 0.0_dp
    do ie = 1, nel
      e = ie
      if (present(elist)) e = elist(ie)
      if (scn%elem_model(e) == 0) cycle
      g0 = sys%elems%gp_ptr(e)
      ng = sys%elems%gp_ptr(e + 1) - g0
      if (ng == 0) cycle
      e0 = sys%elems%edof_ptr(e)
      nstr = sys%elems%nstr(e)
      ! Per-model data, looked up once per run of elements of the same model.
      if (scn%elem_model(e) /= mv%im) call view_model(scn, sys, scn%elem_model(e), mv)
      call gather(sys%elems, e, u, ue, ndof)
      fe(1:ndof) = 0.0_dp
      any_c = .false.
      if (mv%linear .and. sys%extended .and. .not. tangent) then
        call linear_element_q(sys, e, mv%im, ue, esumq, uq)
        cycle
      end if
      if (tangent) ke(1:ndof, 1:ndof) = 0.0_dp
      if (tangent) ka(1:ndof, 1:ndof) = 0.0_dp
      keeps_a = .false.                     ! (a kernel that forms ka: the antisymmetric part of eq (9)'s Jacobian)
      if (mv%large) then
        une(1:ndof) = 0.0_dp
        if (present(un)) then
          do k = 1, ndof
            j = sys%elems%edof(e0 + k - 1)
            if (j > 0) une(k) = un(j)
          end do
        end if
        if (mv%beam) then
          call large_beam_element(scn, sys, mv, e, g0, ng, ue, une, present(un), correct, tangent, fe, fc, ke, any_c, &
            wsum, dsum)
        else if (mv%per_length .or. nstr == 1) then
          call large_axial_element(scn, sys, mv, e, g0, ng, ue, une, correct, tangent, fe, fc, ke, any_c, wsum, dsum)
        else
          if (tangent) kg(1:ndof, 1:ndof) = 0.0_dp
          keeps_a = .true.
          if (nstr == 6) then
            call large_solid_element(scn, sys, mv, e, g0, ng, ndof, ue, une, correct, tangent, fe, fc, ke, kg, ka, &
              any_c, wsum, dsum)
          else
            call large_plane_element(scn, sys, mv, e, g0, ng, ndof, ue, une, correct, tangent, fe, fc, ke, kg, ka, &
              any_c, wsum, dsum)
          end if
          if (tangent .and. allocated(sys%ops%gval)) call sys%ops%pat%add_element(sys%ops%gval, &
            sys%elems%edof(e0:e0 + ndof - 1), kg(1:ndof, 1:ndof))
        end if
      else if (mv%linear .and. (nstr == 4 .or. nstr == 2 .or. nstr == 1 .or. nstr == 6)) then
        call linear_element(sys%elems, sys%pts%eps_t, sys%pts%sig_t, g0, ng, ndof, nstr, mv%im, ue, tangent, fe, ke, esum)
      else
        keeps_a = .true.
        call nonlinear_element(scn, sys, mv, g0, ng, ndof, nstr, ue, correct, tangent, fe, fc, ke, ka, any_c, wsum, &
          dsum, esum)
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
        if (keeps_a .and. tangent .and. correct .and. allocated(sys%ops%aval)) &
          call sys%ops%pat%add_element(sys%ops%aval, dofs, ka(1:ndof, 1:ndof))
      end associate
      ! Support reactions (PROBE … RX|RY|MZ) take the correction force of eq (9) on their rows.
      if (any_c .and. sys%react%nslot > 0 .and. .not. present(elist)) call sys%react%add_correction(e, fc)
    end do
    sys%elems%round_floor = sqrt(sys%elems%round_floor)
    if (sys%extended) then
      fint = real(sys%fint_q, dp)
      esum = real(esumq + real(esum, qp), dp)
    end if
    inc = work_increment_t(wsum, esum, dsum)
  end subroutine internal_force

  !> The committed points of the linear elastic elements from the committed u, where the steps
  !> took Bσ = K0 u and left them unevaluated (sys%pts%current false): every element (fields,
  !> checkpoints), or with supports only those of the support reactions (reaction_update reads
  !> their stresses; the others stay as they were).
  subroutine refresh_points(scn, sys, u, supports)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    real(dp), intent(in) :: u(:)
    logical, intent(in) :: supports
    real(dp) :: ue(MAX_EDOF), fe(MAX_EDOF), ke(1, 1), esum
    integer :: e, g0, ng, ndof
    if (sys%pts%current) return
    if (supports .and. sys%react%nslot == 0) return
    esum = 0.0_dp
    do e = 1, scn%mesh%nelem
      if (supports) then
        if (sys%react%ent_ptr(e + 1) == sys%react%ent_ptr(e)) cycle
      end if
      if (scn%elem_model(e) == 0) cycle
      if (.not. sys%elems%model_linear(scn%elem_model(e))) cycle   ! (their points are always evaluated)
      g0 = sys%elems%gp_ptr(e)
      ng = sys%elems%gp_ptr(e + 1) - g0
      if (ng == 0) cycle
      call gather(sys%elems, e, u, ue, ndof)
      fe(1:ndof) = 0.0_dp
      call linear_element(sys%elems, sys%pts%eps, sys%pts%sig, g0, ng, ndof, sys%elems%nstr(e), scn%elem_model(e), &
        ue, .false., fe, ke, esum)
    end do
    if (.not. supports) sys%pts%current = .true.
  end subroutine refresh_points

  !> ue(1:ndof) = the displacements of element e's DOFs (0 on the fixed ones).
  pure subroutine gather(elems, e, u, ue, ndof)
    type(element_table_t), intent(in) :: elems
    integer, intent(in) :: e
    real(dp), intent(in) :: u(:)
    real(dp), intent(out) :: ue(:)
    integer, intent(out) :: ndof
    integer :: e0, k, j
    e0 = elems%edof_ptr(e)
    ndof = elems%edof_ptr(e + 1) - e0
    do k = 1, ndof
      j = elems%edof(e0 + k - 1)
      ue(k) = 0.0_dp
      if (j > 0) ue(k) = u(j)
    end do
  end subroutine gather

  !> The strain energy ½ Σ w σ·ε of the linear elastic points at u, σ = D B u, as the element loop
  !> sums it (the same operations in the same order: the same value bit for bit), without the
  !> element forces: what a history line reports where Bσ = K0 u (½ u·K0 u would round at eps x
  !> the condition of K0). Surface elements from their gradients; the others through their
  !> element kernel, the trial points as scratch (the steps do not read them: sys%pts%trial_current).
  subroutine linear_strain_energy(scn, sys, u, esum)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    real(dp), intent(in) :: u(:)
    real(dp), intent(out) :: esum
    real(dp) :: ue(MAX_EDOF), fe(MAX_EDOF), ke(1, 1)
    integer :: e, g0, ng, ndof, im
    esum = 0.0_dp
    do e = 1, scn%mesh%nelem
      im = scn%elem_model(e)
      if (im == 0) cycle
      if (.not. sys%elems%model_linear(im)) cycle
      g0 = sys%elems%gp_ptr(e)
      ng = sys%elems%gp_ptr(e + 1) - g0
      if (ng == 0) cycle
      call gather(sys%elems, e, u, ue, ndof)
      if (sys%elems%nstr(e) == 4 .and. sys%elems%gr_ptr(g0) > 0) then
        call energy_points_plane(ndof / 2, ng, sys%elems%grad(sys%elems%gr_ptr(g0)), sys%elems%wt(g0), ue, &
          sys%elems%dmat(1, 1, im), esum)
      else
        fe(1:ndof) = 0.0_dp
        call linear_element(sys%elems, sys%pts%eps_t, sys%pts%sig_t, g0, ng, ndof, sys%elems%nstr(e), im, ue, .false., &
          fe, ke, esum)
      end if
    end do
  end subroutine linear_strain_energy

  !> linear_points_plane's strain energy alone: the same strains and stresses, no element force.
  pure subroutine energy_points_plane(nen, ng, g, w, ue, d, esum)
    integer, intent(in) :: nen, ng
    real(dp), intent(in) :: g(2, nen, ng), w(ng), ue(2, nen), d(MAX_NSTRAIN, MAX_NSTRAIN)
    real(dp), intent(inout) :: esum
    integer :: ig
    real(dp) :: e1, e2, e3, e4, s1, s2, s3, s4
    e3 = 0.0_dp
    do ig = 1, ng
      call plane_strains(nen, g(1, 1, ig), ue, e1, e2, e4)
      call stress_4(d, e1, e2, e3, e4, s1, s2, s3, s4)
      esum = esum + 0.5_dp * w(ig) * (s1 * e1 + s2 * e2 + s3 * e3 + s4 * e4)
    end do
  end subroutine energy_points_plane

  !> Before the first step: keep Bσ = K0 u (stiffness_product) only if it reproduces the element
  !> loop on a rough test displacement (strain at every scale, on every equation): forces and
  !> strain energy to a relative 1e-10, where both round at 1e-15. Any model the product would not
  !> represent goes back to the loop instead of giving other forces. The points are left as the
  !> loop wrote them; the caller's initial state overwrites them.
  subroutine check_k0_product(scn, sys, fint, fk)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    real(dp), intent(inout) :: fint(:), fk(:)   !< workspace (neq)
    real(dp), allocatable :: u(:), fc(:)
    type(work_increment_t) :: inc
    real(dp) :: e_loop, e_prod
    integer :: i
    if (.not. sys%ops%k0u%active()) return
    allocate (u(size(fint)), fc(size(fint)))
    do i = 1, size(u)
      u(i) = 1.0e-3_dp * sin(0.7_dp * i) + 1.0e-6_dp * real(mod(7 * i, 13), dp)
    end do
    call internal_force(scn, sys, u, fk, fc, .false., .false., inc)
    e_prod = inc%elastic
    call sys%ops%k0u%disable()
    call internal_force(scn, sys, u, fint, fc, .false., .false., inc)
    e_loop = inc%elastic
    if (norm2(fk - fint) <= 1.0e-10_dp * norm2(fint) .and. abs(e_prod - e_loop) <= 1.0e-10_dp * abs(e_loop)) &
      call sys%ops%k0u%enable()
  end subroutine check_k0_product

  !> Linear elastic points of one element: fixed-size kernels over the element's points (B,
  !> w, eps_t and sig_t of consecutive points are contiguous; passed by sequence association,
  !> no copies), and B'DB w into ke with the tangent.
  subroutine linear_element(elems, eps, sig, g0, ng, ndof, nstr, im, ue, tangent, fe, ke, esum)
    type(element_table_t), intent(in) :: elems
    real(dp), intent(inout) :: eps(MAX_NSTRAIN, *), sig(MAX_NSTRAIN, *)   !< the points written (trial or committed)
    integer, intent(in) :: g0, ng, ndof, nstr, im
    real(dp), intent(in) :: ue(:)
    logical, intent(in) :: tangent
    real(dp), intent(inout) :: fe(:), ke(:, :), esum
    real(dp) :: bl(MAX_NSTRAIN * MAX_EDOF)
    integer :: p, igp
    p = elems%b_ptr(g0)
    select case (nstr)
    case (6)                                   ! solids: from their gradients, or their stored B (BBAR)
      if (elems%gr_ptr(g0) > 0) then
        call linear_points_solid(ndof / 3, ng, elems%grad(elems%gr_ptr(g0)), elems%wt(g0), ue, elems%dmat(1, 1, im), &
          eps(1, g0), sig(1, g0), fe, esum)
      else
        do igp = g0, g0 + ng - 1
          call b_times(6, ndof, elems%bmat(p + 6 * ndof * (igp - g0)), ue, eps(1, igp))
          sig(1:6, igp) = matmul(elems%dmat(1:6, 1:6, im), eps(1:6, igp))
          esum = esum + 0.5_dp * elems%wt(igp) * dot_product(sig(1:6, igp), eps(1:6, igp))
          call add_btsig(6, ndof, elems%bmat(p + 6 * ndof * (igp - g0)), sig(1, igp), elems%wt(igp), fe)
        end do
      end if
    case (4)
      if (elems%gr_ptr(g0) > 0) then
        call linear_points_plane(ndof / 2, ng, elems%grad(elems%gr_ptr(g0)), elems%wt(g0), ue, &
          elems%dmat(1, 1, im), eps(1, g0), sig(1, g0), fe, esum)
      else
        call linear_points_4(ndof, ng, elems%bmat(p), elems%wt(g0), ue, elems%dmat(1, 1, im), &
          eps(1, g0), sig(1, g0), fe, esum)
      end if
    case (2)
      call linear_points_2(ndof, ng, elems%bmat(p), elems%wt(g0), ue, elems%dmat(1, 1, im), &
        eps(1, g0), sig(1, g0), fe, esum)
    case default
      call linear_points_1(ndof, ng, elems%bmat(p), elems%wt(g0), ue, elems%dmat(1, 1, im), &
        eps(1, g0), sig(1, g0), fe, esum)
    end select
    if (tangent) then
      do igp = g0, g0 + ng - 1
        call elems%point_b(igp, nstr, ndof, bl)
        call add_btdb(nstr, ndof, bl, elems%dmat(1, 1, im), elems%wt(igp), ke)
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
    real(dp) :: bl(MAX_NSTRAIN * MAX_EDOF)
    integer :: e0, g0, ng, ndof, nstr, k, j, a, b2, igp
    g0 = sys%elems%gp_ptr(e)
    ng = sys%elems%gp_ptr(e + 1) - g0
    e0 = sys%elems%edof_ptr(e)
    ndof = sys%elems%edof_ptr(e + 1) - e0
    nstr = sys%elems%nstr(e)
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
      call sys%elems%point_b(igp, nstr, ndof, bl)
      wq = real(sys%elems%wt(igp), qp)
      epsq(1:nstr) = 0.0_qp
      do k = 1, ndof
        if (ueq(k) == 0.0_qp) cycle
        do a = 1, nstr
          if (bl((k - 1) * nstr + a) /= 0.0_dp) epsq(a) = epsq(a) + real(bl((k - 1) * nstr + a), qp) * ueq(k)
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
          if (bl((k - 1) * nstr + a) /= 0.0_dp) feq(k) = feq(k) + wq * (real(bl((k - 1) * nstr + a), qp) * sigq(a))
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
  subroutine nonlinear_element(scn, sys, mv, g0, ng, ndof, nstr, ue, correct, tangent, fe, fc, ke, ka, any_c, wsum, &
                               dsum, esum)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(model_view_t), intent(in) :: mv
    integer, intent(in) :: g0, ng, ndof, nstr
    real(dp), intent(in) :: ue(:)
    logical, intent(in) :: correct, tangent
    real(dp), intent(inout) :: fe(:), fc(:), ke(:, :), wsum, dsum, esum
    real(dp), intent(inout) :: ka(:, :)   !< with tangent and correct: += B' (the antisymmetric part of dbar) B
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
      if (tangent) then                     ! (with the correction: the tangent of 2Bσ̄ - Bσ(n), law_step_t's dbar)
        if (correct .and. r%has_dbar) then
          ! dbar = d(2σ̄)/dΔε is not symmetric: its symmetric part to ke (CHOLMOD's S), the rest to ka
          ! (iterate_eq9's anti_sweep)
          call add_anti(nstr, ndof, sys%elems%bmat(p), r%dbar, sys%elems%bmat(p), w, ka)
          call sym_part(r%dbar(1:nstr, 1:nstr))
          call add_btdb(nstr, ndof, sys%elems%bmat(p), r%dbar, w, ke)
        else
          call add_btdb(nstr, ndof, sys%elems%bmat(p), r%dtan, w, ke)
        end if
      end if
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
      call elastic_point_4(d, w(ig), e1, e2, e3, e4, eps(1, ig), sig(1, ig), esum, s1, s2, s3, s4)
      do k = 1, ndof
        fe(k) = fe(k) + (b(1, k, ig) * s1 + b(2, k, ig) * s2 + b(3, k, ig) * s3 + b(4, k, ig) * s4)
      end do
    end do
  end subroutine linear_points_4

  !> One linear elastic point with four strain components: sigma = D eps stored with eps, its
  !> strain energy ½ w sigma.eps added to esum, and w sigma returned (s1..s4) for the element force.
  pure subroutine elastic_point_4(d, w, e1, e2, e3, e4, eps, sig, esum, s1, s2, s3, s4)
    real(dp), intent(in) :: d(MAX_NSTRAIN, MAX_NSTRAIN), w, e1, e2, e3, e4
    real(dp), intent(inout) :: eps(4), sig(4), esum
    real(dp), intent(out) :: s1, s2, s3, s4
    call stress_4(d, e1, e2, e3, e4, s1, s2, s3, s4)
    eps(1) = e1
    eps(2) = e2
    eps(3) = e3
    eps(4) = e4
    sig(1) = s1
    sig(2) = s2
    sig(3) = s3
    sig(4) = s4
    esum = esum + 0.5_dp * w * (s1 * e1 + s2 * e2 + s3 * e3 + s4 * e4)
    s1 = w * s1
    s2 = w * s2
    s3 = w * s3
    s4 = w * s4
  end subroutine elastic_point_4

  !> linear_points_4 for the surface elements from their shape-function gradients g (dN_a/dx,
  !> dN_a/dy by node) instead of B, whose other three quarters are zeros (B(1, 2a-1) = B(4, 2a) =
  !> dN_a/dx, B(2, 2a) = B(4, 2a-1) = dN_a/dy, row 3 zero): a quarter of the memory stream. The
  !> same operations on the nonzero terms in the same order (the zero terms of B add exact zeros),
  !> so the same results bit for bit.
  pure subroutine linear_points_plane(nen, ng, g, w, ue, d, eps, sig, fe, esum)
    integer, intent(in) :: nen, ng
    real(dp), intent(in) :: g(2, nen, ng), w(ng), ue(2, nen), d(MAX_NSTRAIN, MAX_NSTRAIN)
    real(dp), intent(inout) :: eps(MAX_NSTRAIN, ng), sig(MAX_NSTRAIN, ng), fe(2, nen), esum
    integer :: ig, a
    real(dp) :: e1, e2, e3, e4, s1, s2, s3, s4
    e3 = 0.0_dp
    do ig = 1, ng
      e1 = 0.0_dp
      e2 = 0.0_dp
      e4 = 0.0_dp
      call plane_strains(nen, g(1, 1, ig), ue, e1, e2, e4)
      call elastic_point_4(d, w(ig), e1, e2, e3, e4, eps(1, ig), sig(1, ig), esum, s1, s2, s3, s4)
      do a = 1, nen
        fe(1, a) = fe(1, a) + (g(1, a, ig) * s1 + g(2, a, ig) * s4)
        fe(2, a) = fe(2, a) + (g(2, a, ig) * s2 + g(1, a, ig) * s4)
      end do
    end do
  end subroutine linear_points_plane

  !> The plane strains of one point from its shape-function gradients g(:, a) and the nodal
  !> displacements: e1 = ε_xx, e2 = ε_yy, e4 = γ_xy (ε_zz = 0), summed node by node.
  pure subroutine plane_strains(nen, g, ue, e1, e2, e4)
    integer, intent(in) :: nen
    real(dp), intent(in) :: g(2, nen), ue(2, nen)
    real(dp), intent(out) :: e1, e2, e4
    integer :: a
    e1 = 0.0_dp
    e2 = 0.0_dp
    e4 = 0.0_dp
    do a = 1, nen
      e1 = e1 + g(1, a) * ue(1, a)
      e2 = e2 + g(2, a) * ue(2, a)
      e4 = e4 + g(2, a) * ue(1, a)
      e4 = e4 + g(1, a) * ue(2, a)
    end do
  end subroutine plane_strains

  !> σ = D ε with four components, row by row.
  pure subroutine stress_4(d, e1, e2, e3, e4, s1, s2, s3, s4)
    real(dp), intent(in) :: d(MAX_NSTRAIN, MAX_NSTRAIN), e1, e2, e3, e4
    real(dp), intent(out) :: s1, s2, s3, s4
    s1 = d(1, 1) * e1 + d(1, 2) * e2 + d(1, 3) * e3 + d(1, 4) * e4
    s2 = d(2, 1) * e1 + d(2, 2) * e2 + d(2, 3) * e3 + d(2, 4) * e4
    s3 = d(3, 1) * e1 + d(3, 2) * e2 + d(3, 3) * e3 + d(3, 4) * e4
    s4 = d(4, 1) * e1 + d(4, 2) * e2 + d(4, 3) * e3 + d(4, 4) * e4
  end subroutine stress_4

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

  !> Linear elastic solid points (HEX8, TET4) from their shape-function gradients g (dN_a/dx, dN_a/dy,
  !> dN_a/dz by node): eps = B ue with B's three entries a column, sigma = D eps, fe += w B'sigma.
  pure subroutine linear_points_solid(nen, ng, g, w, ue, d, eps, sig, fe, esum)
    integer, intent(in) :: nen, ng
    real(dp), intent(in) :: g(3, nen, ng), w(ng), ue(3, nen), d(MAX_NSTRAIN, MAX_NSTRAIN)
    real(dp), intent(inout) :: eps(MAX_NSTRAIN, ng), sig(MAX_NSTRAIN, ng), fe(3, nen), esum
    integer :: ig, a, i
    real(dp) :: e(6), s(6)
    do ig = 1, ng
      e = 0.0_dp
      do a = 1, nen
        e(1) = e(1) + g(1, a, ig) * ue(1, a)
        e(2) = e(2) + g(2, a, ig) * ue(2, a)
        e(3) = e(3) + g(3, a, ig) * ue(3, a)
        e(4) = e(4) + g(2, a, ig) * ue(1, a) + g(1, a, ig) * ue(2, a)
        e(5) = e(5) + g(3, a, ig) * ue(2, a) + g(2, a, ig) * ue(3, a)
        e(6) = e(6) + g(3, a, ig) * ue(1, a) + g(1, a, ig) * ue(3, a)
      end do
      do i = 1, 6
        s(i) = d(i, 1) * e(1) + d(i, 2) * e(2) + d(i, 3) * e(3) + d(i, 4) * e(4) + d(i, 5) * e(5) + d(i, 6) * e(6)
      end do
      eps(1:6, ig) = e
      sig(1:6, ig) = s
      esum = esum + 0.5_dp * w(ig) * dot_product(s, e)
      s = w(ig) * s
      do a = 1, nen
        fe(1, a) = fe(1, a) + (g(1, a, ig) * s(1) + g(2, a, ig) * s(4) + g(3, a, ig) * s(6))
        fe(2, a) = fe(2, a) + (g(1, a, ig) * s(4) + g(2, a, ig) * s(2) + g(3, a, ig) * s(5))
        fe(3, a) = fe(3, a) + (g(1, a, ig) * s(6) + g(2, a, ig) * s(5) + g(3, a, ig) * s(3))
      end do
    end do
  end subroutine linear_points_solid

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
end module internal_forces
