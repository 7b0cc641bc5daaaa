!> Reader for Gmsh meshes, MSH formats 4.1 ($MeshFormat 4.1 0 8; binary 4.1 1 8 in gmsh_binary)
!> and 2.2 (2.2 0 8; its $Nodes and $Elements in gmsh_msh2), in the xy plane, or in a DIMENSION 3
!> scene a volume mesh: 4 (4-node tetrahedron) -> TET4, 5 (8-node hexahedron) -> HEX8, 11 -> TET10,
!> 17 -> HEX20, 6 (6-node prism) -> WEDGE6 (an inverted volume is refused, named); its points,
!> lines and surfaces are no elements there, their nodes join their physical groups (the faces
!> for FIX and contact).
!>
!> Sections read: $MeshFormat, $PhysicalNames, $Entities, $Nodes, $Elements; any other section is
!> skipped. Element types: 15 (point) -> MASS, 1 (2-node line) -> BAR2, 2 (3-node triangle) ->
!> TRI3, 9 (6-node triangle) -> TRI6, 3 (4-node quadrangle) -> QUAD4, 16 (8-node quadrangle,
!> corners then mid-sides 1-2, 2-3, 3-4, 4-1 as ours) -> QUAD8; 8 (3-node line, the boundary
!> curves of second-order meshes) gives no element, its nodes join its physical groups. Surfaces
!> given clockwise (normal -z) are renumbered counter-clockwise.
!>
!> The file is parsed line by line into local arrays and added to the mesh only once all of it is
!> valid, so a failed read leaves the mesh untouched. Every error message starts with
!> "<path>:<line>: ". Cost is O(file size): node tags go through an array over [minTag, maxTag].
module gmsh_reader
  use, intrinsic :: iso_fortran_env, only: int64, iostat_end, iostat_eor
  use kinds, only: dp, zero_tol
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use mesh, only: mesh_t, MAX_COORD
  use element_traits, only: etype_nen, MAX_NEN
  use number_text, only: parse_real_text, NUM_OK
  use array_utils, only: heap_sort, sort_by_key, grow
  use line_reader, only: open_reader, close_reader, next_line, get_int, get_real_tok, fail, tok, clip
  use os_utils, only: is_directory
  use gmsh_state, only: pname_t, gmsh_t, LINE3, node_of, too_many, node_coordinates, gmsh_type_name, data_line, &
    next_line_or_eof, header_ints, end_section, element_kind, store_element, alloc_elements, begin_elements, repeated_name
  use gmsh_msh2, only: read_nodes_msh2, read_elements_msh2
  use gmsh_binary, only: read_msh41_binary
  implicit none
  private
  public :: read_gmsh

