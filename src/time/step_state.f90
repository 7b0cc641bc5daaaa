!> The state the time loop advances (u, v and what the next step reuses: Bσ(n), F(n), M v(n))
!> and the iterate of a step, with the optional extended-precision shadow of SCHEME PRECISION
!> EXTENDED: when it is on, u, v, Bσ(n), M v(n), the right-hand side and the residual are also
!> carried unrounded (docs/precision.md) and every double value is the rounding of its shadow.
!> The step is written once; each operation below picks its precision.
module step_state
  use kinds, only: dp, qp
  use scene, only: scene_t
  use assembly, only: system_t, commit_state, mass_times, mass_times_q, damping_times, is_damped, external_force
  use internal_forces, only: internal_force, work_increment_t
  use checkpoint, only: ckpt_file_t
  use newmark_scheme, only: rhs_eq9, residual_eq9, velocity_eq3, massless_rows_eq9, momentum_eq2
  implicit none
  private
  public :: step_state_t

  type :: step_state_t
    logical :: extended = .false.
    !> M v(n+1) by the momentum balance of the step instead of the product (momentum_form)
    logical :: momentum_form = .false.
    real(dp) :: h = 0.0_dp, c4 = 0.0_dp      !< step, 4/h²
    real(qp) :: a = 0.0_qp                   !< 2/h unrounded (extended)
    ! Start of the step (state): u(n), v(n), Bσ(n), F(n), M v(n).
    real(dp), allocatable :: u(:), v(:), fint_n(:), f_n(:), mv(:)
    ! The step: F(n+1), right-hand side of (9), iterate du and its update ddu, residual r, trial
    ! u(n) + du with its Bσ(n+1) and Bσc, M du; v(n+1) by (3) before the impact correction (extended).
    real(dp), allocatable :: f_np1(:), rhs(:), du(:), ddu(:), r(:), utrial(:), fint(:), fcorr(:), mdu(:), v_eq3(:)
    real(dp), allocatable :: cdu(:)          !< C du (MODEL DAMPING)
    real(dp), allocatable :: du_prev(:)      !< the last iterate's du (a relaxed iterate: iterate_eq9)
    real(dp), allocatable :: aw(:), ay(:)    !< work of the antisymmetric sweep (iterate_eq9's anti_sweep)
    real(dp), allocatable :: res_hist(:)     !< residual norm of each iteration of the step
    ! Follower pressures (KINEMATICS LARGE): F(n+1) = the dead part f_fix + the sides' forces at the
    ! trial configuration, at t(n+1); f_new the scratch of its update.
    real(dp) :: t_np1 = 0.0_dp
    real(dp), allocatable :: f_fix(:), f_new(:)
    real(dp) :: kinetic = 0.0_dp             !< ½ v'Mv at the end of the last step
    !> The run's share per step of TOLERANCE x its energy scale (max kinetic + internal so far over
    !> the steps of the run): the residual work a step left at the attainable residual may keep.
    real(dp) :: energy_share = 0.0_dp
    integer, allocatable :: massless(:)      !< IMPACT MASSLESS: the massless contact equations
    type(work_increment_t) :: inc            !< energies of the last trial (work, elastic, dissipated)
    ! Extended-precision shadow.
    real(qp), allocatable :: u_q(:), v_q(:), fint_n_q(:), mv_q(:), rhs_q(:), r_q(:), utrial_q(:), mdu_q(:)
  contains
    procedure :: init => state_init
    procedure :: set_initial => state_set_initial
    procedure :: set_load => state_set_load
    procedure :: begin_step => state_begin_step
    procedure :: set_step => state_set_step
    procedure :: trial => state_trial
    procedure :: refresh_geometry => state_refresh_geometry
    procedure :: residual => state_residual
    procedure :: velocity => state_velocity
    procedure :: absorb_velocity_change => state_absorb
    procedure :: commit => state_commit
    procedure :: damping_work => state_damping_work
    procedure :: massless_work => state_massless_work
    procedure :: save => state_save
    procedure :: load => state_load
  end type step_state_t

