!> The pieces of node-to-segment contact that follows the configuration (docs/contact.md, "Pairing
!> that follows the configuration"): pair_segment's choice of the closest point of an outline (a
!> segment inside, a corner outside, never a far side projected onto from within), the two sides
!> of a line element and orient_lines, pair_on's row = the gradient of the distance (central
!> differences), and constraint_rows' rewrite of a row that changes length.
program test_contact_geometry
  use kinds, only: dp
  use mesh_segments, only: segment_set_t, segment_pair_t, pair_segment, pair_on, orient_lines, node_stars
  use mesh, only: mesh_t
  use mesh_generators, only: generate_rectangle
  use element_traits, only: ET_QUAD4
  use constraint_rows, only: constraint_rows_t
  use errors, only: STAT_OK
  use testing, only: check, check_close, test_summary
  implicit none

  call test_outline()
  call test_line_sides()
  call test_gradient()
  call test_rewrite()
  call test_stars()
  call test_summary('contact_geometry')

contains

  !> A closed counter-clockwise polygon of nodes 1..n (outward: right of each side).
  function polygon(n) result(s)
    integer, intent(in) :: n
    type(segment_set_t) :: s
    integer :: k
    s%n = n
    allocate (s%p(n), s%q(n), s%outward(n))
    do k = 1, n
      s%p(k) = k
      s%q(k) = modulo(k, n) + 1
    end do
    s%outward = .true.
  end function polygon

  !> A parallelogram (0,0) (2,0) (3,1) (1,1); node 5 is the contact node.
  subroutine test_outline()
    type(segment_set_t) :: s
    type(segment_pair_t) :: pr
    real(dp) :: x(2, 5)
    s = polygon(4)
    x(:, 1:4) = reshape([0.0_dp, 0.0_dp, 2.0_dp, 0.0_dp, 3.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], [2, 4])
    x(:, 5) = [0.5_dp, -0.2_dp]                  ! below the bottom side
    call pair_segment(x, s, 5, pr)
    call check(pr%seg == 1 .and. .not. pr%vertex, 'below a side: that side')
    call check_close(pr%gap, 0.2_dp, 1.0e-15_dp, 'below a side: gap = distance 0.2')
    call check_close(pr%xi, 0.25_dp, 1.0e-15_dp, 'below a side: xi = 0.25')
    call check(all(abs(pr%normal - [0.0_dp, -1.0_dp]) <= 1.0e-15_dp), 'below a side: outward normal (0, -1)')
    x(:, 5) = [0.5_dp, 0.1_dp]                   ! inside, near the bottom
    call pair_segment(x, s, 5, pr)
    call check(pr%seg == 1, 'inside near a side: that side')
    call check_close(pr%gap, -0.1_dp, 1.0e-14_dp, 'inside near a side: gap = -0.1 (a penetration)')
    ! Past corner (2, 0), it projects onto the far top side only: the corner, not the top side
    ! (whose signed distance, -1.4, would be a spurious penetration).
    x(:, 5) = [2.2_dp, -0.4_dp]
    call pair_segment(x, s, 5, pr)
    call check(pr%vertex .and. pr%nodes(2) == 2 .and. pr%nodes(3) == 0, 'past a corner: the corner (node to node)')
    call check_close(pr%gap, sqrt(0.2_dp**2 + 0.4_dp**2), 1.0e-15_dp, 'past a corner: gap = distance to the corner')
    call check(all(abs(pr%normal - [0.2_dp, -0.4_dp] / sqrt(0.2_dp)) <= 1.0e-15_dp), &
      'past a corner: normal from the corner to the node')
  end subroutine test_outline

  !> A chain of line elements 1-2-3 given as 2->1 and 2->3: orient_lines makes it end to end; a
  !> node keeps its side, and crossing the line makes its gap negative.
  subroutine test_line_sides()
    type(segment_set_t) :: s
    type(segment_pair_t) :: pr
    real(dp) :: x(2, 4)
    integer :: side
    s%n = 2
    allocate (s%p(2), s%q(2), s%outward(2))
    s%p = [2, 2]
    s%q = [1, 3]
    s%outward = .false.
    call orient_lines(s, 4)
    call check((s%q(1) == s%p(2)) .or. (s%q(2) == s%p(1)), 'orient_lines: the chain runs end to end')
    x(:, 1:3) = reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 2.0_dp, 0.0_dp], [2, 3])
    x(:, 4) = [1.5_dp, 0.1_dp]
    call pair_segment(x, s, 4, pr)
    side = pr%side
    call check_close(pr%gap, 0.1_dp, 1.0e-15_dp, 'line: gap 0.1 on the side the node is on')
    x(:, 4) = [0.5_dp, 0.1_dp]                   ! the other segment, same side of the chain
    call pair_segment(x, s, 4, pr, side)
    call check_close(pr%gap, 0.1_dp, 1.0e-15_dp, 'line: the same side on the next segment of the chain')
    x(:, 4) = [0.5_dp, -0.1_dp]
    call pair_segment(x, s, 4, pr, side)
    call check_close(pr%gap, -0.1_dp, 1.0e-15_dp, 'line: crossed, the gap is negative')
    call pair_segment(x, s, 4, pr)
    call check_close(pr%gap, 0.1_dp, 1.0e-15_dp, 'line: without a side, the side it is on now')
    x(:, 4) = [2.3_dp, -0.4_dp]                  ! past the end: round it, either side
    call pair_segment(x, s, 4, pr, side)
    call check(pr%vertex .and. pr%gap > 0.0_dp, 'line: past its end, the distance to the end node')
  end subroutine test_line_sides

  !> The row (weights w along the normal) is the gradient of the gap with the partner kept:
  !> central differences on every coordinate of b, a and c, a segment and a corner.
  subroutine test_gradient()
    type(segment_set_t) :: s
    type(segment_pair_t) :: pr, pp, pm
    real(dp) :: x(2, 5), xp(2, 5), fd, an, err
    real(dp), parameter :: eps = 1.0e-6_dp
    integer :: i, d, k, v, case
    s = polygon(4)
    x(:, 1:4) = reshape([0.0_dp, 0.0_dp, 2.0_dp, 0.1_dp, 3.0_dp, 1.2_dp, 1.0_dp, 0.9_dp], [2, 4])
    do case = 1, 2
      if (case == 1) then
        x(:, 5) = [0.7_dp, -0.3_dp]
        v = 0
      else
        x(:, 5) = [2.3_dp, -0.4_dp]
        v = 2
      end if
      call pair_on(x, s, 5, 1, v, pr)
      err = 0.0_dp
      do i = 1, 3
        if (pr%nodes(i) == 0) cycle
        do d = 1, 2
          k = pr%nodes(i)
          xp = x
          xp(d, k) = x(d, k) + eps
          call pair_on(xp, s, 5, 1, v, pp)
          xp(d, k) = x(d, k) - eps
          call pair_on(xp, s, 5, 1, v, pm)
          fd = (pp%gap - pm%gap) / (2.0_dp * eps)
          an = pr%w(i) * pr%normal(d)
          err = max(err, abs(fd - an))
        end do
      end do
      call check(err <= 1.0e-8_dp, merge('row = gradient of the distance to a segment (1e-8)', &
        'row = gradient of the distance to a corner  (1e-8)', case == 1))
    end do
  end subroutine test_gradient

  !> Rows 1..3; row 2 rewritten longer (with a repeated equation merged), then shorter: the
  !> products agree with the dense rows, the other rows are intact.
  subroutine test_rewrite()
    type(constraint_rows_t) :: c
    real(dp) :: u(8), dense(3, 8)
    integer :: stat, j
    character(len=:), allocatable :: msg
    logical :: ok
    u = [(real(j, dp)**2, j = 1, 8)]
    call c%add(1.0_dp, [1, 2], [1.0_dp, -1.0_dp])
    call c%add(2.0_dp, [3, 4], [0.5_dp, 0.5_dp])
    call c%add(3.0_dp, [8, 7], [2.0_dp, 1.0_dp])
    call c%finalize(8, stat, msg)
    call check(stat == STAT_OK, 'rows finalized')
    dense = 0.0_dp
    dense(1, 1:2) = [1.0_dp, -1.0_dp]
    dense(3, 7:8) = [1.0_dp, 2.0_dp]
    call c%rewrite(2, -1.0_dp, [6, 5, 0, 6, 2, 4], [1.0_dp, 2.0_dp, 9.0_dp, 0.5_dp, -1.0_dp, 3.0_dp], [5, 6])
    dense(2, :) = 0.0_dp
    dense(2, [2, 4, 5, 6]) = [-1.0_dp, 3.0_dp, 2.0_dp, 1.5_dp]
    ok = abs(c%gap0(2) + 1.0_dp) == 0.0_dp .and. all(c%nodes(2) == [5, 6]) .and. c%last(2) - c%first(2) == 3
    do j = 1, 3
      ok = ok .and. abs(c%dot(j, u) - dot_product(dense(j, :), u)) <= 1.0e-14_dp * 100.0_dp
    end do
    call check(ok, 'rewrite longer: 4 entries, sorted and merged, other rows intact')
    call c%rewrite(2, 0.5_dp, [7], [4.0_dp], [0, 7])
    dense(2, :) = 0.0_dp
    dense(2, 7) = 4.0_dp
    ok = c%last(2) == c%first(2) .and. c%first(3) == c%last(2) + 1
    do j = 1, 3
      ok = ok .and. abs(c%dot(j, u) - dot_product(dense(j, :), u)) <= 1.0e-14_dp * 100.0_dp
    end do
    call check(ok, 'rewrite shorter: one entry, the next row follows it')
  end subroutine test_rewrite

  !> node_stars on a 3 x 2 QUAD4 grid (nodes numbered row by row, 4 per row): a corner node's star is
  !> its element (4 nodes), an edge node's two elements (6), the inner nodes' four (9).
  subroutine test_stars()
    type(mesh_t) :: m
    integer, allocatable :: ptr(:), star(:)
    integer :: stat, i
    character(len=:), allocatable :: msg
    logical :: ok
    call generate_rectangle(m, 'g', [0.0_dp, 0.0_dp], 3.0_dp, 2.0_dp, 3, 2, ET_QUAD4, stat, msg)
    call check(stat == STAT_OK .and. m%nnode == 12, 'a 3 x 2 grid of QUAD4')
    call node_stars(m, [(i, i = 1, m%nnode)], ptr, star)
    ok = .true.
    do i = 1, m%nnode
      associate (st => star(ptr(i):ptr(i + 1) - 1))
        ok = ok .and. any(st == i) .and. size(st) == merge(4, merge(9, 6, inner(m, i)), corner(m, i))
        ok = ok .and. all(max(abs(m%x(1, st) - m%x(1, i)), abs(m%x(2, st) - m%x(2, i))) <= 1.0_dp + 1.0e-12_dp)
      end associate
    end do
    call check(ok, 'node_stars: 4 / 6 / 9 nodes around a corner / edge / inner node, all within one cell')
  end subroutine test_stars

  logical function corner(m, i)
    type(mesh_t), intent(in) :: m
    integer, intent(in) :: i
    corner = (abs(m%x(1, i)) < 1e-12_dp .or. abs(m%x(1, i) - 3) < 1e-12_dp) .and. &
      (abs(m%x(2, i)) < 1e-12_dp .or. abs(m%x(2, i) - 2) < 1e-12_dp)
  end function corner

  logical function inner(m, i)
    type(mesh_t), intent(in) :: m
    integer, intent(in) :: i
    inner = m%x(1, i) > 1e-12_dp .and. m%x(1, i) < 3 - 1e-12_dp .and. m%x(2, i) > 1e-12_dp .and. m%x(2, i) < 2 - 1e-12_dp
  end function inner
end program test_contact_geometry
