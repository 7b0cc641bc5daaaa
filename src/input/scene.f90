!> The scene: everything a run needs, built from a keyword file (docs/input.md) after the
!> command-line overrides. Statements are interpreted in two passes so that the order of
!> definitions and their uses does not matter, except inside the mesh (a GROUP or ELEMENT
!> refers to groups defined above it).
module scene
  use kinds, only: dp, zero_tol
  use errors, only: STAT_OK, STAT_INPUT, set_error, str, upper
  use mesh, only: mesh_t, ET_MASS, ET_SPRING, ET_BAR2, ET_BEAM2, ET_QUAD4, ET_QUAD8, etype_from_name, etype_name, &
    etype_nen, DOF_UX, DOF_UY, DOF_RZ
  use section, only: section_t
  use material_law, only: material_t, law_check, LAW_ELASTIC, LAW_NONLINEAR_ELASTIC, LAW_ELASTOPLASTIC, LAW_VON_MISES, &
    PK_1D, PK_BEAM, PK_PSTRAIN, PK_PSTRESS
  use scene_parser, only: schema_t, statement_t, token_t, parse_file, apply_override, stmt_error, find_param, &
    count_param, get_real, get_int, get_word, to_real, to_int, check_required
  use mesh_generators, only: generate_line, generate_rectangle, MAX_GENERATED_ELEMENTS
  use gmsh_reader, only: read_gmsh
  use elements, only: elem_check_geometry
  implicit none
  private
  public :: scene_t, model_t, fix_t, initial_t, load_t, function_t, probe_t
  public :: load_scene, scene_schema, function_value, model_point_kind
  public :: INIT_DISPLACEMENT, INIT_VELOCITY, INIT_STATIC, condition_t
  public :: IMPACT_OFF, IMPACT_PAPER, IMPACT_PERSIST

  integer, parameter :: INIT_DISPLACEMENT = 1, INIT_VELOCITY = 2, INIT_STATIC = 3
  integer, parameter :: IMPACT_OFF = 0, IMPACT_PAPER = 1, IMPACT_PERSIST = 2
  integer, parameter :: IMPACT_MODES(3) = [IMPACT_PAPER, IMPACT_PERSIST, IMPACT_OFF]  !< in SCHEME IMPACT's word order
  !> Upper bounds of SECTION LAYERS and MODEL SUBSTEPS (far above any useful value; see do_section, do_model).
  integer, parameter, public :: MAX_LAYERS = 1000, MAX_SUBSTEPS = 10000

  !> One unilateral contact condition g = g0 + n.(u_b - u_a) >= 0 (method.md section 3): a node
  !> against a rigid plane (node_a = 0: g = g0 + n.u_b) or a node b against a node a.
  type :: condition_t
    character(len=:), allocatable :: source   !< the OBSTACLE or GAP statement's name
    integer :: node_a = 0, node_b = 0
    real(dp) :: normal(2) = 0.0_dp
    real(dp) :: g0 = 0.0_dp
    integer :: line = 0
  end type condition_t

  !> MODELE: an element group with its formulation, material, section and mass kind.
  type :: model_t
    character(len=:), allocatable :: group
    integer :: egroup = 0
    integer :: etype = 0          !< element type of every element of the model
    integer :: material = 0       !< index in scene%materials (0 for MASS elements)
    type(section_t) :: sec        !< copy of the section, with the model's plane option
    logical :: lumped = .false.
    integer :: substeps = 0       !< sub-increments of the laws (Cast3M SOUS_INCREMENT); 0 = AUTO
    integer :: line = 0
  end type model_t

  !> BLOQUE: homogeneous supports on DOFs of a node group.
  type :: fix_t
    integer :: ngroup = 0
    logical :: dofs(3) = .false.
    integer :: line = 0
  end type fix_t

  !> Initial displacement or velocity on a node group, or a static preload (released at t = 0).
  type :: initial_t
    integer :: kind = 0
    integer :: ngroup = 0
    real(dp) :: values(3) = 0.0_dp
    logical :: mask(3) = .false.
    integer :: line = 0
  end type initial_t

  !> Piecewise-linear function of time, constant beyond its ends.
  type :: function_t
    character(len=:), allocatable :: name
    real(dp), allocatable :: t(:), f(:)
  end type function_t

  !> Nodal forces on every node of a group, times a function of time.
  type :: load_t
    character(len=:), allocatable :: name
    integer :: ngroup = 0
    real(dp) :: force(3) = 0.0_dp
    integer :: func = 0          !< 0: constant 1
  end type load_t

  type :: probe_t
    character(len=:), allocatable :: label   !< group.DOF
    integer :: node = 0
    integer :: dof = 0
    integer :: line = 0
  end type probe_t

  type :: scene_t
    character(len=:), allocatable :: path, title
    type(mesh_t) :: mesh
    type(material_t), allocatable :: materials(:)
    type(section_t), allocatable :: sections(:)
    type(model_t), allocatable :: models(:)
    integer, allocatable :: elem_model(:)     !< (nelem) model of each element, 0 = not modelled
    integer, allocatable :: node_line(:)      !< (nnode) line of the statement that created each node
    type(fix_t), allocatable :: fixes(:)
    type(initial_t), allocatable :: initials(:)
    type(function_t), allocatable :: functions(:)
    type(load_t), allocatable :: loads(:)
    real(dp) :: gravity(2) = 0.0_dp
    integer :: gravity_func = 0
    real(dp) :: t_start = 0.0_dp, t_end = 0.0_dp, dt = 0.0_dp
    real(dp) :: tolerance = 1.0e-10_dp
    integer :: max_iterations = 25
    logical :: energy_correction = .true.     !< add Bσc of eq (9)
    logical :: tangent = .false.              !< iteration matrix: consistent tangent (else K0 + 4M/h²)
    logical :: extended = .false.             !< SCHEME PRECISION EXTENDED
    integer :: history_every = 1
    integer :: fields_every = -1              !< -1: first and last step only; 0: never
    integer :: checkpoint_every = 0           !< OUTPUT CHECKPOINT EVERY k (0: none)
    type(probe_t), allocatable :: probes(:)
    type(condition_t), allocatable :: conditions(:)   !< unilateral contacts (OBSTACLE, GAP)
    integer :: impact = IMPACT_PAPER                  !< SCHEME IMPACT
    integer :: multipliers = 0                        !< SCHEME MULTIPLIERS: 0 AUTO, 1 SCHUR, 2 AUGMENTED
    integer :: augmented_above = 128                  !< SCHEME AUGMENTED_ABOVE (AUTO's switch)
  end type scene_t

contains

  !> The grammar of a scene file: keywords, their leading tokens and parameters.
  subroutine scene_schema(sch)
    type(schema_t), intent(out) :: sch
    call sch%add_keyword('TITLE', 1, 1, once=.true.)
    call sch%add_keyword('DIMENSION', 1, 1, once=.true.)
    call sch%add_keyword('NODE', 1, 1)
    call sch%add_param('NODE', 'AT', 2, 2)
    call sch%add_keyword('ELEMENT', 1, 1)
    call sch%add_param('ELEMENT', 'TYPE', 1, 1)
    call sch%add_param('ELEMENT', 'NODES', 1, -1)
    call sch%add_keyword('GROUP', 1, 1)
    call sch%add_param('GROUP', 'NODES', 1, -1)
    call sch%add_param('GROUP', 'ELEMENTS', 1, -1)
    call sch%add_keyword('LINE', 1, 1)
    call sch%add_param('LINE', 'FROM', 2, 2)
    call sch%add_param('LINE', 'TO', 2, 2)
    call sch%add_param('LINE', 'ELEMENTS', 1, 1)
    call sch%add_param('LINE', 'TYPE', 1, 1)
    call sch%add_keyword('RECTANGLE', 1, 1)
    call sch%add_param('RECTANGLE', 'ORIGIN', 2, 2)
    call sch%add_param('RECTANGLE', 'SIZE', 2, 2)
    call sch%add_param('RECTANGLE', 'ELEMENTS', 2, 2)
    call sch%add_param('RECTANGLE', 'TYPE', 1, 1)
    call sch%add_param('RECTANGLE', 'ANGLE', 1, 1)
    call sch%add_keyword('GMSH', 1, 1)
    call sch%add_param('GMSH', 'FILE', 1, 1)
    call sch%add_keyword('MATERIAL', 1, 1)
    call sch%add_param('MATERIAL', 'ELASTIC', 0, 0)
    call sch%add_param('MATERIAL', 'NONLINEAR_ELASTIC', 0, 0)
    call sch%add_param('MATERIAL', 'ELASTOPLASTIC', 0, 0)
    call sch%add_param('MATERIAL', 'VON_MISES', 0, 0)
    call sch%add_param('MATERIAL', 'B', 1, 1)
    call sch%add_param('MATERIAL', 'YIELD', 1, 1)
    call sch%add_param('MATERIAL', 'H_ISO', 1, 1)
    call sch%add_param('MATERIAL', 'H_KIN', 1, 1)
    call sch%add_param('MATERIAL', 'YOUNG', 1, 1)
    call sch%add_param('MATERIAL', 'POISSON', 1, 1)
    call sch%add_param('MATERIAL', 'DENSITY', 1, 1)
    call sch%add_keyword('SECTION', 1, 1)
    call sch%add_param('SECTION', 'AREA', 1, 1)
    call sch%add_param('SECTION', 'INERTIA', 1, 1)
    call sch%add_param('SECTION', 'HEIGHT', 1, 1)
    call sch%add_param('SECTION', 'THICKNESS', 1, 1)
    call sch%add_param('SECTION', 'MASS', 1, 1)
    call sch%add_param('SECTION', 'DIRECTION', 2, 2)
    call sch%add_param('SECTION', 'GAUSS', 1, 1)
    call sch%add_param('SECTION', 'LAYERS', 1, 1)
    call sch%add_keyword('MODEL', 1, 1)
    call sch%add_param('MODEL', 'TYPE', 1, 1)
    call sch%add_param('MODEL', 'MATERIAL', 1, 1)
    call sch%add_param('MODEL', 'SECTION', 1, 1)
    call sch%add_param('MODEL', 'MASS', 1, 1)
    call sch%add_param('MODEL', 'PLANE', 1, 1)
    call sch%add_param('MODEL', 'SUBSTEPS', 1, 1)
    call sch%add_keyword('FIX', 1, 1)
    call sch%add_param('FIX', 'UX', 0, 0)
    call sch%add_param('FIX', 'UY', 0, 0)
    call sch%add_param('FIX', 'RZ', 0, 0)
    call sch%add_param('FIX', 'ALL', 0, 0)
    call sch%add_keyword('INITIAL', 1, 1)
    call sch%add_param('INITIAL', 'DISPLACEMENT', 2, 3)
    call sch%add_param('INITIAL', 'VELOCITY', 2, 3)
    call sch%add_param('INITIAL', 'STATIC', 0, 0)
    call sch%add_param('INITIAL', 'FORCE', 2, 3)
    call sch%add_keyword('GRAVITY', 0, 0, once=.true.)
    call sch%add_param('GRAVITY', 'GX', 1, 1)
    call sch%add_param('GRAVITY', 'GY', 1, 1)
    call sch%add_param('GRAVITY', 'FUNCTION', 1, 1)
    call sch%add_keyword('LOAD', 1, 1)
    call sch%add_param('LOAD', 'NODES', 1, 1)
    call sch%add_param('LOAD', 'FORCE', 2, 3)
    call sch%add_param('LOAD', 'FUNCTION', 1, 1)
    call sch%add_keyword('FUNCTION', 1, 1)
    call sch%add_param('FUNCTION', 'POINTS', 2, -1)
    call sch%add_keyword('TIME', 0, 0, once=.true., required=.true., hint='TIME STEP h END t')
    call sch%add_param('TIME', 'STEP', 1, 1)
    call sch%add_param('TIME', 'END', 1, 1)
    call sch%add_param('TIME', 'START', 1, 1)
    call sch%add_keyword('SCHEME', 0, 0, once=.true.)
    call sch%add_param('SCHEME', 'NEWMARK', 0, 0)
    call sch%add_param('SCHEME', 'TOLERANCE', 1, 1)
    call sch%add_param('SCHEME', 'MAX_ITERATIONS', 1, 1)
    call sch%add_param('SCHEME', 'ENERGY_CORRECTION', 1, 1)
    call sch%add_param('SCHEME', 'ITERATION', 1, 1)
    call sch%add_param('SCHEME', 'IMPACT', 1, 1)
    call sch%add_param('SCHEME', 'PRECISION', 1, 1)
    call sch%add_param('SCHEME', 'MULTIPLIERS', 1, 1)
    call sch%add_param('SCHEME', 'AUGMENTED_ABOVE', 1, 1)
    call sch%add_keyword('OBSTACLE', 1, 1)
    call sch%add_param('OBSTACLE', 'NODES', 1, 1)
    call sch%add_param('OBSTACLE', 'POINT', 2, 2)
    call sch%add_param('OBSTACLE', 'NORMAL', 2, 2)
    call sch%add_keyword('GAP', 1, 1)
    call sch%add_param('GAP', 'NODES', 1, 1)
    call sch%add_param('GAP', 'WITH', 1, 1)
    call sch%add_param('GAP', 'PAIRS', 2, -1)
    call sch%add_param('GAP', 'NORMAL', 2, 2)
    call sch%add_keyword('OUTPUT', 0, 0, once=.true.)
    call sch%add_param('OUTPUT', 'HISTORY', 1, 2)
    call sch%add_param('OUTPUT', 'FIELDS', 1, 2)
    call sch%add_param('OUTPUT', 'PROBE', 2, -1, repeatable=.true.)
    call sch%add_param('OUTPUT', 'CHECKPOINT', 1, 2)
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
      scn%functions(0), scn%loads(0), scn%probes(0), scn%conditions(0))
    ! Pass 1: mesh and definitions, in file order.
    allocate (scn%node_line(0))
    do i = 1, size(st)
      nn0 = scn%mesh%nnode
      select case (st(i)%keyword)
      case ('DIMENSION')
        call do_dimension(st(i), stat, errmsg)
      case ('TITLE')
        scn%title = st(i)%lead(1)%text
      case ('NODE')
        call do_node(scn, st(i), stat, errmsg)
      case ('ELEMENT')
        call do_element(scn, st(i), stat, errmsg)
      case ('GROUP')
        call do_group(scn, st(i), stat, errmsg)
      case ('LINE')
        call do_line(scn, st(i), stat, errmsg)
      case ('RECTANGLE')
        call do_rectangle(scn, st(i), stat, errmsg)
      case ('GMSH')
        call do_gmsh(scn, st(i), path, stat, errmsg)
      case ('MATERIAL')
        call do_material(scn, st(i), stat, errmsg)
      case ('SECTION')
        call do_section(scn, st(i), stat, errmsg)
      case ('FUNCTION')
        call do_function(scn, st(i), stat, errmsg)
      end select
      if (stat /= STAT_OK) return
      if (scn%mesh%nnode > nn0) scn%node_line = [scn%node_line, spread(st(i)%line, 1, scn%mesh%nnode - nn0)]
    end do
    ! Pass 2: what refers to the mesh and the definitions.
    allocate (scn%elem_model(scn%mesh%nelem))
    scn%elem_model = 0
    do i = 1, size(st)
      select case (st(i)%keyword)
      case ('MODEL')
        call do_model(scn, st(i), stat, errmsg)
      case ('FIX')
        call do_fix(scn, st(i), stat, errmsg)
      case ('INITIAL')
        call do_initial(scn, st(i), stat, errmsg)
      case ('GRAVITY')
        call do_gravity(scn, st(i), stat, errmsg)
      case ('LOAD')
        call do_load(scn, st(i), stat, errmsg)
      case ('TIME')
        call do_time(scn, st(i), stat, errmsg)
      case ('SCHEME')
        call do_scheme(scn, st(i), stat, errmsg)
      case ('OUTPUT')
        call do_output(scn, st(i), stat, errmsg)
      case ('OBSTACLE')
        call do_obstacle(scn, st(i), stat, errmsg)
      case ('GAP')
        call do_gap(scn, st(i), stat, errmsg)
      end select
      if (stat /= STAT_OK) return
    end do
    if (size(scn%models) == 0) then
      call set_error(stat, errmsg, STAT_INPUT, path // ':1: no MODEL statement: nothing to compute')
      return
    end if
    call check_required(st, sch, path, stat, errmsg)
  end subroutine load_scene

  subroutine do_dimension(st, stat, errmsg)
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: d
    call to_int(st%lead(1), st, d, stat, errmsg)
    if (stat /= STAT_OK) return
    if (d /= 2) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'only DIMENSION 2 is supported', st%lead(1)))
  end subroutine do_dimension

  subroutine do_node(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: xy(2)
    integer :: id
    call check_new_group_name(scn, st, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_real(st, 'AT', xy(1), stat, errmsg, index=1)
    if (stat /= STAT_OK) return
    call get_real(st, 'AT', xy(2), stat, errmsg, index=2)
    if (stat /= STAT_OK) return
    call scn%mesh%add_node(xy, id)
    call scn%mesh%add_node_group(st%lead(1)%text, [id])
  end subroutine do_node

  !> A new group name must not shadow an existing node or element group.
  subroutine check_new_group_name(scn, st, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (scn%mesh%find_node_group(st%lead(1)%text) > 0 .or. scn%mesh%find_elem_group(st%lead(1)%text) > 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'a group of this name already exists', st%lead(1)))
    end if
  end subroutine check_new_group_name

  !> Element type named by parameter key; allowed(:) restricts the choice.
  subroutine get_etype(st, key, allowed, et, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    integer, intent(in) :: allowed(:)
    integer, intent(out) :: et
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: w, names
    integer :: k, i
    call get_word(st, key, w, stat, errmsg)
    if (stat /= STAT_OK) return
    et = etype_from_name(upper(w))
    if (any(allowed == et)) return
    names = ''
    do i = 1, size(allowed)
      names = names // merge(', ', '  ', i > 1) // etype_name(allowed(i))
    end do
    names = adjustl(names)
    k = find_param(st, key)
    call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'element type not allowed here (expected one of: ' // &
      trim(names) // ')', st%params(k)%values(1)))
  end subroutine get_etype

  subroutine do_element(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: et, k, nen, nv, i, j, ig, id
    integer, allocatable :: nodes(:), ids(:)
    call check_new_group_name(scn, st, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_etype(st, 'TYPE', [ET_MASS, ET_SPRING, ET_BAR2, ET_BEAM2, ET_QUAD4, ET_QUAD8], et, stat, errmsg)
    if (stat /= STAT_OK) return
    k = find_param(st, 'NODES')
    if (k == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'missing parameter NODES'))
      return
    end if
    nen = etype_nen(et)
    nv = size(st%params(k)%values)
    if (mod(nv, nen) /= 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'NODES lists ' // str(nv) // ' nodes, not a multiple of ' &
        // str(nen) // ' (nodes of a ' // etype_name(et) // ')', st%params(k)%keytok))
      return
    end if
    allocate (nodes(nen), ids(nv / nen))
    do i = 1, nv / nen
      do j = 1, nen
        associate (tok => st%params(k)%values((i - 1) * nen + j))
          ig = scn%mesh%find_node_group(tok%text)
          if (ig == 0) then
            call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'unknown node group', tok))
            return
          end if
          if (size(scn%mesh%ngroups(ig)%items) /= 1) then
            call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'node group has ' // &
              str(size(scn%mesh%ngroups(ig)%items)) // ' nodes; an element node must name one node', tok))
            return
          end if
          nodes(j) = scn%mesh%ngroups(ig)%items(1)
        end associate
      end do
      call scn%mesh%add_element(et, nodes, id)
      ids(i) = id
    end do
    call scn%mesh%add_elem_group(st%lead(1)%text, ids)
  end subroutine do_element

  subroutine do_group(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: kn, ke, i, ig
    integer, allocatable :: items(:)
    logical, allocatable :: used(:)
    call check_new_group_name(scn, st, stat, errmsg)
    if (stat /= STAT_OK) return
    kn = find_param(st, 'NODES')
    ke = find_param(st, 'ELEMENTS')
    if ((kn == 0) .eqv. (ke == 0)) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'give exactly one of NODES or ELEMENTS'))
      return
    end if
    if (kn > 0) then
      allocate (used(scn%mesh%nnode))
      used = .false.
      do i = 1, size(st%params(kn)%values)
        ig = scn%mesh%find_node_group(st%params(kn)%values(i)%text)
        if (ig == 0) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'unknown node group', st%params(kn)%values(i)))
          return
        end if
        used(scn%mesh%ngroups(ig)%items) = .true.
      end do
      items = pack([(i, i = 1, scn%mesh%nnode)], used)
      call scn%mesh%add_node_group(st%lead(1)%text, items)
    else
      allocate (used(scn%mesh%nelem))
      used = .false.
      do i = 1, size(st%params(ke)%values)
        ig = scn%mesh%find_elem_group(st%params(ke)%values(i)%text)
        if (ig == 0) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'unknown element group', st%params(ke)%values(i)))
          return
        end if
        used(scn%mesh%egroups(ig)%items) = .true.
      end do
      items = pack([(i, i = 1, scn%mesh%nelem)], used)
      call scn%mesh%add_elem_group(st%lead(1)%text, items)
    end if
  end subroutine do_group

  subroutine do_line(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: p0(2), p1(2)
    integer :: nel, et
    call check_new_group_name(scn, st, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_pair(st, 'FROM', p0, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_pair(st, 'TO', p1, stat, errmsg)
    if (stat /= STAT_OK) return
    ! Upper bound: an absurd count must be an input error, not an allocation failure (fuzz).
    call get_int(st, 'ELEMENTS', nel, stat, errmsg, lower=1, lower_inclusive=.true., upper=MAX_GENERATED_ELEMENTS, &
      upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_etype(st, 'TYPE', [ET_BAR2, ET_BEAM2, ET_SPRING], et, stat, errmsg)
    if (stat /= STAT_OK) return
    if (norm2(p1 - p0) <= zero_tol * max(1.0_dp, norm2(p0), norm2(p1))) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'FROM and TO coincide: zero-length line', &
        st%params(find_param(st, 'TO'))%keytok))
      return
    end if
    call generate_line(scn%mesh, st%lead(1)%text, p0, p1, nel, et, stat, errmsg)
    if (stat /= STAT_OK) errmsg = stmt_error(st, errmsg)
  end subroutine do_line

  subroutine do_rectangle(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: origin(2), lxy(2), angle
    integer :: nx, ny, et
    real(dp), parameter :: pi = acos(-1.0_dp)
    call check_new_group_name(scn, st, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_pair(st, 'ORIGIN', origin, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_real(st, 'SIZE', lxy(1), stat, errmsg, index=1, lower=0.0_dp, lower_inclusive=.false.)
    if (stat /= STAT_OK) return
    call get_real(st, 'SIZE', lxy(2), stat, errmsg, index=2, lower=0.0_dp, lower_inclusive=.false.)
    if (stat /= STAT_OK) return
    call get_int(st, 'ELEMENTS', nx, stat, errmsg, index=1, lower=1, lower_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_int(st, 'ELEMENTS', ny, stat, errmsg, index=2, lower=1, lower_inclusive=.true.)
    if (stat /= STAT_OK) return
    ! nx*ny is bounded without forming it (it may overflow): an absurd mesh is an input error, not an
    ! allocation failure or hours of node generation (found by tests/fuzz/fuzz.py).
    if (nx > MAX_GENERATED_ELEMENTS / ny) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'ELEMENTS ' // str(nx) // ' x ' // str(ny) // &
        ' exceeds the limit of ' // str(MAX_GENERATED_ELEMENTS) // ' elements', &
        st%params(find_param(st, 'ELEMENTS'))%values(1)))
      return
    end if
    call get_etype(st, 'TYPE', [ET_QUAD4, ET_QUAD8], et, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_real(st, 'ANGLE', angle, stat, errmsg, default=0.0_dp)
    if (stat /= STAT_OK) return
    call generate_rectangle(scn%mesh, st%lead(1)%text, origin, lxy(1), lxy(2), nx, ny, et, stat, errmsg, &
      angle=angle * pi / 180.0_dp)
    if (stat /= STAT_OK) errmsg = stmt_error(st, errmsg)
  end subroutine do_rectangle

  subroutine do_gmsh(scn, st, scene_path, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: scene_path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: file, full, msg
    call check_new_group_name(scn, st, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_word(st, 'FILE', file, stat, errmsg)
    if (stat /= STAT_OK) return
    full = resolve_path(scene_path, file)
    call read_gmsh(scn%mesh, full, st%lead(1)%text, stat, msg)
    if (stat /= STAT_OK) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, msg, st%params(find_param(st, 'FILE'))%values(1)))
    end if
  end subroutine do_gmsh

  !> A path relative to the directory of the scene file (absolute paths unchanged).
  pure function resolve_path(scene_path, file) result(full)
    character(len=*), intent(in) :: scene_path, file
    character(len=:), allocatable :: full
    integer :: k
    if (len(file) > 0) then
      if (file(1:1) == '/') then
        full = file
        return
      end if
    end if
    k = index(scene_path, '/', back=.true.)
    full = scene_path(1:k) // file
  end function resolve_path

  subroutine do_material(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(material_t) :: mat
    integer :: i, nlaw
    do i = 1, size(scn%materials)
      if (scn%materials(i)%name == st%lead(1)%text) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'material defined twice', st%lead(1)))
        return
      end if
    end do
    mat%name = st%lead(1)%text
    nlaw = count([find_param(st, 'ELASTIC') > 0, find_param(st, 'NONLINEAR_ELASTIC') > 0, &
      find_param(st, 'ELASTOPLASTIC') > 0, find_param(st, 'VON_MISES') > 0])
    if (nlaw /= 1) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'give exactly one law (ELASTIC, NONLINEAR_ELASTIC, ' // &
        'ELASTOPLASTIC or VON_MISES)', st%lead(1)))
      return
    end if
    mat%law = LAW_ELASTIC
    if (find_param(st, 'NONLINEAR_ELASTIC') > 0) mat%law = LAW_NONLINEAR_ELASTIC
    if (find_param(st, 'ELASTOPLASTIC') > 0) mat%law = LAW_ELASTOPLASTIC
    if (find_param(st, 'VON_MISES') > 0) mat%law = LAW_VON_MISES
    call check_law_params(st, mat%law, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_real(st, 'B', mat%nl_b, stat, errmsg, default=0.0_dp)
    if (stat /= STAT_OK) return
    if (mat%law == LAW_ELASTOPLASTIC .or. mat%law == LAW_VON_MISES) then
      call get_real(st, 'YIELD', mat%yield, stat, errmsg, lower=0.0_dp, lower_inclusive=.false.)
      if (stat /= STAT_OK) return
    end if
    call get_real(st, 'H_ISO', mat%h_iso, stat, errmsg, default=0.0_dp, lower=0.0_dp, lower_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_real(st, 'H_KIN', mat%h_kin, stat, errmsg, default=0.0_dp, lower=0.0_dp, lower_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_real(st, 'YOUNG', mat%young, stat, errmsg, lower=0.0_dp, lower_inclusive=.false.)
    if (stat /= STAT_OK) return
    call get_real(st, 'POISSON', mat%poisson, stat, errmsg, default=0.0_dp, lower=-1.0_dp, lower_inclusive=.false.)
    if (stat /= STAT_OK) return
    if (mat%poisson >= 0.5_dp) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'POISSON must be < 0.5', &
        st%params(find_param(st, 'POISSON'))%values(1)))
      return
    end if
    call get_real(st, 'DENSITY', mat%density, stat, errmsg, default=0.0_dp, lower=0.0_dp, lower_inclusive=.true.)
    if (stat /= STAT_OK) return
    scn%materials = [scn%materials, mat]
  end subroutine do_material

  subroutine do_section(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(section_t) :: sec
    integer :: i
    do i = 1, size(scn%sections)
      if (scn%sections(i)%name == st%lead(1)%text) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'section defined twice', st%lead(1)))
        return
      end if
    end do
    sec%name = st%lead(1)%text
    call get_real(st, 'AREA', sec%area, stat, errmsg, default=0.0_dp, lower=0.0_dp, lower_inclusive=.false.)
    if (stat /= STAT_OK) return
    call get_real(st, 'INERTIA', sec%inertia, stat, errmsg, default=0.0_dp, lower=0.0_dp, lower_inclusive=.false.)
    if (stat /= STAT_OK) return
    call get_real(st, 'HEIGHT', sec%height, stat, errmsg, default=0.0_dp, lower=0.0_dp, lower_inclusive=.false.)
    if (stat /= STAT_OK) return
    call get_real(st, 'THICKNESS', sec%thickness, stat, errmsg, default=1.0_dp, lower=0.0_dp, lower_inclusive=.false.)
    if (stat /= STAT_OK) return
    call get_real(st, 'MASS', sec%mass, stat, errmsg, default=0.0_dp, lower=0.0_dp, lower_inclusive=.true.)
    if (stat /= STAT_OK) return
    if (find_param(st, 'DIRECTION') > 0) then
      call get_pair(st, 'DIRECTION', sec%direction, stat, errmsg)
      if (stat /= STAT_OK) return
      if (norm2(sec%direction) <= 0.0_dp) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'DIRECTION must be a non-zero vector', &
          st%params(find_param(st, 'DIRECTION'))%keytok))
        return
      end if
      sec%direction = sec%direction / norm2(sec%direction)
      sec%has_direction = .true.
    end if
    call get_int(st, 'GAUSS', sec%gauss, stat, errmsg, default=0, lower=1, lower_inclusive=.true.)
    if (stat /= STAT_OK) return
    ! LAYERS <= MAX_LAYERS: each layer carries state at every Gauss point of every element, and a
    ! count near 2**31 failed to allocate or ran for hours (found by tests/fuzz/fuzz.py).
    call get_int(st, 'LAYERS', sec%layers, stat, errmsg, default=0, lower=1, lower_inclusive=.true., &
      upper=MAX_LAYERS, upper_inclusive=.true.)
    if (stat /= STAT_OK) return
    if (sec%gauss > 5) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'GAUSS must be between 1 and 5', &
        st%params(find_param(st, 'GAUSS'))%values(1)))
      return
    end if
    scn%sections = [scn%sections, sec]
  end subroutine do_section

  subroutine do_function(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(function_t) :: fn
    integer :: k, n, i
    do i = 1, size(scn%functions)
      if (scn%functions(i)%name == st%lead(1)%text) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'function defined twice', st%lead(1)))
        return
      end if
    end do
    fn%name = st%lead(1)%text
    k = find_param(st, 'POINTS')
    if (k == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'missing parameter POINTS (pairs of time and value)'))
      return
    end if
    n = size(st%params(k)%values)
    if (mod(n, 2) /= 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'POINTS needs pairs of time and value, found ' // &
        str(n) // ' numbers', st%params(k)%keytok))
      return
    end if
    allocate (fn%t(n / 2), fn%f(n / 2))
    do i = 1, n / 2
      call to_real(st%params(k)%values(2 * i - 1), st, fn%t(i), stat, errmsg)
      if (stat /= STAT_OK) return
      call to_real(st%params(k)%values(2 * i), st, fn%f(i), stat, errmsg)
      if (stat /= STAT_OK) return
      if (i > 1) then
        if (fn%t(i) <= fn%t(i - 1)) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'times must increase', &
            st%params(k)%values(2 * i - 1)))
          return
        end if
      end if
    end do
    scn%functions = [scn%functions, fn]
  end subroutine do_function

  subroutine do_model(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(model_t) :: md
    integer :: ig, e, i, et0, isec, imodel
    character(len=:), allocatable :: w, msg
    real(dp) :: x(2, 8), msize
    md%group = st%lead(1)%text
    msize = model_size(scn%mesh)
    md%line = st%line
    ig = scn%mesh%find_elem_group(md%group)
    if (ig == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'unknown element group', st%lead(1)))
      return
    end if
    md%egroup = ig
    associate (items => scn%mesh%egroups(ig)%items)
      if (size(items) == 0) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'element group is empty', st%lead(1)))
        return
      end if
      et0 = scn%mesh%etype(items(1))
      if (any(scn%mesh%etype(items) /= et0)) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'element group mixes element types; model each type '// &
          'in its own group', st%lead(1)))
        return
      end if
      md%etype = et0
      if (find_param(st, 'TYPE') > 0) then
        if (any(et0 == [ET_SPRING, ET_BAR2, ET_BEAM2])) then
          call get_etype(st, 'TYPE', [ET_SPRING, ET_BAR2, ET_BEAM2], md%etype, stat, errmsg)
        else
          call get_etype(st, 'TYPE', [et0], md%etype, stat, errmsg)
        end if
        if (stat /= STAT_OK) return
      end if
    end associate
    ! Material (not for point masses).
    md%material = 0
    if (find_param(st, 'MATERIAL') > 0) then
      call get_word(st, 'MATERIAL', w, stat, errmsg)
      do i = 1, size(scn%materials)
        if (scn%materials(i)%name == w) md%material = i
      end do
      if (md%material == 0) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'unknown material', &
          st%params(find_param(st, 'MATERIAL'))%values(1)))
        return
      end if
    else if (md%etype /= ET_MASS) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'missing parameter MATERIAL (required for ' // &
        etype_name(md%etype) // ')', st%lead(1)))
      return
    end if
    ! Section.
    isec = 0
    if (find_param(st, 'SECTION') > 0) then
      call get_word(st, 'SECTION', w, stat, errmsg)
      do i = 1, size(scn%sections)
        if (scn%sections(i)%name == w) isec = i
      end do
      if (isec == 0) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'unknown section', &
          st%params(find_param(st, 'SECTION'))%values(1)))
        return
      end if
      md%sec = scn%sections(isec)
    else if (any(md%etype == [ET_MASS, ET_BAR2, ET_BEAM2])) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'missing parameter SECTION (required for ' // &
        etype_name(md%etype) // ')', st%lead(1)))
      return
    else
      md%sec%name = '(default)'
    end if
    call check_section(st, md, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_word(st, 'MASS', w, stat, errmsg, default='CONSISTENT')
    if (stat /= STAT_OK) return
    select case (upper(w))
    case ('CONSISTENT')
      md%lumped = .false.
    case ('LUMPED')
      md%lumped = .true.
    case default
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected CONSISTENT or LUMPED', &
        st%params(find_param(st, 'MASS'))%values(1)))
      return
    end select
    call get_word(st, 'SUBSTEPS', w, stat, errmsg, default='AUTO')
    if (stat /= STAT_OK) return
    if (upper(w) == 'AUTO') then
      md%substeps = 0
    else
      ! SUBSTEPS <= MAX_SUBSTEPS: the laws loop over the sub-increments at every point and iteration,
      ! so SUBSTEPS 1000000000 hung the run (found by tests/fuzz/fuzz.py); AUTO stays <= 100.
      call get_int(st, 'SUBSTEPS', md%substeps, stat, errmsg, lower=1, lower_inclusive=.true., &
        upper=MAX_SUBSTEPS, upper_inclusive=.true.)
      if (stat /= STAT_OK) return
    end if
    call get_word(st, 'PLANE', w, stat, errmsg, default='STRAIN')
    if (stat /= STAT_OK) return
    select case (upper(w))
    case ('STRAIN')
      md%sec%plane_stress = .false.
    case ('STRESS')
      md%sec%plane_stress = .true.
    case default
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected STRAIN or STRESS', &
        st%params(find_param(st, 'PLANE'))%values(1)))
      return
    end select
    if (md%material > 0) then
      call check_model_law(st, md, scn%materials(md%material), stat, errmsg)
      if (stat /= STAT_OK) return
    end if
    imodel = size(scn%models) + 1
    associate (items => scn%mesh%egroups(ig)%items)
      do i = 1, size(items)
        e = items(i)
        if (scn%elem_model(e) /= 0) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'element ' // str(e) // ' already belongs to the ' // &
            'model of group ' // scn%models(scn%elem_model(e))%group // ' (line ' // &
            str(scn%models(scn%elem_model(e))%line) // ')', st%lead(1)))
          return
        end if
        scn%mesh%etype(e) = md%etype
        x(:, 1:etype_nen(md%etype)) = scn%mesh%x(:, scn%mesh%conn(1:etype_nen(md%etype), e))
        call elem_check_geometry(md%etype, x(:, 1:etype_nen(md%etype)), md%sec, stat, msg, size_ref=msize)
        if (stat /= STAT_OK) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, etype_name(md%etype) // ' element ' // str(i) // &
            ' of group ' // md%group // ' (nodes ' // node_list(scn%mesh%conn(1:etype_nen(md%etype), e)) // '): ' &
            // msg, st%lead(1)))
          return
        end if
        scn%elem_model(e) = imodel
      end do
    end associate
    scn%models = [scn%models, md]
  end subroutine do_model

  pure function node_list(nodes) result(s)
    integer, intent(in) :: nodes(:)
    character(len=:), allocatable :: s
    integer :: i
    s = ''
    do i = 1, size(nodes)
      if (i > 1) s = s // ' '
      s = s // str(nodes(i))
    end do
  end function node_list

  !> The section characteristics an element type needs.
  subroutine check_section(st, md, stat, errmsg)
    type(statement_t), intent(in) :: st
    type(model_t), intent(in) :: md
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: need
    stat = STAT_OK
    need = ''
    select case (md%etype)
    case (ET_MASS)
      if (md%sec%mass <= 0.0_dp) need = 'MASS > 0'
    case (ET_BAR2)
      if (md%sec%area <= 0.0_dp) need = 'AREA'
    case (ET_BEAM2)
      ! A fibre section (LAYERS) integrates its inertia over the layers: INERTIA is not used.
      if (md%sec%area <= 0.0_dp) need = 'AREA'
      if (md%sec%inertia <= 0.0_dp .and. md%sec%layers == 0) then
        if (len(need) > 0) need = need // ' and '
        need = need // 'INERTIA'
      end if
    end select
    if (len(need) > 0) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'section ' // md%sec%name // &
      ' lacks ' // trim(need) // ' needed by ' // etype_name(md%etype) // ' elements', st%lead(1)))
  end subroutine check_section

  !> Which laws an element type accepts (1D laws on springs, bars and fibre beams, J2 on
  !> quads) and what they need: material_law's law_check, with the statement's file:line.
  subroutine check_model_law(st, md, mat, stat, errmsg)
    type(statement_t), intent(in) :: st
    type(model_t), intent(in) :: md
    type(material_t), intent(in) :: mat
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: msg
    call law_check(mat, model_point_kind(md), md%sec, stat, msg)
    if (stat /= STAT_OK) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'material ' // mat%name // ' on ' // &
      etype_name(md%etype) // ' elements: ' // msg, st%params(find_param(st, 'MATERIAL'))%values(1)))
  end subroutine check_model_law

  !> Material-point kind of a model's integration points (material_law PK_*; 0 for masses).
  pure integer function model_point_kind(md) result(pk)
    type(model_t), intent(in) :: md
    select case (md%etype)
    case (ET_SPRING, ET_BAR2)
      pk = PK_1D
    case (ET_BEAM2)
      pk = PK_BEAM
    case (ET_QUAD4, ET_QUAD8)
      pk = merge(PK_PSTRESS, PK_PSTRAIN, md%sec%plane_stress)
    case default
      pk = 0
    end select
  end function model_point_kind


  !> Index of the node group named by a token, with an error naming it when unknown.
  subroutine node_group(scn, st, tok, ig, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    type(token_t), intent(in) :: tok
    integer, intent(out) :: ig
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    ig = scn%mesh%find_node_group(tok%text)
    if (ig == 0) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'unknown node group', tok))
  end subroutine node_group

  subroutine do_fix(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(fix_t) :: fx
    call node_group(scn, st, st%lead(1), fx%ngroup, stat, errmsg)
    if (stat /= STAT_OK) return
    fx%dofs = [find_param(st, 'UX') > 0, find_param(st, 'UY') > 0, find_param(st, 'RZ') > 0]
    if (find_param(st, 'ALL') > 0) fx%dofs = .true.
    if (.not. any(fx%dofs)) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'no DOF to fix (expected UX, UY, RZ or ALL)', st%lead(1)))
      return
    end if
    fx%line = st%line
    scn%fixes = [scn%fixes, fx]
  end subroutine do_fix

  !> Values of a parameter with 2 or 3 numbers (x, y[, rotation]).
  subroutine get_vector(st, key, v, mask, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    real(dp), intent(out) :: v(3)
    logical, intent(out) :: mask(3)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, i
    v = 0.0_dp
    mask = .false.
    k = find_param(st, key)
    do i = 1, size(st%params(k)%values)
      call to_real(st%params(k)%values(i), st, v(i), stat, errmsg)
      if (stat /= STAT_OK) return
      mask(i) = .true.
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
    nkind = count([find_param(st, 'DISPLACEMENT') > 0, find_param(st, 'VELOCITY') > 0, find_param(st, 'STATIC') > 0])
    if (nkind /= 1) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'give exactly one of DISPLACEMENT, VELOCITY or ' // &
        'STATIC FORCE', st%lead(1)))
      return
    end if
    if (find_param(st, 'DISPLACEMENT') > 0) then
      ic%kind = INIT_DISPLACEMENT
      call get_vector(st, 'DISPLACEMENT', ic%values, ic%mask, stat, errmsg)
    else if (find_param(st, 'VELOCITY') > 0) then
      ic%kind = INIT_VELOCITY
      call get_vector(st, 'VELOCITY', ic%values, ic%mask, stat, errmsg)
    else
      ic%kind = INIT_STATIC
      if (find_param(st, 'FORCE') == 0) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'STATIC needs FORCE fx fy [mz]', &
          st%params(find_param(st, 'STATIC'))%keytok))
        return
      end if
      call get_vector(st, 'FORCE', ic%values, ic%mask, stat, errmsg)
    end if
    if (stat /= STAT_OK) return
    if (ic%kind /= INIT_STATIC .and. find_param(st, 'FORCE') > 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'FORCE goes with STATIC only', &
        st%params(find_param(st, 'FORCE'))%keytok))
      return
    end if
    scn%initials = [scn%initials, ic]
  end subroutine do_initial

  !> Index of the function named by parameter FUNCTION (0 when absent).
  subroutine get_function(scn, st, ifn, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: ifn
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: w
    integer :: i
    ifn = 0
    stat = STAT_OK
    if (find_param(st, 'FUNCTION') == 0) return
    call get_word(st, 'FUNCTION', w, stat, errmsg)
    if (stat /= STAT_OK) return
    do i = 1, size(scn%functions)
      if (scn%functions(i)%name == w) ifn = i
    end do
    if (ifn == 0) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'unknown function', &
      st%params(find_param(st, 'FUNCTION'))%values(1)))
  end subroutine get_function

  subroutine do_gravity(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call get_real(st, 'GX', scn%gravity(1), stat, errmsg, default=0.0_dp)
    if (stat /= STAT_OK) return
    call get_real(st, 'GY', scn%gravity(2), stat, errmsg, default=0.0_dp)
    if (stat /= STAT_OK) return
    call get_function(scn, st, scn%gravity_func, stat, errmsg)
  end subroutine do_gravity

  subroutine do_load(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(load_t) :: ld
    logical :: mask(3)
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
    call get_vector(st, 'FORCE', ld%force, mask, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_function(scn, st, ld%func, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%loads = [scn%loads, ld]
  end subroutine do_load

  subroutine do_time(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call get_real(st, 'STEP', scn%dt, stat, errmsg, lower=0.0_dp, lower_inclusive=.false.)
    if (stat /= STAT_OK) return
    call get_real(st, 'START', scn%t_start, stat, errmsg, default=0.0_dp)
    if (stat /= STAT_OK) return
    call get_real(st, 'END', scn%t_end, stat, errmsg)
    if (stat /= STAT_OK) return
    if (scn%t_end <= scn%t_start) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'END must be after START (' // str(scn%t_start) // ')', &
        st%params(find_param(st, 'END'))%values(1)))
      return
    end if
    if ((scn%t_end - scn%t_start) / scn%dt > 2.0e9_dp) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'more than 2e9 steps', &
        st%params(find_param(st, 'STEP'))%values(1)))
    end if
  end subroutine do_time

  subroutine do_scheme(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k
    call get_real(st, 'TOLERANCE', scn%tolerance, stat, errmsg, default=1.0e-10_dp, lower=0.0_dp, &
      lower_inclusive=.false.)
    if (stat /= STAT_OK) return
    call get_int(st, 'MAX_ITERATIONS', scn%max_iterations, stat, errmsg, default=25, lower=1, lower_inclusive=.true.)
    if (stat /= STAT_OK) return
    call get_choice(st, 'ENERGY_CORRECTION', ['ON ', 'OFF'], 'ON', k, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%energy_correction = k == 1
    call get_choice(st, 'ITERATION', ['ELASTIC', 'TANGENT'], 'ELASTIC', k, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%tangent = k == 2
    call get_choice(st, 'IMPACT', ['PAPER  ', 'PERSIST', 'OFF    '], 'PAPER', k, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%impact = IMPACT_MODES(k)
    call get_choice(st, 'PRECISION', ['DOUBLE  ', 'EXTENDED'], 'DOUBLE', k, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%extended = k == 2
    call get_choice(st, 'MULTIPLIERS', ['AUTO     ', 'SCHUR    ', 'AUGMENTED'], 'AUTO', k, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%multipliers = k - 1
    call get_int(st, 'AUGMENTED_ABOVE', scn%augmented_above, stat, errmsg, default=128, lower=0, lower_inclusive=.true.)
    if (stat /= STAT_OK) return
  end subroutine do_scheme

  !> "[EVERY] k" of OUTPUT HISTORY / FIELDS.
  subroutine get_every(st, key, every, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    integer, intent(inout) :: every
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, n
    stat = STAT_OK
    k = find_param(st, key)
    if (k == 0) return
    n = size(st%params(k)%values)
    if (n == 2) then
      if (upper(st%params(k)%values(1)%text) /= 'EVERY') then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected EVERY k', st%params(k)%values(1)))
        return
      end if
    end if
    call to_int(st%params(k)%values(n), st, every, stat, errmsg)
    if (stat /= STAT_OK) return
    if (every < 0) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'must be >= 0 (0: never)', &
      st%params(k)%values(n)))
  end subroutine get_every

  subroutine do_output(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, occ, i, ig, d
    type(probe_t) :: pr
    call get_every(st, 'HISTORY', scn%history_every, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_every(st, 'FIELDS', scn%fields_every, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_every(st, 'CHECKPOINT', scn%checkpoint_every, stat, errmsg)
    if (stat /= STAT_OK) return
    do occ = 1, count_param(st, 'PROBE')
      k = find_param(st, 'PROBE', occ)
      associate (vals => st%params(k)%values)
        if (mod(size(vals), 2) /= 0) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'PROBE takes pairs: group DOF', st%params(k)%keytok))
          return
        end if
        do i = 1, size(vals), 2
          call node_group(scn, st, vals(i), ig, stat, errmsg)
          if (stat /= STAT_OK) return
          if (size(scn%mesh%ngroups(ig)%items) /= 1) then
            call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'a probe needs a one-node group; this one has ' &
              // str(size(scn%mesh%ngroups(ig)%items)) // ' nodes', vals(i)))
            return
          end if
          select case (upper(vals(i + 1)%text))
          case ('UX')
            d = DOF_UX
          case ('UY')
            d = DOF_UY
          case ('RZ')
            d = DOF_RZ
          case default
            call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected a DOF: UX, UY or RZ', vals(i + 1)))
            return
          end select
          pr%node = scn%mesh%ngroups(ig)%items(1)
          pr%dof = d
          pr%label = vals(i)%text // '.' // upper(vals(i + 1)%text)
          pr%line = st%line
          scn%probes = [scn%probes, pr]
        end do
      end associate
    end do
  end subroutine do_output

  !> Largest extent of the mesh, the length scale of the gap tolerance.
  pure real(dp) function model_size(m)
    type(mesh_t), intent(in) :: m
    model_size = 1.0_dp
    if (m%nnode > 0) model_size = max(maxval(m%x(1, 1:m%nnode)) - minval(m%x(1, 1:m%nnode)), &
      maxval(m%x(2, 1:m%nnode)) - minval(m%x(2, 1:m%nnode)), tiny(1.0_dp))
  end function model_size

  !> A unit vector from parameter key.
  subroutine get_unit(st, key, n, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    real(dp), intent(out) :: n(2)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call get_pair(st, key, n, stat, errmsg)
    if (stat /= STAT_OK) return
    if (norm2(n) <= 0.0_dp) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, key // ' must be a non-zero vector', &
        st%params(find_param(st, key))%keytok))
      return
    end if
    n = n / norm2(n)
  end subroutine get_unit

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
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'node ' // str(c%node_b) // ' (x = ' // &
          str(scn%mesh%x(1, c%node_b)) // ', y = ' // str(scn%mesh%x(2, c%node_b)) // ') starts ' // str(-c%g0) // &
          ' inside the obstacle', st%lead(1)))
      else
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'nodes ' // str(c%node_a) // ' and ' // &
          str(c%node_b) // ' start interpenetrated by ' // str(-c%g0), st%lead(1)))
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
    real(dp) :: p(2), n(2)
    integer :: ig, k, i
    type(condition_t) :: c
    k = find_param(st, 'NODES')
    if (k == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'missing parameter NODES', st%lead(1)))
      return
    end if
    call node_group(scn, st, st%params(k)%values(1), ig, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_pair(st, 'POINT', p, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_unit(st, 'NORMAL', n, stat, errmsg)
    if (stat /= STAT_OK) return
    do i = 1, size(scn%mesh%ngroups(ig)%items)
      c%source = st%lead(1)%text
      c%node_a = 0
      c%node_b = scn%mesh%ngroups(ig)%items(i)
      c%normal = n
      c%g0 = dot_product(n, scn%mesh%x(:, c%node_b) - p)
      c%line = st%line
      call check_penetration(scn, st, c, stat, errmsg)
      if (stat /= STAT_OK) return
      scn%conditions = [scn%conditions, c]
    end do
  end subroutine do_obstacle

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
    real(dp) :: n(2), d, dbest
    logical :: given
    type(condition_t) :: c
    integer, allocatable :: pa(:), pb(:)
    kn = find_param(st, 'NODES')
    kw = find_param(st, 'WITH')
    kp = find_param(st, 'PAIRS')
    given = find_param(st, 'NORMAL') > 0
    if (given) then
      call get_unit(st, 'NORMAL', n, stat, errmsg)
      if (stat /= STAT_OK) return
    end if
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
      call node_group(scn, st, st%params(kn)%values(1), ga, stat, errmsg)
      if (stat /= STAT_OK) return
      call node_group(scn, st, st%params(kw)%values(1), gb, stat, errmsg)
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
      if (given) then
        c%normal = n
      else
        d = norm2(scn%mesh%x(:, b) - scn%mesh%x(:, a))
        if (d <= 1.0e-12_dp * model_size(scn%mesh)) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'nodes ' // str(a) // ' and ' // str(b) // &
            ' coincide: give NORMAL', st%lead(1)))
          return
        end if
        c%normal = (scn%mesh%x(:, b) - scn%mesh%x(:, a)) / d
      end if
      c%g0 = dot_product(c%normal, scn%mesh%x(:, b) - scn%mesh%x(:, a))
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
      node = scn%mesh%ngroups(g)%items(1)
    end subroutine one_node
  end subroutine do_gap

  !> Index in choices(:) of the word given to parameter key (default when absent).
  subroutine get_choice(st, key, choices, default, k, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key, choices(:), default
    integer, intent(out) :: k
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: w, names
    integer :: i
    call get_word(st, key, w, stat, errmsg, default=default)
    if (stat /= STAT_OK) return
    do k = 1, size(choices)
      if (upper(w) == trim(choices(k))) return
    end do
    names = trim(choices(1))
    do i = 2, size(choices)
      names = names // ' or ' // trim(choices(i))
    end do
    call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, key // ': expected ' // names, &
      st%params(find_param(st, key))%values(1)))
  end subroutine get_choice

  !> Parameters that the chosen law does not use are refused rather than ignored.
  subroutine check_law_params(st, law, stat, errmsg)
    type(statement_t), intent(in) :: st
    integer, intent(in) :: law
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=5), parameter :: keys(4) = [character(len=5) :: 'B', 'YIELD', 'H_ISO', 'H_KIN']
    logical :: allowed(4)
    integer :: i, k
    stat = STAT_OK
    select case (law)
    case (LAW_NONLINEAR_ELASTIC)
      allowed = [.true., .false., .false., .false.]
    case (LAW_ELASTOPLASTIC, LAW_VON_MISES)
      allowed = [.false., .true., .true., .true.]
    case default
      allowed = .false.
    end select
    do i = 1, size(keys)
      k = find_param(st, trim(keys(i)))
      if (k > 0 .and. .not. allowed(i)) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'parameter ' // trim(keys(i)) // &
          ' does not belong to this law', st%params(k)%keytok))
        return
      end if
    end do
  end subroutine check_law_params

  !> Two numbers of a parameter.
  subroutine get_pair(st, key, p, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    real(dp), intent(out) :: p(2)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call get_real(st, key, p(1), stat, errmsg, index=1)
    if (stat /= STAT_OK) return
    call get_real(st, key, p(2), stat, errmsg, index=2)
  end subroutine get_pair

  !> Value of a piecewise-linear function at time t (constant beyond its ends); 1 for ifn = 0.
  pure real(dp) function function_value(fns, ifn, t) result(f)
    type(function_t), intent(in) :: fns(:)
    integer, intent(in) :: ifn
    real(dp), intent(in) :: t
    integer :: i, n
    real(dp) :: s
    f = 1.0_dp
    if (ifn == 0) return
    associate (tt => fns(ifn)%t, ff => fns(ifn)%f)
      n = size(tt)
      if (t <= tt(1)) then
        f = ff(1)
      else if (t >= tt(n)) then
        f = ff(n)
      else
        do i = 2, n
          if (t <= tt(i)) exit
        end do
        s = (t - tt(i - 1)) / (tt(i) - tt(i - 1))
        f = (1.0_dp - s) * ff(i - 1) + s * ff(i)
      end if
    end associate
  end function function_value
end module scene
