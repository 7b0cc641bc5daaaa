!> Scene input: the models (MODEL): element group, formulation, material, section, mass, sub-increments.
!> Their grammar (schema) and their handlers; scene_loader calls them.
module scene_models
  use kinds, only: dp, zero_tol
  use errors, only: STAT_OK, STAT_INPUT, set_error, str, upper
  use material_law, only: material_t, law_check, law_is_linear, LAW_ELASTOPLASTIC, LAW_VON_MISES, LAW_ELASTIC, &
    law_nearly_isochoric
  use law_types, only: NSUB_EXACT
  use statement, only: statement_t, stmt_error, find_param, get_int, get_word, get_real
  use statement_schema, only: schema_t
  use elements, only: elem_check_geometry
  use scene, only: scene_t, model_t, fix_t, MAX_SUBSTEPS, model_point_kind
  use scene_helpers, only: get_etype, model_size
  use number_text, only: real_text
  use element_traits, only: FAMILY_LINE, etype_family, etypes_of_family, etype_needs_material, etype_section_needs, &
    etype_name, etype_nen, ET_MASS, ET_BAR2, ET_BEAM2, ET_QUAD4, ET_TRI3, FAMILY_SURFACE, etype_dimension, MAX_NEN, DOF_UX, &
    ET_HEX8, ET_TET4
  implicit none
  private
  public :: models_schema, models_statement, default_mass, check_tuned

  !> c h/dx above 1 by less than this is 1: the rounding of c, h and dx of a step meant as dx/c.
  real(dp), parameter :: COURANT_TOL = 1.0e-9_dp

  real(dp), parameter :: MAX_DAMPING = 1.0e100_dp   !< DAMPING ALPHA and BETA at most

