!> Numbering of the free degrees of freedom. A node carries the DOFs its modelled elements
!> use (UX UY for masses, springs, bars and quads, plus RZ for beams); supports (FIX) are
!> eliminated from the system, not penalized.
module dof_map
  use mesh, only: mesh_t
  use scene, only: scene_t
  use elements, only: elem_dof_mask
  use element_traits, only: ET_BEAM2
  implicit none
  private
  public :: build_dof_map, equation_bodies, cayley_rotations, imposed_dofs, DOF_ABSENT, DOF_FIXED

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

  !> body(ieq): the mesh-connected component (through modelled elements) holding equation
  !> ieq, numbered from 1; IMPACT PERSIST scales the velocity of a body as a whole.
  subroutine equation_bodies(scn, eqn, neq, body)
    type(scene_t), intent(in) :: scn
    integer, intent(in) :: eqn(:, :)
    integer, intent(in) :: neq
    integer, allocatable, intent(out) :: body(:)
    integer, allocatable :: parent(:), label(:)
    integer :: e, a, n, ra, rb, nb
    allocate (parent(scn%mesh%nnode), label(scn%mesh%nnode), body(neq))
    parent = [(n, n = 1, scn%mesh%nnode)]
    do e = 1, scn%mesh%nelem
      if (scn%elem_model(e) == 0) cycle
      ra = root(scn%mesh%conn(1, e))
      do a = 2, scn%mesh%nen(e)
        rb = root(scn%mesh%conn(a, e))
        if (ra /= rb) parent(rb) = ra
      end do
    end do
    label = 0
    nb = 0
    body = 0
    do n = 1, scn%mesh%nnode
      ra = root(n)
      if (label(ra) == 0) then
        nb = nb + 1
        label(ra) = nb
      end if
      do a = 1, size(eqn, 1)
        if (eqn(a, n) > 0) body(eqn(a, n)) = label(ra)
      end do
    end do
  contains
    integer function root(i)
      integer, intent(in) :: i
      root = i
      do while (parent(root) /= root)
        parent(root) = parent(parent(root))
        root = parent(root)
      end do
    end function root
  end subroutine equation_bodies

  !> The rotation equations a step turns by the Cayley angle 2 atan(Δw/2) of its increment Δw
  !> (docs/large-displacements.md, "Angular momentum"): RZ of the nodes whose rotation only LARGE
  !> BEAM2 elements use, not imposed, when eq (9) carries its correction (ENERGY_CORRECTION ON).
  !> A node shared with a SMALL beam keeps the additive rotation its linear element needs.
  subroutine cayley_rotations(scn, eqn, neq, mask, list)
    type(scene_t), intent(in) :: scn
    integer, intent(in) :: eqn(:, :)
    integer, intent(in) :: neq
    logical, allocatable, intent(out) :: mask(:)
    integer, allocatable, intent(out) :: list(:)
    logical, allocatable :: large(:), other(:), imposed(:, :)
    integer :: e, a, n, k
    logical :: lb
    allocate (mask(neq), large(scn%mesh%nnode), other(scn%mesh%nnode))
    mask = .false.
    large = .false.
    other = .false.
    do e = 1, scn%mesh%nelem
      if (scn%elem_model(e) == 0) cycle
      if (scn%mesh%etype(e) /= ET_BEAM2) cycle      ! the only element with RZ
      lb = scn%models(scn%elem_model(e))%large
      do a = 1, scn%mesh%nen(e)
        n = scn%mesh%conn(a, e)
        large(n) = large(n) .or. lb
        other(n) = other(n) .or. .not. lb
      end do
    end do
    call imposed_dofs(scn, imposed)
    other = other .or. imposed(3, :)
    if (scn%energy_correction) then
      do n = 1, scn%mesh%nnode
        if (large(n) .and. .not. other(n) .and. eqn(3, n) > 0) mask(eqn(3, n)) = .true.
      end do
    end if
    list = pack([(k, k = 1, neq)], mask)
  end subroutine cayley_rotations

  !> mask(d, n): DOF d of node n is imposed (IMPOSE).
  pure subroutine imposed_dofs(scn, mask)
    type(scene_t), intent(in) :: scn
    logical, allocatable, intent(out) :: mask(:, :)
    integer :: k
    allocate (mask(3, scn%mesh%nnode))
    mask = .false.
    do k = 1, size(scn%imposes)
      mask(scn%imposes(k)%dof, scn%mesh%ngroups(scn%imposes(k)%ngroup)%items) = .true.
    end do
  end subroutine imposed_dofs
end module dof_map
