!> The groups of method.md section 6: bodies (the mesh-connected components of the equations)
!> linked by active conditions and by the conditions whose energy a correction changes. A union-
!> find forest over the bodies; each mode that scales groups (PERSIST, MASSLESS, SYMMETRIC's
!> fallback, the rows that follow the geometry) builds its own.
module impact_groups
  use errors, only: STAT_OK, STAT_INPUT, set_error
  use constraint_rows, only: constraint_rows_t
  implicit none
  private

  type, public :: impact_groups_t
    private
    integer :: nb = 0                        !< bodies
    integer, allocatable :: parent(:)        !< union-find forest over the bodies
    integer, allocatable :: cgroup(:)        !< representative body of condition j's group (0: none, -1: no body)
  contains
    procedure :: init => groups_init
    procedure :: build => groups_build
    procedure :: n_bodies => groups_n_bodies
    procedure :: is_root => groups_is_root
    procedure :: of => groups_of
    procedure :: rows_of => groups_rows_of
    procedure :: members => groups_members
  end type impact_groups_t

contains

  !> Room for neq equations (at most neq bodies) and nc conditions.
  pure subroutine groups_init(self, neq, nc)
    class(impact_groups_t), intent(inout) :: self
    integer, intent(in) :: neq, nc
    if (allocated(self%parent)) deallocate (self%parent, self%cgroup)
    allocate (self%parent(neq), self%cgroup(nc))
  end subroutine groups_init

  !> The groups of the conditions of c that are active (now) or change the energy (changing);
  !> body(i) the body of equation i (0: none).
  subroutine groups_build(self, c, body, now, changing, stat, errmsg)
    class(impact_groups_t), intent(inout) :: self
    type(constraint_rows_t), intent(in) :: c
    integer, intent(in) :: body(:)
    logical, intent(in) :: now(:), changing(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: i, j, p, bj, nc
    stat = STAT_OK
    self%nb = 0
    nc = size(now)
    if (size(body) /= c%n_equations()) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_end_step: body(:) must have one entry per equation')
      return
    end if
    if (size(body) > 0) self%nb = max(maxval(body), 0)
    if (.not. allocated(self%parent)) call self%init(size(body), nc)        ! (init: before the time loop)
    if (size(self%parent) < self%nb) then
      deallocate (self%parent)
      allocate (self%parent(self%nb))
    end if
    if (size(self%cgroup) /= nc) then
      deallocate (self%cgroup)
      allocate (self%cgroup(nc))
    end if
    associate (parent => self%parent, cgroup => self%cgroup)
      do i = 1, self%nb
        parent(i) = i
      end do
      cgroup = 0
      do j = 1, nc
        if (.not. (now(j) .or. changing(j))) cycle
        do p = c%first(j), c%last(j)
          bj = body(c%eq_at(p))
          if (bj <= 0) then
            cgroup(j) = -1
            exit
          end if
          if (cgroup(j) == 0) then
            cgroup(j) = bj
          else
            call union(parent, cgroup(j), bj)
          end if
        end do
      end do
      do j = 1, nc
        if (cgroup(j) > 0) cgroup(j) = find(parent, cgroup(j))
      end do
    end associate
  end subroutine groups_build

  pure integer function groups_n_bodies(self)
    class(impact_groups_t), intent(in) :: self
    groups_n_bodies = self%nb
  end function groups_n_bodies

  !> True when body grp represents its group.
  pure logical function groups_is_root(self, grp)
    class(impact_groups_t), intent(in) :: self
    integer, intent(in) :: grp
    groups_is_root = find(self%parent, grp) == grp
  end function groups_is_root

  !> The group of condition j (0: neither active nor changing, -1: on an equation without body).
  pure integer function groups_of(self, j)
    class(impact_groups_t), intent(in) :: self
    integer, intent(in) :: j
    groups_of = self%cgroup(j)
  end function groups_of

  !> m(j) = condition j belongs to group grp.
  pure subroutine groups_members(self, grp, m)
    class(impact_groups_t), intent(in) :: self
    integer, intent(in) :: grp
    logical, intent(out) :: m(:)
    integer :: j
    do j = 1, size(m)
      m(j) = self%cgroup(j) == grp
    end do
  end subroutine groups_members

  !> rows = the equations of group grp.
  pure subroutine groups_rows_of(self, body, grp, rows)
    class(impact_groups_t), intent(in) :: self
    integer, intent(in) :: body(:), grp
    logical, intent(out) :: rows(:)
    integer :: i
    do i = 1, size(body)
      rows(i) = body(i) > 0
      if (rows(i)) rows(i) = find(self%parent, body(i)) == grp
    end do
  end subroutine groups_rows_of

  pure recursive integer function find(parent, i) result(r)
    integer, intent(in) :: parent(:), i
    r = i
    if (parent(i) /= i) r = find(parent, parent(i))
  end function find

  pure subroutine union(parent, a, b)
    integer, intent(inout) :: parent(:)
    integer, intent(in) :: a, b
    integer :: ra, rb
    ra = find(parent, a)
    rb = find(parent, b)
    if (ra /= rb) parent(max(ra, rb)) = min(ra, rb)
  end subroutine union
end module impact_groups
