!> The structured block of DIMENSION 3 (BOX): nx x ny x nz cells on [x0, x0+lx] x [y0, y0+ly] x
!> [z0, z0+lz], HEX8 or HEX20 (its mid-edge nodes shared with the neighbours), or each cell cut into
!> six TET4 or TET10 (Kuhn's cut: every tetrahedron runs from the cell's low corner to its high one
!> along the three edges in some order, so that every face of every cell is cut along the same
!> diagonal as its neighbour's: the mesh is conforming), or into two WEDGE6 prisms along the diagonal
!> of its faces z = const.
module mesh_box
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error
  use mesh, only: mesh_t
  use element_traits, only: ET_HEX8, ET_TET4, ET_HEX20, ET_TET10, ET_WEDGE6, etype_name
  implicit none
  private
  public :: generate_box

  !> The HEX8 corners (Gmsh's order) as offsets (i, j, k) in the cell.
  integer, parameter :: CORNER(3, 8) = reshape([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1], &
    [3, 8])
  !> HEX20's mid-edge nodes: the corners of each edge (Gmsh's order).
  integer, parameter :: HEDGE(2, 12) = reshape([1, 2, 1, 4, 1, 5, 2, 3, 2, 6, 3, 4, 3, 7, 4, 8, 5, 6, 5, 8, 6, 7, 7, 8], &
    [2, 12])
  !> TET10's mid-edge nodes: the corners of each edge (Gmsh's order).
  integer, parameter :: TEDGE(2, 6) = reshape([1, 2, 2, 3, 3, 1, 4, 1, 4, 3, 4, 2], [2, 6])
  !> Kuhn's six tetrahedra: the axes taken in the order of each permutation, the odd ones with
  !> their last two vertices swapped (a positive volume).
  !> WEDGE6: the cell's two prisms on the diagonal 1-3 of its faces z = const (cell corners, Gmsh's order):
  !> triangles 1 2 3 and 1 3 4 counter-clockwise from above, the same above them.
  integer, parameter :: WEDGE_OF_CELL(6, 2) = reshape([1, 2, 3, 5, 6, 7, 1, 3, 4, 5, 7, 8], [6, 2])
  integer, parameter :: PERM(3, 6) = reshape([1, 2, 3, 2, 3, 1, 3, 1, 2, 1, 3, 2, 3, 2, 1, 2, 1, 3], [3, 6])

