!> 3 x 3 matrices in closed form, for the solids' Jacobians, deformation gradients and right
!> Cauchy-Green tensors (element_solid, large_solid, law_hyperelastic): the determinant and the
!> adjugate (A adj(A) = det(A) I), so that a caller divides once and checks det itself; and the
!> symmetric part of a small square matrix in place (a law's tangent before a symmetric assembly).
module small_matrix
  use kinds, only: dp
  implicit none
  private
  public :: det3, adjugate3, sym_part

contains

  pure real(dp) function det3(a)
    real(dp), intent(in) :: a(3, 3)
    det3 = a(1, 1) * (a(2, 2) * a(3, 3) - a(2, 3) * a(3, 2)) - a(1, 2) * (a(2, 1) * a(3, 3) - a(2, 3) * a(3, 1)) + &
      a(1, 3) * (a(2, 1) * a(3, 2) - a(2, 2) * a(3, 1))
  end function det3

  !> adj(A), the transpose of A's cofactor matrix.
  pure function adjugate3(a) result(c)
    real(dp), intent(in) :: a(3, 3)
    real(dp) :: c(3, 3)
    c(1, 1) = a(2, 2) * a(3, 3) - a(2, 3) * a(3, 2)
    c(1, 2) = a(1, 3) * a(3, 2) - a(1, 2) * a(3, 3)
    c(1, 3) = a(1, 2) * a(2, 3) - a(1, 3) * a(2, 2)
    c(2, 1) = a(2, 3) * a(3, 1) - a(2, 1) * a(3, 3)
    c(2, 2) = a(1, 1) * a(3, 3) - a(1, 3) * a(3, 1)
    c(2, 3) = a(1, 3) * a(2, 1) - a(1, 1) * a(2, 3)
    c(3, 1) = a(2, 1) * a(3, 2) - a(2, 2) * a(3, 1)
    c(3, 2) = a(1, 2) * a(3, 1) - a(1, 1) * a(3, 2)
    c(3, 3) = a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)
  end function adjugate3

  !> a = ½(a + a') in place (the same arithmetic on both halves: the result is exactly symmetric).
  pure subroutine sym_part(a)
    real(dp), intent(inout) :: a(:, :)
    real(dp) :: t
    integer :: i, j
    do j = 1, size(a, 2)
      do i = 1, j
        t = 0.5_dp * (a(i, j) + a(j, i))
        a(i, j) = t
        a(j, i) = t
      end do
    end do
  end subroutine sym_part
end module small_matrix
