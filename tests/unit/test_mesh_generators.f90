!> Structured generators: node counts, exact coordinates, groups, counter-clockwise connectivity and
!> shared QUAD8 mid-side nodes. Coordinates are sums of a few products of exact binary fractions, so
!> they are compared with a tolerance of a few ulps of the mesh size (1e-14 relative).
program test_mesh_generators
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT
  use mesh, only: mesh_t
  use element_traits, only: ET_BAR2, ET_BEAM2, ET_SPRING, ET_QUAD4, ET_QUAD8, ET_MASS
  use mesh_generators, only: generate_line, generate_rectangle, MAX_GENERATED_ELEMENTS
  use testing, only: check, check_close, test_summary
  implicit none

  real(dp), parameter :: tol = 1.0e-14_dp

  call test_line()
  call test_line_errors()
  call test_rectangle_quad4()
  call test_rectangle_quad8_rotated()
  call test_rectangle_errors()
  call test_summary('mesh_generators')

contains

  !> Group items by name (empty if the group is missing, which the count checks then catch).
  function ngroup(m, name) result(items)
    type(mesh_t), intent(in) :: m
    character(len=*), intent(in) :: name
    integer, allocatable :: items(:)
    integer :: ig
    ig = m%find_node_group(name)
    if (ig == 0) then
      allocate (items(0))
    else
      items = m%ngroups(ig)%items
    end if
  end function ngroup

  function egroup(m, name) result(items)
    type(mesh_t), intent(in) :: m
    character(len=*), intent(in) :: name
    integer, allocatable :: items(:)
    integer :: ig
    ig = m%find_elem_group(name)
    if (ig == 0) then
      allocate (items(0))
    else
      items = m%egroups(ig)%items
    end if
  end function egroup

  !> Twice the signed area of the polygon through the given nodes (shoelace formula).
  pure real(dp) function area2(m, nodes)
    type(mesh_t), intent(in) :: m
    integer, intent(in) :: nodes(:)
    integer :: i, j
    area2 = 0.0_dp
    do i = 1, size(nodes)
      j = mod(i, size(nodes)) + 1
      area2 = area2 + m%x(1, nodes(i)) * m%x(2, nodes(j)) - m%x(1, nodes(j)) * m%x(2, nodes(i))
    end do
  end function area2

  subroutine test_line()
    type(mesh_t) :: m
    integer :: stat, id, i, nel, e
    character(len=:), allocatable :: errmsg
    integer, allocatable :: g(:)
    real(dp) :: p0(2), p1(2), t
    logical :: ok

    ! A node already in the mesh: the generator must append after it.
    call m%add_node([9.0_dp, 9.0_dp], id)
    p0 = [1.0_dp, 2.0_dp]
    p1 = [4.0_dp, -2.0_dp]   ! length 5
    nel = 4
    call generate_line(m, 'beam', p0, p1, nel, ET_BEAM2, stat, errmsg)
    call check(stat == STAT_OK, 'line: generated')
    call check(m%nnode == 1 + nel + 1, 'line: nel+1 new nodes')
    call check(m%nelem == nel, 'line: nel elements')
    call check(all(m%etype(1:nel) == ET_BEAM2), 'line: element type')
    allocate (g(0))  ! first assignment of a fresh allocatable: avoids a gfortran 12 false warning
    g = ngroup(m, 'beam')
    call check(size(g) == nel + 1, 'line: node group has all nodes')
    ok = size(g) == nel + 1
    if (ok) then
      do i = 1, nel + 1
        t = real(i - 1, dp) / nel
        ok = ok .and. all(abs(m%x(:, g(i)) - (p0 + t * (p1 - p0))) <= tol * 5.0_dp)
      end do
    end if
    call check(ok, 'line: nodes equally spaced from p0 to p1')
    ok = size(g) == nel + 1
    if (ok) then
      do e = 1, nel
        ok = ok .and. all(m%conn(1:2, e) == g(e:e + 1)) .and. all(m%conn(3:, e) == 0)
      end do
    end if
    call check(ok, 'line: element e joins nodes e and e+1')
    do e = 1, nel
      call check_close(norm2(m%x(:, m%conn(2, e)) - m%x(:, m%conn(1, e))), 5.0_dp / nel, tol, 'line: element length')
    end do
    call check(size(egroup(m, 'beam')) == nel, 'line: element group')
    g = ngroup(m, 'beam.start')
    call check(size(g) == 1, 'line: start group size')
    if (size(g) == 1) call check(all(m%x(:, g(1)) == p0), 'line: start node at p0')
    g = ngroup(m, 'beam.end')
    if (size(g) == 1) call check(all(m%x(:, g(1)) == p1), 'line: end node at p1')
    g = ngroup(m, 'beam.mid')
    call check(size(g) == 1, 'line: mid group size')
    if (size(g) == 1) call check(all(abs(m%x(:, g(1)) - 0.5_dp * (p0 + p1)) <= tol * 5.0_dp), &
      'line: even nel, mid node at the midpoint')

    ! Odd nel: the mid node is one of the two nearest the midpoint, at distance L/(2 nel).
    call generate_line(m, 'spr', [0.0_dp, 0.0_dp], [0.0_dp, 3.0_dp], 3, ET_SPRING, stat, errmsg)
    call check(stat == STAT_OK, 'line: odd nel generated')
    g = ngroup(m, 'spr.mid')
    if (size(g) == 1) call check_close(abs(m%x(2, g(1)) - 1.5_dp), 0.5_dp, tol, 'line: odd nel, mid node nearest')
    call check(size(egroup(m, 'spr')) == 3 .and. m%etype(m%nelem) == ET_SPRING, 'line: spring elements')

    call generate_line(m, 'bar1', [0.0_dp, 0.0_dp], [1.0_dp, 0.0_dp], 1, ET_BAR2, stat, errmsg)
    call check(stat == STAT_OK .and. m%etype(m%nelem) == ET_BAR2, 'line: single BAR2 element')
    g = ngroup(m, 'bar1.mid')
    call check(size(g) == 1, 'line: nel=1 has a mid node')
  end subroutine test_line

  subroutine test_line_errors()
    type(mesh_t) :: m
    integer :: stat
    character(len=:), allocatable :: errmsg
    call generate_line(m, 'l', [0.0_dp, 0.0_dp], [1.0_dp, 0.0_dp], 0, ET_BAR2, stat, errmsg)
    call check(stat == STAT_INPUT .and. allocated(errmsg), 'line error: nel = 0')
    call generate_line(m, 'l', [1.0_dp, 1.0_dp], [1.0_dp, 1.0_dp], 2, ET_BAR2, stat, errmsg)
    call check(stat == STAT_INPUT, 'line error: zero length')
    call generate_line(m, 'l', [0.0_dp, 0.0_dp], [1.0_dp, 0.0_dp], 2, ET_QUAD4, stat, errmsg)
    call check(stat == STAT_INPUT, 'line error: QUAD4 element type')
    call generate_line(m, 'l', [0.0_dp, 0.0_dp], [1.0_dp, 0.0_dp], 2, ET_MASS, stat, errmsg)
    call check(stat == STAT_INPUT, 'line error: MASS element type')
    ! Counts found by the fuzzer (tests/fuzz): 2**31-1 elements overflowed nel+1 and failed to allocate.
    call generate_line(m, 'l', [0.0_dp, 0.0_dp], [1.0_dp, 0.0_dp], huge(1), ET_BAR2, stat, errmsg)
    call check(stat == STAT_INPUT .and. index(errmsg, 'limit') > 0, 'line error: huge(1) elements refused', errmsg)
    call generate_line(m, 'l', [0.0_dp, 0.0_dp], [1.0_dp, 0.0_dp], MAX_GENERATED_ELEMENTS + 1, ET_BAR2, stat, errmsg)
    call check(stat == STAT_INPUT, 'line error: MAX_GENERATED_ELEMENTS + 1 elements refused')
    call check(m%nnode == 0 .and. m%nelem == 0, 'line error: mesh untouched')
  end subroutine test_line_errors

  subroutine test_rectangle_quad4()
    type(mesh_t) :: m
    integer :: stat, nx, ny, e, i
    character(len=:), allocatable :: errmsg
    integer, allocatable :: g(:)
    real(dp) :: lx, ly, o(2), atot
    logical :: ok

    nx = 4
    ny = 3
    lx = 2.0_dp
    ly = 1.5_dp
    o = [1.0_dp, -1.0_dp]
    call generate_rectangle(m, 'plate', o, lx, ly, nx, ny, ET_QUAD4, stat, errmsg)
    call check(stat == STAT_OK, 'quad4: generated')
    call check(m%nnode == (nx + 1) * (ny + 1), 'quad4: (nx+1)(ny+1) nodes')
    call check(m%nelem == nx * ny, 'quad4: nx*ny elements')
    call check(all(m%etype(1:m%nelem) == ET_QUAD4), 'quad4: element type')
    call check(size(egroup(m, 'plate')) == nx * ny, 'quad4: element group')
    call check(size(ngroup(m, 'plate')) == m%nnode, 'quad4: node group')

    ! Every element counter-clockwise with area lx*ly/(nx*ny); areas add up to lx*ly.
    ok = .true.
    atot = 0.0_dp
    do e = 1, m%nelem
      ok = ok .and. abs(0.5_dp * area2(m, m%conn(1:4, e)) - lx * ly / (nx * ny)) <= tol * lx * ly
      atot = atot + 0.5_dp * area2(m, m%conn(1:4, e))
    end do
    call check(ok, 'quad4: each element counter-clockwise with area lx*ly/(nx*ny)')
    call check_close(atot, lx * ly, 1.0e-13_dp, 'quad4: total area')

    ! Edges, ordered along the edge, with the right coordinates.
    allocate (g(0))  ! first assignment of a fresh allocatable: avoids a gfortran 12 false warning
    g = ngroup(m, 'plate.bottom')
    call check(size(g) == nx + 1, 'quad4: bottom size')
    call check(all(abs(m%x(2, g) - o(2)) <= tol), 'quad4: bottom at y = y0')
    call check(all(m%x(1, g(2:)) > m%x(1, g(:size(g) - 1))), 'quad4: bottom ordered by x')
    g = ngroup(m, 'plate.top')
    call check(size(g) == nx + 1 .and. all(abs(m%x(2, g) - (o(2) + ly)) <= tol), 'quad4: top at y = y0 + ly')
    g = ngroup(m, 'plate.left')
    call check(size(g) == ny + 1 .and. all(abs(m%x(1, g) - o(1)) <= tol), 'quad4: left at x = x0')
    call check(all(m%x(2, g(2:)) > m%x(2, g(:size(g) - 1))), 'quad4: left ordered by y')
    g = ngroup(m, 'plate.right')
    call check(size(g) == ny + 1 .and. all(abs(m%x(1, g) - (o(1) + lx)) <= tol), 'quad4: right at x = x0 + lx')
    ! Nodes equally spaced along the bottom edge.
    g = ngroup(m, 'plate.bottom')
    ok = .true.
    do i = 1, nx + 1
      ok = ok .and. abs(m%x(1, g(i)) - (o(1) + lx * (i - 1) / nx)) <= tol * lx
    end do
    call check(ok, 'quad4: bottom nodes equally spaced')

    call check_corner(m, 'plate.bottom_left', o, 'quad4')
    call check_corner(m, 'plate.bottom_right', o + [lx, 0.0_dp], 'quad4')
    call check_corner(m, 'plate.top_left', o + [0.0_dp, ly], 'quad4')
    call check_corner(m, 'plate.top_right', o + [lx, ly], 'quad4')
    ! nx even, ny odd: nearest nodes to the centre are at distance ly/(2 ny) from it.
    g = ngroup(m, 'plate.center')
    call check(size(g) == 1, 'quad4: center group size')
    if (size(g) == 1) call check_close(norm2(m%x(:, g(1)) - (o + 0.5_dp * [lx, ly])), ly / (2 * ny), tol, &
      'quad4: center node nearest the centre')
  end subroutine test_rectangle_quad4

  subroutine check_corner(m, name, p, label)
    type(mesh_t), intent(in) :: m
    character(len=*), intent(in) :: name, label
    real(dp), intent(in) :: p(2)
    integer, allocatable :: g(:)
    allocate (g(0))  ! first assignment of a fresh allocatable: avoids a gfortran 12 false warning
    g = ngroup(m, name)
    call check(size(g) == 1, label // ': ' // name // ' has one node')
    if (size(g) == 1) call check(all(abs(m%x(:, g(1)) - p) <= tol * max(1.0_dp, maxval(abs(p)))), &
      label // ': ' // name // ' position')
  end subroutine check_corner

  subroutine test_rectangle_quad8_rotated()
    type(mesh_t) :: m
    integer :: stat, nx, ny, e, k, n1, n2, nbefore
    character(len=:), allocatable :: errmsg
    integer, allocatable :: g(:), used(:)
    real(dp) :: lx, ly, o(2), th, c, s, atot, ex(2), ey(2), p(2)
    logical :: ok, mid_ok

    nx = 3
    ny = 2
    lx = 3.0_dp
    ly = 1.0_dp
    o = [0.5_dp, 0.25_dp]
    th = 0.7_dp
    c = cos(th)
    s = sin(th)
    ex = [c, s]    ! rotated local axes
    ey = [-s, c]
    call generate_line(m, 'other', [0.0_dp, 0.0_dp], [0.0_dp, 1.0_dp], 2, ET_BAR2, stat, errmsg)
    nbefore = m%nnode
    call generate_rectangle(m, 'r8', o, lx, ly, nx, ny, ET_QUAD8, stat, errmsg, angle=th)
    call check(stat == STAT_OK, 'quad8: generated')
    call check(m%nnode - nbefore == (2 * nx + 1) * (2 * ny + 1) - nx * ny, 'quad8: (2nx+1)(2ny+1) - nx*ny nodes')
    allocate (g(0))  ! first assignment of a fresh allocatable: avoids a gfortran 12 false warning
    g = egroup(m, 'r8')
    call check(size(g) == nx * ny, 'quad8: nx*ny elements')
    call check(all(m%etype(g) == ET_QUAD8), 'quad8: element type')

    ! Counter-clockwise corners with the exact area; mid-side nodes at the midpoints of their sides.
    ok = .true.
    mid_ok = .true.
    atot = 0.0_dp
    do k = 1, size(g)
      e = g(k)
      ok = ok .and. abs(0.5_dp * area2(m, m%conn(1:4, e)) - lx * ly / (nx * ny)) <= 1.0e-13_dp * lx * ly
      ! The 8-node boundary polygon (corner, mid, corner, ...) must be counter-clockwise too.
      ok = ok .and. area2(m, m%conn([1, 5, 2, 6, 3, 7, 4, 8], e)) > 0.0_dp
      atot = atot + 0.5_dp * area2(m, m%conn(1:4, e))
      do n1 = 1, 4
        n2 = mod(n1, 4) + 1
        mid_ok = mid_ok .and. all(abs(m%x(:, m%conn(4 + n1, e)) - 0.5_dp * (m%x(:, m%conn(n1, e)) &
                                  + m%x(:, m%conn(n2, e)))) <= 1.0e-14_dp * 4.0_dp)
      end do
    end do
    call check(ok, 'quad8: rotated elements counter-clockwise with area lx*ly/(nx*ny)')
    call check(mid_ok, 'quad8: mid-side nodes at the side midpoints')
    call check_close(atot, lx * ly, 1.0e-13_dp, 'quad8: total area')

    ! Every new node is used (no orphan centre nodes) and interior mid-side nodes are shared.
    allocate (used(m%nnode))
    used = 0
    do k = 1, size(g)
      used(m%conn(1:8, g(k))) = used(m%conn(1:8, g(k))) + 1
    end do
    call check(all(used(nbefore + 1:) > 0), 'quad8: every node belongs to an element')
    ! Nodes in exactly two elements: interior mid-sides ((nx-1) ny vertical, nx (ny-1) horizontal) and
    ! the non-corner boundary vertices (2 (nx-1) + 2 (ny-1)).
    call check(count(used(nbefore + 1:) == 2) == (nx - 1) * ny + nx * (ny - 1) + 2 * (nx - 1) + 2 * (ny - 1), &
      'quad8: shared nodes (interior mid-sides and boundary vertices between two elements)')

    ! Edges in the rotated frame: bottom has 2nx+1 nodes along ex at local v = 0.
    g = ngroup(m, 'r8.bottom')
    call check(size(g) == 2 * nx + 1, 'quad8: bottom edge has 2nx+1 nodes (with mid-sides)')
    ok = .true.
    do k = 1, size(g)
      p = m%x(:, g(k)) - o
      ok = ok .and. abs(dot_product(p, ey)) <= tol * 4.0_dp .and. &
           abs(dot_product(p, ex) - lx * (k - 1) / (2 * nx)) <= tol * 4.0_dp
    end do
    call check(ok, 'quad8: bottom nodes on the rotated edge, ordered, spacing lx/(2nx)')
    g = ngroup(m, 'r8.right')
    call check(size(g) == 2 * ny + 1, 'quad8: right edge has 2ny+1 nodes')
    ok = .true.
    do k = 1, size(g)
      p = m%x(:, g(k)) - o
      ok = ok .and. abs(dot_product(p, ex) - lx) <= tol * 4.0_dp .and. &
           abs(dot_product(p, ey) - ly * (k - 1) / (2 * ny)) <= tol * 4.0_dp
    end do
    call check(ok, 'quad8: right nodes on the rotated edge, ordered')
    call check(size(ngroup(m, 'r8.top')) == 2 * nx + 1 .and. size(ngroup(m, 'r8.left')) == 2 * ny + 1, &
      'quad8: top and left edge sizes')
    call check_corner(m, 'r8.top_right', o + lx * ex + ly * ey, 'quad8')
    call check_corner(m, 'r8.bottom_right', o + lx * ex, 'quad8')
    call check_corner(m, 'r8.top_left', o + ly * ey, 'quad8')
    ! nx odd, ny even: the centre (1.5, 0.5) is a mid-side node of the half-step grid.
    g = ngroup(m, 'r8.center')
    if (size(g) == 1) call check(norm2(m%x(:, g(1)) - (o + 0.5_dp * lx * ex + 0.5_dp * ly * ey)) <= tol * 4.0_dp, &
      'quad8: center node at the centre')

    ! nx = ny = 1: the centre is the (absent) element centre; the nearest nodes are mid-sides.
    call generate_rectangle(m, 'one', [0.0_dp, 0.0_dp], 2.0_dp, 1.0_dp, 1, 1, ET_QUAD8, stat, errmsg)
    call check(stat == STAT_OK .and. size(ngroup(m, 'one')) == 8, 'quad8: single element has 8 nodes')
    g = ngroup(m, 'one.center')
    if (size(g) == 1) call check_close(norm2(m%x(:, g(1)) - [1.0_dp, 0.5_dp]), 0.5_dp, tol, &
      'quad8: single element, center node is a nearest mid-side')
  end subroutine test_rectangle_quad8_rotated

  subroutine test_rectangle_errors()
    type(mesh_t) :: m
    integer :: stat
    character(len=:), allocatable :: errmsg
    call generate_rectangle(m, 'r', [0.0_dp, 0.0_dp], 1.0_dp, 1.0_dp, 0, 2, ET_QUAD4, stat, errmsg)
    call check(stat == STAT_INPUT, 'rectangle error: nx = 0')
    call generate_rectangle(m, 'r', [0.0_dp, 0.0_dp], 1.0_dp, 1.0_dp, 2, -1, ET_QUAD4, stat, errmsg)
    call check(stat == STAT_INPUT, 'rectangle error: ny < 0')
    call generate_rectangle(m, 'r', [0.0_dp, 0.0_dp], 0.0_dp, 1.0_dp, 2, 2, ET_QUAD4, stat, errmsg)
    call check(stat == STAT_INPUT, 'rectangle error: lx = 0')
    call generate_rectangle(m, 'r', [0.0_dp, 0.0_dp], 1.0_dp, -1.0_dp, 2, 2, ET_QUAD8, stat, errmsg)
    call check(stat == STAT_INPUT, 'rectangle error: ly < 0')
    call generate_rectangle(m, 'r', [0.0_dp, 0.0_dp], 1.0_dp, 1.0_dp, 2, 2, ET_BEAM2, stat, errmsg)
    call check(stat == STAT_INPUT .and. index(errmsg, 'BEAM2') > 0, 'rectangle error: BEAM2 element type', errmsg)
    ! Counts found by the fuzzer (tests/fuzz): 65536 x 65536 overflows a default integer (to 0),
    ! 46341 x 46341 overflows (nx+1)(ny+1); a product of exactly the limit + 1 is refused too.
    call generate_rectangle(m, 'r', [0.0_dp, 0.0_dp], 1.0_dp, 1.0_dp, 65536, 65536, ET_QUAD4, stat, errmsg)
    call check(stat == STAT_INPUT .and. index(errmsg, 'limit') > 0, 'rectangle error: 65536 x 65536 refused', errmsg)
    call generate_rectangle(m, 'r', [0.0_dp, 0.0_dp], 1.0_dp, 1.0_dp, 46341, 46341, ET_QUAD8, stat, errmsg)
    call check(stat == STAT_INPUT, 'rectangle error: 46341 x 46341 refused')
    call generate_rectangle(m, 'r', [0.0_dp, 0.0_dp], 1.0_dp, 1.0_dp, huge(1), 1, ET_QUAD4, stat, errmsg)
    call check(stat == STAT_INPUT, 'rectangle error: huge(1) x 1 refused')
    call generate_rectangle(m, 'r', [0.0_dp, 0.0_dp], 1.0_dp, 1.0_dp, MAX_GENERATED_ELEMENTS / 7 + 1, 7, ET_QUAD4, &
      stat, errmsg)
    call check(stat == STAT_INPUT, 'rectangle error: (limit/7 + 1) x 7 refused')
    call check(m%nnode == 0 .and. m%nelem == 0, 'rectangle error: mesh untouched')
  end subroutine test_rectangle_errors
end program test_mesh_generators
