!> The state of a run that the time loop advances, and its checkpoint: u, v and the step's
!> iterate, the iteration matrices, the contact set with its followers and event locator, the
!> energies, the run's time grid (a located contact onset shifts it: t_shift), and the counters.
module run_state
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use scene, only: scene_t
  use contact, only: contact_set_t
  use assembly, only: system_t, save_points, load_points
  use energy, only: energy_t
  use internal_forces, only: refresh_points
  use step_state, only: step_state_t
  use iteration_matrix, only: iteration_matrix_t
  use nonlinear_zone, only: zone_t
  use static_preload, only: static_report_t
  use contact_geometry, only: following_t
  use event_location, only: event_locator_t
  use step_control, only: step_controller_t
  use checkpoint, only: ckpt_file_t
  use scene_fingerprint, only: fingerprint_mismatch
  implicit none
  private
  public :: run_state_t, save_checkpoint, load_checkpoint, steps_for, init_levels, select_level, release_matrices

  type :: run_state_t
    integer :: nsteps = 0
    real(dp) :: h = 0.0_dp
    !> Step k ends at t_start + k h + t_shift: a step split at an impact's onset (SCHEME EVENTS
    !> LOCATE) ends there, the grid shifted by the part not taken (h_located − h, event_location).
    real(dp) :: t_shift = 0.0_dp, h_located = 0.0_dp
    real(dp) :: t_now = 0.0_dp, h_used = 0.0_dp    !< the end of the last step and its length
    real(dp) :: h_min_used = 0.0_dp, h_max_used = 0.0_dp   !< the shortest and longest steps so far
    type(step_controller_t) :: ctl                 !< TIME … ADAPTIVE (step_control)
    !> The last located event was an onset: the step after it closes the contact at a zero gap
    !> (closing_onset: that step, which TIME … ADAPTIVE does not judge).
    logical :: after_onset = .false., closing_onset = .false.
    type(step_state_t) :: st                 !< u, v and the iterate of the step
    !> S and its policy at the run's step: one of levels, S at STEP 2^k for k = k_lo … (TIME …
    !> ADAPTIVE: each factorized at its first use and kept, so that a return to a length costs no
    !> factorization; one level otherwise).
    type(iteration_matrix_t), pointer :: mat => null()
    type(iteration_matrix_t), pointer :: levels(:) => null()
    integer :: k_lo = 0
    type(iteration_matrix_t) :: mat_sub      !< S of SCHEME RETRY's sub-steps (set up at each retry)
    type(zone_t) :: zone                     !< SCHEME ZONE: the iteration on the nonlinear elements' equations
    integer :: retried = 0, max_sub = 1      !< steps retried as sub-steps, the most sub-steps of one
    integer :: impact_retried = 0            !< of which because of their impact correction (impact_short)
    logical :: step_short = .false.          !< the step at hand was (impact_short)
    logical :: step_located = .false.        !< the step at hand was split at an impact's onset
    type(event_locator_t) :: events          !< SCHEME EVENTS LOCATE (event_location)
    type(energy_t) :: en
    ! Unilateral contact (method.md section 3).
    logical :: has_contact = .false.
    type(contact_set_t) :: cs
    type(following_t) :: follow              !< the conditions paired in the configuration of each step
    integer, allocatable :: body(:)          !< mesh-connected component of each equation (PERSIST)
    ! Rigid modes on the free equations (translations x, y and the rotation about the origin in
    ! the reference configuration) and M times them: the momenta of history.csv, PERSIST.
    real(dp), allocatable :: rig(:, :), mrig(:, :)
    real(dp), allocatable :: crig(:, :), cmrig(:, :)  !< the same, rotation about the origin of the step's end (following contacts)
    real(dp), allocatable :: lam(:)          !< step multipliers of the last iterate
    logical, allocatable :: act0(:)          !< the LCP's warm start at the start of a step (retries)
    real(dp), allocatable :: vtry(:), mvtry(:)   !< v(n+1), M v(n+1) before the commit (impact_short)
    integer, allocatable :: imp_row(:), imp_slot(:)   !< IMPOSE rows summed by reaction probes
    real(dp), allocatable :: imp_w(:)                 !< and their weights (MZ ABOUT: the arm)
    type(static_report_t) :: pre             !< STATIC: the preload
  end type run_state_t

