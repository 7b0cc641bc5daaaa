!> Gmsh 4.1 importer: the small meshes of tests/data (counts, coordinates, physical groups, element
!> orientation), malformed files rejected with "<file>:<line>: ", and a 1e5-element file read in
!> linear time. Run from the repository root (tests/run_tests.sh does). Coordinates in the files are
!> exact binary fractions, so they are compared exactly or with 1e-14 tolerances.
program test_gmsh_reader
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, str
  use mesh, only: mesh_t
  use element_traits, only: ET_MASS, ET_BAR2, ET_QUAD4, ET_QUAD8, ET_TRI3, ET_TRI6
  use gmsh_reader, only: read_gmsh
  use testing, only: check, check_close, test_summary
  implicit none

  character(len=*), parameter :: dir = 'tests/data/'
  real(dp), parameter :: tol = 1.0e-14_dp

  call test_square_quad4()
  call test_rect_quad8()
  call test_clockwise()
  call test_sparse_tags()
  call test_triangles()
  call test_msh22()
  call test_errors()
  call test_large()
  call test_summary('gmsh_reader')

contains

  subroutine get_ngroup(m, name, items)
    type(mesh_t), intent(in) :: m
    character(len=*), intent(in) :: name
    integer, allocatable, intent(out) :: items(:)
    integer :: ig
    ig = m%find_node_group(name)
    if (ig == 0) then
      allocate (items(0))
    else
      items = m%ngroups(ig)%items
    end if
  end subroutine get_ngroup

  subroutine get_egroup(m, name, items)
    type(mesh_t), intent(in) :: m
    character(len=*), intent(in) :: name
    integer, allocatable, intent(out) :: items(:)
    integer :: ig
    ig = m%find_elem_group(name)
    if (ig == 0) then
      allocate (items(0))
    else
      items = m%egroups(ig)%items
    end if
  end subroutine get_egroup

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

  !> QUAD8 mid-side nodes at the midpoints of sides 1-2, 2-3, 3-4, 4-1.
  logical function mids_ok(m, e)
    type(mesh_t), intent(in) :: m
    integer, intent(in) :: e
    integer :: k
    mids_ok = .true.
    do k = 1, 4
      mids_ok = mids_ok .and. all(abs(m%x(:, m%conn(4 + k, e)) - 0.5_dp * (m%x(:, m%conn(k, e)) + &
                                  m%x(:, m%conn(mod(k, 4) + 1, e)))) <= tol)
    end do
  end function mids_ok

  logical function sorted_unique(a)
    integer, intent(in) :: a(:)
    sorted_unique = all(a(2:) > a(:size(a) - 1))
  end function sorted_unique

  subroutine test_square_quad4()
    type(mesh_t) :: m
    integer :: stat, id, e, k, i, j
    character(len=:), allocatable :: errmsg
    integer, allocatable :: g(:), eg(:)
    logical :: ok, found

    call m%add_node([7.0_dp, 7.0_dp], id)   ! imported nodes must come after existing ones
    call read_gmsh(m, dir // 'square_quad4.msh', 'sq', stat, errmsg)
    call check(stat == STAT_OK, 'square: read', errmsg)
    if (stat /= STAT_OK) return
    call check(m%nnode == 1 + 9, 'square: 9 nodes')
    call check(m%nelem == 1 + 4 + 4, 'square: 1 point, 4 lines, 4 quads')
    call check(count(m%etype(1:m%nelem) == ET_QUAD4) == 4 .and. count(m%etype(1:m%nelem) == ET_BAR2) == 4 .and. &
               count(m%etype(1:m%nelem) == ET_MASS) == 1, 'square: element types')
    ! Nodes are the 3x3 grid {0, 1/2, 1}^2, each point once.
    ok = .true.
    do i = 0, 2
      do j = 0, 2
        found = .false.
        do k = 2, m%nnode
          if (all(m%x(:, k) == 0.5_dp * [i, j])) found = .true.
        end do
        ok = ok .and. found
      end do
    end do
    call check(ok, 'square: nodes on the 3x3 grid of the unit square')
    ! Quads: counter-clockwise squares of side 1/2.
    ok = .true.
    do e = 1, m%nelem
      if (m%etype(e) /= ET_QUAD4) cycle
      ok = ok .and. abs(0.5_dp * area2(m, m%conn(1:4, e)) - 0.25_dp) <= tol
      ok = ok .and. all(m%conn(1:4, e) >= 2) .and. all(m%conn(5:, e) == 0)
    end do
    call check(ok, 'square: quads counter-clockwise with area 1/4')
    ok = .true.
    do e = 1, m%nelem
      if (m%etype(e) == ET_BAR2) ok = ok .and. abs(norm2(m%x(:, m%conn(1, e)) - m%x(:, m%conn(2, e))) - 0.5_dp) <= tol
    end do
    call check(ok, 'square: lines of length 1/2')

    call get_egroup(m, 'sq', eg)
    call check(size(eg) == 8 .and. all(m%etype(eg) /= ET_MASS), 'square: group sq has the 8 lines and quads')
    call get_ngroup(m, 'sq', g)
    call check(size(g) == 9 .and. sorted_unique(g) .and. all(g >= 2), 'square: node group sq has all 9 nodes')

    call get_egroup(m, 'sq.left', eg)
    call check(size(eg) == 2 .and. all(m%etype(eg) == ET_BAR2), 'square: left has 2 lines')
    call get_ngroup(m, 'sq.left', g)
    call check(size(g) == 3 .and. sorted_unique(g), 'square: left has 3 nodes, sorted')
    if (size(g) > 0) call check(all(m%x(1, g) == 0.0_dp), 'square: left nodes at x = 0')
    call get_ngroup(m, 'sq.right', g)
    call check(size(g) == 3 .and. sorted_unique(g), 'square: right has 3 nodes')
    if (size(g) > 0) call check(all(m%x(1, g) == 1.0_dp), 'square: right nodes at x = 1')
    call get_egroup(m, 'sq.body', eg)
    call check(size(eg) == 4 .and. all(m%etype(eg) == ET_QUAD4), 'square: body has the 4 quads')
    call get_ngroup(m, 'sq.body', g)
    call check(size(g) == 9 .and. sorted_unique(g), 'square: body has 9 nodes')
    call get_egroup(m, 'sq.corner', eg)
    call check(size(eg) == 1, 'square: corner has one element')
    if (size(eg) == 1) call check(m%etype(eg(1)) == ET_MASS .and. all(m%x(:, m%conn(1, eg(1))) == 0.0_dp), &
      'square: corner is a point element at the origin')
    call get_ngroup(m, 'sq.corner', g)
    call check(size(g) == 1, 'square: corner node group')
  end subroutine test_square_quad4

  subroutine test_rect_quad8()
    type(mesh_t) :: m
    integer :: stat, e1, e2
    character(len=:), allocatable :: errmsg
    integer, allocatable :: g(:), eg(:)

    call read_gmsh(m, dir // 'rect_quad8.msh', 'q8', stat, errmsg)
    call check(stat == STAT_OK, 'quad8: read (with a $NodeData section skipped)', errmsg)
    if (stat /= STAT_OK) return
    ! 2x1 QUAD8 with shared mid-side nodes: (2*2+1)(2*1+1) - 2*1 = 13 nodes.
    call check(m%nnode == 13, 'quad8: 13 nodes')
    call check(m%nelem == 3, 'quad8: 3 elements')
    call get_egroup(m, 'q8', eg)
    call check(size(eg) == 2, 'quad8: prefix group has the 2 quads (not the point)')
    if (size(eg) /= 2) return
    e1 = eg(1)
    e2 = eg(2)
    call check(all(m%etype(eg) == ET_QUAD8), 'quad8: element type')
    call check_close(0.5_dp * area2(m, m%conn(1:4, e1)), 1.0_dp, tol, 'quad8: element 1 ccw, area 1')
    call check_close(0.5_dp * area2(m, m%conn(1:4, e2)), 1.0_dp, tol, 'quad8: element 2 ccw, area 1')
    call check(mids_ok(m, e1) .and. mids_ok(m, e2), 'quad8: mid-side nodes at the side midpoints')
    ! Shared side x = 1: side 2-3 of the left element is side 4-1 of the right one.
    call check(m%conn(6, e1) == m%conn(8, e2), 'quad8: mid-side node of the common side shared')
    call check(all(m%x(:, m%conn(1, e1)) == [0.0_dp, 0.0_dp]) .and. all(m%x(:, m%conn(3, e2)) == [2.0_dp, 1.0_dp]), &
      'quad8: corner coordinates')
    call get_egroup(m, 'q8.body', eg)
    call check(size(eg) == 2, 'quad8: body group')
    call get_ngroup(m, 'q8.body', g)
    call check(size(g) == 13 .and. sorted_unique(g), 'quad8: body nodes')
    call get_egroup(m, 'q8.physical_9', eg)
    call check(size(eg) == 2, 'quad8: unnamed physical group 9 -> physical_9')
    call get_egroup(m, 'q8.anchor', eg)
    call check(size(eg) == 1, 'quad8: anchor point group')
    if (size(eg) == 1) call check(m%etype(eg(1)) == ET_MASS .and. all(m%x(:, m%conn(1, eg(1))) == 0.0_dp), &
      'quad8: anchor point at the origin')
  end subroutine test_rect_quad8

  subroutine test_clockwise()
    type(mesh_t) :: m
    integer :: stat, e
    character(len=:), allocatable :: errmsg
    logical :: ok

    ! Blank prefix, no physical groups: nodes and elements only, no group.
    call read_gmsh(m, dir // 'clockwise.msh', '', stat, errmsg)
    call check(stat == STAT_OK, 'clockwise: read', errmsg)
    if (stat /= STAT_OK) return
    call check(m%nnode == 12 .and. m%nelem == 2, 'clockwise: counts')
    call check(m%nngroup == 0 .and. m%negroup == 0, 'clockwise: blank prefix and no physical group -> no group')
    ok = .true.
    do e = 1, m%nelem
      ok = ok .and. abs(0.5_dp * area2(m, m%conn(1:4, e)) - 1.0_dp) <= tol
    end do
    call check(ok, 'clockwise: quadrangles renumbered counter-clockwise')
    call check(m%etype(2) == ET_QUAD8, 'clockwise: second element QUAD8')
    if (m%etype(2) == ET_QUAD8) call check(mids_ok(m, 2), 'clockwise: QUAD8 mid-side nodes follow their sides')
    call check(all(m%x(:, m%conn(1, 1)) == 0.0_dp), 'clockwise: first corner kept')
  end subroutine test_clockwise

  !> Triangles: a TRI6 counter-clockwise, a TRI3 and a TRI6 clockwise (renumbered, the TRI6's
  !> mid-side nodes following their sides); the three are halves of the unit square,
  !> half: areas 1/2 each.
  subroutine test_triangles()
    type(mesh_t) :: m
    integer :: stat, e, k, a, b
    logical :: ok
    real(dp) :: ar
    character(len=:), allocatable :: errmsg
    call read_gmsh(m, dir // 'tri_clockwise.msh', 't', stat, errmsg)
    call check(stat == STAT_OK, 'triangles: read', errmsg)
    if (stat /= STAT_OK) return
    call check(m%nelem == 3 .and. all(m%etype(1:3) == [ET_TRI6, ET_TRI3, ET_TRI6]), 'triangles: TRI6, TRI3, TRI6')
    ok = .true.
    do e = 1, 3
      ar = 0.0_dp
      do k = 1, 3
        a = m%conn(k, e)
        b = m%conn(mod(k, 3) + 1, e)
        ar = ar + 0.5_dp * (m%x(1, a) * m%x(2, b) - m%x(1, b) * m%x(2, a))
      end do
      ok = ok .and. abs(ar - 0.5_dp) <= tol
      if (m%etype(e) == ET_TRI6) then
        do k = 1, 3              ! mid-side node k + 3 halfway along side k
          a = m%conn(k, e)
          b = m%conn(mod(k, 3) + 1, e)
          ok = ok .and. all(abs(m%x(:, m%conn(k + 3, e)) - 0.5_dp * (m%x(:, a) + m%x(:, b))) <= tol)
        end do
      end if
    end do
    call check(ok, 'triangles: counter-clockwise, area 1/2 each, mid-side nodes on their sides')
  end subroutine test_triangles

  !> MSH 2.2: two TRI6 (the second clockwise) of physical surface "plate" and a 3-node line of
  !> physical curve "bottom" (no element; its nodes make the node group); tags from 10 to 90.
  subroutine test_msh22()
    type(mesh_t) :: m
    integer :: stat, e, k, a, b, ib, ip
    logical :: ok
    real(dp) :: ar
    character(len=:), allocatable :: errmsg
    call read_gmsh(m, dir // 'tri_msh22.msh', 'v2', stat, errmsg)
    call check(stat == STAT_OK, 'MSH 2.2: read', errmsg)
    if (stat /= STAT_OK) return
    call check(m%nnode == 9 .and. m%nelem == 2 .and. all(m%etype(1:2) == ET_TRI6), 'MSH 2.2: 9 nodes, 2 TRI6 (no line element)')
    ok = .true.
    do e = 1, 2
      ar = 0.0_dp
      do k = 1, 3
        a = m%conn(k, e)
        b = m%conn(mod(k, 3) + 1, e)
        ar = ar + 0.5_dp * (m%x(1, a) * m%x(2, b) - m%x(1, b) * m%x(2, a))
        ok = ok .and. all(abs(m%x(:, m%conn(k + 3, e)) - 0.5_dp * (m%x(:, a) + m%x(:, b))) <= tol)
      end do
      ok = ok .and. abs(ar - 0.5_dp) <= tol
    end do
    call check(ok, 'MSH 2.2: counter-clockwise, mid-side nodes on their sides')
    ib = m%find_node_group('v2.bottom')
    ip = m%find_elem_group('v2.plate')
    call check(ib > 0 .and. ip > 0, 'MSH 2.2: physical groups bottom (nodes) and plate (elements)')
    if (ib > 0) call check(size(m%ngroups(ib)%items) == 3 .and. all(abs(m%x(2, m%ngroups(ib)%items)) <= tol), &
      'MSH 2.2: the 3-node line gives node group bottom, its 3 nodes on y = 0')
    if (ip > 0) call check(size(m%egroups(ip)%items) == 2, 'MSH 2.2: element group plate holds the 2 triangles')
  end subroutine test_msh22

  !> Node tags up to 3e8: looked up by binary search instead of a 3e8-entry array.
  subroutine test_sparse_tags()
    type(mesh_t) :: m
    integer :: stat
    character(len=:), allocatable :: errmsg
    call read_gmsh(m, dir // 'sparse_tags.msh', 's', stat, errmsg)
    call check(stat == STAT_OK, 'sparse tags: read', errmsg)
    if (stat /= STAT_OK) return
    call check(m%nnode == 4 .and. m%nelem == 1, 'sparse tags: counts')
    call check(all(m%x(:, m%conn(1, 1)) == [0.0_dp, 0.0_dp]) .and. all(m%x(:, m%conn(3, 1)) == [1.0_dp, 1.0_dp]), &
      'sparse tags: connectivity maps tags to the right coordinates')
    call check_close(0.5_dp * area2(m, m%conn(1:4, 1)), 1.0_dp, tol, 'sparse tags: unit square')
  end subroutine test_sparse_tags

  subroutine test_errors()
    call check_error('bad_version.msh', 2, 'version')
    call check_binary_error('bad_binary.msh', 'byte order')
    call check_binary_error('bad_binary_truncated.msh', 'beyond the file')
    call check_error('bad_truncated.msh', 12, 'end of file')
    call check_error('bad_unknown_node.msh', 19, 'unknown node tag 7')
    call check_error('bad_quad9.msh', 28, '9-node quadrangle')
    call check_error('bad_missing_end.msh', 15, '$EndNodes')
    call check_error('bad_number.msh', 12, '"0x"')
    call check_error('bad_no_elements.msh', 15, 'missing $Elements')
    call check_error('bad_not_msh.msh', 1, '$MeshFormat')
    call check_error('bad_count.msh', 15, 'expected 5 nodes')
    call check_error('bad_duplicate_tag.msh', 10, 'duplicate node tag 3')
    call check_error('bad_nonplanar.msh', 13, 'xy plane')
    call check_error('bad_short_element.msh', 19, '4 node tags')
    call check_error('bad_elements_first.msh', 4, '$Nodes')
    call check_error('bad_sparse_duplicate.msh', 15, 'duplicate node tag 5')
    ! The shared number reader: an overflowing coordinate is an input error, never a trap.
    call check_error('bad_overflow.msh', 13, 'out of range')
    ! Issue 37: two physical groups of one name (merged silently before); a binary element naming
    ! node tag 2^32 + 4 (read as node 4 before), refused as out of range like the ASCII reader.
    call check_error('bad_physical_twice.msh', 7, 'physical name "edge" given twice')
    call check_binary_error('bad_binary_tag.msh', 'tag out of range')
    call check_error('no_such_file.msh', 0, 'cannot open')
    call check_endless()
  end subroutine test_errors

  !> A file without newlines that never ends (found by tests/fuzz: GMSH ... FILE /dev/zero read until
  !> memory ran out) is refused at its first line; so is a regular file whose first line exceeds 1 MiB.
  subroutine check_endless()
    type(mesh_t) :: m
    integer :: stat, u, tlen
    character(len=:), allocatable :: errmsg, path
    character(len=256) :: tmpdir
    logical :: exists
    inquire (file='/dev/zero', exist=exists)
    if (exists) then
      call read_gmsh(m, '/dev/zero', 'z', stat, errmsg)
      if (.not. allocated(errmsg)) errmsg = ''
      call check(stat == STAT_INPUT .and. index(errmsg, '/dev/zero:1: line longer than') == 1, &
        'error /dev/zero: refused at line 1', errmsg)
    end if
    call get_environment_variable('TMPDIR', tmpdir, tlen)
    if (tlen == 0) tmpdir = '/tmp'
    path = trim(tmpdir) // '/rebond_test_gmsh_long_line.msh'
    open (newunit=u, file=path, status='replace', action='write', form='formatted')
    write (u, '(a)') repeat('x', 2 * 1048576)
    close (u)
    call read_gmsh(m, path, 'z', stat, errmsg)
    if (.not. allocated(errmsg)) errmsg = ''
    call check(stat == STAT_INPUT .and. index(errmsg, path // ':1: line longer than') == 1, &
      'error 2 MiB line: refused at line 1', errmsg)
    call check(m%nnode == 0 .and. m%nelem == 0, 'error long lines: mesh untouched')
    open (newunit=u, file=path, status='old')
    close (u, status='delete')
  end subroutine check_endless

  !> The file must be rejected with STAT_INPUT, a message starting "<path>:<line>: " and containing what.
  !> A binary file's error: "<path>: byte N (binary MSH 4.1): ...what...", mesh untouched.
  subroutine check_binary_error(file, what)
    character(len=*), intent(in) :: file, what
    type(mesh_t) :: m
    integer :: stat
    character(len=:), allocatable :: errmsg
    call read_gmsh(m, dir // file, 'x', stat, errmsg)
    if (.not. allocated(errmsg)) errmsg = ''
    call check(stat == STAT_INPUT .and. index(errmsg, dir // file // ': byte ') == 1 .and. index(errmsg, what) > 0 &
      .and. m%nnode == 0, 'error ' // file // ': message and mesh untouched', 'got "' // errmsg // '"')
  end subroutine check_binary_error

  subroutine check_error(file, line, what)
    character(len=*), intent(in) :: file, what
    integer, intent(in) :: line
    type(mesh_t) :: m
    integer :: stat
    character(len=:), allocatable :: errmsg, head
    call read_gmsh(m, dir // file, 'x', stat, errmsg)
    head = dir // file // ':' // str(line) // ': '
    call check(stat == STAT_INPUT, 'error ' // file // ': STAT_INPUT')
    if (.not. allocated(errmsg)) errmsg = ''
    call check(index(errmsg, head) == 1 .and. index(errmsg, what) > 0, 'error ' // file // ': message', &
      'got "' // errmsg // '", expected "' // head // '...' // what // '..."')
    call check(m%nnode == 0 .and. m%nelem == 0 .and. m%nngroup == 0, 'error ' // file // ': mesh untouched')
  end subroutine check_error

  !> A 317x317 QUAD4 grid (100489 elements) with node tags in reverse order, written then read back:
  !> counts and total area are exact; a quadratic tag lookup would take minutes, so 20 s is generous.
  subroutine test_large()
    integer, parameter :: n = 317
    type(mesh_t) :: m
    character(len=:), allocatable :: path, errmsg
    character(len=256) :: tmpdir
    integer :: u, i, j, k, nn, stat, tlen, e, c0, c1, rate
    integer, allocatable :: g(:)
    real(dp) :: atot, h, secs

    call get_environment_variable('TMPDIR', tmpdir, tlen)
    if (tlen == 0) tmpdir = '/tmp'
    path = trim(tmpdir) // '/rebond_test_gmsh_large.msh'
    nn = (n + 1)**2
    h = 1.0_dp / n
    open (newunit=u, file=path, status='replace', action='write')
    write (u, '(a)') '$MeshFormat', '4.1 0 8', '$EndMeshFormat'
    write (u, '(a)') '$PhysicalNames', '1', '2 1 "plate"', '$EndPhysicalNames'
    write (u, '(a)') '$Entities', '0 0 1 0', '1 0 0 0 1 1 0 1 1 0', '$EndEntities'
    write (u, '(a)') '$Nodes'
    write (u, '(4(i0,1x))') 1, nn, 1, nn
    write (u, '(4(i0,1x))') 2, 1, 0, nn
    do k = 1, nn
      write (u, '(i0)') nn + 1 - k     ! tag of grid point k
    end do
    do j = 0, n
      do i = 0, n
        write (u, '(es24.16,1x,es24.16,a)') i * h, j * h, ' 0'
      end do
    end do
    write (u, '(a)') '$EndNodes', '$Elements'
    write (u, '(4(i0,1x))') 1, n * n, 1, n * n
    write (u, '(4(i0,1x))') 2, 1, 3, n * n
    e = 0
    do j = 0, n - 1
      do i = 0, n - 1
        e = e + 1
        k = j * (n + 1) + i + 1      ! grid point of the lower-left corner
        write (u, '(5(i0,1x))') e, nn + 1 - k, nn + 1 - (k + 1), nn + 1 - (k + n + 2), nn + 1 - (k + n + 1)
      end do
    end do
    write (u, '(a)') '$EndElements'
    close (u)

    call system_clock(c0, rate)
    call read_gmsh(m, path, 'big', stat, errmsg)
    call system_clock(c1)
    secs = real(c1 - c0, dp) / rate
    write (*, '(a,f8.3,a)') '# large mesh read in ', secs, ' s'
    open (newunit=u, file=path, status='old')
    close (u, status='delete')
    call check(stat == STAT_OK, 'large: read', errmsg)
    if (stat /= STAT_OK) return
    call check(m%nnode == nn .and. m%nelem == n * n, 'large: counts')
    atot = 0.0_dp
    do e = 1, m%nelem
      atot = atot + 0.5_dp * area2(m, m%conn(1:4, e))
    end do
    call check_close(atot, 1.0_dp, 1.0e-10_dp, 'large: total area 1 (all quads counter-clockwise)')
    call get_ngroup(m, 'big.plate', g)
    call check(size(g) == nn, 'large: physical group nodes')
    call check(secs < 20.0_dp, 'large: read time linear (< 20 s)', 'took ' // str(secs) // ' s')
  end subroutine test_large
end program test_gmsh_reader
