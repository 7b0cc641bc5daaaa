!> The time integrator: Newmark's average-acceleration scheme (beta = 1/4, gamma = 1/2) as
!> written in method.md sections 1 and 2. Only u and v are state; each step solves eq (9)
!>     4M/h² du + Bσ(n+1) + Bσc = F(n+1) + F(n) - Bσ(n) + 4M v(n)/h
!> (eq (5) when the correction is off or every law is linear) by iteration with the matrix
!> S = K0 + 4M/h² (factorized once per step size) or the consistent tangent, then sets the
!> velocity by eq (3). With linear laws the first iterate is exact (eq 7) and the loop ends.
module newmark
  use kinds, only: dp, qp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str
  use scene, only: scene_t, IMPACT_OFF
  use dof_map, only: equation_bodies
  use contact, only: contact_set_t, contact_event_t, contact_report_t, contact_add, contact_finalize, &
    contact_set_mass, contact_prepare, contact_solve_step, contact_end_step, contact_add_force, EVENT_ESTABLISH, &
    contact_set_rigid_modes
  use assembly, only: system_t, internal_force, commit_state, external_force, mass_times, initial_state, &
    element_stress, nodal_values, dof_label, dof_origin, stored_energy, mass_times_q
  use cholmod_binding, only: cholmod_factor_t
  use energy, only: energy_t
  use history_writer, only: csv_file_t
  use fields_hdf5, only: fields_writer_t
  use os_utils, only: make_directory, install_signal_handlers, signal_received
  use checkpoint, only: ckpt_file_t
  use energy, only: ENERGY_STATE_SIZE
  use text_format, only: put_es, put_int, put_text
  implicit none
  private
  public :: run_options_t, run_summary_t, prepare_run, run_newmark, run_state_t, velocity_eq3, rhs_eq9
  public :: HISTORY_HEADER, EVENTS_HEADER

  !> Column names of the result files: public contracts, extended at the end only.
  character(len=*), parameter :: HISTORY_HEADER = &
    'step,time,kinetic,internal,external,correction,balance,iterations,active_contacts,dissipated,stored'
  character(len=*), parameter :: EVENTS_HEADER = 'step,time,constraint,nodes,event,gap_start,multiplier,energy_restored'

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
    ! Contact multipliers (contact_multipliers): Schur columns computed (solves with S), trial
    ! active sets solved by Schur / by the augmented system, its LU factorizations.
    integer(8) :: schur_columns = 0, schur_solves = 0, augmented_solves = 0, augmented_factorizations = 0
  end type run_summary_t

  !> Everything the time loop works on, allocated before it starts.
  type :: run_state_t
    integer :: nsteps = 0
    real(dp) :: h = 0.0_dp
    real(dp), allocatable :: u(:), v(:), du(:), ddu(:), r(:), rhs(:), fint_n(:), fint(:), f_n(:), f_np1(:)
    real(dp), allocatable :: mv(:), mdu(:), utrial(:), sval(:), fcorr(:), res_hist(:)
    ! SCHEME PRECISION EXTENDED: the right-hand side, M v, M du, Bσ and the residual unrounded.
    real(qp), allocatable :: rhs_q(:), mv_q(:), mdu_q(:), fint_n_q(:), r_q(:), u_q(:), v_q(:), utrial_q(:)
    type(cholmod_factor_t) :: factor
    ! Unilateral contact (method.md section 3).
    logical :: has_contact = .false.
    type(contact_set_t) :: cs
    integer, allocatable :: body(:)          !< mesh-connected component of each equation (PERSIST)
    real(dp), allocatable :: du_free(:), lam(:)
    real(dp), allocatable :: reaction(:, :)  !< nodal reactions R(n+1) for fields.h5
    type(energy_t) :: en
  end type run_state_t

