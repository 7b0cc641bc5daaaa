!> The outline of a node group: its free sides (group_sides: the sides of surface elements whose
!> nodes are all in the group and that no other element shares, for PRESSURE and TRACTION) and
!> its contact segments (group_segments, GAP … SEGMENTS, docs/contact.md: the straight pieces of
!> those sides, a 3-node side as two, and the line elements with both ends in the group). A side
!> or piece runs counter-clockwise around its element (elements are counter-clockwise): the body
!> on its left, its outward normal on its right; a line element has no side (two-sided).
module mesh_segments
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use mesh, only: mesh_t
  use array_utils, only: grow
  use element_traits, only: etype_sides, etype_family, FAMILY_LINE
  implicit none
  private
  public :: side_set_t, segment_set_t, segment_pair_t, group_sides, group_segments, closest_segment, pair_segment, pair_on, &
    orient_lines, node_stars, NO_PARTNER

  !> The gap of a node that has no partner (a following condition's empty row: never active).
  real(dp), parameter :: NO_PARTNER = 1.0e30_dp

  !> Free side s: nodes node(1:nsn(s), s) (2, or 3 with the mid-side node second), of element
  !> elem(s).
  type :: side_set_t
    integer :: n = 0
    integer, allocatable :: node(:, :), nsn(:), elem(:)
  end type side_set_t

  !> Segment s runs from node p(s) to node q(s); outward(s): the body is on its left, its outward
  !> normal is the right of p -> q.
  type :: segment_set_t
    integer :: n = 0
    integer, allocatable :: p(:), q(:)
    logical, allocatable :: outward(:)
  end type segment_set_t

  !> A node's contact partner on a segment set (pair_segment): the gap g = n.Σ_k w(k) x(nodes(k))
  !> over nodes(k) > 0 (b first); seg = 0: none (an empty set).
  type :: segment_pair_t
    integer :: seg = 0
    integer :: nodes(3) = 0
    real(dp) :: w(3) = 0.0_dp, normal(2) = 0.0_dp, gap = 0.0_dp, xi = 0.0_dp
    logical :: vertex = .false.              !< paired with a segment's end, not a point inside it
    integer :: side = 0                      !< a line element: b's side (+1 right of p -> q, -1 left)
  end type segment_pair_t

contains

  !> The free sides of the node group items (node numbers). Fails, naming the node, when a node
  !> of the group is on no free side (the group is not a set of element sides).
  subroutine group_sides(m, items, sides, stat, errmsg)
    type(mesh_t), intent(in) :: m
    integer, intent(in) :: items(:)
    type(side_set_t), intent(out) :: sides
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical, allocatable :: in(:), on(:)
    integer, allocatable :: lo(:), hi(:), own(:), nd(:), nsn(:), elem(:)
    integer :: e, k, side(3, 4), nside, ns, nc, i, j
    stat = STAT_OK
    allocate (in(m%nnode), on(m%nnode))
    in = .false.
    in(items) = .true.
    ! Candidates: the sides with all their nodes in the group, side c at nd(3c-2:3c).
    nc = 0
    allocate (nd(48), nsn(16), elem(16))
    do e = 1, m%nelem
      call etype_sides(m%etype(e), side, nside, ns)
      do k = 1, nside
        if (.not. all(in(m%conn(side(1:ns, k), e)))) cycle
        nc = nc + 1
        call grow(nd, 3 * nc)
        call grow(nsn, nc)
        call grow(elem, nc)
        nd(3 * nc - 2:3 * nc) = 0
        nd(3 * nc - 2:3 * nc - 3 + ns) = m%conn(side(1:ns, k), e)
        nsn(nc) = ns
        elem(nc) = e
      end do
    end do
    allocate (lo(nc), hi(nc), own(nc))
    lo = [(nd(3 * i - 2), i = 1, nc)]
    hi = [(nd(3 * i - 3 + nsn(i)), i = 1, nc)]
    own = 1
    ! A side listed twice (by its two elements) lies inside the body: not a free side.
    call drop_shared(lo, hi, own, nc, m%nnode)
    sides%n = count(own(1:nc) == 1)
    allocate (sides%node(3, sides%n), sides%nsn(sides%n), sides%elem(sides%n))
    j = 0
    on = .false.
    do i = 1, nc
      if (own(i) /= 1) cycle
      j = j + 1
      sides%node(:, j) = nd(3 * i - 2:3 * i)
      sides%nsn(j) = nsn(i)
      sides%elem(j) = elem(i)
      on(nd(3 * i - 2:3 * i - 3 + nsn(i))) = .true.
    end do
    do i = 1, size(items)
      if (.not. on(items(i))) then
        call set_error(stat, errmsg, STAT_INPUT, 'node ' // str(m%node_tag(items(i))) // &
          ' is on no free element side whose nodes are all in the group')
        return
      end if
    end do
  end subroutine group_sides

  !> The contact segments of the node group items: the straight pieces of its free sides and its
  !> line elements. Fails, naming the node, when a node of the group is on no segment or on more
  !> than two (not a chain of element sides).
  subroutine group_segments(m, items, segs, stat, errmsg)
    type(mesh_t), intent(in) :: m
    integer, intent(in) :: items(:)
    type(segment_set_t), intent(out) :: segs
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(side_set_t) :: sides
    logical, allocatable :: in(:)
    integer, allocatable :: cnt(:)
    integer :: e, i, j, k, nline, a, b
    character(len=:), allocatable :: msg
    allocate (in(m%nnode), cnt(m%nnode))
    in = .false.
    in(items) = .true.
    call group_sides(m, items, sides, stat, msg)   ! nodes on line elements only are counted below
    stat = STAT_OK
    nline = 0
    do e = 1, m%nelem
      if (etype_family(m%etype(e)) /= FAMILY_LINE) cycle
      if (in(m%conn(1, e)) .and. in(m%conn(2, e))) nline = nline + 1
    end do
    allocate (segs%p(2 * sides%n + nline), segs%q(2 * sides%n + nline), segs%outward(2 * sides%n + nline))
    k = 0
    do i = 1, sides%n
      do j = 1, sides%nsn(i) - 1
        k = k + 1
        segs%p(k) = sides%node(j, i)
        segs%q(k) = sides%node(j + 1, i)
        segs%outward(k) = .true.
      end do
    end do
    do e = 1, m%nelem
      if (etype_family(m%etype(e)) /= FAMILY_LINE) cycle
      a = m%conn(1, e)
      b = m%conn(2, e)
      if (.not. (in(a) .and. in(b))) cycle
      k = k + 1
      segs%p(k) = a
      segs%q(k) = b
      segs%outward(k) = .false.
    end do
    segs%n = k
    cnt = 0
    do i = 1, segs%n
      cnt(segs%p(i)) = cnt(segs%p(i)) + 1
      cnt(segs%q(i)) = cnt(segs%q(i)) + 1
    end do
    do j = 1, size(items)
      if (cnt(items(j)) == 0) then
        call set_error(stat, errmsg, STAT_INPUT, 'node ' // str(m%node_tag(items(j))) // &
          ' is on no free element side (or line element) whose both ends are in the group')
        return
      else if (cnt(items(j)) > 2) then
        call set_error(stat, errmsg, STAT_INPUT, 'node ' // str(m%node_tag(items(j))) // ' joins ' // str(cnt(items(j))) // &
          ' segments: the group is not a chain of element sides')
        return
      end if
    end do
  end subroutine group_segments

  !> Mark (own = -1) the sides that occur twice (same end nodes, either direction): inside the
  !> body.
  !> Bucketed by the smaller end node: linear in the number of candidates.
  pure subroutine drop_shared(lo, hi, own, nc, nnode)
    integer, intent(inout) :: lo(:), hi(:), own(:)
    integer, intent(in) :: nc, nnode
    integer :: head(nnode), next(nc), i, k, key
    head = 0
    do i = 1, nc
      if (own(i) /= 1) cycle
      key = min(lo(i), hi(i))
      k = head(key)
      do while (k > 0)
        if (own(k) == 1 .and. max(lo(k), hi(k)) == max(lo(i), hi(i))) then
          own(k) = -1
          own(i) = -1
          exit
        end if
        k = next(k)
      end do
      if (own(i) == -1) cycle
      next(i) = head(key)
      head(key) = i
    end do
  end subroutine drop_shared

  !> The segment closest to point x among those that do not hold node skip and onto which x
  !> projects (parameter xi in [0, 1] along p -> q, within tol), with the point's distance d, its
  !> normal n (outward for a surface side, towards x for a line element) and the signed gap
  !> g = n.(x - (1-xi) x_p - xi x_q). best = 0 when no segment qualifies.
  pure subroutine closest_segment(m, segs, x, skip, best, xi, n, g)
    type(mesh_t), intent(in) :: m
    type(segment_set_t), intent(in) :: segs
    real(dp), intent(in) :: x(2)
    integer, intent(in) :: skip
    integer, intent(out) :: best
    real(dp), intent(out) :: xi, n(2), g
    real(dp), parameter :: tol = 1.0e-9_dp
    real(dp) :: t(2), l2, s, d, dbest, xp(2)
    integer :: k
    best = 0
    xi = 0.0_dp
    n = 0.0_dp
    g = 0.0_dp
    dbest = huge(1.0_dp)
    do k = 1, segs%n
      if (segs%p(k) == skip .or. segs%q(k) == skip) cycle
      xp = m%x(:, segs%p(k))
      t = m%x(:, segs%q(k)) - xp
      l2 = dot_product(t, t)
      if (.not. l2 > 0.0_dp) cycle
      s = dot_product(x - xp, t) / l2
      if (s < -tol .or. s > 1.0_dp + tol) cycle
      s = min(max(s, 0.0_dp), 1.0_dp)
      d = norm2(x - (xp + s * t))
      if (d < dbest) then
        dbest = d
        best = k
        xi = s
      end if
    end do
    if (best == 0) return
    xp = m%x(:, segs%p(best))
    t = m%x(:, segs%q(best)) - xp
    n = [t(2), -t(1)] / norm2(t)
    if (.not. segs%outward(best) .and. dot_product(n, x - xp) < 0.0_dp) n = -n
    g = dot_product(n, x - (xp + xi * t))
  end subroutine closest_segment

  !> The line-element segments of segs turned so that along each chain every segment starts
  !> where the one before ends: a side of the chain (pair_segment's side) is then the same side
  !> on all its segments. nnode nodes in the mesh; a node is on at most two segments (group_segments).
  pure subroutine orient_lines(segs, nnode)
    type(segment_set_t), intent(inout) :: segs
    integer, intent(in) :: nnode
    integer :: at(2, nnode), stack(segs%n), k, m, i, top, nd, e
    logical :: done(segs%n)
    at = 0
    do k = 1, segs%n
      if (segs%outward(k)) cycle
      do e = 1, 2
        nd = merge(segs%p(k), segs%q(k), e == 1)
        i = merge(1, 2, at(1, nd) == 0)
        at(i, nd) = k
      end do
    end do
    done = segs%outward(1:segs%n)
    do k = 1, segs%n
      if (done(k)) cycle
      done(k) = .true.
      top = 1
      stack(1) = k
      do while (top > 0)
        m = stack(top)
        top = top - 1
        do e = 1, 2                            ! the neighbours at m's end q, then at its start p
          nd = merge(segs%q(m), segs%p(m), e == 1)
          do i = 1, 2
            if (at(i, nd) == 0 .or. at(i, nd) == m) cycle
            if (done(at(i, nd))) cycle
            call turn(segs, at(i, nd), nd, e == 1)
            done(at(i, nd)) = .true.
            top = top + 1
            stack(top) = at(i, nd)
          end do
        end do
      end do
    end do
  end subroutine orient_lines

  !> Segment j, sharing node nd with the one before: made to start at nd (after) or end there.
  pure subroutine turn(segs, j, nd, after)
    type(segment_set_t), intent(inout) :: segs
    integer, intent(in) :: j, nd
    logical, intent(in) :: after
    integer :: tmp
    if ((after .and. segs%p(j) /= nd) .or. (.not. after .and. segs%q(j) /= nd)) then
      tmp = segs%p(j)
      segs%p(j) = segs%q(j)
      segs%q(j) = tmp
    end if
  end subroutine turn

  !> The contact partner of node b among the segments segs (other than those ending at b) in the
  !> configuration x(2, nnode): the closest point of the outline. Inside a segment (b projects
  !> onto it) the gap is b's signed distance along that segment's normal, as closest_segment's;
  !> at a segment's end v (a corner), outside the body (on the outward side of v's segment, or
  !> always for a line element) it is the distance |x_b - x_v| along the line from v to b (a
  !> node-to-node row, invariant under rotation as the others), inside it the signed distance to
  !> the segment's line through v (a penetration, which the step closes); on that line (the
  !> outline straight through v) the corner. A node outside is thus never paired with a far side
  !> it happens to project onto from within the body, and a side b is behind by more than a
  !> quarter of its length is skipped (the far side of a body, through it).
  !> A line element has two sides: b's is side (+1: the right of p -> q, -1: its left; 0 or
  !> absent: the one b is on now), so that a node that crosses the line has a negative gap.
  !> A function of x (and side) only: re-pairing at every step needs no history (restarts bit
  !> for bit).
  pure subroutine pair_segment(x, segs, b, pr, side, skip)
    real(dp), intent(in) :: x(:, :)
    type(segment_set_t), intent(in) :: segs
    integer, intent(in) :: b
    type(segment_pair_t), intent(out) :: pr
    integer, intent(in), optional :: side
    logical, intent(in), optional :: skip(:)  !< nodes whose segments are no partners (b's elements')
    real(dp), parameter :: tol = 1.0e-9_dp
    real(dp) :: t(2), l2, s, sc, d, dbest, xp(2), xb(2), over
    integer :: k, kbest, v
    logical :: inside
    xb = x(:, b)
    dbest = huge(1.0_dp)
    kbest = 0
    v = 0
    over = 0.0_dp
    inside = .false.
    ! The closest point of the outline: inside a segment (b projects onto it), or an end. A side
    ! that b is behind by more than a quarter of its length is no partner: the far side of a
    ! body (through it), not a penetration a step makes.
    do k = 1, segs%n
      if (segs%p(k) == b .or. segs%q(k) == b) cycle
      if (present(skip)) then
        if (skip(segs%p(k)) .or. skip(segs%q(k))) cycle
      end if
      xp = x(:, segs%p(k))
      t = x(:, segs%q(k)) - xp
      l2 = dot_product(t, t)
      if (.not. l2 > 0.0_dp) cycle
      s = dot_product(xb - xp, t) / l2
      sc = min(max(s, 0.0_dp), 1.0_dp)
      if (segs%outward(k)) then
        if (t(2) * (xb(1) - xp(1)) - t(1) * (xb(2) - xp(2)) < -0.25_dp * l2) cycle
      end if
      d = norm2(xb - (xp + sc * t))
      if (d < dbest .or. (d == dbest .and. s >= -tol .and. s <= 1.0_dp + tol .and. .not. inside)) then
        dbest = d
        kbest = k
        inside = s >= -tol .and. s <= 1.0_dp + tol
        v = merge(segs%p(k), segs%q(k), sc == 0.0_dp)
        over = abs(s - sc) * sqrt(l2)
      end if
    end do
    if (kbest == 0) return
    call pair_on(x, segs, b, kbest, 0, pr, side, clamp=.true.)
    if (inside) return
    ! Past the ends: the corner v outside the body (and round a line element's end, on either
    ! side); inside it, beneath the corner more than beyond it (the overshoot along the segment),
    ! the line through v. A node further along the segment's line is beyond the corner, not in it
    ! (the same straight outline bent a little by the step).
    if (pr%gap >= 0.0_dp .or. .not. segs%outward(kbest) .or. -pr%gap < over) &
      call pair_on(x, segs, b, kbest, v, pr, side)
  end subroutine pair_segment

  !> The nodes of the elements around each of nodes(:) (the node itself included): star(ptr(i) :
  !> ptr(i+1) - 1) for nodes(i). Through a node-to-element map, linear in the mesh. Self-contact
  !> takes no partner there: a node cannot touch the sides of its own elements.
  pure subroutine node_stars(m, nodes, ptr, star)
    type(mesh_t), intent(in) :: m
    integer, intent(in) :: nodes(:)
    integer, allocatable, intent(out) :: ptr(:), star(:)
    integer :: eptr(m%nnode + 1), elist(max(size(m%conn), 1)), fill(m%nnode), e, a, i, k, n, c, pass
    logical :: seen(m%nnode)
    eptr = 0
    do e = 1, m%nelem
      do a = 1, m%nen(e)
        eptr(m%conn(a, e) + 1) = eptr(m%conn(a, e) + 1) + 1
      end do
    end do
    eptr(1) = 1
    do i = 1, m%nnode
      eptr(i + 1) = eptr(i + 1) + eptr(i)
    end do
    fill = eptr(1:m%nnode)
    do e = 1, m%nelem
      do a = 1, m%nen(e)
        elist(fill(m%conn(a, e))) = e
        fill(m%conn(a, e)) = fill(m%conn(a, e)) + 1
      end do
    end do
    allocate (ptr(size(nodes) + 1), star(0))
    seen = .false.
    do pass = 1, 2                           ! count, then fill
      ptr(1) = 1
      do i = 1, size(nodes)
        n = ptr(i)
        do k = eptr(nodes(i)), eptr(nodes(i) + 1) - 1
          do a = 1, m%nen(elist(k))
            c = m%conn(a, elist(k))
            if (seen(c)) cycle
            seen(c) = .true.
            if (pass == 2) star(n) = c
            n = n + 1
          end do
        end do
        do k = eptr(nodes(i)), eptr(nodes(i) + 1) - 1    ! unmark
          seen(m%conn(1:m%nen(elist(k)), elist(k))) = .false.
        end do
        ptr(i + 1) = n
      end do
      if (pass == 1) then
        deallocate (star)
        allocate (star(ptr(size(nodes) + 1) - 1))
      end if
    end do
  end subroutine node_stars

  !> Node b paired with segment k of segs (v = 0: the point at xi of its line, xi the foot of the
  !> perpendicular, within [0, 1] with clamp) or with its end node v (the gap |x_b - x_v| along the
  !> line from v to b). side as in pair_segment. With the partner of a step fixed, the row is a
  !> smooth function of x: the iteration of a step re-evaluates it with this.
  pure subroutine pair_on(x, segs, b, k, v, pr, side, clamp)
    real(dp), intent(in) :: x(:, :)
    type(segment_set_t), intent(in) :: segs
    integer, intent(in) :: b, k, v
    type(segment_pair_t), intent(out) :: pr
    integer, intent(in), optional :: side
    logical, intent(in), optional :: clamp
    real(dp) :: t(2), xp(2), xb(2), n(2), dx(2)
    xb = x(:, b)
    xp = x(:, segs%p(k))
    t = x(:, segs%q(k)) - xp
    pr%seg = k
    pr%xi = dot_product(xb - xp, t) / dot_product(t, t)
    if (present(clamp)) then
      if (clamp) pr%xi = min(max(pr%xi, 0.0_dp), 1.0_dp)
    end if
    n = [t(2), -t(1)] / norm2(t)
    if (.not. segs%outward(k)) then
      pr%side = 1
      if (dot_product(n, xb - xp) < 0.0_dp) pr%side = -1
      if (present(side)) then
        if (side /= 0) pr%side = side
      end if
      n = pr%side * n
    end if
    if (v > 0) then
      dx = xb - x(:, v)
      pr%vertex = .true.
      pr%xi = merge(0.0_dp, 1.0_dp, v == segs%p(k))
      pr%nodes = [b, v, 0]
      pr%w = [1.0_dp, -1.0_dp, 0.0_dp]
      pr%normal = n                          ! on the corner itself: the segment's normal
      pr%gap = 0.0_dp
      if (norm2(dx) > 0.0_dp) then
        pr%normal = dx / norm2(dx)
        pr%gap = norm2(dx)
      end if
      return
    end if
    pr%nodes = [b, segs%p(k), segs%q(k)]
    pr%w = [1.0_dp, -(1.0_dp - pr%xi), -pr%xi]
    pr%normal = n
    pr%gap = dot_product(n, xb - (xp + pr%xi * t))
  end subroutine pair_on
end module mesh_segments
