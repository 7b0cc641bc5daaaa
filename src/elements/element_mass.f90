!> MASS element: a point mass on one node carrying UX, UY. It has no stiffness and no
!> integration points; it only contributes diag(m, m) to the mass matrix.
module element_mass
  use kinds, only: dp
  use section, only: section_t
  implicit none
  private
  public :: mass_mass

contains

  !> Mass matrix diag(m, m) with m = sec%mass; lumped and consistent are the same.
  pure subroutine mass_mass(sec, me)
    type(section_t), intent(in) :: sec
    real(dp), intent(out) :: me(2, 2)
    me = 0.0_dp
    me(1, 1) = sec%mass
    me(2, 2) = sec%mass
  end subroutine mass_mass
end module element_mass
