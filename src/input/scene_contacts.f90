!> Scene input: the unilateral contacts (OBSTACLE, GAP): one condition per node, node pair,
!> node facing a segment (GAP … SEGMENTS) or in 3D a face (GAP … FACES: scene_gap_faces).
!> Their grammar (schema) and their handlers; scene_loader calls them.
module scene_contacts
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use statement, only: statement_t, token_t, stmt_error, find_param, get
  use statement_schema, only: schema_t
  use scene, only: scene_t, condition_t, contact_nodes, condition_keyword
  use contact_modes, only: IMPACT_AUTO, IMPACT_PAPER, IMPACT_PERSIST, IMPACT_MASSLESS, IMPACT_SYMMETRIC, IMPACT_NAMES, &
    SOLVER_AUTO, SOLVER_SCHUR
  use element_traits, only: ET_MASS, ET_SPRING
  use material_law, only: law_is_linear, law_name
  use scene_helpers, only: node_group, get_point, model_size, get_unit, get_choice, check_modelled, get_function, &
    on_models, modelled_group, get_restitution
  use scene_gap_faces, only: do_gap_faces
  use mesh_segments, only: segment_set_t, segment_pair_t, group_segments, closest_segment, pair_segment, orient_lines, &
    node_stars, NO_PARTNER
  implicit none
  private
  public :: contacts_schema, contacts_statement, resolve_impact

  character(len=8), parameter :: CURVED_WORDS(3) = [character(len=8) :: 'RADIUS', 'INSIDE', 'OUTSIDE']
  character(len=8), parameter :: PLANE_WORDS(2) = [character(len=8) :: 'POINT', 'NORMAL']

