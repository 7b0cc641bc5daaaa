!> The discrete system of a scene: DOF numbering, the element table (element_table.f90: every
!> integration point's weight and B, computed once), the sparse K0 and M on one pattern, the
!> loads, the points' states and the support reactions.
module assembly
  use kinds, only: dp, qp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str, check_alloc
  use mesh, only: DOF_NAMES, NODE_DOFS, DOF_AXIS, rigid_mode_row
  use element_traits, only: ET_BEAM2, etype_needs_material, etype_family, FAMILY_SURFACE, FAMILY_VOLUME, MAX_NEN
  use contact_modes, only: IMPACT_MASSLESS, IMPACT_SYMMETRIC
  use loads, only: load_nodal_forces
  use follower_loads, only: follower_set_t
  use scene, only: scene_t, probe_weight, function_value, model_point_kind, tuned_mix, contact_nodes, INIT_DISPLACEMENT, &
    INIT_VELOCITY, INIT_ANGULAR, &
    INIT_STATIC, TRANSLATION_SLOT
  use dof_map, only: build_dof_map, cayley_rotations, imposed_dofs, equation_bodies, DOF_ABSENT, DOF_FIXED
  use stiffness_product, only: k0_product_t
  use lapack_pure, only: dsyev
  use sparse_matrix, only: sym_csc_t
  use pair_blocks, only: pair_block_t
  use elements, only: elem_dof_mask, elem_ndof, elem_nstrain, elem_mass, &
    elem_elastic_d, MAX_EDOF, MAX_NSTRAIN
  use material_law, only: law_is_linear, law_nstate, law_stored, law_elastic_matrix, LAW_HYPERELASTIC, LAW_VON_MISES
  use law_hyperelastic, only: nh_lame, nh_mean_energy
  use checkpoint, only: ckpt_file_t
  use reactions, only: reaction_set_t
  use contact_mass, only: move_contact_mass, lump_contact_rows
  use element_table, only: element_table_t, build_element_table, add_btdb
  implicit none
  private
  public :: system_t, build_system, commit_state, external_force, &
    mass_times, initial_state, dof_label, dof_origin, stored_energy, mass_times_q, &
    save_points, load_points, damping_times, is_damped, reaction_update

  !> Nodal forces of one LOAD statement on the free DOFs (sparse).
  type :: load_vector_t
    integer, allocatable :: eq(:)
    real(dp), allocatable :: f(:)
    integer :: func = 0
  end type load_vector_t

  !> The DOF map: equations of the free DOFs (supports eliminated).
  type :: dof_table_t
    integer :: neq = 0                       !< free equations
    integer, allocatable :: eqn(:, :)        !< (3, nnode) equation of each node DOF (>0), fixed (-1), absent (0)
    logical, allocatable :: cayley(:)        !< (neq) a rotation turned by the Cayley angle of its increment
    integer, allocatable :: cayley_eq(:)     !< those equations (cayley_rotations)
  end type dof_table_t

  !> The integration-point states: committed (end of the last step) and trial; q internal
  !> variables. Saved and loaded with the checkpoints (save_points, load_points).
  type :: point_states_t
    real(dp), allocatable :: eps(:, :), sig(:, :), eps_t(:, :), sig_t(:, :), q(:, :), q_t(:, :)
    integer :: nq = 0                        !< internal variables per point (largest over models)
    ! Linear elastic points are evaluated on demand where Bσ is K0 u (stiffness_product): the
    ! committed (trial) arrays hold the committed (trial) u's points only when current (trial_current).
    logical :: current = .true., trial_current = .true.
    integer, allocatable :: nsub_pt(:)       !< SUBSTEPS AUTO: largest count chosen so far in the step
  end type point_states_t

  !> The operators on one sparse pattern: K0, M (and its diagonal when lumped), the tangent.
  type :: operators_t
    type(sym_csc_t) :: pat                   !< shared pattern of K0, M and the iteration matrix
    real(dp), allocatable :: kval(:), mval(:)
    logical :: mass_diagonal = .false.       !< every model lumped: M is its diagonal
    real(dp), allocatable :: mdiag(:)
    type(sym_csc_t) :: mpat                  !< M without its zeros (mass_times; sym_csc_t%compact)
    type(pair_block_t) :: mblk               !< M by node blocks, where they pay (mass_times; pair_blocks)
    real(dp), allocatable :: mcomp(:)
    real(dp), allocatable :: tval(:)         !< tangent stiffness on the pattern (ITERATION TANGENT)
    !> The compressive part of the LARGE surface elements' geometric stiffness (negative semi-
    !> definite), apart from tval: the iteration matrix adds it where S stays positive definite.
    real(dp), allocatable :: gval(:)
    !> The antisymmetric part of the Jacobian of eq (9)'s forces that tval (symmetric, for CHOLMOD)
    !> leaves out (wants_anti), its upper triangle on the pattern: iterate_eq9 takes it in with one
    !> more solve (anti_sweep).
    real(dp), allocatable :: aval(:)
    real(dp), allocatable :: cval(:)         !< Rayleigh damping C = Σ (alpha M_e + beta K0_e) (MODEL DAMPING)
    type(k0_product_t) :: k0u                !< Bσ = K0 u for a linear elastic small-strain model
  end type operators_t

  !> The external forces: M g, the LOAD statements' nodal vectors, the follower pressures.
  type :: load_set_t
    real(dp), allocatable :: fgrav(:)        !< M g on the free DOFs
    type(load_vector_t), allocatable :: vectors(:)
    type(follower_set_t), public :: fol      !< PRESSURE on KINEMATICS LARGE sides (follower_loads)
  end type load_set_t

  !> The discrete system of a scene, by role.
  type :: system_t
    type(dof_table_t) :: dofs
    type(element_table_t) :: elems
    type(point_states_t) :: pts
    type(operators_t) :: ops
    type(load_set_t) :: loads
    type(reaction_set_t) :: react            !< support reactions of the RX/RY/MZ probes
    ! SCHEME PRECISION EXTENDED: linear elastic points evaluated in quadruple precision.
    logical :: extended = .false.
    real(qp), allocatable :: fint_q(:)       !< internal forces of the last evaluation, unrounded
  end type system_t

