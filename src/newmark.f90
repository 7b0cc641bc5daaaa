!> The time integrator: Newmark's average-acceleration scheme (beta = 1/4, gamma = 1/2) as
!> written in method.md section 1. Only u and v are state; each step solves eq (5)
!>     4M/h² du + Bσ(n+1) = F(n+1) + F(n) - Bσ(n) + 4M v(n)/h
!> by iteration with the matrix S = K0 + 4M/h² (factorized once per step size), then sets the
!> velocity by eq (3). With linear laws the first iterate is exact (eq 7) and the loop ends.
module newmark
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str
  use scene, only: scene_t
  use assembly, only: system_t, internal_force, commit_state, external_force, mass_times, initial_state, &
    element_stress, nodal_values, dof_label
  use cholmod_binding, only: cholmod_factor_t
  use energy, only: energy_t
  use history_writer, only: csv_file_t
  use fields_hdf5, only: fields_writer_t
  use os_utils, only: make_directory
  implicit none
  private
  public :: run_options_t, run_summary_t, prepare_run, run_newmark, run_state_t, velocity_eq3

  type :: run_options_t
    character(len=:), allocatable :: outdir
    logical :: quiet = .false.
  end type run_options_t

  type :: run_summary_t
    integer :: steps = 0
    real(dp) :: wall = 0.0_dp
    real(dp) :: max_rel_balance = 0.0_dp
    integer :: iterations = 0
  end type run_summary_t

  !> Everything the time loop works on, allocated before it starts.
  type :: run_state_t
    integer :: nsteps = 0
    real(dp) :: h = 0.0_dp
    real(dp), allocatable :: u(:), v(:), du(:), ddu(:), r(:), rhs(:), fint_n(:), fint(:), f_n(:), f_np1(:)
    real(dp), allocatable :: mv(:), mdu(:), utrial(:), sval(:)
    type(cholmod_factor_t) :: factor
    type(energy_t) :: en
  end type run_state_t

