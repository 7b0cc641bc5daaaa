!> Constitutive laws behind one interface. A law integrates the stress along the straight
!> strain path eps(s) = eps_n + s*deps, s in [0,1], in nsub sub-increments, and returns the
!> end stress, the path-mean stress (trapezoid over the sub-increments, method.md section 2),
!> the new internal variables, the work per unit weight and its dissipated part.
!> Material-point kinds: PK_1D (springs: force/elongation, bars: axial stress/strain),
!> PK_BEAM (section resultants N, M against axial strain and curvature), PK_PSTRAIN and
!> PK_PSTRESS (quads: xx, yy, zz, xy with engineering shear).
module material_law
  use kinds, only: dp
  use section, only: section_t
  use law_elastic, only: elastic_update
  implicit none
  private
  public :: material_t, law_update, law_is_linear, law_nstate, law_name
  public :: LAW_ELASTIC, PK_1D, PK_BEAM, PK_PSTRAIN, PK_PSTRESS, pk_nstrain

  integer, parameter :: LAW_ELASTIC = 1
  integer, parameter :: PK_1D = 1, PK_BEAM = 2, PK_PSTRAIN = 3, PK_PSTRESS = 4

  type :: material_t
    character(len=:), allocatable :: name
    integer :: law = LAW_ELASTIC
    real(dp) :: young = 0.0_dp     !< Young's modulus [Pa]; for SPRING the stiffness [N/m]
    real(dp) :: poisson = 0.0_dp
    real(dp) :: density = 0.0_dp   !< [kg/m3]
  end type material_t

contains

  !> Upper-case name of a law.
  pure function law_name(law) result(name)
    integer, intent(in) :: law
    character(len=:), allocatable :: name
    select case (law)
    case (LAW_ELASTIC)
      name = 'ELASTIC'
    case default
      name = '?'
    end select
  end function law_name

  !> Number of generalized strain components of a material-point kind.
  pure integer function pk_nstrain(pk)
    integer, intent(in) :: pk
    select case (pk)
    case (PK_1D)
      pk_nstrain = 1
    case (PK_BEAM)
      pk_nstrain = 2
    case default
      pk_nstrain = 4
    end select
  end function pk_nstrain

  !> True when the stress is a linear function of the strain (no iteration, no correction).
  pure logical function law_is_linear(mat)
    type(material_t), intent(in) :: mat
    law_is_linear = mat%law == LAW_ELASTIC
  end function law_is_linear

  !> Number of internal variables per material point.
  pure integer function law_nstate(mat, pk, sec)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: pk
    type(section_t), intent(in) :: sec
    law_nstate = 0
  end function law_nstate

  !> Integrate the law over one step (see the module header). d is the elastic matrix of the
  !> point (nstr x nstr, from elements' elem_elastic_d). work is sigbar . deps, per unit weight.
  pure subroutine law_update(mat, sec, pk, d, nsub, eps_n, deps, sig_n, q_n, sig, sigbar, q, work, dissip)
    type(material_t), intent(in) :: mat
    type(section_t), intent(in) :: sec
    integer, intent(in) :: pk, nsub
    real(dp), intent(in) :: d(:, :), eps_n(:), deps(:), sig_n(:), q_n(:)
    real(dp), intent(out) :: sig(:), sigbar(:), q(:)
    real(dp), intent(out) :: work, dissip
    select case (mat%law)
    case default
      call elastic_update(d, deps, sig_n, sig, sigbar)
      q = q_n
      dissip = 0.0_dp
    end select
    work = dot_product(sigbar, deps)
  end subroutine law_update
end module material_law
