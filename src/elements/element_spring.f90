!> SPRING element: two nodes carrying UX, UY, massless.
!> Generalized strain: the elongation e = n . (u2 - u1) [m] along the unit axis n, with one
!> "integration point" of weight 1, so the generalized stress is the spring force [N] and the
!> elastic D is the stiffness k [N/m] (the material's YOUNG for springs).
!> The axis n is sec%direction (normalised) when the section gives one, else node 1 -> node 2.
!> A direction is required when the nodes coincide. It is fixed in space (small displacements),
!> so a spring whose direction is not along its nodes is not rotation-invariant.
module element_spring
  use kinds, only: dp, zero_tol
  use section, only: section_t
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  implicit none
  private
  public :: spring_axis, spring_b, spring_check

contains

  !> Unit axis of the spring; ok is false (and n zero) when none can be defined.
  pure subroutine spring_axis(x, sec, n, ok)
    real(dp), intent(in) :: x(2, 2)
    type(section_t), intent(in) :: sec
    real(dp), intent(out) :: n(2)
    logical, intent(out) :: ok
    real(dp) :: d(2), nrm
    if (sec%has_direction) then
      d = sec%direction
    else
      d = x(:, 2) - x(:, 1)
    end if
    nrm = norm2(d)
    ok = nrm > 0.0_dp
    if (ok) then
      n = d / nrm
    else
      n = 0.0_dp
    end if
  end subroutine spring_axis

  !> B (1 x 4) such that e = B u_e, and the weight (1).
  pure subroutine spring_b(x, sec, b, wt)
    real(dp), intent(in) :: x(2, 2)
    type(section_t), intent(in) :: sec
    real(dp), intent(out) :: b(1, 4), wt
    real(dp) :: n(2)
    logical :: ok
    call spring_axis(x, sec, n, ok)
    b(1, 1:2) = -n
    b(1, 3:4) = n
    wt = 1.0_dp
  end subroutine spring_b

  !> Reject a zero direction, or coincident nodes (|x2 - x1| <= zero_tol * ref) without one.
  pure subroutine spring_check(x, sec, ref, stat, errmsg)
    real(dp), intent(in) :: x(2, 2)
    type(section_t), intent(in) :: sec
    real(dp), intent(in) :: ref
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: len
    stat = STAT_OK
    if (sec%has_direction) then
      if (norm2(sec%direction) <= 0.0_dp) then
        call set_error(stat, errmsg, STAT_INPUT, 'SPRING direction is the zero vector')
      end if
      return
    end if
    len = norm2(x(:, 2) - x(:, 1))
    if (len <= zero_tol * ref) then
      call set_error(stat, errmsg, STAT_INPUT, 'SPRING nodes coincide (distance ' // str(len) // &
        ') and its section gives no DIRECTION')
    end if
  end subroutine spring_check
end module element_spring
