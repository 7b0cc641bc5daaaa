!> Numbering of the free degrees of freedom. A node carries the DOFs its modelled elements
!> use (UX UY for masses, springs, bars and quads, plus RZ for beams); supports (FIX) are
!> eliminated from the system, not penalized.
module dof_map
  use mesh, only: mesh_t
  use scene, only: scene_t
  use elements, only: elem_dof_mask
  implicit none
  private
  public :: build_dof_map, DOF_ABSENT, DOF_FIXED

  integer, parameter :: DOF_ABSENT = 0, DOF_FIXED = -1

contains

  !> eqn(d, node) = equation number (> 0), DOF_FIXED or DOF_ABSENT; neq free equations.
  subroutine build_dof_map(scn, eqn, neq)
    type(scene_t), intent(in) :: scn
    integer, allocatable, intent(out) :: eqn(:, :)
    integer, intent(out) :: neq
    logical, allocatable :: present(:, :)
    logical :: mask(3)
    integer :: e, a, i, n, d
    allocate (present(3, scn%mesh%nnode), eqn(3, scn%mesh%nnode))
    present = .false.
    do e = 1, scn%mesh%nelem
      if (scn%elem_model(e) == 0) cycle
      mask = elem_dof_mask(scn%mesh%etype(e))
      do a = 1, scn%mesh%nen(e)
        n = scn%mesh%conn(a, e)
        present(:, n) = present(:, n) .or. mask
      end do
    end do
    eqn = merge(1, DOF_ABSENT, present)
    do i = 1, size(scn%fixes)
      associate (nodes => scn%mesh%ngroups(scn%fixes(i)%ngroup)%items)
        do d = 1, 3
          if (.not. scn%fixes(i)%dofs(d)) cycle
          where (present(d, nodes)) eqn(d, nodes) = DOF_FIXED
        end do
      end associate
    end do
    neq = 0
    do n = 1, scn%mesh%nnode
      do d = 1, 3
        if (eqn(d, n) > 0) then
          neq = neq + 1
          eqn(d, n) = neq
        end if
      end do
    end do
  end subroutine build_dof_map
end module dof_map