contains

  !> Room for n equations and max_iter iterations; step h.
  subroutine state_init(self, n, max_iter, h, extended)
    class(step_state_t), intent(inout) :: self
    integer, intent(in) :: n, max_iter
    real(dp), intent(in) :: h
    logical, intent(in) :: extended
    self%h = h
    self%c4 = 4.0_dp / h**2
    self%a = 2.0_qp / real(h, qp)
    self%extended = extended
    allocate (self%u(n), self%v(n), self%fint_n(n), self%f_n(n), self%mv(n), self%f_np1(n), self%rhs(n), &
      self%du(n), self%ddu(n), self%r(n), self%utrial(n), self%fint(n), self%fcorr(n), self%mdu(n), self%v_eq3(n), &
      self%cdu(n), self%du_prev(n), self%aw(n), self%ay(n), self%res_hist(max_iter))
    if (extended) allocate (self%rhs_q(n), self%mv_q(n), self%mdu_q(n), self%r_q(n), self%utrial_q(n))
  end subroutine state_init

  !> The initial state: u0, v0 (set by the caller in u and v), Bσ(u0) along the path from zero
  !> strain (committed as the points' state), M v0 and the kinetic energy; F(t_start) is the
  !> caller's.
  subroutine state_set_initial(self, scn, sys, preloaded)
    class(step_state_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    logical, intent(in) :: preloaded   !< STATIC: the laws are at u (committed), their path ends there
    if (preloaded) then
      call internal_force(scn, sys, self%u, self%fint_n, self%fcorr, .false., allocated(sys%ops%tval), self%inc, &
        un=self%u)
    else
      call internal_force(scn, sys, self%u, self%fint_n, self%fcorr, .false., allocated(sys%ops%tval), self%inc)
    end if
    call commit_state(sys)
    call mass_times(sys, self%v, self%mv)
    self%kinetic = 0.5_dp * dot_product(self%v, self%mv)
    if (self%extended) then
      ! The state itself is kept unrounded: rounding u and v to double at every step drifts
      ! the energy by a fraction of eps per step (docs/precision.md).
      self%u_q = real(self%u, qp)
      self%v_q = real(self%v, qp)
      if (preloaded) then
        call internal_force(scn, sys, self%u, self%fint_n, self%fcorr, .false., allocated(sys%ops%tval), self%inc, &
          uq=self%u_q, un=self%u)
      else
        call internal_force(scn, sys, self%u, self%fint_n, self%fcorr, .false., allocated(sys%ops%tval), self%inc, &
          uq=self%u_q)
      end if
      self%fint_n_q = sys%fint_q
      call mass_times_q(sys, self%v_q, self%mv_q)
      self%kinetic = real(0.5_qp * sum(self%v_q * self%mv_q), dp)
    end if
  end subroutine state_set_initial

  !> The step size of the steps that follow (SCHEME RETRY's sub-steps, and back).
  pure subroutine state_set_step(self, h)
    class(step_state_t), intent(inout) :: self
    real(dp), intent(in) :: h
    self%h = h
    self%c4 = 4.0_dp / h**2
    self%a = 2.0_qp / real(h, qp)
  end subroutine state_set_step

  !> F(n+1) at t1: the loads on the start configuration (the first iterate's, du = 0); with
  !> follower pressures, their dead part too (follower_update moves them with the iterate).
  subroutine state_set_load(self, scn, sys, t1)
    class(step_state_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: t1
    self%t_np1 = t1
    if (sys%loads%fol%n == 0) then
      call external_force(scn, sys, t1, self%f_np1, self%u)
      return
    end if
    if (.not. allocated(self%f_fix)) allocate (self%f_fix(size(self%u)), self%f_new(size(self%u)))   ! once a run
    call external_force(scn, sys, t1, self%f_fix)
    self%f_np1 = self%f_fix
    call sys%loads%fol%add_force(scn, t1, self%u, self%f_np1)
  end subroutine state_set_load

  !> The follower pressures at the trial configuration: F(n+1) and the right-hand side of (9)
  !> take the change; with tangent, the load stiffness -sym(∂F/∂u) joins the tangent.
  subroutine follower_update(self, scn, sys, tangent)
    class(step_state_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    logical, intent(in) :: tangent
    integer :: i
    self%f_new = self%f_fix
    call sys%loads%fol%add_force(scn, self%t_np1, self%utrial, self%f_new)
    do i = 1, size(self%f_new)
      self%rhs(i) = self%rhs(i) + (self%f_new(i) - self%f_np1(i))
      if (self%extended) self%rhs_q(i) = self%rhs_q(i) + (real(self%f_new(i), qp) - real(self%f_np1(i), qp))
      self%f_np1(i) = self%f_new(i)
    end do
    if (tangent) call sys%loads%fol%add_tangent(scn, self%t_np1, sys%ops%pat, sys%ops%tval)
  end subroutine follower_update

  !> Start a step (F(n+1) in f_np1): the right-hand side of (9) and the residual of the first
  !> iterate du = 0, where Bσ(n+1) = Bσ(n) and Bσc = 0.
  subroutine state_begin_step(self)
    class(step_state_t), intent(inout) :: self
    call rhs_eq9(self%h, self%f_np1, self%f_n, self%fint_n, self%mv, self%rhs)
    if (allocated(self%massless)) call massless_rows_eq9(self%massless, self%f_np1, self%rhs)
    self%du = 0.0_dp
    self%r = self%rhs - self%fint_n
    if (self%extended) then
      call rhs_eq9(self%a, self%f_np1, self%f_n, self%fint_n_q, self%mv_q, self%rhs_q)
      if (allocated(self%massless)) call massless_rows_eq9(self%massless, self%f_np1, self%rhs_q)
      self%r = real(self%rhs_q - self%fint_n_q, dp)
    end if
  end subroutine state_begin_step

  !> The trial state u(n) + du: strains, stresses along the step's path, Bσ(n+1) and, with
  !> correct, the correction force Bσc of eq (9).
  subroutine state_trial(self, scn, sys, correct, tangent)
    class(step_state_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    logical, intent(in) :: correct
    logical, intent(in), optional :: tangent   !< assemble the tangent (default: when it exists)
    logical :: kt
    kt = allocated(sys%ops%tval)
    if (present(tangent)) kt = kt .and. tangent
    if (self%extended) then
      self%utrial_q = self%u_q + real(self%du, qp)
      self%utrial = real(self%utrial_q, dp)
      call internal_force(scn, sys, self%utrial, self%fint, self%fcorr, correct, kt, self%inc, &
        uq=self%utrial_q, un=self%u)
    else
      self%utrial = self%u + self%du
      call internal_force(scn, sys, self%utrial, self%fint, self%fcorr, correct, kt, self%inc, un=self%u)
    end if
    if (sys%loads%fol%n > 0) call follower_update(self, scn, sys, kt)
  end subroutine state_trial

  !> KINEMATICS LARGE after a restart: the elements' current axes (kept in the element table for
  !> the support reactions) from the loaded u, through a trial of no increment; with tangent, the
  !> tangent there too (before the SCHEME RETRY sub-steps of a step whose tangent did not
  !> factorize: its last tangent, of an iterate that may have inverted an element, is no start).
  subroutine state_refresh_geometry(self, scn, sys, tangent)
    class(step_state_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    logical, intent(in), optional :: tangent
    logical :: kt
    kt = .false.
    if (present(tangent)) kt = tangent .and. allocated(sys%ops%tval)
    call internal_force(scn, sys, self%u, self%fint, self%fcorr, .false., kt, self%inc, un=self%u)
  end subroutine state_refresh_geometry

  !> r = the residual of eq (9) at the trial state (without the contact forces).
  subroutine state_residual(self, sys)
    class(step_state_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    if (self%extended) then
      call mass_times_q(sys, real(self%du, qp), self%mdu_q)
      call residual_eq9(self%a, self%rhs_q, self%mdu_q, sys%fint_q, self%fcorr, self%r_q)
      self%r = real(self%r_q, dp)
    else
      call mass_times(sys, self%du, self%mdu)
      if (is_damped(sys)) then
        ! 4M du/h² + 2C du/h = (4/h²)(M du + (h/2) C du): damping enters as part of the inertia.
        call damping_times(sys, self%du, self%cdu)
        self%mdu = self%mdu + (0.5_dp * self%h) * self%cdu
      end if
      call residual_eq9(self%c4, self%rhs, self%mdu, self%fint, self%fcorr, self%r)
    end if
  end subroutine state_residual

  !> The energy the damping removed in the step: the trapezoid work ½du'C(v(n) + v(n+1)) =
  !> du'C du / h, exactly what eq (9) takes out of ½v'Mv (0 without MODEL DAMPING).
  real(dp) function state_damping_work(self, sys) result(w)
    class(step_state_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    w = 0.0_dp
    if (.not. is_damped(sys)) return
    call damping_times(sys, self%du, self%cdu)
    w = dot_product(self%du, self%cdu) / self%h
  end function state_damping_work

  !> IMPACT MASSLESS, before the commit: ½ du'(Bσ(n) - F(n)) over the massless rows, the work the
  !> step counts beyond the trapezoid rule by writing them as equilibrium at n+1 (their
  !> imbalance at n: the start reactions, or a node out of equilibrium snapping to it).
  pure real(dp) function state_massless_work(self) result(w)
    class(step_state_t), intent(in) :: self
    integer :: k, i
    w = 0.0_dp
    if (.not. allocated(self%massless)) return
    do k = 1, size(self%massless)
      i = self%massless(k)
      w = w + self%du(i) * (self%fint_n(i) - self%f_n(i))
    end do
    w = 0.5_dp * w
  end function state_massless_work

  !> End of the step: v(n+1) by eq (3), M v(n+1); v_eq3 keeps it for the extended shadow (absorb).
  !> With momentum_form, M v(n+1) is the step's momentum balance (momentum_eq2) instead of the
  !> product by M.
  subroutine state_velocity(self, sys)
    class(step_state_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    call velocity_eq3(self%h, self%du, self%v)
    if (self%extended) then
      call velocity_eq3(self%a, self%du, self%v_q)
      self%v = real(self%v_q, dp)
    end if
    if (self%momentum_form) then
      call momentum_eq2(self%h, self%f_n, self%f_np1, self%fint_n, self%fint, self%mv)
    else
      call mass_times(sys, self%v, self%mv)
    end if
    if (self%extended) self%v_eq3 = self%v
  end subroutine state_velocity

  !> After the impact correction changed v (and M v): carry the change into the shadow.
  subroutine state_absorb(self)
    class(step_state_t), intent(inout) :: self
    if (self%extended) self%v_q = self%v_q + real(self%v - self%v_eq3, qp)
  end subroutine state_absorb

  !> The trial state becomes the state: u(n+1), Bσ(n+1), F(n+1), M v(n+1), kinetic energy.
  subroutine state_commit(self, sys)
    class(step_state_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    integer :: k, i, n
    ! A LARGE beam's rotation turns by the Cayley angle of its Newmark increment, as its chord
    ! does under the trapezoidal rule (cayley_rotations; docs/large-displacements.md).
    n = 0
    if (allocated(sys%dofs%cayley_eq)) n = size(sys%dofs%cayley_eq)
    do k = 1, n
      i = sys%dofs%cayley_eq(k)
      if (self%extended) then
        self%utrial_q(i) = self%u_q(i) + 2.0_qp * atan(0.5_qp * real(self%du(i), qp))
        self%utrial(i) = real(self%utrial_q(i), dp)
      else
        self%utrial(i) = self%u(i) + 2.0_dp * atan(0.5_dp * self%du(i))
      end if
    end do
    self%u = self%utrial
    self%fint_n = self%fint
    self%f_n = self%f_np1
    self%kinetic = 0.5_dp * dot_product(self%v, self%mv)
    if (self%extended) then
      self%fint_n_q = sys%fint_q
      self%u_q = self%utrial_q
      self%v = real(self%v_q, dp)
      call mass_times_q(sys, self%v_q, self%mv_q)
      self%mv = real(self%mv_q, dp)
      self%kinetic = real(0.5_qp * sum(self%v_q * self%mv_q), dp)
    end if
  end subroutine state_commit

  !> The state into an open checkpoint (sticky stat, as ckpt_file_t).
  subroutine state_save(self, ck, stat, errmsg)
    class(step_state_t), intent(in) :: self
    type(ckpt_file_t), intent(inout) :: ck
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call ck%put('u', self%u, stat, errmsg)
    call ck%put('v', self%v, stat, errmsg)
    call ck%put('fint_n', self%fint_n, stat, errmsg)
    call ck%put('f_n', self%f_n, stat, errmsg)
    call ck%put('mv', self%mv, stat, errmsg)
    if (self%extended) then
      call ck%put('u_q', self%u_q, stat, errmsg)
      call ck%put('v_q', self%v_q, stat, errmsg)
      call ck%put('fint_n_q', self%fint_n_q, stat, errmsg)
      call ck%put('mv_q', self%mv_q, stat, errmsg)
    end if
  end subroutine state_save

  subroutine state_load(self, ck, stat, errmsg)
    class(step_state_t), intent(inout) :: self
    type(ckpt_file_t), intent(inout) :: ck
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call ck%get('u', self%u, stat, errmsg)
    call ck%get('v', self%v, stat, errmsg)
    call ck%get('fint_n', self%fint_n, stat, errmsg)
    call ck%get('f_n', self%f_n, stat, errmsg)
    call ck%get('mv', self%mv, stat, errmsg)
    if (self%extended) then
      call ck%get('u_q', self%u_q, stat, errmsg)
      call ck%get('v_q', self%v_q, stat, errmsg)
      call ck%get('fint_n_q', self%fint_n_q, stat, errmsg)
      call ck%get('mv_q', self%mv_q, stat, errmsg)
    end if
  end subroutine state_load
end module step_state
