!> Newmark's average-acceleration scheme (β = 1/4, γ = 1/2) as the named pure pieces of
!> method.md sections 1 and 2. Only u and v are state; a step solves eq (9)
!>     4M/h² du + Bσ(n+1) + Bσc = F(n+1) + F(n) - Bσ(n) + 4M v(n)/h
!> (eq (5) when σc = 0, eq (7) for linear elasticity) and sets the velocity by eq (3).
!> Each piece has a double-precision form and an extended one (SCHEME PRECISION EXTENDED:
!> the right-hand side, M v, M du, Bσ and the residual kept unrounded, with a = 2/h given
!> unrounded so that 4/h = 2a, 4/h² = a² and 2/h = a share one rounding).
module newmark_scheme
  use kinds, only: dp, qp
  implicit none
  private
  public :: velocity_eq3, rhs_eq9, residual_eq9, massless_rows_eq9, momentum_eq2

  interface velocity_eq3
    module procedure velocity_eq3_dp, velocity_eq3_qp
  end interface velocity_eq3

  interface rhs_eq9
    module procedure rhs_eq9_dp, rhs_eq9_qp
  end interface rhs_eq9

  interface massless_rows_eq9
    module procedure massless_rows_eq9_dp, massless_rows_eq9_qp
  end interface massless_rows_eq9

  interface residual_eq9
    module procedure residual_eq9_dp, residual_eq9_qp
  end interface residual_eq9

contains

  !> Eq (3): v(n+1) = 2 du / h - v(n).
  pure subroutine velocity_eq3_dp(h, du, v)
    real(dp), intent(in) :: h, du(:)
    real(dp), intent(inout) :: v(:)
    v = 2.0_dp * du / h - v
  end subroutine velocity_eq3_dp

  !> Eq (3) with a = 2/h unrounded: v(n+1) = a du - v(n).
  pure subroutine velocity_eq3_qp(a, du, v)
    real(qp), intent(in) :: a
    real(dp), intent(in) :: du(:)
    real(qp), intent(inout) :: v(:)
    v = a * real(du, qp) - v
  end subroutine velocity_eq3_qp

  !> The trapezoidal momentum balance the scheme is, M (v(n+1) - v(n)) = h/2 (F(n) + F(n+1) - Bσ(n)
  !> - Bσ(n+1)) (eq 2 with the average-acceleration rule), giving M v(n+1) without a product by M.
  !> It equals M v(n+1) of eq (3) up to h/2 times the solve's residual, the same rounding the
  !> energy balance already carries as ½ du'(S du - r); used on linear steps without contact, whose
  !> equation (9) is S du = r with nothing added (newmark's prepare_run decides).
  pure subroutine momentum_eq2(h, f_n, f_np1, fint_n, fint, mv)
    real(dp), intent(in) :: h, f_n(:), f_np1(:), fint_n(:), fint(:)
    real(dp), intent(inout) :: mv(:)
    mv = mv + (0.5_dp * h) * ((f_n + f_np1) - (fint_n + fint))
  end subroutine momentum_eq2

  !> Right-hand side of eq (9): F(n+1) + F(n) - Bσ(n) + 4M v(n)/h, with the true Bσ(n) of the
  !> end of the last step: the previous step's Bσc is never carried over (method.md section 2).
  pure subroutine rhs_eq9_dp(h, f_np1, f_n, fint_n, mv, rhs)
    real(dp), intent(in) :: h, f_np1(:), f_n(:), fint_n(:), mv(:)
    real(dp), intent(out) :: rhs(:)
    rhs = f_np1 + f_n - fint_n + (4.0_dp / h) * mv
  end subroutine rhs_eq9_dp

  !> The same with a = 2/h, Bσ(n) and M v(n) unrounded.
  pure subroutine rhs_eq9_qp(a, f_np1, f_n, fint_n, mv, rhs)
    real(qp), intent(in) :: a, fint_n(:), mv(:)
    real(dp), intent(in) :: f_np1(:), f_n(:)
    real(qp), intent(out) :: rhs(:)
    rhs = real(f_np1, qp) + real(f_n, qp) - fint_n + 2.0_qp * a * mv
  end subroutine rhs_eq9_qp

  !> IMPACT MASSLESS: the rows eqs of the massless contact DOFs written as equilibrium at n+1,
  !> Bσ(n+1) + Bσc = F(n+1) + C'Λ (so Λ = R(n+1)): their right-hand side is F(n+1) alone. Their
  !> trapezoid form (9), F(n) + F(n+1) - Bσ(n) - Bσ(n+1) + C'Λ = 0 with M = 0, carries an
  !> imbalance at n over and flips it every step: the node zigzags (docs/contact.md).
  pure subroutine massless_rows_eq9_dp(eqs, f_np1, rhs)
    integer, intent(in) :: eqs(:)
    real(dp), intent(in) :: f_np1(:)
    real(dp), intent(inout) :: rhs(:)
    rhs(eqs) = f_np1(eqs)
  end subroutine massless_rows_eq9_dp

  pure subroutine massless_rows_eq9_qp(eqs, f_np1, rhs)
    integer, intent(in) :: eqs(:)
    real(dp), intent(in) :: f_np1(:)
    real(qp), intent(inout) :: rhs(:)
    rhs(eqs) = real(f_np1(eqs), qp)
  end subroutine massless_rows_eq9_qp

  !> Residual of eq (9) at the iterate du: r = rhs - 4M du/h² - Bσ(n+1) - Bσc, given mdu = M du
  !> (c4 = 4/h²); the residual of eq (5) when fcorr = Bσc = 0. Contact forces are not in it
  !> (the driver adds C'Λ to judge convergence).
  pure subroutine residual_eq9_dp(c4, rhs, mdu, fint, fcorr, r)
    real(dp), intent(in) :: c4, rhs(:), mdu(:), fint(:), fcorr(:)
    real(dp), intent(out) :: r(:)
    r = rhs - c4 * mdu - fint - fcorr
  end subroutine residual_eq9_dp

  !> The same unrounded, with a = 2/h (4/h² = a²).
  pure subroutine residual_eq9_qp(a, rhs, mdu, fint, fcorr, r)
    real(qp), intent(in) :: a, rhs(:), mdu(:), fint(:)
    real(dp), intent(in) :: fcorr(:)
    real(qp), intent(out) :: r(:)
    r = rhs - a**2 * mdu - fint - real(fcorr, qp)
  end subroutine residual_eq9_qp
end module newmark_scheme
