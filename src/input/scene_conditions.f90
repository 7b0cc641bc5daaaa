!> Scene input: supports, initial state and loads (FIX, INITIAL, GRAVITY, LOAD, PRESSURE, TRACTION).
!> Their grammar (schema) and their handlers; scene_loader calls them.
module scene_conditions
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, upper, str
  use statement, only: statement_t, stmt_error, find_param, get_real, get_word, to_real
  use statement_schema, only: schema_t
  use scene, only: scene_t, fix_t, initial_t, load_t, impose_t, INIT_DISPLACEMENT, INIT_VELOCITY, INIT_STATIC, LOAD_PRESSURE, &
    LOAD_TRACTION, INIT_ANGULAR, SPIN_LINE
  use mesh_segments, only: side_set_t, group_sides
  use mesh_faces, only: face_set_t, group_faces
  use scene_helpers, only: node_group, check_modelled, get_point, get_function, get_pair, check_count
  use mesh, only: MAX_COORD, NODE_DOFS, DOF_UX, DOF_UY, DOF_RZ, DOF_UZ, DOF_NAMES
  implicit none
  private
  public :: conditions_schema, conditions_statement, loads_modelled

contains

  subroutine conditions_schema(sch)
    type(schema_t), intent(inout) :: sch
    call sch%add_keyword('FIX', 1, 1)
    call sch%add_param('FIX', 'UX', 0, 0)
    call sch%add_param('FIX', 'UY', 0, 0)
    call sch%add_param('FIX', 'RZ', 0, 0)
    call sch%add_param('FIX', 'UZ', 0, 0)
    call sch%add_param('FIX', 'ALL', 0, 0)
    call sch%add_keyword('INITIAL', 1, 1)
    call sch%add_param('INITIAL', 'DISPLACEMENT', 2, 3)
    call sch%add_param('INITIAL', 'VELOCITY', 2, 3)
    call sch%add_param('INITIAL', 'STATIC', 0, 0)
    call sch%add_param('INITIAL', 'FORCE', 2, 3)
    call sch%add_param('INITIAL', 'FUNCTION', 1, 1)
    call sch%add_param('INITIAL', 'ALONG', 1, 1)
    call sch%add_param('INITIAL', 'ANGULAR_VELOCITY', 1, 3)
    call sch%add_param('INITIAL', 'ABOUT', 2, 3)
    call sch%add_keyword('GRAVITY', 0, 0, once=.true.)
    call sch%add_param('GRAVITY', 'GX', 1, 1)
    call sch%add_param('GRAVITY', 'GY', 1, 1)
    call sch%add_param('GRAVITY', 'GZ', 1, 1)
    call sch%add_param('GRAVITY', 'FUNCTION', 1, 1)
    call sch%add_keyword('LOAD', 1, 1)
    call sch%add_param('LOAD', 'NODES', 1, 1)
    call sch%add_param('LOAD', 'FORCE', 2, 3)
    call sch%add_param('LOAD', 'FUNCTION', 1, 1)
    call sch%add_keyword('IMPOSE', 1, 1)
    call sch%add_param('IMPOSE', 'UX', 0, 0)
    call sch%add_param('IMPOSE', 'UY', 0, 0)
    call sch%add_param('IMPOSE', 'RZ', 0, 0)
    call sch%add_param('IMPOSE', 'UZ', 0, 0)
    call sch%add_param('IMPOSE', 'VALUE', 1, 1)
    call sch%add_param('IMPOSE', 'FUNCTION', 1, 1)
    call sch%add_keyword('PRESSURE', 1, 1)
    call sch%add_param('PRESSURE', 'VALUE', 1, 1)
    call sch%add_param('PRESSURE', 'FUNCTION', 1, 1)
    call sch%add_param('PRESSURE', 'DEAD', 0, 0)
    call sch%add_keyword('TRACTION', 1, 1)
    call sch%add_param('TRACTION', 'VALUE', 2, 3)
    call sch%add_param('TRACTION', 'FUNCTION', 1, 1)
  end subroutine conditions_schema

  !> One conditions statement (pass 2 of load_scene).
  subroutine conditions_statement(scn, st, path, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    select case (st%keyword)
    case ('FIX')
      call do_fix(scn, st, stat, errmsg)
    case ('INITIAL')
      call do_initial(scn, st, stat, errmsg)
    case ('GRAVITY')
      call do_gravity(scn, st, stat, errmsg)
    case ('LOAD')
      call do_load(scn, st, stat, errmsg)
    case ('IMPOSE')
      call do_impose(scn, st, stat, errmsg)
    case ('PRESSURE', 'TRACTION')
      call do_side_load(scn, st, stat, errmsg)
    end select
  end subroutine conditions_statement

  !> LOAD, PRESSURE and TRACTION act on nodes that carry a modelled element (check_modelled; pass
  !> 3 of load_scene, once every MODEL is read).
  subroutine loads_modelled(scn, st, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: ig, k
    stat = STAT_OK
    select case (st%keyword)
    case ('LOAD')
      k = find_param(st, 'NODES')
      call node_group(scn, st, st%params(k)%values(1), ig, stat, errmsg)
      if (stat == STAT_OK) call check_modelled(scn, st, st%params(k)%values(1), scn%mesh%ngroups(ig)%items, stat, errmsg)
    case ('PRESSURE', 'TRACTION')
      call node_group(scn, st, st%lead(1), ig, stat, errmsg)
      if (stat == STAT_OK) call check_modelled(scn, st, st%lead(1), scn%mesh%ngroups(ig)%items, stat, errmsg)
      if (stat /= STAT_OK .or. st%keyword /= 'PRESSURE' .or. find_param(st, 'DEAD') > 0) return
      ! A follower pressure on a ring (2π r at the current radius) has the potential p V, which the
      ! trapezoid's booking of its work does not keep exactly: not offered.
      if (any(scn%models%large .and. scn%models%sec%axisymmetric)) call set_error(stat, errmsg, STAT_INPUT, &
        stmt_error(st, 'a PRESSURE that follows the sides of an axisymmetric KINEMATICS LARGE model is not ' // &
        'available: say DEAD (the pressure then keeps its reference direction and ring)', st%lead(1)))
      if (scn%mesh%ndim == 3 .and. any(scn%models%large)) call set_error(stat, errmsg, STAT_INPUT, &
        stmt_error(st, 'a PRESSURE that follows the faces of a 3D KINEMATICS LARGE model is not available yet: ' // &
        'say DEAD (the pressure then keeps its reference direction and area)', st%lead(1)))
    end select
  end subroutine loads_modelled

  subroutine do_fix(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(fix_t) :: fx
    call node_group(scn, st, st%lead(1), fx%ngroup, stat, errmsg)
    if (stat /= STAT_OK) return
    call dof_words(scn, st, fx%dofs, stat, errmsg)
    if (stat /= STAT_OK) return
    if (find_param(st, 'ALL') > 0) fx%dofs = .true.
    if (.not. any(fx%dofs)) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'no DOF to fix (expected ' // &
        trim(merge('UX, UY, UZ', 'UX, UY, RZ', scn%mesh%ndim == 3)) // ' or ALL)', st%lead(1)))
      return
    end if
    fx%line = st%line
    scn%fixes = [scn%fixes, fx]
  end subroutine do_fix

  !> The DOF words of a FIX or IMPOSE (UX UY RZ in 2D, UX UY UZ in 3D) as DOF slots; a word of the
  !> other dimension is an error naming it.
  subroutine dof_words(scn, st, flags, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    logical, intent(out) :: flags(NODE_DOFS)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    flags = .false.
    flags(DOF_UX) = find_param(st, 'UX') > 0
    flags(DOF_UY) = find_param(st, 'UY') > 0
    flags(DOF_RZ) = find_param(st, 'RZ') > 0
    flags(DOF_UZ) = find_param(st, 'UZ') > 0
    if (scn%mesh%ndim == 3 .and. flags(DOF_RZ)) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'RZ is a DOF of planar beams; a DIMENSION 3 scene has ' // &
        'UX, UY, UZ', st%params(find_param(st, 'RZ'))%keytok))
    else if (scn%mesh%ndim == 2 .and. flags(DOF_UZ)) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'UZ needs DIMENSION 3', st%params(find_param(st, 'UZ'))%keytok))
    end if
  end subroutine dof_words

  !> The DOF slot of the i-th number of a vector parameter: x, y, then the rotation RZ in 2D or z in 3D.
  pure integer function vector_slot(ndim, i)
    integer, intent(in) :: ndim, i
    integer, parameter :: slots(3, 2:3) = reshape([DOF_UX, DOF_UY, DOF_RZ, DOF_UX, DOF_UY, DOF_UZ], [3, 2])
    vector_slot = slots(i, ndim)
  end function vector_slot

  !> Values of a parameter with 2 or 3 numbers (x, y[, rotation] in 2D, x, y[, z] in 3D) into their
  !> DOF slots (vector_slot), each within ±MAX_COORD (1e100: their squares, the energies, stay finite).
  !> In 3D a vector takes its three numbers (another count is an error) unless scalar_ok (PRESSURE's
  !> VALUE p).
  subroutine get_vector(scn, st, key, v, mask, stat, errmsg, scalar_ok)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    real(dp), intent(out) :: v(NODE_DOFS)
    logical, intent(out) :: mask(NODE_DOFS)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical, intent(in), optional :: scalar_ok
    integer :: k, i, j
    logical :: whole
    v = 0.0_dp
    mask = .false.
    k = find_param(st, key)
    whole = scn%mesh%ndim == 3                 ! (3D: x y z; in 2D a third value is rz)
    if (present(scalar_ok)) whole = whole .and. .not. scalar_ok
    if (whole) then
      call check_count(st, key, 3, stat, errmsg)
      if (stat /= STAT_OK) return
    end if
    do i = 1, size(st%params(k)%values)
      j = vector_slot(scn%mesh%ndim, i)
      call to_real(st%params(k)%values(i), st, v(j), stat, errmsg)
      if (stat /= STAT_OK) return
      if (abs(v(j)) > MAX_COORD) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, key // ' values must be within ±1e100', &
          st%params(k)%values(i)))
        return
      end if
      mask(j) = .true.
    end do
    stat = STAT_OK
  end subroutine get_vector

  subroutine do_initial(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(initial_t) :: ic
    integer :: nkind
    call node_group(scn, st, st%lead(1), ic%ngroup, stat, errmsg)
    if (stat /= STAT_OK) return
    ic%line = st%line
    nkind = count([find_param(st, 'DISPLACEMENT') > 0, find_param(st, 'VELOCITY') > 0, find_param(st, 'STATIC') > 0, &
      find_param(st, 'ANGULAR_VELOCITY') > 0])
    if (nkind /= 1) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'give exactly one of DISPLACEMENT, VELOCITY, ' // &
        'ANGULAR_VELOCITY or STATIC FORCE', st%lead(1)))
      return
    end if
    if (find_param(st, 'ABOUT') > 0 .and. find_param(st, 'ANGULAR_VELOCITY') == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'ABOUT goes with ANGULAR_VELOCITY', &
        st%params(find_param(st, 'ABOUT'))%keytok))
      return
    end if
    if (find_param(st, 'ANGULAR_VELOCITY') > 0) then
      call do_initial_spin(scn, st, ic, stat, errmsg)
      return
    end if
    if (find_param(st, 'DISPLACEMENT') > 0) then
      ic%kind = INIT_DISPLACEMENT
      call get_vector(scn, st, 'DISPLACEMENT', ic%values, ic%mask, stat, errmsg)
    else if (find_param(st, 'VELOCITY') > 0) then
      ic%kind = INIT_VELOCITY
      call get_vector(scn, st, 'VELOCITY', ic%values, ic%mask, stat, errmsg)
    else
      ic%kind = INIT_STATIC
      if (find_param(st, 'FORCE') == 0) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'STATIC needs FORCE ' // &
          trim(merge('fx fy fz  ', 'fx fy [mz]', scn%mesh%ndim == 3)), st%params(find_param(st, 'STATIC'))%keytok))
        return
      end if
      call get_vector(scn, st, 'FORCE', ic%values, ic%mask, stat, errmsg)
    end if
    if (stat /= STAT_OK) return
    if (ic%kind /= INIT_STATIC .and. find_param(st, 'FORCE') > 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'FORCE goes with STATIC only', &
        st%params(find_param(st, 'FORCE'))%keytok))
      return
    end if
    call initial_profile(scn, st, ic, stat, errmsg)
    if (stat /= STAT_OK) return
    call initial_once(scn, st, ic, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%initials = [scn%initials, ic]
  end subroutine do_initial

  !> INITIAL group ANGULAR_VELOCITY w ABOUT x y: the rigid spin ω × (X - x0) added to the velocity
  !> of every node of the group (and w to the rotation rate of beams), on top of a VELOCITY given
  !> to the same nodes: the one pair of INITIALs on a node that is not an error. Two spins on a node
  !> are.
  subroutine do_initial_spin(scn, st, ic, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    type(initial_t), intent(inout) :: ic
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: i, n, nd
    ic%kind = INIT_ANGULAR
    nd = scn%mesh%ndim
    if (scn%mesh%ndim == 3) then                 ! ω = (wx, wy, wz) about the point x y z
      call get_pair(st, 'ANGULAR_VELOCITY', ic%omega, stat, errmsg)
      if (stat /= STAT_OK) return
      if (any(abs(ic%omega) > MAX_COORD)) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'ANGULAR_VELOCITY values must be within ±1e100', &
          st%params(find_param(st, 'ANGULAR_VELOCITY'))%keytok))
        return
      end if
    else
      call get_real(st, 'ANGULAR_VELOCITY', ic%values(3), stat, errmsg, lower=-MAX_COORD, lower_inclusive=.true., &
        upper=MAX_COORD, upper_inclusive=.true.)
    end if
    if (stat /= STAT_OK) return
    if (find_param(st, 'ABOUT') == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'ANGULAR_VELOCITY needs ABOUT x y (3D: x y z), the ' // &
        'axis', st%params(find_param(st, 'ANGULAR_VELOCITY'))%keytok))
      return
    end if
    call get_point(st, 'ABOUT', ic%about(1:nd), stat, errmsg)
    if (stat /= STAT_OK) return
    if (find_param(st, 'FUNCTION') > 0 .or. find_param(st, 'FORCE') > 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'ANGULAR_VELOCITY takes no FUNCTION or FORCE', &
        st%params(max(find_param(st, 'FUNCTION'), find_param(st, 'FORCE')))%keytok))
      return
    end if
    ic%mask = .true.
    if (.not. allocated(scn%initial_line)) then
      allocate (scn%initial_line(SPIN_LINE, scn%mesh%nnode))
      scn%initial_line = 0
    end if
    associate (nodes => scn%mesh%ngroups(ic%ngroup)%items)
      do i = 1, size(nodes)
        n = nodes(i)
        if (scn%initial_line(SPIN_LINE, n) /= 0) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'node ' // str(scn%mesh%node_tag(n)) // &
            ' already spins by INITIAL at line ' // str(scn%initial_line(SPIN_LINE, n)) // ' (one ANGULAR_VELOCITY per node)', &
            st%lead(1)))
          return
        end if
        scn%initial_line(SPIN_LINE, n) = st%line
      end do
    end associate
    scn%initials = [scn%initials, ic]
  end subroutine do_initial_spin

  !> Each component of a node's initial displacement or velocity is set by one INITIAL at most: a
  !> second would replace or add to the first without a word. A component counts as set when its
  !> value is not zero (a zero stands for "nothing here": VELOCITY 0 0 w gives a spin alone, which
  !> another INITIAL may give a profile of vx, vy); the INITIALs of a node add up (assembly's
  !> initial_state). The error names the node, the component and the line of the first.
  subroutine initial_once(scn, st, ic, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    type(initial_t), intent(in) :: ic
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=2), parameter :: comp(2 * NODE_DOFS) = ['ux', 'uy', 'rz', 'uz', 'vx', 'vy', 'wz', 'vz']
    integer :: k0, i, n, d
    stat = STAT_OK
    if (ic%kind == INIT_DISPLACEMENT) then
      k0 = 0
    else if (ic%kind == INIT_VELOCITY) then
      k0 = NODE_DOFS
    else
      return
    end if
    if (.not. allocated(scn%initial_line)) then
      allocate (scn%initial_line(SPIN_LINE, scn%mesh%nnode))   ! (SPIN_LINE: ANGULAR_VELOCITY, do_initial_spin)
      scn%initial_line = 0
    end if
    associate (nodes => scn%mesh%ngroups(ic%ngroup)%items)
      do i = 1, size(nodes)
        n = nodes(i)
        do d = 1, NODE_DOFS
          if (.not. ic%mask(d) .or. ic%values(d) == 0.0_dp) cycle
          if (scn%initial_line(k0 + d, n) /= 0) then
            call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, trim(merge('DISPLACEMENT', 'VELOCITY    ', k0 == 0)) // &
              ' ' // comp(k0 + d) // ' of node ' // str(scn%mesh%node_tag(n)) // ' already given by INITIAL at line ' // &
              str(scn%initial_line(k0 + d, n)) // ' (one INITIAL per component of a node; a zero leaves it free)', &
              st%lead(1)))
            return
          end if
          scn%initial_line(k0 + d, n) = st%line
        end do
      end do
    end associate
  end subroutine initial_once

  !> FUNCTION f ALONG X|Y|Z (default X; Z in 3D): the values vary with position, times f of the node's
  !> x (or y, z), f a FUNCTION's piecewise-linear table read as a function of the coordinate.
  subroutine initial_profile(scn, st, ic, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    type(initial_t), intent(inout) :: ic
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: w
    call get_function(scn, st, ic%func, stat, errmsg)
    if (stat /= STAT_OK) return
    if (ic%func > 0 .and. ic%kind == INIT_STATIC) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'FUNCTION goes with DISPLACEMENT or VELOCITY', &
        st%params(find_param(st, 'FUNCTION'))%keytok))
      return
    end if
    if (find_param(st, 'ALONG') == 0) return
    if (ic%func == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'ALONG goes with FUNCTION', &
        st%params(find_param(st, 'ALONG'))%keytok))
      return
    end if
    call get_word(st, 'ALONG', w, stat, errmsg)
    if (stat /= STAT_OK) return
    select case (upper(w))
    case ('X')
      ic%along = 1
    case ('Y')
      ic%along = 2
    case ('Z')
      ic%along = 3
      if (scn%mesh%ndim /= 3) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'ALONG Z needs DIMENSION 3', &
        st%params(find_param(st, 'ALONG'))%values(1)))
    case default
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected X, Y or Z', &
        st%params(find_param(st, 'ALONG'))%values(1)))
    end select
  end subroutine initial_profile

  subroutine do_gravity(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call get_real(st, 'GX', scn%gravity(1), stat, errmsg, default=0.0_dp, lower=-MAX_COORD, lower_inclusive=.true., &
      upper=MAX_COORD, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_real(st, 'GY', scn%gravity(2), stat, errmsg, default=0.0_dp, lower=-MAX_COORD, lower_inclusive=.true., &
      upper=MAX_COORD, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    if (find_param(st, 'GZ') > 0 .and. scn%mesh%ndim /= 3) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'GZ needs DIMENSION 3', st%params(find_param(st, 'GZ'))%keytok))
      return
    end if
    call get_real(st, 'GZ', scn%gravity(3), stat, errmsg, default=0.0_dp, lower=-MAX_COORD, lower_inclusive=.true., &
      upper=MAX_COORD, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_function(scn, st, scn%gravity_func, stat, errmsg)
  end subroutine do_gravity

  subroutine do_load(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(load_t) :: ld
    logical :: mask(NODE_DOFS)
    integer :: k
    ld%name = st%lead(1)%text
    k = find_param(st, 'NODES')
    if (k == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'missing parameter NODES', st%lead(1)))
      return
    end if
    call node_group(scn, st, st%params(k)%values(1), ld%ngroup, stat, errmsg)
    if (stat /= STAT_OK) return
    if (find_param(st, 'FORCE') == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'missing parameter FORCE', st%lead(1)))
      return
    end if
    call get_vector(scn, st, 'FORCE', ld%force, mask, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_function(scn, st, ld%func, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%loads = [scn%loads, ld]
  end subroutine do_load

  !> PRESSURE group VALUE p [FUNCTION f] [DEAD] | TRACTION group VALUE tx ty [FUNCTION f]: a load on the
  !> free element sides of a node group (src/assembly/loads.f90); a group that is not a set of
  !> sides (a node on none of them) is refused, naming the node.
  subroutine do_side_load(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(load_t) :: ld
    type(side_set_t) :: sides
    type(face_set_t) :: faces
    logical :: mask(NODE_DOFS)
    real(dp) :: v(NODE_DOFS)
    ld%name = st%lead(1)%text
    call node_group(scn, st, st%lead(1), ld%ngroup, stat, errmsg)
    if (stat /= STAT_OK) return
    if (scn%mesh%ndim == 3) then
      call group_faces(scn%mesh, scn%mesh%ngroups(ld%ngroup)%items, faces, stat, errmsg)
      if (stat /= STAT_OK) errmsg = stmt_error(st, errmsg // ' (' // st%keyword // ' acts on the faces of solids)', &
        st%lead(1))
    else
      call group_sides(scn%mesh, scn%mesh%ngroups(ld%ngroup)%items, sides, stat, errmsg)
      if (stat /= STAT_OK) errmsg = stmt_error(st, errmsg // ' (' // st%keyword // ' acts on the sides of surface ' // &
        'elements)', st%lead(1))
    end if
    if (stat /= STAT_OK) return
    ld%kind = LOAD_PRESSURE
    if (st%keyword == 'TRACTION') ld%kind = LOAD_TRACTION
    ld%dead = find_param(st, 'DEAD') > 0                  ! (a PRESSURE on a SMALL model is dead anyway)
    if (find_param(st, 'VALUE') == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'missing parameter VALUE', st%lead(1)))
      return
    end if
    if (st%keyword == 'TRACTION') then
      call check_count(st, 'VALUE', scn%mesh%ndim, stat, errmsg)
      if (stat /= STAT_OK) return
    end if
    call get_vector(scn, st, 'VALUE', v, mask, stat, errmsg, scalar_ok=.true.)   ! (p, or tx ty [tz]: UX UY [UZ])
    if (stat /= STAT_OK) return
    ld%force(1:3) = [v(DOF_UX), v(DOF_UY), v(DOF_UZ)]
    call get_function(scn, st, ld%func, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%loads = [scn%loads, ld]
  end subroutine do_side_load

  !> IMPOSE group UX|UY|RZ [VALUE a] FUNCTION f: the displacement a f(t) on that DOF of every
  !> node of the group (one DOF per statement). Held exactly by a multiplier (docs/input.md).
  subroutine do_impose(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(impose_t) :: im
    logical :: flags(NODE_DOFS)
    call node_group(scn, st, st%lead(1), im%ngroup, stat, errmsg)
    if (stat /= STAT_OK) return
    call dof_words(scn, st, flags, stat, errmsg)
    if (stat /= STAT_OK) return
    if (count(flags) /= 1) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'give one DOF: ' // &
        trim(merge('UX, UY or UZ', 'UX, UY or RZ', scn%mesh%ndim == 3)), st%lead(1)))
      return
    end if
    im%dof = findloc(flags, .true., 1)
    call get_real(st, 'VALUE', im%value, stat, errmsg, default=1.0_dp, lower=-MAX_COORD, lower_inclusive=.true., &
      upper=MAX_COORD, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    if (find_param(st, 'FUNCTION') == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'missing parameter FUNCTION (the displacement ' // &
        'history)', st%lead(1)))
      return
    end if
    call get_function(scn, st, im%func, stat, errmsg)
    if (stat /= STAT_OK) return
    im%line = st%line
    call impose_once(scn, st, im, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%imposes = [scn%imposes, im]
  end subroutine do_impose

  !> A DOF is imposed by one IMPOSE at most: two would be two equalities on one DOF, dependent (or
  !> contradictory) rows of the step's multipliers. The error names the node and the first line.
  subroutine impose_once(scn, st, im, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    type(impose_t), intent(in) :: im
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical, allocatable :: held(:)
    integer :: k, i
    stat = STAT_OK
    allocate (held(scn%mesh%nnode))
    do k = 1, size(scn%imposes)
      if (scn%imposes(k)%dof /= im%dof) cycle
      held = .false.
      held(scn%mesh%ngroups(scn%imposes(k)%ngroup)%items) = .true.
      associate (b => scn%mesh%ngroups(im%ngroup)%items)
        do i = 1, size(b)
          if (.not. held(b(i))) cycle
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, DOF_NAMES(im%dof) // ' of node ' // &
            str(scn%mesh%node_tag(b(i))) // ' already imposed by IMPOSE at line ' // str(scn%imposes(k)%line) // &
            ' (one IMPOSE per DOF)', st%lead(1)))
          return
        end do
      end associate
    end do
  end subroutine impose_once
end module scene_conditions
