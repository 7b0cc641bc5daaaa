!> J2 (von Mises) plasticity for plane strain and plane stress, with linear isotropic (h_iso)
!> and kinematic (h_kin) hardening, calibrated so that a uniaxial stress path reproduces the
!> 1D bilinear law: slope d sigma / d eps_p = h_iso + h_kin after yield at sy.
!> Vectors have 4 components (xx, yy, zz, xy); strains carry the engineering shear gamma_xy,
!> stress-like vectors (stress, back stress) the tensor xy component.
!> Yield: f = sqrt(3/2) |dev(sigma) - beta| - (sy + h_iso alpha), |s|^2 = sxx^2+syy^2+szz^2+2 sxy^2.
!> Flow: d eps_p = dlam n, n = xi/|xi|; d alpha = sqrt(2/3) dlam; d beta = (2/3) h_kin d eps_p.
!> One increment is the closed-form radial return (backward Euler, exact for proportional
!> loading). Plane strain: ezz = 0, szz from the law. Plane stress: the 3D return is applied and
!> szz = 0 is enforced by a local Newton iteration on the increment of ezz, using the zz-zz entry
!> of the consistent tangent; the total ezz is kept in the state, the tangent is the 3D consistent
!> tangent statically condensed on szz = 0.
!> State q (VM_NSTATE = 10): q(1:4) plastic strain (engineering shear), q(5) alpha (accumulated
!> equivalent plastic strain), q(6:9) back stress (deviatoric), q(10) total ezz (plane stress; 0 in
!> plane strain).
module law_von_mises
  use kinds, only: dp
  use subincrement, only: return_map_t, subincrement_path
  use law_types, only: law_params_t, law_step_t
  implicit none
  private
  public :: VM_NSTATE, vm_d3, vm_dps, vm_return, vm_path, vm_trial_ratio, vm_stored, vm_dev, vm_norm, vm_map_t

  integer, parameter :: VM_NSTATE = 10
  integer, parameter :: PS_MAXIT = 50                 !< plane stress: Newton iterations on ezz
  real(dp), parameter :: PS_RTOL = 1.0e-13_dp         !< plane stress: |szz| <= PS_RTOL (sy + |sigma|)

  !> The law's one-step map for the sub-incrementation.
  type, extends(return_map_t) :: vm_map_t
    type(law_params_t) :: p
    logical :: plane_stress = .false.
  contains
    procedure :: step => vm_step
  end type vm_map_t

