!> The sub-incrementation of method.md section 2, written once for every law: a law gives its
!> one-step map (return_map_t), this module integrates it along the straight strain path
!> ε(s) = ε(n) + s Δε of a step in N equal sub-increments and forms the path-mean stress
!>     σ̄ = (1/N) [ σ0/2 + σ1 + … + σ(N-1) + σN/2 ]
!> and the plastic work (trapezoid of σ·Δεp over the sub-increments); correction_stress forms
!> the σc of eq (9). material_law calls it for the spring, bar and quad laws, beam_fibre for
!> each layer of a fibre section.
module subincrement
  use kinds, only: dp
  use law_types, only: MAX_COMPONENTS
  implicit none
  private
  public :: return_map_t, subincrement_path, correction_stress, MAX_COMPONENTS, MAX_STATE

  !> Largest internal-variable vector of a point (law_types: the largest stress): the locals are fixed-size (no
  !> allocation at the integration points); every law is within them (1D: 1 and 3, quads: 4
  !> and 10), a larger one is out of bounds (make check-debug).
  integer, parameter :: MAX_STATE = 16

  !> What a law supplies: one sub-increment of its constitutive update.
  type, abstract :: return_map_t
  contains
    procedure(step_i), deferred :: step
  end type return_map_t

  abstract interface
    !> Sub-increment k of n along eps_n + s deps (ns stress components, nq internal variables;
    !> explicit shapes: this runs at every sub-increment of every plastic point, descriptors
    !> would cost more than the law): from the stress s0 and internal variables q0
    !> at its start and its strain increment de = deps/n, the stress s1 and variables q1 at its
    !> end, the plastic strain increment dep and the consistent tangent dtan = dσ/dε. A law
    !> whose stress is a function of the strain takes the strain at the end of the
    !> sub-increment as eps_n + deps (k/n) (exactly eps_n + deps at k = n).
    pure subroutine step_i(self, ns, nq, k, n, eps_n, deps, de, s0, q0, s1, q1, dep, dtan)
      import :: return_map_t, dp
      class(return_map_t), intent(in) :: self
      integer, intent(in) :: ns, nq, k, n
      real(dp), intent(in) :: eps_n(ns), deps(ns), de(ns), s0(ns), q0(nq)
      real(dp), intent(out) :: s1(ns), q1(nq), dep(ns), dtan(ns, ns)
    end subroutine step_i
  end interface

contains

  !> The path of one step in n >= 1 sub-increments: end stress sig, internal variables q, the
  !> path-mean stress sigbar (trapezoid rule over σ0 = sig_n … σN = sig), the plastic work
  !> dissip = Σ_k ½ (σ(k-1) + σk)·Δεp_k and the tangent of the last sub-increment. dmean:
  !> d(2σ̄)/dΔε, the tangent of the forces eq (9) carries with its correction, from the chain of
  !> the sub-increments X_k = dσ_k/dΔε: with cel, the law's elastic compliance (a return map whose
  !> trial is σ(k-1) + D_e Δε/N), X_k = D_k (cel X_(k-1) + I/N) (the hardening variables' share
  !> left out); without, X_k = (k/N) D_k. dmean = (2/N) (Σ_{k<N} X_k + X_N/2).
  pure subroutine subincrement_path(map, n, eps_n, deps, sig_n, q_n, sig, sigbar, q, dissip, dtan, dmean, cel)
    class(return_map_t), intent(in) :: map
    integer, intent(in) :: n
    real(dp), intent(in), contiguous :: eps_n(:), deps(:), sig_n(:), q_n(:)
    real(dp), intent(out), contiguous :: sig(:), sigbar(:), q(:), dtan(:, :)
    real(dp), intent(out) :: dissip
    real(dp), intent(out), optional :: dmean(:, :)
    real(dp), intent(in), optional :: cel(:, :)
    real(dp) :: x(MAX_COMPONENTS, MAX_COMPONENTS), y(MAX_COMPONENTS, MAX_COMPONENTS)
    integer :: i
    real(dp) :: s0(MAX_COMPONENTS), acc(MAX_COMPONENTS), dep(MAX_COMPONENTS), de(MAX_COMPONENTS), qk(MAX_STATE)
    integer :: k, ns, nq
    ns = size(sig)
    nq = size(q)
    de(1:ns) = deps / real(n, dp)
    s0(1:ns) = sig_n
    qk(1:nq) = q_n(1:nq)
    acc(1:ns) = 0.5_dp * sig_n
    dissip = 0.0_dp
    if (present(dmean)) dmean = 0.0_dp
    x(1:ns, 1:ns) = 0.0_dp
    do k = 1, n
      call map%step(ns, nq, k, n, eps_n, deps, de, s0, qk, sig, q, dep, dtan)
      dissip = dissip + 0.5_dp * dot_product(s0(1:ns) + sig, dep(1:ns))
      if (k < n) acc(1:ns) = acc(1:ns) + sig
      if (present(dmean)) then
        if (present(cel)) then
          y(1:ns, 1:ns) = matmul(cel(1:ns, 1:ns), x(1:ns, 1:ns))
          do i = 1, ns
            y(i, i) = y(i, i) + 1.0_dp / real(n, dp)
          end do
          x(1:ns, 1:ns) = matmul(dtan(1:ns, 1:ns), y(1:ns, 1:ns))
        else
          x(1:ns, 1:ns) = (real(k, dp) / real(n, dp)) * dtan(1:ns, 1:ns)
        end if
        dmean = dmean + merge(1.0_dp, 0.5_dp, k < n) * (2.0_dp / real(n, dp)) * x(1:ns, 1:ns)
      end if
      s0(1:ns) = sig
      qk(1:nq) = q
    end do
    sigbar = (acc(1:ns) + 0.5_dp * sig) / real(n, dp)
  end subroutine subincrement_path

  !> Eq (9): σc = 2 σ̄ - (σ(n) + σ(n+1)), twice the mean deviation of the path from its chord;
  !> Bσc on the left of (9) cancels the energy the trapezoid rule invents (the lunule).
  pure subroutine correction_stress(sigbar, sig_n, sig, sc)
    real(dp), intent(in) :: sigbar(:), sig_n(:), sig(:)
    real(dp), intent(out) :: sc(:)
    sc = 2.0_dp * sigbar - (sig_n + sig)
  end subroutine correction_stress
end module subincrement
