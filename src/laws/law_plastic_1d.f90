!> Uniaxial elastoplasticity with linear isotropic (h_iso) and kinematic (h_kin) hardening;
!> h_iso = h_kin = 0 is perfectly plastic. Yield f = |sigma - beta| - (sy + h_iso alpha).
!> Internal variables q = [eps_p (plastic strain), alpha (accumulated plastic strain),
!> beta (back stress)]. The return mapping of one increment is closed-form and exact for a
!> monotonic strain increment starting on or inside the yield surface (linear hardening:
!> the plastic branch of the stress-strain curve is a straight line of slope E H/(E + H),
!> H = h_iso + h_kin). For springs read force for stress and elongation for strain.
module law_plastic_1d
  use kinds, only: dp
  use subincrement, only: return_map_t, subincrement_path
  use law_types, only: law_params_t
  implicit none
  private
  public :: P1D_NSTATE, plastic_1d_return, plastic_1d_inside, plastic_1d_path, plastic_1d_map_t
  public :: plastic_auto_nsub, AUTO_ALPHA, AUTO_NMAX

  !> The law's one-step map for the sub-incrementation: plastic_1d_return.
  type, extends(return_map_t) :: plastic_1d_map_t
    type(law_params_t) :: p
  contains
    procedure :: step => plastic_1d_step
  end type plastic_1d_map_t

  integer, parameter :: P1D_NSTATE = 3
  !> AUTO rule of the plastic laws: N = clamp(ceil(r / AUTO_ALPHA), 1, AUTO_NMAX), with r the
  !> elastic trial stress increment measured in yield stresses (see docs/materials.md).
  real(dp), parameter :: AUTO_ALPHA = 0.25_dp
  integer, parameter :: AUTO_NMAX = 100

contains

  !> AUTO number of sub-increments for a trial stress increment of r yield stresses.
  pure integer function plastic_auto_nsub(r)
    real(dp), intent(in) :: r
    real(dp) :: x
    x = abs(r) / AUTO_ALPHA
    if (.not. x <= real(AUTO_NMAX, dp)) x = real(AUTO_NMAX, dp)   ! also catches NaN
    plastic_auto_nsub = min(AUTO_NMAX, max(1, ceiling(x)))
  end function plastic_auto_nsub

  !> True when the elastic trial sig_n + e deps stays inside the yield surface of the frozen
  !> state q_n: by convexity the whole straight path is then elastic.
  pure logical function plastic_1d_inside(p, sig_n, q_n, deps)
    type(law_params_t), intent(in) :: p
    real(dp), intent(in) :: sig_n, q_n(:), deps
    plastic_1d_inside = abs(sig_n + p%young * deps - q_n(3)) - (p%yield + p%h_iso * q_n(2)) <= 0.0_dp
  end function plastic_1d_inside

  !> One increment: elastic predictor, closed-form return. dep is the plastic strain increment,
  !> et the algorithmic (consistent) tangent dsig/dde.
  pure subroutine plastic_1d_return(p, sig_n, q_n, de, sig, q, dep, et)
    type(law_params_t), intent(in) :: p
    real(dp), intent(in) :: sig_n, q_n(:), de
    real(dp), intent(out) :: sig, q(:), dep, et
    real(dp) :: str, xi, f, dg, sg, e, sy, hi, hk
    e = p%young
    sy = p%yield
    hi = p%h_iso
    hk = p%h_kin
    str = sig_n + e * de
    xi = str - q_n(3)
    f = abs(xi) - (sy + hi * q_n(2))
    q(1:P1D_NSTATE) = q_n(1:P1D_NSTATE)
    if (f <= 0.0_dp) then
      sig = str
      dep = 0.0_dp
      et = e
    else
      dg = f / (e + hi + hk)
      sg = sign(1.0_dp, xi)
      dep = dg * sg
      sig = str - e * dep
      q(1) = q_n(1) + dep
      q(2) = q_n(2) + dg
      q(3) = q_n(3) + hk * dep
      et = e * (hi + hk) / (e + hi + hk)
    end if
  end subroutine plastic_1d_return

  !> One sub-increment (return_map_t): the closed-form return of plastic_1d_return.
  pure subroutine plastic_1d_step(self, ns, nq, k, n, eps_n, deps, de, s0, q0, s1, q1, dep, dtan)
    class(plastic_1d_map_t), intent(in) :: self
    integer, intent(in) :: ns, nq, k, n
    real(dp), intent(in) :: eps_n(ns), deps(ns), de(ns), s0(ns), q0(nq)
    real(dp), intent(out) :: s1(ns), q1(nq), dep(ns), dtan(ns, ns)
    call plastic_1d_return(self%p, s0(1), q0, de(1), s1(1), q1, dep(1), dtan(1, 1))
  end subroutine plastic_1d_step

  !> Straight strain path deps in nsub >= 1 sub-increments. If the whole step is elastic
  !> (plastic_1d_inside) nothing is sub-incremented: sig = sig_n + e deps, sigbar the exact chord
  !> midpoint, nused = 0. Otherwise subincrement_path gives sigbar, the trapezoid mean of
  !> sigma_0 = sig_n .. sigma_N, and dissip, the trapezoid sum of sigma . dep over the
  !> sub-increments; nused = nsub; et is the tangent of the last sub-increment.
  pure subroutine plastic_1d_path(p, nsub, sig_n, q_n, deps, sig, sigbar, q, dissip, nused, et)
    type(law_params_t), intent(in) :: p
    real(dp), intent(in) :: sig_n, q_n(:), deps
    integer, intent(in) :: nsub
    real(dp), intent(out) :: sig, sigbar, q(:), dissip, et
    integer, intent(out) :: nused
    real(dp) :: s(1), sb(1), t(1, 1), qn(P1D_NSTATE), qk(P1D_NSTATE)
    if (plastic_1d_inside(p, sig_n, q_n, deps)) then
      sig = sig_n + p%young * deps
      sigbar = 0.5_dp * (sig_n + sig)
      q(1:P1D_NSTATE) = q_n(1:P1D_NSTATE)
      dissip = 0.0_dp
      nused = 0
      et = p%young
      return
    end if
    nused = max(1, nsub)
    qn = q_n(1:P1D_NSTATE)           ! contiguous locals: no temporary at the call
    call subincrement_path(plastic_1d_map_t(p), nused, [0.0_dp], [deps], [sig_n], qn, s, sb, qk, &
      dissip, t)
    q(1:P1D_NSTATE) = qk
    sig = s(1)
    sigbar = sb(1)
    et = t(1, 1)
  end subroutine plastic_1d_path
end module law_plastic_1d
