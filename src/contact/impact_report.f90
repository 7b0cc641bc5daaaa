!> What the end of a step with contact reports (contact_end_step): counts, the works of the step
!> and what each impact mode did. Each mode adds to it its own entries; the driver reads it.
module impact_report
  use kinds, only: dp
  implicit none
  private

  !> Summary of one contact_end_step.
  type, public :: contact_report_t
    integer :: n_active = 0, n_establish = 0, n_release = 0
    real(dp) :: energy_error = 0.0_dp        !< Σ E_j over the established conditions
    real(dp) :: energy_restored = 0.0_dp     !< kinetic energy added, measured
    real(dp) :: scheme_work = 0.0_dp         !< ½ Λ'C du: the work the scheme counts for the multiplier
    real(dp) :: reaction_work = 0.0_dp       !< MASSLESS: ½ R(n)'C du, the start reactions' share of it
    real(dp) :: imposed_work = 0.0_dp        !< ½ Λ'C du over the bilateral rows: the work of imposed motion
    real(dp) :: obstacle_work = 0.0_dp       !< moving obstacles: ½ Λ'shift and their impulses' V'Δ(M v)
    integer :: fp_iterations = 0             !< impulse fixed point (14)
    real(dp) :: fp_change = 0.0_dp           !< its final relative change
    integer :: fp_failures = 0               !< 1 if (14) had no all-negative solution (see impulse_fixed_point)
    integer :: persist_groups = 0, persist_fallbacks = 0
    integer :: reflection_rank = 0           !< rank of A M⁻¹A' in (16) (< rows: dependent rows)
    real(dp) :: impact_dissipated = 0.0_dp   !< kinetic energy removed by RESTITUTION e < 1 (never negative)
    real(dp) :: held = 0.0_dp                !< SYMMETRIC: energy taken into (> 0) or given back from (< 0) the contacts' hold
    real(dp) :: snap_dissipated = 0.0_dp     !< MASSLESS: lost by massless nodes snapping to equilibrium (driver's)
    real(dp) :: friction_dissipated = 0.0_dp !< FRICTION: -½ Λ_T'C_T du, the friction's dissipation in the step (>= 0)
    real(dp) :: unrestored = 0.0_dp          !< energy a scaling could not give back or take off (left in the balance)
  end type contact_report_t
end module impact_report
