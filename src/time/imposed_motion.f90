!> IMPOSE group UX|UY|RZ [VALUE a] FUNCTION f (docs/input.md): prescribed displacements held
!> exactly by the step's multipliers. Each imposed DOF is a bilateral row of the contact set,
!> u_i - a f(t(n+1)) = 0 at the end of every step, always active, its multiplier of any sign the
!> trapezoidal reaction R(n) + R(n+1). Its work over the step, ½ Λ du_i, is the work of the
!> imposed motion, which the driver adds to the external work: the balance stays exact.
!> OBSTACLE … VELOCITY (obstacle_targets): a rigid plane's prescribed translation moves its
!> conditions' gaps; the contact set books its work (contact_frame).
module imposed_motion
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use scene, only: scene_t, function_value, function_slope, probe_weight, function_integral, condition_tangent
  use assembly, only: system_t
  use dof_map, only: DOF_FIXED, DOF_ABSENT
  use array_utils, only: grow
  use contact, only: contact_set_t, contact_add, contact_set_bilateral, contact_set_gap0
  use contact_geometry, only: following_t
  implicit none
  private
  public :: imposed_start, imposed_rows, imposed_targets, imposed_probe_map, imposed_reactions, obstacle_targets

  character(len=2), parameter :: DOF_NAME(3) = ['UX', 'UY', 'RZ']

