!> The contact segments of a node group (GAP … SEGMENTS, docs/contact.md): the straight pieces
!> of the mesh's outline whose two ends are in the group, that is the free sides of surface
!> elements (a side two elements share is inside the body) and the line elements. They must form
!> chains: every node of the group on one or two segments. A surface side knows its outward
!> normal (the elements run counter-clockwise); a line element has none (two-sided).
module mesh_segments
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use mesh, only: mesh_t
  use element_traits, only: etype_segments, etype_family, FAMILY_SURFACE, MAX_SEGMENTS
  implicit none
  private
  public :: segment_set_t, group_segments, closest_segment

  !> Segment s runs from node p(s) to node q(s); outward(s): the body is on its left, its outward
  !> normal is the right of p -> q.
  type :: segment_set_t
    integer :: n = 0
    integer, allocatable :: p(:), q(:)
    logical, allocatable :: outward(:)
  end type segment_set_t

contains

  !> The segments of the node group items (node numbers). Fails, naming the node, when a node of
  !> the group is on no segment or on more than two (not a chain of edges).
  subroutine group_segments(m, items, segs, stat, errmsg)
    type(mesh_t), intent(in) :: m
    integer, intent(in) :: items(:)
    type(segment_set_t), intent(out) :: segs
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical, allocatable :: in(:)
    integer, allocatable :: cnt(:), lo(:), hi(:), own(:)
    integer :: e, k, nseg, seg(2, MAX_SEGMENTS), a, b, nc, i, j
    logical :: surf
    stat = STAT_OK
    allocate (in(m%nnode), cnt(m%nnode))
    in = .false.
    in(items) = .true.
    ! Candidates: pieces of outlines with both ends in the group.
    allocate (lo(16), hi(16), own(16))
    nc = 0
    do e = 1, m%nelem
      call etype_segments(m%etype(e), seg, nseg)
      surf = etype_family(m%etype(e)) == FAMILY_SURFACE
      do k = 1, nseg
        a = m%conn(seg(1, k), e)
        b = m%conn(seg(2, k), e)
        if (.not. (in(a) .and. in(b))) cycle
        if (nc == size(lo)) call grow3(lo, hi, own)
        nc = nc + 1
        lo(nc) = a
        hi(nc) = b
        own(nc) = merge(1, 0, surf)
      end do
    end do
    ! A surface side listed twice (both directions) lies between two elements: not a segment.
    call drop_shared(lo, hi, own, nc, m%nnode)
    allocate (segs%p(nc), segs%q(nc), segs%outward(nc))
    segs%n = 0
    do i = 1, nc
      if (own(i) < 0) cycle
      segs%n = segs%n + 1
      segs%p(segs%n) = lo(i)
      segs%q(segs%n) = hi(i)
      segs%outward(segs%n) = own(i) == 1
    end do
    cnt = 0
    do i = 1, segs%n
      cnt(segs%p(i)) = cnt(segs%p(i)) + 1
      cnt(segs%q(i)) = cnt(segs%q(i)) + 1
    end do
    do j = 1, size(items)
      if (cnt(items(j)) == 0) then
        call set_error(stat, errmsg, STAT_INPUT, 'node ' // str(items(j)) // &
          ' is on no free element side (or line element) whose both ends are in the group')
        return
      else if (cnt(items(j)) > 2) then
        call set_error(stat, errmsg, STAT_INPUT, 'node ' // str(items(j)) // ' joins ' // str(cnt(items(j))) // &
          ' segments: the group is not a chain of element sides')
        return
      end if
    end do
  end subroutine group_segments

  !> Mark (own = -1) the surface sides that occur twice, in either direction: inside the body.
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

  pure subroutine grow3(a, b, c)
    integer, allocatable, intent(inout) :: a(:), b(:), c(:)
    integer, allocatable :: t(:)
    integer :: n
    n = size(a)
    allocate (t(2 * n))
    t(1:n) = a
    call move_alloc(t, a)
    allocate (t(2 * n))
    t(1:n) = b
    call move_alloc(t, b)
    allocate (t(2 * n))
    t(1:n) = c
    call move_alloc(t, c)
  end subroutine grow3

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
end module mesh_segments
