!> IMPACT PERSIST (method.md section 6, docs/contact.md): in each group of bodies linked by active
!> conditions that holds an established one, the velocity is projected on zero normal velocity of
!> all its active conditions (the hzero step with gains 1), then scaled about the rigid motion the
!> contact cannot change so that the group's kinetic energy is T1 + Σ E_j. Groups the projection
!> leaves without kinetic energy are returned in fallback for PAPER. Inputs and outputs are
!> arguments; the scratch is the mode's own.
module impact_persist
  use kinds, only: dp
  use errors, only: STAT_OK
  use constraint_rows, only: constraint_rows_t
  use impact_kernels, only: persist_scale
  use impact_report, only: contact_report_t
  use impact_space, only: impact_space_t, MAX_RIGID
  use impact_groups, only: impact_groups_t
  implicit none
  private

  type, public :: persist_t
    private
    type(impact_groups_t) :: groups
    integer, allocatable :: idx(:)
    logical, allocatable :: mem(:), rows(:)
    real(dp), allocatable :: gain(:), nu(:), z(:), vp(:), mvp(:), vn(:), mvn(:)
  contains
    procedure :: init => persist_init
    procedure :: correct => persist_correction
  end type persist_t

contains

  !> Scratch for neq equations and nc conditions (before the time loop).
  subroutine persist_init(self, neq, nc)
    class(persist_t), intent(inout) :: self
    integer, intent(in) :: neq, nc
    if (allocated(self%idx)) deallocate (self%idx, self%mem, self%gain, self%nu, self%z, self%rows, self%vp, self%mvp, &
      self%vn, self%mvn)
    allocate (self%idx(nc), self%mem(nc), self%gain(nc), self%nu(nc), self%z(nc), self%rows(neq), self%vp(neq), &
      self%mvp(neq), self%vn(neq), self%mvn(neq))
    call self%groups%init(neq, nc)
  end subroutine persist_init

  !> Section 6 for the conditions est established in the step (now: active at its end; e: E_j of
  !> (10); body(i): the body of equation i). RESTITUTION e < 1 on an established condition: Newton's
  !> law (gains 1 + e, maintained contacts 1) tells the kinetic energy the impact keeps, the rest is
  !> booked in rep%impact_dissipated. Groups whose projected kinetic energy, less their rigid
  !> motion's, is at most min_fraction of the target, and conditions on equations without body,
  !> are left untouched: fallback(j) (their established conditions). Out: v, mv (= M v); cimp(j)
  !> += the projection's impulses along c_j and the scaling's normal impulses; bimp(:, j) += a
  !> held group's scaling momentum.
  subroutine persist_correction(self, sp, c, body, est, now, e, inelastic, min_fraction, v, mv, cimp, bimp, fallback, &
    rep, stat, errmsg)
    class(persist_t), intent(inout) :: self
    type(impact_space_t), intent(inout) :: sp
    type(constraint_rows_t), intent(in) :: c
    integer, intent(in) :: body(:)
    logical, intent(in) :: est(:), now(:), inelastic
    real(dp), intent(in) :: e(:), min_fraction
    real(dp), intent(inout) :: v(:), mv(:), cimp(:), bimp(:, :)
    logical, intent(out) :: fallback(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: j, grp, rank, n, k, nm, mk(MAX_RIGID)
    real(dp) :: t1, tp, tstar, s, acm(MAX_RIGID), tcm, dis, dm(MAX_RIGID), pb(3)
    stat = STAT_OK
    fallback = .false.
    if (.not. allocated(self%idx)) call self%init(size(v), size(est))
    call self%groups%build(c, body, now, est, stat, errmsg)
    if (stat /= STAT_OK) return
    do j = 1, size(est)
      if (est(j) .and. self%groups%of(j) <= 0) fallback(j) = .true.
    end do
    associate (mem => self%mem, rows => self%rows, idx => self%idx)
      do grp = 1, self%groups%n_bodies()
        if (.not. self%groups%is_root(grp)) cycle
        call self%groups%members(grp, mem)
        if (.not. any(est .and. mem)) cycle
        rep%persist_groups = rep%persist_groups + 1
        call self%groups%rows_of(body, grp, rows)
        n = 0
        do j = 1, size(est)
          if (.not. (now(j) .and. mem(j))) cycle
          n = n + 1
          idx(n) = j
        end do
        t1 = 0.5_dp * sum(v * mv, mask=rows)
        dis = 0.0_dp
        self%vp = v
        self%mvp = mv
        if (inelastic) then
          do k = 1, n
            self%gain(k) = 1.0_dp
            if (est(idx(k))) self%gain(k) = 1.0_dp + c%restitution(idx(k))
          end do
          if (any(self%gain(1:n) < 2.0_dp .and. est(idx(1:n)))) then
            self%vn = v
            self%mvn = mv
            call sp%hzero_step(c, idx(1:n), self%gain(1:n), self%vn, self%mvn, self%nu, rank, stat, errmsg)
            if (stat /= STAT_OK) return
            dis = t1 - 0.5_dp * sum(self%vn * self%mvn, mask=rows)
          end if
        end if
        self%gain(1:n) = 1.0_dp
        call sp%hzero_step(c, idx(1:n), self%gain(1:n), self%vp, self%mvp, self%nu, rank, stat, errmsg)   ! the projection
        if (stat /= STAT_OK) return
        tp = 0.5_dp * sum(self%vp * self%mvp, mask=rows)
        tstar = t1 + sum(e, mask=est .and. mem) - dis
        ! Scale about the group's rigid motion that its conditions leave invariant (a rigid
        ! motion the contact cannot change: the tangential translation and the rotation about
        ! the contact normal against a wall, every translation between free bodies): the momenta
        ! the contact cannot change and the zero normal velocities are kept.
        call sp%rigid_motion(c, body, rows, idx, n, self%mvp, acm, tcm, nm, mk)
        if (.not. (tp - tcm > min_fraction * tstar)) then
          where (est .and. mem) fallback = .true.
          rep%persist_fallbacks = rep%persist_fallbacks + 1
          cycle                                  ! (PAPER takes over)
        end if
        s = persist_scale(tstar, tcm, tp - tcm)
        ! A target below the rigid motion's energy cannot be reached by scaling (s = 0): the rest
        ! stays in the balance, and the driver says so.
        if (tstar < tcm) rep%unrestored = rep%unrestored + (tcm - tstar)
        cimp = cimp - self%nu                    ! the projection's impulses along c_j
        rep%impact_dissipated = rep%impact_dissipated + dis
        call sp%scale_about_rigid(rows, acm, nm, mk, s, self%vp, self%mvp, v, mv, dm, pb)
        call sp%book_scaling(idx, n, nm, dm, pb, findloc(est .and. mem, .true., 1), self%z, cimp, bimp)
      end do
    end associate
  end subroutine persist_correction
end module impact_persist
