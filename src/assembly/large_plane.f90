!> KINEMATICS LARGE surface elements (QUAD4, QUAD8, TRI3, TRI6; docs/large-displacements.md):
!> total Lagrangian, the strains of the current configuration at each point, the forces Bσ(n+1)
!> and the correction force of eq (9) from a discrete gradient, so that the step's internal work is
!> the laws' exact path work. FORMULATION BBAR (docs/locking.md): the points' strains take the
!> element's mean dilatation, and their forces the element's mean pressure.
module large_plane
  use kinds, only: dp
  use small_matrix, only: sym_part
  use scene, only: scene_t
  use assembly, only: system_t
  use elements, only: MAX_EDOF, MAX_GAUSS
  use material_law, only: law_step_t
  use element_points, only: model_view_t, point_update
  use element_table, only: add_anti
  use law_hyperelastic, only: nh_stress, nh_tangent, nh_discrete_stress
  use log_strain, only: hencky_strain, log_tangent, log_curvature, positive_inplane, positive_all
  implicit none
  private
  public :: large_plane_element

  integer, parameter :: MAX_NEN = MAX_EDOF / 2
  real(dp), parameter :: EYE(2, 2) = reshape([1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [2, 2])
  real(dp), parameter :: I2(4) = [1.0_dp, 1.0_dp, 0.0_dp, 0.0_dp]   !< the in-plane identity (Voigt)
  real(dp), parameter :: I3(4) = [1.0_dp, 1.0_dp, 1.0_dp, 0.0_dp]   !< the identity of the normal strains

  !> One point of the element during a trial: kinematics, the law's strains and stresses.
  type :: plane_pt_t
    real(dp) :: dn(2, MAX_NEN)       !< ∇N (reference)
    real(dp) :: nr(MAX_NEN)          !< AXISYMMETRIC: N_a / R (the reference B's hoop row; 0 otherwise)
    real(dp) :: fn(2, 2), f1(2, 2)   !< F(n), F(n+1) in the plane
    real(dp) :: zn, z1               !< F_θθ = 1 + u_r/R at n and n+1 (1 unless AXISYMMETRIC)
    real(dp) :: b1(4, MAX_EDOF)      !< B_NL(F(n+1)) (dE = B_NL du; columns u_x, u_y of each node)
    real(dp) :: bm(4, MAX_EDOF)      !< B_NL(F_mid), F_mid = ½(F(n) + F(n+1)): the B of the step's force
    real(dp) :: en(4), e1(4)         !< Green-Lagrange strains
    real(dp) :: ln(4), l1(4)         !< the strains the law sees (E, or ℓ; with BBAR ℓ̄)
    real(dp) :: lon(4), lo1(4)       !< the point's own ℓ (the secant of its log map; = ln, l1 without BBAR)
    real(dp) :: pn(4, 4), pl(4, 4)   !< dℓ/dE at n and n+1 (log strain)
    real(dp) :: tn(4), t1(4), tbar(4)  !< stresses on ℓ (with BBAR: the element's mean pressure)
    real(dp) :: dm(4, 4)             !< the law's tangent on ℓ
    real(dp) :: wpt, dpt    !< path work and its dissipated part
    real(dp) :: snoise      !< HYPERELASTIC with BBAR: the noise of its volumetric S̄ (secant_stress)
  end type plane_pt_t

contains

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
  !> FORMULATION BBAR (mean_dilatation): the law sees ℓ̄ = ℓ + ½(<tr ℓ> - tr ℓ) I₂ (tr the in-plane
  !> trace, <> the element's volume mean), which is linear in the points' ℓ: the forces take
  !> T̃ = T + ½(<tr T> - tr T) I₂ at every point (mean_pressure), the step's work Σ w T̄·Δℓ̄ stays
  !> exact through the same secants, and bmat keeps the B of ℓ̄ (the support reactions' Σ w B'T).
  subroutine large_plane_element(scn, sys, mv, e, g0, ng, ndof, ue, une, correct, tangent, fe, fc, ke, kg, ka, any_c, &
                                 wsum, dsum)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(model_view_t), intent(in) :: mv
    integer, intent(in) :: e, g0, ng, ndof
    real(dp), intent(in) :: ue(:), une(:)
    logical, intent(in) :: correct, tangent
    real(dp), intent(inout) :: fe(:), fc(:), ke(:, :), wsum, dsum
    real(dp), intent(inout) :: kg(:, :)   !< with tangent: += the compressive part of the geometric stiffness
    real(dp), intent(inout) :: ka(:, :)   !< with tangent and correct: += the Jacobian's antisymmetric part
    logical, intent(inout) :: any_c
    type(plane_pt_t) :: pt(MAX_GAUSS)
    real(dp) :: mrow(MAX_EDOF), mrow_m(MAX_EDOF), jmean, wtot, gcurv(4, 4)
    integer :: k, ntr
    fc(1:ndof) = 0.0_dp
    jmean = 0.0_dp
    wtot = sum(sys%elems%wt(g0:g0 + ng - 1))
    do k = 1, ng
      call point_kinematics(sys, mv, e, g0 + k - 1, ndof / 2, ue, une, pt(k))
    end do
    ntr = merge(3, 2, mv%axi)             ! the normal strains of the volume change
    if (mv%bbar .and. .not. mv%hyper) call mean_dilatation(sys%elems%wt(g0:g0 + ng - 1), ntr, pt(1:ng))
    do k = 1, ng
      call point_law(scn, sys, mv, g0 + k - 1, tangent, correct, pt(k))
    end do
    if (mv%bbar) then
      if (mv%hyper) then
        call mean_volume(mv%lame(1), sys%elems%wt(g0:g0 + ng - 1), pt(1:ng), jmean)
        do k = 1, ng                ! (a loop, not an array constructor: no temporary)
          sys%pts%sig_t(1:4, g0 + k - 1) = pt(k)%t1
        end do
      else
        call mean_pressure(sys%elems%wt(g0:g0 + ng - 1), ntr, sys%pts%sig(1:4, g0:g0 + ng - 1), pt(1:ng))
      end if
      mrow(1:ndof) = 0.0_dp
      mrow_m(1:ndof) = 0.0_dp
      do k = 1, ng                ! <b_v>: the mean of the in-plane trace rows of P B_NL(F(n+1))
        call add_trace_row(sys%elems%wt(g0 + k - 1) / wtot, ntr, pt(k), ndof, mrow, mrow_m)
      end do
    end if
    do k = 1, ng
      call point_forces(sys, mv, g0 + k - 1, ndof, correct, tangent, pt(k), mrow, mrow_m, fe, fc, ke, kg, ka, wsum, dsum)
    end do
    if (tangent .and. mv%bbar .and. mv%hyper) then
      ! HYPERELASTIC's volumetric energy W λ/2 <ln J>²: its Hessian W λ m m' (m = d<ln J>/du, mrow)
      ! and the log map's curvature λ <ln J> I₂ : d²ℓ/dE² at each point (split: ke, kg).
      do k = 1, ndof
        ke(1:ndof, k) = ke(1:ndof, k) + mv%lame(1) * wtot * mrow(1:ndof) * mrow(k)
      end do
      do k = 1, ng
        call log_curvature(pt(k)%e1, mv%lame(1) * jmean * I2, gcurv)
        call add_split(ke, kg, sys%elems%wt(g0 + k - 1), pt(k)%b1, gcurv, ndof, mv%axi)
      end do
    end if
    any_c = any_c .or. correct
  end subroutine large_plane_element

  !> Point igp's ∇N, F and E at n and n+1, and the strains its law will see (E, or ℓ and P).
  subroutine point_kinematics(sys, mv, e, igp, nen, ue, une, q)
    type(system_t), intent(inout) :: sys
    type(model_view_t), intent(in) :: mv
    integer, intent(in) :: e, igp, nen
    real(dp), intent(in) :: ue(:), une(:)
    type(plane_pt_t), intent(inout) :: q
    real(dp) :: hn(2, 2), h1(2, 2), hzn, hz1
    integer :: a, p
    logical :: okn, ok1
    p = sys%elems%b_ptr(igp)
    do a = 1, nen
      q%dn(1, a) = sys%elems%bref(p + (2 * a - 2) * 4)          ! B(1, 2a-1) = dN_a/dX
      q%dn(2, a) = sys%elems%bref(p + (2 * a - 1) * 4 + 1)      ! B(2, 2a)   = dN_a/dY
      q%nr(a) = 0.0_dp
      if (mv%axi) q%nr(a) = sys%elems%bref(p + (2 * a - 2) * 4 + 2)   ! B(3, 2a-1) = N_a/R
    end do
    hn = grad(une)
    h1 = grad(ue)
    q%fn = hn + EYE
    q%f1 = h1 + EYE
    hzn = hoop(une)
    hz1 = hoop(ue)
    q%zn = 1.0_dp + hzn
    q%z1 = 1.0_dp + hz1
    ! An element turned inside out (det F <= 0) has no strain energy of its own to show it:
    ! reported to the step (iterate_eq9), as for the axial members.
    if (sys%elems%inverted == 0 .and. (q%f1(1, 1) * q%f1(2, 2) - q%f1(1, 2) * q%f1(2, 1) <= 0.0_dp .or. &
        q%z1 <= 0.0_dp)) sys%elems%inverted = e
    q%en = green(hn, hzn)
    q%e1 = green(h1, hz1)
    call bnl(q%f1, q%z1, q%dn, q%nr, nen, q%b1)
    call bnl(0.5_dp * (q%fn + q%f1), 0.5_dp * (q%zn + q%z1), q%dn, q%nr, nen, q%bm)
    ! The Hencky strain: the law's with STRAIN_MEASURE LOG; HYPERELASTIC with BBAR takes its ln J.
    if (mv%log_strain .or. (mv%hyper .and. mv%bbar)) then
      call hencky_strain(q%en, q%lon, q%pn, okn)
      call hencky_strain(q%e1, q%lo1, q%pl, ok1)
      ! C singular: det F = 0, which is reported as an inversion.
      if (.not. (okn .and. ok1)) q%lo1 = q%lon
    else
      q%lon = q%en
      q%lo1 = q%e1
      q%pn = reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, &
        0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [4, 4])
      q%pl = q%pn
    end if
    q%ln = q%lon
    q%l1 = q%lo1
    if (mv%hyper) then
      q%ln = q%en
      q%l1 = q%e1
    end if
    q%snoise = 0.0_dp
  contains
    !> The displacement gradient H = Σ u_a ⊗ ∇N_a (F = I + H).
    pure function grad(u) result(f)
      real(dp), intent(in) :: u(:)
      real(dp) :: f(2, 2)
      integer :: k
      f = 0.0_dp
      do k = 1, nen
        f(1, :) = f(1, :) + u(2 * k - 1) * q%dn(:, k)
        f(2, :) = f(2, :) + u(2 * k) * q%dn(:, k)
      end do
    end function grad
    !> The hoop part of the gradient, u_r/R = Σ u_a N_a/R (F_θθ = 1 + it; 0 unless AXISYMMETRIC).
    pure real(dp) function hoop(u) result(hz)
      real(dp), intent(in) :: u(:)
      integer :: k
      hz = 0.0_dp
      do k = 1, nen
        hz = hz + u(2 * k - 1) * q%nr(k)
      end do
    end function hoop
    !> E = ½(H + H' + H'H) as [Exx, Eyy, Eθθ, 2 Exy] (the engineering shear, as the small strain's
    !> γ; Eθθ = hz + ½ hz², 0 in plane strain), from H: ½(F'F - I) would lose a small strain to round-off.
    pure function green(h, hz) result(eg)
      real(dp), intent(in) :: h(2, 2), hz
      real(dp) :: eg(4), c(2, 2)
      c = matmul(transpose(h), h)
      eg = [h(1, 1) + 0.5_dp * c(1, 1), h(2, 2) + 0.5_dp * c(2, 2), hz + 0.5_dp * hz * hz, h(1, 2) + h(2, 1) + c(1, 2)]
    end function green
  end subroutine point_kinematics

  !> FORMULATION BBAR, the strains: at every point the in-plane trace of the strain the law sees
  !> replaced by the element's volume mean (weights w), at n and at n+1:
  !>     ℓ̄ = ℓ + ½ (<tr ℓ> - tr ℓ) I₂,   <tr ℓ> = Σ w tr ℓ / Σ w.
  !> On the Hencky strain tr ℓ = ln J (plane strain), so J̄ is the element's geometric mean of J at
  !> every point (F-bar); in small strain it is B-bar. ℓ̄ is linear in the points' ℓ.
  !> AXISYMMETRIC (ntr = 3): the trace over the three normal strains, ℓ̄ = ℓ + ⅓ (<tr ℓ> - tr ℓ) I₃.
  pure subroutine mean_dilatation(w, ntr, pt)
    real(dp), intent(in) :: w(:)
    integer, intent(in) :: ntr
    type(plane_pt_t), intent(inout) :: pt(:)
    real(dp) :: mn, m1
    integer :: k
    mn = 0.0_dp                     ! (loops: sections of pt's components would be copied to the heap)
    m1 = 0.0_dp
    do k = 1, size(pt)
      mn = mn + w(k) * trace(pt(k)%ln, ntr)
      m1 = m1 + w(k) * trace(pt(k)%l1, ntr)
    end do
    mn = mn / sum(w)
    m1 = m1 / sum(w)
    do k = 1, size(pt)
      pt(k)%ln = with_trace(pt(k)%ln, mn, ntr)
      pt(k)%l1 = with_trace(pt(k)%l1, m1, ntr)
    end do
  end subroutine mean_dilatation

  !> The trace of a Voigt 4-vector: in-plane (ntr = 2), or of the three normal components (3).
  pure real(dp) function trace(v, ntr)
    real(dp), intent(in) :: v(4)
    integer, intent(in) :: ntr
    trace = v(1) + v(2)
    if (ntr == 3) trace = trace + v(3)
  end function trace

  !> v with its trace replaced by m: v + ½ (m - tr v) I₂ (ntr = 2), v + ⅓ (m - tr v) I₃ (ntr = 3).
  pure function with_trace(v, m, ntr) result(r)
    real(dp), intent(in) :: v(4), m
    integer, intent(in) :: ntr
    real(dp) :: r(4)
    if (ntr == 3) then
      r = v + (m - trace(v, 3)) / 3.0_dp * I3
    else
      r = v + 0.5_dp * (m - (v(1) + v(2))) * I2
    end if
  end function with_trace

  !> FORMULATION BBAR, the stresses: the virtual work Σ w T·δℓ̄ = Σ w T̃·δℓ with
  !>     T̃ = T + ½ (<tr T> - tr T) I₂,
  !> each point's in-plane deviator and the element's mean in-plane pressure; for T(n) (sn, the
  !> committed stresses), T(n+1) and the step's T̄ alike (so Σ w T̃̄·Δℓ = Σ w T̄·Δℓ̄, the laws' work).
  pure subroutine mean_pressure(w, ntr, sn, pt)
    real(dp), intent(in) :: w(:), sn(:, :)
    integer, intent(in) :: ntr
    type(plane_pt_t), intent(inout) :: pt(:)
    real(dp) :: mn, m1, mb
    integer :: k
    mn = 0.0_dp
    m1 = 0.0_dp
    mb = 0.0_dp
    do k = 1, size(pt)
      mn = mn + w(k) * trace(sn(1:4, k), ntr)
      m1 = m1 + w(k) * trace(pt(k)%t1, ntr)
      mb = mb + w(k) * trace(pt(k)%tbar, ntr)
    end do
    mn = mn / sum(w)
    m1 = m1 / sum(w)
    mb = mb / sum(w)
    do k = 1, size(pt)
      pt(k)%tn = with_trace(sn(1:4, k), mn, ntr)
      pt(k)%t1 = with_trace(pt(k)%t1, m1, ntr)
      pt(k)%tbar = with_trace(pt(k)%tbar, mb, ntr)
    end do
  end subroutine mean_pressure

  !> FORMULATION BBAR with HYPERELASTIC: the volumetric energy λ/2 ln² J of each point taken on the
  !> element's mean <ln J> = Σ w tr ℓ / Σ w (tr ℓ = ln J in plane strain; the rest of ψ is each
  !> point's: point_law), so the element stores Σ w ψ_dev + W λ/2 <ln J>² (nh_mean_energy). Its
  !> stress at each point, on E: λ <ln J> Pᵀ I₂ at n+1 (added to t1; tn is the committed total), and
  !> the step's λ <ln J>_mid Gᵀ I₂ (secant_stress: Σ w of its work on ΔE = W λ/2 Δ<ln J>², exactly).
  subroutine mean_volume(lam, w, pt, j1)
    real(dp), intent(in) :: lam, w(:)
    type(plane_pt_t), intent(inout) :: pt(:)
    real(dp), intent(out) :: j1          !< <ln J> at n+1
    real(dp) :: jn, pb, sv(4), noise
    integer :: k
    jn = 0.0_dp
    j1 = 0.0_dp
    do k = 1, size(pt)
      jn = jn + w(k) * (pt(k)%lon(1) + pt(k)%lon(2))
      j1 = j1 + w(k) * (pt(k)%lo1(1) + pt(k)%lo1(2))
    end do
    jn = jn / sum(w)
    j1 = j1 / sum(w)
    pb = 0.5_dp * lam * (jn + j1)
    do k = 1, size(pt)
      associate (q => pt(k))
        q%t1 = q%t1 + lam * j1 * (q%pl(1, :) + q%pl(2, :))
        call secant_stress(pb * I2, q%lon, q%lo1, q%en, q%e1, q%pn, q%pl, sv, noise)
        q%tbar = q%tbar + sv
        q%wpt = q%wpt + pb * ((q%lo1(1) + q%lo1(2)) - (q%lon(1) + q%lon(2)))
        q%snoise = noise
      end associate
    end do
  end subroutine mean_volume

  !> mrow += wr (I₂' P(n+1) B_NL(F(n+1))): a point's share of the mean in-plane trace row of dℓ/du.
  pure subroutine add_trace_row(wr, ntr, q, ndof, mrow, mrow_m)
    real(dp), intent(in) :: wr
    integer, intent(in) :: ntr
    type(plane_pt_t), intent(in) :: q
    integer, intent(in) :: ndof
    real(dp), intent(inout) :: mrow(:)
    real(dp), intent(inout) :: mrow_m(:)   !< the same of P_m B_NL(F_mid), P_m = ½(P(n) + P(n+1))
    real(dp) :: tr1(4), trm(4)
    integer :: a
    tr1 = q%pl(1, :) + q%pl(2, :)
    trm = 0.5_dp * (q%pn(1, :) + q%pn(2, :)) + 0.5_dp * tr1
    if (ntr == 3) then
      tr1 = tr1 + q%pl(3, :)
      trm = trm + 0.5_dp * (q%pn(3, :) + q%pl(3, :))
    end if
    do a = 1, ndof
      mrow(a) = mrow(a) + wr * dot_product(tr1, q%b1(:, a))
      mrow_m(a) = mrow_m(a) + wr * dot_product(trm, q%bm(:, a))
    end do
  end subroutine add_trace_row

  !> Point igp through its law from the strains q%ln to q%l1 (the law's committed state at n): the
  !> stresses T(n), T(n+1), the step's T̄ (T̄·Δℓ is the law's path work, wpt; dissipated part
  !> dpt) and the law's tangent dm on ℓ (the tangent of 2T̄ with the correction, where the law has
  !> it). ELASTIC: the Hencky material on ℓ, T = D ℓ (St Venant-Kirchhoff on E); HYPERELASTIC:
  !> neo-Hookean on E; VON_MISES: J2 additive in ℓ (or on E), sub-incremented by point_update.
  !> The point keeps (and reports) its pair (ℓ, T) in eps_t, sig_t.
  subroutine point_law(scn, sys, mv, igp, tangent, correct, q)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(model_view_t), intent(in) :: mv
    integer, intent(in) :: igp
    logical, intent(in) :: tangent, correct
    type(plane_pt_t), intent(inout) :: q
    type(law_step_t) :: r
    real(dp) :: lm(2)
    q%dpt = 0.0_dp
    q%tn = sys%pts%sig(1:4, igp)
    if (mv%hyper) then
      ! (With BBAR the volumetric term λ/2 ln² J is the element's: mean_volume.)
      lm = mv%lame
      if (mv%bbar) lm(1) = 0.0_dp
      q%t1 = nh_stress(lm, q%e1, mv%pstress)
      q%tbar = nh_discrete_stress(lm, q%en, q%e1, mv%pstress)
      if (tangent) q%dm = nh_tangent(lm, q%e1, mv%pstress)
    else if (mv%von_mises) then
      call point_update(scn, sys, mv, igp, q%ln, q%l1 - q%ln, r)
      q%t1 = r%sig(1:4)
      q%tbar = r%sigbar(1:4)
      q%dpt = r%dissip
      if (tangent) q%dm = r%dtan(1:4, 1:4)
      if (tangent .and. correct .and. r%has_dbar) q%dm = r%dbar(1:4, 1:4)
    else
      q%t1 = matmul(sys%elems%dmat(1:4, 1:4, mv%im), q%l1)
      q%tbar = 0.5_dp * (q%tn + q%t1)
      if (tangent) q%dm = sys%elems%dmat(1:4, 1:4, mv%im)
    end if
    sys%pts%eps_t(1:4, igp) = q%l1
    sys%pts%sig_t(1:4, igp) = q%t1
    q%wpt = dot_product(q%tbar, q%l1 - q%ln)
  end subroutine point_law

  !> Point igp's share of the element's forces: f(n+1) += w B_NL(F(n+1))' S(n+1), the correction
  !> fc += w (2 B_NL(F_mid)' S̄ - B_NL(F(n))' S(n) - f(n+1)'s), S = P'T (S = T on E) and S̄ = G'T̄
  !> (secant_stress); the work and dissipation sums; bmat; with tangent, ke += the point's tangent:
  !> w B' (P'DP + T:d²ℓ/dE², positive part) B + the geometric part with the tensile part of S.
  !> With BBAR the material part is w B̄'D B̄ (B̄ the B of ℓ̄: mrow, the mean trace row) and the log
  !> map's curvature keeps its positive part alone. With correct, the step tangent: B̂ (step_b, from
  !> B_NL(F_mid), mrow_m and B(n+1)) and S̄ in those terms, ka += the antisymmetric part.
  subroutine point_forces(sys, mv, igp, ndof, correct, tangent, q, mrow, mrow_m, fe, fc, ke, kg, ka, wsum, dsum)
    type(system_t), intent(inout) :: sys
    type(model_view_t), intent(in) :: mv
    integer, intent(in) :: igp, ndof
    logical, intent(in) :: correct, tangent
    type(plane_pt_t), intent(in) :: q
    real(dp), intent(in) :: mrow(:), mrow_m(:)
    real(dp), intent(inout) :: fe(:), fc(:), ke(:, :), kg(:, :), wsum, dsum
    real(dp), intent(inout) :: ka(:, :)   !< with tangent and correct: += the antisymmetric part (step_b)
    real(dp) :: sn(4), s1(4), sbar(4), sg(4), snoise, bn(4, MAX_EDOF), bb(4, MAX_EDOF), bh(4, MAX_EDOF), bhe(4, MAX_EDOF), &
      bl(4, MAX_EDOF), br(4, MAX_EDOF), &
      dm(4, 4), gc(4, 4), st(2, 2), sc(2, 2), w, g, gcm, pmax
    integer :: p, nen, a, b, i
    p = sys%elems%b_ptr(igp)
    w = sys%elems%wt(igp)
    nen = ndof / 2
    snoise = 0.0_dp
    if (tangent) dm = q%dm
    snoise = q%snoise
    if (mv%log_strain) then
      sn = matmul(q%tn, q%pn)
      s1 = matmul(q%t1, q%pl)
      call secant_stress(q%tbar, q%lon, q%lo1, q%en, q%e1, q%pn, q%pl, sbar, snoise)
      if (tangent .and. .not. (mv%bbar .or. correct)) call log_tangent(q%e1, q%t1, q%pl, dm, mv%axi)
    else
      sn = q%tn
      s1 = q%t1
      sbar = q%tbar
    end if
    ! The attainable residual (iterate_eq9's floor): that stress noise, and the strain's own round-off
    ! through the point's stiffness λ + 2μ (a nearly incompressible material: λ/μ = 5000 at ν = 0.4999
    ! puts it above TOLERANCE x the force scale) and the log map: ℓ = ½ log1p(2e) of a stretch λ
    ! carries ε (|ℓ| + |e| P), P = dℓ/dE up to 1/λ² (4000 at the axis-wall corner of the crushed 16 x 80
    ! Taylor bar), and S = PᵀT multiplies it by P again; the force by F and the point's ∇N.
    pmax = max(1.0_dp, maxval(abs(q%pl)))
    snoise = hypot(snoise, pmax * sys%elems%dmat(1, 1, mv%im) * 4.0_dp * epsilon(1.0_dp) * &
      (1.0_dp + maxval(abs(q%l1)) + pmax * maxval(abs(q%e1))))
    if (snoise > 0.0_dp) sys%elems%round_floor = sys%elems%round_floor + &
      (w * snoise * max(1.0_dp, maxval(abs(q%f1))))**2 * sum(q%dn(:, 1:nen)**2)
    call bnl(q%fn, q%zn, q%dn, q%nr, nen, bn)
    do a = 1, ndof                          ! (loops, not reshape/matmul: no temporaries)
      if (mv%bbar .and. .not. mv%hyper) then  ! the B of ℓ̄: Q P B_NL + ½ I₂ <b_v>
        do i = 1, 4
          bb(i, a) = dot_product(q%pl(i, :), q%b1(:, a))
        end do
        call set_trace(bb(:, a), mrow(a), mv%axi)
        sys%elems%bmat(p + 4 * a - 4:p + 4 * a - 1) = bb(:, a)
      else if (mv%log_strain) then          ! the B of the point's strain: P B_NL for ℓ
        do i = 1, 4
          sys%elems%bmat(p + 4 * a - 5 + i) = dot_product(q%pl(i, :), q%b1(:, a))
        end do
      else
        sys%elems%bmat(p + 4 * a - 4:p + 4 * a - 1) = q%b1(:, a)
      end if
      fe(a) = fe(a) + w * s_dot_b(s1, q%b1, a)
    end do
    wsum = wsum + w * q%wpt
    dsum = dsum + w * q%dpt
    if (correct) then
      do a = 1, ndof
        fc(a) = fc(a) + w * (2.0_dp * s_dot_b(sbar, q%bm, a) - s_dot_b(sn, bn, a) - s_dot_b(s1, q%b1, a))
      end do
    end if
    if (.not. tangent) return
    ! With the correction the force is eq (9)'s 2 w B_NL(F_mid)' S̄: its tangent takes the step's B
    ! (step_b) and the geometric part with S̄ (step_tangent); without, B(n+1) and S(n+1).
    sg = s1
    if (correct) then
      ! B̂ and the antisymmetric part (step_b); the log map's curvature with T̄ through B̂ on E
      ! (2 B_NL(F_mid)' (dG'/dE T̄) B_NL(F(n+1)), G ≈ P_m); the geometric part with S̄.
      call step_b(mv, q, mrow_m, bb, ndof, bl, br)
      bh(:, 1:ndof) = 0.5_dp * (bl(:, 1:ndof) + br(:, 1:ndof))
      call add_anti(4, ndof, bl, dm, br, w, ka)
      call sym_part(dm)                    ! (the law's dbar is not symmetric)
      sg = sbar
      bhe(:, 1:ndof) = 0.5_dp * (q%bm(:, 1:ndof) + q%b1(:, 1:ndof))
      if (mv%log_strain) then
        call log_curvature(q%e1, q%tbar, gc)
        call add_anti(4, ndof, q%bm, gc, q%b1, w, ka)
      end if
    else
      bh(:, 1:ndof) = q%b1(:, 1:ndof)
      if (mv%bbar .and. .not. mv%hyper) bh(:, 1:ndof) = bb(:, 1:ndof)
      bhe(:, 1:ndof) = q%b1(:, 1:ndof)
      if (mv%log_strain) call log_curvature(q%e1, q%t1, gc)
    end if
    if ((mv%bbar .and. .not. mv%hyper) .or. (correct .and. mv%log_strain)) then
      ! The law's tangent (that of 2T̄ with the correction: not always positive) on ℓ (or ℓ̄), the
      ! log map's curvature T : d²ℓ/dE² through B_NL: each split into ke and kg.
      call add_split(ke, kg, w, bh, dm, ndof, mv%axi)
      if (mv%log_strain) call add_split(ke, kg, w, bhe, gc, ndof, mv%axi)
    else
      call add_btdb(ke, w, bh, dm, ndof)
    end if
    ! Geometric part ∇N_a' S ∇N_b on both directions: the tensile part of S in ke, the compressive
    ! part in kg (the iteration matrix takes it where S stays positive definite: iteration_matrix).
    st = reshape([sg(1), sg(4), sg(4), sg(2)], [2, 2])
    sc = st
    call tensile_part(st)
    sc = sc - st
    do a = 1, nen
      do b = 1, nen
        g = w * dot_product(q%dn(:, a), matmul(st, q%dn(:, b)))
        gcm = w * dot_product(q%dn(:, a), matmul(sc, q%dn(:, b)))
        do i = 1, 2
          ke(2 * a - 2 + i, 2 * b - 2 + i) = ke(2 * a - 2 + i, 2 * b - 2 + i) + g
          kg(2 * a - 2 + i, 2 * b - 2 + i) = kg(2 * a - 2 + i, 2 * b - 2 + i) + gcm
        end do
      end do
    end do
    if (.not. mv%axi) return
    ! The hoop part, d²Eθθ/du_ra du_rb = N_a N_b / R²: S_θθ (an eigenvalue of S) to ke or kg.
    do a = 1, nen
      do b = 1, nen
        g = w * sg(3) * q%nr(a) * q%nr(b)
        if (sg(3) > 0.0_dp) then
          ke(2 * a - 1, 2 * b - 1) = ke(2 * a - 1, 2 * b - 1) + g
        else
          kg(2 * a - 1, 2 * b - 1) = kg(2 * a - 1, 2 * b - 1) + g
        end if
      end do
    end do
  end subroutine point_forces

  !> The B's of eq (9)'s step tangent (the energy correction on): the force 2 w B_l' T̄ (B_l, bl here,
  !> the B of the step's force: B_NL(F_mid), through P_m = ½(P(n) + P(n+1)) for ℓ, with BBAR the
  !> element's mean trace row of those, mrow_m) has the Jacobian B_l' D B_r + the geometric part with
  !> S̄, B_r (br) the B of the strain at n+1 (bb with BBAR, P(n+1) B_NL(F(n+1)) for ℓ, else
  !> B_NL(F(n+1))) and D the law's tangent of 2T̄. With B̂ = ½(B_l + B_r) and δ = B_r - B_l its
  !> symmetric part is B̂' D_s B̂ - ¼ δ' D_s δ + the antisymmetric parts of D (D_s = ½(D + D')): the
  !> tangent takes B̂' D_s B̂ (to O(δ²), δ = O(ΔF) the step's change of the gradient; B_r' D B_r, the
  !> tangent at n+1, misses it by O(ΔF): Newton then contracts by only about |ΔF| per iterate, 1/40
  !> to 1/100 on the Taylor bar's impact) and ka the antisymmetric part (add_anti).
  pure subroutine step_b(mv, q, mrow_m, bb, ndof, bl, br)
    type(model_view_t), intent(in) :: mv
    type(plane_pt_t), intent(in) :: q
    real(dp), intent(in) :: mrow_m(:), bb(:, :)
    integer, intent(in) :: ndof
    real(dp), intent(out) :: bl(:, :), br(:, :)
    real(dp) :: pm(4, 4)
    integer :: a, i
    if (.not. ((mv%bbar .and. .not. mv%hyper) .or. mv%log_strain)) then
      bl(:, 1:ndof) = q%bm(:, 1:ndof)
      br(:, 1:ndof) = q%b1(:, 1:ndof)
      return
    end if
    pm = 0.5_dp * (q%pn + q%pl)
    do a = 1, ndof
      do i = 1, 4
        bl(i, a) = dot_product(pm(i, :), q%bm(:, a))
      end do
      if (.not. (mv%bbar .and. .not. mv%hyper)) then
        do i = 1, 4
          br(i, a) = dot_product(q%pl(i, :), q%b1(:, a))
        end do
        cycle
      end if
      call set_trace(bl(:, a), mrow_m(a), mv%axi)
      br(:, a) = bb(:, a)
    end do
  end subroutine step_b


  !> B-bar's column b (xx, yy, zz, xy rows) given the element's mean trace: its normal rows (in-plane,
  !> with the hoop row when axi) shifted alike so that their sum is target.
  pure subroutine set_trace(b, target, axi)
    real(dp), intent(inout) :: b(4)
    real(dp), intent(in) :: target
    logical, intent(in) :: axi
    real(dp) :: tr
    if (axi) then
      tr = (target - (b(1) + b(2) + b(3))) / 3.0_dp
      b(1:3) = b(1:3) + tr
    else
      tr = 0.5_dp * (target - (b(1) + b(2)))
      b(1:2) = b(1:2) + tr
    end if
  end subroutine set_trace

  !> The step's second Piola-Kirchhoff stress of a STRAIN_MEASURE LOG point: S̄ = G'T̄, T̄ the law's
  !> step stress on the Hencky strain (its path mean: T̄·Δℓ is the law's path work) and G a secant
  !> of the map E -> ℓ, G ΔE = Δℓ:
  !>     G = P_m + φ r ⊗ d / (d·ΔE),  P_m = ½(P(n) + P(n+1)),  r = Δℓ - P_m ΔE,  d = ΔE (shear halved),
  !> so that S̄·ΔE = T̄·Δℓ: the step's work is the law's. r is the trapezoid rule's error on the
  !> smooth log map, O(|ℓ'''| |ΔE|³): the material part stays in T̄ (as σ̄ in small strain). Its
  !> round-off, ν ≈ 64 ε (|ℓ| + |E| + |P| |ΔE|), divided by |ΔE| would put noise in S̄ at small
  !> increments of a strained point (Newton then stagnates: the 8 x 40 Taylor bar at 69 µs). φ is
  !> the larger of two smooth steps: of |ΔE|/δ from 0 at δ = ν^(1/3) to 1 at 2δ (the term left out
  !> where it is below |T̄| δ³ in work on a gently curved map), and of |T̄·r| / (|T̄| ν) from 0 at 1 to
  !> 1 at 2 (kept wherever the work it carries stands above its round-off: a crushed point, λ² =
  !> 1/4000, has |ℓ'''| ~ 1/λ⁶, and the cut-off on |ΔE| alone left 3e-7 J in one step's balance of
  !> the axisymmetric Taylor bar). snoise: the stress noise left, |T̄| δ², or |T̄| ν / |ΔE| where
  !> the second step brings the term in below 2δ, for the attainable residual (round_floor).
  pure subroutine secant_stress(tbar, ln, l1, en, e1, pn, p1, sbar, snoise)
    real(dp), intent(in) :: tbar(4), ln(4), l1(4), en(4), e1(4), pn(4, 4), p1(4, 4)
    real(dp), intent(out) :: sbar(4), snoise
    real(dp) :: pm(4, 4), de(4), dd(4), r(4), den, delta, nu, x, phi, phiw, tn, wr
    integer :: i
    pm = 0.5_dp * (pn + p1)
    de = e1 - en
    dd = [de(1), de(2), de(3), 0.5_dp * de(4)]
    den = dot_product(dd, de)
    sbar = matmul(tbar, pm)
    tn = norm2(tbar)
    nu = 64.0_dp * epsilon(1.0_dp) * (sum(abs(l1) + abs(ln)) + sum(abs(e1) + abs(en)))
    delta = nu**(1.0_dp / 3.0_dp)
    snoise = tn * delta**2
    if (.not. (den > 0.0_dp .and. tn > 0.0_dp)) return
    x = sqrt(den) / max(delta, tiny(1.0_dp)) - 1.0_dp
    phi = smooth01(x)
    do i = 1, 4
      r(i) = (l1(i) - ln(i)) - dot_product(pm(i, :), de)
    end do
    wr = dot_product(tbar, r)
    nu = nu + 64.0_dp * epsilon(1.0_dp) * max(1.0_dp, maxval(abs(pm))) * sum(abs(de))
    phiw = smooth01(abs(wr) / (tn * nu) - 1.0_dp)
    if (phiw > phi) snoise = max(snoise, tn * nu / sqrt(den))
    phi = max(phi, phiw)
    if (phi > 0.0_dp) sbar = sbar + (phi * wr / den) * dd
  end subroutine secant_stress

  !> 0 for x <= 0, 1 for x >= 1, x²(3 - 2x) between (C¹).
  pure real(dp) function smooth01(x)
    real(dp), intent(in) :: x
    smooth01 = min(max(x, 0.0_dp), 1.0_dp)
    smooth01 = smooth01 * smooth01 * (3.0_dp - 2.0_dp * smooth01)
  end function smooth01

  !> The in-plane block of m (4 x 4 on the strain b maps du to; xx, yy, xy) symmetrized and split:
  !> ke += w b' m⁺ b with m⁺ its positive part, kg += w b' (m - m⁺) b (m's zz row and column are
  !> zero through b in plane strain). axi: the whole 4 x 4 (the hoop row of b is not zero).
  pure subroutine add_split(ke, kg, w, b, m, ndof, axi)
    real(dp), intent(inout) :: ke(:, :), kg(:, :)
    real(dp), intent(in) :: w, b(:, :), m(4, 4)
    integer, intent(in) :: ndof
    logical, intent(in) :: axi
    integer, parameter :: ip(3) = [1, 2, 4]
    real(dp) :: a3(3, 3), a4(4, 4), mp(4, 4), mn(4, 4)
    mp = 0.0_dp
    if (axi) then
      a4 = 0.5_dp * (m + transpose(m))
      mn = a4
      call positive_all(a4, mp)
    else
      a3 = 0.5_dp * (m(ip, ip) + transpose(m(ip, ip)))
      mn = 0.0_dp
      mn(ip, ip) = a3
      call positive_inplane(a3, mp)
    end if
    call add_btdb(ke, w, b, mp, ndof)
    mn = mn - mp
    if (any(mn /= 0.0_dp)) call add_btdb(kg, w, b, mn, ndof)      ! m positive definite: nothing to split
  end subroutine add_split

  !> dE = B_NL(F) du (rows as green's; columns u_x, u_y of each node), ∇N in dn; the hoop row
  !> dEθθ = F_θθ Σ N_a/R du_ra (fz = F_θθ, nr = N_a/R: zero unless AXISYMMETRIC).
  pure subroutine bnl(f, fz, dn, nr, nen, bb)
    real(dp), intent(in) :: f(2, 2), fz, dn(:, :), nr(:)
    integer, intent(in) :: nen
    real(dp), intent(out) :: bb(:, :)
    integer :: k
    bb = 0.0_dp
    do k = 1, nen
      bb(3, 2 * k - 1) = fz * nr(k)
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
end module large_plane