contains

  !> The initial state of the imposed DOFs: u = a f(t0), v = a f'(t0) (right derivative). A DOF
  !> also fixed, or one its node does not carry, is bad input naming the statement.
  subroutine imposed_start(scn, sys, u, v, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(inout) :: u(:), v(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, i, n, eq
    character(len=:), allocatable :: why
    stat = STAT_OK
    do k = 1, size(scn%imposes)
      associate (im => scn%imposes(k), nodes => scn%mesh%ngroups(scn%imposes(k)%ngroup)%items)
        do i = 1, size(nodes)
          n = nodes(i)
          eq = sys%dofs%eqn(im%dof, n)
          if (eq == DOF_FIXED .or. eq == DOF_ABSENT) then
            if (eq == DOF_FIXED) then
              why = ' has its ' // DOF_NAME(im%dof) // ' fixed (FIX and IMPOSE on one DOF)'
            else
              why = ' carries no ' // DOF_NAME(im%dof)
            end if
            call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(im%line) // ': IMPOSE ' // &
              scn%mesh%ngroups(im%ngroup)%name // ': node ' // str(n) // why // ", at '" // DOF_NAME(im%dof) // "'")
            return
          end if
          u(eq) = im%value * function_value(scn%functions, im%func, scn%t_start)
          v(eq) = im%value * function_slope(scn%functions, im%func, scn%t_start)
        end do
      end associate
    end do
  end subroutine imposed_start

  !> Append the bilateral rows, one per imposed DOF, after the contact conditions.
  subroutine imposed_rows(scn, sys, cs)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    type(contact_set_t), intent(inout) :: cs
    integer :: k, i, n
    if (size(scn%imposes) == 0) return
    call contact_set_bilateral(cs, size(scn%conditions) + 1)
    do k = 1, size(scn%imposes)
      associate (im => scn%imposes(k), nodes => scn%mesh%ngroups(scn%imposes(k)%ngroup)%items)
        do i = 1, size(nodes)
          n = nodes(i)
          call contact_add(cs, -im%value * function_value(scn%functions, im%func, scn%t_start), &
            [sys%dofs%eqn(im%dof, n)], [1.0_dp], nodes=[0, n], label='IMPOSE ' // scn%mesh%ngroups(im%ngroup)%name)
        end do
      end associate
    end do
  end subroutine imposed_rows

  !> Before the step ending at t: each row's target, g_j = u_i - a f(t) = 0.
  subroutine imposed_targets(scn, cs, t)
    type(scene_t), intent(in) :: scn
    type(contact_set_t), intent(inout) :: cs
    real(dp), intent(in) :: t
    integer :: k, i, j
    j = size(scn%conditions)
    do k = 1, size(scn%imposes)
      associate (im => scn%imposes(k))
        do i = 1, size(scn%mesh%ngroups(im%ngroup)%items)
          j = j + 1
          call contact_set_gap0(cs, j, -im%value * function_value(scn%functions, im%func, t))
        end do
      end associate
    end do
  end subroutine imposed_targets

  !> Before the step from t0 to t1: each moving plane obstacle's condition j (row j) at its
  !> place at t1, g0 - n.w(t1) with w(t) = velocity x ∫ f from the start time, what the step's
  !> motion takes off the gap, n.(w(t1) - w(t0)), and its velocity at t1 (contact_frame); a
  !> moving circle's centre displacements w(t0), w(t1) and velocity to its rows (follow).
  subroutine obstacle_targets(scn, cs, follow, t0, t1)
    type(scene_t), intent(in) :: scn
    type(contact_set_t), intent(inout) :: cs
    type(following_t), intent(inout) :: follow
    real(dp), intent(in) :: t0, t1
    integer :: j, k
    real(dp) :: f1, vn
    do j = 1, size(scn%conditions)
      associate (c => scn%conditions(j))
        if (.not. c%moving) cycle
        f1 = function_value(scn%functions, c%vfunc, t1)
        if (c%follow) then                     ! a circle: its centre's motion (contact_geometry)
          call follow%move(j, c%velocity(1:2) * function_integral(scn%functions, c%vfunc, scn%t_start, t0), &
            c%velocity(1:2) * function_integral(scn%functions, c%vfunc, scn%t_start, t1), c%velocity(1:2) * f1)
          cycle
        end if
        vn = dot_product(c%normal(1:scn%mesh%ndim), c%velocity(1:scn%mesh%ndim))
        call contact_set_gap0(cs, j, c%g0 - vn * function_integral(scn%functions, c%vfunc, scn%t_start, t1))
        call cs%move_obstacle(j, vn * function_integral(scn%functions, c%vfunc, t0, t1), vn * f1, c%velocity * f1)
        do k = 1, scn%mesh%ndim - 1            ! FRICTION: the slip is relative to the obstacle
          if (cs%tangent_row(j, k) == 0) exit
          if (scn%mesh%ndim == 3) then
            vn = dot_product(c%velocity, condition_tangent(c, 3, k))
          else
            vn = dot_product(c%velocity(1:2), [-c%normal(2), c%normal(1)])
          end if
          call cs%move_obstacle(cs%tangent_row(j, k), vn * function_integral(scn%functions, c%vfunc, t0, t1), vn * f1, &
            c%velocity * f1)
        end do
      end associate
    end do
  end subroutine obstacle_targets

  !> The (row, slot, weight) triples of the support-reaction probes (PROBE group RX|RY|MZ, in
  !> order) that sum an imposed DOF: its node in the probe's group, its DOF the probe's direction
  !> (weight 1), or for MZ ABOUT any translation, weighted by its arm (probe_weight).
  subroutine imposed_probe_map(scn, row, slot, weight)
    type(scene_t), intent(in) :: scn
    integer, allocatable, intent(out) :: row(:), slot(:)
    real(dp), allocatable, intent(out) :: weight(:)
    logical, allocatable :: member(:)
    integer :: k, i, j, s, p, np, npair, n
    real(dp) :: w
    allocate (row(8), slot(8), weight(8), member(scn%mesh%nnode))
    s = 0
    npair = 0
    do p = 1, size(scn%probes)
      if (.not. scn%probes(p)%reaction) cycle
      s = s + 1
      member = .false.
      member(scn%mesh%ngroups(scn%probes(p)%ngroup)%items) = .true.
      j = size(scn%conditions)
      do k = 1, size(scn%imposes)
        np = size(scn%mesh%ngroups(scn%imposes(k)%ngroup)%items)
        do i = 1, np
          j = j + 1
          n = scn%mesh%ngroups(scn%imposes(k)%ngroup)%items(i)
          w = probe_weight(scn%probes(p), scn%imposes(k)%dof, scn%mesh%x(:, n))
          if (w == 0.0_dp .or. .not. member(n)) cycle
          npair = npair + 1
          call grow(row, npair)
          call grow(slot, npair)
          call grow(weight, npair)
          row(npair) = j
          slot(npair) = s
          weight(npair) = w
        end do
      end do
    end do
    row = row(1:npair)
    slot = slot(1:npair)
    weight = weight(1:npair)
  end subroutine imposed_probe_map

  !> After a step: the mean force of the step at each imposed DOF, half its multiplier (which
  !> stands for R(n) + R(n+1)), added to the reaction probes that sum it.
  subroutine imposed_reactions(cs, row, slot, weight, value)
    type(contact_set_t), intent(in) :: cs
    integer, intent(in) :: row(:), slot(:)
    real(dp), intent(in) :: weight(:)
    real(dp), intent(inout) :: value(:)
    integer :: k
    do k = 1, size(row)
      value(slot(k)) = value(slot(k)) + 0.5_dp * weight(k) * cs%multiplier(row(k))
    end do
  end subroutine imposed_reactions
end module imposed_motion
