!> The mesh: node coordinates, element connectivity and named groups of nodes and elements.
!> Generators (mesh_generators), the Gmsh reader (gmsh_reader) and explicit NODE/ELEMENT
!> statements all build a mesh_t through the procedures below.
module mesh
  use kinds, only: dp
  use element_traits, only: etype_nen, MAX_NEN, DOF_UX, DOF_UY, DOF_RZ, DOF_UZ, NODE_DOFS, DOF_NAMES, DOF_AXIS
  implicit none
  private
  public :: mesh_t, group_t
  public :: DOF_UX, DOF_UY, DOF_RZ, DOF_UZ, NODE_DOFS, DOF_NAMES, DOF_AXIS, MAX_COORD, rigid_mode_row

  !> Largest coordinate accepted (scene and Gmsh): squares, areas and r x (M v) stay finite.
  real(dp), parameter :: MAX_COORD = 1.0e100_dp

  ! Element types and their node order: element_traits.

  ! Degrees of freedom of a node (DOF_*, NODE_DOFS, DOF_NAMES): element_traits, re-exported here.

  !> A named list of node or element numbers (1-based, in the mesh's numbering).
  type :: group_t
    character(len=:), allocatable :: name
    integer, allocatable :: items(:)
  end type group_t

  !> Groups by name: an open-addressing hash table of group indices (0: empty slot), its size a
  !> power of two at least twice the count, so that a scene of 1e5 named nodes and groups loads
  !> in linear time (a linear search made it quadratic).
  type :: group_index_t
    integer, allocatable :: slot(:)
  end type group_index_t

  type :: mesh_t
    integer :: ndim = 2                    !< space dimension (DIMENSION: 2 or 3)
    integer :: nnode = 0
    integer :: nelem = 0
    real(dp), allocatable :: x(:, :)       !< (ndim, nnode) coordinates
    integer, allocatable :: tag(:)         !< (nnode) the user's number of each node (Gmsh's tag; else its index)
    integer, allocatable :: etype(:)       !< (nelem) element type ET_*
    integer, allocatable :: conn(:, :)     !< (MAX_NEN, nelem) node numbers, 0 past nen
    integer :: nngroup = 0
    integer :: negroup = 0
    type(group_t), allocatable :: ngroups(:)  !< node groups
    type(group_t), allocatable :: egroups(:)  !< element groups
    type(group_index_t) :: nindex, eindex     !< the groups by name
  contains
    procedure :: add_node
    procedure :: add_element
    procedure :: add_node_group
    procedure :: add_elem_group
    procedure :: find_node_group
    procedure :: find_elem_group
    procedure :: nen
    procedure :: node_tag
    procedure :: subset_elements
  end type mesh_t

