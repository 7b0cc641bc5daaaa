!> Unilateral contact with one Lagrange multiplier per step and the impact energy corrections
!> of method.md sections 3 and 6 (user documentation: docs/contact.md).
!>
!> A condition j is a gap g_j(u) = g0_j + c_j'u >= 0 over the free equations (the rows of C,
!> constraint_rows). Per step:
!>   contact_solve_step  (every iteration) g_free = g0 + C(u_n + du_free); LCP for the step
!>                       multiplier Λ >= 0 with g = g_free + W Λ >= 0, Λ'g = 0; du = du_free + Z Λ
!>                       where Z = S⁻¹C', W = C S⁻¹ C' (S the iteration matrix K0 + 4M/h²);
!>   contact_end_step    (after eq (3)) events, E_j = ½ Λ_j g_j(n) (10), then the impact mode's
!>                       correction, each mode in its own module (impact_paper: impulses (12)-(15)
!>                       and the hzero reflection (16); impact_persist: the projection, (16) with
!>                       gains 1, and scaling of the body; impact_massless; impact_symmetric);
!>                       reactions R(n+1) = Λ - R(n), reported only.
!> The pure kernels are in impact_kernels, the rows of C in constraint_rows, the state between
!> steps (and its checkpoint) in contact_state, M⁻¹ and the rigid modes in impact_space; this
!> module holds them together with the multiplier system, the modes and the workspaces, all
!> private: the driver reads the set through its accessors.
!>
!> Linear solves go through inverse_op_t (x = A⁻¹ b): CHOLMOD factors, a diagonal, or any test
!> double; the multipliers of the LCP come from contact_multipliers (Schur columns of the active
!> conditions, or the augmented sparse system for large active sets). Do not copy a
!> contact_set_t (it may own a CHOLMOD factor of M and an UMFPACK factor): pass it by reference
!> and call contact_destroy when done. Nothing is allocated per step once the workspaces have
!> reached the largest active set of the run.
module contact
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use sparse_matrix, only: sym_csc_t
  use spd_factor, only: spd_factor_t
  use inverse_ops, only: inverse_op_t, diag_inverse_t, chol_inverse_t, chol_ref_t
  use lcp, only: lcp_pivot
  use checkpoint, only: ckpt_file_t
  use constraint_rows, only: constraint_rows_t, LABEL_LEN, MAX_REWRITE
  use contact_state, only: contact_state_t
  use contact_multipliers, only: multiplier_system_t
  use coulomb, only: coulomb_t
  use contact_modes, only: IMPACT_OFF, IMPACT_PAPER, IMPACT_PERSIST, IMPACT_MASSLESS, IMPACT_SYMMETRIC, SOLVER_AUTO, &
    SOLVER_SCHUR, SOLVER_AUGMENTED, SWITCH_DEFAULT
  use impact_kernels, only: impact_energy_error
  use impact_report, only: contact_report_t
  use impact_space, only: impact_space_t, MAX_RIGID
  use impact_paper, only: paper_t
  use impact_persist, only: persist_t
  use impact_massless, only: massless_t
  use impact_symmetric, only: symmetric_t
  use impact_scaling, only: scaling_t
  implicit none
  private
  public :: IMPACT_OFF, IMPACT_PAPER, IMPACT_PERSIST, IMPACT_SYMMETRIC, EVENT_ESTABLISH, EVENT_RELEASE, LABEL_LEN
  public :: inverse_op_t, diag_inverse_t, chol_inverse_t
  public :: SOLVER_AUTO, SOLVER_SCHUR, SOLVER_AUGMENTED, SWITCH_DEFAULT
  public :: contact_set_t, contact_settings_t, contact_event_t, contact_report_t, multiplier_counters_t, row_geometry_t
  public :: contact_set_bilateral, contact_set_gap0, contact_rewrite, contact_step_gaps
  public :: contact_add_friction
  public :: contact_add, contact_finalize, contact_set_mass, contact_prepare, contact_solve_step, contact_set_resting, &
    contact_schur_only, &
    contact_end_step, contact_shortfall, contact_add_force, contact_gaps, contact_destroy, contact_w_matrix, contact_am_block, &
    contact_set_rigid_modes, contact_events, hzero_reflection

  integer, parameter :: EVENT_ESTABLISH = 1, EVENT_RELEASE = 2

  !> One line of events.csv.
  type :: contact_event_t
    integer :: index = 0                     !< condition
    integer :: kind = 0                      !< EVENT_ESTABLISH or EVENT_RELEASE
    real(dp) :: gap_start = 0.0_dp           !< g_j(n)
    real(dp) :: gap_end = 0.0_dp             !< g_j(n+1)
    real(dp) :: multiplier = 0.0_dp          !< Λ_j
    real(dp) :: reaction = 0.0_dp            !< R_j(n+1)
    real(dp) :: energy = 0.0_dp              !< E_j (10), restored by the correction
    real(dp) :: y = 0.0_dp                   !< impulse factor y_j = λ_j h of (13)-(14) (PAPER)
  end type contact_event_t

  !> The pairing a row that follows the geometry was written with (contact_rewrite): g = n.Σ_k w(k)
  !> x(nodes(k)) over nodes(k) > 0, b first; the outputs put its forces on these nodes.
  type :: row_geometry_t
    integer :: nodes(3) = 0
    real(dp) :: w(3) = 0.0_dp, normal(2) = 0.0_dp
  end type row_geometry_t

  !> What the user or a test may set before contact_finalize (read there and at each use).
  type :: contact_settings_t
    real(dp) :: gap_rtol = 1.0e-12_dp        !< gap tolerance = gap_rtol * model size
    real(dp) :: fp_tol = 1.0e-14_dp          !< relative change ending the impulse fixed point
    integer :: fp_max_iter = 500
    !> PERSIST (and SYMMETRIC) fall back to PAPER's reflection where the projection leaves the group
    !> less than this share of its target energy: a rigid-like impact (a point mass, a body landing
    !> with every node), whose energy scaling would pour into vibration (docs/contact.md, Limits).
    real(dp) :: persist_min_fraction = 1.0e-2_dp
    real(dp) :: massless_min_fraction = 1.0e-6_dp !< MASSLESS: below it a group cannot be scaled (left unrestored)
    integer :: solver = SOLVER_AUTO          !< multipliers: SOLVER_AUTO, SOLVER_SCHUR or SOLVER_AUGMENTED
    integer :: switch_size = SWITCH_DEFAULT  !< AUTO: augmented above this many active conditions
    integer(8) :: z_max_entries = 8388608_8  !< 64 MB: initial size of the Schur column cache
  end type contact_settings_t

  !> The work of the multiplier system since contact_finalize (run summary, docs/performance.md).
  type :: multiplier_counters_t
    integer(8) :: columns = 0, schur_solves = 0, augmented_solves = 0, factorizations = 0, singular = 0
    integer :: cache_columns = 0             !< Schur columns the cache holds now
  end type multiplier_counters_t

  !> The candidate conditions, their state and the cached operators.
  type :: contact_set_t
    private
    type(contact_settings_t), public :: settings
    type(constraint_rows_t) :: c             !< the rows of C, g0, nodes, labels
    type(contact_state_t) :: st              !< state between steps (checkpointed)
    integer :: nc = 0, neq = 0
    integer :: first_bilateral = huge(1)     !< rows from here on are equalities (IMPOSE), always active
    logical, allocatable :: bilat(:)         !< IMPOSE's rows and FRICTION's tangential rows: no contacts
    logical, allocatable :: tangent(:)       !< FRICTION's tangential rows (coulomb)
    type(coulomb_t) :: fr                    !< Coulomb's law on them
    logical, allocatable :: follow(:)        !< rows rewritten at each step (contact_rewrite)
    real(dp), allocatable :: xg(:)           !< the work of those rows the end of the step gives back
    ! Their pairing now (geo_now: the end configuration after end_geometry) and in the step's
    ! iteration (geo_step, taken by contact_step_gaps): the step multiplier acted along the latter.
    type(row_geometry_t), allocatable :: geo_now(:), geo_step(:)
    logical :: gaps_kept = .false.           !< gn, gend hold the step's gaps (contact_step_gaps)
    real(dp) :: length_scale = 1.0_dp        !< model size (tolerances are relative to it)
    integer :: lcp_iter = 0                  !< pivots of the last LCP
    logical :: finalized = .false., prepared = .false., mass_set = .false.
    type(multiplier_system_t) :: ms          !< W = C S⁻¹C' for the LCP (Schur columns or augmented)
    ! M⁻¹ and the rigid modes, with what the impact modes share (impact_space), and the modes,
    ! each with its own scratch: results leave them through their arguments.
    type(impact_space_t) :: sp
    type(paper_t) :: paper
    type(persist_t) :: persist
    type(massless_t) :: massless
    type(symmetric_t) :: symmetric
    type(scaling_t) :: following             !< the work of the rows that follow the geometry
    ! Impulses of the end-of-step correction in the last step (docs/contact.md, "Contact
    ! force"): cimp(j) along c_j (the impulse (12), the reflection (16), PERSIST's projection),
    ! bimp(:, j) the momentum PERSIST's scaling gave the group of condition j (x, y, z).
    real(dp), allocatable :: cimp(:), bimp(:, :)
    real(dp), allocatable :: lam_step(:)     !< the step multiplier R(n) + R(n+1) of the last step
    ! Events of the last contact_end_step: ev(1:n_ev).
    type(contact_event_t), allocatable :: ev(:)
    integer :: n_ev = 0
    ! The conditions of the last end of step (step_conditions): gaps g(n), g(n+1); active now,
    ! established, released; E_j (10); y_j of (13)-(14); the reactions; the modes' fallbacks.
    real(dp), allocatable :: gn(:), gend(:), e(:), y(:), r(:)
    logical, allocatable :: now(:), est(:), rel(:), fallback(:)
    logical, allocatable :: changing(:)      !< the rows that follow the geometry and are active
    ! Workspaces of the step's LCP (contact_solve_step) and of hzero_reflection's ν (tests).
    real(dp), allocatable :: wq(:), wdiag(:), nu(:), tolj(:), xw(:)
    logical, allocatable :: viol(:)
    logical :: inelastic = .false.           !< a condition has RESTITUTION e < 1
    ! Moving obstacles (move_obstacle): over the step the obstacle takes wshift(j) off the gap,
    ! its normal velocity at the end is wrate(j), its velocity wvel(:, j); the frame of a group's
    ! obstacles (vframe, M vframe) for the impact corrections (contact_frame).
    logical :: moving = .false., framed = .false.
    real(dp), allocatable :: wshift(:), wrate(:), wvel(:, :), vframe(:), mvframe(:)
    logical, allocatable :: fr_framed(:)     ! (workspaces of obstacle_frame: bodies, their velocity,
    real(dp), allocatable :: fr_wb(:, :), fr_gain(:), fr_target(:)   ! the conditions it projects on)
    integer, allocatable :: fr_conds(:)
  contains
    procedure :: n_conditions => cs_n_conditions
    procedure :: n_active => cs_n_active
    procedure :: n_events => cs_n_events
    procedure :: event => cs_event
    procedure :: reaction => cs_reaction
    procedure :: multiplier => cs_multiplier
    procedure :: correction_impulse => cs_correction_impulse
    procedure :: tangential => cs_tangential
    procedure :: tangent_row => cs_tangent_row
    procedure :: body_impulse => cs_body_impulse
    procedure :: gap => cs_gap
    procedure :: gap_end => cs_gap_end
    procedure :: follows => cs_follows
    procedure :: step_geometry => cs_step_geometry
    procedure :: end_geometry => cs_end_geometry
    procedure :: is_active => cs_is_active
    procedure :: nodes => cs_nodes
    procedure :: label => cs_label
    procedure :: lcp_iterations => cs_lcp_iterations
    procedure :: counters => cs_counters
    procedure :: warm_start => cs_warm_start
    procedure :: last_active_set => cs_last_active_set
    procedure :: changing_set => cs_changing_set
    procedure :: row_state => cs_row_state
    procedure :: set_solver => cs_set_solver
    procedure :: move_obstacle => cs_move_obstacle
    procedure :: save => cs_save
    procedure :: load => cs_load
  end type contact_set_t


  interface
    !> Check the conditions against neq free equations, set the model size and allocate the
    !> state and the workspaces (contact_setup).
    module subroutine contact_finalize(cs, neq, length_scale, stat, errmsg, mode)
      type(contact_set_t), intent(inout), target :: cs
      integer, intent(in) :: neq
      real(dp), intent(in) :: length_scale
      integer, intent(in), optional :: mode
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine contact_finalize

    !> End of a converged step, after eq (3) gave v = v(n+1) and mv = M v(n+1) (contact_impact).
    module subroutine contact_end_step(cs, mode, u_n, du, v, mv, energy_restored, stat, errmsg, body, report, step)
      type(contact_set_t), intent(inout) :: cs
      integer, intent(in) :: mode
      real(dp), intent(in) :: u_n(:), du(:)
      real(dp), intent(inout) :: v(:), mv(:)
      real(dp), intent(out) :: energy_restored
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
      integer, intent(in), optional :: body(:)
      type(contact_report_t), intent(out), optional :: report
      real(dp), intent(in), optional :: step           !< h: FRICTION's stuck contacts (friction_impulses)
    end subroutine contact_end_step

    !> FRICTION on the correction's impulses, then the sticking contacts' slip rates, after the
    !> energy restored is measured (contact_friction).
    module subroutine friction_impulses(cs, h, v, mv, rep, stat, errmsg)
      type(contact_set_t), intent(inout) :: cs
      real(dp), intent(in) :: h
      real(dp), intent(inout) :: v(:), mv(:)
      type(contact_report_t), intent(inout) :: rep
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine friction_impulses

    !> What the impact correction of the step that just converged would leave in the energy
    !> balance (MASSLESS; 0 otherwise), before anything is committed (contact_impact).
    module subroutine contact_shortfall(cs, mode, u_n, du, v, mv, body, shortfall, stat, errmsg)
      type(contact_set_t), intent(inout) :: cs
      integer, intent(in) :: mode
      real(dp), intent(in) :: u_n(:), du(:)
      real(dp), intent(inout) :: v(:), mv(:)
      integer, intent(in) :: body(:)
      real(dp), intent(out) :: shortfall
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine contact_shortfall

    !> a(1:n, 1:n) = C_idx M⁻¹ C_idx' for the conditions idx(1:n) (contact_impact).
    module subroutine contact_am_block(cs, idx, n, a, stat, errmsg)
      type(contact_set_t), intent(inout) :: cs
      integer, intent(in) :: idx(:), n
      real(dp), intent(out) :: a(:, :)
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine contact_am_block

    !> (16) The hzero step about the conditions conds with the gains 1 + e (2: the reflection;
    !> 1: PERSIST's projection; RESTITUTION e: Newton's law) (contact_impact).
    module subroutine hzero_reflection(cs, conds, gain, v, mv, rank, stat, errmsg)
      type(contact_set_t), intent(inout) :: cs
      integer, intent(in) :: conds(:)
      real(dp), intent(in) :: gain(:)
      real(dp), intent(inout) :: v(:), mv(:)
      integer, intent(out) :: rank
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine hzero_reflection
    !> Lumped mass M = diag(mdiag); a consistent one (pattern, values) factorized with CHOLMOD;
    !> any M⁻¹ operator (copied); each checked on every condition (contact_mass_ops).
    module subroutine set_mass_diag(cs, mdiag, stat, errmsg)
      type(contact_set_t), intent(inout) :: cs
      real(dp), intent(in) :: mdiag(:)
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine set_mass_diag
    module subroutine set_mass_chol(cs, pat, mval, stat, errmsg)
      type(contact_set_t), intent(inout) :: cs
      type(sym_csc_t), intent(in) :: pat
      real(dp), intent(in), contiguous :: mval(:)
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine set_mass_chol
    module subroutine set_mass_op(cs, op, stat, errmsg)
      type(contact_set_t), intent(inout) :: cs
      class(inverse_op_t), intent(in) :: op
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine set_mass_op
    module subroutine contact_destroy_mass(cs)
      type(contact_set_t), intent(inout) :: cs
    end subroutine contact_destroy_mass

    !> One iteration of the step with any S⁻¹ operator (contact_step).
    module subroutine solve_step_op(cs, s, u_n, du_free, du, lambda, stat, errmsg)
      type(contact_set_t), intent(inout), target :: cs
      class(inverse_op_t), intent(inout), target :: s
      real(dp), intent(in) :: u_n(:), du_free(:)
      real(dp), intent(out) :: du(:)
      real(dp), intent(out) :: lambda(:)
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine solve_step_op

    !> Condition j's obstacle moves (contact_frame).
    module subroutine cs_move_obstacle(self, j, shift, rate, vel)
      class(contact_set_t), intent(inout) :: self
      integer, intent(in) :: j
      real(dp), intent(in) :: shift, rate, vel(:)
    end subroutine cs_move_obstacle

    !> The velocity v, mv taken into (enter) or out of the frame of the obstacles the groups
    !> touch, for the impact corrections (contact_frame).
    module subroutine obstacle_frame(cs, enter, body, v, mv, stat, errmsg)
      type(contact_set_t), intent(inout) :: cs
      logical, intent(in) :: enter
      integer, intent(in) :: body(:)
      real(dp), intent(inout) :: v(:), mv(:)
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine obstacle_frame
  end interface

  interface contact_set_mass
    module procedure set_mass_diag, set_mass_chol, set_mass_op
  end interface contact_set_mass

  interface contact_prepare
    module procedure prepare_chol, prepare_op
  end interface contact_prepare

  interface contact_solve_step
    module procedure solve_step_chol, solve_step_op
  end interface contact_solve_step

contains

  ! ---------------------------------------------------------------------------------------
  ! Accessors (read-only views for the driver and the tests)
  ! ---------------------------------------------------------------------------------------

  pure integer function cs_n_conditions(self)
    class(contact_set_t), intent(in) :: self
    cs_n_conditions = self%nc
  end function cs_n_conditions

  !> Conditions active at the end of the last step.
  pure integer function cs_n_active(self)
    class(contact_set_t), intent(in) :: self
    cs_n_active = 0
    if (allocated(self%st%active)) cs_n_active = count(self%st%active)
  end function cs_n_active

  !> Events of the last contact_end_step: event(1) .. event(n_events()).
  pure integer function cs_n_events(self)
    class(contact_set_t), intent(in) :: self
    cs_n_events = self%n_ev
  end function cs_n_events

  pure function cs_event(self, k) result(ev)
    class(contact_set_t), intent(in) :: self
    integer, intent(in) :: k
    type(contact_event_t) :: ev
    ev = self%ev(k)
  end function cs_event

  !> The events of the last contact_end_step as an array (tests; allocates).
  pure function contact_events(cs) result(ev)
    type(contact_set_t), intent(in) :: cs
    type(contact_event_t), allocatable :: ev(:)
    ev = cs%ev(1:cs%n_ev)
  end function contact_events

  !> Physical reaction R_j(n+1) = Λ_j - R_j(n) of condition j at the end of the last step
  !> (0 when inactive; reported only, never put back into a step).
  pure real(dp) function cs_reaction(self, j)
    class(contact_set_t), intent(in) :: self
    integer, intent(in) :: j
    cs_reaction = self%st%r_prev(j)
  end function cs_reaction

  !> The step multiplier of condition j in the last step, R(n) + R(n+1): the LCP's Λ_j, or under
  !> IMPACT MASSLESS (whose Λ_j is R(n+1)) Λ_j plus the reaction it started the step with.
  pure real(dp) function cs_multiplier(self, j)
    class(contact_set_t), intent(in) :: self
    integer, intent(in) :: j
    cs_multiplier = self%lam_step(j)
  end function cs_multiplier

  !> FRICTION on condition j: its tangential step multiplier Λ_T (along t = n turned by +90°;
  !> in 3D along t1, or t2 with k = 2), the slip of the last step c_T du and the tangential
  !> impulse of its impact correction (all 0 on a frictionless condition).
  pure subroutine cs_tangential(self, j, lambda_t, slip, impulse_t, k)
    class(contact_set_t), intent(in) :: self
    integer, intent(in) :: j
    real(dp), intent(out) :: lambda_t, slip, impulse_t
    integer, intent(in), optional :: k
    integer :: t
    lambda_t = 0.0_dp
    slip = 0.0_dp
    impulse_t = 0.0_dp
    t = self%fr%tangent_of(j)
    if (present(k)) then
      if (k == 2) t = self%fr%tangent2_of(j)
    end if
    if (t == 0) return
    lambda_t = self%st%lambda(t)
    slip = self%gend(t) - self%gn(t)
    impulse_t = self%cimp(t)
  end subroutine cs_tangential

  !> FRICTION: the tangential row of condition j (0: frictionless); k = 2: the second one (3D).
  pure integer function cs_tangent_row(self, j, k) result(t)
    class(contact_set_t), intent(in) :: self
    integer, intent(in) :: j
    integer, intent(in), optional :: k
    t = self%fr%tangent_of(j)
    if (present(k)) then
      if (k == 2) t = self%fr%tangent2_of(j)
    end if
  end function cs_tangent_row

  !> Impulse of the end-of-step correction of the last step along c_j (0 without one).
  pure real(dp) function cs_correction_impulse(self, j)
    class(contact_set_t), intent(in) :: self
    integer, intent(in) :: j
    cs_correction_impulse = self%cimp(j)
  end function cs_correction_impulse

  !> Momentum (x, y, z) that PERSIST's scaling gave the group of condition j in the last step.
  pure function cs_body_impulse(self, j) result(p)
    class(contact_set_t), intent(in) :: self
    integer, intent(in) :: j
    real(dp) :: p(3)
    p = self%bimp(:, j)
  end function cs_body_impulse

  !> Gap g_j(n+1) at the end of the last step.
  pure real(dp) function cs_gap(self, j)
    class(contact_set_t), intent(in) :: self
    integer, intent(in) :: j
    cs_gap = self%st%gap_n(j)
  end function cs_gap

  !> Whether row j follows the geometry (contact_rewrite).
  pure logical function cs_follows(self, j)
    class(contact_set_t), intent(in) :: self
    integer, intent(in) :: j
    cs_follows = .false.
    if (allocated(self%follow)) cs_follows = self%follow(j)
  end function cs_follows

  !> The pairing of a following row during the last step (its multiplier's direction).
  pure function cs_step_geometry(self, j) result(g)
    class(contact_set_t), intent(in) :: self
    integer, intent(in) :: j
    type(row_geometry_t) :: g
    g = self%geo_step(j)
  end function cs_step_geometry

  !> The pairing of a following row now (after the step: its impact corrections' direction).
  pure function cs_end_geometry(self, j) result(g)
    class(contact_set_t), intent(in) :: self
    integer, intent(in) :: j
    type(row_geometry_t) :: g
    g = self%geo_now(j)
  end function cs_end_geometry

  !> g_j(n+1) of the step kept by contact_step_gaps.
  pure real(dp) function cs_gap_end(self, j)
    class(contact_set_t), intent(in) :: self
    integer, intent(in) :: j
    cs_gap_end = self%gend(j)
  end function cs_gap_end

  pure logical function cs_is_active(self, j)
    class(contact_set_t), intent(in) :: self
    integer, intent(in) :: j
    cs_is_active = self%st%active(j)
  end function cs_is_active

  !> [node_a, node_b] of condition j (node_a = 0: rigid obstacle).
  pure function cs_nodes(self, j) result(nodes)
    class(contact_set_t), intent(in) :: self
    integer, intent(in) :: j
    integer :: nodes(2)
    nodes = self%c%nodes(j)
  end function cs_nodes

  pure function cs_label(self, j) result(label)
    class(contact_set_t), intent(in) :: self
    integer, intent(in) :: j
    character(len=LABEL_LEN) :: label
    label = self%c%label(j)
  end function cs_label

  pure integer function cs_lcp_iterations(self)
    class(contact_set_t), intent(in) :: self
    cs_lcp_iterations = self%lcp_iter
  end function cs_lcp_iterations

  pure function cs_counters(self) result(k)
    class(contact_set_t), intent(in) :: self
    type(multiplier_counters_t) :: k
    k%columns = self%ms%n_columns
    k%schur_solves = self%ms%n_schur
    k%augmented_solves = self%ms%n_kkt
    k%factorizations = self%ms%n_lu
    k%singular = self%ms%n_singular
    k%cache_columns = self%ms%cap
  end function cs_counters

  !> The trial active set the next LCP starts from (by default the last one).
  pure subroutine cs_warm_start(self, active)
    class(contact_set_t), intent(inout) :: self
    logical, intent(in) :: active(:)
    self%st%active_iter = active
  end subroutine cs_warm_start

  !> The trial active set the next LCP would start from (to start a step again: warm_start).
  pure subroutine cs_last_active_set(self, active)
    class(contact_set_t), intent(in) :: self
    logical, intent(out) :: active(:)
    active = self%st%active_iter
  end subroutine cs_last_active_set

  !> Does the active set of the step's last iterate establish or release a contact condition?
  pure logical function cs_changing_set(self)
    class(contact_set_t), intent(in) :: self
    integer :: j
    cs_changing_set = .false.
    do j = 1, self%nc
      if (self%bilat(j)) cycle
      if (self%st%active_iter(j) .neqv. self%st%active(j)) cs_changing_set = .true.
    end do
  end function cs_changing_set

  !> Condition j as the event locator sees it (event_location): a unilateral condition (not an
  !> IMPOSE row), active at n, active in the step's last iterate (trial) with its multiplier Λ_j,
  !> and its normal velocity c_j'v less the obstacle's (OBSTACLE … VELOCITY).
  pure subroutine cs_row_state(self, j, unilateral, active, trial, lambda, v, rate)
    class(contact_set_t), intent(in) :: self
    integer, intent(in) :: j
    real(dp), intent(in), optional :: v(:)
    logical, intent(out) :: unilateral, active, trial
    real(dp), intent(out) :: lambda
    real(dp), intent(out), optional :: rate
    unilateral = .not. self%bilat(j)
    active = self%st%active(j)
    trial = self%st%active_iter(j)
    lambda = self%st%lambda(j)
    if (.not. (present(v) .and. present(rate))) return
    rate = self%c%dot(j, v)
    if (self%moving) rate = rate - self%wrate(j)
  end subroutine cs_row_state

  !> Change how the multipliers are computed (SOLVER_AUTO, SOLVER_SCHUR, SOLVER_AUGMENTED).
  pure subroutine cs_set_solver(self, solver)
    class(contact_set_t), intent(inout) :: self
    integer, intent(in) :: solver
    self%settings%solver = solver
    self%ms%mode = solver
  end subroutine cs_set_solver

  !> The contact state into an open checkpoint (sticky stat, as ckpt_file_t).
  subroutine cs_save(self, ck, stat, errmsg)
    class(contact_set_t), intent(in) :: self
    type(ckpt_file_t), intent(inout) :: ck
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call self%st%save(ck, stat, errmsg)
    call self%fr%save(ck, stat, errmsg)
  end subroutine cs_save

  subroutine cs_load(self, ck, stat, errmsg)
    class(contact_set_t), intent(inout) :: self
    type(ckpt_file_t), intent(inout) :: ck
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call self%st%load(ck, stat, errmsg)
    call self%fr%load(ck, stat, errmsg)
  end subroutine cs_load

  ! ---------------------------------------------------------------------------------------
  ! Building the set
  ! ---------------------------------------------------------------------------------------

  !> Append the condition g0 + Σ coefs(k) u(eqs(k)) >= 0 (see constraint_rows: entries with
  !> eqs(k) <= 0 are skipped). nodes = [node_a, node_b] (0 for a rigid obstacle) and label
  !> name it in messages and events.
  pure subroutine contact_add(cs, g0, eqs, coefs, nodes, label, restitution)
    type(contact_set_t), intent(inout) :: cs
    real(dp), intent(in) :: g0
    integer, intent(in) :: eqs(:)
    real(dp), intent(in) :: coefs(:)
    integer, intent(in), optional :: nodes(2)
    character(len=*), intent(in), optional :: label
    real(dp), intent(in), optional :: restitution   !< e in [0, 1] (default 1: elastic)
    call cs%c%add(g0, eqs, coefs, nodes, label, restitution)
    cs%nc = cs%c%n()
    cs%finalized = .false.
  end subroutine contact_add

  !> FRICTION mu > 0 on condition j (added): its tangential row Σ coefs(k) u(eqs(k)) (the slip,
  !> along the tangent t = n turned by +90°; in 3D along t1, and eqs2, coefs2 the row along t2),
  !> appended after every other row (coulomb).
  pure subroutine contact_add_friction(cs, j, eqs, coefs, mu, eqs2, coefs2)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: j, eqs(:)
    real(dp), intent(in) :: coefs(:), mu
    integer, intent(in), optional :: eqs2(:)
    real(dp), intent(in), optional :: coefs2(:)
    call cs%c%add(0.0_dp, eqs, coefs, cs%c%nodes(j), cs%c%label(j))
    cs%nc = cs%c%n()
    if (present(eqs2)) then
      call cs%c%add(0.0_dp, eqs2, coefs2, cs%c%nodes(j), cs%c%label(j))
      cs%nc = cs%c%n()
      call cs%fr%add(cs%nc - 1, j, mu, cs%nc)
    else
      call cs%fr%add(cs%nc, j, mu)
    end if
    cs%finalized = .false.
  end subroutine contact_add_friction

  !> Rows first.. (added last) are bilateral: equalities g_j = 0 held by a multiplier of any sign
  !> (IMPOSE: prescribed displacements), always active, without impact events or corrections.
  pure subroutine contact_set_bilateral(cs, first)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: first
    cs%first_bilateral = first
    cs%finalized = .false.
  end subroutine contact_set_bilateral

  !> A new g0 for row j (a bilateral row: minus its target at the end of the coming step).
  pure subroutine contact_set_gap0(cs, j, g0)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: j
    real(dp), intent(in) :: g0
    call cs%c%set_gap0(j, g0)
  end subroutine contact_set_gap0

  !> Row j rewritten for the configuration at the start of a step (contact_geometry: GAP …
  !> SEGMENTS in a KINEMATICS LARGE model) and marked as following the geometry: consecutive
  !> steps linearize the gap about different configurations, and the work the multiplier of a
  !> held contact does across that difference is given back at the end of the step
  !> (contact_end_step). The Schur multipliers only (the augmented pattern would change). Call
  !> contact_prepare before the next solve.
  subroutine contact_rewrite(cs, j, g0, eqs, coefs, geo, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(in) :: j
    real(dp), intent(in) :: g0
    integer, intent(in) :: eqs(:)
    real(dp), intent(in) :: coefs(:)
    type(row_geometry_t), intent(in) :: geo        !< the pairing (outputs; messages name b and the nearer end)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (.not. cs%finalized .or. j < 1 .or. j >= min(cs%first_bilateral, cs%nc + 1)) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_rewrite: condition ' // str(j) // ' is not a contact of a ' // &
        'finalized set')
    else if (cs%ms%mode /= SOLVER_SCHUR) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_rewrite: rows that follow the geometry need SCHEME ' // &
        'MULTIPLIERS SCHUR')
    else if (size(eqs) > MAX_REWRITE .or. size(coefs) /= size(eqs)) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_rewrite: at most ' // str(MAX_REWRITE) // ' entries, as many ' // &
        'coefficients as equations')
    end if
    if (stat /= STAT_OK) return
    ! b and the partner's node nearer the contact point (w(3) = -ξ; a corner has no third node)
    call cs%c%rewrite(j, g0, eqs, coefs, [merge(geo%nodes(3), geo%nodes(2), -geo%w(3) > 0.5_dp .and. geo%nodes(3) > 0), &
      geo%nodes(1)])
    cs%geo_now(j) = geo
    if (.not. cs%follow(j)) cs%geo_step(j) = geo
    cs%follow(j) = .true.
    cs%prepared = .false.
  end subroutine contact_rewrite

  !> The step's gaps g(n) = g0 + C u_n and g(n+1) = g(n) + C du with the rows the multipliers
  !> worked with, kept for contact_end_step: rows that follow the geometry are then rewritten at
  !> the end configuration (contact_geometry) for the impact corrections.
  subroutine contact_step_gaps(cs, u_n, du)
    type(contact_set_t), intent(inout) :: cs
    real(dp), intent(in) :: u_n(:), du(:)
    integer :: j
    if (.not. cs%finalized) return
    call cs%c%gaps(u_n, cs%gn)
    do j = 1, cs%nc
      cs%gend(j) = cs%gn(j) + cs%c%dot(j, du)
    end do
    if (cs%moving) cs%gn = cs%gn + cs%wshift     ! (the rows hold g0 at the step's end)
    cs%geo_step = cs%geo_now
    cs%gaps_kept = .true.
  end subroutine contact_step_gaps

  !> Free the caches and the factors.
  subroutine contact_destroy(cs)
    type(contact_set_t), intent(inout) :: cs
    call contact_destroy_mass(cs)
    call cs%ms%destroy()
    cs%prepared = .false.
    cs%mass_set = .false.
  end subroutine contact_destroy

  ! ---------------------------------------------------------------------------------------
  ! C and the blocks of A M⁻¹A'
  ! ---------------------------------------------------------------------------------------

  !> g = g0 + C u.
  pure subroutine contact_gaps(cs, u, g)
    type(contact_set_t), intent(in) :: cs
    real(dp), intent(in) :: u(:)
    real(dp), intent(out) :: g(:)
    call cs%c%gaps(u, g)
  end subroutine contact_gaps

  !> f <- f + C'Λ with the multiplier of the last contact_solve_step: the contact force on the
  !> right of (5)/(9), for the driver's residual.
  pure subroutine contact_add_force(cs, f)
    type(contact_set_t), intent(in) :: cs
    real(dp), intent(inout) :: f(:)
    if (cs%nc == 0 .or. .not. allocated(cs%st%lambda)) return
    call cs%c%add_transpose(cs%st%lambda, f)
  end subroutine contact_add_force


  !> STATIC (static_preload): the conditions hold the structure at rest with the multipliers lam
  !> of the static equilibrium, the reactions R(0) the first step starts from (its Λ = R(0) + R(1)
  !> then keeps them), the conditions with lam > 0 active (their closing is no impact).
  subroutine contact_set_resting(cs, lam)
    type(contact_set_t), intent(inout) :: cs
    real(dp), intent(in) :: lam(:)
    if (cs%nc == 0) return
    ! (IMPOSE's bilateral rows are no contacts: never active, no reaction kept; contact_impact.)
    cs%st%active = lam > 0.0_dp .and. .not. cs%bilat
    cs%st%r_prev = merge(lam, 0.0_dp, cs%st%active)
    cs%st%lambda = lam
    cs%st%active_iter = cs%st%active .or. cs%bilat
    ! The outputs of t = 0 read the static forces as ½ Λ (contacts, and IMPOSE's reactions).
    cs%lam_step = 2.0_dp * merge(lam, 0.0_dp, cs%st%active .or. cs%bilat)
    cs%cimp = 0.0_dp
  end subroutine contact_set_resting

  !> MULTIPLIERS AUTO takes the Schur columns whatever the active set's size while schur_only
  !> (STATIC: S = K + κ C_A'C_A is stiffness-dominated, where the augmented system's LU needs far
  !> more refinement than in the dynamics); back to SCHEME AUGMENTED_ABOVE after.
  subroutine contact_schur_only(cs, schur_only)
    type(contact_set_t), intent(inout) :: cs
    logical, intent(in) :: schur_only
    cs%ms%switch_size = cs%settings%switch_size
    if (schur_only) cs%ms%switch_size = huge(1)
  end subroutine contact_schur_only

  !> W = C S⁻¹ C' over every candidate (nc solves; diagnostics and tests, not the run).
  subroutine contact_w_matrix(cs, s, w, stat, errmsg)
    type(contact_set_t), intent(inout), target :: cs
    class(inverse_op_t), intent(inout), target :: s
    real(dp), intent(out) :: w(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: j
    stat = STAT_OK
    call cs%ms%bind(cs%c, s)
    do j = 1, cs%nc
      call cs%ms%column(j, cs%xw, stat, errmsg)
      if (stat /= STAT_OK) exit
      call cs%c%times(cs%xw, w(:, j))
    end do
    call cs%ms%unbind()
    w = 0.5_dp * (w + transpose(w))
  end subroutine contact_w_matrix

  ! ---------------------------------------------------------------------------------------
  ! Mass and iteration-matrix operators
  ! ---------------------------------------------------------------------------------------

  !> A new iteration matrix S = K0 + 4M/h² (per step size, or per iteration with TANGENT), the
  !> driver's CHOLMOD factor: the cached Schur columns are dropped. pat and sval (the pattern
  !> and values of S) enable the augmented system; without them only SOLVER_SCHUR works.
  subroutine prepare_chol(cs, s, stat, errmsg, pat, sval)
    type(contact_set_t), intent(inout), target :: cs
    type(spd_factor_t), intent(inout), target :: s
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(sym_csc_t), intent(in), optional :: pat
    real(dp), intent(in), optional :: sval(:)
    type(chol_ref_t) :: op
    op%f => s
    call prepare_op(cs, op, stat, errmsg, pat, sval)
  end subroutine prepare_chol

  !> Same with any S⁻¹ operator.
  subroutine prepare_op(cs, s, stat, errmsg, pat, sval)
    type(contact_set_t), intent(inout), target :: cs
    class(inverse_op_t), intent(inout) :: s
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(sym_csc_t), intent(in), optional :: pat
    real(dp), intent(in), optional :: sval(:)
    stat = STAT_OK
    if (.not. cs%finalized) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_prepare: call contact_finalize first')
      return
    end if
    cs%prepared = .false.
    if (cs%nc > 0) then
      call cs%ms%bind(cs%c)
      call cs%ms%prepare(stat, errmsg, pat, sval)
      call cs%ms%unbind()
      if (stat /= STAT_OK) return
    end if
    cs%prepared = .true.
  end subroutine prepare_op

  !> The rigid modes of the model on the free equations, t (neq, 2 or 3: the translations x and y
  !> (1 on every node's UX, resp. UY), the rotation about the origin), mt = M t, and free(k, b):
  !> mode k is a free motion of body b (body(:) of contact_end_step; no support or imposed DOF
  !> it moves). A PERSIST, MASSLESS or SYMMETRIC scaling keeps the momentum of a group along its
  !> free modes that its active conditions leave invariant (docs/contact.md, "What a correction
  !> may change"). Without free, every mode counts as free.
  subroutine contact_set_rigid_modes(cs, t, mt, stat, errmsg, free)
    type(contact_set_t), intent(inout) :: cs
    real(dp), intent(in) :: t(:, :), mt(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical, intent(in), optional :: free(:, :)
    stat = STAT_OK
    if (.not. cs%finalized .or. size(t, 1) /= cs%neq .or. any(shape(mt) /= shape(t)) .or. size(t, 2) < 2 .or. &
      size(t, 2) > MAX_RIGID) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_set_rigid_modes: call contact_finalize first; t and M t ' // &
        'must be (neq, 2 to 6)')
      return
    end if
    if (present(free)) then
      if (size(free, 1) < size(t, 2)) then
        call set_error(stat, errmsg, STAT_INPUT, 'contact_set_rigid_modes: free must be (modes, bodies)')
        return
      end if
    end if
    call cs%sp%set_rigid_modes(t, mt, free)
  end subroutine contact_set_rigid_modes

  ! ---------------------------------------------------------------------------------------
  ! The step
  ! ---------------------------------------------------------------------------------------

  !> One iteration of the step: with u_n the displacement at the start of the step and du_free
  !> the update without contact forces, find the step multiplier lambda (LCP) and the constrained
  !> update du = du_free + S⁻¹C'Λ; s is the factor of the S given to contact_prepare.
  subroutine solve_step_chol(cs, s, u_n, du_free, du, lambda, stat, errmsg)
    type(contact_set_t), intent(inout), target :: cs
    type(spd_factor_t), intent(inout), target :: s
    real(dp), intent(in) :: u_n(:), du_free(:)
    real(dp), intent(out) :: du(:)
    real(dp), intent(out) :: lambda(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(chol_ref_t), target :: op
    op%f => s
    call solve_step_op(cs, op, u_n, du_free, du, lambda, stat, errmsg)
  end subroutine solve_step_chol

end module contact
