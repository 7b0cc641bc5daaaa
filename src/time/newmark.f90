!> The time loop of Newmark's average-acceleration scheme (method.md sections 1-3): prepare the
!> run (initial state, the iteration matrix, the contact conditions), then per step the
!> external forces, the iteration of eq (9) and the end of the step (newmark_step), the energy
!> accounts, the outputs (run_outputs) and the checkpoints, with one exit path: whatever
!> stops the run, the result files are closed and the summary tells what was done.
module newmark
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str
  use scene, only: scene_t, condition_row, condition_tangent, COND_NODES
  use contact_modes, only: IMPACT_PAPER, IMPACT_PERSIST, IMPACT_MASSLESS, IMPACT_SYMMETRIC
  use dof_map, only: equation_bodies, body_rigid_freedom
  use imposed_motion, only: imposed_start, imposed_rows, imposed_targets, imposed_probe_map, imposed_reactions, &
    obstacle_targets
  use contact, only: contact_report_t, contact_add, contact_add_friction, contact_finalize, contact_set_mass, &
    contact_prepare, contact_set_rigid_modes, contact_gaps, contact_step_gaps, contact_shortfall
  use newmark_scheme, only: velocity_eq3
  use assembly, only: system_t, external_force, mass_times, initial_state, dof_label, dof_origin, reaction_update, is_damped
  use energy, only: energy_t
  use internal_forces, only: refresh_points, check_k0_product, linear_strain_energy
  use iteration_matrix, only: iteration_matrix_t
  use contact_checks, only: check_massless, check_initial_gaps
  use static_preload, only: static_solve
  use cholmod_binding, only: factor_stats_t
  use newmark_step, only: residual_history, step_report_t, iterate_eq9, iterate_eq9_zone, end_step, following_rows, &
    STEP_CONVERGED, &
    STEP_DIVERGED, STEP_NOT_CONVERGED, &
    STEP_NONFINITE, STEP_INVERTED, STEP_INDEFINITE
  use run_outputs, only: output_set_t, HISTORY_HEADER, EVENTS_HEADER
  use mesh_segments, only: node_stars
  use model_modes, only: rigid_modes, rotation_mode
  use os_utils, only: make_directory, install_signal_handlers, signal_received
  use run_state, only: run_state_t, save_checkpoint, load_checkpoint, steps_for, init_levels, select_level
  implicit none
  private
  public :: run_options_t, run_summary_t, prepare_run, run_newmark, run_state_t
  public :: HISTORY_HEADER, EVENTS_HEADER

  !> advance's outcome when TIME … ADAPTIVE wants the step again at half its length.
  integer, parameter :: STEP_REJECTED = 101

  type :: run_options_t
    character(len=:), allocatable :: outdir
    character(len=:), allocatable :: restart   !< checkpoint to continue from (--restart)
    logical :: quiet = .false.
  end type run_options_t

  type :: run_summary_t
    integer :: steps = 0
    real(dp) :: wall = 0.0_dp
    real(dp) :: max_rel_balance = 0.0_dp
    integer :: iterations = 0
    integer :: retried = 0                   !< steps taken again as sub-steps (SCHEME RETRY)
    integer :: impact_retried = 0            !< of which for their impact correction (impact_short)
    integer :: located = 0                   !< steps cut at a contact event (SCHEME EVENTS LOCATE)
    !> TIME … ADAPTIVE: steps taken again at half their length, doublings, halvings, steps kept at
    !> MIN above the tolerance; the shortest and longest steps.
    integer :: adapt_rejected = 0, adapt_grown = 0, adapt_shrunk = 0, adapt_at_min = 0
    real(dp) :: h_min_used = 0.0_dp, h_max_used = 0.0_dp
    integer :: max_substeps = 1              !< the most sub-steps one step took
    integer(8) :: factorizations = 0         !< of the iteration matrix S (setup, TANGENT, AUTO, RETRY)
    integer(8) :: geometric_dropped = 0      !< of them, tangents factorized again without their compressive geometric part
    type(factor_stats_t) :: factor           !< the factor of S as CHOLMOD's analysis made it
    ! Contact multipliers (contact_multipliers): Schur columns computed (solves with S), trial
    ! active sets solved by Schur / by the augmented system, its LU factorizations.
    integer(8) :: schur_columns = 0, schur_solves = 0, augmented_solves = 0, augmented_factorizations = 0
    integer :: following = 0                 !< conditions re-paired at every step (GAP … SEGMENTS, LARGE)
    integer(8) :: repairings = 0             !< their changes of partner (segment or corner)
  end type run_summary_t

  !> Everything the time loop works on, allocated before it starts.