contains

  !> Eq (3): v(n+1) = 2 du / h - v(n).
  pure subroutine velocity_eq3(h, du, v)
    real(dp), intent(in) :: h, du(:)
    real(dp), intent(inout) :: v(:)
    v = 2.0_dp * du / h - v
  end subroutine velocity_eq3

  !> Right-hand side of eq (9): F(n+1) + F(n) - Bσ(n) + 4M v(n)/h, with the true Bσ(n) of the
  !> end of the last step: the previous step's Bσc is never carried over (method.md section 2).
  pure subroutine rhs_eq9(h, f_np1, f_n, fint_n, mv, rhs)
    real(dp), intent(in) :: h, f_np1(:), f_n(:), fint_n(:), mv(:)
    real(dp), intent(out) :: rhs(:)
    rhs = f_np1 + f_n - fint_n + (4.0_dp / h) * mv
  end subroutine rhs_eq9

  !> Factorize S = K0 + 4M/h², set the initial state (u0, v0, internal forces, energies).
  !> Everything that can reveal bad input (a singular system) happens here, before any output.
  subroutine prepare_run(scn, sys, rs, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(run_state_t), intent(inout) :: rs
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: n, minor
    real(dp) :: span, kin0
    real(dp), allocatable :: fstatic(:), ustatic(:)
    logical :: has_static

    n = sys%neq
    rs%h = scn%dt
    span = scn%t_end - scn%t_start
    rs%nsteps = nint(span / rs%h)
    if (abs(rs%nsteps * rs%h - span) > 1.0e-9_dp * span) rs%nsteps = ceiling(span / rs%h)
    rs%nsteps = max(rs%nsteps, 1)
    allocate (rs%u(n), rs%v(n), rs%du(n), rs%ddu(n), rs%r(n), rs%rhs(n), rs%fint_n(n), rs%fint(n), rs%f_n(n), &
      rs%f_np1(n), rs%mv(n), rs%mdu(n), rs%utrial(n), rs%fcorr(n), fstatic(n), ustatic(n), &
      rs%res_hist(scn%max_iterations))

    call initial_state(scn, sys, rs%u, rs%v, fstatic, has_static, stat, errmsg)
    if (stat /= STAT_OK) return
    if (has_static) then
      ! Static preload: K0 u = f, released at t = 0.
      call rs%factor%factorize(sys%pat, sys%kval, stat, errmsg, minor)
      if (stat /= STAT_OK) then
        call set_error(stat, errmsg, STAT_INPUT, dof_origin(scn, sys, minor) // &
          ': INITIAL STATIC: the stiffness is singular at ' // &
          dof_label(scn, sys, minor) // ' (a rigid-body mode not held by supports?)')
        return
      end if
      call rs%factor%solve(fstatic, ustatic, stat, errmsg)
      if (stat /= STAT_OK) return
      rs%u = rs%u + ustatic
    end if
    rs%sval = sys%kval + (4.0_dp / rs%h**2) * sys%mval
    call rs%factor%factorize(sys%pat, rs%sval, stat, errmsg, minor)
    if (stat /= STAT_OK) then
      call set_error(stat, errmsg, STAT_INPUT, dof_origin(scn, sys, minor) // ': singular system K0 + 4M/h2 at ' // &
        dof_label(scn, sys, minor) // ' (no mass and no stiffness on this mode)')
      return
    end if
    if (size(scn%conditions) > 0) then
      call setup_contact(scn, sys, rs, stat, errmsg)
      if (stat /= STAT_OK) return
    end if
    ! Initial internal forces and strain energy: the laws take the path from zero strain to u0.
    call internal_force(scn, sys, rs%u, rs%fint_n, rs%fcorr, .false., allocated(sys%tval))
    call commit_state(sys)
    call mass_times(sys, rs%v, rs%mv)
    kin0 = 0.5_dp * dot_product(rs%v, rs%mv)
    if (sys%extended) then
      ! The state itself is kept unrounded: rounding u and v to double at every step drifts
      ! the energy by a fraction of eps per step (docs/precision.md).
      allocate (rs%rhs_q(n), rs%mv_q(n), rs%mdu_q(n), rs%r_q(n), rs%utrial_q(n))
      rs%u_q = real(rs%u, qp)
      rs%v_q = real(rs%v, qp)
      call internal_force(scn, sys, rs%u, rs%fint_n, rs%fcorr, .false., allocated(sys%tval), uq=rs%u_q)
      rs%fint_n_q = sys%fint_q
      call mass_times_q(sys, rs%v_q, rs%mv_q)
      kin0 = real(0.5_qp * sum(rs%v_q * rs%mv_q), dp)
    end if
    call rs%en%start(kin0, sys%work_t, sys%elastic_t)
    call external_force(scn, sys, scn%t_start, rs%f_n)
  end subroutine prepare_run

  !> The contact conditions as constraint rows on the free equations: g = g0 + n.(u_b - u_a);
  !> the mass for the impulse and the reflection, the Schur data of S for the multipliers.
  subroutine setup_contact(scn, sys, rs, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    type(run_state_t), intent(inout) :: rs
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: j, k, a, b, eqs(4)
    real(dp) :: coefs(4), lscale
    real(dp), allocatable :: trig(:, :), mtrig(:, :)
    character(len=:), allocatable :: msg
    rs%has_contact = .true.
    do j = 1, size(scn%conditions)
      associate (c => scn%conditions(j))
        a = c%node_a
        b = c%node_b
        eqs = 0
        coefs(1:2) = c%normal
        coefs(3:4) = -c%normal
        eqs(1:2) = max(sys%eqn(1:2, b), 0)
        if (a > 0) eqs(3:4) = max(sys%eqn(1:2, a), 0)
        call contact_add(rs%cs, c%g0, eqs, coefs, nodes=[a, b], label=c%source)
      end associate
    end do
    associate (x => scn%mesh%x(:, 1:scn%mesh%nnode))
      lscale = max(maxval(x(1, :)) - minval(x(1, :)), maxval(x(2, :)) - minval(x(2, :)))
    end associate
    if (lscale <= 0.0_dp) lscale = 1.0_dp
    rs%cs%settings%solver = scn%multipliers
    rs%cs%settings%switch_size = scn%augmented_above
    call contact_finalize(rs%cs, sys%neq, lscale, stat, errmsg)
    if (stat /= STAT_OK) return
    if (scn%impact /= IMPACT_OFF) then
      ! The impulse (12) and the reflection (16) need M^-1: every DOF must carry mass.
      if (sys%mass_diagonal) then
        call contact_set_mass(rs%cs, sys%mdiag, stat, msg)
      else
        call contact_set_mass(rs%cs, sys%pat, sys%mval, stat, msg)
      end if
      if (stat /= STAT_OK) then
        call set_error(stat, errmsg, STAT_INPUT, scn%path // ': SCHEME IMPACT PAPER/PERSIST needs a mass on every ' // &
          'degree of freedom (the impulse of eq (12) and the reflection of eq (16) use M^-1): ' // msg)
        return
      end if
    end if
    call contact_prepare(rs%cs, rs%factor, stat, errmsg, sys%pat, rs%sval)
    if (stat /= STAT_OK) return
    ! Rigid translations on the free equations, for PERSIST's momentum-keeping scaling.
    allocate (trig(sys%neq, 2), mtrig(sys%neq, 2))
    trig = 0.0_dp
    do j = 1, scn%mesh%nnode
      do k = 1, 2
        if (sys%eqn(k, j) > 0) trig(sys%eqn(k, j), k) = 1.0_dp
      end do
    end do
    do k = 1, 2
      call mass_times(sys, trig(:, k), mtrig(:, k))
    end do
    call contact_set_rigid_modes(rs%cs, trig, mtrig, stat, errmsg)
    if (stat /= STAT_OK) return
    call equation_bodies(scn, sys%eqn, sys%neq, rs%body)
    allocate (rs%du_free(sys%neq), rs%lam(size(scn%conditions)), rs%reaction(3, scn%mesh%nnode))
    rs%lam = 0.0_dp
    rs%reaction = 0.0_dp
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
    type(csv_file_t) :: hist, probes
    type(fields_writer_t) :: fields
    real(dp), allocatable :: nodal_u(:, :), nodal_v(:, :), estress(:, :), preals(:), hreals(:), htail(:)
    integer :: step, iter, total_iter, i
    integer(8) :: c0, c1, crate, clast
    real(dp) :: t, h, dw_ext, dw_corr, kin, c4, e_rest
    real(qp) :: aq
    integer :: nactive, step0, k, done
    logical :: elastic_fallback
    character(len=32) :: part
    type(csv_file_t) :: ev
    type(contact_report_t) :: crep
    logical :: write_fields
    character(len=:), allocatable :: header

    h = rs%h
    c4 = 4.0_dp / h**2
    ! EXTENDED: 4/h and 4/h² of eq (5) and 2/h of eq (3) from one unrounded a = 2/h, so that the
    ! energy identity (8) holds beyond double precision.
    aq = 2.0_qp / real(h, qp)
    call make_directory(opts%outdir, stat, errmsg)
    if (stat /= STAT_OK) return
    step0 = 0
    total_iter = 0
    if (allocated(opts%restart)) then
      call load_checkpoint(opts%restart, step0, total_iter, stat, errmsg)
      if (stat /= STAT_OK) return
    end if
    header = 'step,time'
    do i = 1, size(scn%probes)
      header = header // ',' // scn%probes(i)%label
    end do
    if (step0 > 0) then
      ! Lines a killed run wrote after its checkpoint are dropped, then the run appends.
      call hist%resume(opts%outdir // '/history.csv', HISTORY_HEADER, step0, stat, errmsg)
      if (stat /= STAT_OK) return
      call probes%resume(opts%outdir // '/probes.csv', header, step0, stat, errmsg)
    else
      call hist%open(opts%outdir // '/history.csv', HISTORY_HEADER, stat, errmsg)
      if (stat /= STAT_OK) return
      call probes%open(opts%outdir // '/probes.csv', header, stat, errmsg)
    end if
    if (stat /= STAT_OK) return
    write_fields = scn%fields_every /= 0
    allocate (nodal_u(3, scn%mesh%nnode), nodal_v(3, scn%mesh%nnode), estress(4, scn%mesh%nelem), &
      preals(1 + size(scn%probes)), hreals(6), htail(2))
    if (write_fields) then
      if (step0 > 0) then
        write (part, '(a,i6.6)') 'fields_restart_', step0
        call fields%open(opts%outdir, scn%mesh, stat, errmsg, basename=trim(part))
      else
        call fields%open(opts%outdir, scn%mesh, stat, errmsg)
      end if
      if (stat /= STAT_OK) return
    end if

    if (rs%has_contact) then
      if (step0 > 0) then
        call ev%resume(opts%outdir // '/events.csv', EVENTS_HEADER, step0, stat, errmsg)
      else
        call ev%open(opts%outdir // '/events.csv', EVENTS_HEADER, stat, errmsg)
      end if
      if (stat /= STAT_OK) return
    end if
    nactive = 0
    if (rs%has_contact) nactive = rs%cs%n_active()
    call install_signal_handlers(stat, errmsg)
    if (stat /= STAT_OK) return
    call system_clock(c0, crate)
    clast = c0
    if (step0 == 0) then
      call write_outputs(0, scn%t_start, 0)
      if (stat /= STAT_OK) return
    end if

    done = step0
    do step = step0 + 1, rs%nsteps
      t = scn%t_start + step * h
      call external_force(scn, sys, t, rs%f_np1)
      call rhs_eq9(h, rs%f_np1, rs%f_n, rs%fint_n, rs%mv, rs%rhs)
      ! Iterate eq (9) on du from du = 0, where Bσ(n+1) = Bσ(n) and Bσc = 0.
      rs%du = 0.0_dp
      rs%r = rs%rhs - rs%fint_n
      if (sys%extended) then
        rs%rhs_q = real(rs%f_np1, qp) + real(rs%f_n, qp) - rs%fint_n_q + 2.0_qp * aq * rs%mv_q
        rs%r = real(rs%rhs_q - rs%fint_n_q, dp)
      end if
      elastic_fallback = .false.
      do iter = 1, scn%max_iterations
        if (allocated(sys%tval) .and. .not. elastic_fallback) then
          ! ITERATION TANGENT: refactorize with the tangent of the latest state.
          rs%sval = sys%tval + c4 * sys%mval
          call rs%factor%factorize(sys%pat, rs%sval, stat, errmsg)
          if (stat /= STAT_OK) then
            errmsg = 'step ' // str(step) // ' (t = ' // str(t) // '): tangent matrix: ' // errmsg
            call finish()
            return
          end if
          if (rs%has_contact) then
            call contact_prepare(rs%cs, rs%factor, stat, errmsg, sys%pat, rs%sval)
            if (stat /= STAT_OK) then
              call finish()
              return
            end if
          end if
        end if
        call rs%factor%solve(rs%r, rs%ddu, stat, errmsg)
        if (stat /= STAT_OK) return
        if (rs%has_contact) then
          ! Multipliers: the unconstrained iterate, then du = du_free + S^-1 C' Lambda with the
          ! active set of the LCP (gaps >= 0, Lambda >= 0, complementarity).
          rs%du_free = rs%du + rs%ddu
          call contact_solve_step(rs%cs, rs%factor, rs%u, rs%du_free, rs%du, rs%lam, stat, errmsg)
          if (stat /= STAT_OK) then
            errmsg = 'step ' // str(step) // ' (t = ' // str(t) // '): contact: ' // errmsg
            call finish()
            return
          end if
        else
          rs%du = rs%du + rs%ddu
        end if
        if (sys%extended) then
          rs%utrial_q = rs%u_q + real(rs%du, qp)
          rs%utrial = real(rs%utrial_q, dp)
          call internal_force(scn, sys, rs%utrial, rs%fint, rs%fcorr, scn%energy_correction, allocated(sys%tval), &
            uq=rs%utrial_q)
        else
          rs%utrial = rs%u + rs%du
          call internal_force(scn, sys, rs%utrial, rs%fint, rs%fcorr, scn%energy_correction, allocated(sys%tval))
        end if
        if (sys%linear .and. .not. sys%extended) exit
        ! Residual of eq (9); Bσ(n+1) and Bσc were updated together.
        if (sys%extended) then
          call mass_times_q(sys, real(rs%du, qp), rs%mdu_q)
          rs%r_q = rs%rhs_q - aq**2 * rs%mdu_q - sys%fint_q - real(rs%fcorr, qp)
          rs%r = real(rs%r_q, dp)
        else
          call mass_times(sys, rs%du, rs%mdu)
          rs%r = rs%rhs - c4 * rs%mdu - rs%fint - rs%fcorr
        end if
        ! rs%r is the residual without the contact forces: the next unconstrained iterate is
        ! du + S^-1 r and contact_solve_step adds S^-1 C' Lambda with the total multiplier.
        ! Convergence is judged on the full residual, with C' Lambda on the right of eq (9).
        if (rs%has_contact) then
          rs%ddu = rs%r
          call contact_add_force(rs%cs, rs%ddu)
          rs%res_hist(iter) = norm2(rs%ddu)
        else
          rs%res_hist(iter) = norm2(rs%r)
        end if
        if (.not. (rs%res_hist(iter) <= huge(1.0_dp))) then
          ! Non-finite: the state of the last good step is saved, the first offending DOF named.
          k = max(first_nonfinite(rs%r), 1)
          call save_checkpoint(step - 1, t - h, total_iter, stat, errmsg)
          call set_error(stat, errmsg, STAT_RUN, 'step ' // str(step) // ' (t = ' // str(t) // &
            '): the iteration of eq (9) diverged (residual ' // str(rs%res_hist(iter)) // ' at iteration ' // &
            str(iter) // ', first non-finite at ' // dof_label(scn, sys, k) // '; residual norms: ' // &
            history_text(rs%res_hist(1:iter)) // '); try a smaller TIME STEP or SCHEME ITERATION TANGENT; the ' // &
            'state of step ' // str(step - 1) // ' is in ' // opts%outdir // '/checkpoint.h5')
          call finish()
          return
        end if
        if (sys%linear) then
          ! Refinement of a linear step: on until the residual stops falling (round-off).
          if (iter >= 2) then
            if (rs%res_hist(iter) >= 0.5_dp * rs%res_hist(iter - 1)) exit
          end if
          ! (An absolute floor such as 16 eps x force scale stops too early: at small steps the
          ! scale is 4Mv/h and the first iterate passes it unrefined.)
          if (rs%res_hist(iter) == 0.0_dp .or. iter == min(scn%max_iterations, 6)) exit
          cycle
        end if
        if (rs%res_hist(iter) <= scn%tolerance * force_scale()) exit
        if (allocated(sys%tval) .and. .not. elastic_fallback .and. iter >= 4) then
          ! The tangent iteration stalls when a point switches between plastic loading and
          ! elastic unloading from one iterate to the next (perfect plasticity): after two
          ! iterates in a row without progress, go on with K0 + 4M/h², which contracts
          ! monotonically, for the rest of the step. (One iterate without progress is normal
          ! for Newton near a collapse.)
          if (rs%res_hist(iter) >= 0.99_dp * rs%res_hist(iter - 1) .and. &
            rs%res_hist(iter - 1) >= 0.99_dp * rs%res_hist(iter - 2)) then
            elastic_fallback = .true.
            rs%sval = sys%kval + c4 * sys%mval
            call rs%factor%factorize(sys%pat, rs%sval, stat, errmsg)
            if (stat == STAT_OK .and. rs%has_contact) call contact_prepare(rs%cs, rs%factor, stat, errmsg, sys%pat, &
              rs%sval)
            if (stat /= STAT_OK) then
              call finish()
              return
            end if
          end if
        end if
        if (iter == scn%max_iterations) then
          call set_error(stat, errmsg, STAT_RUN, 'step ' // str(step) // ' (t = ' // str(t) // &
            ') did not converge in ' // str(iter) // ' iterations (tolerance ' // str(scn%tolerance) // &
            ' x force scale ' // str(force_scale()) // '); residual norms: ' // history_text(rs%res_hist(1:iter)))
          call finish()
          return
        end if
      end do
      total_iter = total_iter + iter
      ! A non-finite result stops the run; the state of the last good step is saved first.
      k = first_nonfinite(rs%du)
      if (k == 0) k = first_nonfinite(rs%fint)
      if (k > 0) then
        call save_checkpoint(step - 1, t - h, total_iter - iter, stat, errmsg)
        call set_error(stat, errmsg, STAT_RUN, 'step ' // str(step) // ' (t = ' // str(t) // &
          '): non-finite displacement or internal force at ' // dof_label(scn, sys, k) // &
          '; the state of step ' // str(step - 1) // ' is in ' // opts%outdir // '/checkpoint.h5')
        call finish()
        return
      end if
      ! End of step: eq (3), energies, new state.
      call commit_state(sys)
      dw_ext = 0.5_dp * dot_product(rs%du, rs%f_n + rs%f_np1)
      dw_corr = 0.5_dp * dot_product(rs%du, rs%fcorr)
      call velocity_eq3(h, rs%du, rs%v)
      if (sys%extended) then
        rs%v_q = aq * real(rs%du, qp) - rs%v_q
        rs%v = real(rs%v_q, dp)
      end if
      call mass_times(sys, rs%v, rs%mv)
      e_rest = 0.0_dp
      nactive = 0
      if (rs%has_contact) then
        ! Order at the end of a step: (3), then (12)-(15), then (16) (or PERSIST).
        rs%ddu = rs%v    ! v(n+1) by eq (3), to carry the correction into the unrounded state
        call contact_end_step(rs%cs, scn%impact, rs%u, rs%du, rs%v, rs%mv, e_rest, stat, errmsg, &
          body=rs%body, report=crep)
        if (stat /= STAT_OK) then
          errmsg = 'step ' // str(step) // ' (t = ' // str(t) // '): impact correction: ' // errmsg
          call finish()
          return
        end if
        nactive = crep%n_active
        if (crep%fp_failures > 0) write (0, '(a)') 'rebond: warning: step ' // str(step) // ' (t = ' // str(t) // &
          '): the coupled impulses (14) have no all-negative solution; decoupled roots of (13) scaled to restore ' // &
          'the lost energy exactly'
        if (sys%extended) rs%v_q = rs%v_q + real(rs%v - rs%ddu, qp)
        call write_events(step, t)
        if (stat /= STAT_OK) return
      end if
      rs%u = rs%utrial
      rs%fint_n = rs%fint
      rs%f_n = rs%f_np1
      kin = 0.5_dp * dot_product(rs%v, rs%mv)
      if (sys%extended) then
        rs%fint_n_q = sys%fint_q
        rs%u_q = rs%utrial_q
        rs%v = real(rs%v_q, dp)
        call mass_times_q(sys, rs%v_q, rs%mv_q)
        rs%mv = real(rs%mv_q, dp)
        kin = real(0.5_qp * sum(rs%v_q * rs%mv_q), dp)
      end if
      call rs%en%add_step(kin, sys%work_t, dw_ext, dw_corr + e_rest, sys%dissip_t, sys%elastic_t)
      if (.not. (abs(rs%en%balance()) <= huge(1.0_dp))) then
        call write_outputs(step, t, iter)
        call set_error(stat, errmsg, STAT_RUN, 'step ' // str(step) // ' (t = ' // str(t) // &
          '): the energies overflowed (kinetic ' // str(rs%en%kinetic) // ', internal ' // str(rs%en%internal()) // &
          '): displacements or velocities beyond what double precision can square')
        call finish()
        return
      end if
      call write_outputs(step, t, iter)
      if (stat /= STAT_OK) return
      if (scn%checkpoint_every > 0) then
        if (mod(step, scn%checkpoint_every) == 0 .or. step == rs%nsteps) then
          call save_checkpoint(step, t, total_iter, stat, errmsg)
          if (stat /= STAT_OK) return
        end if
      end if
      if (signal_received() /= 0) then
        ! SIGINT or SIGTERM: a checkpoint of this complete step, the summary, a non-zero exit.
        call save_checkpoint(step, t, total_iter, stat, errmsg)
        if (stat /= STAT_OK) return
        call fill_summary(step)
        call set_error(stat, errmsg, STAT_RUN, 'interrupted by signal ' // str(signal_received()) // ' after step ' // &
          str(step) // ' (t = ' // str(t) // '); continue with --restart ' // opts%outdir // '/checkpoint.h5')
        call finish()
        return
      end if
      done = step
      if (.not. opts%quiet) call progress(step, t)
    end do
    call finish()
    call fill_summary(rs%nsteps)
    if (.not. opts%quiet) write (0, '(a)') ''

  contains

    subroutine fill_summary(last)
      integer, intent(in) :: last
      summary%steps = last
      summary%iterations = total_iter
      summary%max_rel_balance = rs%en%relative_balance()
      if (rs%has_contact) then
        associate (k => rs%cs%counters())
          summary%schur_columns = k%columns
          summary%schur_solves = k%schur_solves
          summary%augmented_solves = k%augmented_solves
          summary%augmented_factorizations = k%factorizations
        end associate
      end if
      call system_clock(c1)
      summary%wall = real(c1 - c0, dp) / real(crate, dp)
    end subroutine fill_summary

    !> Index of the first NaN or infinite entry, 0 if none.
    integer function first_nonfinite(x)
      real(dp), intent(in) :: x(:)
      integer :: i
      first_nonfinite = 0
      do i = 1, size(x)
        if (.not. (abs(x(i)) <= huge(1.0_dp))) then
          first_nonfinite = i
          return
        end if
      end do
    end function first_nonfinite

    !> The whole state at the end of step `step` in OUTDIR/checkpoint.h5, atomically.
    subroutine save_checkpoint(step, t, iters, stat, errmsg)
      integer, intent(in) :: step, iters
      real(dp), intent(in) :: t
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
      type(ckpt_file_t) :: ck
      call ck%create(opts%outdir // '/checkpoint.h5', stat, errmsg)
      if (stat /= STAT_OK) return
      call ck%put('step', step, stat, errmsg)
      call ck%put('time', t, stat, errmsg)
      call ck%put('iterations', iters, stat, errmsg)
      call ck%put('neq', sys%neq, stat, errmsg)
      call ck%put('u', rs%u, stat, errmsg)
      call ck%put('v', rs%v, stat, errmsg)
      call ck%put('fint_n', rs%fint_n, stat, errmsg)
      call ck%put('f_n', rs%f_n, stat, errmsg)
      call ck%put('mv', rs%mv, stat, errmsg)
      call ck%put('eps', sys%eps, stat, errmsg)
      call ck%put('sig', sys%sig, stat, errmsg)
      if (sys%nq > 0) call ck%put('q', sys%q, stat, errmsg)
      call ck%put('energy', rs%en%pack_state(), stat, errmsg)
      if (sys%extended) then
        call ck%put('u_q', rs%u_q, stat, errmsg)
        call ck%put('v_q', rs%v_q, stat, errmsg)
        call ck%put('fint_n_q', rs%fint_n_q, stat, errmsg)
        call ck%put('mv_q', rs%mv_q, stat, errmsg)
      end if
      if (rs%has_contact) call rs%cs%save(ck, stat, errmsg)
      call ck%commit(stat, errmsg)
    end subroutine save_checkpoint

    !> The state saved by save_checkpoint, checked against this scene's sizes.
    subroutine load_checkpoint(path, step, iters, stat, errmsg)
      character(len=*), intent(in) :: path
      integer, intent(out) :: step, iters
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
      type(ckpt_file_t) :: ck
      integer :: neq
      real(dp) :: en(ENERGY_STATE_SIZE), tck
      call ck%open(path, stat, errmsg)
      if (stat /= STAT_OK) return
      call ck%get('step', step, stat, errmsg)
      call ck%get('time', tck, stat, errmsg)
      call ck%get('iterations', iters, stat, errmsg)
      call ck%get('neq', neq, stat, errmsg)
      if (stat == STAT_OK .and. (neq /= sys%neq .or. step < 0 .or. step > rs%nsteps)) then
        call set_error(stat, errmsg, STAT_INPUT, 'checkpoint ' // path // ': step ' // str(step) // ' of a system of ' // &
          str(neq) // ' equations does not fit this scene (' // str(sys%neq) // ' equations, ' // str(rs%nsteps) // &
          ' steps)')
      end if
      call ck%get('u', rs%u, stat, errmsg)
      call ck%get('v', rs%v, stat, errmsg)
      call ck%get('fint_n', rs%fint_n, stat, errmsg)
      call ck%get('f_n', rs%f_n, stat, errmsg)
      call ck%get('mv', rs%mv, stat, errmsg)
      call ck%get('eps', sys%eps, stat, errmsg)
      call ck%get('sig', sys%sig, stat, errmsg)
      if (sys%nq > 0) call ck%get('q', sys%q, stat, errmsg)
      call ck%get('energy', en, stat, errmsg)
      if (stat == STAT_OK) call rs%en%unpack_state(en)
      if (sys%extended) then
        call ck%get('u_q', rs%u_q, stat, errmsg)
        call ck%get('v_q', rs%v_q, stat, errmsg)
        call ck%get('fint_n_q', rs%fint_n_q, stat, errmsg)
        call ck%get('mv_q', rs%mv_q, stat, errmsg)
      end if
      if (rs%has_contact) call rs%cs%load(ck, stat, errmsg)
      call ck%close()
    end subroutine load_checkpoint

    !> Force scale of the step for the convergence test (docs/input.md, SCHEME TOLERANCE).
    real(dp) function force_scale()
      force_scale = max(norm2(rs%f_np1 + rs%f_n), norm2(rs%fint_n), norm2(rs%fint), norm2((4.0_dp / h) * rs%mv), &
        tiny(1.0_dp))
    end function force_scale

    !> Residual norms as text, for the non-convergence report.
    function history_text(res) result(txt)
      real(dp), intent(in) :: res(:)
      character(len=:), allocatable :: txt
      integer :: k
      character(len=16) :: buf
      txt = ''
      do k = 1, size(res)
        write (buf, '(es10.3)') res(k)
        txt = txt // trim(adjustl(buf)) // merge(', ', '  ', k < size(res))
      end do
      txt = trim(txt)
    end function history_text

    subroutine write_outputs(step, t, iter)
      integer, intent(in) :: step, iter
      real(dp), intent(in) :: t
      integer :: k
      logical :: last
      last = step == rs%nsteps
      if (scn%history_every > 0) then
        if (mod(step, scn%history_every) == 0 .or. last) then
          hreals = [t, rs%en%kinetic, rs%en%internal(), rs%en%external(), rs%en%correction(), rs%en%balance()]
          if (sys%linear) then
            htail = [0.0_dp, rs%en%elastic]
          else
            htail = [rs%en%dissipated(), stored_energy(scn, sys)]
          end if
          call hist%write_row(step, hreals, [iter, nactive], stat, errmsg, htail)
          if (stat /= STAT_OK) return
          preals(1) = t
          do k = 1, size(scn%probes)
            preals(k + 1) = 0.0_dp
            associate (j => sys%eqn(scn%probes(k)%dof, scn%probes(k)%node))
              if (j > 0) preals(k + 1) = rs%u(j)
            end associate
          end do
          call probes%write_row(step, preals, [integer ::], stat, errmsg)
          if (stat /= STAT_OK) return
        end if
      end if
      if (write_fields) then
        if (step == 0 .or. last .or. (scn%fields_every > 0 .and. mod(step, max(scn%fields_every, 1)) == 0)) then
          call nodal_values(sys, rs%u, nodal_u)
          call nodal_values(sys, rs%v, nodal_v)
          call element_stress(sys, estress)
          if (rs%has_contact) then
            call contact_reactions()
            call fields%write_step(step, t, nodal_u, nodal_v, estress, stat, errmsg, reaction=rs%reaction)
          else
            call fields%write_step(step, t, nodal_u, nodal_v, estress, stat, errmsg)
          end if
        end if
      end if
    end subroutine write_outputs

    subroutine progress(step, t)
      integer, intent(in) :: step
      real(dp), intent(in) :: t
      real(dp) :: el, eta
      call system_clock(c1)
      if (real(c1 - c0, dp) / crate < 2.0_dp .or. real(c1 - clast, dp) / crate < 1.0_dp) return
      clast = c1
      el = real(c1 - c0, dp) / crate
      eta = el * (rs%nsteps - step) / step
      write (0, '(a,i0,a,i0,a,es11.4,a,f5.1,a,f9.1,a)', advance='no') achar(13) // 'step ', step, '/', rs%nsteps, &
        '  t = ', t, '  (', 100.0_dp * step / rs%nsteps, ' %)  ETA ', eta, ' s   '
    end subroutine progress

    !> Nodal reactions R(n+1) = Lambda - R(n) of the contact conditions (R on node b along n,
    !> its opposite on node a).
    subroutine contact_reactions()
      integer :: j
      rs%reaction = 0.0_dp
      do j = 1, size(scn%conditions)
        associate (c => scn%conditions(j))
          rs%reaction(1:2, c%node_b) = rs%reaction(1:2, c%node_b) + rs%cs%reaction(j) * c%normal
          if (c%node_a > 0) rs%reaction(1:2, c%node_a) = rs%reaction(1:2, c%node_a) - rs%cs%reaction(j) * c%normal
        end associate
      end do
    end subroutine contact_reactions

    !> events.csv: one line per contact established or released in the step, built with
    !> text_format in a fixed buffer (no internal WRITE, no allocation: these are in the loop).
    subroutine write_events(step, t)
      integer, intent(in) :: step
      real(dp), intent(in) :: t
      type(contact_event_t) :: event
      integer :: k, j, pos
      character(len=256) :: line
      do k = 1, rs%cs%n_events()
        event = rs%cs%event(k)
        j = event%index
        pos = 0
        call put_int(line, pos, step)
        call put_text(line, pos, ',')
        call put_es(line, pos, t)
        call put_text(line, pos, ',')
        call put_int(line, pos, j)
        call put_text(line, pos, ',')
        if (scn%conditions(j)%node_a > 0) then
          call put_int(line, pos, scn%conditions(j)%node_a)
          call put_text(line, pos, ' ')
        end if
        call put_int(line, pos, scn%conditions(j)%node_b)
        if (event%kind == EVENT_ESTABLISH) then
          call put_text(line, pos, ',establish,')
        else
          call put_text(line, pos, ',release,')
        end if
        call put_es(line, pos, event%gap_start)
        call put_text(line, pos, ',')
        call put_es(line, pos, event%multiplier)
        call put_text(line, pos, ',')
        call put_es(line, pos, merge(event%energy, 0.0_dp, event%kind == EVENT_ESTABLISH))
        write (ev%unit, '(a)') line(1:pos)
      end do
      if (rs%cs%n_events() > 0) flush (ev%unit)
    end subroutine write_events

    !> Close the result files; the summary then tells what was done (also on failure: a
    !> sweep records the steps and the balance of a case that stopped).
    subroutine finish()
      call fill_summary(done)
      if (rs%has_contact) call ev%close()
      call hist%close()
      call probes%close()
      if (write_fields) call fields%close()
    end subroutine finish
  end subroutine run_newmark
end module newmark