contains

  !> The whole state at the end of step `step` in OUTDIR/checkpoint.h5, atomically: each
  !> owner writes its own fields.
  subroutine save_checkpoint(scn, outdir, sys, rs, step, t, iters, stat, errmsg)
    type(scene_t), intent(in) :: scn
    character(len=*), intent(in) :: outdir
    type(system_t), intent(inout) :: sys
    type(run_state_t), intent(in) :: rs
    integer, intent(in) :: step, iters
    real(dp), intent(in) :: t
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(ckpt_file_t) :: ck
    call ck%create(outdir // '/checkpoint.h5', stat, errmsg)
    if (stat /= STAT_OK) return
    call ck%put('scene', scn%fingerprint, stat, errmsg)
    call ck%put('step', step, stat, errmsg)
    call ck%put('time', t, stat, errmsg)
    call ck%put('iterations', iters, stat, errmsg)
    call ck%put('time_shift', rs%t_shift, stat, errmsg)
    call ck%put('located_onset', merge(1, 0, rs%step_located .and. rs%after_onset), stat, errmsg)
    if (rs%has_contact) call rs%events%save(ck, stat, errmsg)
    call rs%ctl%save(ck, rs%h, stat, errmsg)
    call ck%put('neq', sys%dofs%neq, stat, errmsg)
    call rs%st%save(ck, stat, errmsg)
    call rs%mat%save(ck, stat, errmsg)
    ! ITERATION TANGENT and AUTO start a step from the tangent of the last iterate: kept, so that
    ! a restart iterates with the same matrix (bit for bit).
    if (allocated(sys%ops%tval)) call ck%put('tangent', sys%ops%tval, stat, errmsg)
    if (allocated(sys%ops%gval)) call ck%put('tangent_geometric', sys%ops%gval, stat, errmsg)
    if (allocated(sys%ops%aval)) call ck%put('tangent_antisymmetric', sys%ops%aval, stat, errmsg)
    call refresh_points(scn, sys, rs%st%u, .false.)
    call save_points(sys, ck, stat, errmsg)
    call rs%en%save(ck, stat, errmsg)
    if (rs%has_contact) call rs%cs%save(ck, stat, errmsg)
    call ck%commit(stat, errmsg)
  end subroutine save_checkpoint

  !> The state saved by save_checkpoint, checked against this scene's sizes.
  subroutine load_checkpoint(scn, path, sys, rs, step, iters, stat, errmsg)
    type(scene_t), intent(in) :: scn
    character(len=*), intent(in) :: path
    type(system_t), intent(inout) :: sys
    type(run_state_t), intent(inout) :: rs
    integer, intent(out) :: step, iters
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(ckpt_file_t) :: ck
    integer :: neq, flag, minor
    real(dp) :: tck, hck
    character(len=:), allocatable :: saved, why
    step = 0
    iters = 0
    call ck%open(path, stat, errmsg)
    if (stat /= STAT_OK) return
    ! The state means something only under the scene that wrote it.
    call ck%get('scene', saved, stat, errmsg)
    if (stat == STAT_OK) then
      why = fingerprint_mismatch(saved, scn%fingerprint)
      if (len(why) > 0) call set_error(stat, errmsg, STAT_INPUT, 'checkpoint ' // path // &
        ' belongs to another scene: ' // why // ' (only TIME END and OUTPUT may change for a restart)')
    end if
    call ck%get('step', step, stat, errmsg)
    call ck%get('time', tck, stat, errmsg)
    call ck%get('iterations', iters, stat, errmsg)
    call ck%get('time_shift', rs%t_shift, stat, errmsg)
    call ck%get('located_onset', flag, stat, errmsg)
    rs%step_located = flag == 1
    rs%after_onset = rs%step_located
    call ck%get('neq', neq, stat, errmsg)
    ! The steps left to END from the checkpoint's time (a located onset shifted the grid).
    if (stat == STAT_OK .and. step >= 0) rs%nsteps = step + steps_for(scn%t_end - tck, rs%h, scn%t_end - scn%t_start)
    if (stat == STAT_OK .and. (neq /= sys%dofs%neq .or. step < 0 .or. tck >= scn%t_end + rs%h)) then
      call set_error(stat, errmsg, STAT_INPUT, 'checkpoint ' // path // ': step ' // str(step) // ' of a system of ' // &
        str(neq) // ' equations does not fit this scene (' // str(sys%dofs%neq) // ' equations, ' // str(rs%nsteps) // &
        ' steps)')
    end if
    rs%t_now = tck
    ! ADAPTIVE: the step the run had reached, S factorized at it before a saved tangent is put back.
    call rs%ctl%load(ck, hck, stat, errmsg)
    if (stat == STAT_OK .and. rs%ctl%on .and. hck /= rs%h) then
      rs%h = hck
      call select_level(rs, scn, sys, hck, stat, errmsg, minor)
    end if
    call rs%st%load(ck, stat, errmsg)
    call rs%mat%load(sys, ck, stat, errmsg)
    if (allocated(sys%ops%tval)) call ck%get('tangent', sys%ops%tval, stat, errmsg)
    if (allocated(sys%ops%gval)) call ck%get('tangent_geometric', sys%ops%gval, stat, errmsg)
    if (allocated(sys%ops%aval)) call ck%get('tangent_antisymmetric', sys%ops%aval, stat, errmsg)
    call load_points(sys, ck, stat, errmsg)
    call rs%en%load(ck, stat, errmsg)
    if (rs%has_contact) call rs%cs%load(ck, stat, errmsg)
    if (rs%has_contact) call rs%events%load(ck, rs%cs%n_conditions(), stat, errmsg)
    call ck%close()
  end subroutine load_checkpoint

  !> The steps of length h that cover span (≥ 0): span/h rounded to the nearest integer when
  !> within 1e-9 of the run's span (whole), else rounded up.
  pure integer function steps_for(span, h, whole) result(n)
    real(dp), intent(in) :: span, h, whole
    n = nint(span / h)
    if (abs(n * h - span) > 1.0e-9_dp * whole) n = ceiling(span / h)
    n = max(n, 0)
  end function steps_for

  !> The levels of S: STEP 2^k for MIN ≤ STEP 2^k ≤ MAX under TIME … ADAPTIVE, STEP alone
  !> otherwise; mat at STEP's (not factorized yet: select_level).
  subroutine init_levels(rs, scn)
    type(run_state_t), intent(inout) :: rs
    type(scene_t), intent(in) :: scn
    integer :: k_hi, k
    rs%k_lo = 0
    k_hi = 0
    if (scn%adaptive) then
      rs%k_lo = -floor(log(scn%dt / scn%adapt_hmin) / log(2.0_dp) + 1.0e-9_dp)
      k_hi = floor(log(scn%adapt_hmax / scn%dt) / log(2.0_dp) + 1.0e-9_dp)
    end if
    allocate (rs%levels(k_hi - rs%k_lo + 1))
    rs%mat => rs%levels(1 - rs%k_lo)
    ! SCHEME SOLVER: each S factorized by CHOLMOD or MUMPS (its instance started at its first use).
    do k = 1, size(rs%levels)
      call rs%levels(k)%factor%choose(scn%linear_solver, scn%out_of_core)
    end do
    call rs%mat_sub%factor%choose(scn%linear_solver, scn%out_of_core)
  end subroutine init_levels

  !> mat becomes S at h = STEP 2^k, factorized now if this level has not been yet or was left on a
  !> tangent (the others keep their factors).
  subroutine select_level(rs, scn, sys, h, stat, errmsg, minor)
    type(run_state_t), intent(inout) :: rs
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: h
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, intent(out) :: minor
    integer :: k
    stat = STAT_OK
    minor = 0
    k = nint(log(h / scn%dt) / log(2.0_dp))
    k = min(max(k - rs%k_lo + 1, 1), size(rs%levels))
    rs%mat => rs%levels(k)
    ! (A level left on an ITERATION AUTO tangent starts again from K0 + 4M/h², as after a restart.)
    if (rs%mat%n_factor == 0 .or. rs%mat%on_tangent_now()) call rs%mat%setup(sys, h, stat, errmsg, minor, scn%iter_auto)
  end subroutine select_level

  !> The factors of S freed (gfortran does not finalize locals: a sweep runs many cases).
  subroutine release_matrices(rs)
    type(run_state_t), intent(inout) :: rs
    integer :: k
    if (associated(rs%levels)) then
      do k = 1, size(rs%levels)
        call rs%levels(k)%destroy()
      end do
      deallocate (rs%levels)
    end if
    nullify (rs%mat)
    call rs%mat_sub%destroy()
  end subroutine release_matrices
end module run_state