contains

  subroutine models_schema(sch)
    type(schema_t), intent(inout) :: sch
    call sch%add_keyword('MODEL', 1, 1)
    call sch%add_param('MODEL', 'TYPE', 1, 1)
    call sch%add_param('MODEL', 'MATERIAL', 1, 1)
    call sch%add_param('MODEL', 'SECTION', 1, 1)
    call sch%add_param('MODEL', 'MASS', 1, 2)
    call sch%add_param('MODEL', 'PLANE', 1, 1)
    call sch%add_param('MODEL', 'SUBSTEPS', 1, 1)
    call sch%add_param('MODEL', 'KINEMATICS', 1, 1)
    call sch%add_param('MODEL', 'STRAIN_MEASURE', 1, 1)
    call sch%add_param('MODEL', 'DAMPING', 2, 4)
    call sch%add_param('MODEL', 'FORMULATION', 1, 1)
    call sch%add_param('MODEL', 'AXISYMMETRIC', 0, 0)
  end subroutine models_schema

  !> One models statement (pass 2 of load_scene).
  subroutine models_statement(scn, st, path, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: path
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    select case (st%keyword)
    case ('MODEL')
      call do_model(scn, st, stat, errmsg)
    end select
  end subroutine models_statement

  subroutine do_model(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(model_t) :: md
    integer :: ig, e, i, k, et0, isec, imodel
    character(len=:), allocatable :: w, msg
    real(dp) :: x(3, MAX_NEN), msize
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
        if (etype_family(et0) == FAMILY_LINE) then
          call get_etype(st, 'TYPE', etypes_of_family(FAMILY_LINE), md%etype, stat, errmsg)
        else
          call get_etype(st, 'TYPE', [et0], md%etype, stat, errmsg)
        end if
        if (stat /= STAT_OK) return
      end if
    end associate
    if (etype_dimension(md%etype) /= scn%mesh%ndim .and. md%etype /= ET_MASS) then   ! (a MASS lives in either)
      if (scn%mesh%ndim == 3) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, etype_name(md%etype) // ' elements in a DIMENSION 3 ' // &
          'scene (3D elements: HEX8, HEX20, TET4, TET10, WEDGE6, and MASS)', st%lead(1)))
      else
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, etype_name(md%etype) // ' elements in a planar scene ' // &
          '(they need DIMENSION 3)', st%lead(1)))
      end if
      return
    end if
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
    else if (etype_needs_material(md%etype)) then
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
    else if (len(etype_section_needs(md%etype)) > 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'missing parameter SECTION (required for ' // &
        etype_name(md%etype) // ')', st%lead(1)))
      return
    else
      md%sec%name = '(default)'
    end if
    call check_section(st, md, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_mass(st, md, stat, errmsg)
    if (stat /= STAT_OK) return
    call get_word(st, 'SUBSTEPS', w, stat, errmsg, default='AUTO')
    if (stat /= STAT_OK) return
    if (upper(w) == 'AUTO') then
      md%substeps = 0
    else if (upper(w) == 'EXACT') then
      md%substeps = NSUB_EXACT
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
    call get_axisymmetric(st, md, scn, stat, errmsg)
    if (stat == STAT_OK) call get_damping(st, md, stat, errmsg)
    if (stat == STAT_OK) call get_kinematics(st, md, stat, errmsg)
    if (stat /= STAT_OK) return
    if (md%material > 0) call check_model_law(st, md, scn%materials(md%material), stat, errmsg)
    if (stat == STAT_OK) call get_strain(st, md, scn, stat, errmsg)
    if (stat == STAT_OK) call get_formulation(st, md, scn, stat, errmsg)
    if (stat == STAT_OK .and. scn%mesh%ndim == 3) call check_solid_model(st, md, stat, errmsg)
    if (stat /= STAT_OK) return
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
        x(1:scn%mesh%ndim, 1:etype_nen(md%etype)) = scn%mesh%x(:, scn%mesh%conn(1:etype_nen(md%etype), e))
        call elem_check_geometry(md%etype, x(1:scn%mesh%ndim, 1:etype_nen(md%etype)), md%sec, stat, msg, size_ref=msize)
        if (stat /= STAT_OK) then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, etype_name(md%etype) // ' element ' // str(i) // &
            ' of group ' // md%group // ' (nodes ' // node_list([(scn%mesh%node_tag(scn%mesh%conn(k, e)), &
            k = 1, etype_nen(md%etype))]) // '): ' &
            // msg, st%lead(1)))
          return
        end if
        scn%elem_model(e) = imodel
      end do
    end associate
    if (md%sec%axisymmetric) call axis_support(scn, st, md, msize, stat, errmsg)
    if (stat /= STAT_OK) return
    scn%models = [scn%models, md]
  end subroutine do_model

  !> AXISYMMETRIC (docs/input.md, "Axisymmetric models"): surface elements only, not with PLANE,
  !> and a scene whose surface models are all axisymmetric or all planar, without bars or beams
  !> (a bar's or a beam's section has no meaning as a ring); springs and point masses are rings.
  subroutine get_axisymmetric(st, md, scn, stat, errmsg)
    type(statement_t), intent(in) :: st
    type(model_t), intent(inout) :: md
    type(scene_t), intent(in) :: scn
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, im
    stat = STAT_OK
    k = find_param(st, 'AXISYMMETRIC')
    md%sec%axisymmetric = k > 0
    do im = 1, size(scn%models)
      if (k > 0 .and. (scn%models(im)%etype == ET_BAR2 .or. scn%models(im)%etype == ET_BEAM2)) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'AXISYMMETRIC in a scene with ' // &
          etype_name(scn%models(im)%etype) // ' elements (model of group ' // scn%models(im)%group // ', line ' // &
          str(scn%models(im)%line) // '): a bar or a beam is not a ring', st%params(k)%keytok))
      else if ((md%etype == ET_BAR2 .or. md%etype == ET_BEAM2) .and. scn%models(im)%sec%axisymmetric) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, etype_name(md%etype) // ' in an axisymmetric scene ' // &
          '(model of group ' // scn%models(im)%group // ', line ' // str(scn%models(im)%line) // &
          '): a bar or a beam is not a ring', st%lead(1)))
      else if (etype_family(md%etype) == FAMILY_SURFACE .and. etype_family(scn%models(im)%etype) == FAMILY_SURFACE &
               .and. (scn%models(im)%sec%axisymmetric .neqv. k > 0)) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'a scene is axisymmetric or planar: the model of ' // &
          'group ' // scn%models(im)%group // ' (line ' // str(scn%models(im)%line) // ') is ' // &
          trim(merge('axisymmetric', 'planar      ', scn%models(im)%sec%axisymmetric)), st%lead(1)))
      end if
      if (stat /= STAT_OK) return
    end do
    if (k == 0) return
    if (etype_family(md%etype) /= FAMILY_SURFACE) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'AXISYMMETRIC is for surface elements (QUAD4, QUAD8, ' // &
        'TRI3, TRI6), not ' // etype_name(md%etype), st%params(k)%keytok))
    else if (find_param(st, 'PLANE') > 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'AXISYMMETRIC with PLANE: a model is plane strain, ' // &
        'plane stress or axisymmetric', st%params(find_param(st, 'PLANE'))%keytok))
    else if (md%sec%has_thickness) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'AXISYMMETRIC with SECTION ' // md%sec%name // &
        ' which gives a THICKNESS: an axisymmetric model is the whole ring (2 pi r), it has no thickness', &
        st%params(find_param(st, 'SECTION'))%values(1)))
    end if
  end subroutine get_axisymmetric

  !> An axisymmetric model's nodes: x = r >= 0 (a node at r < 0, beyond zero_tol of the model's
  !> size, is refused, named by its tag), and the nodes on the axis (|r| within that tolerance)
  !> held at u_r = 0 by a support of their own, the node group "(axis of GROUP)", which the run
  !> announces (scene_report).
  subroutine axis_support(scn, st, md, msize, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    type(model_t), intent(in) :: md
    real(dp), intent(in) :: msize
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical, allocatable :: on_axis(:)
    type(fix_t) :: fx
    integer :: i, a, n, e
    stat = STAT_OK
    allocate (on_axis(scn%mesh%nnode))
    on_axis = .false.
    associate (items => scn%mesh%egroups(md%egroup)%items)
      do i = 1, size(items)
        e = items(i)
        do a = 1, etype_nen(md%etype)
          n = scn%mesh%conn(a, e)
          if (scn%mesh%x(1, n) < -zero_tol * msize) then
            call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'AXISYMMETRIC: node ' // str(scn%mesh%node_tag(n)) // &
              ' of group ' // md%group // ' is at r = x = ' // real_text(scn%mesh%x(1, n)) // ' < 0 (x is the radius, ' // &
              'y the axis)', st%params(find_param(st, 'AXISYMMETRIC'))%keytok))
            return
          end if
          on_axis(n) = scn%mesh%x(1, n) <= zero_tol * msize
        end do
      end do
    end associate
    if (.not. any(on_axis)) return
    call scn%mesh%add_node_group('(axis of ' // md%group // ')', pack([(n, n = 1, scn%mesh%nnode)], on_axis))
    fx%ngroup = scn%mesh%nngroup
    fx%dofs = .false.
    fx%dofs(DOF_UX) = .true.
    fx%line = st%line
    scn%fixes = [scn%fixes, fx]
  end subroutine axis_support

  !> MASS CONSISTENT | LUMPED | MIXED [alpha] | TUNED: the element mass alpha x consistent + (1 - alpha)
  !> x lumped (MIXED alone: alpha = 1/2). Above 1 the consistent part is extrapolated: allowed on BAR2
  !> up to 3/2 excluded (where the element mass stops being positive definite), for the mass tuned
  !> to the step, alpha = 1/2 + (c h / dx)^2, which TUNED takes element by element (tuned_mix;
  !> docs/contact.md, "A mass tuned to the step"; c h/dx <= 1 checked by check_tuned).
  subroutine get_mass(st, md, stat, errmsg)
    type(statement_t), intent(in) :: st
    type(model_t), intent(inout) :: md
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: w
    integer :: ip
    call get_word(st, 'MASS', w, stat, errmsg, default='CONSISTENT')
    if (stat /= STAT_OK) return
    ip = find_param(st, 'MASS')
    md%mass_said = ip /= 0
    select case (upper(w))
    case ('CONSISTENT')
      md%lumped = .false.
    case ('LUMPED')
      md%lumped = .true.
    case ('MIXED')
      md%mixed = .true.
    case ('TUNED')
      md%mixed = .true.
      md%tuned = .true.
      if (md%etype /= ET_BAR2) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'TUNED is the rule of a 1D bar: BAR2 models only (' // &
          etype_name(md%etype) // ' elements; MIXED alpha for them)', st%params(ip)%values(1)))
        return
      end if
    case default
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected CONSISTENT, LUMPED, MIXED or TUNED', &
        st%params(ip)%values(1)))
      return
    end select
    if (ip == 0) return
    if (size(st%params(ip)%values) < 2) return
    if (.not. md%mixed .or. md%tuned) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'a mixing factor follows MIXED only', &
        st%params(ip)%values(2)))
      return
    end if
    if (md%etype == ET_BAR2) then
      call get_real(st, 'MASS', md%mix, stat, errmsg, index=2, lower=0.0_dp, lower_inclusive=.true., &
        upper=1.5_dp, upper_inclusive=.false.)
    else
      call get_real(st, 'MASS', md%mix, stat, errmsg, index=2, lower=0.0_dp, lower_inclusive=.true., &
        upper=1.0_dp, upper_inclusive=.true.)
      if (stat /= STAT_OK) errmsg = errmsg // ' (above 1 on BAR2 only: ' // etype_name(md%etype) // ' elements)'
    end if
  end subroutine get_mass

  !> The mass of a model that says no MASS: TUNED on a small-displacement, linear elastic BAR2 model
  !> whose every element has c h/dx <= 1 (the step resolves the wave, where the tuned mass is measured
  !> best: rebound, release and contact force, docs/contact.md "The default mass"), CONSISTENT
  !> otherwise (Cast3M's). The rule tunes the elastic wave: a nonlinear law slows it (near 3/2 the
  !> mass's shortest wave then needs sub-steps to converge), and LARGE's rotations turn it into
  !> transverse motion.
  subroutine default_mass(scn)
    type(scene_t), intent(inout) :: scn
    integer :: i, k, e
    real(dp) :: c, r
    do i = 1, size(scn%models)
      associate (md => scn%models(i))
        if (md%mass_said .or. md%etype /= ET_BAR2 .or. md%large .or. md%material == 0) cycle
        associate (mat => scn%materials(md%material))
          if (.not. law_is_linear(mat) .or. mat%density <= 0.0_dp .or. mat%young <= 0.0_dp) cycle
          c = sqrt(mat%young / mat%density)
        end associate
        r = 0.0_dp
        associate (items => scn%mesh%egroups(md%egroup)%items)
          do k = 1, size(items)
            e = items(k)
            r = max(r, courant(scn, c, e))
          end do
        end associate
        if (r > 1.0_dp + COURANT_TOL) cycle
        md%mixed = .true.
        md%tuned = .true.
      end associate
    end do
  end subroutine default_mass

  !> MASS TUNED needs c h/dx <= 1 on every element of the model (past it the rule would pass 3/2, where
  !> the mass stops being positive definite), and a wave speed: the first element past it is named.
  !> A model at c h/dx = 1 on every element is marked tuned_exact (IMPACT AUTO takes PERSIST there).
  subroutine check_tuned(scn, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: i, k, e
    real(dp) :: c, r
    stat = STAT_OK
    do i = 1, size(scn%models)
      associate (md => scn%models(i))
        if (.not. md%tuned) cycle
        associate (mat => scn%materials(md%material))
          if (mat%density <= 0.0_dp .or. mat%young <= 0.0_dp) then
            call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(md%line) // ': MODEL ' // md%group // &
              ': MASS TUNED needs the wave speed of material ' // mat%name // " (YOUNG and DENSITY > 0), at 'TUNED'")
            return
          end if
          c = sqrt(mat%young / mat%density)
        end associate
        md%tuned_exact = .true.
        associate (items => scn%mesh%egroups(md%egroup)%items)
          do k = 1, size(items)
            e = items(k)
            r = courant(scn, c, e)
            if (r > 1.0_dp + COURANT_TOL) then
              call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(md%line) // ': MODEL ' // md%group // &
                ': MASS TUNED needs c h/dx <= 1 (element ' // str(k) // ' of the group: ' // real_text(r) // &
                "; a smaller TIME STEP or MIXED alpha), at 'TUNED'")
              return
            end if
            if (r < 1.0_dp - COURANT_TOL) md%tuned_exact = .false.
          end do
        end associate
      end associate
    end do
  end subroutine check_tuned

  !> c h/dx of 2-node element e of the scene (wave speed c, the TIME STEP).
  pure real(dp) function courant(scn, c, e)
    type(scene_t), intent(in) :: scn
    real(dp), intent(in) :: c
    integer, intent(in) :: e
    courant = c * scn%dt / norm2(scn%mesh%x(:, scn%mesh%conn(2, e)) - scn%mesh%x(:, scn%mesh%conn(1, e)))
  end function courant

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

  !> What a DIMENSION 3 model offers so far (HEX8 and TET4, ELASTIC and VON_MISES, small strain; B-bar
  !> HEX8): its other options are refused by name rather than ignored.
  subroutine check_solid_model(st, md, stat, errmsg)
    type(statement_t), intent(in) :: st
    type(model_t), intent(inout) :: md
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=16), parameter :: refused(2) = [character(len=16) :: 'PLANE', 'AXISYMMETRIC']
    integer :: k, ip
    stat = STAT_OK
    do k = 1, size(refused)
      ip = find_param(st, trim(refused(k)))
      if (ip == 0) cycle
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, trim(refused(k)) // ' is not a property of ' // &
        etype_name(md%etype) // ' elements (3D solids)', st%params(ip)%keytok))
      return
    end do
    ! KINEMATICS LARGE on solids: St Venant-Kirchhoff or J2 on (E, S), FORMULATION STANDARD (large_solid).
    ip = find_param(st, 'STRAIN_MEASURE')
    if (md%log_strain) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'STRAIN_MEASURE LOG is not available on ' // &
        etype_name(md%etype) // ' yet (3D solids: GREEN)', st%params(ip)%values(1)))
      return
    end if
    if (md%large .and. md%bbar) then
      ip = find_param(st, 'FORMULATION')
      if (ip > 0) then
        if (upper(st%params(ip)%values(1)%text) == 'BBAR') then
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'FORMULATION BBAR with KINEMATICS LARGE is not ' // &
            'available on ' // etype_name(md%etype) // ' yet (STANDARD)', st%params(ip)%values(1)))
          return
        end if
      end if
    end if
    if (md%large) md%bbar = .false.              ! (AUTO: STANDARD, the only LARGE solid formulation)
    if (md%tuned .and. md%mass_said) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, &
      'MASS TUNED is for 2-node bars (3D solids: CONSISTENT, LUMPED or MIXED)', st%params(find_param(st, 'MASS'))%keytok))
  end subroutine check_solid_model

  !> The section characteristics an element type needs.
  subroutine check_section(st, md, stat, errmsg)
    type(statement_t), intent(in) :: st
    type(model_t), intent(in) :: md
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: need, needs
    stat = STAT_OK
    need = ''
    needs = etype_section_needs(md%etype)
    if (index(needs, 'MASS') > 0 .and. md%sec%mass <= 0.0_dp) need = 'MASS > 0'
    if (index(needs, 'AREA') > 0 .and. md%sec%area <= 0.0_dp) need = 'AREA'
    ! A fibre section (LAYERS) integrates its inertia over the layers: INERTIA is not used.
    if (index(needs, 'INERTIA') > 0 .and. md%sec%inertia <= 0.0_dp .and. md%sec%layers == 0) then
      if (len(need) > 0) need = need // ' and '
      need = need // 'INERTIA'
    end if
    if (len(need) > 0) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'section ' // md%sec%name // &
      ' lacks ' // trim(need) // ' needed by ' // etype_name(md%etype) // ' elements', st%lead(1)))
  end subroutine check_section

  !> Which laws an element type accepts (1D laws on springs, bars and fibre beams, J2 on
  !> quads) and what they need: material_law's law_check, with the statement's file:line; SUBSTEPS
  !> EXACT for laws with a potential only.
  subroutine check_model_law(st, md, mat, stat, errmsg)
    type(statement_t), intent(in) :: st
    type(model_t), intent(in) :: md
    type(material_t), intent(in) :: mat
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: msg
    call law_check(mat, model_point_kind(md), md%sec, stat, msg)
    if (stat /= STAT_OK) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'material ' // mat%name // ' on ' // &
        etype_name(md%etype) // ' elements: ' // msg, st%params(find_param(st, 'MATERIAL'))%values(1)))
    else if (md%substeps == NSUB_EXACT .and. (mat%law == LAW_ELASTOPLASTIC .or. mat%law == LAW_VON_MISES)) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'SUBSTEPS EXACT is the discrete gradient of a law with a ' // &
        'potential (NONLINEAR_ELASTIC; ELASTIC and HYPERELASTIC are exact already); the work of material ' // mat%name // &
        ' depends on its path: use SUBSTEPS N or AUTO', st%params(find_param(st, 'SUBSTEPS'))%values(1)))
    end if
  end subroutine check_model_law
  !> DAMPING ALPHA a BETA b (either or both, a, b >= 0): Rayleigh damping C = a M + b K0 of the
  !> model's elements (K0: the initial stiffness).
  !> KINEMATICS SMALL | LARGE (default SMALL). LARGE exists for BAR2 and SPRING (the axial
  !> strain of the current length), BEAM2 (corotational) and the surface elements (total
  !> Lagrangian: ELASTIC, St Venant-Kirchhoff, or HYPERELASTIC, checked with the scene),
  !> docs/large-displacements.md; a SPRING with a DIRECTION (zero length) has no current axis.
  subroutine get_kinematics(st, md, stat, errmsg)
    type(statement_t), intent(in) :: st
    type(model_t), intent(inout) :: md
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: w
    call get_word(st, 'KINEMATICS', w, stat, errmsg, default='SMALL')
    if (stat /= STAT_OK) return
    select case (upper(w))
    case ('SMALL')
      md%large = .false.
    case ('LARGE')
      md%large = .true.
      if (md%etype == ET_MASS) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'KINEMATICS LARGE has no form for ' // &
          etype_name(md%etype) // ' elements (a point mass has no strain; BAR2, SPRING, BEAM2, QUAD4, QUAD8, TRI3 ' // &
          'and TRI6 and the solids have one)', &
          st%params(find_param(st, 'KINEMATICS'))%values(1)))
      else if (md%sec%has_direction) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'KINEMATICS LARGE: a SPRING with a DIRECTION has no ' // &
          'current axis', st%params(find_param(st, 'KINEMATICS'))%values(1)))
      end if
    case default
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected SMALL or LARGE', &
        st%params(find_param(st, 'KINEMATICS'))%values(1)))
    end select
  end subroutine get_kinematics

  !> STRAIN_MEASURE GREEN | LOG (default GREEN): the strain measure of a KINEMATICS LARGE surface element.
  !> LOG, the Hencky strain ½ ln C with its conjugate stress (docs/large-displacements.md, "Large
  !> plastic strains"): ELASTIC is then the Hencky material and VON_MISES J2 additive in the
  !> logarithmic strain, for large plastic strains (plane strain or plane stress: the law finds the
  !> thickness's log strain as in small strain). HYPERELASTIC is its own finite-strain law.
  subroutine get_strain(st, md, scn, stat, errmsg)
    type(statement_t), intent(in) :: st
    type(model_t), intent(inout) :: md
    type(scene_t), intent(in) :: scn
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: w
    integer :: k, law
    stat = STAT_OK
    k = find_param(st, 'STRAIN_MEASURE')
    if (k == 0) return
    call get_word(st, 'STRAIN_MEASURE', w, stat, errmsg)
    if (stat /= STAT_OK) return
    law = 0
    if (md%material > 0) law = scn%materials(md%material)%law
    if (upper(w) /= 'GREEN' .and. upper(w) /= 'LOG') then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected GREEN or LOG', st%params(k)%values(1)))
    else if (.not. md%large .or. etype_family(md%etype) == FAMILY_LINE .or. md%material == 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'STRAIN_MEASURE is the strain measure of a KINEMATICS LARGE ' // &
        'surface element (QUAD4, QUAD8, TRI3, TRI6)', st%params(k)%values(1)))
    else if (upper(w) == 'LOG' .and. law /= LAW_ELASTIC .and. law /= LAW_VON_MISES) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'STRAIN_MEASURE LOG works with ELASTIC (Hencky) and ' // &
        'VON_MISES; material ' // scn%materials(md%material)%name // ' is its own finite-strain law', st%params(k)%values(1)))
    else
      md%log_strain = upper(w) == 'LOG'
    end if
  end subroutine get_strain

  !> FORMULATION AUTO | BBAR | STANDARD (default AUTO): BBAR gives every point of a plane-strain
  !> surface element the element's mean dilatation (docs/locking.md): in small strain B-bar, the
  !> in-plane trace of B replaced by its volume mean over the element's points; in KINEMATICS LARGE
  !> the same on the strain the law sees (with STRAIN_MEASURE LOG the in-plane trace of the Hencky
  !> strain is ln J: F-bar, J replaced by the element's geometric mean), the points' in-plane
  !> pressure by the element's mean in the forces. The strain stays linear in the points' strains,
  !> so eq (9)'s discrete gradients and the energy identity are unchanged. AUTO: BBAR for QUAD4 in
  !> plane strain with VON_MISES (isochoric flow: standard QUAD4 locks) or ELASTIC or HYPERELASTIC with
  !> POISSON >= 0.49 (a ν = 0.4999 cantilever deflects 6 % of its due at 80 x 8: tests/scenes/locking;
  !> HYPERELASTIC then keeps its volumetric energy λ/2 ln² J on the element's mean ln J),
  !> STANDARD otherwise. TRI3 has one point (nothing to average: use QUAD4 or TRI6); plane stress
  !> has no volumetric constraint to relieve (the thickness is free).
  subroutine get_formulation(st, md, scn, stat, errmsg)
    type(statement_t), intent(in) :: st
    type(model_t), intent(inout) :: md
    type(scene_t), intent(in) :: scn
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: w
    integer :: k
    logical :: auto
    stat = STAT_OK
    auto = (md%etype == ET_QUAD4 .or. md%etype == ET_HEX8) .and. .not. md%sec%plane_stress .and. md%material > 0
    if (auto) auto = law_nearly_isochoric(scn%materials(md%material))
    md%bbar = auto
    k = find_param(st, 'FORMULATION')
    if (k == 0) return
    call get_word(st, 'FORMULATION', w, stat, errmsg)
    if (stat /= STAT_OK) return
    select case (upper(w))
    case ('STANDARD')
      md%bbar = .false.
    case ('AUTO')
      md%bbar = auto
    case ('BBAR')
      if ((etype_family(md%etype) /= FAMILY_SURFACE .and. md%etype /= ET_HEX8 .and. md%etype /= ET_TET4) .or. &
          md%material == 0) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'FORMULATION BBAR is for surface elements (QUAD4, ' // &
          'QUAD8, TRI6) and HEX8 with a material', st%params(k)%values(1)))
      else if (md%etype == ET_TRI3 .or. md%etype == ET_TET4) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'FORMULATION BBAR on ' // etype_name(md%etype) // &
          ': its one point is its mean already (it locks under isochoric flow: use QUAD4 or HEX8, which take ' // &
          'BBAR)', st%params(k)%values(1)))
      else if (md%sec%plane_stress) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'FORMULATION BBAR in plane stress: the thickness is ' // &
          'free, there is no volumetric locking to relieve (PLANE STRAIN takes it)', st%params(k)%values(1)))
      else
        md%bbar = .true.
      end if
    case default
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected AUTO, BBAR or STANDARD', st%params(k)%values(1)))
    end select
  end subroutine get_formulation

  subroutine get_damping(st, md, stat, errmsg)
    type(statement_t), intent(in) :: st
    type(model_t), intent(inout) :: md
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, i
    real(dp) :: x
    stat = STAT_OK
    md%alpha = 0.0_dp
    md%beta = 0.0_dp
    k = find_param(st, 'DAMPING')
    if (k == 0) return
    associate (vals => st%params(k)%values)
      if (mod(size(vals), 2) /= 0) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'DAMPING takes pairs: ALPHA a and/or BETA b', &
          vals(size(vals))))
        return
      end if
      do i = 1, size(vals), 2
        ! a, b within [0, 1e100] (C = a M + b K0 and its products with velocities stay finite)
        call get_real(st, 'DAMPING', x, stat, errmsg, index=i + 1, lower=0.0_dp, lower_inclusive=.true., &
          upper=MAX_DAMPING, upper_inclusive=.true.)
        if (stat /= STAT_OK) return
        if (i > 1) then
          if (upper(vals(i)%text) == upper(vals(1)%text)) then
            call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'DAMPING gives ' // upper(vals(i)%text) // &
              ' twice', vals(i)))
            return
          end if
        end if
        select case (upper(vals(i)%text))
        case ('ALPHA')
          md%alpha = x
        case ('BETA')
          md%beta = x
        case default
          call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'expected ALPHA or BETA', vals(i)))
          return
        end select
      end do
    end associate
  end subroutine get_damping
end module scene_models
