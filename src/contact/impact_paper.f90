!> IMPACT PAPER (method.md section 3): the energy E_j (10) lost when contact j is established is
!> given back by the impulses of (12)-(15), then the velocities of the impacting points are
!> reversed by the hzero step (16). Also the fallback of PERSIST and SYMMETRIC for groups their
!> projection leaves without kinetic energy. Inputs and outputs are arguments; the scratch is
!> the mode's own.
module impact_paper
  use kinds, only: dp
  use errors, only: STAT_OK
  use constraint_rows, only: constraint_rows_t
  use impact_kernels, only: impulse_fixed_point
  use impact_report, only: contact_report_t
  use impact_space, only: impact_space_t
  implicit none
  private

  type, public :: paper_t
    private
    integer, allocatable :: idx(:)
    real(dp), allocatable :: gain(:), nu(:), sv(:), ct(:), wq(:), work2(:), gmat(:, :)
  contains
    procedure :: init => paper_init
    procedure :: correct => paper_correction
  end type paper_t

contains

  !> Scratch for nc conditions (before the time loop; gmat grows with the largest set).
  subroutine paper_init(self, nc)
    class(paper_t), intent(inout) :: self
    integer, intent(in) :: nc
    if (allocated(self%idx)) deallocate (self%idx, self%gain, self%nu, self%sv, self%ct, self%wq, self%work2, self%gmat)
    allocate (self%idx(nc), self%gain(nc), self%nu(nc), self%sv(nc), self%ct(nc), self%wq(nc), self%work2(2 * nc), &
      self%gmat(min(nc, 64), min(nc, 64)))
  end subroutine paper_init

  !> Dense room for n conditions together (it only grows).
  subroutine reserve(self, nc, n)
    type(paper_t), intent(inout) :: self
    integer, intent(in) :: nc, n
    integer :: m
    if (.not. allocated(self%idx)) call self%init(nc)
    if (size(self%gmat, 1) >= n) return
    m = max(n, 2 * size(self%gmat, 1))
    deallocate (self%gmat)
    allocate (self%gmat(m, m))
  end subroutine reserve

  !> IMPACT PAPER for the conditions sel (all established in the step): the impulses of
  !> (12)-(15) (impulse_eq12_15), then the hzero reflection (16) about all of them, with the
  !> gains 1 + e_j of their RESTITUTION (Newton's law: the kinetic energy it takes is booked in
  !> rep%impact_dissipated). lambda: the step multipliers; e: E_j of (10). Out: y(j) the impulse
  !> factors of (13)-(14) on sel; cimp(j) += the impulses along c_j; v, mv (= M v) corrected.
  subroutine paper_correction(self, sp, c, sel, lambda, e, fp_tol, fp_max_iter, v, mv, y, cimp, rep, stat, errmsg)
    class(paper_t), intent(inout) :: self
    type(impact_space_t), intent(inout) :: sp
    type(constraint_rows_t), intent(in) :: c
    logical, intent(in) :: sel(:)
    real(dp), intent(in) :: lambda(:), e(:), fp_tol
    integer, intent(in) :: fp_max_iter
    real(dp), intent(inout) :: v(:), mv(:), y(:), cimp(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: j, n, rank
    real(dp) :: t_elastic
    logical :: inelastic
    call reserve(self, size(sel), 0)
    call impulse_eq12_15(self, sp, c, sel, lambda, e, fp_tol, fp_max_iter, v, mv, y, cimp, rep, stat, errmsg)
    if (stat /= STAT_OK) return
    n = 0
    inelastic = .false.
    do j = 1, size(sel)
      if (.not. sel(j)) cycle
      n = n + 1
      self%idx(n) = j
      self%gain(n) = 1.0_dp + c%restitution(j)
      inelastic = inelastic .or. c%restitution(j) < 1.0_dp
    end do
    if (inelastic) t_elastic = 0.5_dp * dot_product(v, mv)
    call sp%hzero_step(c, self%idx(1:n), self%gain(1:n), v, mv, self%nu, rank, stat, errmsg)
    if (stat /= STAT_OK) return
    rep%reflection_rank = rank
    cimp = cimp - self%nu
    ! RESTITUTION e < 1: Newton's law took (1 - e²) of the normal kinetic energy (measured).
    if (inelastic) rep%impact_dissipated = rep%impact_dissipated + (t_elastic - 0.5_dp * dot_product(v, mv))
  end subroutine paper_correction

  !> (12)-(15) for the conditions sel established in the step with Λ_j > 0: E_j (eq 10) given
  !> back as kinetic energy by the impulses y_j Λ_j c_j, y from the coupled quadratics (14)
  !> (impulse_fixed_point; (13) for one point), then (12) v <- v + M⁻¹ Σ y_j Λ_j c_j.
  subroutine impulse_eq12_15(self, sp, c, sel, lambda, e, fp_tol, fp_max_iter, v, mv, y, cimp, rep, stat, errmsg)
    type(paper_t), intent(inout) :: self
    type(impact_space_t), intent(inout) :: sp
    type(constraint_rows_t), intent(in) :: c
    logical, intent(in) :: sel(:)
    real(dp), intent(in) :: lambda(:), e(:), fp_tol
    integer, intent(in) :: fp_max_iter
    real(dp), intent(inout) :: v(:), mv(:), y(:), cimp(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: change
    integer :: j, k, n, iters
    logical :: conv
    stat = STAT_OK
    n = 0
    do j = 1, size(sel)
      if (.not. (sel(j) .and. lambda(j) > 0.0_dp)) cycle
      n = n + 1
      self%idx(n) = j
    end do
    call reserve(self, size(sel), n)
    if (n == 0) return
    associate (ip => self%idx(1:n), g => self%gmat(1:n, 1:n))
      call sp%am_block(c, ip, n, g, stat, errmsg)
      if (stat /= STAT_OK) return
      do k = 1, n
        g(:, k) = g(:, k) * lambda(ip) * lambda(ip(k))
        self%sv(k) = lambda(ip(k)) * c%dot(ip(k), v)
        self%ct(k) = e(ip(k))
      end do
      call impulse_fixed_point(g, self%sv(1:n), self%ct(1:n), self%wq(1:n), iters, change, conv, fp_tol, fp_max_iter, &
        self%work2)
      rep%fp_iterations = rep%fp_iterations + iters
      rep%fp_change = max(rep%fp_change, change)
      if (.not. conv) rep%fp_failures = rep%fp_failures + 1     ! reported, energy still exact
      self%nu = 0.0_dp
      do k = 1, n
        y(ip(k)) = self%wq(k)
        self%nu(ip(k)) = self%wq(k) * lambda(ip(k))
      end do
    end associate
    call sp%add_minv_ct(c, self%nu, 1.0_dp, v, mv, stat, errmsg)          ! (12)
    if (stat /= STAT_OK) return
    cimp = cimp + self%nu
  end subroutine impulse_eq12_15
end module impact_paper
