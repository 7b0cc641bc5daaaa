!> BAR2 element: two-node truss, UX, UY per node.
!> Strain: the axial strain eps = n . (u2 - u1) / L (constant), one point of weight A*L, so
!> f_int = B^T sigma A L and K = EA/L [c^2 cs; cs s^2] blocks.
!> Mass: consistent rho A L/6 [2 1; 1 2] in each of x and y, lumped rho A L/2 per node and
!> direction (both rotation-invariant, so no transformation is needed).
module element_bar2
  use kinds, only: dp, zero_tol
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  implicit none
  private
  public :: bar2_b, bar2_mass, bar2_check

contains

  !> B (1 x 4) such that eps = B u_e, and the weight A*L.
  pure subroutine bar2_b(x, area, b, wt)
    real(dp), intent(in) :: x(2, 2), area
    real(dp), intent(out) :: b(1, 4), wt
    real(dp) :: d(2), len
    d = x(:, 2) - x(:, 1)
    len = norm2(d)
    if (len > 0.0_dp) then
      b(1, 1:2) = -d / len**2
      b(1, 3:4) = d / len**2
    else
      b = 0.0_dp
    end if
    wt = area * len
  end subroutine bar2_b

  !> Mass matrix (4 x 4), DOFs (ux1, uy1, ux2, uy2).
  pure subroutine bar2_mass(x, area, rho, lumped, me)
    real(dp), intent(in) :: x(2, 2), area, rho
    logical, intent(in) :: lumped
    real(dp), intent(out) :: me(4, 4)
    real(dp) :: m
    integer :: i
    m = rho * area * norm2(x(:, 2) - x(:, 1))
    me = 0.0_dp
    if (lumped) then
      do i = 1, 4
        me(i, i) = 0.5_dp * m
      end do
    else
      do i = 1, 2
        me(i, i) = m / 3.0_dp
        me(i + 2, i + 2) = m / 3.0_dp
        me(i, i + 2) = m / 6.0_dp
        me(i + 2, i) = m / 6.0_dp
      end do
    end if
  end subroutine bar2_mass

  !> Reject a zero length (L <= zero_tol * ref). name is the element type for the message.
  pure subroutine bar2_check(x, ref, name, stat, errmsg)
    real(dp), intent(in) :: x(2, 2), ref
    character(len=*), intent(in) :: name
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: len
    stat = STAT_OK
    len = norm2(x(:, 2) - x(:, 1))
    if (len <= zero_tol * ref) then
      call set_error(stat, errmsg, STAT_INPUT, 'zero-length ' // name // ' element (L = ' // str(len) // &
        ', its two nodes coincide)')
    end if
  end subroutine bar2_check
end module element_bar2
