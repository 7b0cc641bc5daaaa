!> HYPERELASTIC: the compressible neo-Hookean solid, for KINEMATICS LARGE surface elements (total
!> Lagrangian). With C = I + 2E (in plane; C33 = 1 in plane strain) and J = sqrt(det C):
!>   psi(E) = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2
!>   S = mu (I - C^-1) + lambda ln J C^-1,   S33 = lambda ln J (plane strain).
!> Plane stress: C33 = c is the root of S33 = 0, mu (c - 1) + lambda ln J = 0 (J^2 = det C c; one
!> root, found by Newton from c = 1), and then S = mu (I - c C^-1) in the plane; psi at that c is
!> the plane-stress energy (its derivative in c vanishes, so S = dpsi/dE still).
!> mu and lambda the Lame constants of YOUNG and POISSON (at small strain: the ELASTIC law).
!> psi grows without bound as J -> 0: unlike St Venant-Kirchhoff, which softens in compression and
!> lets an element collapse, a neo-Hookean element resists being squashed.
!> Strains and stresses as the surface elements store them: [xx, yy, zz, 2xy] and [xx, yy, zz, xy];
!> the 3D solids' (nh_solid_*: C the whole 3 x 3) [xx, yy, zz, 2xy, 2yz, 2xz] and [xx, yy, zz, xy, yz, xz].
!> The step of eq (9) uses nh_discrete_stress, S̄ with S̄ : ΔE = Δpsi exactly (Gonzalez's midpoint
!> discrete gradient in E, which keeps S̄ symmetric and so the angular momentum): docs/materials.md.
module law_hyperelastic
  use kinds, only: dp
  use small_matrix, only: adjugate3
  implicit none
  private
  public :: nh_lame, nh_energy, nh_stress, nh_tangent, nh_discrete_stress, nh_c33, log1p_, gonzalez_stress, nh_mean_energy
  public :: nh_solid_energy, nh_solid_stress, nh_solid_tangent, nh_solid_discrete_stress

