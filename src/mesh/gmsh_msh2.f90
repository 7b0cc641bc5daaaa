!> The $Nodes and $Elements sections of Gmsh's MSH 2.2 ASCII format (gmsh_reader reads the rest):
!>   $Nodes: number-of-nodes, then "tag x y z" lines;
!>   $Elements: number-of-elements, then "tag type number-of-tags tags... node-tags..." lines,
!>   the first tag the physical group, the second the elementary entity.
!> MSH 2.2 has no $Entities: each (dimension, physical tag) of the elements becomes an entity with
!> that one physical group, so that gmsh_reader's commit builds the same groups as from 4.1.
module gmsh_msh2
  use kinds, only: dp
  use errors, only: STAT_OK, str
  use line_reader, only: get_int, fail, tok, clip
  use element_traits, only: MAX_NEN
  use gmsh_state, only: gmsh_t, node_of, too_many, gmsh_type_name, data_line, header_ints, end_section, &
    element_kind, store_element, index_tags, alloc_elements, begin_elements
  implicit none
  private
  public :: read_nodes_msh2, read_elements_msh2

contains

  !> $Nodes (MSH 2.2): the count, then one "tag x y z" line per node, in the xy plane.
  subroutine read_nodes_msh2(g, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: nnode, k, tag, ios, dup
    real(dp) :: xyz(3), z0
    character(len=:), allocatable :: what
    if (g%have_nodes) then
      call fail(g, stat, errmsg, 'second $Nodes section')
      return
    end if
    g%have_nodes = .true.
    call header_ints(g, 1, 'the number of nodes', stat, errmsg)
    if (stat /= STAT_OK) return
    call get_int(g, 1, 0, huge(1), 'the number of nodes', nnode, stat, errmsg)
    if (stat /= STAT_OK) return
    if (too_many(g, nnode, 8)) then
      call fail(g, stat, errmsg, 'the file is too small to hold the ' // tok(g, 1) // ' nodes announced')
      return
    end if
    allocate (g%x(3, nnode), g%tag_of(nnode), stat=ios)
    if (ios /= 0) then
      call fail(g, stat, errmsg, 'cannot allocate ' // tok(g, 1) // ' nodes')
      return
    end if
    z0 = 0.0_dp
    what = 'a node line "tag x y z"'
    do k = 1, nnode
      call data_line(g, what, stat, errmsg)
      if (stat /= STAT_OK) return
      if (g%ntok /= 4) then
        call fail(g, stat, errmsg, 'expected ' // what // ', found "' // clip(g%line) // '"')
        return
      end if
      call get_int(g, 1, 1, huge(1), 'a node tag', tag, stat, errmsg)
      if (stat /= STAT_OK) return
      call node_xyz(g, xyz, stat, errmsg)
      if (stat /= STAT_OK) return
      if (k == 1) z0 = xyz(3)
      if (abs(xyz(3) - z0) > 1.0e-9_dp * max(1.0_dp, maxval(abs(xyz(1:2)))) .and. g%ndim == 2) then
        call fail(g, stat, errmsg, 'node out of the xy plane: z differs by ' // str(abs(xyz(3) - z0)) // &
          ' from the first node; expected a plane mesh with constant z (a 3D mesh needs DIMENSION 3)')
        return
      end if
      g%x(:, k) = xyz
      g%tag_of(k) = tag
    end do
    g%nnode = nnode
    call end_section(g, '$EndNodes', stat, errmsg)
    if (stat /= STAT_OK) return
    call index_tags(g, dup)
    if (dup /= 0) call fail(g, stat, errmsg, 'duplicate node tag ' // str(dup) // ' in this $Nodes section')
  end subroutine read_nodes_msh2

  !> The coordinates x y z of the current node line (words 2 to 4).
  subroutine node_xyz(g, xyz, stat, errmsg)
    use number_text, only: parse_real_text, NUM_OK
    use mesh, only: MAX_COORD
    type(gmsh_t), intent(inout) :: g
    real(dp), intent(out) :: xyz(3)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: i, ierr
    stat = STAT_OK
    do i = 1, 3
      call parse_real_text(tok(g, 1 + i), xyz(i), ierr)
      if (ierr /= NUM_OK .or. .not. abs(xyz(i)) <= MAX_COORD) then
        call fail(g, stat, errmsg, 'expected a node coordinate within ±1e100, found "' // clip(tok(g, 1 + i)) // '"')
        return
      end if
    end do
  end subroutine node_xyz

  !> $Elements (MSH 2.2): the count, then "tag type ntags tags... nodes..." lines.
  subroutine read_elements_msh2(g, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: nelem, k, j, tag, gtype, ntag, phys, et, nen, dim, ent, node
    integer :: nodes(MAX_NEN)
    call begin_elements(g, stat, errmsg)
    if (stat /= STAT_OK) return
    call header_ints(g, 1, 'the number of elements', stat, errmsg)
    if (stat /= STAT_OK) return
    call get_int(g, 1, 0, huge(1), 'the number of elements', nelem, stat, errmsg)
    if (stat /= STAT_OK) return
    call alloc_elements(g, nelem, 6, tok(g, 1), stat, errmsg)
    if (stat /= STAT_OK) return
    allocate (g%ent_dim(0), g%ent_tag(0), g%ent_ptr(1), g%ent_phys(0))
    g%ent_ptr(1) = 1
    do k = 1, nelem
      call data_line(g, 'an element line "tag type number-of-tags tags... node-tags..."', stat, errmsg)
      if (stat /= STAT_OK) return
      call get_int(g, 1, 0, huge(1), 'an element tag', tag, stat, errmsg)
      if (stat == STAT_OK) call get_int(g, 2, 1, huge(1), 'an element type', gtype, stat, errmsg)
      if (stat == STAT_OK) call get_int(g, 3, 0, 1000, 'the number of tags', ntag, stat, errmsg)
      if (stat /= STAT_OK) return
      call element_kind(g, gtype, et, nen, dim, stat, errmsg)
      if (stat /= STAT_OK) return
      if (g%ntok /= 3 + ntag + nen) then
        call fail(g, stat, errmsg, 'element ' // str(tag) // ': expected ' // str(ntag) // ' tags and ' // str(nen) // &
          ' node tags (' // gmsh_type_name(gtype) // '), found ' // str(g%ntok - 3) // ' fields after the type')
        return
      end if
      phys = 0
      if (ntag >= 1) call get_int(g, 4, -huge(1), huge(1), 'a physical tag', phys, stat, errmsg)
      if (stat /= STAT_OK) return
      do j = 1, nen
        call get_int(g, 3 + ntag + j, -huge(1), huge(1), 'a node tag', node, stat, errmsg)
        if (stat /= STAT_OK) return
        nodes(j) = node_of(g, node)
        if (nodes(j) == 0) then
          call fail(g, stat, errmsg, 'element ' // str(tag) // ': unknown node tag ' // str(node) // &
            ', expected a tag listed in $Nodes')
          return
        end if
      end do
      ent = 0
      if (phys /= 0) call entity_of(g, dim, abs(phys), ent)   ! (a negative tag flips orientation only)
      call store_element(g, gtype, et, dim, ent, nodes(1:nen), stat, errmsg)
      if (stat /= STAT_OK) return
    end do
    call end_section(g, '$EndElements', stat, errmsg)
  end subroutine read_elements_msh2

  !> The synthetic entity of (dim, physical tag): appended with that one physical group if new.
  subroutine entity_of(g, dim, phys, ent)
    type(gmsh_t), intent(inout) :: g
    integer, intent(in) :: dim, phys
    integer, intent(out) :: ent
    do ent = 1, g%nent
      if (g%ent_dim(ent) == dim .and. g%ent_tag(ent) == phys) return
    end do
    g%nent = g%nent + 1
    ent = g%nent
    g%ent_dim = [g%ent_dim, dim]
    g%ent_tag = [g%ent_tag, phys]
    g%ent_phys = [g%ent_phys, phys]
    g%ent_ptr = [g%ent_ptr, g%ent_ptr(ent) + 1]
    g%nphys = g%nphys + 1
  end subroutine entity_of
end module gmsh_msh2