contains

  !> "file:line" of the statement that created the node of equation ieq.
  function dof_origin(scn, sys, ieq) result(s)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    integer, intent(in) :: ieq
    character(len=:), allocatable :: s
    integer :: loc(2)
    loc = findloc(sys%dofs%eqn, ieq)
    s = scn%path // ':' // str(scn%node_line(loc(2)))
  end function dof_origin

  !> Name of an equation: "node N (x, y) DOF".
  function dof_label(scn, sys, ieq) result(s)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    integer, intent(in) :: ieq
    character(len=:), allocatable :: s
    integer :: loc(2)
    loc = findloc(sys%dofs%eqn, ieq)
    s = 'node ' // str(scn%mesh%node_tag(loc(2))) // ' (x = ' // str(scn%mesh%x(1, loc(2))) // ', y = ' // &
      str(scn%mesh%x(2, loc(2)))
    if (scn%mesh%ndim == 3) s = s // ', z = ' // str(scn%mesh%x(3, loc(2)))
    s = s // ') DOF ' // trim(DOF_NAMES(loc(1)))
  end function dof_label

  !> Number the DOFs, compute the element data, assemble K0, M and the load vectors.
  subroutine build_system(scn, sys, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(out) :: sys
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: ast, k
    integer, allocatable :: body(:)
    stat = STAT_OK
    call build_dof_map(scn, sys%dofs%eqn, sys%dofs%neq)
    call cayley_rotations(scn, sys%dofs%eqn, sys%dofs%neq, sys%dofs%cayley, sys%dofs%cayley_eq)
    call check_probes(scn, sys, stat, errmsg)
    if (stat /= STAT_OK) return
    if (sys%dofs%neq == 0) then
      call set_error(stat, errmsg, STAT_INPUT, scn%path // ':1: every degree of freedom is fixed: nothing moves')
      return
    end if
    call model_data(scn, sys)
    call build_element_table(scn, sys%dofs%eqn, sys%elems, stat, errmsg)
    if (stat /= STAT_OK) return
    call sys%loads%fol%build(scn, sys%dofs%eqn)             ! (before reaction_map, which adds to it)
    call reaction_map(scn, sys)
    call assemble_operators(scn, sys, stat, errmsg)
    if (stat /= STAT_OK) return
    if (scn%extended .and. is_damped(sys)) then
      associate (md => scn%models(findloc(scn%models%alpha > 0.0_dp .or. scn%models%beta > 0.0_dp, .true., 1)))
        call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(md%line) // ': MODEL ' // md%group // &
          ": DAMPING is not available with SCHEME PRECISION EXTENDED, at 'DAMPING'")
      end associate
      return
    end if
    call check_operators(scn, sys, stat, errmsg)
    if (stat /= STAT_OK) return
    call build_loads(scn, sys, stat, errmsg)
    if (stat /= STAT_OK) return
    associate (ngp => sys%elems%ngp, nq => sys%pts%nq)
      allocate (sys%pts%eps(MAX_NSTRAIN, ngp), sys%pts%sig(MAX_NSTRAIN, ngp), sys%pts%eps_t(MAX_NSTRAIN, ngp), &
        sys%pts%sig_t(MAX_NSTRAIN, ngp), sys%pts%nsub_pt(ngp), sys%pts%q(nq, ngp), sys%pts%q_t(nq, ngp), stat=ast)
      call check_alloc(ast, 'the states of ' // str(ngp) // ' integration points', &
        8.0_dp * ngp * (4.0_dp * MAX_NSTRAIN + 2.0_dp * nq) + 4.0_dp * ngp, stat, errmsg)
    end associate
    if (stat /= STAT_OK) return
    sys%pts%eps = 0.0_dp
    sys%pts%sig = 0.0_dp
    sys%pts%eps_t = 0.0_dp
    sys%pts%sig_t = 0.0_dp
    sys%pts%nsub_pt = 0
    sys%pts%q = 0.0_dp
    sys%pts%q_t = 0.0_dp
    sys%extended = scn%extended
    if (sys%extended) then
      allocate (sys%fint_q(sys%dofs%neq))
      sys%fint_q = 0.0_qp
    end if
    if (sys%elems%linear .and. .not. (sys%extended .or. scn%forces_points)) then
      call equation_bodies(scn, sys%dofs%eqn, sys%dofs%neq, body)
      call sys%ops%k0u%setup(sys%ops%pat, sys%ops%kval, sys%dofs%eqn, scn%mesh%x, body, held_modes(scn, sys, body))
    end if
    if (scn%tangent .and. .not. sys%elems%linear) then
      allocate (sys%ops%tval(sys%ops%pat%nnz))
      sys%ops%tval = sys%ops%kval
      if (any([(scn%models(k)%large .and. (etype_family(scn%models(k)%etype) == FAMILY_SURFACE .or. &
          etype_family(scn%models(k)%etype) == FAMILY_VOLUME), k = 1, size(scn%models))])) then
        allocate (sys%ops%gval(sys%ops%pat%nnz))
        sys%ops%gval = 0.0_dp
      end if
      if (any([(wants_anti(scn, k), k = 1, size(scn%models))])) then
        allocate (sys%ops%aval(sys%ops%pat%nnz))
        sys%ops%aval = 0.0_dp
      end if
    end if
  end subroutine build_system

  !> Whether model k's Jacobian of eq (9)'s forces has an antisymmetric part the tangent keeps apart
  !> (sys%ops%aval): LARGE surface and volume elements (the step's force at F_mid: large_plane's and
  !> large_solid's step tangent), and small-strain ones under VON_MISES (the law's path-mean dbar);
  !> none without the energy correction (the forces are then f(n+1), whose tangent is kept whole).
  logical function wants_anti(scn, k)
    type(scene_t), intent(in) :: scn
    integer, intent(in) :: k
    integer :: fam
    fam = etype_family(scn%models(k)%etype)
    wants_anti = .false.
    if (.not. scn%energy_correction) return
    if (fam /= FAMILY_SURFACE .and. fam /= FAMILY_VOLUME) return
    if (scn%models(k)%large) wants_anti = .true.
    if (scn%models(k)%material > 0) then
      if (scn%materials(scn%models(k)%material)%law == LAW_VON_MISES .and. .not. scn%models(k)%large) wants_anti = .true.
    end if
  end function wants_anti

  !> held(k, b): body b has an element acting on a fixed DOF where its rigid mode k (2D: UX, UY, the
  !> rotation about the origin; 3D: UX, UY, UZ, the rotations about x, y, z) does not vanish, so
  !> mode k is not a motion the body can make freely (stiffness_product). Structural, whatever the
  !> stiffness: a spring to a support 1e-12 times as stiff as the body still holds it. held(nm + 1, b)
  !> (nm = 3 or 6 modes): the supports leave body b a rigid motion that is none of its free modes (a
  !> pin, or rollers and a pin on other lines: the rigid motions vanishing at its fixed DOFs, the
  !> null space of their constraint rows, outnumber its modes not held): stiffness_product then keeps
  !> the element loop.
  function held_modes(scn, sys, body) result(held)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    integer, intent(in) :: body(:)
    logical, allocatable :: held(:, :)
    real(dp), allocatable :: g(:, :, :)
    real(dp) :: row(6), w(6), work(48), p(3)
    logical :: mask(NODE_DOFS)
    integer :: e, a, n, b, d, info, nm, nd
    nd = scn%mesh%ndim
    nm = merge(6, 3, nd == 3)                  ! 2D: x, y, the rotation; 3D: x, y, z, rotations x, y, z
    allocate (held(nm + 1, maxval(body)), g(nm, nm, maxval(body)))
    held = .false.
    g = 0.0_dp
    do e = 1, scn%mesh%nelem
      if (scn%elem_model(e) == 0) cycle
      mask = elem_dof_mask(scn%mesh%etype(e), scn%mesh%ndim)
      b = 0
      do a = 1, scn%mesh%nen(e)                ! the element's body: that of any free equation
        do d = 1, NODE_DOFS
          if (mask(d) .and. sys%dofs%eqn(d, scn%mesh%conn(a, e)) > 0) b = body(sys%dofs%eqn(d, scn%mesh%conn(a, e)))
        end do
      end do
      if (b == 0) cycle
      do a = 1, scn%mesh%nen(e)
        n = scn%mesh%conn(a, e)
        p = 0.0_dp
        p(1:nd) = scn%mesh%x(1:nd, n)
        do d = 1, NODE_DOFS
          if (.not. (mask(d) .and. sys%dofs%eqn(d, n) == DOF_FIXED)) cycle
          ! The fixed DOF's row: the modes there (2D, UX: 1, 0, -y; UY: 0, 1, x; RZ: 0, 0, 1; 3D, the
          ! translations, then the rotations' e_k x X along the DOF's axis).
          row = rigid_mode_row(d, p(1:nd))
          held(1:nm, b) = held(1:nm, b) .or. row(1:nm) /= 0.0_dp
          call dsyr_n(nm, row, g(:, :, b))
        end do
      end do
    end do
    do b = 1, size(held, 2)
      if (.not. any(held(1:nm, b))) cycle      ! free body: all its modes
      call dsyev('N', 'U', nm, g(:, :, b), nm, w, work, size(work), info)
      held(nm + 1, b) = info /= 0
      if (info == 0) held(nm + 1, b) = count(w(1:nm) <= 1.0e-12_dp * max(w(nm), tiny(1.0_dp))) > count(.not. held(1:nm, b))
    end do
  contains
    pure subroutine dsyr_n(m, r, gb)
      integer, intent(in) :: m
      real(dp), intent(in) :: r(:)
      real(dp), intent(inout) :: gb(:, :)
      integer :: i, j
      do j = 1, m
        do i = 1, m
          gb(i, j) = gb(i, j) + r(i) * r(j)
        end do
      end do
    end subroutine dsyr_n
  end function held_modes

  !> Per model: the elastic matrix D (K0 uses it, and the laws), the point kind, linearity and
  !> the number of internal variables.
  subroutine model_data(scn, sys)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    integer :: im, nstr, nmodel
    nmodel = size(scn%models)
    allocate (sys%elems%dmat(MAX_NSTRAIN, MAX_NSTRAIN, nmodel), sys%elems%pk(nmodel), sys%elems%model_linear(nmodel))
    sys%elems%dmat = 0.0_dp
    do im = 1, nmodel
      associate (md => scn%models(im))
        sys%elems%pk(im) = model_point_kind(md)
        sys%elems%model_linear(im) = .true.
        if (md%material > 0 .and. etype_needs_material(md%etype)) then
          nstr = elem_nstrain(md%etype)
          if (md%etype == ET_BEAM2 .and. md%sec%layers > 0) then
            ! Fibre section: the elastic matrix of the layers, as the fibre laws see it.
            call law_elastic_matrix(scn%materials(md%material), md%sec, sys%elems%pk(im), sys%elems%dmat(1:nstr, 1:nstr, im))
          else
            call elem_elastic_d(md%etype, scn%materials(md%material)%young, scn%materials(md%material)%poisson, &
              md%sec, sys%elems%dmat(1:nstr, 1:nstr, im))
          end if
          ! KINEMATICS LARGE: the strain is not linear in u, so the step iterates (docs/large-displacements.md).
          sys%elems%model_linear(im) = law_is_linear(scn%materials(md%material)) .and. .not. md%large
          sys%elems%any_large = sys%elems%any_large .or. md%large
          sys%elems%linear = sys%elems%linear .and. sys%elems%model_linear(im)
          sys%pts%nq = max(sys%pts%nq, law_nstate(scn%materials(md%material), sys%elems%pk(im), md%sec))
        end if
      end associate
    end do
  end subroutine model_data

  !> One pattern for K0, M and K0 + c M; K0 = Σ B'DB w, M (consistent or lumped per model) and
  !> the gravity load M g (g on the translations: the consistent body force of each element).
  subroutine assemble_operators(scn, sys, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: e, et, im, nen, ndof, nstr, igp, k, a, d, ast, nd
    logical :: mask(NODE_DOFS)
    real(dp) :: x(3, MAX_NEN), ke(MAX_EDOF, MAX_EDOF), me(MAX_EDOF, MAX_EDOF), g(MAX_EDOF), rho, mix
    real(dp) :: mlump(MAX_EDOF, MAX_EDOF), bl(MAX_NSTRAIN * MAX_EDOF)
    logical, allocatable :: massless(:), lumped_rows(:)
    logical :: damped
    if (scn%impact == IMPACT_MASSLESS) call contact_nodes(scn, massless)
    if (scn%impact == IMPACT_SYMMETRIC) call contact_nodes(scn, lumped_rows)
    call sys%ops%pat%build(sys%dofs%neq, sys%elems%edof_ptr, sys%elems%edof, stat, errmsg)
    if (stat /= STAT_OK) return
    damped = any(scn%models%alpha > 0.0_dp .or. scn%models%beta > 0.0_dp)
    if (damped) then
      allocate (sys%ops%cval(sys%ops%pat%nnz), stat=ast)
      call check_alloc(ast, 'the damping matrix', 8.0_dp * sys%ops%pat%nnz, stat, errmsg)
      if (stat /= STAT_OK) return
      sys%ops%cval = 0.0_dp
    end if
    allocate (sys%ops%kval(sys%ops%pat%nnz), sys%ops%mval(sys%ops%pat%nnz), sys%loads%fgrav(sys%dofs%neq), stat=ast)
    call check_alloc(ast, 'K0 and M (' // str(sys%ops%pat%nnz) // ' entries each)', &
      16.0_dp * sys%ops%pat%nnz + 8.0_dp * sys%dofs%neq, stat, errmsg)
    if (stat /= STAT_OK) return
    sys%ops%kval = 0.0_dp
    sys%ops%mval = 0.0_dp
    sys%loads%fgrav = 0.0_dp
    do e = 1, scn%mesh%nelem
      im = scn%elem_model(e)
      if (im == 0) cycle
      et = scn%mesh%etype(e)
      nen = scn%mesh%nen(e)
      ndof = elem_ndof(et, scn%mesh%ndim)
      nstr = elem_nstrain(et)
      associate (dofs => sys%elems%edof(sys%elems%edof_ptr(e):sys%elems%edof_ptr(e + 1) - 1))
        ke(1:ndof, 1:ndof) = 0.0_dp
        do igp = sys%elems%gp_ptr(e), sys%elems%gp_ptr(e + 1) - 1
          call sys%elems%point_b(igp, nstr, ndof, bl)
          call add_btdb(nstr, ndof, bl, sys%elems%dmat(1, 1, im), sys%elems%wt(igp), ke)
        end do
        if (nstr > 0) call sys%ops%pat%add_element(sys%ops%kval, dofs, ke(1:ndof, 1:ndof))
        nd = scn%mesh%ndim
        x(1:nd, 1:nen) = scn%mesh%x(:, scn%mesh%conn(1:nen, e))
        rho = 0.0_dp
        if (scn%models(im)%material > 0) rho = scn%materials(scn%models(im)%material)%density
        call elem_mass(et, x(1:nd, 1:nen), scn%models(im)%sec, rho, scn%models(im)%lumped, me(1:ndof, 1:ndof), &
          scn%models(im)%large)
        if (scn%models(im)%mixed) then
          ! MASS MIXED [alpha]: alpha x consistent + (1 - alpha) x lumped; TUNED: alpha from the step (docs/contact.md).
          call elem_mass(et, x(1:nd, 1:nen), scn%models(im)%sec, rho, .true., mlump(1:ndof, 1:ndof), scn%models(im)%large)
          mix = scn%models(im)%mix
          if (scn%models(im)%tuned) mix = tuned_mix(sqrt(scn%materials(scn%models(im)%material)%young / rho), scn%dt, &
            norm2(x(1:nd, 2) - x(1:nd, 1)))
          me(1:ndof, 1:ndof) = mix * me(1:ndof, 1:ndof) + (1 - mix) * mlump(1:ndof, 1:ndof)
        end if
        if (allocated(massless)) call move_contact_mass(scn%mesh%conn(1:nen, e), elem_dof_mask(et, scn%mesh%ndim), massless, &
          me(1:ndof, 1:ndof))
        if (allocated(lumped_rows)) call lump_contact_rows(scn%mesh%conn(1:nen, e), elem_dof_mask(et, scn%mesh%ndim), lumped_rows, &
          me(1:ndof, 1:ndof))
        call sys%ops%pat%add_element(sys%ops%mval, dofs, me(1:ndof, 1:ndof))
        if (damped) call sys%ops%pat%add_element(sys%ops%cval, dofs, scn%models(im)%alpha * me(1:ndof, 1:ndof) + &
          scn%models(im)%beta * ke(1:ndof, 1:ndof))
        mask = elem_dof_mask(et, scn%mesh%ndim)
        k = 0
        do a = 1, nen
          do d = 1, NODE_DOFS
            if (.not. mask(d)) cycle
            k = k + 1
            g(k) = 0.0_dp
            if (DOF_AXIS(d) > 0) g(k) = scn%gravity(DOF_AXIS(d))
          end do
        end do
        g(1:ndof) = matmul(me(1:ndof, 1:ndof), g(1:ndof))
        do k = 1, ndof
          if (dofs(k) > 0) sys%loads%fgrav(dofs(k)) = sys%loads%fgrav(dofs(k)) + g(k)
        end do
        if (sys%react%nslot > 0) call sys%react%add_couplings(e, dofs, me(1:ndof, 1:ndof), &
          scn%models(im)%alpha * me(1:ndof, 1:ndof) + scn%models(im)%beta * ke(1:ndof, 1:ndof), g(1:ndof))
      end associate
    end do
  end subroutine assemble_operators

  !> A DOF with neither mass nor stiffness makes K0 + 4M/h2 singular: refused, named. A mass
  !> matrix with no off-diagonal entry is kept as its diagonal (lumped).
  subroutine check_operators(scn, sys, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), allocatable :: dk(:), dm(:)
    integer :: i, k
    stat = STAT_OK
    allocate (dk(sys%dofs%neq), dm(sys%dofs%neq))
    call sys%ops%pat%diagonal(sys%ops%kval, dk)
    call sys%ops%pat%diagonal(sys%ops%mval, dm)
    do i = 1, sys%dofs%neq
      if (dk(i) <= 0.0_dp .and. dm(i) <= 0.0_dp) then
        call set_error(stat, errmsg, STAT_INPUT, dof_origin(scn, sys, i) // ': singular system: ' // &
          dof_label(scn, sys, i) // ' has neither mass nor stiffness (fix it, or give it a mass or an element)')
        return
      end if
    end do
    call check_inertia(scn, sys, dm, stat, errmsg)
    if (stat /= STAT_OK) return
    sys%ops%mass_diagonal = .true.
    do k = 1, sys%ops%pat%nnz
      if (sys%ops%mval(k) /= 0.0_dp) then
        if (.not. is_diagonal_position(sys%ops%pat, k)) sys%ops%mass_diagonal = .false.
      end if
    end do
    if (sys%ops%mass_diagonal) then
      sys%ops%mdiag = dm
    else
      call sys%ops%pat%compact(sys%ops%mval, sys%ops%mpat, sys%ops%mcomp)
      call sys%ops%mblk%build(sys%ops%mpat, sys%ops%mcomp)
    end if
  end subroutine check_operators

  !> A probe reads a DOF its node carries (a fixed one reads 0); a DOF no element of the node
  !> has (RZ of a point mass) is an input error, not a column of zeros.
  subroutine check_probes(scn, sys, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k
    logical :: held
    logical, allocatable :: imposed(:, :)
    stat = STAT_OK
    call imposed_dofs(scn, imposed)
    do k = 1, size(scn%probes)
      associate (p => scn%probes(k))
        if (p%reaction) then
          ! a fixed DOF, or an imposed one (IMPOSE), on a node of the group
          held = any(sys%dofs%eqn(p%dof, scn%mesh%ngroups(p%ngroup)%items) == DOF_FIXED) .or. &
            any(imposed(p%dof, scn%mesh%ngroups(p%ngroup)%items))
          if (p%about) held = any(sys%dofs%eqn(:, scn%mesh%ngroups(p%ngroup)%items) == DOF_FIXED) .or. &
            any(imposed(:, scn%mesh%ngroups(p%ngroup)%items))   ! (MZ ABOUT: any direction has an arm)
          if (held) cycle
          call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(p%line) // ': OUTPUT: PROBE ' // p%label // &
            ': no node of the group has this DOF fixed or imposed (a reaction is the force of a FIX or IMPOSE), at ''' // &
            p%label(index(p%label, '.', back=.true.) + 1:) // "'")
          return
        end if
        if (sys%dofs%eqn(p%dof, p%node) /= DOF_ABSENT) cycle
        call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(p%line) // ': OUTPUT: PROBE ' // p%label // &
          ': no element at this node has the DOF ' // trim(DOF_NAMES(p%dof)) // ", at '" // &
          p%label(index(p%label, '.', back=.true.) + 1:) // "'")
        return
      end associate
    end do
  end subroutine check_probes

  !> Every free DOF needs inertia: on a DOF without mass the trapezoid rule of eq (3) holds the
  !> force balance only on average over a step, so a DOF out of equilibrium (an initial
  !> displacement) alternates ±u every step. Refused, except the contact nodes IMPACT MASSLESS
  !> makes massless on purpose (their rows are handled by the contact) and the DOFs of IMPOSE
  !> (their rows are the imposed motion).
  subroutine check_inertia(scn, sys, dm, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: dm(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical, allocatable :: massless(:), imposed(:, :)
    integer :: n, d, i
    stat = STAT_OK
    if (scn%impact == IMPACT_MASSLESS) call contact_nodes(scn, massless)
    call imposed_dofs(scn, imposed)             ! IMPOSE: the motion is given, not integrated
    do n = 1, scn%mesh%nnode
      do d = 1, size(sys%dofs%eqn, 1)
        i = sys%dofs%eqn(d, n)
        if (i <= 0) cycle
        if (dm(i) > 0.0_dp .or. imposed(d, n)) cycle
        if (allocated(massless)) then
          if (massless(n)) cycle
        end if
        call set_error(stat, errmsg, STAT_INPUT, dof_origin(scn, sys, i) // ': ' // dof_label(scn, sys, i) // &
          ' has stiffness but no mass: the scheme needs inertia on every free DOF (give its elements a DENSITY, ' // &
          'add a MASS element, or FIX it)')
        return
      end do
    end do
  end subroutine check_inertia


  !> True when position k of the pattern is a diagonal entry.
  pure logical function is_diagonal_position(pat, k)
    type(sym_csc_t), intent(in) :: pat
    integer, intent(in) :: k
    integer :: lo, hi, mid
    ! column j holds positions colptr(j) .. colptr(j+1)-1; find j by bisection
    lo = 1
    hi = pat%n
    do while (lo < hi)
      mid = (lo + hi + 1) / 2
      if (pat%colptr(mid) <= k) then
        lo = mid
      else
        hi = mid - 1
      end if
    end do
    is_diagonal_position = pat%rowind(k) == lo
  end function is_diagonal_position

  !> The load vectors: each load statement's nodal forces (loads' load_nodal_forces) on the
  !> free equations, scaled by its function at each step (external_force).
  subroutine build_loads(scn, sys, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), allocatable :: fn(:, :)
    integer :: il, n, d, k, cnt
    stat = STAT_OK
    allocate (sys%loads%vectors(size(scn%loads)), fn(NODE_DOFS, scn%mesh%nnode))
    do il = 1, size(scn%loads)
      call load_nodal_forces(scn, scn%loads(il), fn)
      cnt = count(fn /= 0.0_dp .and. sys%dofs%eqn(:, 1:scn%mesh%nnode) > 0)
      allocate (sys%loads%vectors(il)%eq(cnt), sys%loads%vectors(il)%f(cnt))
      k = 0
      do n = 1, scn%mesh%nnode
        do d = 1, NODE_DOFS
          if (fn(d, n) /= 0.0_dp .and. sys%dofs%eqn(d, n) > 0) then
            k = k + 1
            sys%loads%vectors(il)%eq(k) = sys%dofs%eqn(d, n)
            sys%loads%vectors(il)%f(k) = fn(d, n)
          end if
        end do
      end do
      sys%loads%vectors(il)%func = scn%loads(il)%func
    end do
  end subroutine build_loads

  !> The PROBE … RX|RY|MZ slots: each entry is a local DOF of an element at a fixed DOF of the
  !> probe's direction in the probe's group (a node in several groups counts in each); and each
  !> load's force on those fixed DOFs.
  subroutine reaction_map(scn, sys)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    integer, allocatable :: slot_of(:), fslot(:, :)
    logical, allocatable :: member(:, :)
    real(dp), allocatable :: fn(:, :)
    logical :: mask(NODE_DOFS)
    integer :: k, s, e, a, d, n, loc, nfix
    real(dp) :: w
    slot_of = pack([(k, k = 1, size(scn%probes))], [(scn%probes(k)%reaction, k = 1, size(scn%probes))])
    sys%react%nprobe = size(slot_of)
    ! With FIELDS output, one more slot per fixed DOF of a modelled node: the support_reaction field.
    allocate (fslot(NODE_DOFS, scn%mesh%nnode))
    fslot = 0
    nfix = 0
    if (scn%fields_every /= 0) then
      do n = 1, scn%mesh%nnode
        do d = 1, NODE_DOFS
          if (sys%dofs%eqn(d, n) /= DOF_FIXED) cycle
          nfix = nfix + 1
          fslot(d, n) = sys%react%nprobe + nfix
        end do
      end do
    end if
    sys%react%nslot = sys%react%nprobe + nfix
    if (sys%react%nslot == 0) return
    allocate (sys%react%fnode(nfix), sys%react%fdof(nfix))
    do n = 1, scn%mesh%nnode
      do d = 1, NODE_DOFS
        if (fslot(d, n) == 0) cycle
        sys%react%fnode(fslot(d, n) - sys%react%nprobe) = n
        sys%react%fdof(fslot(d, n) - sys%react%nprobe) = d
      end do
    end do
    allocate (member(scn%mesh%nnode, sys%react%nprobe))
    member = .false.
    do s = 1, sys%react%nprobe
      member(scn%mesh%ngroups(scn%probes(slot_of(s))%ngroup)%items, s) = .true.
    end do
    allocate (sys%react%ent_ptr(scn%mesh%nelem + 1), sys%react%ent_loc(16), sys%react%ent_slot(16), sys%react%ent_w(16))
    sys%react%ent_ptr = 0
    do e = 1, scn%mesh%nelem
      sys%react%ent_ptr(e + 1) = sys%react%ent_ptr(e)
      if (scn%elem_model(e) == 0) cycle
      mask = elem_dof_mask(scn%mesh%etype(e), scn%mesh%ndim)
      loc = 0
      do a = 1, scn%mesh%nen(e)
        n = scn%mesh%conn(a, e)
        do d = 1, NODE_DOFS
          if (.not. mask(d)) cycle
          loc = loc + 1
          if (sys%dofs%eqn(d, n) /= DOF_FIXED) cycle
          do s = 1, sys%react%nprobe
            w = probe_weight(scn%probes(slot_of(s)), d, scn%mesh%x(:, n))
            if (w /= 0.0_dp .and. member(n, s)) call sys%react%add_entry(e, loc, s, w)
          end do
          if (fslot(d, n) > 0) call sys%react%add_entry(e, loc, fslot(d, n))
        end do
      end do
    end do
    call sys%react%finish_map(size(scn%loads))
    allocate (fn(NODE_DOFS, scn%mesh%nnode))
    do k = 1, size(scn%loads)
      call load_nodal_forces(scn, scn%loads(k), fn)
      do n = 1, scn%mesh%nnode
        do d = 1, NODE_DOFS
          if (fslot(d, n) > 0) sys%react%load(k, fslot(d, n)) = fn(d, n)
        end do
      end do
      do s = 1, sys%react%nprobe
        do n = 1, scn%mesh%nnode
          do d = 1, NODE_DOFS
            w = probe_weight(scn%probes(slot_of(s)), d, scn%mesh%x(:, n))
            if (fn(d, n) /= 0.0_dp .and. w /= 0.0_dp .and. sys%dofs%eqn(d, n) == DOF_FIXED .and. member(n, s)) &
              sys%react%load(k, s) = sys%react%load(k, s) + w * fn(d, n)
          end do
        end do
      end do
    end do
    ! The follower pressures' forces on those DOFs, evaluated on the configuration (reaction_update).
    associate (fol => sys%loads%fol)
      do k = 1, fol%n
        do a = 1, 2 * fol%nsn(k)
          if (fol%eq(a, k) /= DOF_FIXED) cycle
          n = fol%node((a + 1) / 2, k)
          d = 2 - mod(a, 2)
          if (fslot(d, n) > 0) call fol%add_reaction_entry(k, a, fslot(d, n))
          do s = 1, sys%react%nprobe
            w = probe_weight(scn%probes(slot_of(s)), d, scn%mesh%x(:, n))
            if (w /= 0.0_dp .and. member(n, s)) call fol%add_reaction_entry(k, a, s, w)
          end do
        end do
      end do
    end associate
  end subroutine reaction_map

  !> After the initial state (first) or a step ending at time t: the mean support reaction of
  !> the step for each RX/RY/MZ probe (reactions.f90), from the committed stresses of the
  !> elements at the supports.
  subroutine reaction_update(scn, sys, u, v, t, h, first)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    real(dp), intent(in) :: u(:), v(:), t, h
    logical, intent(in) :: first
    real(dp) :: fe(MAX_EDOF), bl(MAX_NSTRAIN * MAX_EDOF)
    integer :: e, il, p, ndof, nstr, igp, i, k
    if (sys%react%nslot == 0) return
    associate (r => sys%react)
      r%fint_w = 0.0_dp
      do e = 1, scn%mesh%nelem
        if (r%ent_ptr(e + 1) == r%ent_ptr(e)) cycle
        ndof = sys%elems%edof_ptr(e + 1) - sys%elems%edof_ptr(e)
        fe(1:ndof) = 0.0_dp
        nstr = sys%elems%nstr(e)
        do igp = sys%elems%gp_ptr(e), sys%elems%gp_ptr(e + 1) - 1
          call sys%elems%point_b(igp, nstr, ndof, bl)
          ! fe += w B'σ (B column-major, nstr x ndof); explicit loops: no temporaries.
          do k = 1, ndof
            do i = 1, nstr
              fe(k) = fe(k) + sys%elems%wt(igp) * bl((k - 1) * nstr + i) * sys%pts%sig(i, igp)
            end do
          end do
        end do
        do p = r%ent_ptr(e) + 1, r%ent_ptr(e + 1)
          r%fint_w(r%ent_slot(p)) = r%fint_w(r%ent_slot(p)) + r%ent_w(p) * fe(r%ent_loc(p))
        end do
      end do
      r%f_w = function_value(scn%functions, scn%gravity_func, t) * r%grav
      do il = 1, size(r%load, 1)
        r%f_w = r%f_w + function_value(scn%functions, sys%loads%vectors(il)%func, t) * r%load(il, :)
      end do
      call sys%loads%fol%add_reaction(scn, t, u, r%f_w)
      call r%step_mean(r%fint_w, r%f_w, u, v, h, first)
      r%fc_t = 0.0_dp
    end associate
  end subroutine reaction_update

  !> External forces at time t: gravity and the LOAD statements, times their functions; with u,
  !> the follower pressures on the configuration X + u.
  subroutine external_force(scn, sys, t, f, u)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: t
    real(dp), intent(out) :: f(:)
    real(dp), intent(in), optional :: u(:)   !< the configuration of the follower pressures (absent: none)
    integer :: il, k
    real(dp) :: s
    f = function_value(scn%functions, scn%gravity_func, t) * sys%loads%fgrav
    do il = 1, size(sys%loads%vectors)
      s = function_value(scn%functions, sys%loads%vectors(il)%func, t)
      ! An explicit loop: the vector-subscript form allocated temporaries at every step.
      do k = 1, size(sys%loads%vectors(il)%eq)
        f(sys%loads%vectors(il)%eq(k)) = f(sys%loads%vectors(il)%eq(k)) + s * sys%loads%vectors(il)%f(k)
      end do
    end do
    if (present(u)) call sys%loads%fol%add_force(scn, t, u, f)
  end subroutine external_force

  !> y = M x.
  subroutine mass_times(sys, x, y)
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: y(:)
    if (sys%ops%mass_diagonal) then
      y = sys%ops%mdiag * x
    else if (sys%ops%mblk%active()) then
      call sys%ops%mblk%matvec(x, y)
    else
      call sys%ops%mpat%matvec(sys%ops%mcomp, x, y)
    end if
  end subroutine mass_times

  !> True when a model has Rayleigh damping (MODEL DAMPING).
  pure logical function is_damped(sys)
    type(system_t), intent(in) :: sys
    is_damped = allocated(sys%ops%cval)
  end function is_damped

  !> y = C x, the Rayleigh damping matrix (is_damped only).
  subroutine damping_times(sys, x, y)
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: y(:)
    call sys%ops%pat%matvec(sys%ops%cval, x, y)
  end subroutine damping_times

  !> y = M x accumulated in quadruple precision (SCHEME PRECISION EXTENDED).
  subroutine mass_times_q(sys, x, y)
    type(system_t), intent(in) :: sys
    real(qp), intent(in) :: x(:)
    real(qp), intent(out) :: y(:)
    integer :: j, k, i
    if (sys%ops%mass_diagonal) then
      y = real(sys%ops%mdiag, qp) * x
      return
    end if
    y = 0.0_qp
    do j = 1, sys%ops%pat%n
      do k = sys%ops%pat%colptr(j), sys%ops%pat%colptr(j + 1) - 1
        i = sys%ops%pat%rowind(k)
        y(i) = y(i) + real(sys%ops%mval(k), qp) * x(j)
        if (i /= j) y(j) = y(j) + real(sys%ops%mval(k), qp) * x(i)
      end do
    end do
  end subroutine mass_times_q

  !> Recoverable elastic energy of the committed state (history column `stored`).
  real(dp) function stored_energy(scn, sys) result(w)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    integer :: e, im, igp, nstr, nq
    w = 0.0_dp
    do e = 1, scn%mesh%nelem
      im = scn%elem_model(e)
      if (im == 0) cycle
      if (sys%elems%gp_ptr(e + 1) == sys%elems%gp_ptr(e)) cycle
      nstr = elem_nstrain(scn%mesh%etype(e))
      nq = law_nstate(scn%materials(scn%models(im)%material), sys%elems%pk(im), scn%models(im)%sec)
      if (scn%models(im)%bbar .and. scn%materials(scn%models(im)%material)%law == LAW_HYPERELASTIC) then
        associate (g0 => sys%elems%gp_ptr(e), g1 => sys%elems%gp_ptr(e + 1) - 1, mat => scn%materials(scn%models(im)%material))
          w = w + nh_mean_energy(nh_lame(mat%young, mat%poisson), sys%elems%wt(g0:g1), sys%pts%eps(1:4, g0:g1))
        end associate
        cycle
      end if
      do igp = sys%elems%gp_ptr(e), sys%elems%gp_ptr(e + 1) - 1
        w = w + sys%elems%wt(igp) * law_stored(scn%materials(scn%models(im)%material), scn%models(im)%sec, sys%elems%pk(im), &
          sys%elems%dmat(1:nstr, 1:nstr, im), sys%pts%eps(1:nstr, igp), sys%pts%sig(1:nstr, igp), sys%pts%q(1:nq, igp))
      end do
    end do
  end function stored_energy

  !> Accept the trial state as the state at the end of the step.
  !> The arrays are swapped, not copied: internal_force writes every trial point before it
  !> reads it, so the stale values left in the trial arrays are never seen.
  subroutine commit_state(sys)
    type(system_t), intent(inout) :: sys
    real(dp), allocatable :: tmp(:, :)
    sys%pts%nsub_pt = 0
    sys%pts%current = sys%pts%trial_current
    call move_alloc(sys%pts%eps, tmp)
    call move_alloc(sys%pts%eps_t, sys%pts%eps)
    call move_alloc(tmp, sys%pts%eps_t)
    call move_alloc(sys%pts%sig, tmp)
    call move_alloc(sys%pts%sig_t, sys%pts%sig)
    call move_alloc(tmp, sys%pts%sig_t)
    if (sys%pts%nq > 0) then
      call move_alloc(sys%pts%q, tmp)
      call move_alloc(sys%pts%q_t, sys%pts%q)
      call move_alloc(tmp, sys%pts%q_t)
    end if
  end subroutine commit_state

  !> The committed integration-point state (strains, stresses, internal variables) into an
  !> open checkpoint, and back (sticky stat, as ckpt_file_t).
  subroutine save_points(sys, ck, stat, errmsg)
    type(system_t), intent(in) :: sys
    type(ckpt_file_t), intent(inout) :: ck
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call ck%put('eps', sys%pts%eps, stat, errmsg)
    call ck%put('sig', sys%pts%sig, stat, errmsg)
    if (sys%pts%nq > 0) call ck%put('q', sys%pts%q, stat, errmsg)
  end subroutine save_points

  subroutine load_points(sys, ck, stat, errmsg)
    type(system_t), intent(inout) :: sys
    type(ckpt_file_t), intent(inout) :: ck
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call ck%get('eps', sys%pts%eps, stat, errmsg)
    call ck%get('sig', sys%pts%sig, stat, errmsg)
    sys%pts%current = .true.
    if (sys%pts%nq > 0) call ck%get('q', sys%pts%q, stat, errmsg)
  end subroutine load_points

  !> Initial displacement and velocity from the INITIAL statements. STATIC FORCE preloads are
  !> returned in fstatic (the caller solves K0 u = fstatic and adds it). Values given to fixed
  !> DOFs are ignored: the support wins (INITIAL on a whole body that is also clamped).
  subroutine initial_state(scn, sys, u, v, fstatic, has_static, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(out) :: u(:), v(:), fstatic(:)
    logical, intent(out) :: has_static
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: ic, i, d, n, j
    real(dp) :: s, w3(3)
    stat = STAT_OK
    u = 0.0_dp
    v = 0.0_dp
    fstatic = 0.0_dp
    has_static = .false.
    do ic = 1, size(scn%initials)
      associate (c => scn%initials(ic), nodes => scn%mesh%ngroups(scn%initials(ic)%ngroup)%items)
        do i = 1, size(nodes)
          n = nodes(i)
          if (c%kind == INIT_ANGULAR .and. scn%mesh%ndim == 3) then   ! ω × (X - x0) on UX, UY, UZ
            w3 = scn%mesh%x(:, n) - c%about
            w3 = [c%omega(2) * w3(3) - c%omega(3) * w3(2), c%omega(3) * w3(1) - c%omega(1) * w3(3), &
              c%omega(1) * w3(2) - c%omega(2) * w3(1)]
            do d = 1, 3
              j = sys%dofs%eqn(TRANSLATION_SLOT(d), n)
              if (j > 0) v(j) = v(j) + w3(d)
            end do
            cycle
          end if
          if (c%kind == INIT_ANGULAR) then          ! ω × (X - x0) on UX, UY; ω on RZ
            w3 = [-(scn%mesh%x(2, n) - c%about(2)), scn%mesh%x(1, n) - c%about(1), 1.0_dp]
            do d = 1, 3                             ! (2D: UX UY RZ)
              j = sys%dofs%eqn(d, n)
              if (j > 0) v(j) = v(j) + c%values(3) * w3(d)
            end do
            cycle
          end if
          ! FUNCTION f ALONG X|Y: the values times f of the node's coordinate (1 without).
          s = function_value(scn%functions, c%func, scn%mesh%x(c%along, n))
          do d = 1, NODE_DOFS
            if (.not. c%mask(d)) cycle
            j = sys%dofs%eqn(d, n)
            ! Supports win over initial values: a fixed (or absent) DOF keeps zero.
            if (j <= 0) cycle
            select case (c%kind)
            case (INIT_DISPLACEMENT)                ! (INITIALs add up: one sets each component, initial_once)
              u(j) = u(j) + s * c%values(d)
            case (INIT_VELOCITY)
              v(j) = v(j) + s * c%values(d)
            case (INIT_STATIC)
              fstatic(j) = fstatic(j) + c%values(d)
              has_static = .true.
            end select
          end do
        end do
      end associate
    end do
  end subroutine initial_state
end module assembly
