!> Coulomb friction on the step multipliers (docs/contact.md, "Friction").
!>
!> A frictional condition j (gap row c_N) has a tangential row c_T (the tangent t = n turned by
!> +90°) whose "gap" is the slip of the step, s = c_T·Δu: the relative tangential displacement
!> over the step, h times the mid-step velocity the trapezoid rule moves with. On the step
!> multipliers Λ = R(n) + R(n+1) (the ones the energy identity pairs with Δu) Coulomb's law reads
!>   stick   s = 0                     and |Λ_T| <= μ Λ_N,
!>   slip    Λ_T = -μ Λ_N sign(s)      (the force opposes the slip),
!> so that the friction's work over the step, ½ Λ_T s, is never positive: the dissipation
!> -½ Λ_T s >= 0 is booked (history.csv friction_dissipated) and the balance closes with it.
!> The 2D cone is exactly its two facets ±μ Λ_N, met to round-off: no penalty, no regularization.
!>
!> Solution (coulomb_solve): a primal-dual active set over the states of the rows (contact open
!> or closed; stick, slip along +t or -t). For given states the step is linear and its dense
!> system (nonsymmetric: a slipping row's force follows its contact's Λ_N) is solved exactly;
!> states that violate their law change and the pass is repeated. The first version, a fixed
!> point on the thresholds μ Λ_N (Tresca problems), cycled on a block sliding on its base: the
!> friction tips it, and the trailing corner's Λ_N falls by more than the threshold it carries.
!>
!> In 3D a condition has two tangential rows (t1, t2: scene's condition_tangent) and the cone is
!> the circle |Λ_T| <= μ Λ_N, not a pyramid: the submodule coulomb_cone (cone_solve) runs the same
!> active set, a slipping condition's direction being an unknown angle of a Newton iteration.
module coulomb
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str
  use contact_multipliers, only: multiplier_system_t
  use contact_modes, only: SOLVER_AUTO, SOLVER_AUGMENTED
  use lapack_pure, only: dgesv
  use checkpoint, only: ckpt_file_t
  use coulomb_passes, only: FRICTION_FREE, FRICTION_STICK, FRICTION_SLIP_POS, FRICTION_SLIP_NEG, BLOCK_TRIES, fixed_rows, &
    unilateral_violations, limit_changes
  implicit none
  private
  public :: coulomb_t

  integer, parameter :: MAX_PASSES = 200
  real(dp), parameter :: THRESHOLD_RTOL = 1.0e-13_dp

  type :: coulomb_t
    private
    integer :: n = 0                         !< frictional conditions
    integer, allocatable :: trow(:), nrow(:) !< their tangential and normal rows
    integer, allocatable :: trow2(:)         !< 3D: the second tangential row (0 in 2D)
    real(dp), allocatable :: theta(:), sig(:) !< 3D, slipping: the slip's direction in (t1, t2), its length
    real(dp), allocatable :: mu(:)
    integer, allocatable :: state(:)         !< FRICTION_* of the last solve (warm start of the next)
    integer, allocatable :: kof(:)           !< (rows) k of a tangential row, -k of its contact's row, else 0
    ! workspaces: the unknowns' and the columns' rows, the columns kept, the dense system
    integer, allocatable :: rows(:), ipiv(:)
    logical, allocatable :: keep(:)
    real(dp), allocatable :: m(:, :), rhs(:), col(:, :), rho(:)
    logical, allocatable :: on(:)
    ! (3D, coulomb_cone) W's block on the rows, the multipliers on the rows, a row's place in rows
    real(dp), allocatable :: wb(:, :), lr(:), lam_rows(:)
    integer, allocatable :: pos(:)
  contains
    procedure :: add => coulomb_add
    procedure :: count => coulomb_count
    procedure :: init => coulomb_init
    procedure :: solve => coulomb_solve
    procedure :: tangent_mask => coulomb_tangent_mask
    procedure :: tangent_of => coulomb_tangent_of
    procedure :: tangent2_of => coulomb_tangent2_of
    procedure :: mu_of => coulomb_mu_of
    procedure :: sticks => coulomb_sticks
    procedure :: save => coulomb_save
    procedure :: load => coulomb_load
  end type coulomb_t

  interface
    !> 3D: coulomb_solve's problem on the circular cone (coulomb_cone).
    module subroutine cone_solve(self, ms, q, tol, tol_free, bilateral, lam, g, active, wdiag, viol, iterations, stat, &
      errmsg)
      class(coulomb_t), intent(inout) :: self
      type(multiplier_system_t), intent(inout) :: ms
      real(dp), intent(in) :: q(:), tol, tol_free(:)
      logical, intent(in) :: bilateral(:)
      real(dp), intent(inout) :: lam(:)
      real(dp), intent(out) :: g(:)
      logical, intent(inout) :: active(:)
      real(dp), intent(inout) :: wdiag(:)
      logical, intent(inout) :: viol(:)
      integer, intent(out) :: iterations
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine cone_solve
  end interface

contains

  !> Condition nrow gets friction mu > 0 through the tangential row trow (and in 3D trow2)
  !> (set building only).
  pure subroutine coulomb_add(self, trow, nrow, mu, trow2)
    class(coulomb_t), intent(inout) :: self
    integer, intent(in) :: trow, nrow
    real(dp), intent(in) :: mu
    integer, intent(in), optional :: trow2
    integer :: t2
    if (.not. allocated(self%trow)) allocate (self%trow(0), self%nrow(0), self%mu(0), self%trow2(0))
    t2 = 0
    if (present(trow2)) t2 = trow2
    self%trow = [self%trow, trow]
    self%trow2 = [self%trow2, t2]
    self%nrow = [self%nrow, nrow]
    self%mu = [self%mu, mu]
    self%n = size(self%trow)
  end subroutine coulomb_add

  pure integer function coulomb_count(self)
    class(coulomb_t), intent(in) :: self
    coulomb_count = self%n
  end function coulomb_count

  !> Workspaces for nc rows; every tangential row FREE until its contact closes.
  pure subroutine coulomb_init(self, nc)
    class(coulomb_t), intent(inout) :: self
    integer, intent(in) :: nc
    integer :: k
    if (.not. allocated(self%trow)) allocate (self%trow(0), self%nrow(0), self%mu(0), self%trow2(0))
    if (allocated(self%state)) deallocate (self%state, self%kof, self%rows, self%ipiv, self%keep, self%m, &
      self%rhs, self%col, self%rho, self%on, self%theta, self%sig, self%wb, self%lr, self%pos, self%lam_rows)
    allocate (self%state(self%n), self%kof(nc), self%rows(nc), self%ipiv(nc), self%keep(nc), &
      self%m(min(nc, 64), min(nc, 64)), self%rhs(nc), self%col(nc, 1), self%rho(nc), self%on(nc), &
      self%theta(self%n), self%sig(self%n), self%lr(nc), self%pos(nc), self%lam_rows(nc))
    allocate (self%wb(size(self%m, 1), size(self%m, 2)))
    self%state = FRICTION_FREE
    self%theta = 0.0_dp
    self%sig = 0.0_dp
    self%kof = 0
    do k = 1, self%n
      self%kof(self%trow(k)) = k
      if (self%trow2(k) > 0) self%kof(self%trow2(k)) = k
      self%kof(self%nrow(k)) = -k
    end do
  end subroutine coulomb_init

  !> The tangential rows as a mask over the rows (all .false. without friction).
  pure subroutine coulomb_tangent_mask(self, mask)
    class(coulomb_t), intent(in) :: self
    logical, intent(out) :: mask(:)
    mask = .false.
    if (allocated(self%kof)) mask = self%kof > 0
  end subroutine coulomb_tangent_mask

  !> The tangential row of condition j (0: frictionless).
  pure integer function coulomb_tangent_of(self, j) result(t)
    class(coulomb_t), intent(in) :: self
    integer, intent(in) :: j
    t = 0
    if (.not. allocated(self%kof)) return
    if (self%kof(j) < 0) t = self%trow(-self%kof(j))
  end function coulomb_tangent_of

  !> 3D: the second tangential row of condition j (0: frictionless, or 2D).
  pure integer function coulomb_tangent2_of(self, j) result(t)
    class(coulomb_t), intent(in) :: self
    integer, intent(in) :: j
    t = 0
    if (.not. allocated(self%kof)) return
    if (self%kof(j) < 0) t = self%trow2(-self%kof(j))
  end function coulomb_tangent2_of

  !> μ of condition j (0: frictionless).
  pure real(dp) function coulomb_mu_of(self, j) result(mu)
    class(coulomb_t), intent(in) :: self
    integer, intent(in) :: j
    mu = 0.0_dp
    if (.not. allocated(self%kof)) return
    if (self%kof(j) < 0) mu = self%mu(-self%kof(j))
  end function coulomb_mu_of

  !> Whether tangential row t stuck in the last solve.
  pure logical function coulomb_sticks(self, t)
    class(coulomb_t), intent(in) :: self
    integer, intent(in) :: t
    coulomb_sticks = .false.
    if (.not. allocated(self%kof)) return
    if (self%kof(t) > 0) coulomb_sticks = self%state(self%kof(t)) == FRICTION_STICK
  end function coulomb_sticks

  !> The step's multipliers with friction, by a primal-dual active set on the states of every
  !> row: a unilateral row active or not, a tangential row of an active contact sticking or
  !> slipping (±). For given states the step is linear: the active rows' gaps, the sticking
  !> rows' slips and the IMPOSE rows are 0, a slipping row's force is ∓μ Λ_N of its contact,
  !> so that the unknowns Λ_I (I: active, sticking, IMPOSE) solve the dense nonsymmetric system
  !>   Σ_l (W_{I_k I_l} ∓ μ_l W_{I_k t_l}) Λ_{I_l} = -q_{I_k}
  !> (W's columns from the multipliers' Schur cache, LAPACK dgesv; a large zone: the augmented
  !> sparse system, ms%solve_coulomb). Then every state that
  !> violates its law changes at once (a negative normal multiplier releases, a penetrating gap
  !> closes, a stick force out of the cone slips opposite to it, a slip against its force sticks);
  !> after BLOCK_TRIES passes without fewer violations, one change per pass. q: the gaps and slips
  !> without contact forces; tol, tol_free, bilateral (IMPOSE's rows and the tangential ones):
  !> as lcp_pivot; active: the warm start of the unilateral rows and their solution; lam the
  !> solution, g = q + W lam; iterations: the passes.
  subroutine coulomb_solve(self, ms, q, tol, tol_free, bilateral, lam, g, active, wdiag, viol, iterations, stat, errmsg)
    class(coulomb_t), intent(inout) :: self
    type(multiplier_system_t), intent(inout) :: ms
    real(dp), intent(in) :: q(:), tol, tol_free(:)
    logical, intent(in) :: bilateral(:)
    real(dp), intent(inout) :: lam(:)
    real(dp), intent(out) :: g(:)
    logical, intent(inout) :: active(:)
    real(dp), intent(inout) :: wdiag(:)
    logical, intent(inout) :: viol(:)
    integer, intent(out) :: iterations
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: pass, k, j, nv, nbest, tries
    if (self%n > 0) then
      if (self%trow2(1) > 0) then              ! 3D: the circular cone
        call cone_solve(self, ms, q, tol, tol_free, bilateral, lam, g, active, wdiag, viol, iterations, stat, errmsg)
        return
      end if
    end if
    stat = STAT_OK
    iterations = 0
    call open_states(self, active, q, tol)
    nbest = huge(1)
    tries = BLOCK_TRIES
    do pass = 1, MAX_PASSES
      iterations = pass
      call solve_states(self, ms, q, bilateral, active, lam, g, wdiag, stat, errmsg)
      if (stat /= STAT_OK) return
      ! The violations: unilateral rows (the tangential ones are bilateral), then the cone.
      call unilateral_violations(bilateral, active, lam, g, wdiag, tol, tol_free, viol)
      do k = 1, self%n
        j = self%trow(k)
        if (.not. active(self%nrow(k))) cycle
        select case (self%state(k))
        case (FRICTION_STICK)
          viol(j) = abs(lam(j)) > self%mu(k) * max(lam(self%nrow(k)), 0.0_dp) * (1.0_dp + THRESHOLD_RTOL)
        case (FRICTION_SLIP_POS)
          viol(j) = g(j) < -tol
        case (FRICTION_SLIP_NEG)
          viol(j) = g(j) > tol
        end select
      end do
      nv = count(viol)
      if (nv == 0) return
      call limit_changes(viol, nv, nbest, tries)
      where (viol .and. .not. bilateral) active = .not. active
      call open_states(self, active, g, tol)     ! (a contact that closes slips as its slip goes)
      do k = 1, self%n
        j = self%trow(k)
        if (.not. viol(j)) cycle
        if (self%state(k) == FRICTION_STICK) then
          self%state(k) = merge(FRICTION_SLIP_NEG, FRICTION_SLIP_POS, lam(j) > 0.0_dp)
        else
          self%state(k) = FRICTION_STICK
        end if
      end do
    end do
    call set_error(stat, errmsg, STAT_RUN, 'friction: no consistent contact, stick and slip states after ' // &
      str(MAX_PASSES) // ' passes (' // str(nv) // ' conditions still violated)')
  end subroutine coulomb_solve

  !> The tangential rows of the contacts that close (state FREE, their contact active): slipping
  !> the way their slip s goes (s: the slips of the last pass, or without contact forces), stuck
  !> where it is within tol. (Stuck at once, a row that slides carries the force that would stop
  !> it within the step, and its contact opens under that: the states then cycle.)
  pure subroutine open_states(self, active, s, tol)
    class(coulomb_t), intent(inout) :: self
    logical, intent(in) :: active(:)
    real(dp), intent(in) :: s(:), tol
    integer :: k
    do k = 1, self%n
      if (self%state(k) /= FRICTION_FREE .or. .not. active(self%nrow(k))) cycle
      self%state(k) = FRICTION_STICK
      if (s(self%trow(k)) > tol) self%state(k) = FRICTION_SLIP_POS
      if (s(self%trow(k)) < -tol) self%state(k) = FRICTION_SLIP_NEG
    end do
  end subroutine open_states

  !> One pass of coulomb_solve: an open contact's tangent FREE, the system of the states solved,
  !> lam and g = q + W lam.
  subroutine solve_states(self, ms, q, bilateral, active, lam, g, wdiag, stat, errmsg)
    class(coulomb_t), intent(inout) :: self
    type(multiplier_system_t), intent(inout) :: ms
    real(dp), intent(in) :: q(:)
    logical, intent(in) :: bilateral(:)
    logical, intent(in) :: active(:)
    real(dp), intent(out) :: lam(:), g(:)
    real(dp), intent(inout) :: wdiag(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, l, j, ni, nl, info
    logical :: singular
    stat = STAT_OK
    ! The unknowns I (ni) and the columns needed, I and the slipping rows (nl). (An open contact's
    ! tangent is FREE; a closed one's is never FREE here: open_states has set it.)
    call fixed_rows(self%kof, self%nrow, bilateral, active, self%state, self%rows, ni)
    nl = ni
    do k = 1, self%n
      if (.not. slipping(self, k)) cycle
      nl = nl + 1
      self%rows(nl) = self%trow(k)
    end do
    ! A large zone (MULTIPLIERS AUGMENTED, or AUTO above AUGMENTED_ABOVE unknowns): the augmented
    ! sparse system, a slipping row's force tied to its contact's there (ms%solve_coulomb).
    if (ms%kkt_built .and. (ms%mode == SOLVER_AUGMENTED .or. (ms%mode == SOLVER_AUTO .and. ni > ms%switch_size))) then
      self%on = .false.
      self%rho = 0.0_dp
      do l = 1, ni
        self%on(self%rows(l)) = .true.
      end do
      do k = 1, self%n
        if (slipping(self, k)) &
          self%rho(self%trow(k)) = slip_force(self, k, 1.0_dp)
      end do
      call ms%solve_coulomb(q, self%on, self%rho, lam, g, singular, stat, errmsg)
      if (stat /= STAT_OK) return
      if (.not. singular) then
        wdiag = ms%wlow
        return
      end if                                   ! (dependent rows: the Schur columns below)
    end if
    self%keep = .false.
    do l = 1, nl                               ! (a loop: a vector subscript makes a temporary)
      self%keep(self%rows(l)) = .true.
    end do
    call ms%ensure(self%rows, nl, self%keep, stat, errmsg)
    if (stat /= STAT_OK) return
    if (size(self%m, 1) < ni) then             ! grow past the high-water mark
      deallocate (self%m)
      allocate (self%m(2 * ni, 2 * ni))
    end if
    call ms%w_block(self%rows, ni, self%rows, ni, self%m)
    do l = 1, ni
      j = self%rows(l)
      self%rhs(l) = -q(j)
      if (self%kof(j) >= 0) cycle
      k = -self%kof(j)                         ! a contact whose tangent slips: its force follows Λ_N
      if (.not. slipping(self, k)) cycle
      call ms%w_block(self%rows, ni, self%trow(k:k), 1, self%col)
      self%m(1:ni, l) = self%m(1:ni, l) + slip_force(self, k, 1.0_dp) * self%col(1:ni, 1)
    end do
    info = 0
    if (ni > 0) call dgesv(ni, 1, self%m, size(self%m, 1), self%ipiv, self%rhs, size(self%rhs), info)
    if (info /= 0) then
      call set_error(stat, errmsg, STAT_RUN, 'friction: the conditions of the contact zone are dependent (a ' // &
        'FRICTION contact on a DOF an IMPOSE or another contact also holds)')
      return
    end if
    lam = 0.0_dp
    do l = 1, ni
      lam(self%rows(l)) = self%rhs(l)
    end do
    do k = 1, self%n
      if (slipping(self, k)) &
        lam(self%trow(k)) = slip_force(self, k, lam(self%nrow(k)))
    end do
    g = q
    call ms%add_columns(self%rows, nl, lam, g)
    do l = 1, nl
      wdiag(self%rows(l)) = ms%w_entry(self%rows(l), self%rows(l))
    end do
  end subroutine solve_states

  !> Whether friction k's tangential row slips (either way).
  pure logical function slipping(self, k)
    class(coulomb_t), intent(in) :: self
    integer, intent(in) :: k
    slipping = self%state(k) == FRICTION_SLIP_POS .or. self%state(k) == FRICTION_SLIP_NEG
  end function slipping

  !> The force of the slipping tangential row of friction k for a normal multiplier lam_n:
  !> -μ Λ_N along +t (SLIP_POS), +μ Λ_N (SLIP_NEG).
  pure real(dp) function slip_force(self, k, lam_n) result(f)
    class(coulomb_t), intent(in) :: self
    integer, intent(in) :: k
    real(dp), intent(in) :: lam_n
    f = self%mu(k) * lam_n
    if (self%state(k) == FRICTION_SLIP_POS) f = -f
  end function slip_force

  !> The tangential rows' states into an open checkpoint (sticky stat): a restart continues bit for bit.
  subroutine coulomb_save(self, ck, stat, errmsg)
    class(coulomb_t), intent(in) :: self
    type(ckpt_file_t), intent(inout) :: ck
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    if (self%n > 0) call ck%put('contact_friction_state', self%state, stat, errmsg)
    if (self%n > 0 .and. any(self%trow2 > 0)) then
      call ck%put('contact_friction_theta', self%theta, stat, errmsg)
      call ck%put('contact_friction_slip', self%sig, stat, errmsg)
    end if
  end subroutine coulomb_save

  subroutine coulomb_load(self, ck, stat, errmsg)
    class(coulomb_t), intent(inout) :: self
    type(ckpt_file_t), intent(inout) :: ck
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    if (self%n > 0) call ck%get('contact_friction_state', self%state, stat, errmsg)
    if (self%n > 0 .and. any(self%trow2 > 0)) then
      call ck%get('contact_friction_theta', self%theta, stat, errmsg)
      call ck%get('contact_friction_slip', self%sig, stat, errmsg)
    end if
    if (stat == STAT_OK .and. any(self%state < FRICTION_FREE .or. self%state > FRICTION_SLIP_NEG)) &
      call set_error(stat, errmsg, STAT_INPUT, 'checkpoint: contact_friction_state out of range')
  end subroutine coulomb_load
end module coulomb
