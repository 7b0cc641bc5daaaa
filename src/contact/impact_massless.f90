!> IMPACT MASSLESS (docs/contact.md): the contact nodes carry no mass, so there is no normal
!> velocity to reflect or project; the energy the step lost at an establishment (E_j of (10)),
!> or counted at a release (-½ R_j(n) g_j(n+1)), goes to (comes from) the group by scaling its
!> velocity about the rigid motion the contact cannot change (impact_scaling). Groups without
!> kinetic energy are left (rep%unrestored: the balance shows it, and the driver retries the
!> step as sub-steps, contact_shortfall). Inputs and outputs are arguments.
module impact_massless
  use kinds, only: dp
  use constraint_rows, only: constraint_rows_t
  use impact_report, only: contact_report_t
  use impact_space, only: impact_space_t
  use impact_scaling, only: scaling_t
  implicit none
  private

  type, public :: massless_t
    private
    type(scaling_t) :: scaling
    logical, allocatable :: changing(:)
  contains
    procedure :: init => massless_init
    procedure :: correct => massless_correction
  end type massless_t

contains

  !> Scratch for neq equations and nc conditions (before the time loop).
  subroutine massless_init(self, neq, nc)
    class(massless_t), intent(inout) :: self
    integer, intent(in) :: neq, nc
    if (allocated(self%changing)) deallocate (self%changing)
    allocate (self%changing(nc))
    call self%scaling%init(neq, nc)
  end subroutine massless_init

  !> est, rel: the conditions established and released in the step; now: active at its end; e:
  !> their energies (E_j, or minus the release's). Out: v, mv (= M v), cimp, bimp, fallback (the
  !> changing conditions of the groups that could not be scaled), rep.
  subroutine massless_correction(self, sp, c, body, est, rel, now, e, min_fraction, v, mv, cimp, bimp, fallback, rep, &
    stat, errmsg)
    class(massless_t), intent(inout) :: self
    type(impact_space_t), intent(inout) :: sp
    type(constraint_rows_t), intent(in) :: c
    integer, intent(in) :: body(:)
    logical, intent(in) :: est(:), rel(:), now(:)
    real(dp), intent(in) :: e(:), min_fraction
    real(dp), intent(inout) :: v(:), mv(:), cimp(:), bimp(:, :)
    logical, intent(out) :: fallback(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    if (.not. allocated(self%changing)) call self%init(size(v), size(est))
    self%changing = est .or. rel
    call self%scaling%correct(sp, c, body, self%changing, now, e, min_fraction, v, mv, cimp, bimp, fallback, rep, &
      stat, errmsg)
  end subroutine massless_correction
end module impact_massless
