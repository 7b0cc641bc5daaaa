!> The state of the contact conditions between two steps, and its checkpoint: what a restart
!> needs to continue bit for bit (method.md section 3: one multiplier per step, the reactions
!> R(n) reported only, the active set of the last step and the warm start of the next LCP).
module contact_state
  use kinds, only: dp
  use checkpoint, only: ckpt_file_t
  implicit none
  private
  public :: contact_state_t

  type :: contact_state_t
    logical, allocatable :: active(:)        !< active at the end of the last step
    logical, allocatable :: active_iter(:)   !< active set of the last LCP (warm start of the next)
    real(dp), allocatable :: lambda(:)       !< step multiplier Λ of the last LCP
    real(dp), allocatable :: r_prev(:)       !< physical reaction R(n) at the end of the last step
    real(dp), allocatable :: gap_n(:)        !< g(n) = g0 + C u_n of the last solve
    real(dp), allocatable :: gap(:)          !< g(n+1) of the last LCP
    real(dp), allocatable :: held(:)         !< IMPACT SYMMETRIC: energy held by the closed condition
  contains
    procedure :: init => state_init
    procedure :: save => state_save
    procedure :: load => state_load
  end type contact_state_t

contains

  !> nc conditions at their initial gaps g0: nothing active, no reaction.
  pure subroutine state_init(self, g0)
    class(contact_state_t), intent(inout) :: self
    real(dp), intent(in) :: g0(:)
    integer :: nc
    nc = size(g0)
    if (allocated(self%active)) deallocate (self%active, self%active_iter, self%lambda, self%r_prev, self%gap_n, &
      self%gap, self%held)
    allocate (self%active(nc), self%active_iter(nc), self%lambda(nc), self%r_prev(nc), self%gap_n(nc), self%gap(nc), &
      self%held(nc))
    self%held = 0.0_dp
    self%active = .false.
    self%active_iter = .false.
    self%lambda = 0.0_dp
    self%r_prev = 0.0_dp
    self%gap_n = g0
    self%gap = g0
  end subroutine state_init

  !> The fields of a restart into an open checkpoint (names prefixed contact_). stat and errmsg
  !> are sticky, as in ckpt_file_t: a failure earlier in the checkpoint skips the writes.
  subroutine state_save(self, ck, stat, errmsg)
    class(contact_state_t), intent(in) :: self
    type(ckpt_file_t), intent(inout) :: ck
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call ck%put('contact_active', merge(1, 0, self%active), stat, errmsg)
    call ck%put('contact_active_iter', merge(1, 0, self%active_iter), stat, errmsg)
    call ck%put('contact_lambda', self%lambda, stat, errmsg)
    call ck%put('contact_r_prev', self%r_prev, stat, errmsg)
    call ck%put('contact_held', self%held, stat, errmsg)
  end subroutine state_save

  !> The fields saved by state_save, their sizes checked against this set (sticky stat).
  subroutine state_load(self, ck, stat, errmsg)
    class(contact_state_t), intent(inout) :: self
    type(ckpt_file_t), intent(inout) :: ck
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer, allocatable :: flags(:)
    allocate (flags(size(self%active)))
    call ck%get('contact_active', flags, stat, errmsg)
    self%active = flags == 1
    call ck%get('contact_active_iter', flags, stat, errmsg)
    self%active_iter = flags == 1
    call ck%get('contact_lambda', self%lambda, stat, errmsg)
    call ck%get('contact_r_prev', self%r_prev, stat, errmsg)
    call ck%get('contact_held', self%held, stat, errmsg)
  end subroutine state_load
end module contact_state