contains

  subroutine contacts_schema(sch)
    type(schema_t), intent(inout) :: sch
    call sch%add_keyword('OBSTACLE', 1, 1)
    call sch%add_param('OBSTACLE', 'NODES', 1, 1)
    call sch%add_param('OBSTACLE', 'POINT', 2, 3)
    call sch%add_param('OBSTACLE', 'NORMAL', 2, 3)
    call sch%add_param('OBSTACLE', 'RESTITUTION', 1, 1)
    call sch%add_param('OBSTACLE', 'SPHERE', 2, 2)
    call sch%add_param('OBSTACLE', 'CYLINDER', 2, 2)
    call sch%add_param('OBSTACLE', 'RADIUS', 1, 1)
    call sch%add_param('OBSTACLE', 'INSIDE', 0, 0)
    call sch%add_param('OBSTACLE', 'OUTSIDE', 0, 0)
    call sch%add_param('OBSTACLE', 'VELOCITY', 2, 3)
    call sch%add_param('OBSTACLE', 'FUNCTION', 1, 1)
    call sch%add_param('OBSTACLE', 'FRICTION', 1, 1)
    call sch%add_keyword('GAP', 1, 1)
    call sch%add_param('GAP', 'NODES', 1, 1)
    call sch%add_param('GAP', 'WITH', 1, 1)
    call sch%add_param('GAP', 'SEGMENTS', 1, 1)
    call sch%add_param('GAP', 'FACES', 1, 1)
    call sch%add_param('GAP', 'PAIRS', 2, -1)
    call sch%add_param('GAP', 'NORMAL', 2, 3)
    call sch%add_param('GAP', 'RESTITUTION', 1, 1)
    call sch%add_param('GAP', 'PAIRING', 1, 1)
    call sch%add_param('GAP', 'FRICTION', 1, 1)
  end subroutine contacts_schema

  !> One contacts statement (pass 3 of load_scene: after the models and SCHEME).
  subroutine contacts_statement(scn, st, path, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: first
    stat = STAT_OK
    first = size(scn%conditions) + 1
    if (scn%mesh%ndim == 3 .and. (st%keyword == 'OBSTACLE' .or. st%keyword == 'GAP')) call check_3d_contact(st, stat, errmsg)
    if (stat /= STAT_OK) return
    select case (st%keyword)
    case ('OBSTACLE')
      call do_obstacle(scn, st, stat, errmsg)
    case ('GAP')
      call do_gap(scn, st, stat, errmsg)
    end select
    if (stat == STAT_OK) call get_friction(scn, st, first, stat, errmsg)
  end subroutine contacts_statement

  !> What a DIMENSION 3 contact offers so far: plane obstacles and node-to-node gaps, with or
  !> without FRICTION; the other forms are refused by name rather than ignored.
  subroutine check_3d_contact(st, stat, errmsg)
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=8), parameter :: refused(3) = [character(len=8) :: 'SPHERE', 'CYLINDER', 'SEGMENTS']
    integer :: k, ip
    stat = STAT_OK
    do k = 1, size(refused)
      ip = find_param(st, trim(refused(k)))
      if (ip == 0) cycle
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, st%keyword // ' … ' // trim(refused(k)) // &
        ' is not available in DIMENSION 3 yet (3D: plane OBSTACLE, fixed or moving, GAP … WITH, PAIRS or FACES, ' // &
        'with or without FRICTION)', &
        st%params(ip)%keytok))
      return
    end do
  end subroutine check_3d_contact

  !> FRICTION mu (mu >= 0, finite; default 0) on the conditions first.. of the statement just read:
  !> Coulomb friction (docs/contact.md, "Friction"). Refused where the tangent would have to follow
  !> the geometry (a curved obstacle, GAP … SEGMENTS paired at every step): not supported yet,
  !> never ignored.
  subroutine get_friction(scn, st, first, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(in) :: first
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: mu
    integer :: k
    stat = STAT_OK
    k = find_param(st, 'FRICTION')
    if (k == 0) return
    call get(st, 'FRICTION', mu, stat, errmsg, lower=0.0_dp, lower_inclusive=.true., upper=1.0e100_dp, &
      upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    if (mu == 0.0_dp) return
    if (any(scn%conditions(first:)%follow)) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'FRICTION on a contact whose normal follows the ' // &
        'configuration (a SPHERE or CYLINDER obstacle, GAP … SEGMENTS paired at every step) is not supported yet: ' // &
        'a plane OBSTACLE, GAP … WITH or PAIRS, or SEGMENTS with PAIRING START', st%params(k)%keytok))
    else
      scn%conditions(first:)%friction = mu
    end if
  end subroutine get_friction

  !> Refuse an initial penetration beyond 1e-10 of the model size (a gap of zero is a contact
  !> at t = 0, legitimate).
  subroutine check_penetration(scn, st, c, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    type(condition_t), intent(in) :: c
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (c%g0 < -1.0e-10_dp * model_size(scn%mesh)) then
      if (c%node_a == 0) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'node ' // str(scn%mesh%node_tag(c%node_b)) // ' (x = ' // &
          str(scn%mesh%x(1, c%node_b)) // ', y = ' // str(scn%mesh%x(2, c%node_b)) // ') starts ' // str(-c%g0) // &
          ' inside the obstacle', st%lead(1)))
      else
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'nodes ' // str(scn%mesh%node_tag(c%node_a)) // ' and ' // &
          str(scn%mesh%node_tag(c%node_b)) // ' start interpenetrated by ' // str(-c%g0), st%lead(1)))
      end if
    end if
  end subroutine check_penetration

  !> OBSTACLE name NODES group POINT x y NORMAL nx ny: each node of the group stays on the side
  !> of the rigid plane its outward normal points to.
  subroutine do_obstacle(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: p(scn%mesh%ndim), n(scn%mesh%ndim)
    integer :: ig, k, i
    type(condition_t) :: c
    type(condition_t), allocatable :: batch(:)
    k = find_param(st, 'NODES')
    if (k == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'missing parameter NODES', st%lead(1)))
      return
    end if
    call modelled_group(scn, st, st%params(k)%values(1), ig, stat, errmsg)
    if (stat /= STAT_OK) return
    if (find_param(st, 'SPHERE') > 0 .or. find_param(st, 'CYLINDER') > 0) then
      call do_curved_obstacle(scn, st, ig, stat, errmsg)
      return
    end if
    do i = 1, 3
      k = find_param(st, trim(CURVED_WORDS(i)))
      if (k > 0) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, trim(CURVED_WORDS(i)) // ' goes with SPHERE or CYLINDER', &
          st%params(k)%keytok))
        return
      end if
    end do
    call get_point(st, 'POINT', p, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_unit(st, 'NORMAL', n, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_restitution(st, c%restitution, stat, errmsg)
    if (stat == STAT_OK) call get_motion(scn, st, c, stat, errmsg)
    if (stat /= STAT_OK) return
    allocate (batch(size(scn%mesh%ngroups(ig)%items)))
    do i = 1, size(scn%mesh%ngroups(ig)%items)
      c%source = st%lead(1)%text
      c%node_a = 0
      c%node_b = scn%mesh%ngroups(ig)%items(i)
      c%normal = 0.0_dp
      c%normal(1:size(n)) = n
      c%g0 = dot_product(n, scn%mesh%x(:, c%node_b) - p)
      c%line = st%line
      call check_penetration(scn, st, c, stat, errmsg)
      if (stat /= STAT_OK) return
      batch(i) = c
    end do
    scn%conditions = [scn%conditions, batch]        ! (once per statement: linear in the group)
  end subroutine do_obstacle

  !> OBSTACLE … VELOCITY vx vy [vz] [FUNCTION f]: the obstacle's rigid translation at velocity (vx, vy[, vz])
  !> x f(t) (f = 1 without FUNCTION), each component within ±1e100; FUNCTION alone is an error.
  subroutine get_motion(scn, st, c, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    type(condition_t), intent(inout) :: c
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (find_param(st, 'VELOCITY') == 0) then
      if (find_param(st, 'FUNCTION') > 0) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, &
        'FUNCTION scales the obstacle''s VELOCITY vx vy, which is missing', st%params(find_param(st, 'FUNCTION'))%keytok))
      return
    end if
    c%velocity = 0.0_dp
    call get_point(st, 'VELOCITY', c%velocity(1:scn%mesh%ndim), stat, errmsg)
    if (stat == STAT_OK) call get_function(scn, st, c%vfunc, stat, errmsg)
    c%moving = stat == STAT_OK
  end subroutine get_motion

  !> OBSTACLE name NODES group SPHERE|CYLINDER x y RADIUS r INSIDE|OUTSIDE (the plane's circle: a
  !> sphere's or a cylinder's section): each node stays outside (or inside) the rigid circle,
  !> g = ±(|x_b - c| - r) >= 0, its normal through the centre at the node's current position. The
  !> rows follow the configuration (contact_geometry, as PAIRING STEP's): linearized at every step,
  !> during it at the midpoint.
  subroutine do_curved_obstacle(scn, st, ig, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(in) :: ig
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: word
    real(dp) :: ctr(2), d(2), r
    integer :: i, k, s
    type(condition_t) :: c
    type(condition_t), allocatable :: batch(:)
    word = 'SPHERE'
    if (find_param(st, 'CYLINDER') > 0) word = 'CYLINDER'
    k = find_param(st, word)
    do i = 1, 2
      if (find_param(st, trim(PLANE_WORDS(i))) > 0) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, trim(PLANE_WORDS(i)) // ' goes with a plane, not with ' // &
          word, st%params(find_param(st, trim(PLANE_WORDS(i))))%keytok))
        return
      end if
    end do
    if (find_param(st, 'SPHERE') > 0 .and. find_param(st, 'CYLINDER') > 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'SPHERE or CYLINDER, not both', st%params(k)%keytok))
      return
    end if
    call get_point(st, word, ctr, stat, errmsg)
    if (stat /= STAT_OK) return
    if (find_param(st, 'RADIUS') == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, word // ' needs RADIUS r', st%params(k)%keytok))
      return
    end if
    call get(st, 'RADIUS', c%radius, stat, errmsg, lower=0.0_dp, upper=1.0e100_dp, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    if ((find_param(st, 'INSIDE') > 0) .eqv. (find_param(st, 'OUTSIDE') > 0)) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, word // ' needs INSIDE or OUTSIDE (the side of the ' // &
        'circle the nodes stay on), one of them', st%params(k)%keytok))
      return
    end if
    s = merge(-1, 1, find_param(st, 'INSIDE') > 0)
    call get_restitution(st, c%restitution, stat, errmsg)
    if (stat == STAT_OK) call get_motion(scn, st, c, stat, errmsg)
    if (stat /= STAT_OK) return
    call check_following(scn, st, k, stat, errmsg)
    if (stat /= STAT_OK) return
    allocate (batch(size(scn%mesh%ngroups(ig)%items)))
    do i = 1, size(scn%mesh%ngroups(ig)%items)
      c%source = st%lead(1)%text
      c%node_a = 0
      c%node_b = scn%mesh%ngroups(ig)%items(i)
      d = scn%mesh%x(:, c%node_b) - ctr
      r = norm2(d)
      if (r <= 1.0e-12_dp * max(c%radius, model_size(scn%mesh))) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'node ' // str(scn%mesh%node_tag(c%node_b)) // &
          ' is at the centre of the ' // word // ': no normal', st%params(k)%keytok))
        return
      end if
      c%normal = 0.0_dp
      c%normal(1:2) = s * d / r
      c%g0 = s * (r - c%radius)
      c%curved = s
      c%center = ctr
      c%follow = .true.
      c%line = st%line
      call check_penetration(scn, st, c, stat, errmsg)
      if (stat /= STAT_OK) return
      batch(i) = c
    end do
    scn%conditions = [scn%conditions, batch]
  end subroutine do_curved_obstacle

  !> GAP name NODES ga WITH gb [NORMAL nx ny] | GAP name PAIRS a1 b1 a2 b2 … [NORMAL nx ny]:
  !> node-to-node unilateral conditions, b staying on the side of a the normal points to.
  !> With NODES … WITH, each node of ga is paired with the nearest node of gb; without NORMAL
  !> the normal of a pair is the direction from a to b.
  subroutine do_gap(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: kn, kw, kp, ga, gb, i, j, a, b, best
    real(dp) :: n(scn%mesh%ndim), d, dbest
    logical :: given
    type(condition_t) :: c
    integer, allocatable :: pa(:), pb(:)
    kn = find_param(st, 'NODES')
    kw = find_param(st, 'WITH')
    kp = find_param(st, 'PAIRS')
    if (find_param(st, 'FACES') > 0) then
      call do_gap_faces(scn, st, stat, errmsg)
      return
    end if
    if (find_param(st, 'SEGMENTS') > 0) then
      call do_gap_segments(scn, st, stat, errmsg)
      return
    end if
    i = find_param(st, 'PAIRING')
    if (i > 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'PAIRING goes with SEGMENTS or FACES (node-to-node pairs are ' // &
        'made once)', st%params(i)%keytok))
      return
    end if
    given = find_param(st, 'NORMAL') > 0
    if (given) then
      call get_unit(st, 'NORMAL', n, stat, errmsg)
      if (stat /= STAT_OK) return
    end if
    call get_restitution(st, c%restitution, stat, errmsg)
    if (stat /= STAT_OK) return
    if (kp > 0 .and. kn == 0 .and. kw == 0) then
      associate (vals => st%params(kp)%values)
        if (mod(size(vals), 2) /= 0) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'PAIRS takes pairs of one-node groups', &
            st%params(kp)%keytok))
          return
        end if
        allocate (pa(size(vals) / 2), pb(size(vals) / 2))
        do i = 1, size(vals) / 2
          call one_node(vals(2 * i - 1), pa(i), stat, errmsg)
          if (stat /= STAT_OK) return
          call one_node(vals(2 * i), pb(i), stat, errmsg)
          if (stat /= STAT_OK) return
        end do
      end associate
    else if (kn > 0 .and. kw > 0 .and. kp == 0) then
      call modelled_group(scn, st, st%params(kn)%values(1), ga, stat, errmsg)
      if (stat == STAT_OK) call modelled_group(scn, st, st%params(kw)%values(1), gb, stat, errmsg)
      if (stat /= STAT_OK) return
      associate (na => scn%mesh%ngroups(ga)%items, nb => scn%mesh%ngroups(gb)%items)
        allocate (pa(size(na)), pb(size(na)))
        do i = 1, size(na)
          best = 0
          dbest = huge(1.0_dp)
          do j = 1, size(nb)
            if (nb(j) == na(i)) cycle
            d = norm2(scn%mesh%x(:, nb(j)) - scn%mesh%x(:, na(i)))
            if (d < dbest) then
              dbest = d
              best = nb(j)
            end if
          end do
          if (best == 0) then
            call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'no node to pair with node ' // str(na(i)), &
              st%params(kw)%values(1)))
            return
          end if
          pa(i) = na(i)
          pb(i) = best
        end do
        call check_matching(scn, st, st%params(kw)%values(1), pa, pb, nb, given, n, stat, errmsg)
        if (stat /= STAT_OK) return
      end associate
    else
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'give NODES ga WITH gb, or PAIRS a1 b1 …', st%lead(1)))
      return
    end if
    do i = 1, size(pa)
      a = pa(i)
      b = pb(i)
      c%source = st%lead(1)%text
      c%node_a = a
      c%node_b = b
      c%line = st%line
      c%normal = 0.0_dp
      if (given) then
        c%normal(1:size(n)) = n
      else
        d = norm2(scn%mesh%x(:, b) - scn%mesh%x(:, a))
        if (d <= 1.0e-12_dp * model_size(scn%mesh)) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'nodes ' // str(scn%mesh%node_tag(a)) // ' and ' // &
            str(scn%mesh%node_tag(b)) // ' coincide: give NORMAL', st%lead(1)))
          return
        end if
        c%normal(1:size(n)) = (scn%mesh%x(:, b) - scn%mesh%x(:, a)) / d
      end if
      c%g0 = dot_product(c%normal(1:size(n)), scn%mesh%x(:, b) - scn%mesh%x(:, a))
      call check_penetration(scn, st, c, stat, errmsg)
      if (stat /= STAT_OK) return
      scn%conditions = [scn%conditions, c]
    end do
  contains
    subroutine one_node(tok, node, stat, errmsg)
      type(token_t), intent(in) :: tok
      integer, intent(out) :: node
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
      integer :: g
      call node_group(scn, st, tok, g, stat, errmsg)
      if (stat /= STAT_OK) return
      if (size(scn%mesh%ngroups(g)%items) /= 1) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'a pair needs one-node groups', tok))
        return
      end if
      call check_modelled(scn, st, tok, scn%mesh%ngroups(g)%items, stat, errmsg)
      if (stat /= STAT_OK) return
      node = scn%mesh%ngroups(g)%items(1)
    end subroutine one_node
  end subroutine do_gap

  !> GAP name NODES ga SEGMENTS gs [RESTITUTION e]: node-to-segment conditions (docs/contact.md).
  !> Each node of ga is paired, in the initial configuration, with the closest segment of gs it
  !> projects onto (mesh_segments), other than the segments it ends: the gap runs along the
  !> segment's normal (outward for a side of a surface element) to the point at xi along it, and
  !> the row couples the node with the segment's two ends, weights 1, -(1 - xi), -xi. Nodes that
  !> face no segment get no condition; a node of gs touching another segment of gs at rest
  !> (self-contact at rest) is an input error. When a node of ga or gs is on an element of a
  !> KINEMATICS LARGE model the pairing follows the configuration (contact_geometry re-pairs at
  !> every step): every node of ga gets a condition, paired by pair_segment (a segment, or past
  !> the ends a corner); SCHEME MULTIPLIERS becomes SCHUR (AUGMENTED and IMPACT MASSLESS are
  !> refused). PAIRING START keeps the pairing of t = 0 on LARGE models (to measure what following
  !> buys), PAIRING STEP follows the configuration on small-displacement models too.
  subroutine do_gap_segments(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(segment_set_t) :: segs
    type(segment_pair_t) :: pr
    type(condition_t) :: c
    integer, allocatable :: sptr(:), star(:)
    logical, allocatable :: skip(:)
    integer :: ga, gs, i, b, best, kn, ks, npair, k
    real(dp) :: xi, n(2), g, tol
    logical, allocatable :: in_gs(:)
    kn = find_param(st, 'NODES')
    ks = find_param(st, 'SEGMENTS')
    if (kn == 0 .or. find_param(st, 'WITH') > 0 .or. find_param(st, 'PAIRS') > 0 .or. find_param(st, 'NORMAL') > 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'SEGMENTS goes with NODES ga only (no WITH, PAIRS or ' // &
        'NORMAL: the segments give the normal)', st%params(ks)%keytok))
      return
    end if
    call get_restitution(st, c%restitution, stat, errmsg)
    if (stat /= STAT_OK) return
    call modelled_group(scn, st, st%params(kn)%values(1), ga, stat, errmsg)
    if (stat == STAT_OK) call modelled_group(scn, st, st%params(ks)%values(1), gs, stat, errmsg)
    if (stat /= STAT_OK) return
    call group_segments(scn%mesh, scn%mesh%ngroups(gs)%items, segs, stat, errmsg)
    if (stat /= STAT_OK) then
      errmsg = stmt_error(st, 'SEGMENTS ' // scn%mesh%ngroups(gs)%name // ': ' // errmsg, st%params(ks)%values(1))
      return
    end if
    allocate (in_gs(scn%mesh%nnode))
    in_gs = .false.
    in_gs(scn%mesh%ngroups(gs)%items) = .true.
    tol = 1.0e-10_dp * model_size(scn%mesh)
    npair = 0
    c%source = st%lead(1)%text
    c%line = st%line
    ! PAIRING STEP: re-paired in the configuration of every step; START: once, at t = 0. The
    ! default follows the kinematics: STEP when a node of ga or gs is on a LARGE model.
    call get_choice(st, 'PAIRING', ['AUTO ', 'START', 'STEP '], 'AUTO', k, stat, errmsg)
    if (stat /= STAT_OK) return
    c%follow = k == 3 .or. (k == 1 .and. on_models(scn, [scn%mesh%ngroups(ga)%items, scn%mesh%ngroups(gs)%items], &
      scn%models%large))
    if (c%follow) then
      call check_following(scn, st, ks, stat, errmsg)
      if (stat /= STAT_OK) return
      call orient_lines(segs, scn%mesh%nnode)
    end if
    scn%segsets = [scn%segsets, segs]
    c%segset = size(scn%segsets)
    if (c%follow) then                       ! a node touches no side of its own elements
      call node_stars(scn%mesh, scn%mesh%ngroups(ga)%items, sptr, star)
      allocate (skip(scn%mesh%nnode))
      skip = .false.
    end if
    do i = 1, size(scn%mesh%ngroups(ga)%items)
      b = scn%mesh%ngroups(ga)%items(i)
      if (c%follow) then
        if (any((segs%p(1:segs%n) == b .or. segs%q(1:segs%n) == b) .and. .not. segs%outward(1:segs%n))) then
          ! A node of a beam or bar chain has no side of the chain to keep (it lies on it).
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'node ' // str(scn%mesh%node_tag(b)) // ' of ' // &
            scn%mesh%ngroups(ga)%name // ' lies on a line element of ' // scn%mesh%ngroups(gs)%name // ': with the ' // &
            'pairing following the configuration (PAIRING STEP) a node on a beam or bar has no side to keep, so the ' // &
            'self-contact of line elements is not followed (use PAIRING START, or surface elements)', &
            st%params(ks)%values(1)))
          return
        end if
        skip(star(sptr(i):sptr(i + 1) - 1)) = .true.
        call pair_segment(scn%mesh%x, segs, b, pr, skip=skip)
        skip(star(sptr(i):sptr(i + 1) - 1)) = .false.
        best = pr%seg
        c%side = pr%side
        if (best == 0) then                  ! no partner yet: a condition all the same (it may get one)
          c%node_b = b
          c%node_a = 0
          c%node_c = 0
          c%xi = 0.0_dp
          c%normal = 0.0_dp
          c%g0 = NO_PARTNER
          scn%conditions = [scn%conditions, c]
          npair = npair + 1
          cycle
        end if
        xi = pr%xi
        n = pr%normal
        g = pr%gap
      else
        call closest_segment(scn%mesh, segs, scn%mesh%x(:, b), b, best, xi, n, g)
        if (best == 0) cycle
      end if
      if (in_gs(b) .and. abs(g) <= tol) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'node ' // str(scn%mesh%node_tag(b)) // ' of ' // &
          scn%mesh%ngroups(gs)%name // ' touches its segment ' // str(segs%p(best)) // '-' // str(segs%q(best)) // &
          ' at rest (self-contact of a surface with itself)', st%params(ks)%values(1)))
        return
      end if
      if (.not. segs%outward(best) .and. abs(g) <= tol) then
        ! A line element has two sides: a node on it has none to keep (it would pass through).
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'node ' // str(scn%mesh%node_tag(b)) // ' of ' // &
          scn%mesh%ngroups(ga)%name // ' starts on the line element ' // str(scn%mesh%node_tag(segs%p(best))) // '-' // &
          str(scn%mesh%node_tag(segs%q(best))) // ' of ' // scn%mesh%ngroups(gs)%name // ' (gap 0): the side it must ' // &
          'stay on is undetermined; start it at a gap', st%params(ks)%values(1)))
        return
      end if
      c%node_b = b
      c%node_a = segs%p(best)
      c%node_c = segs%q(best)
      if (c%follow) then
        c%node_a = pr%nodes(2)
        c%node_c = pr%nodes(3)                 ! 0 for a corner: node to node
      end if
      c%xi = xi
      c%normal = 0.0_dp
      c%normal(1:2) = n
      c%g0 = g
      call check_penetration(scn, st, c, stat, errmsg)
      if (stat /= STAT_OK) return
      scn%conditions = [scn%conditions, c]
      npair = npair + 1
    end do
    if (npair == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'no node of ' // scn%mesh%ngroups(ga)%name // &
        ' faces a segment of ' // scn%mesh%ngroups(gs)%name, st%params(ks)%values(1)))
    end if
  end subroutine do_gap_segments


  !> A pairing that follows the configuration rewrites its rows at every step: the Schur
  !> multipliers only (the augmented system's pattern is analysed once), and the contact nodes
  !> keep their mass (IMPACT MASSLESS moves the mass of a fixed set of nodes).
  subroutine check_following(scn, st, ks, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(in) :: ks
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (scn%multipliers /= SOLVER_AUTO .and. scn%multipliers /= SOLVER_SCHUR) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'the pairing follows the configuration (PAIRING STEP, ' // &
        'the default with KINEMATICS LARGE) and the rows change at every step: SCHEME MULTIPLIERS AUGMENTED cannot ' // &
        'take them (use SCHUR or AUTO)', st%params(ks)%keytok))
    else if (scn%impact == IMPACT_MASSLESS .or. scn%impact == IMPACT_SYMMETRIC) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'the pairing follows the configuration (PAIRING STEP, ' // &
        'the default with KINEMATICS LARGE): SCHEME IMPACT ' // trim(IMPACT_NAMES(scn%impact)) // ' (which treats the ' // &
        'mass of a fixed set of contact nodes) cannot take it (use PERSIST, PAPER or AUTO)', st%params(ks)%keytok))
    end if
    scn%multipliers = SOLVER_SCHUR
  end subroutine check_following

  !> GAP NODES ga WITH gb pairs nodes one to one, which is right only for matching meshes
  !> (GAP … SEGMENTS is the node-to-segment contact): refused when a node of gb is the nearest to two
  !> nodes of ga (ga the finer side), or when a node of gb left unpaired lies on the contact
  !> surface between paired ones (gb the finer side: it would go through ga's edges). The surface
  !> is the band the paired nodes of gb span along the tangent of the normal (NORMAL, or the mean
  !> direction from a to b; not checked when the pairs point every way).
  subroutine check_matching(scn, st, tok, pa, pb, nb, given, ngiven, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    type(token_t), intent(in) :: tok
    integer, intent(in) :: pa(:), pb(:), nb(:)
    logical, intent(in) :: given
    real(dp), intent(in) :: ngiven(:)            !< (ndim)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=*), parameter :: hint = ': GAP NODES … WITH pairs the nodes of matching meshes ' // &
      '(non-matching meshes: GAP NODES ga SEGMENTS gb; PAIRS lists pairs explicitly)'
    real(dp) :: n(scn%mesh%ndim), t(scn%mesh%ndim, 2), tol, smin(2), smax(2), qmin, qmax, s(2), q, d
    integer :: i, j, k, nt
    logical :: inside
    stat = STAT_OK
    do i = 2, size(pb)
      do j = 1, i - 1
        if (pb(j) == pb(i)) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'non-matching meshes: node ' // str(pb(i)) // &
            ' is the nearest to nodes ' // str(pa(j)) // ' and ' // str(pa(i)) // hint, tok))
          return
        end if
      end do
    end do
    if (given) then
      n = ngiven
    else
      n = 0.0_dp
      do i = 1, size(pa)                         ! (coincident pairs are reported by the caller)
        d = norm2(scn%mesh%x(:, pb(i)) - scn%mesh%x(:, pa(i)))
        if (d > 0.0_dp) n = n + (scn%mesh%x(:, pb(i)) - scn%mesh%x(:, pa(i))) / d
      end do
      n = n / size(pa)
      if (norm2(n) < 0.5_dp) return
      n = n / norm2(n)
    end if
    ! The tangents of the normal: in 2D n turned by +90°, in 3D two orthonormal ones.
    nt = scn%mesh%ndim - 1
    if (nt == 1) then
      t(:, 1) = [-n(2), n(1)]
    else
      k = minloc(abs(n), 1)                      ! the axis least along n
      t(:, 1) = 0.0_dp
      t(k, 1) = 1.0_dp
      t(:, 1) = t(:, 1) - dot_product(t(:, 1), n) * n
      t(:, 1) = t(:, 1) / norm2(t(:, 1))
      t(:, 2) = [n(2) * t(3, 1) - n(3) * t(2, 1), n(3) * t(1, 1) - n(1) * t(3, 1), n(1) * t(2, 1) - n(2) * t(1, 1)]
    end if
    tol = 1.0e-6_dp * model_size(scn%mesh)
    do k = 1, nt
      smin(k) = minval([(dot_product(t(:, k), scn%mesh%x(:, pb(i))), i = 1, size(pb))])
      smax(k) = maxval([(dot_product(t(:, k), scn%mesh%x(:, pb(i))), i = 1, size(pb))])
    end do
    qmin = minval([(dot_product(n, scn%mesh%x(:, pb(i))), i = 1, size(pb))])
    qmax = maxval([(dot_product(n, scn%mesh%x(:, pb(i))), i = 1, size(pb))])
    do j = 1, size(nb)
      if (any(pb == nb(j)) .or. any(pa == nb(j))) cycle
      inside = .true.
      do k = 1, nt
        s(k) = dot_product(t(:, k), scn%mesh%x(:, nb(j)))
        inside = inside .and. s(k) > smin(k) + tol .and. s(k) < smax(k) - tol
      end do
      q = dot_product(n, scn%mesh%x(:, nb(j)))
      if (inside .and. q > qmin - tol .and. q < qmax + tol) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'non-matching meshes: node ' // str(nb(j)) // &
          ' lies between paired nodes and faces none' // hint, tok))
        return
      end if
    end do
  end subroutine check_matching

  !> SCHEME IMPACT after every statement is read: AUTO becomes MASSLESS (consistent mass) or
  !> SYMMETRIC (MIXED, TUNED, LUMPED) when every contact node can give its mass away (none of its
  !> elements with mass has contact nodes only: not a point mass, not a body touching with all its
  !> nodes) and every impact is elastic, PERSIST on MASS TUNED at c h/dx = 1 and otherwise
  !> (docs/contact.md, "The default"). MASSLESS has no velocity at the contact nodes to apply
  !> Newton's law to: RESTITUTION e < 1 with IMPACT MASSLESS is refused, naming the statement.
  subroutine resolve_impact(scn, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical, allocatable :: contact(:)
    integer, allocatable :: nodes(:)
    integer :: i, j, im
    character(len=:), allocatable :: why
    logical, allocatable :: nonlinear(:)
    stat = STAT_OK
    if (scn%impact == IMPACT_MASSLESS .or. scn%impact == IMPACT_SYMMETRIC) then
      why = "IMPACT MASSLESS leaves no velocity at the contact nodes for Newton's law"
      if (scn%impact == IMPACT_SYMMETRIC) why = 'IMPACT SYMMETRIC gives back at the release all it held'
      j = findloc(scn%conditions%restitution < 1.0_dp, .true., 1)
      if (j > 0) then
        call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(scn%conditions(j)%line) // ': ' // &
          condition_keyword(scn%conditions(j)) // ' ' // scn%conditions(j)%source // &
          ': RESTITUTION < 1 needs IMPACT PERSIST or PAPER (' // why // "), at 'RESTITUTION'")
        return
      end if
    end if
    j = findloc(scn%conditions%friction > 0.0_dp, .true., 1)
    if (j > 0 .and. scn%impact == IMPACT_MASSLESS) then
      call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(scn%conditions(j)%line) // ': ' // &
        condition_keyword(scn%conditions(j)) // ' ' // scn%conditions(j)%source // ': FRICTION needs IMPACT ' // &
        "PERSIST, PAPER or SYMMETRIC (MASSLESS's contact nodes carry no inertia for the friction to act on), at 'FRICTION'")
      return
    end if
    ! SCHEME EVENTS AUTO locates contact events where every contact node's element is on the exact
    ! lattice (MASS TUNED at c h/dx = 1): an impact on a step's end is that scheme's exact case
    ! (docs/contact.md, "Contact events located"), and under TIME … ADAPTIVE (whose error estimate
    ! does not judge a step that changes the contact set); LOCATE everywhere.
    call contact_nodes(scn, contact)
    nodes = pack([(i, i = 1, size(contact))], contact)
    scn%locate_events = size(scn%conditions) > 0 .and. (scn%events == 2 .or. (scn%events == 1 .and. (scn%adaptive &
      .or. (size(nodes) > 0 .and. .not. on_models(scn, nodes, .not. scn%models%tuned_exact)))))
    ! A nonlinear law at a contact node's element: MASSLESS's massless rows hold the law's correction
    ! force of eq (9), Bσc, at n+1 where the other rows carry it over the step, and the momentum the
    ! body keeps differs by h/2 Σ Bσc there (a plastic block's corner impact: tangential momentum
    ! off by 8.5e-4 of it). AUTO takes PERSIST there; MASSLESS is refused.
    nonlinear = [(scn%models(im)%material > 0, im = 1, size(scn%models))]
    do im = 1, size(scn%models)
      if (nonlinear(im)) nonlinear(im) = .not. law_is_linear(scn%materials(scn%models(im)%material))
    end do
    if (scn%impact == IMPACT_MASSLESS .and. size(nodes) > 0) then
      if (on_models(scn, nodes, nonlinear)) then
        im = findloc(nonlinear, .true., 1)
        call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(scn%models(im)%line) // ': MODEL ' // &
          scn%models(im)%group // ': IMPACT MASSLESS on a contact node of a nonlinear law (' // &
          law_name(scn%materials(scn%models(im)%material)%law) // "): its correction force at the massless " // &
          "nodes would change the body's momentum; IMPACT PERSIST, PAPER or SYMMETRIC, at '" // scn%models(im)%group // "'")
        return
      end if
    end if
    if (scn%impact /= IMPACT_AUTO) return
    scn%impact_auto = .true.
    if (size(scn%conditions) == 0) then
      scn%impact = IMPACT_PAPER                   ! (no contact: the choice changes nothing)
      return
    end if
    scn%impact = IMPACT_PERSIST
    if (all(scn%conditions%restitution >= 1.0_dp) .and. .not. any(scn%conditions%follow) .and. j == 0) then
      ! No contact node on a KINEMATICS LARGE model: MASSLESS books what a massless node's row leaves
      ! in the step's energy as its snap to equilibrium, f²/(2k) >= 0 for a linear element; on LARGE
      ! elements it came out negative (energy created: the ring of inputs/ring_impact.dat gained 10 %
      ! of its energy at h = T/30, 4e-4 at T/100).
      if (contact_mass_movable(scn, contact) .and. .not. on_models(scn, nodes, scn%models%large)) then
        ! With a consistent mass MASSLESS rebounds best; with MIXED (or LUMPED) SYMMETRIC, whose
        ! rebound then converges with the mesh (docs/contact.md, "IMPACT SYMMETRIC").
        scn%impact = IMPACT_MASSLESS
        if (.not. on_models(scn, nodes, .not. (scn%models%lumped .or. scn%models%mixed))) scn%impact = IMPACT_SYMMETRIC
        ! MASS TUNED at c h/dx = 1 on every contact node's element: the lattice is exact and PERSIST,
        ! which keeps the contact nodes' mass as it is, keeps it so (docs/contact.md, "A mass tuned to
        ! the step"); SYMMETRIC's lumped rows and MASSLESS's moved mass would not.
        if (.not. on_models(scn, nodes, .not. scn%models%tuned_exact)) scn%impact = IMPACT_PERSIST
        if (scn%impact == IMPACT_MASSLESS .and. on_models(scn, nodes, nonlinear)) scn%impact = IMPACT_PERSIST
        ! GAP … FACES: every node of a face is a contact node, and MASSLESS may leave a quadratic
        ! solid's layer under the face without mass (a HEX20 or TET10 slab one element thick).
        if (scn%impact == IMPACT_MASSLESS .and. any(scn%conditions%face(1) > 0)) scn%impact = IMPACT_PERSIST
      end if
    end if
  end subroutine resolve_impact

  !> Whether every contact node (contact(node)) can give its translational mass to a neighbour: no
  !> element that carries mass has contact nodes only (assembly's move_contact_mass would leave it
  !> there).
  logical function contact_mass_movable(scn, contact) result(ok)
    type(scene_t), intent(in) :: scn
    logical, intent(in) :: contact(:)
    integer :: e, im
    logical :: massive
    ok = .true.
    do e = 1, scn%mesh%nelem
      im = scn%elem_model(e)
      if (im == 0) cycle
      associate (md => scn%models(im))
        massive = md%etype == ET_MASS
        if (md%etype /= ET_SPRING .and. md%material > 0) massive = scn%materials(md%material)%density > 0.0_dp
      end associate
      if (massive .and. all(contact(scn%mesh%conn(1:scn%mesh%nen(e), e)))) then
        ok = .false.
        return
      end if
    end do
  end function contact_mass_movable
end module scene_contacts
