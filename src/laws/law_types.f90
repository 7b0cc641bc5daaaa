!> What a law is given and what it gives back at one material point, as types instead of long
!> scalar argument lists: the material parameters (law_params_t, which material_t extends, so a
!> scene's material is passed as it is) and the result of one step (law_step_t). Both are
!> fixed-size: the laws run at every integration point of every step and allocate nothing.
module law_types
  use kinds, only: dp
  implicit none
  private
  public :: law_params_t, law_step_t, MAX_COMPONENTS, NSUB_EXACT, law_step_reset

  !> The sub-increment count that asks a law with a potential for its discrete gradient
  !> (MODEL … SUBSTEPS EXACT): sigbar . deps = psi(eps_n + deps) - psi(eps_n) exactly, one step.
  integer, parameter :: NSUB_EXACT = -1

  !> Largest stress vector of a point (1D: 1, beam section: 2, quads: 4, solids: 6).
  integer, parameter :: MAX_COMPONENTS = 6

  !> Material constants (SI). For springs young is the stiffness [N/m] and yield a force.
  type :: law_params_t
    real(dp) :: young = 0.0_dp     !< Young's modulus [Pa]
    real(dp) :: poisson = 0.0_dp
    real(dp) :: nl_b = 0.0_dp      !< NONLINEAR_ELASTIC: sigma = E eps (1 + b eps^2)
    real(dp) :: yield = 0.0_dp     !< ELASTOPLASTIC, VON_MISES: initial yield stress
    real(dp) :: h_iso = 0.0_dp     !< linear isotropic hardening modulus (d sigma / d eps_p)
    real(dp) :: h_kin = 0.0_dp     !< linear kinematic hardening modulus
  end type law_params_t

  !> One step of a point along its strain path: the end stress sig, the path-mean stress
  !> sigbar (method.md section 2), the tangent dtan = d sig / d deps (material_law: law_update),
  !> the work sigbar . deps and its dissipated part (per unit weight), the sub-increments used
  !> (0: none were needed, the step was elastic and sigma_c = 0 bit for bit).
  !> No component carries a default value (the laws set what they produce: sig(1:ns), sigbar(1:ns),
  !> dtan(1:ns, 1:ns), work, dissip, nused, and dbar with has_dbar; law_step_reset the scalars): a
  !> step is a point's every iteration, and an intent(out) of a default-initialized 6 x 6 type was
  !> built and copied whole at each call, a quarter of the 2D laws' time.
  type :: law_step_t
    real(dp) :: sig(MAX_COMPONENTS)
    real(dp) :: sigbar(MAX_COMPONENTS)
    real(dp) :: dtan(MAX_COMPONENTS, MAX_COMPONENTS)
    real(dp) :: work
    real(dp) :: dissip
    integer :: nused
    !> With has_dbar: dbar = d(2 sigbar)/d(deps), the tangent of the force eq (9) carries with the
    !> correction (Bσ(n+1) + Bσc = 2 Bσ̄ - Bσ(n)); otherwise dtan stands for it.
    real(dp) :: dbar(MAX_COMPONENTS, MAX_COMPONENTS)
    logical :: has_dbar
  end type law_step_t

contains

  !> The scalars of a step before a law fills it: no work, no dissipation, no sub-increment, no dbar.
  pure subroutine law_step_reset(r)
    type(law_step_t), intent(inout) :: r
    r%work = 0.0_dp
    r%dissip = 0.0_dp
    r%nused = 0
    r%has_dbar = .false.
  end subroutine law_step_reset
end module law_types
