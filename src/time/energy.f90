!> The energy accounts behind history.csv. Cumulative works are summed with Neumaier's
!> compensated summation so that round-off of the running sums stays out of the balance.
module energy
  use kinds, only: dp
  use errors, only: STAT_OK
  use checkpoint, only: ckpt_file_t
  implicit none
  private
  public :: energy_t

  type :: sum_t
    real(dp) :: s = 0.0_dp, c = 0.0_dp
  end type sum_t

  type :: energy_t
    real(dp) :: kinetic = 0.0_dp       !< ½ v'Mv
    type(sum_t) :: internal_sum        !< work of the nonlinear internal forces since t = 0 (from zero strain)
    real(dp) :: elastic = 0.0_dp       !< strain energy of the linear elastic models, a function of the state
    type(sum_t) :: external_sum        !< work of the external forces as the scheme sees it, ½ du'(F(n)+F(n+1))
    type(sum_t) :: correction_sum      !< energy restored by corrections
    type(sum_t) :: dissipated_sum      !< plastic work since t = 0
    type(sum_t) :: impact_sum          !< kinetic energy removed by impacts (RESTITUTION e < 1)
    type(sum_t) :: damping_sum         !< energy removed by Rayleigh damping (MODEL DAMPING)
    type(sum_t) :: held_sum            !< energy a contact holds and gives back at its release (IMPACT SYMMETRIC)
    type(sum_t) :: friction_sum        !< energy the contacts' friction dissipated (FRICTION)
    real(dp) :: initial = 0.0_dp       !< kinetic + internal at t = 0
    real(dp) :: max_balance = 0.0_dp   !< max |balance| so far
    real(dp) :: max_scale = 0.0_dp     !< max (kinetic + internal) so far
  contains
    procedure :: start
    procedure :: add_step
    procedure :: internal
    procedure :: external
    procedure :: correction
    procedure :: dissipated
    procedure :: balance
    procedure :: impact_dissipated
    procedure :: add_impact
    procedure :: damping
    procedure :: add_damping
    procedure :: contact_held
    procedure :: add_held
    procedure :: friction
    procedure :: add_friction
    procedure :: relative_balance
    procedure :: pack_state
    procedure :: unpack_state
    procedure :: save
    procedure :: load
  end type energy_t

  integer, parameter, public :: ENERGY_STATE_SIZE = 21

