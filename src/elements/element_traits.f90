!> The element types and their traits, in one table: what the mesh, the input, the assembly
!> and the outputs need to know of a type without its kernels (those are in element_* and the
!> dispatcher elements). Adding an element adds a row here, a kernel module and its cases in
!> elements (README, "Adding an element").
!> Node order of each type:
!>   MASS 1 node; SPRING, BAR2, BEAM2 2 nodes; QUAD4 4 corners counter-clockwise;
!>   QUAD8 4 corners counter-clockwise then 4 mid-side nodes (side 1-2, 2-3, 3-4, 4-1),
!>   as Cast3M's QUA8 and Gmsh's 8-node quadrangle; TRI3 3 corners counter-clockwise; TRI6 3
!>   corners then 3 mid-side nodes (side 1-2, 2-3, 3-1), as Cast3M's TRI6 and Gmsh's 6-node triangle.
!>   HEX8 (DIMENSION 3) the 4 corners of its bottom face counter-clockwise seen from above, then the
!>   4 above them; TET4 corners 1 2 3 counter-clockwise seen from corner 4 (Gmsh's and VTK's order);
!>   HEX20 and TET10 then their mid-edge nodes in Gmsh's order (element_solid), which XDMF's differs
!>   from (etype_xdmf_order); WEDGE6 (a prism) the corners 1 2 3 of a triangle counter-clockwise seen
!>   from the opposite one, then 4 5 6 above them (Gmsh's order; VTK's runs the triangles the other way).
module element_traits
  use material_law, only: PK_1D, PK_BEAM, PK_PSTRAIN, PK_PSTRESS, PK_SOLID
  implicit none
  private
  public :: ET_MASS, ET_SPRING, ET_BAR2, ET_BEAM2, ET_QUAD4, ET_QUAD8, ET_TRI3, ET_TRI6, NUM_ETYPES, MAX_NEN
  public :: ET_HEX8, ET_TET4, ET_HEX20, ET_TET10, ET_WEDGE6, XDMF_WEDGE, XDMF_TETRAHEDRON_10, XDMF_HEXAHEDRON_20, &
    etype_xdmf_order, &
    DOF_UX, DOF_UY, DOF_RZ, DOF_UZ, NODE_DOFS, DOF_NAMES, DOF_AXIS
  public :: FAMILY_POINT, FAMILY_LINE, FAMILY_SURFACE, FAMILY_VOLUME
  public :: XDMF_POLYVERTEX, XDMF_POLYLINE, XDMF_QUADRILATERAL, XDMF_QUADRILATERAL_8, XDMF_TRIANGLE, XDMF_TRIANGLE_6
  public :: XDMF_TETRAHEDRON, XDMF_HEXAHEDRON, etype_dimension
  public :: etype_name, etype_from_name, etype_nen, etype_family, etypes_of_family, etype_needs_material, &
    etype_section_needs, etype_point_kind, etype_xdmf_cell, etype_gmsh, etype_segments, etype_sides, MAX_SEGMENTS, &
    etype_faces, &
    etype_stress_names

  integer, parameter :: ET_MASS = 1, ET_SPRING = 2, ET_BAR2 = 3, ET_BEAM2 = 4, ET_QUAD4 = 5, ET_QUAD8 = 6, ET_TRI3 = 7, &
    ET_TRI6 = 8, ET_HEX8 = 9, ET_TET4 = 10, ET_HEX20 = 11, ET_TET10 = 12, ET_WEDGE6 = 13
  integer, parameter :: NUM_ETYPES = 13
  integer, parameter :: MAX_NEN = 20

  !> Degrees of freedom of a node, in this order (their equations are numbered node by node in it):
  !> UX UY and RZ (planar beams) in 2D, UX UY UZ in 3D; NODE_DOFS slots per node.
  integer, parameter :: DOF_UX = 1, DOF_UY = 2, DOF_RZ = 3, DOF_UZ = 4, NODE_DOFS = 4
  character(len=2), parameter :: DOF_NAMES(NODE_DOFS) = [character(len=2) :: 'UX', 'UY', 'RZ', 'UZ']
  !> The coordinate axis a DOF slot translates along (x 1, y 2, z 3), 0 for the rotation RZ.
  integer, parameter :: DOF_AXIS(NODE_DOFS) = [1, 2, 0, 3]
  integer, parameter :: MAX_SEGMENTS = 8   !< straight pieces of an element's outline (QUAD8)
  !> Families: a point (MASS), a line (LINE generates them; a MODEL may change one line type
  !> into another: SPRING, BAR2, BEAM2), a surface (RECTANGLE generates them), a volume (BOX).
  integer, parameter :: FAMILY_POINT = 1, FAMILY_LINE = 2, FAMILY_SURFACE = 3, FAMILY_VOLUME = 4
  !> XDMF cell codes of a Mixed topology array.
  integer, parameter :: XDMF_POLYVERTEX = 1, XDMF_POLYLINE = 2, XDMF_TRIANGLE = 4, XDMF_QUADRILATERAL = 5, &
    XDMF_TRIANGLE_6 = 36, XDMF_QUADRILATERAL_8 = 37, XDMF_TETRAHEDRON = 6, XDMF_HEXAHEDRON = 9, &
    XDMF_TETRAHEDRON_10 = 38, XDMF_HEXAHEDRON_20 = 48, XDMF_WEDGE = 8

  character(len=*), parameter :: SIGMA2D = 'sigma_xx, sigma_yy, sigma_zz, sigma_xy (Pa)'
  character(len=*), parameter :: SIGMA3D = 'sigma_xx, sigma_yy, sigma_zz, sigma_xy, sigma_yz, sigma_xz (Pa)'

  !> One row of the table.
  type :: etraits_t
    character(len=6) :: name
    integer :: nen                   !< nodes
    integer :: family
    logical :: material              !< needs a MATERIAL (a point mass does not)
    character(len=12) :: section     !< section characteristics it needs: 'MASS', 'AREA', 'AREA INERTIA', ''
    integer :: point_kind            !< material_law PK_* (quads: PK_PSTRAIN, or PK_PSTRESS in plane stress)
    integer :: xdmf_cell             !< XDMF Mixed cell code
    integer :: gmsh                  !< Gmsh element type number (0: none)
    character(len=64) :: stress      !< its stress columns with units (fields.h5 /mesh/stress_components)
  end type etraits_t

  type(etraits_t), parameter :: TRAITS(NUM_ETYPES) = [ &
    etraits_t('MASS', 1, FAMILY_POINT, .false., 'MASS', 0, XDMF_POLYVERTEX, 15, 'none'), &
    etraits_t('SPRING', 2, FAMILY_LINE, .true., '', PK_1D, XDMF_POLYLINE, 0, 'N (spring force, N)'), &
    etraits_t('BAR2', 2, FAMILY_LINE, .true., 'AREA', PK_1D, XDMF_POLYLINE, 1, 'sigma (axial stress, Pa)'), &
    etraits_t('BEAM2', 2, FAMILY_LINE, .true., 'AREA INERTIA', PK_BEAM, XDMF_POLYLINE, 0, &
      'N (axial force, N), M (bending moment, N m)'), &
    etraits_t('QUAD4', 4, FAMILY_SURFACE, .true., '', PK_PSTRAIN, XDMF_QUADRILATERAL, 3, SIGMA2D), &
    etraits_t('QUAD8', 8, FAMILY_SURFACE, .true., '', PK_PSTRAIN, XDMF_QUADRILATERAL_8, 16, SIGMA2D), &
    etraits_t('TRI3', 3, FAMILY_SURFACE, .true., '', PK_PSTRAIN, XDMF_TRIANGLE, 2, SIGMA2D), &
    etraits_t('TRI6', 6, FAMILY_SURFACE, .true., '', PK_PSTRAIN, XDMF_TRIANGLE_6, 9, SIGMA2D), &
    etraits_t('HEX8', 8, FAMILY_VOLUME, .true., '', PK_SOLID, XDMF_HEXAHEDRON, 5, SIGMA3D), &
    etraits_t('TET4', 4, FAMILY_VOLUME, .true., '', PK_SOLID, XDMF_TETRAHEDRON, 4, SIGMA3D), &
    etraits_t('HEX20', 20, FAMILY_VOLUME, .true., '', PK_SOLID, XDMF_HEXAHEDRON_20, 17, SIGMA3D), &
    etraits_t('TET10', 10, FAMILY_VOLUME, .true., '', PK_SOLID, XDMF_TETRAHEDRON_10, 11, SIGMA3D), &
    etraits_t('WEDGE6', 6, FAMILY_VOLUME, .true., '', PK_SOLID, XDMF_WEDGE, 6, SIGMA3D)]

