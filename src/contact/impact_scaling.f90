!> Energy given to (or taken from) groups by scaling alone, no projection: IMPACT MASSLESS's
!> correction (massless contact nodes have no normal velocity to stop; docs/contact.md) and the
!> work of the rows that follow the geometry (contact_rewrite), which every mode but OFF gives
!> back. Each group of bodies linked by active conditions that holds a changing condition j gets
!> the kinetic energy T1 + Σ w_j by scaling its velocity about the rigid motion the contact cannot
!> change. Inputs and outputs are arguments; the scratch is the instance's own.
module impact_scaling
  use kinds, only: dp
  use errors, only: STAT_OK
  use constraint_rows, only: constraint_rows_t
  use impact_kernels, only: persist_scale
  use impact_report, only: contact_report_t
  use impact_space, only: impact_space_t, MAX_RIGID
  use impact_groups, only: impact_groups_t
  implicit none
  private

  type, public :: scaling_t
    private
    type(impact_groups_t) :: groups
    integer, allocatable :: idx(:)
    logical, allocatable :: mem(:), rows(:)
    real(dp), allocatable :: z(:), vp(:), mvp(:)    !< vp, mvp: the velocity before the scaling, M vp
  contains
    procedure :: init => scaling_init
    procedure :: correct => scaling_correction
  end type scaling_t

contains

  !> Scratch for neq equations and nc conditions (before the time loop).
  subroutine scaling_init(self, neq, nc)
    class(scaling_t), intent(inout) :: self
    integer, intent(in) :: neq, nc
    if (allocated(self%idx)) deallocate (self%idx, self%mem, self%z, self%rows, self%vp, self%mvp)
    allocate (self%idx(nc), self%mem(nc), self%z(nc), self%rows(neq), self%vp(neq), self%mvp(neq))
    call self%groups%init(neq, nc)
  end subroutine scaling_init

  !> Scale each group holding a condition of changing (now: active at the step's end) to T1 +
  !> Σ w_j over its changing conditions. Groups whose kinetic energy, less their rigid motion's,
  !> is at most min_fraction of the target cannot be scaled: fallback(j) for their changing
  !> conditions, the energy left in rep%unrestored (the balance shows it), as is a target below
  !> the rigid motion's energy. Out: v, mv (= M v); cimp(j) += the scaling's normal impulses;
  !> bimp(:, j) += a held group's scaling momentum.
  subroutine scaling_correction(self, sp, c, body, changing, now, w, min_fraction, v, mv, cimp, bimp, fallback, rep, &
    stat, errmsg)
    class(scaling_t), intent(inout) :: self
    type(impact_space_t), intent(inout) :: sp
    type(constraint_rows_t), intent(in) :: c
    integer, intent(in) :: body(:)
    logical, intent(in) :: changing(:), now(:)
    real(dp), intent(in) :: w(:), min_fraction
    real(dp), intent(inout) :: v(:), mv(:), cimp(:), bimp(:, :)
    logical, intent(out) :: fallback(:)
    type(contact_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: j, grp, n, nm, mk(MAX_RIGID)
    real(dp) :: t1, tstar, s, acm(MAX_RIGID), tcm, dm(MAX_RIGID), pb(3)
    stat = STAT_OK
    fallback = .false.
    if (.not. allocated(self%idx)) call self%init(size(v), size(now))
    call self%groups%build(c, body, now, changing, stat, errmsg)
    if (stat /= STAT_OK) return
    do j = 1, size(now)
      if (changing(j) .and. self%groups%of(j) <= 0) fallback(j) = .true.
    end do
    associate (mem => self%mem, rows => self%rows, idx => self%idx)
      do grp = 1, self%groups%n_bodies()
        if (.not. self%groups%is_root(grp)) cycle
        call self%groups%members(grp, mem)
        if (.not. any(changing .and. mem)) cycle
        rep%persist_groups = rep%persist_groups + 1
        call self%groups%rows_of(body, grp, rows)
        n = 0
        do j = 1, size(now)
          if (.not. (now(j) .and. mem(j))) cycle
          n = n + 1
          idx(n) = j
        end do
        t1 = 0.5_dp * sum(v * mv, mask=rows)
        self%vp = v
        self%mvp = mv
        tstar = t1 + sum(w, mask=changing .and. mem)
        call sp%rigid_motion(c, body, rows, idx, n, self%mvp, acm, tcm, nm, mk)
        if (.not. (t1 - tcm > min_fraction * tstar)) then
          where (changing .and. mem) fallback = .true.
          rep%persist_fallbacks = rep%persist_fallbacks + 1
          rep%unrestored = rep%unrestored + abs(tstar - t1)
          cycle
        end if
        s = persist_scale(tstar, tcm, t1 - tcm)
        if (tstar < tcm) rep%unrestored = rep%unrestored + (tcm - tstar)
        call sp%scale_about_rigid(rows, acm, nm, mk, s, self%vp, self%mvp, v, mv, dm, pb)
        call sp%book_scaling(idx, n, nm, dm, pb, findloc(changing .and. mem, .true., 1), self%z, cimp, bimp)
      end do
    end associate
  end subroutine scaling_correction
end module impact_scaling
