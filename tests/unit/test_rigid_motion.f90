!> rigid_motion: the rigid motion an impact correction keeps, and the normal impulses that carry a
!> momentum, on small bodies of point masses whose answers are known in closed form:
!> - a row of masses on a wall of normal y: only the x translation is invariant;
!> - one mass on a wall: its rotation is dependent on its translations (dropped), x invariant;
!> - one condition at (x0, 0) of normal x on a ring of masses: the y translation and the rotation
!>   about the contact normal's line are invariant, and the projection keeps their momenta;
!> - node-to-node rows (all translations invariant): the whole rigid motion;
!> - normal_impulses reproduces a momentum of normal impulses, least-norm.
program test_rigid_motion
  use kinds, only: dp
  use testing, only: check, check_close, test_summary
  use rigid_motion, only: invariant_rigid_motion, normal_impulses
  implicit none

  call test_row_on_wall()
  call test_lone_mass()
  call test_one_contact_point()
  call test_pairs()
  call test_impulses()
  call test_summary('rigid_motion')

contains

  !> Bodies of unit point masses at p(2, n) (translations UX UY): g = T'MT, the modes' values at
  !> each node and P = T'M v for the velocity vel(2, n), over the modes tx, ty and r = (-y, x).
  subroutine modes_of(p, vel, g, pk, rmax)
    real(dp), intent(in) :: p(:, :), vel(:, :)
    real(dp), intent(out) :: g(3, 3), pk(3), rmax(3)
    real(dp) :: t(2, 3)
    integer :: i, k, l
    g = 0.0_dp
    pk = 0.0_dp
    rmax = 0.0_dp
    do i = 1, size(p, 2)
      t(:, 1) = [1.0_dp, 0.0_dp]
      t(:, 2) = [0.0_dp, 1.0_dp]
      t(:, 3) = [-p(2, i), p(1, i)]
      do k = 1, 3
        pk(k) = pk(k) + dot_product(t(:, k), vel(:, i))
        rmax(k) = max(rmax(k), maxval(abs(t(:, k))))
        do l = 1, 3
          g(k, l) = g(k, l) + dot_product(t(:, k), t(:, l))
        end do
      end do
    end do
  end subroutine modes_of

  !> e(j, k) = c_j't_k for a row of normal nrm on node i.
  function row_modes(p, i, nrm) result(e)
    real(dp), intent(in) :: p(:, :), nrm(2)
    integer, intent(in) :: i
    real(dp) :: e(3)
    e = [nrm(1), nrm(2), -p(2, i) * nrm(1) + p(1, i) * nrm(2)]
  end function row_modes

  subroutine test_row_on_wall()
    real(dp) :: p(2, 3), vel(2, 3), g(3, 3), pk(3), rmax(3), e(3, 3), a(3), tcm
    integer :: i
    p = reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 2.0_dp, 0.0_dp], [2, 3])
    vel = reshape([3.0_dp, -1.0_dp, 3.0_dp, -2.0_dp, 3.0_dp, 0.5_dp], [2, 3])
    call modes_of(p, vel, g, pk, rmax)
    do i = 1, 3
      e(i, :) = row_modes(p, i, [0.0_dp, 1.0_dp])
    end do
    call invariant_rigid_motion(g, pk, e, [1.0_dp, 1.0_dp, 1.0_dp], rmax, a, tcm)
    call check(abs(a(1) - 3.0_dp) <= 1.0e-14_dp .and. maxval(abs(a(2:3))) <= 1.0e-14_dp, &
      'row on a wall of normal y: v_r = the x translation (3 m/s)')
    call check_close(tcm, 0.5_dp * 3.0_dp * 9.0_dp, 1.0e-14_dp, 'row on a wall: T_r = 1/2 m vx^2')
  end subroutine test_row_on_wall

  subroutine test_lone_mass()
    real(dp) :: p(2, 1), vel(2, 1), g(3, 3), pk(3), rmax(3), e(1, 3), a(3), tcm, vr(2)
    p(:, 1) = [0.3_dp, 0.01_dp]
    vel(:, 1) = [1.7_dp, -1.0_dp]
    call modes_of(p, vel, g, pk, rmax)
    e(1, :) = row_modes(p, 1, [0.0_dp, 1.0_dp])
    call invariant_rigid_motion(g, pk, e, [1.0_dp], rmax, a, tcm)
    vr = [a(1) - a(3) * p(2, 1), a(2) + a(3) * p(1, 1)]
    call check(maxval(abs(vr - [1.7_dp, 0.0_dp])) <= 1.0e-13_dp, &
      'a lone mass on the ground: v_r = its tangential velocity (the rotation, dependent, dropped)')
    call check_close(tcm, 0.5_dp * 1.7_dp**2, 1.0e-13_dp, 'a lone mass: T_r = 1/2 m vx^2')
  end subroutine test_lone_mass

  !> Eight masses on a circle of radius 1, one condition of normal -x at (1, 0): invariant are the
  !> y translation and the rotation about the origin (the contact point moves along y); the x
  !> translation is not. v_r keeps P_y and L, and has no x velocity at the contact point.
  subroutine test_one_contact_point()
    real(dp) :: p(2, 8), vel(2, 8), g(3, 3), pk(3), rmax(3), e(1, 3), a(3), tcm, gr(3), pr(3)
    integer :: i, k
    do i = 1, 8
      p(:, i) = [cos((i - 1) * atan(1.0_dp)), sin((i - 1) * atan(1.0_dp))]
      vel(:, i) = [2.0_dp + 0.1_dp * i, 1.0_dp - 0.05_dp * i * i]
    end do
    call modes_of(p, vel, g, pk, rmax)
    e(1, :) = row_modes(p, 1, [-1.0_dp, 0.0_dp])
    call invariant_rigid_motion(g, pk, e, [1.0_dp], rmax, a, tcm)
    call check(abs(a(1)) <= 1.0e-14_dp, 'one contact point of normal x: no x translation in v_r')
    do k = 1, 3
      gr(k) = dot_product(g(k, :), a)                ! T'M v_r
    end do
    pr = pk - gr
    call check(abs(pr(2)) <= 1.0e-13_dp * abs(pk(2)) .and. abs(pr(3)) <= 1.0e-13_dp * maxval(abs(pk)), &
      'one contact point: v_r carries the y momentum and the angular momentum of v')
    call check_close(tcm, 0.5_dp * dot_product(a, gr), 1.0e-13_dp, 'one contact point: T_r = 1/2 a''G a')
  end subroutine test_one_contact_point

  !> Node-to-node rows (c_j't = 0 for the translations; along the line of their nodes: the
  !> rotation too): the whole rigid motion.
  subroutine test_pairs()
    real(dp) :: g(3, 3), pk(3), rmax(3), e(2, 3), a(3), tcm, x(3)
    g = reshape([4.0_dp, 0.0_dp, -1.0_dp, 0.0_dp, 4.0_dp, 2.0_dp, -1.0_dp, 2.0_dp, 6.0_dp], [3, 3])
    pk = [1.0_dp, -2.0_dp, 0.5_dp]
    rmax = [1.0_dp, 1.0_dp, 2.0_dp]
    e = 0.0_dp
    call invariant_rigid_motion(g, pk, e, [1.0_dp, 1.0_dp], rmax, a, tcm)
    x = solve3(g, pk)
    call check(maxval(abs(a - x)) <= 1.0e-13_dp * maxval(abs(x)), 'node-to-node rows: v_r = G^-1 P (every mode)')
    call check_close(tcm, 0.5_dp * dot_product(x, pk), 1.0e-13_dp, 'node-to-node rows: T_r = 1/2 P''G^-1 P')
  end subroutine test_pairs

  subroutine test_impulses()
    real(dp) :: e(3, 2), z(3), dm(2), zt(3), resid
    ! Three rows seeing two modes; the momentum of impulses zt is reproduced, with the least norm.
    e = reshape([1.0_dp, 1.0_dp, 1.0_dp, 0.0_dp, 1.0_dp, 2.0_dp], [3, 2])
    zt = [0.3_dp, -0.1_dp, 0.7_dp]
    dm = matmul(transpose(e), zt)
    call normal_impulses(e, dm, 2.0_dp, z, resid)
    call check(resid <= 1.0e-14_dp .and. maxval(abs(matmul(transpose(e), z) - dm)) <= 1.0e-14_dp, &
      'normal_impulses: the impulses carry the momentum')
    call check(dot_product(z, z) <= dot_product(zt, zt) + 1.0e-14_dp, 'normal_impulses: of least norm')
    call check(abs(dot_product(z, [1.0_dp, -2.0_dp, 1.0_dp])) <= 1.0e-14_dp, &
      'normal_impulses: no component in the null space of e''')
    ! A momentum no normal impulse can give (dm outside the range of e') is reported.
    e(:, 2) = 0.0_dp
    call normal_impulses(e, [1.0_dp, 1.0_dp], 2.0_dp, z, resid)
    call check(resid > 0.5_dp, 'normal_impulses: a momentum the rows cannot give is reported (residual)')
    ! Rows that see no mode beyond round-off (node-to-node between free bodies): no impulse.
    e = 1.0e-17_dp
    call normal_impulses(e, [1.0e-16_dp, 0.0_dp], 2.0_dp, z, resid)
    call check(all(z == 0.0_dp) .and. resid >= 1.0_dp, 'normal_impulses: round-off rows carry no impulse')
  end subroutine test_impulses

  function solve3(a, b) result(x)
    real(dp), intent(in) :: a(3, 3), b(3)
    real(dp) :: x(3), det
    det = a(1, 1) * (a(2, 2) * a(3, 3) - a(2, 3) * a(3, 2)) - a(1, 2) * (a(2, 1) * a(3, 3) - a(2, 3) * a(3, 1)) + &
      a(1, 3) * (a(2, 1) * a(3, 2) - a(2, 2) * a(3, 1))
    x(1) = (b(1) * (a(2, 2) * a(3, 3) - a(2, 3) * a(3, 2)) - a(1, 2) * (b(2) * a(3, 3) - a(2, 3) * b(3)) + &
      a(1, 3) * (b(2) * a(3, 2) - a(2, 2) * b(3))) / det
    x(2) = (a(1, 1) * (b(2) * a(3, 3) - a(2, 3) * b(3)) - b(1) * (a(2, 1) * a(3, 3) - a(2, 3) * a(3, 1)) + &
      a(1, 3) * (a(2, 1) * b(3) - b(2) * a(3, 1))) / det
    x(3) = (a(1, 1) * (a(2, 2) * b(3) - b(2) * a(3, 2)) - a(1, 2) * (a(2, 1) * b(3) - b(2) * a(3, 1)) + &
      b(1) * (a(2, 1) * a(3, 2) - a(2, 2) * a(3, 1))) / det
  end function solve3
end program test_rigid_motion
