!> Loading a scene: the grammar of the scene file (each statement family adds its keywords)
!> and the two passes that build scene_t from the statements, after the --set overrides.
!> Statements are interpreted in two passes so that the order of definitions and their uses
!> does not matter, except inside the mesh (a GROUP or ELEMENT refers to groups defined above it).
module scene_loader
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use statement, only: statement_t
  use statement_schema, only: schema_t
  use scene_parser, only: parse_file, apply_override, check_required
  use scene, only: scene_t, INIT_STATIC, INIT_ANGULAR, scene_axisymmetric
  use kinds, only: dp
  use material_law, only: LAW_HYPERELASTIC
  use scene_mesh, only: mesh_schema, mesh_statement
  use scene_materials, only: materials_schema, materials_statement
  use scene_models, only: models_schema, models_statement, default_mass, check_tuned
  use scene_conditions, only: conditions_schema, conditions_statement, loads_modelled
  use scene_contacts, only: contacts_schema, contacts_statement, resolve_impact
  use scene_run, only: run_schema, run_statement
  use scene_fingerprint, only: fingerprint_text
  implicit none
  private
  public :: load_scene, scene_schema

contains

  !> The grammar of a scene file: keywords, their leading tokens and parameters.
  subroutine scene_schema(sch)
    type(schema_t), intent(out) :: sch
    call sch%add_keyword('TITLE', 1, 1, once=.true.)
    call mesh_schema(sch)
    call materials_schema(sch)
    call models_schema(sch)
    call conditions_schema(sch)
    call contacts_schema(sch)
    call run_schema(sch)
  end subroutine scene_schema

  !> Parse the scene file, apply the --set overrides, and build the scene.
  subroutine load_scene(path, overrides, scn, stat, errmsg)
    character(len=*), intent(in) :: path
    character(len=*), intent(in) :: overrides(:)
    type(scene_t), intent(out) :: scn
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(schema_t) :: sch
    type(statement_t), allocatable :: st(:)
    integer :: i, nn0

    call scene_schema(sch)
    call parse_file(path, sch, st, stat, errmsg)
    if (stat /= STAT_OK) return
    do i = 1, size(overrides)
      call apply_override(st, sch, trim(overrides(i)), stat, errmsg)
      if (stat /= STAT_OK) return
    end do
    scn%path = path
    scn%title = ''
    allocate (scn%materials(0), scn%sections(0), scn%models(0), scn%fixes(0), scn%initials(0), &
      scn%functions(0), scn%loads(0), scn%imposes(0), scn%probes(0), scn%conditions(0), scn%segsets(0))
    ! Pass 1: mesh and definitions, in file order.
    allocate (scn%node_line(64))
    do i = 1, size(st)
      nn0 = scn%mesh%nnode
      if (st(i)%keyword == 'TITLE') scn%title = st(i)%lead(1)%text
      call mesh_statement(scn, st(i), path, stat, errmsg)
      if (stat == STAT_OK) call materials_statement(scn, st(i), path, stat, errmsg)
      if (stat /= STAT_OK) return
      if (scn%mesh%nnode > nn0) call set_lines(scn%node_line, nn0, scn%mesh%nnode, st(i)%line)
    end do
    scn%node_line = scn%node_line(1:scn%mesh%nnode)
    ! Pass 2: what refers to the mesh and the definitions.
    allocate (scn%elem_model(scn%mesh%nelem))
    scn%elem_model = 0
    do i = 1, size(st)
      call models_statement(scn, st(i), path, stat, errmsg)
      if (stat == STAT_OK) call conditions_statement(scn, st(i), path, stat, errmsg)
      if (stat == STAT_OK) call run_statement(scn, st(i), path, stat, errmsg)
      if (stat /= STAT_OK) return
    end do
    ! Pass 3: the contacts, which need every model's kinematics (GAP … SEGMENTS with LARGE), and
    ! the check that every contact and load node carries a modelled element.
    call modelled_nodes(scn)
    do i = 1, size(st)
      call contacts_statement(scn, st(i), path, stat, errmsg)
      if (stat == STAT_OK) call loads_modelled(scn, st(i), stat, errmsg)
      if (stat /= STAT_OK) return
    end do
    if (size(scn%models) == 0) then
      call set_error(stat, errmsg, STAT_INPUT, path // ':1: no MODEL statement: nothing to compute')
      return
    end if
    call check_required(st, sch, path, stat, errmsg)
    if (stat == STAT_OK .and. scn%time_zero_line > 0 .and. scn%modes == 0 .and. scn%static_steps == 0) &
      call set_error(stat, errmsg, STAT_INPUT, path // ':' // str(scn%time_zero_line) // ": TIME: END equals START: " // &
      "no step to compute (a scene of MODES or STATIC alone says MODES n or STATIC), at 'END'")
    if (stat == STAT_OK) call default_mass(scn)
    if (stat == STAT_OK) call check_tuned(scn, stat, errmsg)
    if (stat == STAT_OK) call resolve_impact(scn, stat, errmsg)
    if (stat == STAT_OK) call check_large(scn, stat, errmsg)
    if (stat == STAT_OK) call check_spin(scn, stat, errmsg)
    ! KINEMATICS LARGE: K0 + 4M/h² holds the reference axes, which a rotating stiff member leaves:
    ! unless the scene says otherwise, the iteration is Newton's (TANGENT), whose quadratic
    ! convergence leaves the energy and momentum errors far below the tolerance (measured in
    ! docs/large-displacements.md against AUTO).
    if (stat == STAT_OK .and. .not. scn%iteration_given .and. any(scn%models%large)) then
      scn%tangent = .true.
      scn%iter_auto = .false.
    end if
    if (stat == STAT_OK) scn%fingerprint = fingerprint_text(st, scn%mesh)
  end subroutine load_scene

  !> lines(n0+1:n1) = line, lines grown by doubling (a scene of 1e5 NODE statements loads in
  !> linear time).
  pure subroutine set_lines(lines, n0, n1, line)
    integer, allocatable, intent(inout) :: lines(:)
    integer, intent(in) :: n0, n1, line
    integer, allocatable :: tmp(:)
    if (n1 > size(lines)) then
      allocate (tmp(max(2 * size(lines), n1)))
      tmp(1:n0) = lines(1:n0)
      call move_alloc(tmp, lines)
    end if
    lines(n0 + 1:n1) = line
  end subroutine set_lines

  !> scn%modelled(node): the node carries an element of some MODEL.
  subroutine modelled_nodes(scn)
    type(scene_t), intent(inout) :: scn
    integer :: e
    allocate (scn%modelled(scn%mesh%nnode))
    scn%modelled = .false.
    do e = 1, scn%mesh%nelem
      if (scn%elem_model(e) /= 0) scn%modelled(scn%mesh%conn(1:scn%mesh%nen(e), e)) = .true.
    end do
  end subroutine modelled_nodes

  !> HYPERELASTIC without KINEMATICS LARGE, and what KINEMATICS LARGE cannot be combined with, named:
  !> stiffness-proportional damping (BETA K0, the reference configuration's stiffness, would resist
  !> the members' rigid rotation) and INITIAL STATIC (it solves K0 u = f, a small-displacement
  !> equilibrium). Every law a surface element accepts (ELASTIC, VON_MISES, HYPERELASTIC) has a
  !> large form (docs/large-displacements.md).
  subroutine check_large(scn, stat, errmsg)
    type(scene_t), intent(in) :: scn
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: i, k
    stat = STAT_OK
    do i = 1, size(scn%models)
      associate (md => scn%models(i))
        if (md%material == 0 .or. md%large) cycle
        if (scn%materials(md%material)%law == LAW_HYPERELASTIC) then
          call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(md%line) // ': MODEL ' // md%group // &
            ': HYPERELASTIC (neo-Hookean) is a finite-strain law: the model needs KINEMATICS LARGE, at ''' // &
            scn%materials(md%material)%name // "'")
          return
        end if
      end associate
    end do
    k = findloc(scn%models%large, .true., 1)
    if (k == 0) return
    do i = 1, size(scn%models)
      associate (md => scn%models(i))
        if (md%large .and. md%sec%axisymmetric .and. md%material > 0) then
          if (scn%materials(md%material)%law == LAW_HYPERELASTIC) then
            call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(md%line) // ': MODEL ' // md%group // &
              ': HYPERELASTIC has no axisymmetric form yet (its thickness stretch is plane strain or plane ' // &
              "stress); ELASTIC and VON_MISES have one, at 'AXISYMMETRIC'")
            return
          end if
        end if
      end associate
    end do
    do i = 1, size(scn%models)
      associate (md => scn%models(i))
        if (md%large .and. md%beta > 0.0_dp) then
          call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(md%line) // ': MODEL ' // md%group // &
            ': DAMPING BETA (K0 of the reference configuration) would resist the rotation of a KINEMATICS LARGE ' // &
            "member; use ALPHA, at 'BETA'")
          return
        end if
      end associate
    end do
    do i = 1, size(scn%initials)
      if (scn%initials(i)%kind == INIT_STATIC) then
        call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(scn%initials(i)%line) // ': INITIAL: STATIC ' // &
          'solves K0 u = f, a small-displacement equilibrium, and MODEL ' // scn%models(k)%group // ' (line ' // &
          str(scn%models(k)%line) // ") has KINEMATICS LARGE, at 'STATIC'")
        return
      end if
    end do
  end subroutine check_large
  !> INITIAL … ANGULAR_VELOCITY in an axisymmetric scene: an in-plane rotation is no rigid motion
  !> of a ring (it stretches the hoops).
  subroutine check_spin(scn, stat, errmsg)
    type(scene_t), intent(in) :: scn
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: i
    stat = STAT_OK
    if (.not. scene_axisymmetric(scn)) return
    do i = 1, size(scn%initials)
      if (scn%initials(i)%kind /= INIT_ANGULAR) cycle
      call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(scn%initials(i)%line) // ': INITIAL: an ' // &
        'in-plane rotation is no rigid motion of an axisymmetric body (it would stretch the hoops), ' // &
        "at 'ANGULAR_VELOCITY'")
      return
    end do
  end subroutine check_spin
end module scene_loader

