!> What the Gmsh readers share (gmsh_reader for MSH 4.1, gmsh_msh2 for MSH 2.2): the parser state
!> (gmsh_t: the current line and its words, what was read so far, node tags and their local
!> numbers), the element kinds rebond reads, and the line helpers whose messages name the file
!> and the line.
module gmsh_state
  use, intrinsic :: iso_fortran_env, only: int64
  use kinds, only: dp, zero_tol
  use errors, only: STAT_OK, str
  use mesh, only: MAX_COORD
  use element_traits, only: etype_nen, etype_gmsh, etype_family, MAX_NEN
  use line_reader, only: line_reader_t, next_line, get_reals, fail, tok, clip
  use array_utils, only: sort_by_key
  implicit none
  private
  public :: pname_t, gmsh_t, LINE3, node_of, too_many, node_coordinates, orient_surface, gmsh_type_name
  public :: data_line, next_line_or_eof, header_ints, end_section, element_kind, store_element, index_tags
  public :: alloc_elements, begin_elements, repeated_name

  !> The element kind of a 3-node line (Gmsh type 8, the boundary curves of second-order meshes), and
  !> in a DIMENSION 3 scene of every point, line and surface element (the boundaries of the volumes):
  !> no rebond element, its nodes join its physical groups (node groups for FIX, PRESSURE ...).
  integer, parameter :: LINE3 = -8

  !> A $PhysicalNames entry.
  type :: pname_t
    integer :: dim = 0, tag = 0
    character(len=:), allocatable :: name
  end type pname_t

  !> Parser state: the current line and its tokens (line_reader_t), and everything read so far
  !> (local numbering).
  type, extends(line_reader_t) :: gmsh_t
    integer :: npn = 0
    type(pname_t), allocatable :: pn(:)            !< physical names
    integer :: nent = 0
    integer, allocatable :: ent_dim(:), ent_tag(:) !< entities
    integer, allocatable :: ent_ptr(:)             !< physical tags of entity i: ent_phys(ent_ptr(i):ent_ptr(i+1)-1)
    integer :: nphys = 0
    integer, allocatable :: ent_phys(:)
    integer :: nnode = 0
    real(dp), allocatable :: x(:, :)               !< (3, nnode): x, y, z
    integer :: ndim = 2                            !< the scene's dimension (m%ndim): 3 reads volumes
    integer(int64) :: fsize = -1                   !< file size in bytes (-1 if unknown), bounds allocations
    integer :: tagmin = 0, tagmax = -1
    logical :: dense = .true.                      !< node tags mapped by node_of_tag, else by sorted_tag
    integer, allocatable :: node_of_tag(:)         !< dense: (tagmin:tagmax) local node number, 0 if none
    integer, allocatable :: sorted_tag(:), sorted_node(:)  !< sparse: tags ascending and their nodes
    integer, allocatable :: tag_of(:)              !< (nnode) the Gmsh tag of each local node
    integer :: nelem = 0
    integer, allocatable :: etype(:), edim(:), eent(:), conn(:, :)   !< etype LINE3: a boundary curve's 3-node line
    integer, allocatable :: enen(:)                !< nodes of each element (LINE3 and 3D boundaries included)
    logical :: have_nodes = .false., have_elements = .false., have_entities = .false.
    integer :: version = 41                         !< MSH 4.1 (41) or 2.2 (22)
    logical :: binary = .false.                     !< file type 1 (MSH 4.1 binary, gmsh_binary)
  end type gmsh_t


