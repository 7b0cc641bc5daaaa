!> Kernels of the sweep metrics against closed forms: apexes of exact parabolas (free flight),
!> linear interpolation, impacts from contact events, errors.
program test_sweep_metrics
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
  use kinds, only: dp
  use testing, only: check, check_close, test_summary
  use sweep_metrics, only: find_apexes, interp_at, contact_periods, metric_error, nan_value
  implicit none
  integer, parameter :: NS = 4001
  real(dp), parameter :: G = 9.81_dp, H = 1.0_dp
  real(dp) :: t(NS), y(NS), tap(3), yap(3), tf, tau, v
  real(dp) :: ts(8), te(8), yl(3)
  integer :: k, n, nest(8)
  logical :: est(8)

  ! A ball bouncing elastically from H: y = H - g/2 (tau - tf)², tau = t mod 2 tf, apexes at
  ! t = (2j - 1) tf... shifted: it starts at the ground going up (tau = 0), apex at tf, 3 tf, ...
  ! The grid step is not aligned with tf, so every apex falls between samples; the parabola
  ! through three samples of an exact parabola gives the apex exactly (to round-off).
  tf = sqrt(2.0_dp * H / G)
  do k = 1, NS
    t(k) = (k - 1) * 1.37e-3_dp
    tau = modulo(t(k), 2.0_dp * tf)
    y(k) = H - 0.5_dp * G * (tau - tf)**2
  end do
  call find_apexes(t, y, tap, yap, n)
  call check(n == 3, 'apex: three apexes found', 'found ' // char(48 + n))
  do k = 1, 3
    call check_close(yap(k), H, 1.0e-13_dp, 'apex height = H for an exact parabola, apex ' // char(48 + k))
    call check_close(tap(k), (2 * k - 1) * tf, 1.0e-11_dp, 'apex time = (2k-1) t_f, apex ' // char(48 + k))
  end do
  ! The refinement matters: the highest sample alone misses H by up to g h²/8.
  call check(H - maxval(y(1:1000)) > 1.0e-7_dp, 'apex: the highest sample is below H (the refinement is needed)')
  ! Fewer apexes than asked (t <= 0.96 s holds the first only): the rest are NaN.
  call find_apexes(t(1:700), y(1:700), tap, yap, n)
  call check(n == 1 .and. ieee_is_nan(yap(2)) .and. ieee_is_nan(yap(3)), 'apex: missing apexes are NaN')
  ! A constant signal has no strict maximum.
  yl = 2.0_dp
  call find_apexes([0.0_dp, 1.0_dp, 2.0_dp], yl, tap(1:1), yap(1:1), n)
  call check(n == 0, 'apex: a plateau is not an apex')

  ! Linear interpolation is exact on a straight line, NaN outside the samples.
  v = interp_at([0.0_dp, 0.5_dp, 2.0_dp], [1.0_dp, 2.0_dp, 5.0_dp], 1.25_dp)
  call check_close(v, 3.5_dp, 1.0e-15_dp, 'interp: y = 1 + 2t at t = 1.25')
  v = interp_at([0.0_dp, 0.5_dp, 2.0_dp], [1.0_dp, 2.0_dp, 5.0_dp], 0.5_dp)
  call check(v == 2.0_dp, 'interp: at a sample, the sample itself')
  call check(ieee_is_nan(interp_at([0.0_dp, 1.0_dp], [0.0_dp, 1.0_dp], 1.5_dp)), 'interp: NaN beyond the last sample')

  ! Impacts: two conditions touch at t = 1 and leave at 1.5 and 1.6, one touches again at 1.62
  ! (within the gap 0.05: same impact), a second impact 5 -> 5.1, a third from 7 never ends.
  est = [.true., .true., .false., .false., .true., .false., .true., .false.]
  call contact_periods([1.0_dp, 1.0_dp, 1.5_dp, 1.6_dp, 1.62_dp, 1.63_dp, 5.0_dp, 5.1_dp], est, 0.05_dp, ts, te, nest, n)
  call check(n == 2, 'impacts: chatter within the gap joins the first impact')
  call check(ts(1) == 1.0_dp .and. te(1) == 1.63_dp .and. nest(1) == 3, 'impacts: first impact 1 -> 1.63, 3 onsets')
  call check_close(te(2) - ts(2), 0.1_dp, 1.0e-14_dp, 'impacts: second impact lasts 0.1')
  call check(nest(2) == 1, 'impacts: second impact has 1 onset')
  call contact_periods([1.0_dp, 1.5_dp, 1.52_dp, 1.53_dp, 7.0_dp], [.true., .false., .true., .false., .true.], 0.01_dp, &
                       ts, te, nest, n)
  call check(n == 3 .and. ieee_is_nan(te(3)), 'impacts: a gap above GAP separates impacts; an unfinished one has no end')
  call contact_periods([1.0_dp], [.false.], 0.01_dp, ts, te, nest, n)
  call check(n == 0, 'impacts: a release without contact is ignored')

  ! Errors.
  call check_close(metric_error(1.1_dp, 1.0_dp, 0.0_dp), 0.1_dp, 1.0e-14_dp, 'error: relative to |reference|')
  call check_close(metric_error(1.1_dp, -1.0_dp, 0.0_dp), 2.1_dp, 1.0e-14_dp, 'error: relative to |negative reference|')
  call check_close(metric_error(0.3_dp, 0.1_dp, 2.0_dp), 0.1_dp, 1.0e-14_dp, 'error: over SCALE when given')
  call check(metric_error(-3.0e-13_dp, 0.0_dp, 0.0_dp) == 3.0e-13_dp, 'error: absolute when the reference is 0')
  call check(ieee_is_nan(metric_error(nan_value(), 1.0_dp, 0.0_dp)), 'error: NaN for a missing value')
  call test_summary('sweep_metrics')
end program test_sweep_metrics
