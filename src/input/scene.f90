!> The scene: everything a run needs, built from a keyword file (docs/input.md) after the
!> command-line overrides. Statements are interpreted in two passes so that the order of
!> definitions and their uses does not matter, except inside the mesh (a GROUP or ELEMENT
!> refers to groups defined above it).
module scene
  use kinds, only: dp
  use array_utils, only: bracket
  use errors, only: upper
  use mesh, only: mesh_t, NODE_DOFS, DOF_UX, DOF_UY, DOF_UZ
  use mesh_segments, only: segment_set_t
  use element_traits, only: etype_point_kind
  use section, only: section_t
  use material_law, only: material_t
  use contact_modes, only: IMPACT_AUTO, SOLVER_AUTO, SWITCH_DEFAULT
  use spd_factor, only: LIBRARY_AUTO
  implicit none
  private
  public :: scene_t, model_t, fix_t, initial_t, load_t, function_t, probe_t
  public :: function_value, model_point_kind, tuned_mix, scene_axisymmetric
  public :: INIT_DISPLACEMENT, INIT_VELOCITY, INIT_STATIC, INIT_ANGULAR, condition_t, condition_nodes, contact_nodes, &
    condition_keyword, condition_row, condition_tangent
  public :: impose_t, function_slope, probe_weight, function_integral, function_prepare

  real(dp), parameter :: TUNED_MAX = 1.4999_dp  !< MASS TUNED's mixing factor at c h/dx = 1
  real(dp), parameter :: TWO_PI = 6.283185307179586476925286766559_dp
  !> The DOF slots of the translations along x, y, z.
  integer, parameter, public :: TRANSLATION_SLOT(3) = [DOF_UX, DOF_UY, DOF_UZ]

  !> The most nodes of a condition: b and a face of 8 (condition_nodes).
  integer, parameter, public :: COND_NODES = 9
  integer, parameter :: INIT_DISPLACEMENT = 1, INIT_VELOCITY = 2, INIT_STATIC = 3, INIT_ANGULAR = 4
  integer, parameter, public :: SPIN_LINE = 2 * NODE_DOFS + 1   !< scene_t%initial_line's ANGULAR_VELOCITY row
  integer, parameter, public :: LOAD_NODAL = 0, LOAD_PRESSURE = 1, LOAD_TRACTION = 2
  !> Upper bounds of SECTION LAYERS and MODEL SUBSTEPS (far above any useful value; see do_section, do_model).
  integer, parameter, public :: MAX_LAYERS = 1000, MAX_SUBSTEPS = 10000

  !> One unilateral contact condition (method.md section 3): a node b against a rigid plane
  !> (node_a = 0: g = g0 + n.u_b), against a node a (g = g0 + n.(u_b - u_a)), against the
  !> point at xi along the segment from node a to node c (node_c > 0, GAP … SEGMENTS:
  !> g = g0 + n.(u_b - (1 - xi) u_a - xi u_c)), or in 3D against the point of a solid's face
  !> (face(1) > 0, GAP … FACES: g = g0 + n.(u_b - Σ N_k u_face(k)), node_a the face's node of the
  !> largest weight, for messages); condition_nodes gives the nodes and weights.
  type :: condition_t
    character(len=:), allocatable :: source   !< the OBSTACLE or GAP statement's name
    integer :: node_a = 0, node_b = 0
    integer :: node_c = 0                     !< second end of the segment (0: node to node or plane)
    integer :: face(8) = 0                    !< GAP … FACES: the face's nodes (0: not a face)
    real(dp) :: face_w(8) = 0.0_dp            !< their weights N_k(ξ, η) at b's foot on the face
    real(dp) :: xi = 0.0_dp                   !< position of the contact point along a -> c
    real(dp) :: normal(3) = 0.0_dp           !< unit normal (x, y[, z]; z = 0 in 2D)
    real(dp) :: g0 = 0.0_dp
    real(dp) :: restitution = 1.0_dp          !< RESTITUTION e: normal velocity after an impact = -e x before
    real(dp) :: friction = 0.0_dp             !< FRICTION mu: Coulomb's coefficient (0: frictionless)
    integer :: line = 0
    integer :: segset = 0                     !< GAP … SEGMENTS: its segments, scene%segsets(segset)
    logical :: follow = .false.               !< re-paired in the configuration of every step (LARGE)
    integer :: side = 0                       !< following, on a line element: b's side of the chain (pair_segment)
    integer :: curved = 0                     !< OBSTACLE … SPHERE|CYLINDER: +1 OUTSIDE, -1 INSIDE (0: a plane or a GAP)
    real(dp) :: center(2) = 0.0_dp, radius = 0.0_dp   !< the curved obstacle's circle
    !> OBSTACLE … VELOCITY vx vy [FUNCTION f]: the obstacle translates rigidly at velocity x f(t),
    !> its displacement velocity x ∫ f from the start time (function_integral); vfunc 0: f = 1.
    logical :: moving = .false.
    real(dp) :: velocity(3) = 0.0_dp          !< (vx, vy[, vz])
    integer :: vfunc = 0
  end type condition_t

  !> MODELE: an element group with its formulation, material, section and mass kind.
  type :: model_t
    character(len=:), allocatable :: group
    integer :: egroup = 0
    integer :: etype = 0          !< element type of every element of the model
    integer :: material = 0       !< index in scene%materials (0 for MASS elements)
    type(section_t) :: sec        !< copy of the section, with the model's plane option
    logical :: lumped = .false.
    logical :: mixed = .false.    !< MASS MIXED: mix x consistent + (1 - mix) x lumped
    real(dp) :: mix = 0.5_dp      !< MASS MIXED's mixing factor (1/2 unless given)
    logical :: tuned = .false.    !< MASS TUNED: each element's mix from the step (tuned_mix)
    logical :: tuned_exact = .false. !< TUNED with c h/dx = 1 on every element: the exact lattice (1D)
    logical :: mass_said = .false. !< MASS given; otherwise default_mass chooses (TUNED or CONSISTENT)
    integer :: substeps = 0       !< sub-increments of the laws (Cast3M SOUS_INCREMENT); 0 = AUTO, NSUB_EXACT = EXACT
    logical :: large = .false.    !< KINEMATICS LARGE: strains from the current configuration
    logical :: log_strain = .false. !< STRAIN_MEASURE LOG: a LARGE surface element on the Hencky strain
    logical :: bbar = .false.     !< FORMULATION BBAR: the element's mean dilatation at its points (B-bar, F-bar)
    real(dp) :: alpha = 0.0_dp    !< DAMPING ALPHA: Rayleigh C = alpha M + beta K0 of the model (1/s)
    real(dp) :: beta = 0.0_dp     !< DAMPING BETA (s)
    integer :: line = 0
  end type model_t

  !> BLOQUE: homogeneous supports on DOFs of a node group.
  type :: fix_t
    integer :: ngroup = 0
    logical :: dofs(NODE_DOFS) = .false.   !< the DOF slots held (mesh's DOF_*)
    integer :: line = 0
  end type fix_t

  !> Initial displacement or velocity on a node group, or a static preload (released at t = 0).
  type :: initial_t
    integer :: kind = 0
    integer :: ngroup = 0
    real(dp) :: values(NODE_DOFS) = 0.0_dp  !< per DOF slot (mesh's DOF_*)
    logical :: mask(NODE_DOFS) = .false.
    integer :: func = 0           !< FUNCTION f ALONG X|Y: values times f(x) or f(y) of each node (0: none)
    integer :: along = 1          !< the coordinate f is evaluated at: 1 (X), 2 (Y) or 3 (Z, in 3D)
    integer :: line = 0
    real(dp) :: about(3) = 0.0_dp !< ANGULAR_VELOCITY w ABOUT x y: the axis (w in values(3)); 3D: the point x y z
    real(dp) :: omega(3) = 0.0_dp !< 3D: ANGULAR_VELOCITY wx wy wz
  end type initial_t

  !> Piecewise-linear function of time, constant beyond its ends.
  !> FUNCTION kinds (docs/input.md, "Functions"): a table of points (POINTS, or TABLE FILE), a sine,
  !> a smooth step.
  integer, parameter, public :: FN_TABLE = 0, FN_SINE = 1, FN_SMOOTH_STEP = 2

  type :: function_t
    character(len=:), allocatable :: name
    integer :: kind = FN_TABLE
    real(dp), allocatable :: t(:), f(:)   !< FN_TABLE: the points (times increasing), linear between
    !> FN_SINE: amplitude sin(2π frequency (t - start) + phase) on [start, finish], 0 outside;
    !> FN_SMOOTH_STEP: 0 up to start, 1 from finish, ξ³(10 - 15ξ + 6ξ²) between (ξ from 0 to 1).
    real(dp) :: amplitude = 1.0_dp, frequency = 0.0_dp, phase = 0.0_dp
    real(dp) :: start = 0.0_dp, finish = huge(1.0_dp)
    real(dp), allocatable :: cum(:)       !< FN_TABLE: ∫ f from t(1) to t(i) (function_prepare)
  end type function_t

  !> Nodal forces on every node of a group, times a function of time.
  !> LOAD (nodal forces), PRESSURE or TRACTION (on the free element sides of a node group,
  !> src/assembly/loads.f90): force(1:3) the nodal force and moment, force(1) the pressure,
  !> force(1:2) the traction.
  type :: load_t
    character(len=:), allocatable :: name
    integer :: kind = LOAD_NODAL
    integer :: ngroup = 0
    real(dp) :: force(NODE_DOFS) = 0.0_dp   !< LOAD: per DOF slot; PRESSURE: p in force(1); TRACTION: force(1:2)
    integer :: func = 0          !< 0: constant 1
    logical :: dead = .false.    !< PRESSURE … DEAD: a dead load on a KINEMATICS LARGE model too
  end type load_t

  !> IMPOSE: the displacement value x f(t) on DOF dof (1 UX, 2 UY, 3 RZ) of every node of a group.
  type :: impose_t
    integer :: ngroup = 0
    integer :: dof = 0
    real(dp) :: value = 1.0_dp
    integer :: func = 0
    integer :: line = 0
  end type impose_t

  type :: probe_t
    character(len=:), allocatable :: label   !< group.DOF
    integer :: node = 0
    integer :: dof = 0
    logical :: velocity = .false.            !< VX, VY, VRZ: the velocity of the DOF
    logical :: reaction = .false.            !< RX, RY, RZ: the support reaction, summed over the group
    integer :: ngroup = 0                    !< the probed node group
    integer :: line = 0
    logical :: about = .false.               !< MZ ABOUT x0 y0: the moment of the group's reactions about x0
    real(dp) :: x0(2) = 0.0_dp
  end type probe_t

  type :: scene_t
    character(len=:), allocatable :: path, title
    type(mesh_t) :: mesh
    type(material_t), allocatable :: materials(:)
    type(section_t), allocatable :: sections(:)
    type(model_t), allocatable :: models(:)
    integer, allocatable :: elem_model(:)     !< (nelem) model of each element, 0 = not modelled
    integer, allocatable :: node_line(:)      !< (nnode) line of the statement that created each node
    logical, allocatable :: modelled(:)       !< (nnode) the node carries an element of some MODEL (after pass 2)
    !> (SPIN_LINE, nnode) the line of the INITIAL that set DOF slot d of a node's DISPLACEMENT
    !> (d) or VELOCITY (NODE_DOFS + d), or its ANGULAR_VELOCITY (SPIN_LINE); 0: not set
    integer, allocatable :: initial_line(:, :)
    type(fix_t), allocatable :: fixes(:)
    type(initial_t), allocatable :: initials(:)
    type(function_t), allocatable :: functions(:)
    type(load_t), allocatable :: loads(:)
    type(impose_t), allocatable :: imposes(:)
    real(dp) :: gravity(3) = 0.0_dp            !< GRAVITY GX GY [GZ] (m/s2)
    integer :: gravity_func = 0
    real(dp) :: t_start = 0.0_dp, t_end = 0.0_dp, dt = 0.0_dp
    !> TIME … ADAPTIVE TOLERANCE tol [MIN hmin] [MAX hmax] (step_control)
    logical :: adaptive = .false.
    real(dp) :: adapt_tol = 0.0_dp, adapt_hmin = 0.0_dp, adapt_hmax = 0.0_dp
    real(dp) :: tolerance = 1.0e-10_dp
    integer :: max_iterations = 25
    integer :: retry = 4                      !< SCHEME RETRY: a failed step is retried as up to 2^retry sub-steps
    logical :: energy_correction = .true.     !< add Bσc of eq (9)
    logical :: energy_test = .true.           !< SCHEME ENERGY_TEST: the residual's work in eq (9)'s convergence test
    ! (The defaults are SCHEME's: ITERATION AUTO also in a scene without a SCHEME statement.)
    logical :: tangent = .true.               !< the consistent tangent is assembled (ITERATION TANGENT or AUTO)
    logical :: iter_auto = .true.             !< ITERATION AUTO: K0 + 4M/h² until the tangent pays (iteration_matrix)
    integer :: zone = 1                       !< SCHEME ZONE: 1 AUTO, 2 ON, 3 OFF (nonlinear_zone)
    logical :: forces_points = .false.        !< SCHEME FORCES POINTS: linear models' Bσ by the element loop too
    integer :: events = 1                     !< SCHEME EVENTS: 1 AUTO, 2 LOCATE, 3 OFF
    logical :: locate_events = .false.        !< contact events located (LOCATE, or AUTO on the exact lattice)
    logical :: iteration_given = .false.      !< SCHEME ITERATION was given (else TANGENT with KINEMATICS LARGE)
    logical :: extended = .false.             !< SCHEME PRECISION EXTENDED
    integer :: modes = 0                      !< MODES n: the n lowest natural frequencies (0: none)
    real(dp) :: modes_above = -1.0_dp         !< MODES … ABOVE f0 (Hz; < 0: from the lowest)
    integer :: modes_line = 0                 !< the MODES statement's line
    integer :: static_steps = 0               !< STATIC STEPS n: the preload's increments (0: no STATIC)
    integer :: static_max_iter = 50           !< STATIC MAX_ITERATIONS: Newton iterations per increment
    real(dp) :: static_tol = 1.0e-10_dp       !< STATIC TOLERANCE: residual / force scale
    integer :: static_line = 0                !< the STATIC statement's line
    integer :: time_zero_line = 0             !< TIME END = START (a MODES-only run): its line
    integer :: history_every = 1
    integer :: fields_every = -1              !< -1: first and last step only; 0: never
    integer :: checkpoint_every = 0           !< OUTPUT CHECKPOINT EVERY k (0: none)
    type(probe_t), allocatable :: probes(:)
    type(condition_t), allocatable :: conditions(:)   !< unilateral contacts (OBSTACLE, GAP)
    type(segment_set_t), allocatable :: segsets(:)    !< the segments of each GAP … SEGMENTS statement
    integer :: impact = IMPACT_AUTO                   !< SCHEME IMPACT (AUTO resolved at load: scene_contacts)
    logical :: impact_auto = .false.                  !< the treatment was chosen by IMPACT AUTO
    integer :: multipliers = SOLVER_AUTO              !< SCHEME MULTIPLIERS (contact_modes)
    integer :: augmented_above = SWITCH_DEFAULT       !< SCHEME AUGMENTED_ABOVE (AUTO's switch)
    integer :: linear_solver = LIBRARY_AUTO           !< SCHEME SOLVER (spd_factor's LIBRARY_*)
    logical :: out_of_core = .false.                  !< SCHEME SOLVER MUMPS OUT_OF_CORE
    character(len=:), allocatable :: fingerprint      !< what a checkpoint's state means (scene_fingerprint)
  end type scene_t


contains

  !> Whether the scene's surface models are axisymmetric (x = r, y the axis; all or none are:
  !> scene_models): its forces, masses, momenta and energies are those of the whole ring.
  pure logical function scene_axisymmetric(scn)
    type(scene_t), intent(in) :: scn
    integer :: im
    scene_axisymmetric = .false.
    if (.not. allocated(scn%models)) return
    do im = 1, size(scn%models)
      if (scn%models(im)%sec%axisymmetric) scene_axisymmetric = .true.
    end do
  end function scene_axisymmetric

  !> The nodes of a condition and their weights along its normal: g = g0 + n.Σ_k w(k) u(node(k))
  !> over the nodes(k) > 0 (b first, then a and c; or b, then a face's nodes).
  pure subroutine condition_nodes(c, nodes, w)
    type(condition_t), intent(in) :: c
    integer, intent(out) :: nodes(COND_NODES)
    real(dp), intent(out) :: w(COND_NODES)
    nodes = 0
    w = 0.0_dp
    if (c%face(1) > 0) then
      nodes = [c%node_b, c%face]
      w = [1.0_dp, -c%face_w]
      where (nodes == 0) w = 0.0_dp
      return
    end if
    nodes(1:3) = [c%node_b, c%node_a, c%node_c]
    w(1:3) = [1.0_dp, -(1.0_dp - c%xi), -c%xi]
    if (c%node_c == 0) w(2) = -1.0_dp
    where (nodes == 0) w = 0.0_dp
  end subroutine condition_nodes

  !> FRICTION's tangent k of condition c (the slip and the tangential force are along the
  !> tangents). 2D (ndim 2): one tangent, the normal turned by +90° about z. 3D: two, t1 the unit
  !> part normal to n of the coordinate axis least aligned with n (the first of equals), t2 = n × t1:
  !> on a floor n = z, t1 = x and t2 = y.
  pure function condition_tangent(c, ndim, k) result(t)
    type(condition_t), intent(in) :: c
    integer, intent(in) :: ndim
    integer, intent(in), optional :: k
    real(dp) :: t(3)
    real(dp) :: e(3), n(3)
    if (ndim /= 3) then
      t = [-c%normal(2), c%normal(1), 0.0_dp]
      return
    end if
    n = c%normal
    e = 0.0_dp
    e(minloc(abs(n), 1)) = 1.0_dp
    t = e - dot_product(e, n) * n
    t = t / norm2(t)
    if (present(k)) then
      if (k == 2) t = [n(2) * t(3) - n(3) * t(2), n(3) * t(1) - n(1) * t(3), n(1) * t(2) - n(2) * t(1)]
    end if
  end function condition_tangent

  !> Condition c's row along the unit vector dir (x, y, z: its normal, or its tangent) on the
  !> translations UX UY UZ of its nodes (condition_nodes' weights; eqn the DOF map):
  !> entries eqs(3k-2:3k) and coefs(3k-2:3k) for node k, eqs 0 where a node or a DOF is absent
  !> (UZ in 2D, where dir(3) = 0).
  pure subroutine condition_row(c, dir, eqn, eqs, coefs)
    type(condition_t), intent(in) :: c
    real(dp), intent(in) :: dir(3)
    integer, intent(in) :: eqn(:, :)
    integer, intent(out) :: eqs(3 * COND_NODES)
    real(dp), intent(out) :: coefs(3 * COND_NODES)
    integer :: k, d, nodes(COND_NODES)
    real(dp) :: w(COND_NODES)
    call condition_nodes(c, nodes, w)
    eqs = 0
    do k = 1, COND_NODES
      coefs(3 * k - 2:3 * k) = w(k) * dir
      if (nodes(k) == 0) cycle
      do d = 1, 3
        eqs(3 * k - 3 + d) = max(eqn(TRANSLATION_SLOT(d), nodes(k)), 0)
      end do
    end do
  end subroutine condition_row

  !> The statement a condition comes from, for messages: OBSTACLE (no node a) or GAP.
  pure function condition_keyword(c) result(k)
    type(condition_t), intent(in) :: c
    character(len=:), allocatable :: k
    if (c%node_a == 0 .and. c%face(1) == 0) then
      k = 'OBSTACLE'
    else
      k = 'GAP'
    end if
  end function condition_keyword

  !> mark(n): node n is in a contact condition (either side of a GAP, a segment's ends).
  pure subroutine contact_nodes(scn, mark)
    type(scene_t), intent(in) :: scn
    logical, allocatable, intent(out) :: mark(:)
    integer :: j, nodes(COND_NODES)
    real(dp) :: w(COND_NODES)
    allocate (mark(scn%mesh%nnode))
    mark = .false.
    do j = 1, size(scn%conditions)
      call condition_nodes(scn%conditions(j), nodes, w)
      where (nodes > 0) mark(max(nodes, 1)) = .true.
    end do
  end subroutine contact_nodes

  !> MASS TUNED's mixing factor for a bar element of length ell, wave speed c, step h: 1/2 + (c h/ell)^2
  !> cancels the trapezoidal rule's phase lag against the mass's lead at second order, so the phase
  !> error of the uniform lattice is fourth order in dx (docs/contact.md, "A mass tuned to the step").
  !> At c h/ell = 1 it would be 3/2, where the element mass is singular: TUNED_MAX (3/2 - 1e-4) there.
  pure real(dp) function tuned_mix(c, h, ell)
    real(dp), intent(in) :: c, h, ell
    tuned_mix = min(0.5_dp + (c * h / ell)**2, TUNED_MAX)
  end function tuned_mix

  !> Material-point kind of a model's integration points (material_law PK_*; 0 for masses).
  pure integer function model_point_kind(md) result(pk)
    type(model_t), intent(in) :: md
    pk = etype_point_kind(md%etype, md%sec%plane_stress)
  end function model_point_kind


  !> Value of a piecewise-linear function at time t (constant beyond its ends); 1 for ifn = 0.
  pure real(dp) function function_value(fns, ifn, t) result(f)
    type(function_t), intent(in) :: fns(:)
    integer, intent(in) :: ifn
    real(dp), intent(in) :: t
    integer :: i
    real(dp) :: s
    f = 1.0_dp
    if (ifn == 0) return
    associate (fn => fns(ifn))
      select case (fn%kind)
      case (FN_SINE)
        f = 0.0_dp
        if (t >= fn%start .and. t <= fn%finish) f = fn%amplitude * sin(TWO_PI * fn%frequency * (t - fn%start) + fn%phase)
      case (FN_SMOOTH_STEP)
        s = min(max((t - fn%start) / (fn%finish - fn%start), 0.0_dp), 1.0_dp)
        f = s**3 * (10.0_dp - 15.0_dp * s + 6.0_dp * s * s)
      case default
        i = bracket(fn%t, t)
        if (i == 0) then
          f = fn%f(1)
        else if (i == size(fn%t)) then
          f = fn%f(i)
        else
          s = (t - fn%t(i)) / (fn%t(i + 1) - fn%t(i))
          f = (1.0_dp - s) * fn%f(i) + s * fn%f(i + 1)
        end if
      end select
    end associate
  end function function_value

  !> The right derivative of a FUNCTION at t (0 beyond a table's ends and outside a sine's or a
  !> step's interval; 0 for ifn = 0, the constant 1).
  pure real(dp) function function_slope(fns, ifn, t) result(d)
    type(function_t), intent(in) :: fns(:)
    integer, intent(in) :: ifn
    real(dp), intent(in) :: t
    integer :: i
    real(dp) :: s, w
    d = 0.0_dp
    if (ifn == 0) return
    associate (fn => fns(ifn))
      select case (fn%kind)
      case (FN_SINE)
        if (t >= fn%start .and. t < fn%finish) d = fn%amplitude * TWO_PI * fn%frequency * &
          cos(TWO_PI * fn%frequency * (t - fn%start) + fn%phase)
      case (FN_SMOOTH_STEP)
        w = fn%finish - fn%start
        s = (t - fn%start) / w
        if (s >= 0.0_dp .and. s < 1.0_dp) d = 30.0_dp * s * s * (1.0_dp - s)**2 / w
      case default
        i = bracket(fn%t, t)
        if (i >= 1 .and. i < size(fn%t)) d = (fn%f(i + 1) - fn%f(i)) / (fn%t(i + 1) - fn%t(i))
      end select
    end associate
  end function function_slope
  !> A table's running integral, cum(i) = ∫ f from t(1) to t(i) (the trapezoid rule is exact on
  !> the piecewise-linear function), for function_integral; nothing for the other kinds.
  pure subroutine function_prepare(fn)
    type(function_t), intent(inout) :: fn
    integer :: i
    if (fn%kind /= FN_TABLE .or. .not. allocated(fn%t)) return
    allocate (fn%cum(size(fn%t)))
    fn%cum(1) = 0.0_dp
    do i = 2, size(fn%t)
      fn%cum(i) = fn%cum(i - 1) + 0.5_dp * (fn%t(i) - fn%t(i - 1)) * (fn%f(i - 1) + fn%f(i))
    end do
  end subroutine function_prepare

  !> ∫ f from t0 to t1, exactly for every kind (the constant 1 for ifn = 0): what a rigid
  !> obstacle moving at velocity x f(t) travels (OBSTACLE … VELOCITY … FUNCTION f).
  pure real(dp) function function_integral(fns, ifn, t0, t1) result(w)
    type(function_t), intent(in) :: fns(:)
    integer, intent(in) :: ifn
    real(dp), intent(in) :: t0, t1
    if (ifn == 0) then
      w = t1 - t0
    else
      w = antiderivative(fns(ifn), t1) - antiderivative(fns(ifn), t0)
    end if
  end function function_integral

  !> A primitive of f: tables from t(1) (cum), sines and steps from their START.
  pure real(dp) function antiderivative(fn, t) result(p)
    type(function_t), intent(in) :: fn
    real(dp), intent(in) :: t
    integer :: i
    real(dp) :: s, w, om
    select case (fn%kind)
    case (FN_SINE)
      om = TWO_PI * fn%frequency
      s = min(max(t, fn%start), fn%finish) - fn%start
      p = fn%amplitude / om * (cos(fn%phase) - cos(om * s + fn%phase))
    case (FN_SMOOTH_STEP)
      w = fn%finish - fn%start
      s = min(max((t - fn%start) / w, 0.0_dp), 1.0_dp)
      p = w * s**4 * (2.5_dp - 3.0_dp * s + s * s) + max(t - fn%finish, 0.0_dp)
    case default
      i = bracket(fn%t, t)
      if (i == 0) then
        p = (t - fn%t(1)) * fn%f(1)
      else if (i == size(fn%t)) then
        p = fn%cum(i) + (t - fn%t(i)) * fn%f(i)
      else
        s = t - fn%t(i)
        p = fn%cum(i) + s * (fn%f(i) + 0.5_dp * s * (fn%f(i + 1) - fn%f(i)) / (fn%t(i + 1) - fn%t(i)))
      end if
    end select
  end function antiderivative

  !> The weight of a node's DOF d (at x) in a reaction probe: 1 on the probed DOF; for MZ ABOUT
  !> x0 y0 the arm of the moment about x0, -(y - y0) on UX, x - x0 on UY, 1 on RZ (reference
  !> positions); 0 otherwise.
  pure real(dp) function probe_weight(pr, d, x) result(w)
    type(probe_t), intent(in) :: pr
    integer, intent(in) :: d
    real(dp), intent(in) :: x(2)
    w = 0.0_dp
    if (.not. pr%about) then
      if (d == pr%dof) w = 1.0_dp
      return
    end if
    select case (d)
    case (1)
      w = -(x(2) - pr%x0(2))
    case (2)
      w = x(1) - pr%x0(1)
    case (3)
      w = 1.0_dp
    end select
  end function probe_weight
end module scene
