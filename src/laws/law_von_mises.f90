!> J2 (von Mises) plasticity for plane strain and plane stress, with linear isotropic (h_iso)
!> and kinematic (h_kin) hardening, calibrated so that a uniaxial stress path reproduces the
!> 1D bilinear law: slope d sigma / d eps_p = h_iso + h_kin after yield at sy.
!> Vectors have 4 components (xx, yy, zz, xy; plane and axisymmetric points) or 6 (xx, yy, zz, xy, yz,
!> xz; 3D solids), nc = their size; strains carry the engineering shears, stress-like vectors
!> (stress, back stress) the tensor components.
!> Yield: f = sqrt(3/2) |dev(sigma) - beta| - (sy + h_iso alpha), |s|^2 = sxx^2+syy^2+szz^2+2 sxy^2.
!> Flow: d eps_p = dlam n, n = xi/|xi|; d alpha = sqrt(2/3) dlam; d beta = (2/3) h_kin d eps_p.
!> One increment is the closed-form radial return (backward Euler, exact for proportional
!> loading). Plane strain: ezz = 0, szz from the law. Plane stress: the 3D return is applied and
!> szz = 0 is enforced by a local Newton iteration on the increment of ezz, using the zz-zz entry
!> of the consistent tangent; the total ezz is kept in the state, the tangent is the 3D consistent
!> tangent statically condensed on szz = 0.
!> State q (vm_state_size(nc): 10 for 4 components, VM_NSTATE; 14 for 6): q(1:nc) plastic strain
!> (engineering shear), q(nc+1) alpha (accumulated equivalent plastic strain), q(nc+2:2nc+1) back
!> stress (deviatoric), q(2nc+2) total ezz (plane stress; 0 otherwise).
module law_von_mises
  use kinds, only: dp
  use subincrement, only: return_map_t, subincrement_path
  use law_types, only: law_params_t, law_step_t, law_step_reset
  implicit none
  private
  public :: VM_NSTATE, vm_d3, vm_dps, vm_return, vm_path, vm_trial_ratio, vm_stored, vm_map_t
  public :: vm_state_size, vm_alpha_index

  integer, parameter :: VM_NSTATE = 10               !< the state of a 4-component point (vm_state_size(4))
  integer, parameter :: NCMAX = 6
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

  !> The state size of a point with nc stress components: plastic strain, alpha, back stress, ezz.
  pure integer function vm_state_size(nc)
    integer, intent(in) :: nc
    vm_state_size = 2 * nc + 2
  end function vm_state_size

  !> Where alpha (the accumulated equivalent plastic strain) is in the state of nc components.
  pure integer function vm_alpha_index(nc)
    integer, intent(in) :: nc
    vm_alpha_index = nc + 1
  end function vm_alpha_index

  !> The trial stress s(1:nc) = s_n + D de (nc = 4 or 6) and the relative stress xi = dev(s) - beta
  !> (beta = q(nc+2:2nc+1)); explicit shapes and constant sizes: the laws run at every point of every
  !> iteration.
  pure subroutine trial_state(nc, ldd, d, de, s_n, q, s, xi)
    integer, intent(in) :: nc, ldd                              ! (ldd: d's leading dimension, >= nc)
    real(dp), intent(in) :: d(ldd, nc), de(nc), s_n(nc), q(2 * nc + 2)
    real(dp), intent(out) :: s(nc), xi(nc)
    real(dp) :: pm
    integer :: i
    if (nc == 4) then             ! (constant sizes: the product unrolled)
      s(1:4) = s_n(1:4) + matmul(d(1:4, 1:4), de(1:4))
    else
      s(1:6) = s_n(1:6) + matmul(d(1:6, 1:6), de(1:6))
    end if
    pm = (s(1) + s(2) + s(3)) / 3.0_dp
    do i = 1, 3
      xi(i) = (s(i) - pm) - q(nc + 1 + i)
    end do
    do i = 4, nc
      xi(i) = s(i) - q(nc + 1 + i)
    end do
  end subroutine trial_state

  !> Tensor norm |s| of a stress-like nc-vector (each shear entry counts twice).
  pure real(dp) function norm_nc(nc, s)
    integer, intent(in) :: nc
    real(dp), intent(in) :: s(nc)
    real(dp) :: t
    integer :: i
    t = s(4)**2
    do i = 5, nc
      t = t + s(i)**2
    end do
    norm_nc = sqrt(s(1)**2 + s(2)**2 + s(3)**2 + 2.0_dp * t)
  end function norm_nc

  !> Isotropic 3D elasticity on (xx, yy, zz, gamma_xy[, gamma_yz, gamma_xz]): 4 x 4, the plane-strain
  !> D, or the whole 6 x 6 (size(d, 1)).
  pure subroutine vm_d3(e, nu, d)
    real(dp), intent(in) :: e, nu
    real(dp), intent(out) :: d(:, :)
    real(dp) :: t(NCMAX, NCMAX)
    call d3_full(e, nu, t)
    d = t(1:size(d, 1), 1:size(d, 2))
  end subroutine vm_d3

  !> vm_d3's whole 6 x 6 (a fixed shape: the return map builds it at every sub-increment).
  pure subroutine d3_full(e, nu, d)
    real(dp), intent(in) :: e, nu
    real(dp), intent(out) :: d(NCMAX, NCMAX)
    real(dp) :: lam, mu
    integer :: i
    mu = e / (2.0_dp * (1.0_dp + nu))
    lam = e * nu / ((1.0_dp + nu) * (1.0_dp - 2.0_dp * nu))
    d = 0.0_dp
    d(1:3, 1:3) = lam
    d(1, 1) = lam + 2.0_dp * mu
    d(2, 2) = lam + 2.0_dp * mu
    d(3, 3) = lam + 2.0_dp * mu
    do i = 4, NCMAX
      d(i, i) = mu
    end do
  end subroutine d3_full

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
    real(dp), intent(in) :: d_el(:, :), deps(:), sy
    real(dp) :: t(NCMAX), dv(NCMAX)
    real(dp) :: z(2 * NCMAX + 2)
    z = 0.0_dp
    call trial_state(size(deps), size(d_el, 1), d_el, deps, z, z, t, dv)
    vm_trial_ratio = sqrt(1.5_dp) * norm_nc(size(deps), dv) / sy
  end function vm_trial_ratio

  !> Recoverable energy 1/2 sigma . C^-1 sigma (isotropic compliance; szz = 0 in plane stress).
  pure real(dp) function vm_stored(e, nu, sig)
    real(dp), intent(in) :: e, nu, sig(:)
    real(dp) :: t
    integer :: i
    t = sig(4)**2
    do i = 5, size(sig)
      t = t + sig(i)**2
    end do
    vm_stored = 0.5_dp * ((sig(1)**2 + sig(2)**2 + sig(3)**2 &
      - 2.0_dp * nu * (sig(1) * sig(2) + sig(2) * sig(3) + sig(3) * sig(1))) / e &
      + 2.0_dp * (1.0_dp + nu) * t / e)
  end function vm_stored

  !> One 3D increment de (zz entry included) from (sig_n, q_n), nc = 4 or 6 components: elastic
  !> predictor with d3, radial return. dep: plastic strain increment (engineering shear); cep:
  !> consistent tangent. (Explicit shapes: it runs at every sub-increment of every yielding point.)
  pure subroutine vm_return(p, nc, sig_n, q_n, de, sig, q, dep, cep)
    type(law_params_t), intent(in) :: p
    integer, intent(in) :: nc
    real(dp), intent(in) :: sig_n(nc), q_n(2 * nc + 2), de(nc)
    real(dp), intent(out) :: sig(nc), q(2 * nc + 2), dep(nc), cep(nc, nc)
    real(dp) :: d3(NCMAX, NCMAX), str(NCMAX), xi(NCMAX), n(NCMAX), nrm, f, g, kb, dpeq, dlam, th, thb, e, nu, sy, hi, hk
    integer :: i, j, ia, ib
    ia = vm_alpha_index(nc)
    ib = ia + 1                                  ! the back stress: q(ib:ib + nc - 1)
    e = p%young
    nu = p%poisson
    sy = p%yield
    hi = p%h_iso
    hk = p%h_kin
    call d3_full(e, nu, d3)                      ! (the 6 x 6; plane strain's D is its leading 4 x 4)
    call trial_state(nc, NCMAX, d3, de, sig_n, q_n, str, xi)
    nrm = norm_nc(nc, xi)
    f = sqrt(1.5_dp) * nrm - (sy + hi * q_n(ia))
    q = q_n
    if (f <= 0.0_dp) then
      sig = str(1:nc)
      dep = 0.0_dp
      cep = d3(1:nc, 1:nc)
      return
    end if
    g = e / (2.0_dp * (1.0_dp + nu))
    kb = e / (3.0_dp * (1.0_dp - 2.0_dp * nu))
    dpeq = f / (3.0_dp * g + hi + hk)
    dlam = sqrt(1.5_dp) * dpeq
    n(1:nc) = xi(1:nc) / nrm
    sig = str(1:nc) - 2.0_dp * g * dlam * n(1:nc)
    dep(1:3) = dlam * n(1:3)
    dep(4:nc) = dlam * (2.0_dp * n(4:nc))
    q(1:nc) = q_n(1:nc) + dep
    q(ia) = q_n(ia) + dpeq
    q(ib:ib + nc - 1) = q_n(ib:ib + nc - 1) + (2.0_dp / 3.0_dp) * hk * dlam * n(1:nc)
    ! C = K 1x1 + 2G th Idev - 2G thb n x n (Simo-Hughes box 3.2 with kinematic hardening);
    ! in Voigt form the gamma columns act on 2 eps_ij, so Idev(i,i) = 1/2 there and n x n has no factor.
    th = 1.0_dp - 2.0_dp * g * dlam / nrm
    thb = 3.0_dp * g / (3.0_dp * g + hi + hk) - 2.0_dp * g * dlam / nrm
    cep = 0.0_dp
    do j = 1, 3
      do i = 1, 3
        cep(i, j) = kb - 2.0_dp * g * th / 3.0_dp
      end do
      cep(j, j) = cep(j, j) + 2.0_dp * g * th
    end do
    do i = 4, nc
      cep(i, i) = g * th
    end do
    do j = 1, nc
      do i = 1, nc
        cep(i, j) = cep(i, j) - 2.0_dp * g * thb * n(i) * n(j)
      end do
    end do
  end subroutine vm_return

  !> One plane-stress increment: (de(1), de(2), de(4)) given, de(3) solved for szz = 0.
  pure subroutine vm_return_ps(p, sig_n, q_n, de, sig, q, dep, ctan)
    type(law_params_t), intent(in) :: p
    real(dp), intent(in) :: sig_n(4), q_n(:), de(4)
    real(dp), intent(out) :: sig(4), q(:), dep(4), ctan(4, 4)
    real(dp) :: d3(4, 4), cep(4, 4), z, d33(4)   ! (plane stress: 4 components)
    integer :: it, i, j
    call vm_d3(p%young, p%poisson, d3)
    z = -(sig_n(3) + d3(3, 1) * de(1) + d3(3, 2) * de(2) + d3(3, 4) * de(4)) / d3(3, 3)
    do it = 1, PS_MAXIT
      d33 = [de(1), de(2), z, de(4)]
      call vm_return(p, 4, sig_n, q_n, d33, sig, q, dep, cep)
      if (abs(sig(3)) <= PS_RTOL * (p%yield + norm_nc(4, sig))) exit
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
    real(dp) :: d(NCMAX)
    d(1:ns) = de(1:ns)
    if (self%plane_stress) then
      d(3) = 0.0_dp
      call vm_return_ps(self%p, s0, q0, d(1:4), s1, q1, dep, dtan)
    else
      call vm_return(self%p, ns, s0, q0, d(1:ns), s1, q1, dep, dtan)
    end if
  end subroutine vm_step

  !> Straight strain path deps in nsub >= 1 sub-increments (see law_plastic_1d's plastic_1d_path
  !> for the conventions): whole-step elastic check with the elastic matrix d_el (plane strain or
  !> plane stress D) and the frozen state -> exact chord, nused = 0; else subincrement_path:
  !> trapezoid mean stress, trapezoid dissipation sum 1/2 (sig_{k-1} + sig_k) . dep_k, and the
  !> consistent tangent of one return over the whole increment (below).
  pure subroutine vm_path(p, plane_stress, nsub, nc, d_el, sig_n, q_n, deps, q, r)
    type(law_params_t), intent(in) :: p
    integer, intent(in) :: nc                       !< stress components: 4, or 6 (3D)
    real(dp), intent(in) :: d_el(nc, nc), sig_n(nc), q_n(:), deps(nc)   ! (explicit shapes: the hot path's loops)
    logical, intent(in) :: plane_stress
    integer, intent(in) :: nsub
    real(dp), intent(out) :: q(:)
    type(law_step_t), intent(out) :: r
    real(dp) :: qn(2 * NCMAX + 2), qk(2 * NCMAX + 2), s1(NCMAX), q1(2 * NCMAX + 2), dep(NCMAX), d(NCMAX), &
      cel(NCMAX, NCMAX), eps0(NCMAX), nu, g, xi(NCMAX), dt4(4, 4), de(NCMAX), sn(NCMAX)
    integer :: ns, ia, i
    call law_step_reset(r)
    ns = vm_state_size(nc)
    ia = vm_alpha_index(nc)
    call trial_state(nc, nc, d_el, deps, sig_n, q_n, r%sig, xi)
    if (sqrt(1.5_dp) * norm_nc(nc, xi) - (p%yield + p%h_iso * q_n(ia)) <= 0.0_dp) then
      r%sigbar(1:nc) = 0.5_dp * (sig_n + r%sig(1:nc))
      q(1:ns) = q_n(1:ns)
      if (plane_stress) q(10) = q_n(10) - p%poisson / (1.0_dp - p%poisson) * (deps(1) + deps(2))
      r%dtan(1:nc, 1:nc) = d_el
      return
    end if
    r%nused = max(1, nsub)
    qn(1:ns) = q_n(1:ns)             ! contiguous locals: no temporary at the calls
    de(1:nc) = deps
    sn(1:nc) = sig_n
    eps0 = 0.0_dp
    if (plane_stress) then
      call subincrement_path(vm_map_t(p, plane_stress), r%nused, eps0(1:4), &
        de(1:4), sn(1:4), qn(1:ns), r%sig(1:4), r%sigbar(1:4), qk(1:ns), r%dissip, dt4, r%dbar(1:4, 1:4))
      r%dtan(1:4, 1:4) = dt4
    else
      ! The isotropic compliance on [xx, yy, zz, 2xy[, 2yz, 2xz]] (the trial of every sub-increment's return).
      nu = p%poisson
      g = 0.5_dp * p%young / (1.0_dp + nu)
      cel = 0.0_dp
      cel(1:3, 1:3) = -nu / p%young
      cel(1, 1) = 1.0_dp / p%young
      cel(2, 2) = cel(1, 1)
      cel(3, 3) = cel(1, 1)
      do i = 4, nc
        cel(i, i) = 1.0_dp / g
      end do
      if (nc == 4) then                          ! (a contiguous tangent: no copy at the call)
        call subincrement_path(vm_map_t(p, plane_stress), r%nused, eps0(1:4), &
          de(1:4), sn(1:4), qn(1:ns), r%sig(1:4), r%sigbar(1:4), qk(1:ns), r%dissip, dt4, r%dbar(1:4, 1:4), &
          cel(1:4, 1:4))
        r%dtan(1:4, 1:4) = dt4
      else
        call subincrement_path(vm_map_t(p, plane_stress), r%nused, eps0(1:nc), &
          de(1:nc), sn(1:nc), qn(1:ns), r%sig(1:nc), r%sigbar(1:nc), qk(1:ns), r%dissip, r%dtan, r%dbar, cel(1:nc, 1:nc))
      end if
    end if
    q(1:ns) = qk(1:ns)
    ! The iteration's tangent: the consistent tangent of one return over the whole increment. The
    ! last sub-increment's, the tangent of a step N times smaller, misses how the flow direction turns
    ! with the increment (the 2 mu dgamma / |xi| part): with AUTO's sub-increments Newton took 30
    ! iterations per step on inputs/taylor_plane.dat where one return needs 7 (nothing changes for N = 1).
    ! With the correction of eq (9) the forces are 2Bσ̄ - Bσ(n): their tangent dbar weighs each
    ! sub-increment's (k/N): an increment that yields half-way is stiffer than its end tangent
    ! (Newton contracted by 0.6 per iteration on the 8 x 40 Taylor bar with the end tangent alone).
    if (r%nused > 1) then
      d(1:nc) = deps
      if (plane_stress) then                     ! (contiguous tangents: no copy at the calls)
        d(3) = 0.0_dp
        call vm_return_ps(p, sn(1:4), qn, d(1:4), s1(1:4), q1, dep(1:4), dt4)
        r%dtan(1:4, 1:4) = dt4
      else if (nc == 4) then
        call vm_return(p, 4, sn(1:4), qn, d(1:4), s1(1:4), q1, dep(1:4), dt4)
        r%dtan(1:4, 1:4) = dt4
      else
        call vm_return(p, 6, sn(1:6), qn, d(1:6), s1(1:6), q1, dep(1:6), r%dtan)
      end if
    end if
    ! (The chain X_k = D_k (cel X_(k-1) + I/N) is not symmetric: dbar is left whole; the callers
    ! assemble its symmetric part (sym_part) in the tangent and its antisymmetric one apart (add_anti),
    ! for iterate_eq9's anti_sweep.)
    r%has_dbar = .true.
  end subroutine vm_path
end module law_von_mises