contains

  pure logical function valid(et)
    integer, intent(in) :: et
    valid = et >= 1 .and. et <= NUM_ETYPES
  end function valid

  !> Name of an element type (upper case), '?' for an unknown code.
  pure function etype_name(et) result(name)
    integer, intent(in) :: et
    character(len=:), allocatable :: name
    name = '?'
    if (valid(et)) name = trim(TRAITS(et)%name)
  end function etype_name

  !> Element type from its (upper-case) name; 0 when unknown.
  pure function etype_from_name(name) result(et)
    character(len=*), intent(in) :: name
    integer :: et
    do et = 1, NUM_ETYPES
      if (trim(TRAITS(et)%name) == name) return
    end do
    et = 0
  end function etype_from_name

  pure integer function etype_nen(et)
    integer, intent(in) :: et
    etype_nen = TRAITS(et)%nen
  end function etype_nen

  !> The space dimension a type lives in: 3 for the volumes, 2 for the others (a MASS, a line
  !> element or a surface element in a DIMENSION 3 scene is refused: scene_models).
  pure integer function etype_dimension(et)
    integer, intent(in) :: et
    etype_dimension = merge(3, 2, TRAITS(et)%family == FAMILY_VOLUME)
  end function etype_dimension

  pure integer function etype_family(et)
    integer, intent(in) :: et
    etype_family = TRAITS(et)%family
  end function etype_family

  !> The types of a family, in table order.
  pure function etypes_of_family(family) result(ets)
    integer, intent(in) :: family
    integer, allocatable :: ets(:)
    integer :: et
    ets = pack([(et, et = 1, NUM_ETYPES)], TRAITS%family == family)
  end function etypes_of_family

  pure logical function etype_needs_material(et)
    integer, intent(in) :: et
    etype_needs_material = TRAITS(et)%material
  end function etype_needs_material

  !> The section characteristics a type needs ('' when none: the default section serves).
  pure function etype_section_needs(et) result(s)
    integer, intent(in) :: et
    character(len=:), allocatable :: s
    s = trim(TRAITS(et)%section)
  end function etype_section_needs

  !> Material-point kind of the type's integration points (0 for a point mass).
  pure integer function etype_point_kind(et, plane_stress)
    integer, intent(in) :: et
    logical, intent(in) :: plane_stress
    etype_point_kind = TRAITS(et)%point_kind
    if (etype_point_kind == PK_PSTRAIN .and. plane_stress) etype_point_kind = PK_PSTRESS
  end function etype_point_kind

  !> The leading entries of a cell in an XDMF Mixed array (cell code, and the node count of the
  !> variable-size Polyvertex and Polyline) and their number.
  pure subroutine etype_xdmf_cell(et, head, nhead)
    integer, intent(in) :: et
    integer, intent(out) :: head(2), nhead
    head = [TRAITS(et)%xdmf_cell, 0]
    nhead = 1
    if (TRAITS(et)%xdmf_cell == XDMF_POLYVERTEX .or. TRAITS(et)%xdmf_cell == XDMF_POLYLINE) then
      head(2) = TRAITS(et)%nen
      nhead = 2
    end if
  end subroutine etype_xdmf_cell

  !> "NAME: its stress columns (units)", as fields.h5 describes them.
  pure function etype_stress_names(et) result(s)
    integer, intent(in) :: et
    character(len=:), allocatable :: s
    s = trim(TRAITS(et)%name) // ': ' // trim(TRAITS(et)%stress)
  end function etype_stress_names

  !> The rebond type of a Gmsh element type number; 0 when rebond has none.
  pure integer function etype_gmsh(gmsh_type) result(et)
    integer, intent(in) :: gmsh_type
    do et = 1, NUM_ETYPES
      if (TRAITS(et)%gmsh == gmsh_type .and. gmsh_type > 0) return
    end do
    et = 0
  end function etype_gmsh

  !> The sides of a surface element as local node lists side(1:nsn, 1:nside), counter-clockwise
  !> (the body on the left of the side's first-to-last direction, the outward normal on the
  !> right): QUAD4 four 2-node sides; QUAD8 four 3-node sides, corner, mid-side node, corner;
  !> TRI3 three 2-node sides; TRI6 three 3-node sides.
  !> Other types have none (nside = 0).
  pure subroutine etype_sides(et, side, nside, nsn)
    integer, intent(in) :: et
    integer, intent(out) :: side(3, 4), nside, nsn
    integer :: k
    side = 0
    nside = 0
    nsn = 0
    if (TRAITS(et)%family /= FAMILY_SURFACE) return
    nside = merge(3, 4, et == ET_TRI3 .or. et == ET_TRI6)     ! corners = sides
    nsn = merge(3, 2, TRAITS(et)%nen > nside)                 ! mid-side nodes after the corners
    do k = 1, nside
      if (nsn == 2) then
        side(1:2, k) = [k, mod(k, nside) + 1]
      else
        side(:, k) = [k, k + nside, mod(k, nside) + 1]
      end if
    end do
  end subroutine etype_sides

  !> The faces of a solid as local node lists face(1:nfn(k), k), k = 1..nface, counter-clockwise seen
  !> from outside (the outward normal along (x2 - x1) x (x3 - x1)): HEX8 six 4-node faces, TET4 four
  !> triangles, WEDGE6 two triangles and three quadrangles. Other types have none (nface = 0).
  pure subroutine etype_faces(et, face, nfn, nface)
    integer, intent(in) :: et
    integer, intent(out) :: face(8, 6), nfn(6), nface
    face = 0
    nfn = 0
    nface = 0
    select case (et)
    case (ET_HEX8, ET_HEX20)                     ! HEX20: the corners, then the mid-edge nodes along them
      nface = 6
      nfn = merge(8, 4, et == ET_HEX20)
      face(1:4, :) = reshape([1, 4, 3, 2, 5, 6, 7, 8, 1, 2, 6, 5, 2, 3, 7, 6, 3, 4, 8, 7, 4, 1, 5, 8], [4, 6])
      face(5:8, :) = reshape([10, 14, 12, 9, 17, 19, 20, 18, 9, 13, 17, 11, 12, 15, 19, 13, 14, 16, 20, 15, &
        10, 11, 18, 16], [4, 6])
      if (et == ET_HEX8) face(5:8, :) = 0
    case (ET_TET4, ET_TET10)                     ! TET10: the corners, then the mid-edge nodes along them
      nface = 4
      nfn(1:4) = merge(6, 3, et == ET_TET10)
      face(1:3, 1:4) = reshape([1, 3, 2, 1, 2, 4, 2, 3, 4, 1, 4, 3], [3, 4])
      face(4:6, 1:4) = reshape([7, 6, 5, 5, 10, 8, 6, 9, 10, 8, 9, 7], [3, 4])
      if (et == ET_TET4) face(4:6, :) = 0
    case (ET_WEDGE6)                             ! the two triangles, then the three quadrangles
      nface = 5
      nfn(1:5) = [3, 3, 4, 4, 4]
      face(1:4, 1:5) = reshape([1, 3, 2, 0, 4, 5, 6, 0, 1, 2, 5, 4, 2, 3, 6, 5, 1, 4, 6, 3], [4, 5])
    end select
  end subroutine etype_faces

  !> The XDMF (VTK) node order of a cell of type et as positions in ours: XDMF's node k is our
  !> order(k). Gmsh's (ours) and XDMF's differ on the mid-edge nodes of HEX20 and TET10 and on the
  !> way WEDGE6's triangles run.
  pure subroutine etype_xdmf_order(et, order)
    integer, intent(in) :: et
    integer, intent(out) :: order(MAX_NEN)
    integer :: k
    order = [(k, k = 1, MAX_NEN)]
    select case (et)
    case (ET_TET10)
      order(9:10) = [10, 9]
    case (ET_HEX20)
      order(9:20) = [9, 12, 14, 10, 17, 19, 20, 18, 11, 13, 15, 16]
    case (ET_WEDGE6)                             ! VTK: the base's right-hand normal points away from the top
      order(1:6) = [1, 3, 2, 4, 6, 5]
    end select
  end subroutine etype_xdmf_order

  !> The straight pieces of an element's outline, as local node pairs seg(:, 1:nseg), for
  !> contact segments: a line element is one piece; a surface element's sides (etype_sides) run
  !> counter-clockwise, a 3-node side as two pieces through its mid-side node; a point has none.
  pure subroutine etype_segments(et, seg, nseg)
    integer, intent(in) :: et
    integer, intent(out) :: seg(2, MAX_SEGMENTS), nseg
    integer :: side(3, 4), nside, nsn, k, i
    seg = 0
    nseg = 0
    if (TRAITS(et)%family == FAMILY_LINE) then
      nseg = 1
      seg(:, 1) = [1, 2]
      return
    end if
    call etype_sides(et, side, nside, nsn)
    do k = 1, nside
      do i = 1, nsn - 1
        nseg = nseg + 1
        seg(:, nseg) = side(i:i + 1, k)
      end do
    end do
  end subroutine etype_segments
end module element_traits
