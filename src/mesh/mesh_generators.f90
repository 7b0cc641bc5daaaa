!> Structured mesh generators: a straight line of 2-node elements and a (rotated) rectangle of
!> QUAD4/QUAD8 elements. Both append to an existing mesh_t and name groups after the part, so
!> that supports, loads and probes can refer to edges, corners and centres by name.
module mesh_generators
  use kinds, only: dp, zero_tol
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use mesh, only: mesh_t
  use element_traits, only: ET_BAR2, ET_BEAM2, ET_SPRING, ET_QUAD4, ET_QUAD8, ET_TRI3, ET_TRI6, etype_name
  implicit none
  private
  public :: generate_line, generate_rectangle, MAX_GENERATED_ELEMENTS

  !> Most elements one LINE or RECTANGLE may generate. Beyond it a count is an input error: larger
  !> meshes failed to allocate (a Fortran runtime error) or overflowed the default-integer node
  !> counts (nx+1)(ny+1), and a count near 2**31 ran for hours (found by tests/fuzz/fuzz.py).
  integer, parameter :: MAX_GENERATED_ELEMENTS = 10000000

contains

  !> nel elements of type et (BAR2, BEAM2 or SPRING) from p0 to p1, on nel+1 new equally spaced nodes.
  !> Groups: element group `name`; node groups `name` (all, from p0 to p1), `name.start`, `name.end`,
  !> `name.mid` (the middle node; for odd nel, of the two nearest the one on the p0 side).
  subroutine generate_line(m, name, p0, p1, nel, et, stat, errmsg)
    type(mesh_t), intent(inout) :: m
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: p0(2), p1(2)
    integer, intent(in) :: nel
    integer, intent(in) :: et
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, allocatable :: nodes(:), elems(:)
    real(dp) :: length
    integer :: i

    stat = STAT_OK
    if (len_trim(name) == 0) then
      call set_error(stat, errmsg, STAT_INPUT, 'line mesh: empty name')
      return
    end if
    if (et /= ET_BAR2 .and. et /= ET_BEAM2 .and. et /= ET_SPRING) then
      call set_error(stat, errmsg, STAT_INPUT, 'line mesh ' // name // ': element type ' // etype_name(et) // &
        ' not allowed (expected BAR2, BEAM2 or SPRING)')
      return
    end if
    if (nel < 1) then
      call set_error(stat, errmsg, STAT_INPUT, 'line mesh ' // name // ': number of elements ' // str(nel) // &
        ' must be at least 1')
      return
    end if
    if (nel > MAX_GENERATED_ELEMENTS) then
      call set_error(stat, errmsg, STAT_INPUT, 'line mesh ' // name // ': number of elements ' // str(nel) // &
        ' exceeds the limit of ' // str(MAX_GENERATED_ELEMENTS))
      return
    end if
    if (.not. (all(abs(p0) <= huge(1.0_dp)) .and. all(abs(p1) <= huge(1.0_dp)))) then
      call set_error(stat, errmsg, STAT_INPUT, 'line mesh ' // name // ': end points must be finite numbers')
      return
    end if
    length = norm2(p1 - p0)
    if (length <= zero_tol * max(norm2(p0), norm2(p1))) then
      call set_error(stat, errmsg, STAT_INPUT, 'line mesh ' // name // ': zero length (start and end points coincide)')
      return
    end if

    allocate (nodes(nel + 1), elems(nel))
    do i = 0, nel
      ! p0 + t (p1 - p0) with t = i/nel, written so that both ends are exact.
      call m%add_node(((nel - i) * p0 + i * p1) / real(nel, dp), nodes(i + 1))
    end do
    do i = 1, nel
      call m%add_element(et, nodes(i:i + 1), elems(i))
    end do

    call m%add_elem_group(name, elems)
    call m%add_node_group(name, nodes)
    call m%add_node_group(name // '.start', nodes(1:1))
    call m%add_node_group(name // '.end', nodes(nel + 1:nel + 1))
    call m%add_node_group(name // '.mid', nodes(nel / 2 + 1:nel / 2 + 1))
  end subroutine generate_line

  !> nx*ny elements QUAD4 or QUAD8 on the rectangle [0,lx]x[0,ly] of local axes placed at origin and
  !> rotated by angle (radians, counter-clockwise, default 0) about it. Connectivity is counter-clockwise;
  !> QUAD8 mid-side nodes are shared between neighbours. Nodes are numbered row by row (bottom to top).
  !> Groups: element group `name`; node groups `name` (all), the edges `name.bottom`, `name.top` (ordered
  !> along local x) and `name.left`, `name.right` (ordered along local y), with QUAD8 mid-side nodes;
  !> the corners `name.bottom_left`, `name.bottom_right`, `name.top_left`, `name.top_right`; and
  !> `name.center`, the node nearest the centre (the lowest-numbered one on ties).
  subroutine generate_rectangle(m, name, origin, lx, ly, nx, ny, et, stat, errmsg, angle)
    type(mesh_t), intent(inout) :: m
    character(len=*), intent(in) :: name
    real(dp), intent(in) :: origin(2)
    real(dp), intent(in) :: lx, ly
    integer, intent(in) :: nx, ny
    integer, intent(in) :: et
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), intent(in), optional :: angle
    integer, allocatable :: id(:, :), all_nodes(:), elems(:)
    integer :: step, imax, jmax, i, j, e, n, icen, per_cell
    real(dp) :: c, s, u, v, d, dmin, theta

    stat = STAT_OK
    if (len_trim(name) == 0) then
      call set_error(stat, errmsg, STAT_INPUT, 'rectangle mesh: empty name')
      return
    end if
    if (.not. any(et == [ET_QUAD4, ET_QUAD8, ET_TRI3, ET_TRI6])) then
      call set_error(stat, errmsg, STAT_INPUT, 'rectangle mesh ' // name // ': element type ' // etype_name(et) // &
        ' not allowed (expected QUAD4, QUAD8, TRI3 or TRI6)')
      return
    end if
    if (nx < 1 .or. ny < 1) then
      call set_error(stat, errmsg, STAT_INPUT, 'rectangle mesh ' // name // ': numbers of elements (' // str(nx) // &
        ', ' // str(ny) // ') must be at least 1')
      return
    end if
    ! nx*ny > MAX without forming the product, which may overflow a default integer.
    per_cell = merge(2, 1, et == ET_TRI3 .or. et == ET_TRI6)
    if (nx > MAX_GENERATED_ELEMENTS / per_cell / ny) then
      call set_error(stat, errmsg, STAT_INPUT, 'rectangle mesh ' // name // ': numbers of elements (' // str(nx) // &
        ', ' // str(ny) // ') give more than the limit of ' // str(MAX_GENERATED_ELEMENTS) // ' elements')
      return
    end if
    theta = 0.0_dp
    if (present(angle)) theta = angle
    if (.not. (abs(lx) <= huge(1.0_dp) .and. abs(ly) <= huge(1.0_dp) .and. all(abs(origin) <= huge(1.0_dp)) &
               .and. abs(theta) <= huge(1.0_dp))) then
      call set_error(stat, errmsg, STAT_INPUT, 'rectangle mesh ' // name // ': origin, lengths and angle must be finite')
      return
    end if
    ! Lengths must be positive: a negative one would mirror the mesh and make the elements clockwise.
    if (lx <= zero_tol * norm2(origin) .or. ly <= zero_tol * norm2(origin) .or. lx <= 0.0_dp .or. ly <= 0.0_dp) then
      call set_error(stat, errmsg, STAT_INPUT, 'rectangle mesh ' // name // ': lengths (' // str(lx) // ', ' // &
        str(ly) // ') must be positive and not negligible against the origin coordinates')
      return
    end if

    ! Nodes live on a grid of (imax+1) x (jmax+1) points; QUAD8 uses the half-step grid without the
    ! element centres (both indices odd), which therefore get id 0; TRI6 uses all of it (a cell's
    ! centre is the mid-side node of its diagonal).
    step = 1
    if (et == ET_QUAD8 .or. et == ET_TRI6) step = 2
    imax = step * nx
    jmax = step * ny
    c = cos(theta)
    s = sin(theta)
    allocate (id(0:imax, 0:jmax), all_nodes((imax + 1) * (jmax + 1)))
    id = 0
    n = 0
    dmin = huge(1.0_dp)
    icen = 0
    do j = 0, jmax
      do i = 0, imax
        if (et == ET_QUAD8 .and. mod(i, 2) == 1 .and. mod(j, 2) == 1) cycle
        u = lx * real(i, dp) / real(imax, dp)
        v = ly * real(j, dp) / real(jmax, dp)
        n = n + 1
        call m%add_node([origin(1) + c * u - s * v, origin(2) + s * u + c * v], id(i, j))
        all_nodes(n) = id(i, j)
        d = (u - 0.5_dp * lx)**2 + (v - 0.5_dp * ly)**2
        if (d < dmin) then
          dmin = d
          icen = id(i, j)
        end if
      end do
    end do

    ! Triangles: each cell cut along its diagonal from (i, j) to the opposite corner, both halves
    ! counter-clockwise.
    allocate (elems(per_cell * nx * ny))
    e = 0
    do j = 0, jmax - step, step
      do i = 0, imax - step, step
        e = e + 1
        select case (et)
        case (ET_QUAD4)
          call m%add_element(ET_QUAD4, [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)], elems(e))
        case (ET_QUAD8)
          call m%add_element(ET_QUAD8, [id(i, j), id(i + 2, j), id(i + 2, j + 2), id(i, j + 2), &
                                        id(i + 1, j), id(i + 2, j + 1), id(i + 1, j + 2), id(i, j + 1)], elems(e))
        case (ET_TRI3)
          call m%add_element(ET_TRI3, [id(i, j), id(i + 1, j), id(i + 1, j + 1)], elems(e))
          e = e + 1
          call m%add_element(ET_TRI3, [id(i, j), id(i + 1, j + 1), id(i, j + 1)], elems(e))
        case (ET_TRI6)
          call m%add_element(ET_TRI6, [id(i, j), id(i + 2, j), id(i + 2, j + 2), &
                                       id(i + 1, j), id(i + 2, j + 1), id(i + 1, j + 1)], elems(e))
          e = e + 1
          call m%add_element(ET_TRI6, [id(i, j), id(i + 2, j + 2), id(i, j + 2), &
                                       id(i + 1, j + 1), id(i + 1, j + 2), id(i, j + 1)], elems(e))
        end select
      end do
    end do

    call m%add_elem_group(name, elems)
    call m%add_node_group(name, all_nodes(1:n))
    call m%add_node_group(name // '.bottom', id(:, 0))
    call m%add_node_group(name // '.top', id(:, jmax))
    call m%add_node_group(name // '.left', id(0, :))
    call m%add_node_group(name // '.right', id(imax, :))
    call m%add_node_group(name // '.bottom_left', [id(0, 0)])
    call m%add_node_group(name // '.bottom_right', [id(imax, 0)])
    call m%add_node_group(name // '.top_left', [id(0, jmax)])
    call m%add_node_group(name // '.top_right', [id(imax, jmax)])
    call m%add_node_group(name // '.center', [icen])
  end subroutine generate_rectangle
end module mesh_generators
