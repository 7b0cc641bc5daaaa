!> Scene input: the mesh statements (DIMENSION, NODE, ELEMENT, GROUP, LINE, RECTANGLE, BOX, GMSH).
!> Their grammar (schema) and their handlers; scene_loader calls them.
module scene_mesh
  use kinds, only: dp, zero_tol
  use errors, only: STAT_OK, STAT_INPUT, set_error, str, upper
  use statement, only: statement_t, stmt_error, find_param, get_real, get_int, get_word, to_int
  use statement_schema, only: schema_t
  use mesh_generators, only: generate_line, generate_rectangle, MAX_GENERATED_ELEMENTS
  use mesh_box, only: generate_box
  use mesh, only: MAX_COORD
  use gmsh_reader, only: read_gmsh
  use scene, only: scene_t
  use scene_helpers, only: get_etype, get_point, resolve_path
  use scene_groups, only: groups_schema, do_group
  use element_traits, only: NUM_ETYPES, FAMILY_LINE, FAMILY_SURFACE, FAMILY_VOLUME, etypes_of_family, etype_nen, etype_name
  implicit none
  private
  public :: mesh_schema, mesh_statement

contains

  subroutine mesh_schema(sch)
    type(schema_t), intent(inout) :: sch
    call sch%add_keyword('DIMENSION', 1, 1, once=.true.)
    call sch%add_keyword('NODE', 1, 1)
    call sch%add_param('NODE', 'AT', 2, 3)
    call sch%add_keyword('ELEMENT', 1, 1)
    call sch%add_param('ELEMENT', 'TYPE', 1, 1)
    call sch%add_param('ELEMENT', 'NODES', 1, -1)
    call groups_schema(sch)
    call sch%add_keyword('LINE', 1, 1)
    call sch%add_param('LINE', 'FROM', 2, 2)
    call sch%add_param('LINE', 'TO', 2, 2)
    call sch%add_param('LINE', 'ELEMENTS', 1, 1)
    call sch%add_param('LINE', 'TYPE', 1, 1)
    call sch%add_keyword('RECTANGLE', 1, 1)
    call sch%add_param('RECTANGLE', 'ORIGIN', 2, 2)
    call sch%add_param('RECTANGLE', 'SIZE', 2, 2)
    call sch%add_param('RECTANGLE', 'ELEMENTS', 2, 2)
    call sch%add_param('RECTANGLE', 'TYPE', 1, 1)
    call sch%add_param('RECTANGLE', 'ANGLE', 1, 1)
    call sch%add_keyword('BOX', 1, 1)
    call sch%add_param('BOX', 'ORIGIN', 3, 3)
    call sch%add_param('BOX', 'SIZE', 3, 3)
    call sch%add_param('BOX', 'ELEMENTS', 3, 3)
    call sch%add_param('BOX', 'TYPE', 1, 1)
    call sch%add_keyword('GMSH', 1, 1)
    call sch%add_param('GMSH', 'FILE', 1, 1)
  end subroutine mesh_schema

  !> One mesh statement (pass 1 of load_scene).
  subroutine mesh_statement(scn, st, path, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (st%keyword /= 'DIMENSION') call dimension_known(scn, st, stat, errmsg)
    if (stat /= STAT_OK) return
    select case (st%keyword)
    case ('DIMENSION')
      call do_dimension(scn, st, stat, errmsg)
    case ('NODE')
      call do_node(scn, st, stat, errmsg)
    case ('ELEMENT')
      call do_element(scn, st, stat, errmsg)
    case ('GROUP')
      call check_new_group_name(scn, st, stat, errmsg)
      if (stat == STAT_OK) call do_group(scn, st, stat, errmsg)
    case ('LINE')
      call do_line(scn, st, stat, errmsg)
    case ('RECTANGLE')
      call do_rectangle(scn, st, stat, errmsg)
    case ('BOX')
      call do_box(scn, st, stat, errmsg)
    case ('GMSH')
      call do_gmsh(scn, st, path, stat, errmsg)
    end select
  end subroutine mesh_statement

  !> DIMENSION 2 (the default) or 3, before any statement that makes nodes (its dimension is theirs).
  subroutine do_dimension(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: d
    call to_int(st%lead(1), st, d, stat, errmsg)
    if (stat /= STAT_OK) return
    if (d /= 2 .and. d /= 3) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected DIMENSION 2 or 3', st%lead(1)))
    else if (scn%mesh%nnode > 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'DIMENSION comes before the statements that make ' // &
        'nodes (NODE, LINE, RECTANGLE, BOX, GMSH)', st%lead(1)))
    else
      scn%mesh%ndim = d
    end if
  end subroutine do_dimension

  !> The mesh statements of one dimension: LINE and RECTANGLE are planar, BOX needs DIMENSION 3 (GMSH
  !> reads a plane mesh in 2D, a volume mesh in 3D).
  subroutine dimension_known(scn, st, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (scn%mesh%ndim == 3 .and. (st%keyword == 'LINE' .or. st%keyword == 'RECTANGLE')) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, st%keyword // ' makes a planar mesh; this scene is ' // &
        'DIMENSION 3 (BOX, GMSH, NODE … AT x y z, ELEMENT)', st%lead(1)))
    else if (scn%mesh%ndim == 2 .and. st%keyword == 'BOX') then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'BOX needs DIMENSION 3 (give it before the mesh)', st%lead(1)))
    end if
  end subroutine dimension_known

  subroutine do_node(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: xy(scn%mesh%ndim)
    integer :: id
    call check_new_group_name(scn, st, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_point(st, 'AT', xy, stat, errmsg)
    if (stat /= STAT_OK) return
    call scn%mesh%add_node(xy, id)
    call scn%mesh%add_node_group(st%lead(1)%text, [id])
  end subroutine do_node

  !> A new group name must not shadow an existing node or element group.
  subroutine check_new_group_name(scn, st, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (scn%mesh%find_node_group(st%lead(1)%text) > 0 .or. scn%mesh%find_elem_group(st%lead(1)%text) > 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'a group of this name already exists', st%lead(1)))
    end if
  end subroutine check_new_group_name

  subroutine do_element(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: et, k, nen, nv, i, j, ig, id
    integer, allocatable :: nodes(:), ids(:)
    call check_new_group_name(scn, st, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_etype(st, 'TYPE', [(k, k = 1, NUM_ETYPES)], et, stat, errmsg)
    if (stat /= STAT_OK) return
    k = find_param(st, 'NODES')
    if (k == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'missing parameter NODES'))
      return
    end if
    nen = etype_nen(et)
    nv = size(st%params(k)%values)
    if (mod(nv, nen) /= 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'NODES lists ' // str(nv) // ' nodes, not a multiple of ' &
        // str(nen) // ' (nodes of a ' // etype_name(et) // ')', st%params(k)%keytok))
      return
    end if
    allocate (nodes(nen), ids(nv / nen))
    do i = 1, nv / nen
      do j = 1, nen
        associate (tok => st%params(k)%values((i - 1) * nen + j))
          ig = scn%mesh%find_node_group(tok%text)
          if (ig == 0) then
            call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'unknown node group', tok))
            return
          end if
          if (size(scn%mesh%ngroups(ig)%items) /= 1) then
            call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'node group has ' // &
              str(size(scn%mesh%ngroups(ig)%items)) // ' nodes; an element node must name one node', tok))
            return
          end if
          nodes(j) = scn%mesh%ngroups(ig)%items(1)
        end associate
      end do
      call scn%mesh%add_element(et, nodes, id)
      ids(i) = id
    end do
    call scn%mesh%add_elem_group(st%lead(1)%text, ids)
  end subroutine do_element

  subroutine do_line(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: p0(2), p1(2)
    integer :: nel, et
    call check_new_group_name(scn, st, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_point(st, 'FROM', p0, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_point(st, 'TO', p1, stat, errmsg)
    if (stat /= STAT_OK) return
    ! Upper bound: an absurd count must be an input error, not an allocation failure (fuzz).
    call get_int(st, 'ELEMENTS', nel, stat, errmsg, lower=1, lower_inclusive=.true., upper=MAX_GENERATED_ELEMENTS, &
      upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_etype(st, 'TYPE', etypes_of_family(FAMILY_LINE), et, stat, errmsg)
    if (stat /= STAT_OK) return
    if (norm2(p1 - p0) <= zero_tol * max(1.0_dp, norm2(p0), norm2(p1))) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'FROM and TO coincide: zero-length line', &
        st%params(find_param(st, 'TO'))%keytok))
      return
    end if
    call generate_line(scn%mesh, st%lead(1)%text, p0, p1, nel, et, stat, errmsg)
    if (stat /= STAT_OK) errmsg = stmt_error(st, errmsg)
  end subroutine do_line

  subroutine do_rectangle(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: origin(2), lxy(2), angle
    integer :: nx, ny, et
    real(dp), parameter :: pi = acos(-1.0_dp)
    call check_new_group_name(scn, st, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_point(st, 'ORIGIN', origin, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_real(st, 'SIZE', lxy(1), stat, errmsg, index=1, lower=0.0_dp, lower_inclusive=.false., upper=MAX_COORD)
    if (stat /= STAT_OK) return
    call get_real(st, 'SIZE', lxy(2), stat, errmsg, index=2, lower=0.0_dp, lower_inclusive=.false., upper=MAX_COORD)
    if (stat /= STAT_OK) return
    call get_int(st, 'ELEMENTS', nx, stat, errmsg, index=1, lower=1, lower_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_int(st, 'ELEMENTS', ny, stat, errmsg, index=2, lower=1, lower_inclusive=.true.)
    if (stat /= STAT_OK) return
    ! nx*ny is bounded without forming it (it may overflow): an absurd mesh is an input error, not an
    ! allocation failure or hours of node generation (found by tests/fuzz/fuzz.py).
    if (nx > MAX_GENERATED_ELEMENTS / ny) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'ELEMENTS ' // str(nx) // ' x ' // str(ny) // &
        ' exceeds the limit of ' // str(MAX_GENERATED_ELEMENTS) // ' elements', &
        st%params(find_param(st, 'ELEMENTS'))%values(1)))
      return
    end if
    call get_etype(st, 'TYPE', etypes_of_family(FAMILY_SURFACE), et, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_real(st, 'ANGLE', angle, stat, errmsg, default=0.0_dp)
    if (stat /= STAT_OK) return
    call generate_rectangle(scn%mesh, st%lead(1)%text, origin, lxy(1), lxy(2), nx, ny, et, stat, errmsg, &
      angle=angle * pi / 180.0_dp)
    if (stat /= STAT_OK) errmsg = stmt_error(st, errmsg)
  end subroutine do_rectangle

  !> BOX name ORIGIN x y z SIZE lx ly lz ELEMENTS nx ny nz TYPE HEX8|TET4 (mesh_box).
  subroutine do_box(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: origin(3), l(3)
    integer :: n(3), et, k
    call check_new_group_name(scn, st, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_point(st, 'ORIGIN', origin, stat, errmsg)
    do k = 1, 3
      if (stat /= STAT_OK) return
      call get_real(st, 'SIZE', l(k), stat, errmsg, index=k, lower=0.0_dp, lower_inclusive=.false., upper=MAX_COORD)
      if (stat /= STAT_OK) return
      call get_int(st, 'ELEMENTS', n(k), stat, errmsg, index=k, lower=1, lower_inclusive=.true., &
        upper=MAX_GENERATED_ELEMENTS, upper_inclusive=.true.)
    end do
    if (stat /= STAT_OK) return
    ! nx ny nz (x 6 for TET4) bounded without forming the product, which may overflow
    if (real(n(1), dp) * n(2) * n(3) * 6 > MAX_GENERATED_ELEMENTS) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'ELEMENTS ' // str(n(1)) // ' x ' // str(n(2)) // ' x ' // &
        str(n(3)) // ' exceeds the limit of ' // str(MAX_GENERATED_ELEMENTS / 6) // ' cells', &
        st%params(find_param(st, 'ELEMENTS'))%values(1)))
      return
    end if
    if (any(l <= zero_tol * max(1.0_dp, maxval(abs(origin))))) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'SIZE negligible against the ORIGIN coordinates', &
        st%params(find_param(st, 'SIZE'))%values(minloc(l, 1))))
      return
    end if
    call get_etype(st, 'TYPE', etypes_of_family(FAMILY_VOLUME), et, stat, errmsg)
    if (stat /= STAT_OK) return
    call generate_box(scn%mesh, st%lead(1)%text, origin, l, n, et, stat, errmsg)
    if (stat /= STAT_OK) errmsg = stmt_error(st, errmsg)
  end subroutine do_box

  subroutine do_gmsh(scn, st, scene_path, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: scene_path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: file, full, msg
    call check_new_group_name(scn, st, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_word(st, 'FILE', file, stat, errmsg)
    if (stat /= STAT_OK) return
    full = resolve_path(scene_path, file)
    call read_gmsh(scn%mesh, full, st%lead(1)%text, stat, msg)
    if (stat /= STAT_OK) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, msg, st%params(find_param(st, 'FILE'))%values(1)))
    end if
  end subroutine do_gmsh
end module scene_mesh
