!> MASS element: a point mass on one node carrying its space's translations (UX, UY; UZ in a
!> DIMENSION 3 scene). It has no stiffness and no integration points; it only contributes
!> m I to the mass matrix.
module element_mass
  use kinds, only: dp
  use section, only: section_t
  implicit none
  private
  public :: mass_mass

contains

  !> Mass matrix m I (nd x nd, nd = 2 or 3, in the leading block of me) with m = sec%mass;
  !> lumped and consistent are the same.
  pure subroutine mass_mass(sec, nd, me)
    type(section_t), intent(in) :: sec
    integer, intent(in) :: nd
    real(dp), intent(out) :: me(:, :)
    integer :: k
    me = 0.0_dp
    do k = 1, nd
      me(k, k) = sec%mass
    end do
  end subroutine mass_mass
end module element_mass
