!> What the passes of Coulomb's active set share in 2D (coulomb) and 3D (coulomb_cone): the states
!> of a frictional condition, the rows whose multipliers are a pass's unknowns, the unilateral
!> rows' violations, and how many changes a pass makes.
module coulomb_passes
  use kinds, only: dp
  implicit none
  private
  public :: FRICTION_FREE, FRICTION_STICK, FRICTION_SLIP_POS, FRICTION_SLIP_NEG, BLOCK_TRIES
  public :: fixed_rows, unilateral_violations, limit_changes

  !> The state of a tangential row: FREE (its contact open: no force), STICK, or slipping along +t
  !> (force -μ Λ_N) or -t (force +μ Λ_N); in 3D SLIP_POS is slipping along the condition's angle θ.
  integer, parameter :: FRICTION_FREE = 0, FRICTION_STICK = 1, FRICTION_SLIP_POS = 2, FRICTION_SLIP_NEG = 3
  !> Passes that may change every violation before one change per pass.
  integer, parameter :: BLOCK_TRIES = 3

contains

  !> The states of the open contacts' tangents FREE (friction k: normal row nrow(k); kof(j) > 0:
  !> row j is a tangential row of friction kof(j)); rows(1:ni) the rows whose multiplier is an
  !> unknown of a pass (I): the active contacts, the bilateral rows, the sticking tangential rows.
  pure subroutine fixed_rows(kof, nrow, bilateral, active, state, rows, ni)
    integer, intent(in) :: kof(:), nrow(:)
    logical, intent(in) :: bilateral(:), active(:)
    integer, intent(inout) :: state(:), rows(:)
    integer, intent(out) :: ni
    integer :: k, j
    do k = 1, size(nrow)
      if (.not. active(nrow(k))) state(k) = FRICTION_FREE
    end do
    ni = 0
    do j = 1, size(active)
      if (kof(j) > 0) then
        if (state(kof(j)) /= FRICTION_STICK) cycle
      else if (.not. (active(j) .or. bilateral(j))) then
        cycle
      end if
      ni = ni + 1
      rows(ni) = j
    end do
  end subroutine fixed_rows

  !> The unilateral rows that violate their law after a pass: an active one pulling (lam w_jj <
  !> -tol), an open one penetrating (g < -tol_free); the other rows' viol .false.
  pure subroutine unilateral_violations(bilateral, active, lam, g, wdiag, tol, tol_free, viol)
    logical, intent(in) :: bilateral(:), active(:)
    real(dp), intent(in) :: lam(:), g(:), wdiag(:), tol, tol_free(:)
    logical, intent(out) :: viol(:)
    integer :: j
    viol = .false.
    do j = 1, size(lam)
      if (bilateral(j)) cycle
      if (active(j)) then
        viol(j) = lam(j) * wdiag(j) < -tol
      else
        viol(j) = g(j) < -tol_free(j)
      end if
    end do
  end subroutine unilateral_violations

  !> All nv violations change at once while their count falls; after BLOCK_TRIES passes without
  !> fewer, only the first (viol reduced to it).
  pure subroutine limit_changes(viol, nv, nbest, tries)
    logical, intent(inout) :: viol(:)
    integer, intent(in) :: nv
    integer, intent(inout) :: nbest, tries
    integer :: k
    if (nv < nbest) then
      nbest = nv
      tries = BLOCK_TRIES
    else if (tries > 0) then
      tries = tries - 1
    else                                       ! one change only: the first violation
      k = findloc(viol, .true., 1)
      viol = .false.
      viol(k) = .true.
    end if
  end subroutine limit_changes

end module coulomb_passes