contains

  !> Eq (3): v(n+1) = 2 du / h - v(n).
  pure subroutine velocity_eq3(h, du, v)
    real(dp), intent(in) :: h, du(:)
    real(dp), intent(inout) :: v(:)
    v = 2.0_dp * du / h - v
  end subroutine velocity_eq3

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
      rs%f_np1(n), rs%mv(n), rs%mdu(n), rs%utrial(n), fstatic(n), ustatic(n))

    call initial_state(scn, sys, rs%u, rs%v, fstatic, has_static, stat, errmsg)
    if (stat /= STAT_OK) return
    if (has_static) then
      ! Static preload: K0 u = f, released at t = 0.
      call rs%factor%factorize(sys%pat, sys%kval, stat, errmsg, minor)
      if (stat /= STAT_OK) then
        call set_error(stat, errmsg, STAT_INPUT, scn%path // ': INITIAL STATIC: the stiffness is singular at ' // &
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
      call set_error(stat, errmsg, STAT_INPUT, scn%path // ': singular system K0 + 4M/h2 at ' // &
        dof_label(scn, sys, minor) // ' (no mass and no stiffness on this mode)')
      return
    end if
    ! Initial internal forces and strain energy: the laws take the path from zero strain to u0.
    call internal_force(scn, sys, rs%u, rs%fint_n)
    call commit_state(sys)
    call mass_times(sys, rs%v, rs%mv)
    kin0 = 0.5_dp * dot_product(rs%v, rs%mv)
    call rs%en%start(kin0, sys%work_t)
    call external_force(scn, sys, scn%t_start, rs%f_n)
  end subroutine prepare_run

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
    real(dp), allocatable :: nodal_u(:, :), nodal_v(:, :), estress(:, :), preals(:), hreals(:)
    integer :: step, iter, total_iter, i
    integer(8) :: c0, c1, crate, clast
    real(dp) :: t, h, dw_ext, kin, c4
    logical :: write_fields
    character(len=:), allocatable :: header

    h = rs%h
    c4 = 4.0_dp / h**2
    call make_directory(opts%outdir, stat, errmsg)
    if (stat /= STAT_OK) return
    call hist%open(opts%outdir // '/history.csv', &
      'step,time,kinetic,internal,external,correction,balance,iterations,active_contacts', stat, errmsg)
    if (stat /= STAT_OK) return
    header = 'step,time'
    do i = 1, size(scn%probes)
      header = header // ',' // scn%probes(i)%label
    end do
    call probes%open(opts%outdir // '/probes.csv', header, stat, errmsg)
    if (stat /= STAT_OK) return
    write_fields = scn%fields_every /= 0
    allocate (nodal_u(3, scn%mesh%nnode), nodal_v(3, scn%mesh%nnode), estress(4, scn%mesh%nelem), &
      preals(1 + size(scn%probes)), hreals(6))
    if (write_fields) then
      call fields%open(opts%outdir, scn%mesh, stat, errmsg)
      if (stat /= STAT_OK) return
    end if

    call system_clock(c0, crate)
    clast = c0
    total_iter = 0
    call write_outputs(0, scn%t_start, 0)
    if (stat /= STAT_OK) return

    do step = 1, rs%nsteps
      t = scn%t_start + step * h
      call external_force(scn, sys, t, rs%f_np1)
      ! Right-hand side of eq (5): F(n+1) + F(n) - Bσ(n) + 4M v(n)/h.
      rs%rhs = rs%f_np1 + rs%f_n - rs%fint_n + (4.0_dp / h) * rs%mv
      ! Iterate on du; the first residual has Bσ(n+1) = Bσ(n) at du = 0.
      rs%du = 0.0_dp
      rs%r = rs%rhs - rs%fint_n
      do iter = 1, scn%max_iterations
        call rs%factor%solve(rs%r, rs%ddu, stat, errmsg)
        if (stat /= STAT_OK) return
        rs%du = rs%du + rs%ddu
        rs%utrial = rs%u + rs%du
        call internal_force(scn, sys, rs%utrial, rs%fint)
        if (sys%linear) exit
        call mass_times(sys, rs%du, rs%mdu)
        rs%r = rs%rhs - c4 * rs%mdu - rs%fint
        if (norm2(rs%r) <= scn%tolerance * force_scale()) exit
        if (iter == scn%max_iterations) then
          call set_error(stat, errmsg, STAT_RUN, 'step ' // str(step) // ' (t = ' // str(t) // &
            ') did not converge in ' // str(iter) // ' iterations: residual ' // str(norm2(rs%r)))
          call finish()
          return
        end if
      end do
      total_iter = total_iter + iter
      ! End of step: eq (3), energies, new state.
      call commit_state(sys)
      dw_ext = 0.5_dp * dot_product(rs%du, rs%f_n + rs%f_np1)
      call velocity_eq3(h, rs%du, rs%v)
      rs%u = rs%utrial
      rs%fint_n = rs%fint
      rs%f_n = rs%f_np1
      call mass_times(sys, rs%v, rs%mv)
      kin = 0.5_dp * dot_product(rs%v, rs%mv)
      call rs%en%add_step(kin, sys%work_t, dw_ext, 0.0_dp)
      call write_outputs(step, t, iter)
      if (stat /= STAT_OK) return
      if (.not. opts%quiet) call progress(step, t)
    end do
    call finish()
    summary%steps = rs%nsteps
    summary%iterations = total_iter
    summary%max_rel_balance = rs%en%relative_balance()
    call system_clock(c1)
    summary%wall = real(c1 - c0, dp) / real(crate, dp)
    if (.not. opts%quiet) write (0, '(a)') ''

  contains

    !> Force scale of the step for the convergence test (docs/input.md, SCHEME TOLERANCE).
    real(dp) function force_scale()
      force_scale = max(norm2(rs%f_np1 + rs%f_n), norm2(rs%fint_n), norm2(rs%fint), norm2((4.0_dp / h) * rs%mv), &
        tiny(1.0_dp))
    end function force_scale

    subroutine write_outputs(step, t, iter)
      integer, intent(in) :: step, iter
      real(dp), intent(in) :: t
      integer :: k
      logical :: last
      last = step == rs%nsteps
      if (scn%history_every > 0) then
        if (mod(step, scn%history_every) == 0 .or. last) then
          hreals = [t, rs%en%kinetic, rs%en%internal(), rs%en%external(), rs%en%correction(), rs%en%balance()]
          call hist%write_row(step, hreals, [iter, 0], stat, errmsg)
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
          call fields%write_step(step, t, nodal_u, nodal_v, estress, stat, errmsg)
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

    subroutine finish()
      call hist%close()
      call probes%close()
      if (write_fields) call fields%close()
    end subroutine finish
  end subroutine run_newmark
end module newmark
