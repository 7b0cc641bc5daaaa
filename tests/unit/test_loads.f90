!> loads' side_forces, the consistent nodal forces of PRESSURE and TRACTION on an element side,
!> against closed forms: a straight 2-node side (p L t / 2 on each end along -n), a straight
!> 3-node side (1/6, 2/3, 1/6 of the total), a curved 3-node side (the pressure's total is -p t
!> times the chord's normal, exactly, whatever the curvature; its moment about the middle node
!> vanishes for a symmetric arc), a traction on a straight side (t L (tx, ty), same shares).
program test_loads
  use kinds, only: dp
  use testing, only: check, check_close, test_summary
  use loads, only: side_forces, side_pressure_stiffness, face_forces
  implicit none
  real(dp) :: x(2, 3), f(2, 3), t, p, l, c, s, n(2), x3(3, 4), f3(3, 8), va(3)
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
  call test_follower_stiffness()
  call test_closed_contour()
  ! 3D faces (face_forces): a warped 4-node face, counter-clockwise seen from outside. The pressure's
  ! total is -p times its vector area 1/2 (x3 - x1) x (x4 - x2), exactly; on a flat square each node
  ! takes a quarter; a triangle's nodes a third of -p A n + A t.
  x3 = reshape([0.0_dp, 0.0_dp, 0.0_dp, 2.0_dp, 0.1_dp, 0.3_dp, 2.2_dp, 1.5_dp, -0.2_dp, -0.1_dp, 1.2_dp, 0.1_dp], [3, 4])
  call face_forces(4, x3, p, [0.0_dp, 0.0_dp, 0.0_dp], f3)
  va = 0.5_dp * cross(x3(:, 3) - x3(:, 1), x3(:, 4) - x3(:, 2))
  do i = 1, 3
    call check_close(sum(f3(i, :)), -p * va(i), 1e-13_dp, 'pressure, warped 4-node face: total = -p x vector area')
  end do
  x3 = reshape([0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp], [3, 4])
  call face_forces(4, x3, p, [1.0_dp, 2.0_dp, 3.0_dp], f3)
  call check(all(abs(f3(:, 2) - [0.25_dp, 0.5_dp, 0.75_dp - 0.25_dp * p]) <= 1e-12_dp * p), &
    'flat unit square: a quarter of -p n + t on each node')
  call face_forces(3, x3, p, [0.0_dp, 0.0_dp, 3.0_dp], f3)
  call check(all(abs(f3(:, 1:3) - spread([0.0_dp, 0.0_dp, (3.0_dp - p) / 6.0_dp], 2, 3)) <= 1e-12_dp * p), &
    'triangle: a third of (-p n + t) A on each node')
  call test_summary('test_loads')

