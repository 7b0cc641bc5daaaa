!> GROUP name NODES|ELEMENTS … (docs/input.md, "Groups"; Cast3M's POIN … PLUS/DROI/CERC, ET, DIFF):
!> the union of groups, or a selection by geometry within all the nodes (elements) or a group OF
!> which they must be part:
!>   BOX x0 y0 x1 y1          the nodes with x0 <= x <= x1 and y0 <= y <= y1,
!>   SPHERE x y RADIUS r      the nodes within r of (x, y) (a disk in the plane),
!>   PLANE x y NORMAL nx ny TOLERANCE t   the nodes within t of the line through (x, y) normal to n,
!> each bound widened by 1e-12 of the model's size (a node on a bound is inside); the elements
!> whose every node is inside; or by operation: INTERSECTION g1 g2, DIFFERENCE g1 g2 (in g1, not in
!> g2). An empty result is an input error.
module scene_groups
  use kinds, only: dp, zero_tol
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use statement, only: statement_t, stmt_error, find_param, get_real, token_t
  use statement_schema, only: schema_t
  use scene, only: scene_t
  use scene_helpers, only: get_point, model_size
  use mesh, only: MAX_COORD
  implicit none
  private
  public :: groups_schema, do_group

  character(len=12), parameter :: SELECTORS(5) = [character(len=12) :: 'BOX', 'SPHERE', 'PLANE', 'INTERSECTION', &
    'DIFFERENCE']

contains

  subroutine groups_schema(sch)
    type(schema_t), intent(inout) :: sch
    call sch%add_keyword('GROUP', 1, 1)
    call sch%add_param('GROUP', 'NODES', 0, -1)
    call sch%add_param('GROUP', 'ELEMENTS', 0, -1)
    call sch%add_param('GROUP', 'BOX', 4, 6)
    call sch%add_param('GROUP', 'SPHERE', 2, 3)
    call sch%add_param('GROUP', 'RADIUS', 1, 1)
    call sch%add_param('GROUP', 'PLANE', 2, 3)
    call sch%add_param('GROUP', 'NORMAL', 2, 3)
    call sch%add_param('GROUP', 'TOLERANCE', 1, 1)
    call sch%add_param('GROUP', 'OF', 1, 1)
    call sch%add_param('GROUP', 'INTERSECTION', 2, 2)
    call sch%add_param('GROUP', 'DIFFERENCE', 2, 2)
  end subroutine groups_schema

  subroutine do_group(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: kn, ke, k, i, ig, nsel, sel, n
    logical :: nodes
    logical, allocatable :: used(:)
    character(len=:), allocatable :: what
    stat = STAT_OK
    kn = find_param(st, 'NODES')
    ke = find_param(st, 'ELEMENTS')
    if ((kn == 0) .eqv. (ke == 0)) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'give exactly one of NODES or ELEMENTS'))
      return
    end if
    nodes = kn > 0
    k = merge(kn, ke, nodes)
    what = trim(merge('node   ', 'element', nodes))
    n = merge(scn%mesh%nnode, scn%mesh%nelem, nodes)
    nsel = 0
    sel = 0
    do i = 1, size(SELECTORS)
      if (find_param(st, trim(SELECTORS(i))) == 0) cycle
      nsel = nsel + 1
      if (nsel == 2) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'one of BOX, SPHERE, PLANE, INTERSECTION, DIFFERENCE', &
          st%params(find_param(st, trim(SELECTORS(i))))%keytok))
        return
      end if
      sel = i
    end do
    call check_companions(st, sel, stat, errmsg)
    if (stat /= STAT_OK) return
    if (sel == 0 .and. size(st%params(k)%values) == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, merge('NODES   ', 'ELEMENTS', nodes) // ' needs ' // &
        'group names, or BOX, SPHERE, PLANE, INTERSECTION or DIFFERENCE', st%params(k)%keytok))
      return
    end if
    if (sel > 0 .and. size(st%params(k)%values) > 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'group names or ' // trim(SELECTORS(sel)) // ', not both', &
        st%params(k)%values(1)))
      return
    end if
    allocate (used(n))
    used = .false.
    select case (sel)
    case (0)                                     ! the union of the groups named
      do i = 1, size(st%params(k)%values)
        call group_index(scn, nodes, st, st%params(k)%values(i), ig, stat, errmsg)
        if (stat /= STAT_OK) return
        call mark(scn, nodes, ig, used)
      end do
    case (4, 5)
      call operation(scn, st, nodes, sel == 4, used, stat, errmsg)
    case default
      call geometric(scn, st, nodes, sel, used, stat, errmsg)
    end select
    if (stat /= STAT_OK) return
    if (.not. any(used)) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'the selection holds no ' // what, st%lead(1)))
      return
    end if
    if (nodes) then
      call scn%mesh%add_node_group(st%lead(1)%text, pack([(i, i = 1, n)], used))
    else
      call scn%mesh%add_elem_group(st%lead(1)%text, pack([(i, i = 1, n)], used))
    end if
  end subroutine do_group

  !> RADIUS goes with SPHERE, NORMAL and TOLERANCE with PLANE, OF with the geometric selectors.
  subroutine check_companions(st, sel, stat, errmsg)
    type(statement_t), intent(in) :: st
    integer, intent(in) :: sel
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=9), parameter :: COMP(4) = [character(len=9) :: 'RADIUS', 'NORMAL', 'TOLERANCE', 'OF']
    logical :: ok(4)
    integer :: i, k
    stat = STAT_OK
    ok = [sel == 2, sel == 3, sel == 3, sel >= 1 .and. sel <= 3]
    do i = 1, size(COMP)
      k = find_param(st, trim(COMP(i)))
      if (k > 0 .and. .not. ok(i)) then
        if (sel == 0) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, trim(COMP(i)) // ' does not go with group names', &
            st%params(k)%keytok))
        else
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, trim(COMP(i)) // ' does not go with ' // &
            trim(SELECTORS(sel)), st%params(k)%keytok))
        end if
        return
      end if
      if (k == 0 .and. ok(i) .and. i <= 3) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, trim(SELECTORS(sel)) // ' needs ' // trim(COMP(i)), &
          st%params(find_param(st, trim(SELECTORS(sel))))%keytok))
        return
      end if
    end do
  end subroutine check_companions

  !> BOX, SPHERE or PLANE (sel 1, 2, 3) within the candidates (all, or the group OF).
  subroutine geometric(scn, st, nodes, sel, used, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    logical, intent(in) :: nodes
    integer, intent(in) :: sel
    logical, intent(inout) :: used(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical, allocatable :: inside(:), cand(:)
    real(dp) :: a(6), c(scn%mesh%ndim), nrm(scn%mesh%ndim), r, tol
    integer :: i, e, k, ig, nd
    stat = STAT_OK
    nd = scn%mesh%ndim
    tol = zero_tol * model_size(scn%mesh)
    select case (sel)
    case (1)                                  ! BOX x0 y0 [z0] x1 y1 [z1]: a(1:nd) the low corner, a(4:3+nd) the high
      k = find_param(st, 'BOX')
      if (size(st%params(k)%values) /= 2 * nd) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'BOX takes ' // str(2 * nd) // ' numbers in a ' // &
          str(nd) // 'D scene', st%params(k)%keytok))
        return
      end if
      do i = 1, 2 * nd
        call get_real(st, 'BOX', a(merge(i, i - nd + 3, i <= nd)), stat, errmsg, index=i, lower=-MAX_COORD, &
          lower_inclusive=.true., upper=MAX_COORD, upper_inclusive=.true.)
        if (stat /= STAT_OK) return
      end do
      if (any(a(4:3 + nd) < a(1:nd))) call set_error(stat, errmsg, STAT_INPUT, &
        stmt_error(st, 'BOX x0 y0 x1 y1 (3D: x0 y0 z0 x1 y1 z1) with x0 <= x1, y0 <= y1, z0 <= z1', &
        st%params(find_param(st, 'BOX'))%keytok))
    case (2)
      call get_point(st, 'SPHERE', c, stat, errmsg)
      if (stat == STAT_OK) call get_real(st, 'RADIUS', r, stat, errmsg, lower=0.0_dp, lower_inclusive=.false., &
        upper=MAX_COORD, upper_inclusive=.true.)
    case (3)
      call get_point(st, 'PLANE', c, stat, errmsg)
      if (stat == STAT_OK) call get_point(st, 'NORMAL', nrm, stat, errmsg)
      if (stat == STAT_OK) call get_real(st, 'TOLERANCE', r, stat, errmsg, lower=0.0_dp, lower_inclusive=.true., &
        upper=MAX_COORD, upper_inclusive=.true.)
      if (stat == STAT_OK .and. norm2(nrm) == 0.0_dp) call set_error(stat, errmsg, STAT_INPUT, &
        stmt_error(st, 'NORMAL must be a non-zero vector', st%params(find_param(st, 'NORMAL'))%keytok))
      if (stat == STAT_OK) nrm = nrm / norm2(nrm)
    end select
    if (stat /= STAT_OK) return
    allocate (inside(scn%mesh%nnode))
    do i = 1, scn%mesh%nnode
      associate (x => scn%mesh%x(:, i))
        select case (sel)
        case (1)
          inside(i) = all(x >= a(1:nd) - tol .and. x <= a(4:3 + nd) + tol)
        case (2)
          inside(i) = norm2(x - c) <= r + tol
        case default
          inside(i) = abs(dot_product(x - c, nrm)) <= r + tol
        end select
      end associate
    end do
    allocate (cand(size(used)))
    cand = .true.
    k = find_param(st, 'OF')
    if (k > 0) then
      call group_index(scn, nodes, st, st%params(k)%values(1), ig, stat, errmsg)
      if (stat /= STAT_OK) return
      cand = .false.
      call mark(scn, nodes, ig, cand)
    end if
    if (nodes) then
      used = cand .and. inside
    else
      do e = 1, scn%mesh%nelem
        used(e) = cand(e) .and. all(inside(scn%mesh%conn(1:scn%mesh%nen(e), e)))
      end do
    end if
  end subroutine geometric

  !> INTERSECTION g1 g2 (inter) or DIFFERENCE g1 g2.
  subroutine operation(scn, st, nodes, inter, used, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    logical, intent(in) :: nodes, inter
    logical, intent(inout) :: used(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical, allocatable :: b(:)
    integer :: k, g1, g2
    k = find_param(st, trim(merge('INTERSECTION', 'DIFFERENCE  ', inter)))
    call group_index(scn, nodes, st, st%params(k)%values(1), g1, stat, errmsg)
    if (stat == STAT_OK) call group_index(scn, nodes, st, st%params(k)%values(2), g2, stat, errmsg)
    if (stat /= STAT_OK) return
    allocate (b(size(used)))
    b = .false.
    call mark(scn, nodes, g1, used)
    call mark(scn, nodes, g2, b)
    if (inter) then
      used = used .and. b
    else
      used = used .and. .not. b
    end if
  end subroutine operation

  !> The node (element) group the token names: ig, or an error at the token.
  subroutine group_index(scn, nodes, st, t, ig, stat, errmsg)
    type(scene_t), intent(in) :: scn
    logical, intent(in) :: nodes
    type(statement_t), intent(in) :: st
    type(token_t), intent(in) :: t
    integer, intent(out) :: ig
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (nodes) then
      ig = scn%mesh%find_node_group(t%text)
    else
      ig = scn%mesh%find_elem_group(t%text)
    end if
    if (ig == 0) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'unknown ' // &
      trim(merge('node group   ', 'element group', nodes)), t))
  end subroutine group_index

  pure subroutine mark(scn, nodes, ig, used)
    type(scene_t), intent(in) :: scn
    logical, intent(in) :: nodes
    integer, intent(in) :: ig
    logical, intent(inout) :: used(:)
    if (nodes) then
      used(scn%mesh%ngroups(ig)%items) = .true.
    else
      used(scn%mesh%egroups(ig)%items) = .true.
    end if
  end subroutine mark
end module scene_groups