contains

  !> Factorize S = K0 + 4M/h², set the initial state (u0, v0, internal forces, energies).
  !> Everything that can reveal bad input (a singular system) happens here, before any output.
  subroutine prepare_run(scn, sys, rs, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(run_state_t), intent(inout) :: rs
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: n, minor
    real(dp) :: span
    real(dp), allocatable :: fstatic(:), ustatic(:)
    logical :: has_static

    n = sys%dofs%neq
    rs%h = scn%dt
    call init_levels(rs, scn)
    span = scn%t_end - scn%t_start
    rs%nsteps = max(steps_for(span, rs%h, span), 1)
    if (scn%time_zero_line > 0) rs%nsteps = 0     ! STATIC alone (TIME END = START): the state of t = 0 only
    call rs%st%init(n, scn%max_iterations, rs%h, sys%extended)
    allocate (fstatic(n), ustatic(n))
    call initial_state(scn, sys, rs%st%u, rs%st%v, fstatic, has_static, stat, errmsg)
    if (stat /= STAT_OK) return
    if (has_static) then
      ! Static preload: K0 u = f, released at t = 0.
      call rs%mat%factor%factorize(sys%ops%pat, sys%ops%kval, stat, errmsg, minor)
      if (stat /= STAT_OK) then
        call set_error(stat, errmsg, STAT_INPUT, dof_origin(scn, sys, minor) // &
          ': INITIAL STATIC: the stiffness is singular at ' // &
          dof_label(scn, sys, minor) // ' (a rigid-body mode not held by supports?)')
        return
      end if
      call rs%mat%factor%solve(fstatic, ustatic, stat, errmsg)
      if (stat /= STAT_OK) return
      rs%st%u = rs%st%u + ustatic
    end if
    call imposed_start(scn, sys, rs%st%u, rs%st%v, stat, errmsg)
    if (stat /= STAT_OK) return
    call imposed_probe_map(scn, rs%imp_row, rs%imp_slot, rs%imp_w)
    call select_level(rs, scn, sys, rs%h, stat, errmsg, minor)
    if (stat /= STAT_OK) then
      call set_error(stat, errmsg, STAT_INPUT, dof_origin(scn, sys, minor) // ': singular system K0 + 4M/h2 at ' // &
        dof_label(scn, sys, minor) // ' (no mass and no stiffness on this mode)')
      return
    end if
    call rs%zone%build(scn, sys, rs%mat%factor%solve_flops())
    call rs%zone%columns(rs%mat%factor, stat, errmsg)
    if (stat /= STAT_OK) return
    call rigid_modes(scn, sys, rs%rig, rs%mrig)
    if (size(scn%conditions) > 0 .or. size(scn%imposes) > 0) then
      call setup_contact(scn, sys, rs, stat, errmsg)
      if (stat /= STAT_OK) return
    end if
    ! Located events (SCHEME EVENTS) cut steps with the sub-steps' S: its factor and the locator's
    ! arrays set up here, not in the time loop.
    if ((rs%has_contact .and. scn%locate_events) .or. scn%adaptive) then
      call rs%mat_sub%setup(sys, rs%h, stat, errmsg, minor, scn%iter_auto)
      if (stat /= STAT_OK) return
    end if
    if (rs%has_contact .and. scn%locate_events) call rs%events%init(rs%cs, sys%dofs%eqn, rs%body)
    call rs%ctl%init(scn, n)
    rs%t_now = scn%t_start
    if (scn%static_steps > 0) call run_static(scn, sys, rs, stat, errmsg)
    if (stat /= STAT_OK) return
    ! Initial internal forces and strain energy: the laws take the path from zero strain to u0
    ! (after STATIC, they are at the committed equilibrium).
    call check_k0_product(scn, sys, rs%st%fint, rs%st%r)
    call rs%st%set_initial(scn, sys, preloaded=scn%static_steps > 0)
    ! The linear fast path (Bσ = K0 u) with nothing added to (9) (no contact rows, damping or
    ! lumped mass, whose product is one pass anyway) takes M v(n+1) from the step's momentum
    ! balance instead of the consistent mass's product (momentum_eq2).
    rs%st%momentum_form = sys%ops%k0u%active() .and. .not. (rs%has_contact .or. is_damped(sys) .or. &
      sys%ops%mass_diagonal)
    if (sys%ops%k0u%active()) call linear_strain_energy(scn, sys, rs%st%u, rs%st%inc%elastic)
    call rs%en%start(rs%st%kinetic, rs%st%inc%work + rs%pre%work_internal, rs%st%inc%elastic, rs%pre%dissipated)
    call refresh_points(scn, sys, rs%st%u, .true.)
    call reaction_update(scn, sys, rs%st%u, rs%st%v, scn%t_start, rs%h, .true.)
    if (scn%static_steps > 0 .and. rs%has_contact) &      ! STATIC: the imposed DOFs' static reactions
      call imposed_reactions(rs%cs, rs%imp_row, rs%imp_slot, rs%imp_w, sys%react%value)
    call external_force(scn, sys, scn%t_start, rs%st%f_n, rs%st%u)
  end subroutine prepare_run

  !> STATIC (static_preload): the equilibrium under the start time's loads becomes u0; the contact
  !> set, left holding it, is prepared again with the dynamics' S (and its following pairs moved).
  subroutine run_static(scn, sys, rs, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(run_state_t), intent(inout) :: rs
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    if (.not. rs%has_contact) then
      call static_solve(scn, sys, rs%st%u, rs%rig, rs%pre, stat, errmsg)
      return
    end if
    call static_solve(scn, sys, rs%st%u, rs%rig, rs%pre, stat, errmsg, rs%cs, rs%lam, rs%follow)
    if (stat == STAT_OK .and. rs%follow%count() > 0) call rs%follow%update(scn%mesh%x, sys%dofs%eqn, rs%st%u, rs%cs, &
      stat, errmsg)
    if (stat == STAT_OK) call contact_prepare(rs%cs, rs%mat%factor, stat, errmsg, sys%ops%pat, rs%mat%sval)
  end subroutine run_static

  !> The contact conditions as constraint rows on the free equations: g = g0 + n.(u_b - u_a);
  !> the mass for the impulse and the reflection, the Schur data of S for the multipliers.
  subroutine setup_contact(scn, sys, rs, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    type(run_state_t), intent(inout) :: rs
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: j, eqs(3 * COND_NODES), eqs2(3 * COND_NODES)
    integer, allocatable :: sptr(:), star(:)
    real(dp) :: coefs(3 * COND_NODES), coefs2(3 * COND_NODES), lscale
    character(len=:), allocatable :: msg
    real(dp), allocatable :: circ(:, :)
    logical, allocatable :: free(:, :)
    rs%has_contact = .true.
    do j = 1, size(scn%conditions)
      associate (c => scn%conditions(j))
        call condition_row(c, c%normal, sys%dofs%eqn, eqs, coefs)
        ! events and messages name b and, for a segment, its end nearer the contact point
        call contact_add(rs%cs, c%g0, eqs, coefs, nodes=[merge(c%node_c, c%node_a, c%xi > 0.5_dp), c%node_b], &
          label=c%source, restitution=c%restitution)
      end associate
    end do
    call imposed_rows(scn, sys, rs%cs)
    do j = 1, size(scn%conditions)            ! FRICTION: a tangential row each, after all the others
      if (scn%conditions(j)%friction <= 0.0_dp) cycle
      call condition_row(scn%conditions(j), condition_tangent(scn%conditions(j), scn%mesh%ndim), sys%dofs%eqn, eqs, coefs)
      if (scn%mesh%ndim == 3) then             ! (3D: two tangential rows, the cone a circle)
        call condition_row(scn%conditions(j), condition_tangent(scn%conditions(j), 3, 2), sys%dofs%eqn, eqs2, coefs2)
        call contact_add_friction(rs%cs, j, eqs, coefs, scn%conditions(j)%friction, eqs2, coefs2)
      else
        call contact_add_friction(rs%cs, j, eqs, coefs, scn%conditions(j)%friction)
      end if
    end do
    associate (x => scn%mesh%x(:, 1:scn%mesh%nnode))
      lscale = maxval(maxval(x, dim=2) - minval(x, dim=2))
    end associate
    if (lscale <= 0.0_dp) lscale = 1.0_dp
    rs%cs%settings%solver = scn%multipliers
    rs%cs%settings%switch_size = scn%augmented_above
    call contact_finalize(rs%cs, sys%dofs%neq, lscale, stat, errmsg, scn%impact)
    if (stat /= STAT_OK) return
    associate (c => scn%conditions)
      call node_stars(scn%mesh, pack(c%node_b, c%follow), sptr, star)
      circ = reshape([(c(j)%center, c(j)%radius, real(c(j)%curved, dp), j = 1, size(c))], [4, size(c)])
      call rs%follow%init(pack([(j, j = 1, size(c))], c%follow), pack(c%node_b, c%follow), pack(c%segset, c%follow), &
        pack(c%side, c%follow), scn%segsets, sptr, star, scn%mesh%nnode, circle=circ(:, pack([(j, j = 1, size(c))], &
        c%follow)))
    end associate
    call rs%follow%update(scn%mesh%x, sys%dofs%eqn, rs%st%u, rs%cs, stat, errmsg)
    if (stat /= STAT_OK) return
    call check_initial_gaps(scn, rs%cs, rs%st%u, lscale, stat, errmsg)
    if (stat /= STAT_OK) return
    if ((scn%impact == IMPACT_PAPER .or. scn%impact == IMPACT_PERSIST .or. scn%impact == IMPACT_SYMMETRIC) .and. &
      size(scn%conditions) > 0) then
      ! The impulse (12), the reflection (16) and SYMMETRIC's impulses need M^-1: every DOF must carry mass.
      if (sys%ops%mass_diagonal) then
        call contact_set_mass(rs%cs, sys%ops%mdiag, stat, msg)
      else
        call contact_set_mass(rs%cs, sys%ops%pat, sys%ops%mval, stat, msg)
      end if
      if (stat /= STAT_OK) then
        call set_error(stat, errmsg, STAT_INPUT, scn%path // ': SCHEME IMPACT PAPER/PERSIST/SYMMETRIC needs a mass on every ' // &
          'degree of freedom (the impulse of eq (12) and the reflection of eq (16) use M^-1): ' // msg)
        return
      end if
    end if
    if (scn%impact == IMPACT_MASSLESS) then
      call check_massless(scn, sys, rs%st%massless, stat, errmsg)
      if (stat /= STAT_OK) return
    end if
    call contact_prepare(rs%cs, rs%mat%factor, stat, errmsg, sys%ops%pat, rs%mat%sval)
    if (stat /= STAT_OK) return
    ! The rigid modes and the bodies they are free on, for the momentum-keeping scaling of
    ! PERSIST, MASSLESS and SYMMETRIC.
    call equation_bodies(scn, sys%dofs%eqn, sys%dofs%neq, rs%body)
    call body_rigid_freedom(scn, sys%dofs%eqn, free)
    call contact_set_rigid_modes(rs%cs, rs%rig, rs%mrig, stat, errmsg, free)
    if (stat /= STAT_OK) return
    if (rs%follow%count() > 0 .or. any(scn%models%large)) then   ! end_geometry turns their rotation
      rs%crig = rs%rig
      rs%cmrig = rs%mrig
    end if
    allocate (rs%lam(rs%cs%n_conditions()), rs%act0(rs%cs%n_conditions()))
    allocate (rs%vtry(sys%dofs%neq), rs%mvtry(sys%dofs%neq))
    rs%lam = 0.0_dp
  end subroutine setup_contact


  !> Integrate from START to END, writing history, probes and fields under opts%outdir.
  subroutine run_newmark(scn, sys, rs, opts, summary, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(run_state_t), intent(inout) :: rs
    type(run_options_t), intent(in) :: opts
    type(run_summary_t), intent(out) :: summary
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(output_set_t) :: outs
    type(step_report_t) :: rep
    integer :: step, step0, total_iter, nactive, done, iters, nsub
    integer(8) :: c0, crate, clast
    real(dp) :: t, t0, tfail

    call system_clock(c0, crate)
    clast = c0
    step0 = 0
    total_iter = 0
    done = 0
    ! A checkpoint that cannot be used is bad input: refused before anything is created.
    stat = STAT_OK
    if (allocated(opts%restart)) call load_checkpoint(scn, opts%restart, sys, rs, step0, total_iter, stat, errmsg)
    if (stat == STAT_OK) call make_directory(opts%outdir, stat, errmsg)
    done = step0
    if (stat == STAT_OK .and. step0 > 0 .and. sys%elems%any_large) call rs%st%refresh_geometry(scn, sys)
    ! After a restart the reactions start again from the loaded state (all state functions).
    if (stat == STAT_OK .and. step0 > 0) call refresh_points(scn, sys, rs%st%u, .true.)
    if (stat == STAT_OK .and. step0 > 0) call reaction_update(scn, sys, rs%st%u, rs%st%v, rs%t_now, rs%h, .true.)
    if (stat == STAT_OK .and. step0 > 0 .and. rs%h /= scn%dt) call use_step(scn, sys, rs, outs, rs%h, 0, stat, errmsg)
    if (stat == STAT_OK) call install_signal_handlers(stat, errmsg)
    if (stat == STAT_OK) call outs%open(scn, opts%outdir, step0, rs%t_now, rs%nsteps, rs%has_contact, stat, errmsg)
    nactive = 0
    if (rs%has_contact) nactive = rs%cs%n_active()
    if (stat == STAT_OK .and. step0 == 0) call write_outputs(outs, scn, sys, rs, 0, scn%t_start, 0, nactive, 0, stat, errmsg)

    step = step0
    do while (step < rs%nsteps)
      if (stat /= STAT_OK) exit
      step = step + 1
      t0 = scn%t_start + (step - 1) * rs%h + rs%t_shift
      if (scn%adaptive) t0 = rs%t_now
      t = scn%t_start + step * rs%h + rs%t_shift
      iters = 0
      nsub = 0
      rs%step_short = .false.
      rs%closing_onset = rs%step_located .and. rs%after_onset    ! the step after a located onset
      rs%after_onset = .false.
      rs%step_located = .false.
      if (rs%has_contact .and. scn%locate_events) call rs%events%begin_step(rs%cs, rs%st%v, rs%h)
      rs%st%energy_share = scn%tolerance * max(rs%en%max_scale, rs%en%initial) / real(rs%nsteps, dp)
      ! (ADAPTIVE: the share of the run's span the step covers.)
      if (scn%adaptive) rs%st%energy_share = scn%tolerance * max(rs%en%max_scale, rs%en%initial) * &
        rs%h / (scn%t_end - scn%t_start)
      if (scn%adaptive) then
        call adaptive_step(scn, sys, rs, outs, step, t0, t, iters, nsub, nactive, rep, tfail, stat, errmsg)
      else
        call advance(scn, sys, rs, outs, step, t0, t, rs%h, 0, iters, nsub, nactive, rep, tfail, stat, errmsg)
      end if
      total_iter = total_iter + iters
      if (stat /= STAT_OK) exit
      if (rep%outcome /= STEP_CONVERGED) then
        call step_failure(scn, sys, rs, rep, opts%outdir, step, tfail, nsub, total_iter, stat, errmsg)
        exit
      end if
      if (rs%step_located) rs%events%located = rs%events%located + 1
      if (rs%step_located .and. .not. scn%adaptive) then
        ! The step ended at the event: the grid goes on from there, to END.
        t = t - rs%h + rs%h_located
        rs%t_shift = rs%t_shift + (rs%h_located - rs%h)
        rs%nsteps = step + steps_for(scn%t_end - t, rs%h, scn%t_end - scn%t_start)
        call outs%set_last(rs%nsteps)
      else if (scn%adaptive) then
        rs%nsteps = step + steps_for(max(scn%t_end - t, 0.0_dp), rs%h, scn%t_end - scn%t_start)
        call outs%set_last(rs%nsteps)
      end if
      rs%h_used = t - t0
      rs%t_now = t
      if (rs%h_max_used == 0.0_dp) rs%h_min_used = rs%h_used
      rs%h_min_used = min(rs%h_min_used, rs%h_used)
      rs%h_max_used = max(rs%h_max_used, rs%h_used)
      if (nsub > 1) then
        rs%retried = rs%retried + 1
        if (rs%step_short) rs%impact_retried = rs%impact_retried + 1
        rs%max_sub = max(rs%max_sub, nsub)
      end if
      if (.not. (abs(rs%en%balance()) <= huge(1.0_dp))) then
        call write_outputs(outs, scn, sys, rs, step, t, iters, nactive, nsub, stat, errmsg)
        call set_error(stat, errmsg, STAT_RUN, at_step(step, t) // 'the energies overflowed (kinetic ' // &
          str(rs%en%kinetic) // ', internal ' // str(rs%en%internal()) // &
          '): displacements or velocities beyond what double precision can square')
        exit
      end if
      call write_outputs(outs, scn, sys, rs, step, t, iters, nactive, nsub, stat, errmsg)
      if (stat /= STAT_OK) exit
      if (scn%checkpoint_every > 0) then
        if (mod(step, scn%checkpoint_every) == 0 .or. step == rs%nsteps) &
          call save_checkpoint(scn, opts%outdir, sys, rs, step, t, total_iter, stat, errmsg)
        if (stat /= STAT_OK) exit
      end if
      done = step
      if (signal_received() /= 0) then
        ! SIGINT or SIGTERM: a checkpoint of this complete step, the summary, a non-zero exit.
        call save_checkpoint(scn, opts%outdir, sys, rs, step, t, total_iter, stat, errmsg)
        if (stat == STAT_OK) call set_error(stat, errmsg, STAT_RUN, 'interrupted by signal ' // &
          str(signal_received()) // ' after step ' // str(step) // ' (t = ' // str(t) // '); continue with --restart ' &
          // opts%outdir // '/checkpoint.h5')
        exit
      end if
      if (.not. opts%quiet) call progress(rs%nsteps, step, t, c0, crate, clast)
    end do
    ! The one exit: files closed, summary filled (also on failure: a sweep records the steps and
    ! the balance of a case that stopped).
    call outs%close(stat, errmsg)
    call fill_summary(rs, done, total_iter, c0, crate, summary)
    if (stat == STAT_OK .and. .not. opts%quiet) write (0, '(a)') ''
  end subroutine run_newmark

  !> TIME … ADAPTIVE: the step from t0 at the controller's length (cut at a function's kink),
  !> taken again at half its length while its local error exceeds the tolerance or it fails and
  !> h/2 >= MIN (step_control); the length of the next step chosen. t: where it ended.
  subroutine adaptive_step(scn, sys, rs, outs, step, t0, t, iters, nsub, nactive, rep, tfail, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(run_state_t), intent(inout), target :: rs
    type(output_set_t), intent(inout) :: outs
    integer, intent(in) :: step
    real(dp), intent(in) :: t0
    real(dp), intent(out) :: t
    integer, intent(inout) :: iters, nsub, nactive
    type(step_report_t), intent(out) :: rep
    real(dp), intent(out) :: tfail
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: hs, hn
    logical :: full
    do
      hs = rs%ctl%to_kink(t0, rs%h)
      full = hs == rs%h
      t = t0 + hs
      if (full) then
        call advance(scn, sys, rs, outs, step, t0, t, hs, 0, iters, nsub, nactive, rep, tfail, stat, errmsg)
      else                                       ! to the kink, with the sub-steps' S
        call use_step(scn, sys, rs, outs, hs, 1, stat, errmsg)
        if (stat == STAT_OK) call advance(scn, sys, rs, outs, step, t0, t, hs, 1, iters, nsub, nactive, rep, tfail, &
          stat, errmsg)
        if (stat == STAT_OK .and. rep%outcome == STEP_CONVERGED) call use_step(scn, sys, rs, outs, rs%h, 0, stat, errmsg)
      end if
      if (stat /= STAT_OK) return
      if (rep%outcome == STEP_CONVERGED) exit
      if (.not. (rep%outcome == STEP_REJECTED .or. rs%ctl%can_halve(rs%h))) return
      ! Again at h/2: nothing was committed.
      if (rep%outcome /= STEP_REJECTED) call rs%ctl%failed(rs%h)
      if (rs%has_contact) call rs%cs%warm_start(rs%act0)
      if (rep%outcome == STEP_INDEFINITE) call rs%st%refresh_geometry(scn, sys, tangent=.true.)
      rs%ctl%shrunk = rs%ctl%shrunk + 1
      call change_length(scn, sys, rs, outs, 0.5_dp * rs%h, stat, errmsg)
      if (stat /= STAT_OK) return
    end do
    if (rs%step_located) t = t0 + rs%h_located
    call rs%ctl%accepted(t - t0, full .and. .not. rs%step_located)
    ! (After a cut at an event, or with EVENTS OFF any step that changed the contact set.)
    hn = rs%ctl%next_length(rs%h, rs%step_located .or. (rs%has_contact .and. .not. scn%locate_events .and. &
      rs%cs%n_events() > 0), &
      rs%step_located .and. rs%after_onset, scn%dt)
    if (hn /= rs%h) call change_length(scn, sys, rs, outs, hn, stat, errmsg)
  end subroutine adaptive_step

  !> The run's step becomes h (TIME … ADAPTIVE): S at h, factorized at its level's first use and
  !> kept (select_level), the contact columns and the zone's set up again with it.
  subroutine change_length(scn, sys, rs, outs, h, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    type(run_state_t), intent(inout), target :: rs
    type(output_set_t), intent(inout) :: outs
    real(dp), intent(in) :: h
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: minor
    rs%h = h
    call select_level(rs, scn, sys, h, stat, errmsg, minor)
    if (stat == STAT_OK) call use_step(scn, sys, rs, outs, h, 0, stat, errmsg)
  end subroutine change_length

  !> The step from t0 to t1 = t0 + h (level 0: a time step; level k: one of its 2^k sub-steps):
  !> F(t1), the iteration of eq (9), then the end of the step. An iteration that fails (not
  !> converged, diverged, not finite) with SCHEME RETRY levels left is taken again as two half
  !> steps, each exact in energy as any step; iters counts every iteration spent, nsub the
  !> sub-steps done. On a failure at the last level rep tells how, tfail its time.
  recursive subroutine advance(scn, sys, rs, outs, step, t0, t1, h, level, iters, nsub, nactive, rep, tfail, &
      stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(run_state_t), intent(inout), target :: rs
    type(output_set_t), intent(inout) :: outs
    integer, intent(in) :: step, level
    real(dp), intent(in) :: t0, t1, h
    integer, intent(inout) :: iters, nsub, nactive
    type(step_report_t), intent(out) :: rep
    real(dp), intent(out) :: tfail
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: tm, theta
    logical :: short, onset
    tfail = t1
    call rs%st%set_load(scn, sys, t1)
    if (size(scn%imposes) > 0) call imposed_targets(scn, rs%cs, t1)
    if (any(scn%conditions%moving)) call obstacle_targets(scn, rs%cs, rs%follow, t0, t1)
    if (rs%has_contact) call rs%cs%last_active_set(rs%act0)
    if (level == 0) then
      call attempt(rs%mat)
    else
      call attempt(rs%mat_sub)
    end if
    if (stat /= STAT_OK) then
      errmsg = at_step(step, t1) // errmsg
      return
    end if
    iters = iters + rep%iterations
    if (rep%outcome == STEP_CONVERGED .and. level == 0 .and. scn%locate_events .and. rs%has_contact) then
      theta = rs%events%event_fraction(rs%cs, h, scn%impact == IMPACT_MASSLESS, onset)
      if (rs%ctl%on .and. theta * h < rs%ctl%hmin) theta = 0.0_dp     ! (ADAPTIVE: no cut below MIN)
      if (theta > 0.0_dp) then
        call cut_at_event(t0 + theta * (t1 - t0), theta * h)
        return
      end if
    end if
    if (rep%outcome == STEP_CONVERGED .and. level == 0 .and. rs%ctl%on) then
      ! TIME … ADAPTIVE: a step whose local error exceeds the tolerance is taken again at h/2.
      if (rs%ctl%judge(sys, rs%st%u, rs%st%du, rs%st%v, h, .not. (rs%has_contact .and. rs%cs%changing_set()) .and. &
          .not. rs%closing_onset)) then
        if (rs%has_contact) call rs%cs%warm_start(rs%act0)
        rep%outcome = STEP_REJECTED
        return
      end if
    end if
    if (rep%outcome == STEP_CONVERGED) then
      short = .false.
      if (level < scn%retry) short = impact_short(scn, sys, rs, stat, errmsg)
      if (stat /= STAT_OK) then
        errmsg = at_step(step, t1) // errmsg
        return
      end if
      rs%step_short = rs%step_short .or. short
      if (.not. short) then
        nsub = nsub + 1
        call finish_step(scn, sys, rs, outs, step, t1, h, nactive, stat, errmsg)
        return
      end if
    end if
    if (level >= scn%retry) return
    ! (ADAPTIVE: the controller halves the step itself while h/2 >= MIN.)
    if (level == 0 .and. rs%ctl%on .and. rs%ctl%can_halve(h)) return
    ! Nothing was committed: the same interval again as two half steps (a failed iteration, or
    ! an impact correction that would leave energy in the balance: impact_short).
    if (rs%has_contact) call rs%cs%warm_start(rs%act0)
    if (rep%outcome == STEP_INDEFINITE) call rs%st%refresh_geometry(scn, sys, tangent=.true.)
    call use_step(scn, sys, rs, outs, 0.5_dp * h, level + 1, stat, errmsg)
    if (stat /= STAT_OK) return
    tm = t0 + 0.5_dp * (t1 - t0)
    call advance(scn, sys, rs, outs, step, t0, tm, 0.5_dp * h, level + 1, iters, nsub, nactive, rep, tfail, stat, errmsg)
    if (stat /= STAT_OK .or. rep%outcome /= STEP_CONVERGED) return
    call advance(scn, sys, rs, outs, step, tm, t1, 0.5_dp * h, level + 1, iters, nsub, nactive, rep, tfail, stat, errmsg)
    if (stat /= STAT_OK .or. rep%outcome /= STEP_CONVERGED) return
    call use_step(scn, sys, rs, outs, h, level, stat, errmsg)
  contains
    !> The step cut at the event's instant tm (an onset or a release; length hm): nothing of the
    !> first attempt was committed; the run's S is restored after it and the caller shifts the grid.
    recursive subroutine cut_at_event(tm, hm)
      real(dp), intent(in) :: tm, hm
      rs%step_located = .true.
      rs%h_located = hm
      rs%after_onset = onset
      call rs%cs%warm_start(rs%act0)
      call use_step(scn, sys, rs, outs, hm, level + 1, stat, errmsg)
      if (stat == STAT_OK) call advance(scn, sys, rs, outs, step, t0, tm, hm, level + 1, iters, nsub, nactive, rep, &
        tfail, stat, errmsg)
      if (stat /= STAT_OK .or. rep%outcome /= STEP_CONVERGED) return
      call use_step(scn, sys, rs, outs, h, level, stat, errmsg)
    end subroutine cut_at_event

    subroutine attempt(mat)
      type(iteration_matrix_t), intent(inout), target :: mat
      call following_rows(scn, sys, rs%st, mat, rs%cs, rs%follow, .false., stat, errmsg)   ! pairs in u(n)
      if (stat /= STAT_OK) return
      if (rs%has_contact .and. rs%zone%on) then
        call iterate_eq9_zone(scn, sys, rs%st, mat, rs%zone, rep, stat, errmsg, rs%cs, rs%lam, rs%follow)
      else if (rs%has_contact) then
        call iterate_eq9(scn, sys, rs%st, mat, rep, stat, errmsg, rs%cs, rs%lam, rs%follow)
      else if (rs%zone%on) then
        call iterate_eq9_zone(scn, sys, rs%st, mat, rs%zone, rep, stat, errmsg)
      else
        call iterate_eq9(scn, sys, rs%st, mat, rep, stat, errmsg)
      end if
    end subroutine attempt
  end subroutine advance

  !> IMPACT MASSLESS: would the impact correction of the step that just converged leave energy in
  !> the balance? A release's ½ R(n) g(n+1) more than the body's kinetic energy can give (a step
  !> about as long as the contact, docs/contact.md): the step is then taken again as sub-steps.
  !> Only on steps where a condition changes (a velocity and a product by M more); not with
  !> conditions that follow the geometry (rewritten at the end configuration first).
  logical function impact_short(scn, sys, rs, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    type(run_state_t), intent(inout) :: rs
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: shortfall
    stat = STAT_OK
    impact_short = .false.
    if (.not. (rs%has_contact .and. scn%impact == IMPACT_MASSLESS)) return
    if (rs%follow%count() > 0 .or. .not. rs%cs%changing_set()) return
    rs%vtry = rs%st%v
    call velocity_eq3(rs%st%h, rs%st%du, rs%vtry)
    call mass_times(sys, rs%vtry, rs%mvtry)
    call contact_shortfall(rs%cs, scn%impact, rs%st%u, rs%st%du, rs%vtry, rs%mvtry, rs%body, shortfall, stat, errmsg)
    if (stat /= STAT_OK) return
    impact_short = shortfall > unrestored_floor(rs%en)
  end function impact_short

  !> The energy an impact correction may leave unrestored before it counts (round-off): 1e-12 of
  !> the kinetic + internal energy. Above it the step is retried (impact_short) or, at the last
  !> level, the run warns (finish_step).
  pure real(dp) function unrestored_floor(en)
    type(energy_t), intent(in) :: en
    unrestored_floor = 1.0e-12_dp * max(abs(en%kinetic) + abs(en%internal()), tiny(1.0_dp))
  end function unrestored_floor

  !> The step h for the steps that follow: the run's S (level 0) or the sub-steps' S, set up
  !> afresh (K0 + 4M/h², so that a retry never depends on an earlier one: restarts stay bit for
  !> bit; the first retry allocates its factor, later ones refactorize it); the contact multipliers'
  !> columns and the nonlinear zone's S⁻¹ columns follow S.
  subroutine use_step(scn, sys, rs, outs, h, level, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    type(run_state_t), intent(inout), target :: rs
    type(output_set_t), intent(inout) :: outs
    real(dp), intent(in) :: h
    integer, intent(in) :: level
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(iteration_matrix_t), pointer :: mat
    integer :: minor
    stat = STAT_OK
    mat => rs%mat
    if (level > 0) then
      mat => rs%mat_sub
      call mat%setup(sys, h, stat, errmsg, minor, scn%iter_auto)
      if (stat /= STAT_OK) return
    end if
    call rs%st%set_step(h)
    call outs%set_step(h)
    call rs%zone%columns(mat%factor, stat, errmsg)
    if (stat /= STAT_OK) return
    if (rs%has_contact) call contact_prepare(rs%cs, mat%factor, stat, errmsg, sys%ops%pat, mat%sval)
  end subroutine use_step

  !> The end of a converged step (or sub-step) at t: the state committed with the impact
  !> correction, the events and contact impulses, the reactions and the step's energies.
  subroutine finish_step(scn, sys, rs, outs, step, t, h, nactive, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(run_state_t), intent(inout) :: rs
    type(output_set_t), intent(inout) :: outs
    integer, intent(in) :: step
    real(dp), intent(in) :: t, h
    integer, intent(inout) :: nactive
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(contact_report_t) :: crep
    real(dp) :: dw_ext, dw_corr, e_rest
    logical :: sampled
    if (rs%has_contact .and. (rs%follow%count() > 0 .or. any(scn%models%large))) then
      call end_geometry(scn, sys, rs, stat, errmsg)
      if (stat /= STAT_OK) return
    end if
    if (rs%has_contact) then
      call end_step(scn, sys, rs%st, dw_ext, dw_corr, e_rest, stat, errmsg, rs%cs, rs%body, crep)
      if (stat /= STAT_OK) then
        errmsg = at_step(step, t) // errmsg
        return
      end if
      nactive = crep%n_active
      dw_ext = dw_ext + crep%imposed_work + crep%obstacle_work   ! IMPOSE, OBSTACLE … VELOCITY: their motion's work
      ! RESTITUTION e < 1: the kinetic energy the impact removed is dissipated, not lost by the
      ! scheme; the correction is what was given back (the measured change plus that).
      if (crep%impact_dissipated /= 0.0_dp) then
        call rs%en%add_impact(crep%impact_dissipated)
        e_rest = e_rest + crep%impact_dissipated
      end if
      if (crep%snap_dissipated /= 0.0_dp) call rs%en%add_impact(crep%snap_dissipated)
      if (crep%friction_dissipated /= 0.0_dp) call rs%en%add_friction(crep%friction_dissipated)
      ! SYMMETRIC: the energy the contacts hold until their release, in its own account.
      if (crep%held /= 0.0_dp) then
        call rs%en%add_held(crep%held)
        e_rest = e_rest + crep%held
      end if
      if (crep%unrestored > unrestored_floor(rs%en)) &
        write (0, '(a)') 'rebond: warning: ' // at_step(step, t) // 'the impact correction could not restore ' // &
        str(crep%unrestored) // ' J (more than the body''s kinetic energy can give: a step about as long as the ' // &
        'contact); it stays in the energy balance. A smaller TIME STEP (or IMPACT PERSIST) avoids it'
      if (crep%fp_failures > 0) write (0, '(a)') 'rebond: warning: ' // at_step(step, t) // &
        'the coupled impulses (14) have no all-negative solution; decoupled roots of (13) scaled to restore ' // &
        'the lost energy exactly'
      call outs%write_events(scn, step, t, rs%cs, stat, errmsg)
      if (stat /= STAT_OK) return
      call outs%add_contact_impulses(scn, sys, rs%st%u, rs%st%du, rs%cs)
    else
      call end_step(scn, sys, rs%st, dw_ext, dw_corr, e_rest, stat, errmsg)
      if (stat /= STAT_OK) return
    end if
    call refresh_points(scn, sys, rs%st%u, .true.)
    call reaction_update(scn, sys, rs%st%u, rs%st%v, t, h, .false.)
    if (size(rs%imp_row) > 0) call imposed_reactions(rs%cs, rs%imp_row, rs%imp_slot, rs%imp_w, &
      sys%react%value)
    ! Bσ = K0 u: the strain energy a history line reports is the points' ½ Σ w σ·ε, as the element
    ! loop has it (½ u·K0 u rounds at eps x the condition of K0: 1e-11 of a bent beam's energy).
    sampled = .not. sys%ops%k0u%active() .or. outs%writes_history(scn, step) .or. step == rs%nsteps
    if (sys%ops%k0u%active() .and. sampled) call linear_strain_energy(scn, sys, rs%st%u, rs%st%inc%elastic)
    ! MODEL DAMPING: the step's damping work du'C du/h is booked, so that the balance holds.
    call rs%en%add_damping(rs%st%damping_work(sys))
    call rs%en%add_step(rs%st%kinetic, rs%st%inc%work, dw_ext, dw_corr + e_rest, rs%st%inc%dissipated, &
      rs%st%inc%elastic, sampled)
  end subroutine finish_step

  !> Before the impact corrections of a step with contacts that follow the geometry: the step's
  !> gaps kept, their rows at the end configuration; and in every contact scene with a KINEMATICS
  !> LARGE model the rotation mode about the origin at the step's end (-y, x on the translations,
  !> 1 on RZ) with M times it, so that a scaling keeps the angular momentum history.csv reports
  !> (about the origin of the current configuration) where the contact cannot change it.
  subroutine end_geometry(scn, sys, rs, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    type(run_state_t), intent(inout) :: rs
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (rs%follow%count() > 0) then
      call contact_step_gaps(rs%cs, rs%st%u, rs%st%du)
      call rs%follow%update(scn%mesh%x, sys%dofs%eqn, rs%st%u, rs%cs, stat, errmsg, rs%st%du, at_end=.true.)
      if (stat /= STAT_OK) return
    end if
    call rotation_mode(scn, sys, rs%crig(:, 3), rs%st%u, rs%st%du)
    call mass_times(sys, rs%crig(:, 3), rs%cmrig(:, 3))
    call contact_set_rigid_modes(rs%cs, rs%crig, rs%cmrig, stat, errmsg)
  end subroutine end_geometry

  !> "step N (t = T): ", the prefix of the messages of a step.
  function at_step(step, t) result(s)
    integer, intent(in) :: step
    real(dp), intent(in) :: t
    character(len=:), allocatable :: s
    s = 'step ' // str(step) // ' (t = ' // str(t) // '): '
  end function at_step

  !> The messages of a step whose iteration did not end well (at time t, after nsub of its
  !> SCHEME RETRY sub-steps); the state of the last good step is saved when the iterate is not
  !> finite and no sub-step of this one was committed.
  subroutine step_failure(scn, sys, rs, rep, outdir, step, t, nsub, total_iter, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(run_state_t), intent(in) :: rs
    type(step_report_t), intent(in) :: rep
    character(len=*), intent(in) :: outdir
    integer, intent(in) :: step, nsub, total_iter
    real(dp), intent(in) :: t
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: where, nodes
    integer :: k
    where = ''
    if (scn%retry > 0) where = '; retried as sub-steps down to h/' // str(2**scn%retry) // ' (SCHEME RETRY ' // &
      str(scn%retry) // ')'
    if (any(rep%outcome == [STEP_DIVERGED, STEP_NONFINITE, STEP_INVERTED, STEP_INDEFINITE])) then
      if (nsub == 0) then
        call save_checkpoint(scn, outdir, sys, rs, step - 1, rs%t_now, total_iter, stat, errmsg)
        where = where // '; the state of step ' // str(step - 1) // ' is in ' // outdir // '/checkpoint.h5'
      else
        where = where // '; ' // str(nsub) // ' of its sub-steps were done, so no checkpoint is written'
      end if
    end if
    select case (rep%outcome)
    case (STEP_DIVERGED)
      call set_error(stat, errmsg, STAT_RUN, at_step(step, t) // 'the iteration of eq (9) diverged (residual ' // &
        str(rs%st%res_hist(rep%iterations)) // ' at iteration ' // str(rep%iterations) // ', first non-finite at ' &
        // dof_label(scn, sys, rep%bad_equation) // '; residual norms: ' // &
        residual_history(rs%st%res_hist(1:rep%iterations)) // '); try a smaller TIME STEP or SCHEME ITERATION ' // &
        'TANGENT' // where)
    case (STEP_INVERTED)
      nodes = ''
      do k = 1, scn%mesh%nen(rep%element)
        if (k > 1) nodes = nodes // ' '
        nodes = nodes // str(scn%mesh%node_tag(scn%mesh%conn(k, rep%element)))
      end do
      call set_error(stat, errmsg, STAT_RUN, at_step(step, t) // 'element ' // str(rep%element) // ' (nodes ' // &
        nodes // ', KINEMATICS LARGE) turned inside out: an axis turned by 90 degrees or more in one step, ' // &
        'a length vanished, or det F <= 0' // where)
    case (STEP_NONFINITE)
      call set_error(stat, errmsg, STAT_RUN, at_step(step, t) // 'non-finite displacement or internal force at ' // &
        dof_label(scn, sys, rep%bad_equation) // where)
    case (STEP_INDEFINITE)
      nodes = ''
      if (rep%element > 0) nodes = ' (element ' // str(rep%element) // ' turned inside out)'
      call set_error(stat, errmsg, STAT_RUN, at_step(step, t) // 'the KINEMATICS LARGE tangent at iteration ' // &
        str(rep%iterations) // ' is not positive definite' // nodes // ': ' // rep%message // '; residual norms: ' // &
        residual_history(rs%st%res_hist(1:max(rep%iterations - 1, 0))) // where)
    case default
      call set_error(stat, errmsg, STAT_RUN, 'step ' // str(step) // ' (t = ' // str(t) // ') did not converge in ' &
        // str(rep%iterations) // ' iterations (tolerance ' // str(scn%tolerance) // ' x force scale ' // &
        str(rep%force_scale) // '); residual norms: ' // residual_history(rs%st%res_hist(1:rep%iterations)) // where)
    end select
  end subroutine step_failure

  !> What was done: steps, iterations, the balance, the multipliers' work, the wall time.
  subroutine fill_summary(rs, last, total_iter, c0, crate, summary)
    type(run_state_t), intent(in) :: rs
    integer, intent(in) :: last, total_iter
    integer(8), intent(in) :: c0, crate
    type(run_summary_t), intent(inout) :: summary
    integer(8) :: c1
    summary%steps = last
    summary%iterations = total_iter
    summary%retried = rs%retried
    summary%impact_retried = rs%impact_retried
    summary%located = rs%events%located
    summary%adapt_rejected = rs%ctl%rejected
    summary%adapt_grown = rs%ctl%grown
    summary%adapt_shrunk = rs%ctl%shrunk
    summary%adapt_at_min = rs%ctl%at_min
    summary%h_min_used = rs%h_min_used
    summary%h_max_used = rs%h_max_used
    summary%factorizations = sum(rs%levels%n_factor) + rs%mat_sub%n_factor
    summary%geometric_dropped = sum(rs%levels%n_geometric_dropped) + rs%mat_sub%n_geometric_dropped
    summary%factor = rs%mat%factor%stats()
    summary%max_substeps = rs%max_sub
    summary%max_rel_balance = rs%en%relative_balance()
    if (rs%has_contact) then
      associate (k => rs%cs%counters())
        summary%schur_columns = k%columns
        summary%schur_solves = k%schur_solves
        summary%augmented_solves = k%augmented_solves
        summary%augmented_factorizations = k%factorizations
      end associate
      summary%following = rs%follow%count()
      summary%repairings = rs%follow%changes()
    end if
    call system_clock(c1)
    summary%wall = real(c1 - c0, dp) / real(crate, dp)
  end subroutine fill_summary

  subroutine write_outputs(outs, scn, sys, rs, step, t, iter, nactive, nsub, stat, errmsg)
    type(output_set_t), intent(inout) :: outs
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(run_state_t), intent(in) :: rs
    integer, intent(in) :: step, iter, nactive, nsub
    real(dp), intent(in) :: t
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    if (outs%writes_fields(scn, step)) call refresh_points(scn, sys, rs%st%u, .false.)
    call outs%set_row_step(merge(rs%h_used, 0.0_dp, step > 0))
    if (rs%has_contact) then
      call outs%write_step(scn, sys, step, t, iter, nactive, nsub, rs%en, rs%st%u, rs%st%v, rs%st%mv, rs%rig, stat, errmsg, &
        rs%cs)
    else
      call outs%write_step(scn, sys, step, t, iter, nactive, nsub, rs%en, rs%st%u, rs%st%v, rs%st%mv, rs%rig, stat, errmsg)
    end if
  end subroutine write_outputs


  !> The progress line on stderr (runs longer than 2 s, at most once a second).
  subroutine progress(nsteps, step, t, c0, crate, clast)
    integer, intent(in) :: nsteps, step
    real(dp), intent(in) :: t
    integer(8), intent(in) :: c0, crate
    integer(8), intent(inout) :: clast
    integer(8) :: c1
    real(dp) :: el, eta
    call system_clock(c1)
    if (real(c1 - c0, dp) / crate < 2.0_dp .or. real(c1 - clast, dp) / crate < 1.0_dp) return
    clast = c1
    el = real(c1 - c0, dp) / crate
    eta = el * (nsteps - step) / step
    write (0, '(a,i0,a,i0,a,es11.4,a,f5.1,a,f9.1,a)', advance='no') achar(13) // 'step ', step, '/', nsteps, &
      '  t = ', t, '  (', 100.0_dp * step / nsteps, ' %)  ETA ', eta, ' s   '
  end subroutine progress
end module newmark
