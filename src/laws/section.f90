!> Cross-section and discrete-element characteristics (Cast3M's CARA): what an element needs
!> beyond its nodes and its material.
module section
  use kinds, only: dp
  implicit none
  private
  public :: section_t

  type :: section_t
    character(len=:), allocatable :: name
    real(dp) :: area = 0.0_dp        !< BAR2, BEAM2: cross-section area [m2]
    real(dp) :: inertia = 0.0_dp     !< BEAM2: second moment of area about the bending axis [m4]
    real(dp) :: height = 0.0_dp      !< BEAM2: section height, for stresses and fibre sections [m]
    real(dp) :: thickness = 1.0_dp   !< QUAD4/QUAD8: out-of-plane thickness [m]
    logical :: has_thickness = .false.  !< THICKNESS was given (an axisymmetric model refuses it)
    real(dp) :: mass = 0.0_dp        !< MASS: point mass [kg]
    real(dp) :: direction(2) = 0.0_dp  !< SPRING: axis when its nodes coincide (else from positions)
    logical :: has_direction = .false.
    logical :: plane_stress = .false.  !< QUAD4/QUAD8: plane stress (else plane strain)
    !> Surface elements: axisymmetric (x = r >= 0, y the axis; the hoop strain u_r/r in the zz row,
    !> weights and masses over the whole circumference, 2 pi r in place of the thickness)
    logical :: axisymmetric = .false.
    integer :: layers = 0            !< BEAM2 fibre section: number of layers (0 = integrated section)
    integer :: gauss = 0             !< BEAM2: Gauss points along the element (0 = element default, 2)
  end type section_t
end module section
