!> Working precision and the few tolerances shared across rebond.
module kinds
  use, intrinsic :: iso_fortran_env, only: dp => real64, qp => real128
  implicit none
  private
  public :: dp, qp, zero_tol

  ! qp (quadruple precision) serves only SCHEME PRECISION EXTENDED: internal forces, residuals
  ! and energies of linear elastic models evaluated beyond double precision.

  !> Relative threshold under which a length, a Jacobian or a pivot counts as zero.
  real(dp), parameter :: zero_tol = 1.0e-12_dp
end module kinds
