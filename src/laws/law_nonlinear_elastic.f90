!> Uniaxial nonlinear (cubic) elasticity: sigma = E eps (1 + b eps^2), energy density
!> psi = E (eps^2/2 + b eps^4/4), tangent E (1 + 3 b eps^2). No internal variables: the stress
!> depends on the end strain only, but the path-mean stress of eq (9) needs the sub-increments.
!> Because sigma is a cubic, the composite trapezoid rule has the exact error (Euler-Maclaurin
!> stops after its first term)
!>   W_N - (psi(eps1) - psi(eps0)) = (deps/N)^2 / 12 * (sigma'(eps1) - sigma'(eps0)),
!> which the AUTO rule inverts to pick N for a relative tolerance.
module law_nonlinear_elastic
  use kinds, only: dp
  use subincrement, only: return_map_t, subincrement_path
  implicit none
  private
  public :: nle_stress, nle_tangent, nle_energy, nle_path, nle_exact, nle_auto_nsub, nle_map_t, NLE_RTOL, NLE_NMAX

  !> The law's one-step map: the stress of the strain at the end of the sub-increment.
  type, extends(return_map_t) :: nle_map_t
    real(dp) :: e = 0.0_dp, b = 0.0_dp
  contains
    procedure :: step => nle_step
  end type nle_map_t

  real(dp), parameter :: NLE_RTOL = 1.0e-4_dp  !< AUTO: target |W_N - W| / (|deps| max|sigma|)
  integer, parameter :: NLE_NMAX = 100         !< AUTO: largest number of sub-increments

contains

  pure real(dp) function nle_stress(e, b, eps)
    real(dp), intent(in) :: e, b, eps
    nle_stress = e * eps * (1.0_dp + b * eps**2)
  end function nle_stress

  pure real(dp) function nle_tangent(e, b, eps)
    real(dp), intent(in) :: e, b, eps
    nle_tangent = e * (1.0_dp + 3.0_dp * b * eps**2)
  end function nle_tangent

  pure real(dp) function nle_energy(e, b, eps)
    real(dp), intent(in) :: e, b, eps
    nle_energy = e * (0.5_dp * eps**2 + 0.25_dp * b * eps**4)
  end function nle_energy

  !> AUTO number of sub-increments: smallest N whose exact trapezoid error is below
  !> NLE_RTOL * |deps| * max(|sigma0|, |sigma1|), clamped to 1..NLE_NMAX.
  pure integer function nle_auto_nsub(e, b, eps_n, deps)
    real(dp), intent(in) :: e, b, eps_n, deps
    real(dp) :: err1, scale, x
    err1 = deps**2 / 12.0_dp * abs(nle_tangent(e, b, eps_n + deps) - nle_tangent(e, b, eps_n))
    scale = NLE_RTOL * abs(deps) * max(abs(nle_stress(e, b, eps_n)), abs(nle_stress(e, b, eps_n + deps)))
    nle_auto_nsub = 1
    if (err1 > 0.0_dp .and. scale > 0.0_dp) then
      x = min(real(NLE_NMAX, dp), sqrt(err1 / scale))
      nle_auto_nsub = max(1, ceiling(x))
    end if
  end function nle_auto_nsub

  !> One sub-increment (return_map_t): sigma of the strain at its end, no plastic strain, the
  !> exact tangent.
  pure subroutine nle_step(self, ns, nq, k, n, eps_n, deps, de, s0, q0, s1, q1, dep, dtan)
    class(nle_map_t), intent(in) :: self
    integer, intent(in) :: ns, nq, k, n
    real(dp), intent(in) :: eps_n(ns), deps(ns), de(ns), s0(ns), q0(nq)
    real(dp), intent(out) :: s1(ns), q1(nq), dep(ns), dtan(ns, ns)
    real(dp) :: e_end
    e_end = eps_n(1) + deps(1) * (real(k, dp) / real(n, dp))
    s1(1) = nle_stress(self%e, self%b, e_end)
    dep(1) = 0.0_dp
    dtan(1, 1) = nle_tangent(self%e, self%b, e_end)
  end subroutine nle_step

  !> Straight path eps_n -> eps_n + deps in nsub >= 1 equal sub-increments (subincrement_path):
  !> end stress, trapezoid mean stress (sigma_0 = sig_n as given) and the consistent tangent
  !> dsig/ddeps (exact).
  pure subroutine nle_path(e, b, nsub, eps_n, deps, sig_n, sig, sigbar, et)
    real(dp), intent(in) :: e, b, eps_n, deps, sig_n
    integer, intent(in) :: nsub
    real(dp), intent(out) :: sig, sigbar, et
    real(dp) :: s(1), sb(1), t(1, 1), q_n(0), q(0), dis
    call subincrement_path(nle_map_t(e, b), max(1, nsub), [eps_n], [deps], [sig_n], q_n, s, sb, q, dis, t)
    sig = s(1)
    sigbar = sb(1)
    et = t(1, 1)
  end subroutine nle_path

  !> SUBSTEPS EXACT: the discrete gradient of psi along eps_n -> eps1 = eps_n + deps,
  !> sigbar = (psi(eps1) - psi(eps_n)) / deps = E ((eps_n + eps1)/2 + b/4 (eps_n + eps1)(eps_n² + eps1²))
  !> (the quotient factored: no cancellation, and its limit sigma(eps_n) as deps -> 0), so that
  !> sigbar deps = delta psi to round-off in one step; sig and et at eps1.
  pure subroutine nle_exact(e, b, eps_n, deps, sig, sigbar, et)
    real(dp), intent(in) :: e, b, eps_n, deps
    real(dp), intent(out) :: sig, sigbar, et
    real(dp) :: eps1
    eps1 = eps_n + deps
    sig = nle_stress(e, b, eps1)
    sigbar = e * (eps_n + eps1) * (0.5_dp + 0.25_dp * b * (eps_n**2 + eps1**2))
    et = nle_tangent(e, b, eps1)
  end subroutine nle_exact
end module law_nonlinear_elastic