contains

  !> Nodes row by row (x fastest, then y, then z) on the grid of the corners, or of the half cells
  !> for the quadratic types (HEX20: not the faces' and cells' centres). Groups: element group
  !> `name`; node groups `name` (all), the faces `name.xmin`, `name.xmax`, `name.ymin`, `name.ymax`,
  !> `name.zmin`, `name.zmax`, and `name.center` (the node nearest the centre, the lowest-numbered
  !> one on ties). The counts are checked by the caller (scene_mesh: at least 1, at most
  !> MAX_GENERATED_ELEMENTS).
  subroutine generate_box(m, name, origin, l, n, et, stat, errmsg)
    type(mesh_t), intent(inout) :: m
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: origin(3), l(3)
    integer, intent(in) :: n(3)
    integer, intent(in) :: et
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, allocatable :: id(:, :, :), elems(:)
    integer :: i, j, k, e, icen, st, g(3), nodd
    real(dp) :: x(3), d, dmin
    stat = STAT_OK
    if (et /= ET_HEX8 .and. et /= ET_TET4 .and. et /= ET_HEX20 .and. et /= ET_TET10 .and. et /= ET_WEDGE6) then
      call set_error(stat, errmsg, STAT_INPUT, 'box mesh ' // name // ': element type ' // etype_name(et) // &
        ' not allowed (expected HEX8, HEX20, TET4, TET10 or WEDGE6)')
      return
    end if
    st = merge(2, 1, et == ET_HEX20 .or. et == ET_TET10)          ! grid points per cell edge
    g = st * n
    allocate (id(0:g(1), 0:g(2), 0:g(3)))
    allocate (elems(merge(6, merge(2, 1, et == ET_WEDGE6), et == ET_TET4 .or. et == ET_TET10) * n(1) * n(2) * n(3)))
    id = 0
    dmin = huge(1.0_dp)
    icen = 0
    do k = 0, g(3)
      do j = 0, g(2)
        do i = 0, g(1)
          nodd = count(mod([i, j, k], 2) == 1)
          if (et == ET_HEX20 .and. nodd >= 2) cycle          ! (no node at a face's or a cell's centre)
          ! origin + (i/g) l, written so that both ends are exact
          x = origin + l * (real([i, j, k], dp) / real(g, dp))
          call m%add_node(x, id(i, j, k))
          d = sum((x - origin - 0.5_dp * l)**2)
          if (d < dmin) then
            dmin = d
            icen = id(i, j, k)
          end if
        end do
      end do
    end do
    e = 0
    do k = 0, n(3) - 1
      do j = 0, n(2) - 1
        do i = 0, n(1) - 1
          call cell_elements(st * [i, j, k])
        end do
      end do
    end do
    call m%add_elem_group(name, elems)
    call m%add_node_group(name, nonzero(reshape(id, [size(id)])))
    call m%add_node_group(name // '.xmin', nonzero(reshape(id(0, :, :), [size(id(0, :, :))])))
    call m%add_node_group(name // '.xmax', nonzero(reshape(id(g(1), :, :), [size(id(0, :, :))])))
    call m%add_node_group(name // '.ymin', nonzero(reshape(id(:, 0, :), [size(id(:, 0, :))])))
    call m%add_node_group(name // '.ymax', nonzero(reshape(id(:, g(2), :), [size(id(:, 0, :))])))
    call m%add_node_group(name // '.zmin', nonzero(reshape(id(:, :, 0), [size(id(:, :, 0))])))
    call m%add_node_group(name // '.zmax', nonzero(reshape(id(:, :, g(3)), [size(id(:, :, 0))])))
    call m%add_node_group(name // '.center', [icen])
  contains
    !> The elements of the cell whose low corner is the grid point c.
    subroutine cell_elements(c)
      integer, intent(in) :: c(3)
      integer :: nodes(20), cc(3, 8), v(3), t(3, 4), p, a
      do a = 1, 8
        cc(:, a) = c + st * CORNER(:, a)        ! the cell's corners on the grid
      end do
      if (et == ET_HEX8 .or. et == ET_HEX20) then
        do a = 1, 8
          nodes(a) = at(cc(:, a))
        end do
        if (et == ET_HEX20) then
          do a = 1, 12
            nodes(8 + a) = at((cc(:, HEDGE(1, a)) + cc(:, HEDGE(2, a))) / 2)
          end do
        end if
        e = e + 1
        call m%add_element(et, nodes(1:merge(20, 8, et == ET_HEX20)), elems(e))
        return
      end if
      if (et == ET_WEDGE6) then                 ! two prisms on the diagonal 1-3 of the cell's xy faces
        do p = 1, 2
          do a = 1, 6
            nodes(a) = at(cc(:, WEDGE_OF_CELL(a, p)))
          end do
          e = e + 1
          call m%add_element(et, nodes(1:6), elems(e))
        end do
        return
      end if
      do p = 1, 6
        v = 0
        t(:, 1) = c
        v(PERM(1, p)) = st
        t(:, 2) = c + v
        v(PERM(2, p)) = st
        t(:, 3) = c + v
        t(:, 4) = c + st
        if (p > 3) t(:, 3:4) = t(:, [4, 3])     ! the odd permutations: a positive volume
        do a = 1, 4
          nodes(a) = at(t(:, a))
        end do
        if (et == ET_TET10) then
          do a = 1, 6
            nodes(4 + a) = at((t(:, TEDGE(1, a)) + t(:, TEDGE(2, a))) / 2)
          end do
        end if
        e = e + 1
        call m%add_element(et, nodes(1:merge(10, 4, et == ET_TET10)), elems(e))
      end do
    end subroutine cell_elements

    integer function at(q)
      integer, intent(in) :: q(3)
      at = id(q(1), q(2), q(3))
    end function at
  end subroutine generate_box

  pure function nonzero(v) result(w)
    integer, intent(in) :: v(:)
    integer, allocatable :: w(:)
    w = pack(v, v > 0)
  end function nonzero
end module mesh_box
