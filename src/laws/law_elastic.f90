!> Linear elasticity: sigma = sigma_n + D deps. The path is straight in stress too, so the
!> path-mean stress is the chord midpoint whatever the number of sub-increments: the
!> correction stress sigma_c of eq (9) is exactly zero.
module law_elastic
  use kinds, only: dp
  implicit none
  private
  public :: elastic_update

contains

  pure subroutine elastic_update(d, deps, sig_n, sig, sigbar)
    real(dp), intent(in) :: d(:, :), deps(:), sig_n(:)
    real(dp), intent(out) :: sig(:), sigbar(:)
    sig = sig_n + matmul(d, deps)
    sigbar = 0.5_dp * (sig_n + sig)
  end subroutine elastic_update
end module law_elastic