contains

  !> Read the Gmsh 4.1 ASCII file `path` and append its nodes, elements and groups to m.
  !> Groups (with P = prefix): element group P (all elements of dimension >= 1) and node group P (all
  !> nodes); for each physical group named NAME (or physical_<tag> when unnamed), element group P.NAME
  !> (its elements, points included) and node group P.NAME (their nodes, sorted). A blank prefix gives
  !> plain NAME groups and no P groups. Physical groups of the same name and different dimensions merge.
  subroutine read_gmsh(m, path, prefix, stat, errmsg)
    type(mesh_t), intent(inout) :: m
    character(len=*), intent(in) :: path
    character(len=*), intent(in) :: prefix
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(gmsh_t) :: g

    stat = STAT_OK
    if (is_directory(path)) then
      call set_error(stat, errmsg, STAT_INPUT, path // ': is a directory, not a Gmsh mesh file')
      return
    end if
    call open_reader(g, path, 'mesh file', stat, errmsg)
    if (stat /= STAT_OK) return

    inquire (unit=g%unit, size=g%fsize)
    g%ndim = m%ndim
    call parse_file(g, m, prefix, stat, errmsg)
    call close_reader(g)
  end subroutine read_gmsh

  !> Parse the open file section by section; on success append its content to m.
  subroutine parse_file(g, m, prefix, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    type(mesh_t), intent(inout) :: m
    character(len=*), intent(in) :: prefix
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical :: ok

    stat = STAT_OK
    call next_line(g, ok, stat, errmsg)
    if (stat /= STAT_OK) return
    if (.not. ok) then
      call fail(g, stat, errmsg, 'empty file, expected $MeshFormat')
      return
    end if
    if (tok(g, 1) /= '$MeshFormat') then
      call fail(g, stat, errmsg, 'expected $MeshFormat on the first line, found "' // clip(g%line) // '"')
      return
    end if
    call read_format(g, stat, errmsg)
    if (stat /= STAT_OK) return
    if (g%binary) then
      call close_reader(g)
      call read_msh41_binary(g, stat, errmsg)
      if (stat == STAT_OK) call commit(g, m, prefix)
      return
    end if

    do
      call next_line(g, ok, stat, errmsg)
      if (stat /= STAT_OK) return
      if (.not. ok) exit
      if (g%ntok /= 1 .or. g%line(g%tb(1):g%tb(1)) /= '$') then
        call fail(g, stat, errmsg, 'expected a section header such as $Nodes, found "' // clip(g%line) // '"')
        return
      end if
      select case (tok(g, 1))
      case ('$MeshFormat')
        call fail(g, stat, errmsg, 'second $MeshFormat section')
      case ('$PhysicalNames')
        call read_physical_names(g, stat, errmsg)
      case ('$Entities')
        call read_entities(g, stat, errmsg)
      case ('$Nodes')
        if (g%version == 22) then
          call read_nodes_msh2(g, stat, errmsg)
        else
          call read_nodes(g, stat, errmsg)
        end if
      case ('$Elements')
        if (g%version == 22) then
          call read_elements_msh2(g, stat, errmsg)
        else
          call read_elements(g, stat, errmsg)
        end if
      case default
        call skip_section(g, stat, errmsg)
      end select
      if (stat /= STAT_OK) return
    end do

    if (.not. g%have_nodes) then
      call fail(g, stat, errmsg, 'end of file: missing $Nodes section')
    else if (.not. g%have_elements) then
      call fail(g, stat, errmsg, 'end of file: missing $Elements section')
    else
      call commit(g, m, prefix)
    end if

  end subroutine parse_file

  ! ---------------------------------------------------------------------------------------------
  ! Sections. Each is entered just after its header line and leaves after its $End line.

  !> $MeshFormat: "4.1 0 8" (version, 0 = ASCII, size of double).
  subroutine read_format(g, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: version
    integer :: ftype, dsize, ierr

    call data_line(g, 'the format line "4.1 0 8"', stat, errmsg)
    if (stat /= STAT_OK) return
    if (g%ntok /= 3) then
      call fail(g, stat, errmsg, 'expected the format line "version file-type data-size" (4.1 0 8), found "' // &
        clip(g%line) // '"')
      return
    end if
    call parse_real_text(tok(g, 1), version, ierr)
    if (ierr /= NUM_OK) then
      call fail(g, stat, errmsg, 'expected a version number, found "' // clip(tok(g, 1)) // '"')
      return
    end if
    if (abs(version - 2.2_dp) <= 1.0e-9_dp) then
      g%version = 22
    else if (abs(version - 4.1_dp) > 1.0e-9_dp) then
      call fail(g, stat, errmsg, 'MSH format version ' // tok(g, 1) // ' is not supported, expected 4.1 or 2.2 ' // &
        '(in Gmsh: Mesh.MshFileVersion = 4.1)')
      return
    end if
    call get_int(g, 2, 0, huge(1), 'the file type', ftype, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_int(g, 3, 0, huge(1), 'the data size', dsize, stat, errmsg)
    if (stat /= STAT_OK) return
    if (ftype /= 0) then
      if (ftype /= 1 .or. g%version /= 41 .or. dsize /= 8) then
        call fail(g, stat, errmsg, 'binary MSH files are read in format 4.1 with 8-byte sizes only (found "' // &
          clip(g%line) // '"; in Gmsh: Mesh.MshFileVersion = 4.1, or Mesh.Binary = 0)')
        return
      end if
      g%binary = .true.
      return                                   ! gmsh_binary reads the rest, $EndMeshFormat included
    end if
    call end_section(g, '$EndMeshFormat', stat, errmsg)
  end subroutine read_format

  !> $PhysicalNames: count, then "dim tag "name"" lines.
  subroutine read_physical_names(g, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: n, i, q1, q2, k
    type(pname_t), allocatable :: tmp(:)

    call header_ints(g, 1, 'the number of physical names', stat, errmsg)
    if (stat /= STAT_OK) return
    call get_int(g, 1, 0, huge(1), 'the number of physical names', n, stat, errmsg)
    if (stat /= STAT_OK) return
    if (too_many(g, n, 6)) then
      call fail(g, stat, errmsg, 'the file is too small to hold the ' // tok(g, 1) // ' physical names announced')
      return
    end if
    ! Several $PhysicalNames sections accumulate.
    if (.not. allocated(g%pn)) allocate (g%pn(0))
    allocate (tmp(g%npn + n))
    tmp(1:g%npn) = g%pn(1:g%npn)
    call move_alloc(tmp, g%pn)
    do i = 1, n
      call data_line(g, 'a physical name line: dim tag "name"', stat, errmsg)
      if (stat /= STAT_OK) return
      q1 = index(g%line, '"')
      q2 = index(g%line, '"', back=.true.)
      if (g%ntok < 3 .or. q1 == 0 .or. q2 <= q1) then
        call fail(g, stat, errmsg, 'expected a physical name line: dim tag "name", found "' // clip(g%line) // '"')
        return
      end if
      g%npn = g%npn + 1
      call get_int(g, 1, 0, 3, 'a dimension (0 to 3)', g%pn(g%npn)%dim, stat, errmsg)
      if (stat /= STAT_OK) return
      call get_int(g, 2, 1, huge(1), 'a physical tag (positive)', g%pn(g%npn)%tag, stat, errmsg)
      if (stat /= STAT_OK) return
      if (g%te(2) >= q1) then
        call fail(g, stat, errmsg, 'expected a physical name line: dim tag "name", found "' // clip(g%line) // '"')
        return
      end if
      g%pn(g%npn)%name = g%line(q1 + 1:q2 - 1)
      k = repeated_name(g)
      if (k > 0) then
        call fail(g, stat, errmsg, 'physical name "' // g%pn(g%npn)%name // '" given twice (dimension ' // &
          tok(g, 1) // ' tag ' // tok(g, 2) // ', and dimension ' // str(g%pn(k)%dim) // ' tag ' // str(g%pn(k)%tag) // &
          '): rebond would merge the two groups; give each its own name')
        return
      end if
    end do
    call end_section(g, '$EndPhysicalNames', stat, errmsg)
  end subroutine read_physical_names

  !> $Entities: numbers of points, curves, surfaces, volumes, then one line per entity:
  !>   point:  tag x y z numPhysicalTags physicalTag...
  !>   others: tag minX minY minZ maxX maxY maxZ numPhysicalTags physicalTag... numBounding boundingTag...
  subroutine read_entities(g, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: counts(0:3), dim, i, k, np, nb, first, bound
    character(len=*), parameter :: what(0:3) = [character(len=7) :: 'point', 'curve', 'surface', 'volume']

    if (g%have_entities) then
      call fail(g, stat, errmsg, 'second $Entities section')
      return
    end if
    g%have_entities = .true.
    call header_ints(g, 4, 'the entity counts "numPoints numCurves numSurfaces numVolumes"', stat, errmsg)
    if (stat /= STAT_OK) return
    do dim = 0, 3
      call get_int(g, dim + 1, 0, huge(1), 'an entity count', counts(dim), stat, errmsg)
      if (stat /= STAT_OK) return
    end do
    if (sum(int(counts, int64)) > huge(1) - 1) then
      call fail(g, stat, errmsg, 'too many entities')
      return
    end if
    if (too_many(g, sum(counts), 8)) then
      call fail(g, stat, errmsg, 'the file is too small to hold the entities announced')
      return
    end if
    allocate (g%ent_dim(sum(counts)), g%ent_tag(sum(counts)), g%ent_ptr(sum(counts) + 1), g%ent_phys(16))
    g%ent_ptr(1) = 1
    do dim = 0, 3
      first = 5
      if (dim > 0) first = 8
      do i = 1, counts(dim)
        call data_line(g, 'a ' // trim(what(dim)) // ' entity line', stat, errmsg)
        if (stat /= STAT_OK) return
        if (g%ntok < first) then
          call fail(g, stat, errmsg, 'expected a ' // trim(what(dim)) // ' entity line with at least ' // &
            str(first) // ' fields, found ' // str(g%ntok))
          return
        end if
        g%nent = g%nent + 1
        g%ent_dim(g%nent) = dim
        call get_int(g, 1, 1, huge(1), 'an entity tag (positive)', g%ent_tag(g%nent), stat, errmsg)
        if (stat /= STAT_OK) return
        do k = 2, first - 1
          call get_real_tok(g, k, 'a coordinate', stat, errmsg)
          if (stat /= STAT_OK) return
        end do
        call get_int(g, first, 0, g%ntok - first, 'the number of physical tags', np, stat, errmsg)
        if (stat /= STAT_OK) return
        nb = 0
        if (dim > 0) then
          if (g%ntok < first + np + 1) then
            call fail(g, stat, errmsg, 'expected the number of bounding entities after the physical tags')
            return
          end if
          call get_int(g, first + np + 1, 0, huge(1), 'the number of bounding entities', nb, stat, errmsg)
          if (stat /= STAT_OK) return
          nb = nb + 1
        end if
        if (g%ntok /= first + np + nb) then
          call fail(g, stat, errmsg, 'expected ' // str(first + np + nb) // ' fields on this ' // trim(what(dim)) // &
            ' entity line, found ' // str(g%ntok))
          return
        end if
        call grow(g%ent_phys, g%nphys + np)
        do k = 1, np
          ! Gmsh may write a physical tag negated to flip the orientation; the group is the same.
          call get_int(g, first + k, -huge(1), huge(1), 'a physical tag', g%ent_phys(g%nphys + k), stat, errmsg)
          if (stat /= STAT_OK) return
          g%ent_phys(g%nphys + k) = abs(g%ent_phys(g%nphys + k))
        end do
        g%nphys = g%nphys + np
        g%ent_ptr(g%nent + 1) = g%nphys + 1
        do k = first + np + 2, g%ntok
          call get_int(g, k, -huge(1), huge(1), 'a bounding entity tag', bound, stat, errmsg)
          if (stat /= STAT_OK) return
        end do
      end do
    end do
    call end_section(g, '$EndEntities', stat, errmsg)
  end subroutine read_entities

  !> $Nodes: "numEntityBlocks numNodes minNodeTag maxNodeTag", then per block
  !> "entityDim entityTag parametric numNodesInBlock", its node tags (one per line), its coordinates
  !> "x y z [u [v [w]]]" (one node per line).
  subroutine read_nodes(g, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: nblock, nnode, b, edim, etag, param, nb, k, tag, ios, zline
    integer, allocatable :: btag(:), perm(:)
    integer(int64) :: range
    real(dp) :: xyz(3), z0, zdev, ext
    real(dp) :: lo(2), hi(2)

    if (g%have_nodes) then
      call fail(g, stat, errmsg, 'second $Nodes section')
      return
    end if
    g%have_nodes = .true.
    call header_ints(g, 4, 'the node header "numEntityBlocks numNodes minNodeTag maxNodeTag"', stat, errmsg)
    if (stat /= STAT_OK) return
    call get_int(g, 1, 0, huge(1), 'the number of entity blocks', nblock, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_int(g, 2, 0, huge(1), 'the number of nodes', nnode, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_int(g, 3, 0, huge(1), 'the minimum node tag', g%tagmin, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_int(g, 4, 0, huge(1), 'the maximum node tag', g%tagmax, stat, errmsg)
    if (stat /= STAT_OK) return
    if (nnode > 0 .and. int(g%tagmax, int64) - g%tagmin + 1 < nnode) then
      call fail(g, stat, errmsg, 'node tag range [' // tok(g, 3) // ', ' // tok(g, 4) // '] cannot hold ' // &
        tok(g, 2) // ' nodes')
      return
    end if
    ! A node takes at least 8 bytes ("t\n" and "x y z\n"): a larger count is garbage, not worth allocating.
    if (too_many(g, nnode, 8)) then
      call fail(g, stat, errmsg, 'the file is too small to hold the ' // tok(g, 2) // ' nodes announced')
      return
    end if
    if (nnode == 0) then
      g%tagmin = 1
      g%tagmax = 0
    end if
    ! Tags go through a direct array over [tagmin, tagmax] unless the range is much larger than the
    ! number of nodes (sparse tags); then through a sorted list and binary search.
    range = int(g%tagmax, int64) - g%tagmin + 1
    g%dense = range <= max(10000000_int64, 4_int64 * nnode)
    if (g%dense) then
      allocate (g%x(3, nnode), g%tag_of(nnode), g%node_of_tag(g%tagmin:g%tagmax), btag(0), stat=ios)
    else
      allocate (g%x(3, nnode), g%tag_of(nnode), g%sorted_tag(nnode), btag(0), stat=ios)
    end if
    if (ios /= 0) then
      call fail(g, stat, errmsg, 'cannot allocate ' // tok(g, 2) // ' nodes with tags in [' // tok(g, 3) // ', ' // &
        tok(g, 4) // ']')
      return
    end if
    if (g%dense) g%node_of_tag = 0
    z0 = 0.0_dp
    zdev = 0.0_dp
    zline = 0
    lo = huge(1.0_dp)
    hi = -huge(1.0_dp)

    do b = 1, nblock
      call header_ints(g, 4, 'a node block header "entityDim entityTag parametric numNodesInBlock"', stat, errmsg)
      if (stat /= STAT_OK) return
      call get_int(g, 1, 0, 3, 'an entity dimension (0 to 3)', edim, stat, errmsg)
      if (stat /= STAT_OK) return
      call get_int(g, 2, -huge(1), huge(1), 'an entity tag', etag, stat, errmsg)
      if (stat /= STAT_OK) return
      call get_int(g, 3, 0, 1, 'the parametric flag (0 or 1)', param, stat, errmsg)
      if (stat /= STAT_OK) return
      call get_int(g, 4, 0, nnode - g%nnode, 'the number of nodes in the block (at most the ' // &
        'nodes announced in the $Nodes header not yet read)', nb, stat, errmsg)
      if (stat /= STAT_OK) return
      if (size(btag) < nb) then
        deallocate (btag)
        allocate (btag(nb))
      end if
      do k = 1, nb
        call data_line(g, 'a node tag', stat, errmsg)
        if (stat /= STAT_OK) return
        if (g%ntok /= 1) then
          call fail(g, stat, errmsg, 'expected one node tag on the line, found "' // clip(g%line) // '"')
          return
        end if
        call get_int(g, 1, g%tagmin, g%tagmax, 'a node tag in the header range [minNodeTag, maxNodeTag]', &
          tag, stat, errmsg)
        if (stat /= STAT_OK) return
        if (g%dense) then
          if (g%node_of_tag(tag) /= 0) then
            call fail(g, stat, errmsg, 'duplicate node tag ' // str(tag))
            return
          end if
          g%node_of_tag(tag) = g%nnode + k
        else
          g%sorted_tag(g%nnode + k) = tag
        end if
        btag(k) = tag
        g%tag_of(g%nnode + k) = tag
      end do
      do k = 1, nb
        call node_coordinates(g, btag(k), 3 + param * min(edim, 3), xyz, stat, errmsg)
        if (stat /= STAT_OK) return
        g%x(:, g%nnode + k) = xyz
        lo = min(lo, xyz(1:2))
        hi = max(hi, xyz(1:2))
        if (g%nnode + k == 1) z0 = xyz(3)
        if (abs(xyz(3) - z0) > zdev) then
          zdev = abs(xyz(3) - z0)
          zline = g%lineno
        end if
      end do
      g%nnode = g%nnode + nb
    end do
    if (g%nnode /= nnode) then
      call next_line_or_eof(g, stat, errmsg)
      if (stat /= STAT_OK) return
      call fail(g, stat, errmsg, 'expected ' // str(nnode) // ' nodes as announced in the $Nodes header, the ' // &
        'blocks hold ' // str(g%nnode))
      return
    end if
    ! A planar scene: the mesh must lie in a plane z = constant (normally z = 0).
    ext = 0.0_dp
    if (nnode > 0) ext = maxval(hi - lo)
    if (zdev > 1.0e-9_dp * ext .and. g%ndim == 2) then
      g%lineno = zline
      call fail(g, stat, errmsg, 'node out of the xy plane: z differs by ' // str(zdev) // ' from the first node; ' // &
        'expected a plane mesh with constant z (a 3D mesh needs DIMENSION 3)')
      return
    end if
    call end_section(g, '$EndNodes', stat, errmsg)
    if (stat /= STAT_OK .or. g%dense) return
    ! Sparse tags: sort, then reject duplicates (reported at $EndNodes, the tag lines being gone).
    allocate (perm(nnode))
    perm = [(k, k = 1, nnode)]
    call sort_by_key(g%sorted_tag, perm)
    g%sorted_node = perm
    do k = 2, nnode
      if (g%sorted_tag(k) == g%sorted_tag(k - 1)) then
        call fail(g, stat, errmsg, 'duplicate node tag ' // str(g%sorted_tag(k)) // ' in this $Nodes section')
        return
      end if
    end do
  end subroutine read_nodes

  !> $Elements: "numEntityBlocks numElements minElementTag maxElementTag", then per block
  !> "entityDim entityTag elementType numElementsInBlock" and one "elementTag nodeTag..." line per element.
  subroutine read_elements(g, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: nblock, nelem, b, edim, etag, gtype, nb, k, j, et, nen, dim, ent, tag, node, etag_dummy
    integer :: nodes(MAX_NEN)

    call begin_elements(g, stat, errmsg)
    if (stat /= STAT_OK) return
    call header_ints(g, 4, 'the element header "numEntityBlocks numElements minElementTag maxElementTag"', &
      stat, errmsg)
    if (stat /= STAT_OK) return
    call get_int(g, 1, 0, huge(1), 'the number of entity blocks', nblock, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_int(g, 2, 0, huge(1), 'the number of elements', nelem, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_int(g, 3, 0, huge(1), 'the minimum element tag', etag_dummy, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_int(g, 4, 0, huge(1), 'the maximum element tag', etag_dummy, stat, errmsg)
    if (stat /= STAT_OK) return
    call alloc_elements(g, nelem, 4, tok(g, 2), stat, errmsg)
    if (stat /= STAT_OK) return

    do b = 1, nblock
      call header_ints(g, 4, 'an element block header "entityDim entityTag elementType numElementsInBlock"', &
        stat, errmsg)
      if (stat /= STAT_OK) return
      call get_int(g, 1, 0, 3, 'an entity dimension (0 to 3)', edim, stat, errmsg)
      if (stat /= STAT_OK) return
      call get_int(g, 2, -huge(1), huge(1), 'an entity tag', etag, stat, errmsg)
      if (stat /= STAT_OK) return
      call get_int(g, 3, 1, huge(1), 'an element type', gtype, stat, errmsg)
      if (stat /= STAT_OK) return
      call element_kind(g, gtype, et, nen, dim, stat, errmsg)
      if (stat /= STAT_OK) return
      if (edim /= dim) then
        call fail(g, stat, errmsg, 'element type ' // str(gtype) // ' (' // gmsh_type_name(gtype) // ') in a block ' // &
          'of dimension ' // str(edim) // ', expected dimension ' // str(dim))
        return
      end if
      call get_int(g, 4, 0, nelem - g%nelem, 'the number of elements in the block (at most the elements ' // &
        'announced in the $Elements header not yet read)', nb, stat, errmsg)
      if (stat /= STAT_OK) return
      ! Entity of the block (its physical groups), 0 if not listed in $Entities.
      ent = 0
      do k = 1, g%nent
        if (g%ent_dim(k) == edim .and. g%ent_tag(k) == etag) then
          ent = k
          exit
        end if
      end do
      do k = 1, nb
        call data_line(g, 'an element line "elementTag nodeTag..."', stat, errmsg)
        if (stat /= STAT_OK) return
        if (g%ntok /= 1 + nen) then
          call fail(g, stat, errmsg, 'expected an element tag and ' // str(nen) // ' node tags (' // &
            gmsh_type_name(gtype) // '), found ' // str(g%ntok) // ' fields')
          return
        end if
        call get_int(g, 1, 0, huge(1), 'an element tag', tag, stat, errmsg)
        if (stat /= STAT_OK) return
        do j = 1, nen
          call get_int(g, 1 + j, -huge(1), huge(1), 'a node tag', tag, stat, errmsg)
          if (stat /= STAT_OK) return
          node = node_of(g, tag)
          if (node == 0) then
            call fail(g, stat, errmsg, 'unknown node tag ' // str(tag) // ', expected a tag listed in $Nodes')
            return
          end if
          nodes(j) = node
        end do
        call store_element(g, gtype, et, dim, ent, nodes(1:nen), stat, errmsg)
        if (stat /= STAT_OK) return
      end do
    end do
    if (g%nelem /= nelem) then
      call next_line_or_eof(g, stat, errmsg)
      if (stat /= STAT_OK) return
      call fail(g, stat, errmsg, 'expected ' // str(nelem) // ' elements as announced in the $Elements header, ' // &
        'the blocks hold ' // str(g%nelem))
      return
    end if
    call end_section(g, '$EndElements', stat, errmsg)
  end subroutine read_elements

  !> Skip an unknown section up to its $End line.
  subroutine skip_section(g, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: endname
    integer :: start
    logical :: ok

    stat = STAT_OK
    if (index(tok(g, 1), '$End') == 1) then
      call fail(g, stat, errmsg, 'unexpected ' // tok(g, 1) // ', expected a section header such as $Nodes')
      return
    end if
    endname = '$End' // tok(g, 1)
    endname = endname(1:4) // endname(6:)
    start = g%lineno
    do
      call next_line(g, ok, stat, errmsg)
      if (stat /= STAT_OK) return
      if (.not. ok) then
        call fail(g, stat, errmsg, 'unexpected end of file, expected ' // endname // ' closing the section opened ' // &
          'at line ' // str(start))
        return
      end if
      if (tok(g, 1) == endname) return
    end do
  end subroutine skip_section

  ! ---------------------------------------------------------------------------------------------
  ! Building the mesh.

  !> Append the parsed nodes, elements and groups to m.
  subroutine commit(g, m, prefix)
    type(gmsh_t), intent(inout) :: g
    type(mesh_t), intent(inout) :: m
    character(len=*), intent(in) :: prefix
    integer, allocatable :: nid(:), eid(:), gid(:), cnt(:), ptr(:), items(:), mark(:), nodes(:)
    character(len=:), allocatable :: pre
    type(pname_t), allocatable :: grp(:)
    integer :: ngrp, i, j, k, e, n, nn

    allocate (nid(g%nnode), eid(g%nelem))
    do i = 1, g%nnode
      call m%add_node(g%x(1:m%ndim, i), nid(i), g%tag_of(i))
    end do
    eid = 0
    do e = 1, g%nelem                          ! (a 3-node line is no element: its nodes join groups)
      if (g%etype(e) /= LINE3) call m%add_element(g%etype(e), nid(g%conn(1:etype_nen(g%etype(e)), e)), eid(e))
    end do

    pre = ''
    if (len_trim(prefix) > 0) then
      pre = trim(prefix) // '.'
      call m%add_node_group(trim(prefix), nid)
      call m%add_elem_group(trim(prefix), pack(eid, g%edim >= 1 .and. eid > 0))
    end if

    ! Physical groups: one per distinct name; gid(j) is the group of the entity/physical-tag pair j,
    ! 0 when it repeats a group already given to the same entity.
    allocate (grp(g%nphys + g%npn), gid(g%nphys))
    ngrp = 0
    gid = 0
    do i = 1, g%nent
      do j = g%ent_ptr(i), g%ent_ptr(i + 1) - 1
        call group_index(group_name(g, g%ent_dim(i), g%ent_phys(j)), k)
        if (all(gid(g%ent_ptr(i):j - 1) /= k)) gid(j) = k
      end do
    end do
    do i = 1, g%npn  ! named groups with no entity still exist, empty
      call group_index(group_name(g, g%pn(i)%dim, g%pn(i)%tag), k)
    end do

    ! Elements of each group, in CSR form.
    allocate (cnt(ngrp), ptr(ngrp + 1))
    cnt = 0
    do e = 1, g%nelem
      if (g%eent(e) == 0) cycle
      do j = g%ent_ptr(g%eent(e)), g%ent_ptr(g%eent(e) + 1) - 1
        if (gid(j) > 0) cnt(gid(j)) = cnt(gid(j)) + 1
      end do
    end do
    ptr(1) = 1
    do k = 1, ngrp
      ptr(k + 1) = ptr(k) + cnt(k)
    end do
    allocate (items(ptr(ngrp + 1) - 1))
    cnt = 0
    do e = 1, g%nelem
      if (g%eent(e) == 0) cycle
      do j = g%ent_ptr(g%eent(e)), g%ent_ptr(g%eent(e) + 1) - 1
        k = gid(j)
        if (k == 0) cycle
        items(ptr(k) + cnt(k)) = e
        cnt(k) = cnt(k) + 1
      end do
    end do

    ! Node groups: unique nodes of the group's elements (marked with the group number), sorted.
    allocate (mark(g%nnode), nodes(g%nnode))
    mark = 0
    do k = 1, ngrp
      nn = 0
      do i = ptr(k), ptr(k + 1) - 1
        e = items(i)
        do j = 1, g%enen(e)
          n = g%conn(j, e)
          if (mark(n) /= k) then
            mark(n) = k
            nn = nn + 1
            nodes(nn) = n
          end if
        end do
      end do
      call heap_sort(nodes(1:nn))
      call m%add_elem_group(pre // grp(k)%name, pack(eid(items(ptr(k):ptr(k + 1) - 1)), &
        eid(items(ptr(k):ptr(k + 1) - 1)) > 0))
      call m%add_node_group(pre // grp(k)%name, nid(nodes(1:nn)))
    end do

  contains

    !> Index of the group called name, appended if new.
    subroutine group_index(name, idx)
      character(len=*), intent(in) :: name
      integer, intent(out) :: idx
      do idx = 1, ngrp
        if (grp(idx)%name == name) return
      end do
      ngrp = ngrp + 1
      grp(ngrp)%name = name
      idx = ngrp
    end subroutine group_index
  end subroutine commit

  !> Name of physical group (dim, tag): from $PhysicalNames, else physical_<tag>.
  pure function group_name(g, dim, tag) result(name)
    type(gmsh_t), intent(in) :: g
    integer, intent(in) :: dim, tag
    character(len=:), allocatable :: name
    integer :: i
    do i = 1, g%npn
      if (g%pn(i)%dim == dim .and. g%pn(i)%tag == tag .and. len(g%pn(i)%name) > 0) then
        name = g%pn(i)%name
        return
      end if
    end do
    name = 'physical_' // str(tag)
  end function group_name

end module gmsh_reader
