!> KINEMATICS LARGE solid elements (HEX8, HEX20, TET4, TET10; docs/large-displacements.md, "3D
!> solids"): the kernel of large_plane for the volume family. Total Lagrangian, F = I + H the 3 x 3
!> deformation gradient at each point, the Green-Lagrange strain E = ½(H + H' + H'H) as
!> [Exx, Eyy, Ezz, 2Exy, 2Eyz, 2Exz] (the small strain's order and engineering shears), the second
!> Piola-Kirchhoff stress S: ELASTIC is St Venant-Kirchhoff (S = D E), HYPERELASTIC the compressible
!> neo-Hookean solid with its discrete stress (S̄·ΔE = Δψ exactly, law_hyperelastic), VON_MISES the J2
!> law on the pair (E, S) (large rotations, small strains: code_aster's GROT_GDEP), sub-incremented
!> along [E(n), E(n+1)] by point_update with its path-mean stress S̄.
!> The discrete gradient of eq (9): E is quadratic in u, so B_NL(F_mid) Δu = ΔE exactly (F_mid =
!> (F(n) + F(n+1))/2), and the step force f̄ = w B_NL(F_mid)' S̄ does the work S̄·ΔE, the law's path
!> work (stored + dissipated; ½(S(n) + S(n+1))·ΔE = Δψ for St Venant-Kirchhoff): Bσc of eq (9) is
!> 2 f̄ - f(n) - f(n+1). The forces are frame-indifferent, so a free body keeps its linear and angular
!> momentum, as in 2D (Simo and Tarnow's energy-momentum step for this material).
module large_solid
  use kinds, only: dp
  use scene, only: scene_t
  use assembly, only: system_t
  use elements, only: MAX_EDOF
  use material_law, only: law_step_t
  use element_points, only: model_view_t, point_update
  use law_hyperelastic, only: nh_solid_stress, nh_solid_tangent, nh_solid_discrete_stress
  use lapack_pure, only: dsyev
  use small_matrix, only: det3, sym_part
  use element_table, only: add_btdb, add_anti
  implicit none
  private
  public :: large_solid_element

  integer, parameter :: NS = 6                       !< the strain components of a solid
  integer, parameter :: NEN_MAX = MAX_EDOF / 3
  real(dp), parameter :: EYE(3, 3) = reshape([1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, &
    1.0_dp], [3, 3])

contains

  !> Element e's forces fe (+)= Σ w B_NL(F(n+1))' S(n+1), the correction fc of eq (9), the work and
  !> dissipation sums, and with tangent ke (+)= w B_NL' D B_NL + the tensile part of the geometric
  !> stiffness (kg the compressive part, which the iteration matrix takes where it keeps S positive:
  !> iteration_matrix). bmat keeps B_NL(F(n+1)) for the support reactions; the points keep (E, S).
  subroutine large_solid_element(scn, sys, mv, e, g0, ng, ndof, ue, une, correct, tangent, fe, fc, ke, kg, ka, any_c, &
                                 wsum, dsum)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(model_view_t), intent(in) :: mv
    integer, intent(in) :: e, g0, ng, ndof
    real(dp), intent(in) :: ue(:), une(:)
    logical, intent(in) :: correct, tangent
    real(dp), intent(inout) :: fe(:), fc(:), ke(MAX_EDOF, MAX_EDOF), kg(:, :), wsum, dsum
    real(dp), intent(inout) :: ka(:, :)   !< with tangent and correct: += the Jacobian's antisymmetric part
    logical, intent(inout) :: any_c
    type(law_step_t) :: r
    real(dp) :: dn(3, NEN_MAX), fn(3, 3), f1(3, 3), en(NS), e1(NS), sn(NS), s1(NS), sbar(NS), dm(NS, NS), &
      b1(NS, MAX_EDOF), bn(NS, MAX_EDOF), bm(NS, MAX_EDOF), w, dpt, snoise
    integer :: k, igp, nen, a, p
    fc(1:ndof) = 0.0_dp
    nen = ndof / 3
    do k = 1, ng
      igp = g0 + k - 1
      p = sys%elems%b_ptr(igp)
      w = sys%elems%wt(igp)
      call solid_kinematics(sys%elems%bref(p:p + NS * ndof - 1), nen, une, dn, fn, en)
      call solid_kinematics(sys%elems%bref(p:p + NS * ndof - 1), nen, ue, dn, f1, e1)
      ! An element turned inside out (det F <= 0) has no strain energy of its own to show it:
      ! reported to the step (iterate_eq9), as for the surface elements.
      if (sys%elems%inverted == 0 .and. det3(f1) <= 0.0_dp) sys%elems%inverted = e
      ! The law: S(n+1), the step's S̄ and its tangent.
      sn = sys%pts%sig(1:NS, igp)
      dpt = 0.0_dp
      if (mv%hyper) then
        s1 = nh_solid_stress(mv%lame, e1)
        sbar = nh_solid_discrete_stress(mv%lame, en, e1)
        if (tangent) dm = nh_solid_tangent(mv%lame, e1)
      else if (mv%von_mises) then
        call point_update(scn, sys, mv, igp, en, e1 - en, r)
        s1 = r%sig(1:NS)
        sbar = r%sigbar(1:NS)
        dpt = r%dissip
        if (tangent) dm = r%dtan(1:NS, 1:NS)
        if (tangent .and. correct .and. r%has_dbar) dm = r%dbar(1:NS, 1:NS)
      else
        s1 = matmul(sys%elems%dmat(1:NS, 1:NS, mv%im), e1)
        sbar = 0.5_dp * (sn + s1)
        dm = sys%elems%dmat(1:NS, 1:NS, mv%im)
      end if
      sys%pts%eps_t(1:NS, igp) = e1
      sys%pts%sig_t(1:NS, igp) = s1
      ! The attainable residual (iterate_eq9's floor): the strain's round-off through the stiffness.
      snoise = sys%elems%dmat(1, 1, mv%im) * 4.0_dp * epsilon(1.0_dp) * (1.0_dp + maxval(abs(e1)))
      sys%elems%round_floor = sys%elems%round_floor + (w * snoise * max(1.0_dp, maxval(abs(f1))))**2 * &
        sum(dn(:, 1:nen)**2)
      call solid_bnl(f1, dn, nen, b1)
      call solid_bnl(fn, dn, nen, bn)
      call solid_bnl(0.5_dp * (fn + f1), dn, nen, bm)
      do a = 1, ndof
        sys%elems%bmat(p + NS * (a - 1):p + NS * a - 1) = b1(:, a)
        fe(a) = fe(a) + w * dot_product(s1, b1(:, a))
      end do
      if (correct) then
        do a = 1, ndof
          fc(a) = fc(a) + w * (2.0_dp * dot_product(sbar, bm(:, a)) - dot_product(sn, bn(:, a)) - dot_product(s1, b1(:, a)))
        end do
      end if
      wsum = wsum + w * dot_product(sbar, e1 - en)
      dsum = dsum + w * dpt
      if (tangent .and. correct) then
        ! eq (9)'s step tangent (large_plane's step_b): the force 2 w B_NL(F_mid)' S̄ has the Jacobian
        ! B_NL(F_mid)' D B_NL(F(n+1)) + the geometric part with S̄; its symmetric part B̂' D_s B̂ (B̂ the
        ! mean of the two B's, to O(ΔF²)) to ke, its antisymmetric part to ka (iterate_eq9's anti_sweep).
        call add_anti(NS, ndof, bm, dm, b1, w, ka)
        call sym_part(dm)
        bm(:, 1:ndof) = 0.5_dp * (bm(:, 1:ndof) + b1(:, 1:ndof))
        call add_btdb(NS, ndof, bm(:, 1:ndof), dm, w, ke)
        call add_geometric(ke, kg, w, sbar, dn, nen)
      else if (tangent) then
        call add_btdb(NS, ndof, b1(:, 1:ndof), dm, w, ke)
        call add_geometric(ke, kg, w, s1, dn, nen)
      end if
    end do
    any_c = any_c .or. correct
  end subroutine large_solid_element

  !> A point's ∇N (dn, from its reference B: B(1, 3a-2) = dN_a/dX, B(2, 3a-1) = dN_a/dY,
  !> B(3, 3a) = dN_a/dZ), F = I + H with H = Σ u_a ⊗ ∇N_a, and E = ½(H + H' + H'H) from H (½(F'F - I)
  !> would lose a small strain to round-off).
  pure subroutine solid_kinematics(bref, nen, u, dn, f, eg)
    real(dp), intent(in) :: bref(:), u(:)
    integer, intent(in) :: nen
    real(dp), intent(out) :: dn(3, NEN_MAX), f(3, 3), eg(NS)
    real(dp) :: h(3, 3), c(3, 3)
    integer :: a, i
    do a = 1, nen
      dn(1, a) = bref(NS * (3 * a - 3) + 1)
      dn(2, a) = bref(NS * (3 * a - 2) + 2)
      dn(3, a) = bref(NS * (3 * a - 1) + 3)
    end do
    h = 0.0_dp
    do a = 1, nen
      do i = 1, 3
        h(i, :) = h(i, :) + u(3 * a - 3 + i) * dn(:, a)
      end do
    end do
    f = EYE + h
    c = matmul(transpose(h), h)
    eg = [h(1, 1) + 0.5_dp * c(1, 1), h(2, 2) + 0.5_dp * c(2, 2), h(3, 3) + 0.5_dp * c(3, 3), &
      h(1, 2) + h(2, 1) + c(1, 2), h(2, 3) + h(3, 2) + c(2, 3), h(1, 3) + h(3, 1) + c(1, 3)]
  end subroutine solid_kinematics

  !> dE = B_NL(F) du (rows as solid_kinematics' E; columns u_x, u_y, u_z of each node):
  !> dE_jk/du_ai = ½(∂_j N_a F_ik + F_ij ∂_k N_a).
  pure subroutine solid_bnl(f, dn, nen, bb)
    real(dp), intent(in) :: f(3, 3), dn(:, :)
    integer, intent(in) :: nen
    real(dp), intent(out) :: bb(:, :)
    integer :: a, i, c
    do a = 1, nen
      do i = 1, 3
        c = 3 * a - 3 + i
        bb(1, c) = f(i, 1) * dn(1, a)
        bb(2, c) = f(i, 2) * dn(2, a)
        bb(3, c) = f(i, 3) * dn(3, a)
        bb(4, c) = f(i, 1) * dn(2, a) + f(i, 2) * dn(1, a)
        bb(5, c) = f(i, 2) * dn(3, a) + f(i, 3) * dn(2, a)
        bb(6, c) = f(i, 1) * dn(3, a) + f(i, 3) * dn(1, a)
      end do
    end do
  end subroutine solid_bnl

  !> The geometric stiffness ∇N_a' S ∇N_b on the three directions: S's tensile part (its positive
  !> eigenvalues, LAPACK dsyev) into ke, the rest into kg. A failed eigensolve puts S whole in kg.
  pure subroutine add_geometric(ke, kg, w, s, dn, nen)
    real(dp), intent(inout) :: ke(:, :), kg(:, :)
    real(dp), intent(in) :: w, s(NS), dn(:, :)
    integer, intent(in) :: nen
    real(dp) :: st(3, 3), sp(3, 3), v(3, 3), lam(3), work(16), g, gc
    integer :: info, a, b, i
    st = reshape([s(1), s(4), s(6), s(4), s(2), s(5), s(6), s(5), s(3)], [3, 3])
    v = st
    call dsyev('V', 'U', 3, v, 3, lam, work, size(work), info)
    sp = 0.0_dp
    if (info == 0) then
      do i = 1, 3
        if (lam(i) > 0.0_dp) sp = sp + lam(i) * spread(v(:, i), 2, 3) * spread(v(:, i), 1, 3)
      end do
    end if
    do b = 1, nen
      do a = 1, nen
        g = w * dot_product(dn(:, a), matmul(sp, dn(:, b)))
        gc = w * dot_product(dn(:, a), matmul(st - sp, dn(:, b)))
        do i = 1, 3
          ke(3 * a - 3 + i, 3 * b - 3 + i) = ke(3 * a - 3 + i, 3 * b - 3 + i) + g
          kg(3 * a - 3 + i, 3 * b - 3 + i) = kg(3 * a - 3 + i, 3 * b - 3 + i) + gc
        end do
      end do
    end do
  end subroutine add_geometric
end module large_solid