contains

  !> Number of nodes of element e.
  pure integer function nen(self, e)
    class(mesh_t), intent(in) :: self
    integer, intent(in) :: e
    nen = etype_nen(self%etype(e))
  end function nen

  !> Append a node; returns its number.
  subroutine add_node(self, xy, id, tag)
    class(mesh_t), intent(inout) :: self
    real(dp), intent(in) :: xy(:)            !< (ndim) its coordinates
    integer, intent(out) :: id
    integer, intent(in), optional :: tag     !< the user's number (Gmsh's tag); default: id
    real(dp), allocatable :: tmp(:, :)
    integer, allocatable :: itmp(:)
    if (.not. allocated(self%x)) allocate (self%x(self%ndim, 64), self%tag(64))
    if (self%nnode == size(self%x, 2)) then
      allocate (tmp(self%ndim, 2 * size(self%x, 2)), itmp(2 * size(self%x, 2)))
      tmp(:, 1:self%nnode) = self%x(:, 1:self%nnode)
      itmp(1:self%nnode) = self%tag(1:self%nnode)
      call move_alloc(tmp, self%x)
      call move_alloc(itmp, self%tag)
    end if
    self%nnode = self%nnode + 1
    self%x(:, self%nnode) = xy(1:self%ndim)
    id = self%nnode
    self%tag(id) = id
    if (present(tag)) self%tag(id) = tag
  end subroutine add_node

  !> The mesh with the same nodes (and node groups) and only the elements keep(1:n) (in that
  !> order); element groups keep their kept elements, renumbered.
  subroutine subset_elements(self, keep, sub)
    class(mesh_t), intent(in) :: self
    integer, intent(in) :: keep(:)
    type(mesh_t), intent(out) :: sub
    integer, allocatable :: newid(:)
    integer :: i, id, k
    sub%ndim = self%ndim
    do i = 1, self%nnode
      call sub%add_node(self%x(:, i), id, self%node_tag(i))
    end do
    allocate (newid(self%nelem))
    newid = 0
    do k = 1, size(keep)
      call sub%add_element(self%etype(keep(k)), self%conn(1:self%nen(keep(k)), keep(k)), newid(keep(k)))
    end do
    do k = 1, self%nngroup
      call sub%add_node_group(self%ngroups(k)%name, self%ngroups(k)%items)
    end do
    do k = 1, self%negroup
      call sub%add_elem_group(self%egroups(k)%name, pack(newid(self%egroups(k)%items), newid(self%egroups(k)%items) > 0))
    end do
  end subroutine subset_elements

  !> The user's number of node n (messages, events.csv): Gmsh's tag for an imported node, else n.
  pure integer function node_tag(self, n)
    class(mesh_t), intent(in) :: self
    integer, intent(in) :: n
    node_tag = n
    if (allocated(self%tag)) then
      if (n >= 1 .and. n <= self%nnode) node_tag = self%tag(n)
    end if
  end function node_tag

  !> Append an element of type et on the given nodes; returns its number.
  subroutine add_element(self, et, nodes, id)
    class(mesh_t), intent(inout) :: self
    integer, intent(in) :: et
    integer, intent(in) :: nodes(:)
    integer, intent(out) :: id
    integer, allocatable :: itmp(:), ctmp(:, :)
    integer :: cap
    if (.not. allocated(self%etype)) then
      allocate (self%etype(64), self%conn(MAX_NEN, 64))
    end if
    cap = size(self%etype)
    if (self%nelem == cap) then
      allocate (itmp(2 * cap), ctmp(MAX_NEN, 2 * cap))
      itmp(1:cap) = self%etype
      ctmp(:, 1:cap) = self%conn
      call move_alloc(itmp, self%etype)
      call move_alloc(ctmp, self%conn)
    end if
    self%nelem = self%nelem + 1
    self%etype(self%nelem) = et
    self%conn(:, self%nelem) = 0
    self%conn(1:size(nodes), self%nelem) = nodes
    id = self%nelem
  end subroutine add_element

  !> Add (or replace) a node group.
  subroutine add_node_group(self, name, items)
    class(mesh_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(in) :: items(:)
    call add_group(self%ngroups, self%nngroup, self%nindex, name, items)
  end subroutine add_node_group

  !> Add (or replace) an element group.
  subroutine add_elem_group(self, name, items)
    class(mesh_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(in) :: items(:)
    call add_group(self%egroups, self%negroup, self%eindex, name, items)
  end subroutine add_elem_group

  subroutine add_group(groups, n, index, name, items)
    type(group_t), allocatable, intent(inout) :: groups(:)
    integer, intent(inout) :: n
    type(group_index_t), intent(inout) :: index
    character(len=*), intent(in) :: name
    integer, intent(in) :: items(:)
    type(group_t), allocatable :: tmp(:)
    integer :: i
    if (.not. allocated(groups)) allocate (groups(16))
    i = lookup(groups, n, index, name)
    if (i > 0) then
      groups(i)%items = items
      return
    end if
    if (n == size(groups)) then
      allocate (tmp(2 * n))
      tmp(1:n) = groups(1:n)
      call move_alloc(tmp, groups)
    end if
    n = n + 1
    groups(n)%name = name
    groups(n)%items = items
    call insert(groups, n, index)
  end subroutine add_group

  !> FNV-1a hash of a name.
  pure integer(8) function name_hash(name) result(h)
    character(len=*), intent(in) :: name
    integer :: k
    h = -3750763034362895579_8
    do k = 1, len(name)
      h = ieor(h, int(iachar(name(k:k)), 8)) * 1099511628211_8
    end do
  end function name_hash

  !> The index of the group called name, 0 if none (the hash table, or none yet: a search).
  pure integer function lookup(groups, n, index, name) result(ig)
    type(group_t), intent(in) :: groups(:)
    integer, intent(in) :: n
    type(group_index_t), intent(in) :: index
    character(len=*), intent(in) :: name
    integer :: m, k
    ig = 0
    if (n == 0) return
    if (.not. allocated(index%slot)) then
      do ig = 1, n
        if (groups(ig)%name == name) return
      end do
      ig = 0
      return
    end if
    m = size(index%slot)
    k = int(iand(name_hash(name), int(m - 1, 8))) + 1
    do
      ig = index%slot(k)
      if (ig == 0) return
      if (groups(ig)%name == name) return
      k = mod(k, m) + 1
    end do
  end function lookup

  !> Group n into the table, which doubles (rebuilt) when half full.
  pure subroutine insert(groups, n, index)
    type(group_t), intent(in) :: groups(:)
    integer, intent(in) :: n
    type(group_index_t), intent(inout) :: index
    integer :: m, i
    if (allocated(index%slot)) then
      if (2 * n <= size(index%slot)) then
        call place(index, groups(n)%name, n)
        return
      end if
    end if
    m = 64
    do while (m < 4 * n)
      m = 2 * m
    end do
    if (allocated(index%slot)) deallocate (index%slot)
    allocate (index%slot(m))
    index%slot = 0
    do i = 1, n
      call place(index, groups(i)%name, i)
    end do
  end subroutine insert

  pure subroutine place(index, name, ig)
    type(group_index_t), intent(inout) :: index
    character(len=*), intent(in) :: name
    integer, intent(in) :: ig
    integer :: m, k
    m = size(index%slot)
    k = int(iand(name_hash(name), int(m - 1, 8))) + 1
    do while (index%slot(k) /= 0)
      k = mod(k, m) + 1
    end do
    index%slot(k) = ig
  end subroutine place

  !> Index of the node group called name (case-sensitive as stored), 0 if none.
  pure integer function find_node_group(self, name) result(ig)
    class(mesh_t), intent(in) :: self
    character(len=*), intent(in) :: name
    ig = 0
    if (allocated(self%ngroups)) ig = lookup(self%ngroups, self%nngroup, self%nindex, name)
  end function find_node_group

  !> Index of the element group called name, 0 if none.
  pure integer function find_elem_group(self, name) result(ig)
    class(mesh_t), intent(in) :: self
    character(len=*), intent(in) :: name
    ig = 0
    if (allocated(self%egroups)) ig = lookup(self%egroups, self%negroup, self%eindex, name)
  end function find_elem_group
  !> The rigid modes about the origin at DOF slot d of a node at x (nd = size(x) = 2 or 3), as one row:
  !> 2D (translation x, translation y, rotation about z): UX 1, 0, -y; UY 0, 1, x; RZ 0, 0, 1.
  !> 3D (translations x, y, z, rotations about x, y, z: e_k x X along the slot's axis), row(1:6).
  pure function rigid_mode_row(d, x) result(row)
    integer, intent(in) :: d
    real(dp), intent(in) :: x(:)
    real(dp) :: row(6)
    row = 0.0_dp
    if (size(x) == 2) then
      row(1:3) = [merge(1.0_dp, 0.0_dp, d == DOF_UX), merge(1.0_dp, 0.0_dp, d == DOF_UY), &
        merge(-x(2), merge(x(1), 1.0_dp, d == DOF_UY), d == DOF_UX)]
      return
    end if
    if (DOF_AXIS(d) > 0) row(DOF_AXIS(d)) = 1.0_dp
    select case (DOF_AXIS(d))
    case (1)
      row(4:6) = [0.0_dp, x(3), -x(2)]
    case (2)
      row(4:6) = [-x(3), 0.0_dp, x(1)]
    case (3)
      row(4:6) = [x(2), -x(1), 0.0_dp]
    end select
  end function rigid_mode_row
end module mesh
