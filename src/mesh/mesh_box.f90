!> The structured block of DIMENSION 3 (BOX): nx x ny x nz HEX8 cells on [x0, x0+lx] x [y0, y0+ly] x
!> [z0, z0+lz], or each cell cut into six TET4 (Kuhn's cut: every tetrahedron runs from the cell's
!> low corner to its high one along the three edges in some order, so that every face of every
!> cell is cut along the same diagonal as its neighbour's: the mesh is conforming).
module mesh_box
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error
  use mesh, only: mesh_t
  use element_traits, only: ET_HEX8, ET_TET4, etype_name
  implicit none
  private
  public :: generate_box

  !> The HEX8 corners (Gmsh's order) as offsets (i, j, k) in the cell.
  integer, parameter :: CORNER(3, 8) = reshape([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1], &
    [3, 8])
  !> Kuhn's six tetrahedra: the axes taken in the order of each permutation, the odd ones with
  !> their last two vertices swapped (a positive volume).
  integer, parameter :: PERM(3, 6) = reshape([1, 2, 3, 2, 3, 1, 3, 1, 2, 1, 3, 2, 3, 2, 1, 2, 1, 3], [3, 6])

contains

  !> Nodes row by row (x fastest, then y, then z). Groups: element group `name`; node groups
  !> `name` (all), the faces `name.xmin`, `name.xmax`, `name.ymin`, `name.ymax`, `name.zmin`,
  !> `name.zmax`, and `name.center` (the node nearest the centre, the lowest-numbered one on ties).
  !> The counts are checked by the caller (scene_mesh: at least 1, at most MAX_GENERATED_ELEMENTS).
  subroutine generate_box(m, name, origin, l, n, et, stat, errmsg)
    type(mesh_t), intent(inout) :: m
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: origin(3), l(3)
    integer, intent(in) :: n(3)
    integer, intent(in) :: et
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, allocatable :: id(:, :, :), elems(:)
    integer :: i, j, k, c, e, icen, p, nodes(8), v(3), t(4)
    real(dp) :: x(3), d, dmin
    stat = STAT_OK
    if (et /= ET_HEX8 .and. et /= ET_TET4) then
      call set_error(stat, errmsg, STAT_INPUT, 'box mesh ' // name // ': element type ' // etype_name(et) // &
        ' not allowed (expected HEX8 or TET4)')
      return
    end if
    allocate (id(0:n(1), 0:n(2), 0:n(3)), elems(merge(6, 1, et == ET_TET4) * n(1) * n(2) * n(3)))
    dmin = huge(1.0_dp)
    icen = 0
    do k = 0, n(3)
      do j = 0, n(2)
        do i = 0, n(1)
          ! origin + (i/nx) l, written so that both ends are exact
          x = origin + l * (real([i, j, k], dp) / real(n, dp))
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
          do c = 1, 8
            nodes(c) = id(i + CORNER(1, c), j + CORNER(2, c), k + CORNER(3, c))
          end do
          if (et == ET_HEX8) then
            e = e + 1
            call m%add_element(ET_HEX8, nodes, elems(e))
            cycle
          end if
          do p = 1, 6
            v = 0
            t(1) = id(i, j, k)
            v(PERM(1, p)) = 1
            t(2) = id(i + v(1), j + v(2), k + v(3))
            v(PERM(2, p)) = 1
            t(3) = id(i + v(1), j + v(2), k + v(3))
            t(4) = id(i + 1, j + 1, k + 1)
            if (p > 3) t(3:4) = [t(4), t(3)]      ! the odd permutations: a positive volume
            e = e + 1
            call m%add_element(ET_TET4, t, elems(e))
          end do
        end do
      end do
    end do
    call m%add_elem_group(name, elems)
    call m%add_node_group(name, reshape(id, [size(id)]))
    call m%add_node_group(name // '.xmin', reshape(id(0, :, :), [size(id(0, :, :))]))
    call m%add_node_group(name // '.xmax', reshape(id(n(1), :, :), [size(id(0, :, :))]))
    call m%add_node_group(name // '.ymin', reshape(id(:, 0, :), [size(id(:, 0, :))]))
    call m%add_node_group(name // '.ymax', reshape(id(:, n(2), :), [size(id(:, 0, :))]))
    call m%add_node_group(name // '.zmin', reshape(id(:, :, 0), [size(id(:, :, 0))]))
    call m%add_node_group(name // '.zmax', reshape(id(:, :, n(3)), [size(id(:, :, 0))]))
    call m%add_node_group(name // '.center', [icen])
  end subroutine generate_box
end module mesh_box
