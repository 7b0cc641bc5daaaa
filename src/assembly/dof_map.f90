!> Numbering of the free degrees of freedom. A node carries the DOFs its modelled elements
!> use (UX UY for masses, springs, bars and quads, plus RZ for beams); supports (FIX) are
!> eliminated from the system, not penalized.
module dof_map
  use kinds, only: dp
  use mesh, only: mesh_t
  use scene, only: scene_t, scene_axisymmetric
  use elements, only: elem_dof_mask
  use element_traits, only: ET_BEAM2, NODE_DOFS, DOF_UX, DOF_UY, DOF_RZ, DOF_UZ
  implicit none
  private
  public :: build_dof_map, equation_bodies, body_rigid_freedom, cayley_rotations, imposed_dofs, DOF_ABSENT, DOF_FIXED

  integer, parameter :: DOF_ABSENT = 0, DOF_FIXED = -1

contains

  !> eqn(d, node) = equation number (> 0), DOF_FIXED or DOF_ABSENT; neq free equations.
  subroutine build_dof_map(scn, eqn, neq)
    type(scene_t), intent(in) :: scn
    integer, allocatable, intent(out) :: eqn(:, :)
    integer, intent(out) :: neq
    logical, allocatable :: present(:, :)
    logical :: mask(NODE_DOFS)
    integer :: e, a, i, n, d
    allocate (present(NODE_DOFS, scn%mesh%nnode), eqn(NODE_DOFS, scn%mesh%nnode))
    present = .false.
    do e = 1, scn%mesh%nelem
      if (scn%elem_model(e) == 0) cycle
      mask = elem_dof_mask(scn%mesh%etype(e), scn%mesh%ndim)
      do a = 1, scn%mesh%nen(e)
        n = scn%mesh%conn(a, e)
        present(:, n) = present(:, n) .or. mask
      end do
    end do
    eqn = merge(1, DOF_ABSENT, present)
    do i = 1, size(scn%fixes)
      associate (nodes => scn%mesh%ngroups(scn%fixes(i)%ngroup)%items)
        do d = 1, NODE_DOFS
          if (.not. scn%fixes(i)%dofs(d)) cycle
          where (present(d, nodes)) eqn(d, nodes) = DOF_FIXED
        end do
      end associate
    end do
    neq = 0
    do n = 1, scn%mesh%nnode
      do d = 1, NODE_DOFS
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
    integer, allocatable :: label(:)
    integer :: n, a, nb
    call node_bodies(scn, label, nb)
    allocate (body(neq))
    body = 0
    do n = 1, scn%mesh%nnode
      do a = 1, size(eqn, 1)
        if (eqn(a, n) > 0) body(eqn(a, n)) = label(n)
      end do
    end do
  end subroutine equation_bodies

  !> free(k, b): the rigid mode k of the model (1, 2: the translations x, y; 3: the rotation about
  !> the origin, -y, x on the translations, 1 on RZ; in 3D 4: z, 5, 6: the rotations about x and y)
  !> is a free motion of body b (equation_bodies'
  !> numbering): no node of b has a DOF that the mode moves held by FIX or IMPOSE (a body pinned
  !> at the origin keeps its rotation). An impact correction keeps the momentum of b along its
  !> free modes that the contact conditions leave invariant (docs/contact.md, "What a correction
  !> may change").
  subroutine body_rigid_freedom(scn, eqn, free)
    type(scene_t), intent(in) :: scn
    integer, intent(in) :: eqn(:, :)
    logical, allocatable, intent(out) :: free(:, :)
    integer, allocatable :: label(:)
    logical, allocatable :: imposed(:, :)
    logical :: held(NODE_DOFS)
    integer :: n, nb, nrig
    real(dp) :: tol
    call node_bodies(scn, label, nb)
    call imposed_dofs(scn, imposed)
    nrig = merge(6, 3, scn%mesh%ndim == 3)
    allocate (free(nrig, nb))
    free = .true.
    tol = 0.0_dp
    if (scn%mesh%nnode > 0) tol = 1.0e-12_dp * maxval(abs(scn%mesh%x(:, 1:scn%mesh%nnode)))
    do n = 1, scn%mesh%nnode
      if (label(n) == 0) cycle
      held = eqn(:, n) == DOF_FIXED .or. (imposed(:, n) .and. eqn(:, n) /= DOF_ABSENT)
      if (held(DOF_UX)) free(1, label(n)) = .false.
      if (held(DOF_UY)) free(2, label(n)) = .false.
      ! The rotation about z moves UX by -y, UY by x and RZ by 1.
      if ((held(DOF_UX) .and. abs(scn%mesh%x(2, n)) > tol) .or. (held(DOF_UY) .and. abs(scn%mesh%x(1, n)) > tol) .or. &
        held(DOF_RZ)) free(3, label(n)) = .false.
      if (nrig == 3) cycle
      ! 3D: z (mode 4); the rotation about x (5) moves UY by -z, UZ by y; about y (6) UX by z, UZ by -x.
      if (held(DOF_UZ)) free(4, label(n)) = .false.
      if ((held(DOF_UY) .and. abs(scn%mesh%x(3, n)) > tol) .or. (held(DOF_UZ) .and. abs(scn%mesh%x(2, n)) > tol)) &
        free(5, label(n)) = .false.
      if ((held(DOF_UX) .and. abs(scn%mesh%x(3, n)) > tol) .or. (held(DOF_UZ) .and. abs(scn%mesh%x(1, n)) > tol)) &
        free(6, label(n)) = .false.
    end do
    ! Axisymmetric: a rigid radial translation or an in-plane rotation would stretch the hoops; the
    ! one rigid motion of a ring is along the axis (y).
    if (scene_axisymmetric(scn)) then
      free(1, :) = .false.
      free(3, :) = .false.
    end if
  end subroutine body_rigid_freedom

  !> label(node): the mesh-connected component (through modelled elements) of each node, from 1
  !> in node order; nb components. Nodes of no modelled element are components of their own.
  subroutine node_bodies(scn, label, nb)
    type(scene_t), intent(in) :: scn
    integer, allocatable, intent(out) :: label(:)
    integer, intent(out) :: nb
    integer, allocatable :: parent(:), rlabel(:)
    integer :: e, a, n, ra, rb
    allocate (parent(scn%mesh%nnode), rlabel(scn%mesh%nnode), label(scn%mesh%nnode))
    parent = [(n, n = 1, scn%mesh%nnode)]
    do e = 1, scn%mesh%nelem
      if (scn%elem_model(e) == 0) cycle
      ra = root(scn%mesh%conn(1, e))
      do a = 2, scn%mesh%nen(e)
        rb = root(scn%mesh%conn(a, e))
        if (ra /= rb) parent(rb) = ra
      end do
    end do
    rlabel = 0
    nb = 0
    do n = 1, scn%mesh%nnode
      ra = root(n)
      if (rlabel(ra) == 0) then
        nb = nb + 1
        rlabel(ra) = nb
      end if
      label(n) = rlabel(ra)
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
  end subroutine node_bodies

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
    allocate (mask(NODE_DOFS, scn%mesh%nnode))
    mask = .false.
    do k = 1, size(scn%imposes)
      mask(scn%imposes(k)%dof, scn%mesh%ngroups(scn%imposes(k)%ngroup)%items) = .true.
    end do
  end subroutine imposed_dofs
end module dof_map
