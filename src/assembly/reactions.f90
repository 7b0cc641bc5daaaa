!> Support reactions (PROBE group RX|RY|RZ): the force the supports of a group exert, summed over
!> the group's fixed DOFs of one direction ("slot"). Supports are eliminated from the system,
!> so the reaction is read from the rows of the fixed DOFs, over a step, as the scheme's own
!> momentum balance of those rows gives it (the trapezoid rule, as for the free rows):
!>
!>     R̄ = [M_fa (v(n+1) − v(n)) + C_fa du] / h + ½ (Bσ(n) + Bσ(n+1) + Bσc)_f − ½ (F(n) + F(n+1))_f
!>
!> (a: the free DOFs; M_fa, C_fa the mass and damping couplings of the fixed rows; Bσc the
!> correction force of eq (9); F gravity and LOAD on the fixed DOFs). It is the mean force of
!> the step: in equilibrium it is Bσ − F. Only the elements touching a probed support are
!> visited: the cost follows the probes.
module reactions
  use kinds, only: dp
  use array_utils, only: grow
  implicit none
  private
  public :: reaction_set_t

  type :: reaction_set_t
    integer :: nslot = 0
    ! Slots 1..nprobe are the PROBE RX|RY|MZ sums; the next ones (FIELDS output) each fixed DOF:
    ! slot nprobe + k is DOF fdof(k) of node fnode(k) (fields.h5 support_reaction).
    integer :: nprobe = 0
    integer, allocatable :: fnode(:), fdof(:)
    ! Entries: local DOF loc of element e belongs to slot with weight ent_w (1; the arm of a
    ! PROBE MZ ABOUT's moment); CSR over the elements.
    integer, allocatable :: ent_ptr(:), ent_loc(:), ent_slot(:)
    real(dp), allocatable :: ent_w(:)
    ! Couplings of the slots' rows to the free equations: Σ M_fa(slot, eq) x(eq) (and C).
    integer, allocatable :: cp_slot(:), cp_eq(:)
    real(dp), allocatable :: cp_m(:), cp_c(:)
    integer :: ncp = 0
    real(dp), allocatable :: grav(:)          !< (nslot) gravity load on the slot's rows (unit function)
    real(dp), allocatable :: load(:, :)       !< (nload, nslot) each LOAD's force on the slot's rows
    ! Step state: values at the start of the step, the correction of the last evaluation, R̄.
    real(dp), allocatable :: p_n(:), cu_n(:), fint_n(:), f_n(:), fc_t(:), value(:)
    real(dp), allocatable :: p_w(:), cu_w(:), fint_w(:), f_w(:)   !< work: the same at the end
  contains
    procedure :: add_entry
    procedure :: add_couplings
    procedure :: finish_map
    procedure :: add_correction
    procedure :: step_mean
  end type reaction_set_t

contains

  !> During the map's construction (elements in order): local DOF loc of element e is in slot,
  !> with weight w (default 1).
  subroutine add_entry(self, e, loc, slot, w)
    class(reaction_set_t), intent(inout) :: self
    integer, intent(in) :: e, loc, slot
    real(dp), intent(in), optional :: w
    integer :: n
    n = self%ent_ptr(e + 1)
    if (.not. allocated(self%ent_w)) allocate (self%ent_w(16))
    call grow(self%ent_loc, n + 1)
    call grow(self%ent_slot, n + 1)
    call grow(self%ent_w, n + 1)
    self%ent_loc(n + 1) = loc
    self%ent_slot(n + 1) = slot
    self%ent_w(n + 1) = 1.0_dp
    if (present(w)) self%ent_w(n + 1) = w
    self%ent_ptr(e + 1) = n + 1
  end subroutine add_entry

  !> Element e's mass and damping rows of its slot DOFs, on its free equations dofs, and its
  !> gravity load g (per unit gravity function) on them.
  subroutine add_couplings(self, e, dofs, me, ce, g)
    class(reaction_set_t), intent(inout) :: self
    integer, intent(in) :: e, dofs(:)
    real(dp), intent(in) :: me(:, :), ce(:, :), g(:)
    integer :: p, k, j, s
    do p = self%ent_ptr(e) + 1, self%ent_ptr(e + 1)
      k = self%ent_loc(p)
      s = self%ent_slot(p)
      self%grav(s) = self%grav(s) + self%ent_w(p) * g(k)
      do j = 1, size(dofs)
        if (dofs(j) <= 0 .or. (me(k, j) == 0.0_dp .and. ce(k, j) == 0.0_dp)) cycle
        self%ncp = self%ncp + 1
        call grow(self%cp_slot, self%ncp)
        call grow(self%cp_eq, self%ncp)
        call grow(self%cp_m, self%ncp)
        call grow(self%cp_c, self%ncp)
        self%cp_slot(self%ncp) = s
        self%cp_eq(self%ncp) = dofs(j)
        self%cp_m(self%ncp) = self%ent_w(p) * me(k, j)
        self%cp_c(self%ncp) = self%ent_w(p) * ce(k, j)
      end do
    end do
  end subroutine add_couplings

  !> After the last entry: ent_ptr as offsets (entries of e: ent_ptr(e)+1 .. ent_ptr(e+1)) and
  !> the per-slot arrays sized.
  subroutine finish_map(self, nload)
    class(reaction_set_t), intent(inout) :: self
    integer, intent(in) :: nload
    allocate (self%grav(self%nslot), self%load(nload, self%nslot), self%p_n(self%nslot), self%cu_n(self%nslot), &
      self%fint_n(self%nslot), self%f_n(self%nslot), self%fc_t(self%nslot), self%value(self%nslot), &
      self%p_w(self%nslot), self%cu_w(self%nslot), self%fint_w(self%nslot), self%f_w(self%nslot))
    self%grav = 0.0_dp
    self%load = 0.0_dp
    self%fc_t = 0.0_dp
    self%value = 0.0_dp
    allocate (self%cp_slot(64), self%cp_eq(64), self%cp_m(64), self%cp_c(64))
  end subroutine finish_map

  !> internal_force: the correction force fc of element e (eq 9) on the slots' rows.
  pure subroutine add_correction(self, e, fc)
    class(reaction_set_t), intent(inout) :: self
    integer, intent(in) :: e
    real(dp), intent(in) :: fc(:)
    integer :: p
    do p = self%ent_ptr(e) + 1, self%ent_ptr(e + 1)
      self%fc_t(self%ent_slot(p)) = self%fc_t(self%ent_slot(p)) + self%ent_w(p) * fc(self%ent_loc(p))
    end do
  end subroutine add_correction

  !> At the end of a step of length h (first: the initial state, no step): with the end-of-step
  !> Bσ of the slots' rows (fint), external force on them (f), u and v, the mean reaction R̄ of
  !> the step into value; the end becomes the start of the next step.
  subroutine step_mean(self, fint, f, u, v, h, first)
    class(reaction_set_t), intent(inout) :: self
    real(dp), intent(in) :: fint(:), f(:), u(:), v(:), h
    logical, intent(in) :: first
    integer :: k
    self%p_w = 0.0_dp
    self%cu_w = 0.0_dp
    do k = 1, self%ncp
      self%p_w(self%cp_slot(k)) = self%p_w(self%cp_slot(k)) + self%cp_m(k) * v(self%cp_eq(k))
      self%cu_w(self%cp_slot(k)) = self%cu_w(self%cp_slot(k)) + self%cp_c(k) * u(self%cp_eq(k))
    end do
    if (first) then
      self%value = fint - f
    else
      self%value = (self%p_w - self%p_n + self%cu_w - self%cu_n) / h + 0.5_dp * (self%fint_n + fint + self%fc_t) - &
        0.5_dp * (self%f_n + f)
    end if
    self%p_n = self%p_w
    self%cu_n = self%cu_w
    self%fint_n = fint
    self%f_n = f
  end subroutine step_mean
end module reactions