contains

  !> The index of an earlier physical name equal to the last one read (g%pn(g%npn)), 0 if none:
  !> two physical groups of one name would be merged into one node group without a word.
  pure integer function repeated_name(g) result(k)
    type(gmsh_t), intent(in) :: g
    do k = 1, g%npn - 1
      if (g%pn(k)%name == g%pn(g%npn)%name) return
    end do
    k = 0
  end function repeated_name

  !> The rebond kind et of Gmsh element type gtype (LINE3 for a 3-node line), its node count and
  !> dimension; stat /= STAT_OK (a message naming the type) for the others (QUAD9, volumes ...).
  subroutine element_kind(g, gtype, et, nen, dim, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    integer, intent(in) :: gtype
    integer, intent(out) :: et, nen, dim
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    nen = 0
    dim = 0
    et = etype_gmsh(gtype)
    if (gtype == 8) et = LINE3
    if (et == 0) then
      call fail(g, stat, errmsg, 'unsupported Gmsh element type ' // str(gtype) // ' (' // gmsh_type_name(gtype) // &
        '); expected 15 (point), 1 (2-node line), 8 (3-node line), 2 (3-node triangle), 9 (6-node triangle), ' // &
        '3 (4-node quadrangle), 16 (8-node quadrangle); in DIMENSION 3 also 4, 11 (4- and 10-node tetrahedra), ' // &
        '5, 17 (8- and 20-node hexahedra), 6 (6-node prism)')
      return
    end if
    if (et == LINE3) then
      nen = 3
      dim = 1
    else
      nen = etype_nen(et)
      dim = etype_family(et) - 1          ! point 0, line 1, surface 2, volume 3
    end if
    if (dim == 3 .and. g%ndim /= 3) then
      call fail(g, stat, errmsg, 'a volume element (' // gmsh_type_name(gtype) // ') in a planar scene: a Gmsh ' // &
        'volume mesh needs DIMENSION 3')
    else if (g%ndim == 3 .and. dim < 3) then
      et = LINE3                          ! a boundary of the volumes: its nodes join its groups
    end if
  end subroutine element_kind

  !> The tag map of the nodes read, from their tags (g%tag_of(1:g%nnode)), as the 4.1 reader
  !> builds it: a direct array over [min, max] unless the tags are sparse, then a sorted list.
  !> dup: a tag given twice (0 if none).
  subroutine index_tags(g, dup)
    type(gmsh_t), intent(inout) :: g
    integer, intent(out) :: dup
    integer, allocatable :: tags(:), perm(:)
    integer(int64) :: range
    integer :: k, n
    n = g%nnode
    dup = 0
    g%tagmin = 1
    g%tagmax = 0
    if (n > 0) then
      g%tagmin = minval(g%tag_of(1:n))
      g%tagmax = maxval(g%tag_of(1:n))
    end if
    range = int(g%tagmax, int64) - g%tagmin + 1
    g%dense = range <= max(10000000_int64, 4_int64 * n)
    allocate (tags(n), perm(n))
    tags(:) = g%tag_of(1:n)
    perm(:) = [(k, k = 1, n)]
    call sort_by_key(tags, perm)
    do k = 2, n
      if (tags(k) == tags(k - 1)) then
        dup = tags(k)
        return
      end if
    end do
    if (g%dense) then
      allocate (g%node_of_tag(g%tagmin:g%tagmax))
      g%node_of_tag = 0
      g%node_of_tag(tags) = perm
    else
      g%sorted_tag = tags
      g%sorted_node = perm
    end if
  end subroutine index_tags

  !> Entering an $Elements section: the first one, after $Nodes.
  subroutine begin_elements(g, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (g%have_elements) then
      call fail(g, stat, errmsg, 'second $Elements section')
    else if (.not. g%have_nodes) then
      call fail(g, stat, errmsg, '$Elements before $Nodes, expected the $Nodes section first')
    end if
    g%have_elements = .true.
  end subroutine begin_elements

  !> Room for nelem elements (word: the header word holding the count, for messages); refused
  !> when nelem records of at least minbytes bytes cannot fit in the file.
  subroutine alloc_elements(g, nelem, minbytes, word, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    integer, intent(in) :: nelem, minbytes
    character(len=*), intent(in) :: word
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: ios
    stat = STAT_OK
    if (too_many(g, nelem, minbytes)) then
      call fail(g, stat, errmsg, 'the file is too small to hold the ' // word // ' elements announced')
      return
    end if
    allocate (g%etype(nelem), g%edim(nelem), g%eent(nelem), g%conn(MAX_NEN, nelem), g%enen(nelem), stat=ios)
    if (ios /= 0) call fail(g, stat, errmsg, 'cannot allocate ' // word // ' elements')
  end subroutine alloc_elements

  !> Append element number g%nelem + 1: kind et, dimension dim, entity ent (0: none), local nodes
  !> nodes(1:nen); a surface is made counter-clockwise (a zero-area one is refused).
  subroutine store_element(g, gtype, et, dim, ent, nodes, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    integer, intent(in) :: gtype, et, dim, ent
    integer, intent(inout) :: nodes(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (dim == 2 .and. g%ndim == 2) then
      call orient_surface(g%x, nodes, stat)
      if (stat /= STAT_OK) then
        call fail(g, stat, errmsg, 'degenerate ' // gmsh_type_name(gtype) // ' (zero area), expected distinct corners')
        return
      end if
    end if
    g%nelem = g%nelem + 1
    g%etype(g%nelem) = et
    g%edim(g%nelem) = dim
    g%eent(g%nelem) = ent
    g%conn(:, g%nelem) = 0
    g%conn(1:size(nodes), g%nelem) = nodes
    g%enen(g%nelem) = size(nodes)
  end subroutine store_element

  !> The next line: "x y z" of node tag (at most maxtok words: parametric coordinates may
  !> follow), each within ±MAX_COORD.
  subroutine node_coordinates(g, tag, maxtok, xyz, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    integer, intent(in) :: tag, maxtok
    real(dp), intent(out) :: xyz(3)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call data_line(g, 'the coordinates "x y z" of a node', stat, errmsg)
    if (stat /= STAT_OK) return
    if (g%ntok < 3 .or. g%ntok > maxtok) then
      call fail(g, stat, errmsg, 'expected the coordinates "x y z" of node ' // str(tag) // ', found "' // &
        clip(g%line) // '"')
      return
    end if
    call get_reals(g, 3, 'a node coordinate', xyz, stat, errmsg)
    if (stat /= STAT_OK) return
    if (any(abs(xyz) > MAX_COORD)) call fail(g, stat, errmsg, 'node ' // str(tag) // ': a coordinate beyond ±1e100, ' // &
      'found "' // clip(g%line) // '"')
  end subroutine node_coordinates


  !> Whether n records of at least minbytes bytes each cannot fit in the file (garbage counts must
  !> not trigger huge allocations).
  pure logical function too_many(g, n, minbytes)
    type(gmsh_t), intent(in) :: g
    integer, intent(in) :: n, minbytes
    too_many = g%fsize >= 0 .and. int(n, int64) > g%fsize / minbytes
  end function too_many


  !> Local node number of a Gmsh node tag, 0 if unknown.
  pure integer function node_of(g, tag) result(node)
    type(gmsh_t), intent(in) :: g
    integer, intent(in) :: tag
    integer :: lo, hi, mid
    node = 0
    if (tag < g%tagmin .or. tag > g%tagmax) return
    if (g%dense) then
      node = g%node_of_tag(tag)
      return
    end if
    lo = 1
    hi = g%nnode
    do while (lo <= hi)
      mid = lo + (hi - lo) / 2
      if (g%sorted_tag(mid) == tag) then
        node = g%sorted_node(mid)
        return
      else if (g%sorted_tag(mid) < tag) then
        lo = mid + 1
      else
        hi = mid - 1
      end if
    end do
  end function node_of


  !> Make a triangle or quadrangle counter-clockwise (reversing a clockwise one: corners
  !> 1 2 3 [4] -> 1 [4] 3 2, mid-sides of sides 12 23 34 41 -> 14 43 32 21, of 12 23 31 -> 13 32 21);
  !> stat = 1 if its area is zero. nodes: corners, then mid-side nodes (3, 4, 6 or 8 of them).
  pure subroutine orient_surface(x, nodes, stat)
    real(dp), intent(in) :: x(:, :)
    integer, intent(inout) :: nodes(:)
    integer, intent(out) :: stat
    real(dp) :: a, d2
    integer :: i, j, nc
    stat = 0
    nc = merge(3, 4, size(nodes) == 3 .or. size(nodes) == 6)
    a = 0.0_dp
    d2 = 0.0_dp
    do i = 1, nc
      j = mod(i, nc) + 1
      a = a + x(1, nodes(i)) * x(2, nodes(j)) - x(1, nodes(j)) * x(2, nodes(i))
      d2 = max(d2, sum((x(:, nodes(j)) - x(:, nodes(i)))**2))
    end do
    if (abs(a) <= zero_tol * d2) then
      stat = 1
    else if (a < 0.0_dp) then
      nodes(2:nc) = nodes(nc:2:-1)
      if (size(nodes) == 2 * nc) nodes(nc + 1:2 * nc) = nodes(2 * nc:nc + 1:-1)
    end if
  end subroutine orient_surface


  !> Gmsh's name of an element type, for messages.
  pure function gmsh_type_name(t) result(s)
    integer, intent(in) :: t
    character(len=:), allocatable :: s
    select case (t)
    case (1); s = '2-node line'
    case (2); s = '3-node triangle'
    case (3); s = '4-node quadrangle'
    case (4); s = '4-node tetrahedron'
    case (5); s = '8-node hexahedron'
    case (6); s = '6-node prism'
    case (7); s = '5-node pyramid'
    case (8); s = '3-node line'
    case (9); s = '6-node triangle'
    case (10); s = '9-node quadrangle'
    case (11); s = '10-node tetrahedron'
    case (12); s = '27-node hexahedron'
    case (13); s = '18-node prism'
    case (14); s = '14-node pyramid'
    case (15); s = '1-node point'
    case (16); s = '8-node quadrangle'
    case (17); s = '20-node hexahedron'
    case (18); s = '15-node prism'
    case (19); s = '13-node pyramid'
    case default; s = 'unknown to rebond'
    end select
  end function gmsh_type_name


  ! ---------------------------------------------------------------------------------------------
  ! Lines and tokens.

  !> next_line where end of file is an error; what = what was expected.
  subroutine data_line(g, what, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    character(len=*), intent(in) :: what
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical :: ok
    call next_line(g, ok, stat, errmsg)
    if (stat /= STAT_OK) return
    if (.not. ok) then
      call fail(g, stat, errmsg, 'unexpected end of file (truncated?), expected ' // what)
      return
    end if
    if (g%line(g%tb(1):g%tb(1)) == '$') then
      call fail(g, stat, errmsg, 'unexpected "' // tok(g, 1) // '" (section too short?), expected ' // what)
    end if
  end subroutine data_line

  !> Advance to the next line so that an error is reported there, but stay on the last line at end of file.
  subroutine next_line_or_eof(g, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical :: ok
    call next_line(g, ok, stat, errmsg)
  end subroutine next_line_or_eof

  !> A data line holding exactly n integers (checked by the caller with get_int).
  subroutine header_ints(g, n, what, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    integer, intent(in) :: n
    character(len=*), intent(in) :: what
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call data_line(g, what, stat, errmsg)
    if (stat /= STAT_OK) return
    if (g%ntok /= n) then
      call fail(g, stat, errmsg, 'expected ' // what // ', found "' // clip(g%line) // '"')
    end if
  end subroutine header_ints

  !> The next line must be the closing tag endname.
  subroutine end_section(g, endname, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    character(len=*), intent(in) :: endname
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical :: ok
    call next_line(g, ok, stat, errmsg)
    if (stat /= STAT_OK) return
    if (.not. ok) then
      call fail(g, stat, errmsg, 'unexpected end of file (truncated?), expected ' // endname)
    else if (g%ntok /= 1 .or. tok(g, 1) /= endname) then
      call fail(g, stat, errmsg, 'expected ' // endname // ', found "' // clip(g%line) // '"')
    end if
  end subroutine end_section

end module gmsh_state