contains

  pure subroutine add(acc, x)
    type(sum_t), intent(inout) :: acc
    real(dp), intent(in) :: x
    real(dp) :: t
    t = acc%s + x
    if (abs(acc%s) >= abs(x)) then
      acc%c = acc%c + ((acc%s - t) + x)
    else
      acc%c = acc%c + ((x - t) + acc%s)
    end if
    acc%s = t
  end subroutine add

  pure real(dp) function value(acc)
    type(sum_t), intent(in) :: acc
    value = acc%s + acc%c
  end function value

  !> Initial state: kinetic energy and initial internal energy (strain energy of u0).
  !> For linear elastic models the cumulative work of the internal forces equals the strain
  !> energy of the current state; that state function is used for them (pass elastic0 and
  !> elastic), so that rounding does not accumulate step after step.
  pure subroutine start(self, kinetic0, internal0, elastic0, dissipated0)
    class(energy_t), intent(inout) :: self
    real(dp), intent(in) :: kinetic0, internal0
    real(dp), intent(in), optional :: elastic0
    real(dp), intent(in), optional :: dissipated0   !< of internal0, dissipated (a STATIC preload's plastic work)
    self%kinetic = kinetic0
    self%elastic = 0.0_dp
    if (present(elastic0)) self%elastic = elastic0
    self%internal_sum = sum_t()
    self%external_sum = sum_t()
    self%correction_sum = sum_t()
    self%dissipated_sum = sum_t()
    self%impact_sum = sum_t()
    self%damping_sum = sum_t()
    self%held_sum = sum_t()
    self%friction_sum = sum_t()
    call add(self%internal_sum, internal0)
    if (present(dissipated0)) call add(self%dissipated_sum, dissipated0)
    self%initial = kinetic0 + self%internal()
    self%max_balance = 0.0_dp
    self%max_scale = abs(self%initial)
  end subroutine start

  !> Account for one step: new kinetic energy and the works of the step.
  pure subroutine add_step(self, kinetic, dw_internal, dw_external, dw_correction, dw_dissipated, elastic, sampled)
    class(energy_t), intent(inout) :: self
    real(dp), intent(in) :: kinetic, dw_internal, dw_external, dw_correction
    real(dp), intent(in), optional :: dw_dissipated, elastic
    !> .false.: the elastic energy is not the one the balance is judged on (Bσ = K0 u between
    !> history lines: stiffness_product), so the step does not enter max |balance| (default .true.)
    logical, intent(in), optional :: sampled
    self%kinetic = kinetic
    if (present(elastic)) self%elastic = elastic
    call add(self%internal_sum, dw_internal)
    call add(self%external_sum, dw_external)
    call add(self%correction_sum, dw_correction)
    if (present(dw_dissipated)) call add(self%dissipated_sum, dw_dissipated)
    if (present(sampled)) then
      if (.not. sampled .and. abs(self%balance()) <= huge(1.0_dp)) return
    end if
    ! A non-finite balance must not vanish in max(): it is reported as huge.
    if (abs(self%balance()) <= huge(1.0_dp)) then
      self%max_balance = max(self%max_balance, abs(self%balance()))
    else
      self%max_balance = huge(1.0_dp)
    end if
    self%max_scale = max(self%max_scale, abs(self%kinetic + self%internal()))
  end subroutine add_step

  pure real(dp) function internal(self)
    class(energy_t), intent(in) :: self
    internal = value(self%internal_sum) + self%elastic
  end function internal

  pure real(dp) function external(self)
    class(energy_t), intent(in) :: self
    external = value(self%external_sum)
  end function external

  pure real(dp) function dissipated(self)
    class(energy_t), intent(in) :: self
    dissipated = value(self%dissipated_sum)
  end function dissipated

  !> Kinetic energy removed by inelastic impacts since t = 0.
  pure real(dp) function impact_dissipated(self)
    class(energy_t), intent(in) :: self
    impact_dissipated = value(self%impact_sum)
  end function impact_dissipated

  !> An inelastic impact removed e (>= 0) of kinetic energy: booked, so that the balance holds
  !> (call before add_step of the same step, which updates the maximum |balance|).
  pure subroutine add_impact(self, e)
    class(energy_t), intent(inout) :: self
    real(dp), intent(in) :: e
    call add(self%impact_sum, e)
  end subroutine add_impact

  !> Energy removed by damping since t = 0.
  pure real(dp) function damping(self)
    class(energy_t), intent(in) :: self
    damping = value(self%damping_sum)
  end function damping

  !> The damping of a step removed e (>= 0): booked like an impact's loss (before add_step).
  pure subroutine add_damping(self, e)
    class(energy_t), intent(inout) :: self
    real(dp), intent(in) :: e
    call add(self%damping_sum, e)
  end subroutine add_damping

  !> Energy the contacts hold now (IMPACT SYMMETRIC: taken at an establishment, given back at
  !> the release): it rises and falls, and is 0 when no contact holds any.
  pure real(dp) function contact_held(self)
    class(energy_t), intent(in) :: self
    contact_held = value(self%held_sum)
  end function contact_held

  !> A contact took (e > 0) or gave back (e < 0) held energy: booked so that the balance holds.
  pure subroutine add_held(self, e)
    class(energy_t), intent(inout) :: self
    real(dp), intent(in) :: e
    call add(self%held_sum, e)
  end subroutine add_held

  !> Energy the friction of the contacts dissipated since t = 0.
  pure real(dp) function friction(self)
    class(energy_t), intent(in) :: self
    friction = value(self%friction_sum)
  end function friction

  !> The friction of a step dissipated e (>= 0): booked like an impact's loss (before add_step).
  pure subroutine add_friction(self, e)
    class(energy_t), intent(inout) :: self
    real(dp), intent(in) :: e
    call add(self%friction_sum, e)
  end subroutine add_friction

  pure real(dp) function correction(self)
    class(energy_t), intent(in) :: self
    correction = value(self%correction_sum)
  end function correction

  !> Energy the scheme created: kinetic + internal + impact dissipation - external - (kinetic +
  !> internal at t = 0). Corrections are not subtracted: they give back what the scheme lost,
  !> and the balance is what remains wrong after them. The energy an inelastic impact removes
  !> (RESTITUTION e < 1), the work of the damping (MODEL DAMPING), the energy a contact holds
  !> until its release (IMPACT SYMMETRIC) and the friction's dissipation (FRICTION) are physics,
  !> not errors: they are counted with the internal work.
  pure real(dp) function balance(self)
    class(energy_t), intent(in) :: self
    real(dp) :: lost
    lost = value(self%impact_sum) + value(self%damping_sum) + value(self%held_sum) + value(self%friction_sum)
    if (lost == 0.0_dp) then
      balance = ((self%kinetic + self%internal()) - value(self%external_sum)) - self%initial
    else
      balance = ((self%kinetic + self%internal() + lost) - value(self%external_sum)) - self%initial
    end if
  end function balance

  !> Every accumulator, compensation terms included, for a checkpoint (bit-exact restart).
  pure function pack_state(self) result(x)
    class(energy_t), intent(in) :: self
    real(dp) :: x(ENERGY_STATE_SIZE)
    x = [self%kinetic, self%internal_sum%s, self%internal_sum%c, self%elastic, self%external_sum%s, &
      self%external_sum%c, self%correction_sum%s, self%correction_sum%c, self%dissipated_sum%s, &
      self%dissipated_sum%c, self%initial, self%max_balance, self%max_scale, self%impact_sum%s, self%impact_sum%c, &
      self%damping_sum%s, self%damping_sum%c, self%held_sum%s, self%held_sum%c, self%friction_sum%s, &
      self%friction_sum%c]
  end function pack_state

  pure subroutine unpack_state(self, x)
    class(energy_t), intent(inout) :: self
    real(dp), intent(in) :: x(ENERGY_STATE_SIZE)
    self%kinetic = x(1)
    self%internal_sum = sum_t(x(2), x(3))
    self%elastic = x(4)
    self%external_sum = sum_t(x(5), x(6))
    self%correction_sum = sum_t(x(7), x(8))
    self%dissipated_sum = sum_t(x(9), x(10))
    self%initial = x(11)
    self%max_balance = x(12)
    self%max_scale = x(13)
    self%impact_sum = sum_t(x(14), x(15))
    self%damping_sum = sum_t(x(16), x(17))
    self%held_sum = sum_t(x(18), x(19))
    self%friction_sum = sum_t(x(20), x(21))
  end subroutine unpack_state

  !> The accounts into an open checkpoint (sticky stat, as ckpt_file_t).
  subroutine save(self, ck, stat, errmsg)
    class(energy_t), intent(in) :: self
    type(ckpt_file_t), intent(inout) :: ck
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call ck%put('energy', self%pack_state(), stat, errmsg)
  end subroutine save

  subroutine load(self, ck, stat, errmsg)
    class(energy_t), intent(inout) :: self
    type(ckpt_file_t), intent(inout) :: ck
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    real(dp) :: x(ENERGY_STATE_SIZE)
    call ck%get('energy', x, stat, errmsg)
    if (stat == STAT_OK) call self%unpack_state(x)
  end subroutine load

  !> max |balance| relative to the largest kinetic + internal seen.
  pure real(dp) function relative_balance(self)
    class(energy_t), intent(in) :: self
    relative_balance = 0.0_dp
    if (self%max_scale > 0.0_dp) relative_balance = self%max_balance / self%max_scale
  end function relative_balance
end module energy
