!> loads' side_forces, the consistent nodal forces of PRESSURE and TRACTION on an element side,
!> against closed forms: a straight 2-node side (p L t / 2 on each end along -n), a straight
!> 3-node side (1/6, 2/3, 1/6 of the total), a curved 3-node side (the pressure's total is -p t
!> times the chord's normal, exactly, whatever the curvature; its moment about the middle node
!> vanishes for a symmetric arc), a traction on a straight side (t L (tx, ty), same shares).
program test_loads
  use kinds, only: dp
  use testing, only: check, check_close, test_summary
  use loads, only: side_forces
  implicit none
  real(dp) :: x(2, 3), f(2, 3), t, p, l, c, s, n(2)
  integer :: i

  t = 0.1_dp
  p = 2.0e6_dp
  ! A straight 2-node side from (0, 0) to (3, 4) (L = 5): outward normal on the right of the
  ! direction, (4, -3)/5; the pressure pushes along -n.
  x = 0.0_dp
  x(:, 2) = [3.0_dp, 4.0_dp]
  call side_forces(2, x, t, p, [0.0_dp, 0.0_dp], f)
  n = [0.8_dp, -0.6_dp]
  do i = 1, 2
    call check_close(f(1, i), -p * 5.0_dp * t / 2 * n(1), 1e-14_dp, 'pressure, 2-node side: x force on each end')
    call check_close(f(2, i), -p * 5.0_dp * t / 2 * n(2), 1e-14_dp, 'pressure, 2-node side: y force on each end')
  end do
  ! The same side with its mid-side node: 1/6, 2/3, 1/6.
  x(:, 3) = x(:, 2)
  x(:, 2) = 0.5_dp * x(:, 3)
  call side_forces(3, x, t, p, [0.0_dp, 0.0_dp], f)
  call check_close(f(1, 1), -p * 5.0_dp * t / 6 * n(1), 1e-14_dp, 'pressure, 3-node side: end share 1/6')
  call check_close(f(2, 2), -p * 5.0_dp * t * 2 / 3 * n(2), 1e-14_dp, 'pressure, 3-node side: middle share 2/3')
  call check_close(f(2, 3), -p * 5.0_dp * t / 6 * n(2), 1e-14_dp, 'pressure, 3-node side: other end 1/6')
  ! A curved 3-node side: a circular arc of radius 1 from angle -60 to 60 deg about the origin,
  ! run so that the outward normal (right of the direction) points away from the centre.
  c = cos(acos(-1.0_dp) / 3)
  s = sin(acos(-1.0_dp) / 3)
  x(:, 1) = [c, -s]
  x(:, 2) = [1.0_dp, 0.0_dp]
  x(:, 3) = [c, s]
  call side_forces(3, x, t, p, [0.0_dp, 0.0_dp], f)
  ! chord (0, 2 s): its right normal (2 s, 0); the total is -p t (2 s, 0)
  call check_close(sum(f(1, :)), -p * t * 2 * s, 1e-14_dp, 'pressure, curved side: total x = -p t chord normal')
  call check(abs(sum(f(2, :))) <= 1e-9_dp * p * t, 'pressure, curved side: total y = 0 (symmetric arc)')
  call check(abs(f(2, 1) + f(2, 3)) <= 1e-9_dp * p * t .and. abs(f(1, 1) - f(1, 3)) <= 1e-9_dp * p * t, &
    'pressure, curved side: symmetric end forces')
  ! A traction (tx, ty) on the straight 2-node side: t L (tx, ty) / 2 on each end, whatever the
  ! side's direction; and the 3-node side's shares.
  x = 0.0_dp
  x(:, 2) = [3.0_dp, 4.0_dp]
  call side_forces(2, x, t, 0.0_dp, [1.0e5_dp, -2.0e5_dp], f)
  call check_close(f(1, 1), 5.0_dp * t * 1.0e5_dp / 2, 1e-14_dp, 'traction, 2-node side: x share')
  call check_close(f(2, 2), -5.0_dp * t * 2.0e5_dp / 2, 1e-14_dp, 'traction, 2-node side: y share')
  x(:, 3) = x(:, 2)
  x(:, 2) = 0.5_dp * x(:, 3)
  call side_forces(3, x, t, 0.0_dp, [1.0e5_dp, -2.0e5_dp], f)
  call check_close(f(1, 2), 5.0_dp * t * 1.0e5_dp * 2 / 3, 1e-14_dp, 'traction, 3-node side: middle share')
  call check_close(sum(f(2, :)), -5.0_dp * t * 2.0e5_dp, 1e-14_dp, 'traction, 3-node side: total')
  call test_summary('test_loads')
end program test_loads