contains

  !> log(1 + x) accurate for small x (Goldberg: the rounding of 1 + x cancels out).
  pure real(dp) function log1p_(x)
    real(dp), intent(in) :: x
    real(dp) :: u
    u = 1.0_dp + x
    if (u == 1.0_dp) then
      log1p_ = x
    else
      log1p_ = log(u) * (x / (u - 1.0_dp))
    end if
  end function log1p_

  !> Lame constants (lambda, mu) of YOUNG and POISSON.
  pure function nh_lame(young, poisson) result(lm)
    real(dp), intent(in) :: young, poisson
    real(dp) :: lm(2)
    lm(2) = young / (2.0_dp * (1.0_dp + poisson))
    lm(1) = young * poisson / ((1.0_dp + poisson) * (1.0_dp - 2.0_dp * poisson))
  end function nh_lame

  !> det C - 1 and ln J of a strain e, without cancellation at small strain.
  pure subroutine det_parts(e, dm1, lnj)
    real(dp), intent(in) :: e(4)
    real(dp), intent(out) :: dm1, lnj
    dm1 = 2.0_dp * (e(1) + e(2)) + 4.0_dp * e(1) * e(2) - e(4)**2
    lnj = 0.5_dp * log1p_(dm1)
  end subroutine det_parts

  !> Stored energy per unit reference volume. Written as mu (tr E - ln J) + lambda/2 (ln J)^2 with
  !> tr E - ln J = ½ (tr C - 2 - log(det C)) taken from log1p's complement, so that a small strain
  !> keeps its relative accuracy.
  !> pstress: plane stress (psi at the C33 of S33 = 0: mu (tr E + (c - 1)/2 - ln J) + ...).
  pure real(dp) function nh_energy(lm, e, pstress) result(psi)
    real(dp), intent(in) :: lm(2), e(4)
    logical, intent(in), optional :: pstress
    real(dp) :: dm1, lnj, d
    call det_parts(e, dm1, lnj)
    d = 0.0_dp
    if (is_ps(pstress)) then
      d = nh_c33(lm, e)
      lnj = lnj + 0.5_dp * log1p_(d)
    end if
    psi = lm(2) * ((e(1) + e(2)) + 0.5_dp * d - lnj) + 0.5_dp * lm(1) * lnj**2
  end function nh_energy

  pure logical function is_ps(pstress)
    logical, intent(in), optional :: pstress
    is_ps = .false.
    if (present(pstress)) is_ps = pstress
  end function is_ps

  !> C^-1 (as xx, yy, xy) and ln J of a strain e.
  pure subroutine c_inverse(e, ci, lnj)
    real(dp), intent(in) :: e(4)
    real(dp), intent(out) :: ci(3), lnj
    real(dp) :: dm1, det
    call det_parts(e, dm1, lnj)
    det = 1.0_dp + dm1
    ci = [1.0_dp + 2.0_dp * e(2), 1.0_dp + 2.0_dp * e(1), -e(4)] / det
  end subroutine c_inverse

  !> Second Piola-Kirchhoff stress [xx, yy, zz, xy]. I - C^-1 = (C - I) C^-1 = 2 E C^-1 keeps a
  !> small strain's accuracy.
  !> Plane stress (pstress): S = mu (I - c C^-1) = mu 2 E C^-1 - mu (c - 1) C^-1, S33 = 0.
  pure function nh_stress(lm, e, pstress) result(s)
    real(dp), intent(in) :: lm(2), e(4)
    logical, intent(in), optional :: pstress
    real(dp) :: s(4), ci(3), lnj, exy, p
    call c_inverse(e, ci, lnj)
    exy = 0.5_dp * e(4)
    ! The isotropic part p C^-1: lambda ln J, or in plane stress -mu (c - 1).
    p = lm(1) * lnj
    if (is_ps(pstress)) p = -lm(2) * nh_c33(lm, e)
    ! 2 E C^-1 (symmetric for these commuting tensors): components xx, yy, xy.
    s(1) = lm(2) * 2.0_dp * (e(1) * ci(1) + exy * ci(3)) + p * ci(1)
    s(2) = lm(2) * 2.0_dp * (exy * ci(3) + e(2) * ci(2)) + p * ci(2)
    s(4) = lm(2) * 2.0_dp * (e(1) * ci(3) + exy * ci(2)) + p * ci(3)
    s(3) = lm(1) * lnj
    if (is_ps(pstress)) s(3) = 0.0_dp
  end function nh_stress

  !> dS/dE as a 4 x 4 matrix on [xx, yy, zz, 2xy] (the zz column zero: E33 = 0 in plane strain):
  !> C_IJKL = a Ci_IJ Ci_KL + g (Ci_IK Ci_JL + Ci_IL Ci_JK), Ci = C^-1, with a = lambda and
  !> g = mu - lambda ln J (plane strain), or, C33 = c following S33 = 0, a = mu lambda /
  !> (mu + lambda/(2c)) and g = mu c (plane stress; its zz row zero).
  pure function nh_tangent(lm, e, pstress) result(d)
    real(dp), intent(in) :: lm(2), e(4)
    logical, intent(in), optional :: pstress
    real(dp) :: d(4, 4), ci(3), lnj, g, a0, c
    integer, parameter :: ii(3) = [1, 2, 1], jj(3) = [1, 2, 2], row(3) = [1, 2, 4]
    real(dp) :: cm(2, 2)
    integer :: a, b
    call c_inverse(e, ci, lnj)
    cm = reshape([ci(1), ci(3), ci(3), ci(2)], [2, 2])
    a0 = lm(1)
    g = lm(2) - lm(1) * lnj
    if (is_ps(pstress)) then
      c = 1.0_dp + nh_c33(lm, e)
      a0 = lm(2) * lm(1) / (lm(2) + 0.5_dp * lm(1) / c)
      g = lm(2) * c
    end if
    d = 0.0_dp
    do a = 1, 3
      do b = 1, 3
        d(row(a), row(b)) = a0 * cm(ii(a), jj(a)) * cm(ii(b), jj(b)) + &
          g * (cm(ii(a), ii(b)) * cm(jj(a), jj(b)) + cm(ii(a), jj(b)) * cm(jj(a), ii(b)))
      end do
      if (.not. is_ps(pstress)) d(3, row(a)) = lm(1) * cm(ii(a), jj(a))
    end do
  end function nh_tangent

  !> The step's stress: S̄ = S(E_mid) + c ΔE^ (ΔE^ the tensor ΔE as [xx, yy, 0, xy]), c such that
  !> S̄ . ΔE = psi(E1) - psi(En) exactly (the strain vectors' dot product is S : ΔE). Δpsi is
  !> taken as a difference of terms that each keep the increment's accuracy; where the defect
  !> Δpsi - S(E_mid) . ΔE (of order |ΔE|^3) is below the round-off of those terms, c = 0 (the
  !> identity then holds to that round-off). Plane stress (pstress): Δpsi = psi(E1) - psi(En), the
  !> noise then that of psi itself.
  pure function nh_discrete_stress(lm, en, e1, pstress) result(sb)
    real(dp), intent(in) :: lm(2), en(4), e1(4)
    logical, intent(in), optional :: pstress
    real(dp) :: sb(4), de(4), sm(4), dn, d1, ln, l1, dlnj, dpsi, noise, psi1, psin
    de = e1 - en
    sm = nh_stress(lm, 0.5_dp * (en + e1), pstress)
    call det_parts(en, dn, ln)
    call det_parts(e1, d1, l1)
    ! ln J1 - ln Jn = ½ log1p_((det C1 - det Cn) / det Cn), det C1 - det Cn from the increments.
    dlnj = 0.5_dp * log1p_((2.0_dp * (de(1) + de(2)) + 4.0_dp * (de(1) * e1(2) + en(1) * de(2)) - de(4) * (e1(4) + en(4))) &
      / (1.0_dp + dn))
    dpsi = lm(2) * ((de(1) + de(2)) - dlnj) + 0.5_dp * lm(1) * (l1 + ln) * dlnj
    noise = 64.0_dp * epsilon(1.0_dp) * (lm(2) * (abs(de(1) + de(2)) + abs(dlnj)) + lm(1) * abs((l1 + ln) * dlnj) + &
      sum(abs(sm * de)))
    if (is_ps(pstress)) then
      psi1 = nh_energy(lm, e1, pstress)
      psin = nh_energy(lm, en, pstress)
      dpsi = psi1 - psin
      noise = 64.0_dp * epsilon(1.0_dp) * (abs(psi1) + abs(psin) + sum(abs(sm * de)))
    end if
    sb = gonzalez_stress(sm, de, dpsi, noise)
  end function nh_discrete_stress

  !> The step's stress S̄ on the Green-Lagrange increment de that does the work w: the mean
  !> sa of the end stresses plus Gonzalez's term along de (the tensor metric: shear halved), so
  !> that S̄ · de = w exactly and S̄ stays symmetric (angular momentum). The term is of the size of
  !> the trapezoid's error on the path, O(|de|²). w - sa·de below noise (the round-off of w and of
  !> sa·de: w comes from end values, Δψ or the law's work on a Δℓ that is the difference of two
  !> logarithms) is round-off, not a path error: divided by |de|² it would make S̄ explode on a
  !> step that barely strains, so S̄ = sa there (the work it leaves out is that round-off). The
  !> neo-Hookean discrete stress and STRAIN_MEASURE LOG's step stress (plane_point) use it.
  pure function gonzalez_stress(sa, de, w, noise) result(sbar)
    real(dp), intent(in) :: sa(4), de(4), w, noise
    real(dp) :: sbar(4)
    call gonzalez_n(4, sa, de, w, noise, sbar)
  end function gonzalez_stress

  !> gonzalez_stress on n = 4 (surfaces) or 6 (solids) components, the shears after the normals.
  pure subroutine gonzalez_n(n, sa, de, w, noise, sbar)
    integer, intent(in) :: n
    real(dp), intent(in) :: sa(n), de(n), w, noise
    real(dp), intent(out) :: sbar(n)
    real(dp) :: dd(6), den, gap             ! (a fixed size: no heap array in the laws' loop)
    dd(1:3) = de(1:3)
    dd(4:n) = 0.5_dp * de(4:n)
    den = dot_product(dd(1:n), de)
    gap = w - dot_product(sa, de)
    sbar = sa
    if (den > 0.0_dp .and. abs(gap) > noise) sbar = sa + (gap / den) * dd(1:n)
  end subroutine gonzalez_n

  !> 3D solids: the tensor 2E of a strain vector [xx, yy, zz, 2xy, 2yz, 2xz], det C - 1 = i1 + i2 + i3
  !> (the invariants of A = C - I = 2E: no cancellation at small strain), ln J, and C^-1.
  pure subroutine solid_parts(e, dm1, lnj, ci)
    real(dp), intent(in) :: e(6)
    real(dp), intent(out) :: dm1, lnj, ci(3, 3)
    real(dp) :: a(3, 3), c(3, 3), i1, i2, i3
    a = reshape([2.0_dp * e(1), e(4), e(6), e(4), 2.0_dp * e(2), e(5), e(6), e(5), 2.0_dp * e(3)], [3, 3])
    i1 = a(1, 1) + a(2, 2) + a(3, 3)
    i2 = a(1, 1) * a(2, 2) + a(2, 2) * a(3, 3) + a(1, 1) * a(3, 3) - a(1, 2)**2 - a(2, 3)**2 - a(1, 3)**2
    i3 = a(1, 1) * (a(2, 2) * a(3, 3) - a(2, 3)**2) - a(1, 2) * (a(1, 2) * a(3, 3) - a(2, 3) * a(1, 3)) + &
      a(1, 3) * (a(1, 2) * a(2, 3) - a(2, 2) * a(1, 3))
    dm1 = i1 + i2 + i3
    lnj = 0.5_dp * log1p_(dm1)
    c = a
    c(1, 1) = c(1, 1) + 1.0_dp
    c(2, 2) = c(2, 2) + 1.0_dp
    c(3, 3) = c(3, 3) + 1.0_dp
    ci = adjugate3(c)
    ci = ci / (1.0_dp + dm1)
  end subroutine solid_parts

  !> 3D: psi = mu (tr E - ln J) + lambda/2 (ln J)^2 per unit reference volume.
  pure real(dp) function nh_solid_energy(lm, e) result(psi)
    real(dp), intent(in) :: lm(2), e(6)
    real(dp) :: dm1, lnj, ci(3, 3)
    call solid_parts(e, dm1, lnj, ci)
    psi = lm(2) * ((e(1) + e(2) + e(3)) - lnj) + 0.5_dp * lm(1) * lnj**2
  end function nh_solid_energy

  !> 3D: S = mu 2E C^-1 + lambda ln J C^-1 (I - C^-1 = 2E C^-1, symmetric: E and C commute) as
  !> [xx, yy, zz, xy, yz, xz].
  pure function nh_solid_stress(lm, e) result(s)
    real(dp), intent(in) :: lm(2), e(6)
    real(dp) :: s(6), dm1, lnj, ci(3, 3), a(3, 3), m(3, 3)
    integer, parameter :: ii(6) = [1, 2, 3, 1, 2, 1], jj(6) = [1, 2, 3, 2, 3, 3]
    integer :: k
    call solid_parts(e, dm1, lnj, ci)
    a = reshape([2.0_dp * e(1), e(4), e(6), e(4), 2.0_dp * e(2), e(5), e(6), e(5), 2.0_dp * e(3)], [3, 3])
    m = matmul(a, ci)
    do k = 1, 6
      s(k) = lm(2) * 0.5_dp * (m(ii(k), jj(k)) + m(jj(k), ii(k))) + lm(1) * lnj * ci(ii(k), jj(k))
    end do
  end function nh_solid_stress

  !> 3D: dS/dE, 6 x 6 on [xx, yy, zz, 2xy, 2yz, 2xz]: C_IJKL = lambda Ci_IJ Ci_KL + g (Ci_IK Ci_JL +
  !> Ci_IL Ci_JK), g = mu - lambda ln J.
  pure function nh_solid_tangent(lm, e) result(d)
    real(dp), intent(in) :: lm(2), e(6)
    real(dp) :: d(6, 6), dm1, lnj, ci(3, 3), g
    integer, parameter :: ii(6) = [1, 2, 3, 1, 2, 1], jj(6) = [1, 2, 3, 2, 3, 3]
    integer :: a, b
    call solid_parts(e, dm1, lnj, ci)
    g = lm(2) - lm(1) * lnj
    do b = 1, 6
      do a = 1, 6
        d(a, b) = lm(1) * ci(ii(a), jj(a)) * ci(ii(b), jj(b)) + &
          g * (ci(ii(a), ii(b)) * ci(jj(a), jj(b)) + ci(ii(a), jj(b)) * ci(jj(a), ii(b)))
      end do
    end do
  end function nh_solid_tangent

  !> 3D: the step's stress S̄ = S(E_mid) + Gonzalez's term (gonzalez_n), S̄ . ΔE = psi(E1) - psi(En)
  !> exactly: Δpsi = mu (Δ tr E - Δ ln J) + lambda/2 (ln J1 + ln Jn) Δ ln J, Δ ln J = ½ log1p((det C1 -
  !> det Cn) / det Cn); the round-off of the difference of the two det C - 1 is in the noise.
  pure function nh_solid_discrete_stress(lm, en, e1) result(sb)
    real(dp), intent(in) :: lm(2), en(6), e1(6)
    real(dp) :: sb(6), de(6), sm(6), dn, d1, ln, l1, dlnj, dpsi, noise, ci(3, 3)
    de = e1 - en
    sm = nh_solid_stress(lm, 0.5_dp * (en + e1))
    call solid_parts(en, dn, ln, ci)
    call solid_parts(e1, d1, l1, ci)
    dlnj = 0.5_dp * log1p_((d1 - dn) / (1.0_dp + dn))
    dpsi = lm(2) * ((de(1) + de(2) + de(3)) - dlnj) + 0.5_dp * lm(1) * (l1 + ln) * dlnj
    noise = 64.0_dp * epsilon(1.0_dp) * (lm(2) * (abs(de(1) + de(2) + de(3)) + abs(dlnj)) + &
      lm(1) * abs((l1 + ln) * dlnj) + sum(abs(sm * de)) + (lm(2) + lm(1) * abs(l1 + ln)) * (abs(d1) + abs(dn)))
    call gonzalez_n(6, sm, de, dpsi, noise, sb)
  end function nh_solid_discrete_stress

  !> The energy of a plane-strain element under FORMULATION BBAR (docs/locking.md): its points' ψ
  !> with the volumetric term on the element's mean ln J, Σ w [μ/2 (tr C - 3) - μ ln J] + Σ w λ/2 <ln J>²,
  !> <ln J> = Σ w ln J / Σ w (weights w, Green-Lagrange strains e(1:4, :)).
  pure real(dp) function nh_mean_energy(lm, w, e) result(psi)
    real(dp), intent(in) :: lm(2), w(:), e(:, :)
    real(dp) :: lnj
    integer :: k
    psi = 0.0_dp
    lnj = 0.0_dp
    do k = 1, size(w)
      psi = psi + w(k) * nh_energy([0.0_dp, lm(2)], e(1:4, k), .false.)
      lnj = lnj + w(k) * 0.5_dp * log1p_(2.0_dp * (e(1, k) + e(2, k)) + 4.0_dp * e(1, k) * e(2, k) - e(4, k)**2)
    end do
    psi = psi + 0.5_dp * lm(1) * lnj**2 / sum(w)
  end function nh_mean_energy

  !> Plane stress: C33 - 1 of a strain e, the root of mu (c - 1) + lambda/2 (ln det C + ln c) = 0
  !> (increasing in c: one root), by Newton on d = c - 1 from 0 (quadratic; converged to 4 ulps).
  pure real(dp) function nh_c33(lm, e) result(d)
    real(dp), intent(in) :: lm(2), e(4)
    real(dp) :: dm1, lnj2, f, fp, step
    integer :: it
    call det_parts(e, dm1, lnj2)
    d = 0.0_dp
    do it = 1, 60
      f = lm(2) * d + lm(1) * (lnj2 + 0.5_dp * log1p_(d))
      fp = lm(2) + 0.5_dp * lm(1) / (1.0_dp + d)
      step = f / fp
      d = max(d - step, -1.0_dp + 1.0e-300_dp)
      if (abs(step) <= 4.0_dp * epsilon(1.0_dp) * (1.0_dp + abs(d))) exit
    end do
  end function nh_c33
end module law_hyperelastic