contains

  pure function cross(u, v) result(w)
    real(dp), intent(in) :: u(3), v(3)
    real(dp) :: w(3)
    w = [u(2) * v(3) - u(3) * v(2), u(3) * v(1) - u(1) * v(3), u(1) * v(2) - u(2) * v(1)]
  end function cross


  !> side_pressure_stiffness is -sym(∂f/∂x) of side_forces: f is linear in the nodes, so a central
  !> difference is exact to round-off; on a curved 3-node side and a straight 2-node one.
  subroutine test_follower_stiffness()
    real(dp) :: x0(2, 3), xp(2, 3), xm(2, 3), fp(2, 3), fm(2, 3), d(6, 6), ke(6, 6), pr, scale
    integer :: m, a, b, nsn
    character(len=40) :: tag
    pr = 3.0e5_dp
    x0 = reshape([0.0_dp, 0.0_dp, 0.52_dp, 0.31_dp, 1.0_dp, 0.2_dp], [2, 3])
    do nsn = 2, 3
      if (nsn == 2) x0(:, 2) = x0(:, 3)
      do b = 1, 2 * nsn
        xp = x0
        xm = x0
        xp(2 - mod(b, 2), (b + 1) / 2) = xp(2 - mod(b, 2), (b + 1) / 2) + 1.0e-3_dp
        xm(2 - mod(b, 2), (b + 1) / 2) = xm(2 - mod(b, 2), (b + 1) / 2) - 1.0e-3_dp
        call side_forces(nsn, xp, 1.0_dp, pr, [0.0_dp, 0.0_dp], fp)
        call side_forces(nsn, xm, 1.0_dp, pr, [0.0_dp, 0.0_dp], fm)
        do a = 1, 2 * nsn
          d(a, b) = (fp(2 - mod(a, 2), (a + 1) / 2) - fm(2 - mod(a, 2), (a + 1) / 2)) / 2.0e-3_dp
        end do
      end do
      call side_pressure_stiffness(nsn, pr, ke)
      m = 2 * nsn
      scale = maxval(abs(d(1:m, 1:m)))
      write (tag, '(i0,a)') nsn, '-node side'
      call check(maxval(abs(ke(1:m, 1:m) + 0.5_dp * (d(1:m, 1:m) + transpose(d(1:m, 1:m))))) <= 1e-12_dp * scale, &
        'follower pressure stiffness = -sym(df/dx), ' // trim(tag))
      call check(maxval(abs(ke(1:m, 1:m) - transpose(ke(1:m, 1:m)))) == 0.0_dp, 'follower stiffness symmetric, ' // trim(tag))
    end do
  end subroutine test_follower_stiffness

  !> A closed contour (a quadrilateral, counter-clockwise, 2-node sides): the pressure has the
  !> potential P A (A the shoelace area), so f = -P grad A, the assembled derivative is symmetric
  !> (the sides' skew ends cancel) and the assembled ke is P times the Hessian of A.
  subroutine test_closed_contour()
    real(dp) :: xq(2, 4), f(2, 4), fs(2, 3), ke(6, 6), k(8, 8), h(8, 8), x(2, 3), pr, ga, xp(2, 4), xm(2, 4)
    integer :: s, i, j, a, b, nd(2)
    pr = 2.0e5_dp
    xq = reshape([0.0_dp, 0.0_dp, 1.1_dp, 0.1_dp, 0.9_dp, 0.8_dp, -0.2_dp, 0.7_dp], [2, 4])
    f = 0.0_dp
    k = 0.0_dp
    do s = 1, 4
      nd = [s, mod(s, 4) + 1]
      x = 0.0_dp
      x(:, 1:2) = xq(:, nd)
      call side_forces(2, x, 1.0_dp, pr, [0.0_dp, 0.0_dp], fs)
      call side_pressure_stiffness(2, pr, ke)
      do i = 1, 2
        f(:, nd(i)) = f(:, nd(i)) + fs(:, i)
        do j = 1, 2
          k(2 * nd(i) - 1:2 * nd(i), 2 * nd(j) - 1:2 * nd(j)) = k(2 * nd(i) - 1:2 * nd(i), 2 * nd(j) - 1:2 * nd(j)) + &
            ke(2 * i - 1:2 * i, 2 * j - 1:2 * j)
        end do
      end do
    end do
    do b = 1, 8
      xp = xq
      xm = xq
      xp(2 - mod(b, 2), (b + 1) / 2) = xp(2 - mod(b, 2), (b + 1) / 2) + 1.0e-3_dp
      xm(2 - mod(b, 2), (b + 1) / 2) = xm(2 - mod(b, 2), (b + 1) / 2) - 1.0e-3_dp
      ga = (area(xp) - area(xm)) / 2.0e-3_dp                   ! exact: A is quadratic
      call check_close(f(2 - mod(b, 2), (b + 1) / 2), -pr * ga, 1e-12_dp, 'closed contour: f = -P grad A', &
        atol=1e-12_dp * pr)
      do a = 1, 8
        h(a, b) = (dga(xp, a) - dga(xm, a)) / 2.0e-3_dp
      end do
    end do
    call check(maxval(abs(k - pr * h)) <= 1e-9_dp * pr, 'closed contour: assembled ke = P x Hessian of A')
  end subroutine test_closed_contour

  pure real(dp) function area(xq)
    real(dp), intent(in) :: xq(2, 4)
    integer :: i
    area = 0.0_dp
    do i = 1, 4
      area = area + 0.5_dp * (xq(1, i) * xq(2, mod(i, 4) + 1) - xq(1, mod(i, 4) + 1) * xq(2, i))
    end do
  end function area

  !> ∂A/∂(component a) by a central difference (exact: A is quadratic).
  pure real(dp) function dga(xq, a)
    real(dp), intent(in) :: xq(2, 4)
    integer, intent(in) :: a
    real(dp) :: xp(2, 4), xm(2, 4)
    xp = xq
    xm = xq
    xp(2 - mod(a, 2), (a + 1) / 2) = xp(2 - mod(a, 2), (a + 1) / 2) + 1.0e-3_dp
    xm(2 - mod(a, 2), (a + 1) / 2) = xm(2 - mod(a, 2), (a + 1) / 2) - 1.0e-3_dp
    dga = (area(xp) - area(xm)) / 2.0e-3_dp
  end function dga
end program test_loads