contains

  !> Deviator of a stress-like 4-vector.
  pure function vm_dev(s) result(d)
    real(dp), intent(in) :: s(4)
    real(dp) :: d(4), p
    p = (s(1) + s(2) + s(3)) / 3.0_dp
    d = [s(1) - p, s(2) - p, s(3) - p, s(4)]
  end function vm_dev

  !> Tensor norm of a stress-like 4-vector (the xy entry counts twice).
  pure real(dp) function vm_norm(s)
    real(dp), intent(in) :: s(4)
    vm_norm = sqrt(s(1)**2 + s(2)**2 + s(3)**2 + 2.0_dp * s(4)**2)
  end function vm_norm

  !> Isotropic 3D elasticity restricted to (xx, yy, zz, gamma_xy): the plane-strain D.
  pure subroutine vm_d3(e, nu, d)
    real(dp), intent(in) :: e, nu
    real(dp), intent(out) :: d(4, 4)
    real(dp) :: lam, mu
    mu = e / (2.0_dp * (1.0_dp + nu))
    lam = e * nu / ((1.0_dp + nu) * (1.0_dp - 2.0_dp * nu))
    d = 0.0_dp
    d(1:3, 1:3) = lam
    d(1, 1) = lam + 2.0_dp * mu
    d(2, 2) = lam + 2.0_dp * mu
    d(3, 3) = lam + 2.0_dp * mu
    d(4, 4) = mu
  end subroutine vm_d3

  !> Plane-stress D (szz = 0: zz row and column zero), as elements' quad_elastic_d.
  pure subroutine vm_dps(e, nu, d)
    real(dp), intent(in) :: e, nu
    real(dp), intent(out) :: d(4, 4)
    real(dp) :: f
    f = e / (1.0_dp - nu**2)
    d = 0.0_dp
    d(1, 1) = f
    d(2, 2) = f
    d(1, 2) = f * nu
    d(2, 1) = f * nu
    d(4, 4) = e / (2.0_dp * (1.0_dp + nu))
  end subroutine vm_dps

  !> Trial stress increment d_el deps in yield stresses (von Mises equivalent / sy): the
  !> measure of the AUTO rule.
  pure real(dp) function vm_trial_ratio(d_el, deps, sy)
    real(dp), intent(in) :: d_el(4, 4), deps(4), sy
    vm_trial_ratio = sqrt(1.5_dp) * vm_norm(vm_dev(matmul(d_el, deps))) / sy
  end function vm_trial_ratio

  !> Recoverable energy 1/2 sigma . C^-1 sigma (isotropic compliance; szz = 0 in plane stress).
  pure real(dp) function vm_stored(e, nu, sig)
    real(dp), intent(in) :: e, nu, sig(4)
    vm_stored = 0.5_dp * ((sig(1)**2 + sig(2)**2 + sig(3)**2 &
      - 2.0_dp * nu * (sig(1) * sig(2) + sig(2) * sig(3) + sig(3) * sig(1))) / e &
      + 2.0_dp * (1.0_dp + nu) * sig(4)**2 / e)
  end function vm_stored

  !> One 3D increment de (zz entry included) from (sig_n, q_n): elastic predictor with d3, radial
  !> return. dep: plastic strain increment (engineering shear); cep: consistent tangent.
  pure subroutine vm_return(p, sig_n, q_n, de, sig, q, dep, cep)
    type(law_params_t), intent(in) :: p
    real(dp), intent(in) :: sig_n(4), q_n(:), de(4)
    real(dp), intent(out) :: sig(4), q(:), dep(4), cep(4, 4)
    real(dp) :: d3(4, 4), str(4), xi(4), n(4), nrm, f, g, kb, dpeq, dlam, th, thb, e, nu, sy, hi, hk
    integer :: i, j
    e = p%young
    nu = p%poisson
    sy = p%yield
    hi = p%h_iso
    hk = p%h_kin
    call vm_d3(e, nu, d3)
    str = sig_n + matmul(d3, de)
    xi = vm_dev(str) - q_n(6:9)
    nrm = vm_norm(xi)
    f = sqrt(1.5_dp) * nrm - (sy + hi * q_n(5))
    q(1:VM_NSTATE) = q_n(1:VM_NSTATE)
    if (f <= 0.0_dp) then
      sig = str
      dep = 0.0_dp
      cep = d3
      return
    end if
    g = e / (2.0_dp * (1.0_dp + nu))
    kb = e / (3.0_dp * (1.0_dp - 2.0_dp * nu))
    dpeq = f / (3.0_dp * g + hi + hk)
    dlam = sqrt(1.5_dp) * dpeq
    n = xi / nrm
    sig = str - 2.0_dp * g * dlam * n
    dep = dlam * [n(1), n(2), n(3), 2.0_dp * n(4)]
    q(1:4) = q_n(1:4) + dep
    q(5) = q_n(5) + dpeq
    q(6:9) = q_n(6:9) + (2.0_dp / 3.0_dp) * hk * dlam * n
    ! C = K 1x1 + 2G th Idev - 2G thb n x n (Simo-Hughes box 3.2 with kinematic hardening);
    ! in Voigt form the gamma column acts on 2 eps_xy, so Idev(4,4) = 1/2 and n x n has no factor.
    th = 1.0_dp - 2.0_dp * g * dlam / nrm
    thb = 3.0_dp * g / (3.0_dp * g + hi + hk) - 2.0_dp * g * dlam / nrm
    cep = 0.0_dp
    do j = 1, 3
      do i = 1, 3
        cep(i, j) = kb - 2.0_dp * g * th / 3.0_dp
      end do
      cep(j, j) = cep(j, j) + 2.0_dp * g * th
    end do
    cep(4, 4) = g * th
    do j = 1, 4
      do i = 1, 4
        cep(i, j) = cep(i, j) - 2.0_dp * g * thb * n(i) * n(j)
      end do
    end do
  end subroutine vm_return

  !> One plane-stress increment: (de(1), de(2), de(4)) given, de(3) solved for szz = 0.
  pure subroutine vm_return_ps(p, sig_n, q_n, de, sig, q, dep, ctan)
    type(law_params_t), intent(in) :: p
    real(dp), intent(in) :: sig_n(4), q_n(:), de(4)
    real(dp), intent(out) :: sig(4), q(:), dep(4), ctan(4, 4)
    real(dp) :: d3(4, 4), cep(4, 4), z, d33(4)
    integer :: it, i, j
    call vm_d3(p%young, p%poisson, d3)
    z = -(sig_n(3) + d3(3, 1) * de(1) + d3(3, 2) * de(2) + d3(3, 4) * de(4)) / d3(3, 3)
    do it = 1, PS_MAXIT
      d33 = [de(1), de(2), z, de(4)]
      call vm_return(p, sig_n, q_n, d33, sig, q, dep, cep)
      if (abs(sig(3)) <= PS_RTOL * (p%yield + vm_norm(sig))) exit
      z = z - sig(3) / cep(3, 3)
    end do
    sig(3) = 0.0_dp
    q(10) = q_n(10) + z
    ctan = 0.0_dp
    do j = 1, 4
      if (j == 3) cycle
      do i = 1, 4
        if (i == 3) cycle
        ctan(i, j) = cep(i, j) - cep(i, 3) * cep(3, j) / cep(3, 3)
      end do
    end do
  end subroutine vm_return_ps

  !> One sub-increment (return_map_t): vm_return, or vm_return_ps in plane stress (whose
  !> through-thickness strain is an unknown: de(3) is not used).
  pure subroutine vm_step(self, ns, nq, k, n, eps_n, deps, de, s0, q0, s1, q1, dep, dtan)
    class(vm_map_t), intent(in) :: self
    integer, intent(in) :: ns, nq, k, n
    real(dp), intent(in) :: eps_n(ns), deps(ns), de(ns), s0(ns), q0(nq)
    real(dp), intent(out) :: s1(ns), q1(nq), dep(ns), dtan(ns, ns)
    real(dp) :: d(4)
    d = de(1:4)
    if (self%plane_stress) then
      d(3) = 0.0_dp
      call vm_return_ps(self%p, s0, q0, d, s1, q1, dep, dtan)
    else
      call vm_return(self%p, s0, q0, d, s1, q1, dep, dtan)
    end if
  end subroutine vm_step

  !> Straight strain path deps in nsub >= 1 sub-increments (see law_plastic_1d's plastic_1d_path
  !> for the conventions): whole-step elastic check with the elastic matrix d_el (plane strain or
  !> plane stress D) and the frozen state -> exact chord, nused = 0; else subincrement_path:
  !> trapezoid mean stress, trapezoid dissipation sum 1/2 (sig_{k-1} + sig_k) . dep_k, and the
  !> consistent tangent of one return over the whole increment (below).
  pure subroutine vm_path(p, plane_stress, nsub, d_el, sig_n, q_n, deps, q, r)
    type(law_params_t), intent(in) :: p
    real(dp), intent(in) :: d_el(4, 4), sig_n(4), q_n(:), deps(4)
    logical, intent(in) :: plane_stress
    integer, intent(in) :: nsub
    real(dp), intent(out) :: q(:)
    type(law_step_t), intent(out) :: r
    real(dp) :: qn(VM_NSTATE), qk(VM_NSTATE), s1(4), q1(VM_NSTATE), dep(4), d(4), cel(4, 4), nu, g
    r%sig = sig_n + matmul(d_el, deps)
    if (sqrt(1.5_dp) * vm_norm(vm_dev(r%sig) - q_n(6:9)) - (p%yield + p%h_iso * q_n(5)) <= 0.0_dp) then
      r%sigbar = 0.5_dp * (sig_n + r%sig)
      q(1:VM_NSTATE) = q_n(1:VM_NSTATE)
      if (plane_stress) q(10) = q_n(10) - p%poisson / (1.0_dp - p%poisson) * (deps(1) + deps(2))
      r%dtan = d_el
      return
    end if
    r%nused = max(1, nsub)
    qn = q_n(1:VM_NSTATE)            ! contiguous locals: no temporary at the call
    if (plane_stress) then
      call subincrement_path(vm_map_t(p, plane_stress), r%nused, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], &
        deps, sig_n, qn, r%sig, r%sigbar, qk, r%dissip, r%dtan, r%dbar(1:4, 1:4))
    else
      ! The isotropic compliance on [xx, yy, zz, 2xy] (the trial of every sub-increment's return).
      nu = p%poisson
      g = 0.5_dp * p%young / (1.0_dp + nu)
      cel = 0.0_dp
      cel(1:3, 1:3) = -nu / p%young
      cel(1, 1) = 1.0_dp / p%young
      cel(2, 2) = cel(1, 1)
      cel(3, 3) = cel(1, 1)
      cel(4, 4) = 1.0_dp / g
      call subincrement_path(vm_map_t(p, plane_stress), r%nused, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], &
        deps, sig_n, qn, r%sig, r%sigbar, qk, r%dissip, r%dtan, r%dbar(1:4, 1:4), cel)
    end if
    q(1:VM_NSTATE) = qk
    ! The iteration's tangent: the consistent tangent of one return over the whole increment. The
    ! last sub-increment's, the tangent of a step N times smaller, misses how the flow direction turns
    ! with the increment (the 2 mu dgamma / |xi| part): with AUTO's sub-increments Newton took 30
    ! iterations per step on inputs/taylor_plane.dat where one return needs 7 (nothing changes for N = 1).
    ! With the correction of eq (9) the forces are 2Bσ̄ - Bσ(n): their tangent dbar weighs each
    ! sub-increment's (k/N): an increment that yields half-way is stiffer than its end tangent
    ! (Newton contracted by 0.6 per iteration on the 8 x 40 Taylor bar with the end tangent alone).
    if (r%nused > 1) then
      d = deps
      if (plane_stress) then
        d(3) = 0.0_dp
        call vm_return_ps(p, sig_n, q_n, d, s1, q1, dep, r%dtan)
      else
        call vm_return(p, sig_n, q_n, d, s1, q1, dep, r%dtan)
      end if
    end if
    ! (The chain X_k = D_k (cel X_(k-1) + I/N) is not symmetric: its symmetric part, as the
    ! iteration matrix takes it; half of each would depend on the equations' order.)
    r%dbar(1:4, 1:4) = 0.5_dp * (r%dbar(1:4, 1:4) + transpose(r%dbar(1:4, 1:4)))
    r%has_dbar = .true.
  end subroutine vm_path
end module law_von_mises
