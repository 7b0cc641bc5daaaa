!> newmark's eq (3) and the energy accounts (energy_t): exact identities of the trapezoidal
!> rule, hand-computed balances, and Neumaier's compensated summation where naive summation
!> loses the small increments. All numbers in the hand checks are exact binary fractions, so
!> they are compared exactly unless stated otherwise.
program test_newmark
  use kinds, only: dp
  use newmark_scheme, only: velocity_eq3, momentum_eq2
  use energy, only: energy_t
  use testing, only: check, check_close, test_summary
  implicit none

  call test_eq3()
  call test_energy_by_hand()
  call test_neumaier()
  call test_sdof_energy()
  call test_momentum_eq2()
  call test_summary('newmark')

contains

  !> Eq (3) is exact for a constant acceleration a: du = v0 h + a h²/2 gives v1 = v0 + a h.
  !> Remark 1.1: a DOF that does not move over a step has its velocity reversed.
  subroutine test_eq3()
    real(dp), parameter :: h = 0.5_dp
    real(dp) :: v(3), v0(3), a(3), du(3)
    v0 = [1.0_dp, -2.0_dp, 0.25_dp]
    a = [4.0_dp, 8.0_dp, -3.0_dp]
    du = v0 * h + a * h**2 / 2.0_dp
    v = v0
    call velocity_eq3(h, du, v)
    call check(all(v == v0 + a * h), 'eq3: constant acceleration, v(n+1) = v(n) + a h exactly')
    v = v0
    call velocity_eq3(h, [0.0_dp, 0.0_dp, 0.0_dp], v)
    call check(all(v == -v0), 'eq3: du = 0 reverses the velocity (remark 1.1)')
    v = v0
    call velocity_eq3(h, v0 * h, v)
    call check(all(v == v0), 'eq3: uniform motion du = v h keeps v')
  end subroutine test_eq3

  !> balance = kinetic + internal - external - (kinetic + internal at t = 0), with known numbers.
  subroutine test_energy_by_hand()
    type(energy_t) :: en
    call en%start(2.0_dp, 3.0_dp)
    call check(en%balance() == 0.0_dp .and. en%initial == 5.0_dp .and. en%internal() == 3.0_dp, &
               'energy: start sets initial = kinetic + internal, balance 0')
    call check(en%relative_balance() == 0.0_dp, 'energy: relative balance 0 at start')
    call en%add_step(4.0_dp, 1.0_dp, 2.0_dp, 0.5_dp)
    ! kinetic 4, internal 3 + 1, external 2: 4 + 4 - 2 - 5 = 1.
    call check(en%kinetic == 4.0_dp .and. en%internal() == 4.0_dp .and. en%external() == 2.0_dp .and. &
               en%correction() == 0.5_dp, 'energy: step 1 accounts')
    call check(en%balance() == 1.0_dp, 'energy: step 1 balance = 4 + 4 - 2 - 5 = 1')
    call check(en%relative_balance() == 1.0_dp / 8.0_dp, 'energy: relative balance 1 / max(kin + int) = 1/8')
    call en%add_step(1.0_dp, -1.0_dp, 0.0_dp, 0.25_dp)
    ! kinetic 1, internal 3, external 2: 1 + 3 - 2 - 5 = -3; corrections are not subtracted.
    call check(en%balance() == -3.0_dp, 'energy: step 2 balance = -3 (corrections not subtracted)')
    call check(en%correction() == 0.75_dp, 'energy: corrections accumulate')
    call check(en%max_balance == 3.0_dp .and. en%max_scale == 8.0_dp .and. en%relative_balance() == 3.0_dp / 8.0_dp, &
               'energy: max |balance| 3 over max(kin + int) 8')
    call en%start(0.0_dp, 0.0_dp)
    call check(en%balance() == 0.0_dp .and. en%external() == 0.0_dp .and. en%correction() == 0.0_dp .and. &
               en%relative_balance() == 0.0_dp, 'energy: start resets the sums')
  end subroutine test_energy_by_hand

  !> 1 + 1000 x 1e-16: each 1e-16 is below half an ulp of 1 (1.1e-16), so naive summation stays
  !> at 1; the compensated sum is the double nearest 1 + 1e-13. And the classic
  !> 1 + 1e100 + 1 - 1e100 = 2, where naive and Kahan summation give 0.
  subroutine test_neumaier()
    type(energy_t) :: en
    real(dp) :: naive
    integer :: i
    call en%start(0.0_dp, 1.0_dp)
    naive = 1.0_dp
    do i = 1, 1000
      call en%add_step(0.0_dp, 1.0e-16_dp, 1.0e-16_dp, 1.0e-16_dp)
      naive = naive + 1.0e-16_dp
    end do
    call check(naive == 1.0_dp, 'neumaier: naive summation loses the increments (the test discriminates)')
    call check(en%internal() == 1.0_dp + 1.0e-13_dp, 'neumaier: internal 1 + 1000 x 1e-16 = 1 + 1e-13 to the last bit')
    call check_close(en%external(), 1.0e-13_dp, 1.0e-12_dp, 'neumaier: external 1000 x 1e-16')
    ! balance = (1 + 1e-13) - 1e-13 - 1: zero up to one rounding of the total (ulp(1) = 2.2e-16).
    call check(abs(en%balance()) <= epsilon(1.0_dp), 'neumaier: balance of equal internal and external works ~ 0')
    call en%start(0.0_dp, 1.0_dp)
    call en%add_step(0.0_dp, 1.0e100_dp, 0.0_dp, 0.0_dp)
    call en%add_step(0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp)
    call en%add_step(0.0_dp, -1.0e100_dp, 0.0_dp, 0.0_dp)
    call check(en%internal() == 2.0_dp, 'neumaier: 1 + 1e100 + 1 - 1e100 = 2')
  end subroutine test_neumaier

  !> One DOF m u'' + k u = 0 advanced with eq (7) and eq (3), accounted as newmark does: the
  !> trapezoidal rule conserves ½ m v² + ½ k u² exactly, so the balance is round-off only. Each
  !> step's roundings (the solve, eq (3), u + du) change the energy by a few eps x E, and they do not
  !> average out (the sequence is deterministic and periodic: measured 2.3e-13 E after 1000 steps,
  !> i.e. ~ N eps E); the bound is the worst-case linear growth 10 N eps E = 2.2e-12 E, still four
  !> orders of magnitude below an O(h) scheme error.
  subroutine test_sdof_energy()
    real(dp), parameter :: m = 2.0_dp, k = 8.0_dp, h = 0.3_dp
    type(energy_t) :: en
    integer, parameter :: nsteps = 1000
    real(dp) :: u, v(1), du(1), e0, tol
    integer :: n
    u = 0.1_dp
    v = 0.5_dp
    e0 = 0.5_dp * m * v(1)**2 + 0.5_dp * k * u**2
    call en%start(0.5_dp * m * v(1)**2, 0.5_dp * k * u**2)
    tol = 10 * nsteps * epsilon(1.0_dp)
    do n = 1, nsteps
      du = (-2.0_dp * k * u + 4.0_dp * m * v(1) / h) / (k + 4.0_dp * m / h**2)
      call velocity_eq3(h, du, v)
      call en%add_step(0.5_dp * m * v(1)**2, 0.5_dp * du(1) * k * (2.0_dp * u + du(1)), 0.0_dp, 0.0_dp)
      u = u + du(1)
    end do
    call check(en%relative_balance() <= tol, 'sdof: trapezoidal rule conserves energy over 1000 steps', &
               'max |balance| / E = ' // fmt(en%relative_balance()) // ' > ' // fmt(tol))
    call check_close(en%internal(), 0.5_dp * k * u**2, 0.0_dp, 'sdof: internal account = ½ k u²', tol * e0)
    call check_close(en%kinetic + en%internal(), e0, tol, 'sdof: total energy = initial')
  end subroutine test_sdof_energy

  !> Eq (2) times M, the step's momentum balance (momentum_eq2), against M v(n+1) of eq (3) on two
  !> masses (consistent mass) joined by a spring, pushed by a load on mass 1 for half the run: the
  !> two agree to the solve's rounding at every step, and without the load the total momentum is
  !> the load's impulse, the internal forces cancelling exactly.
  subroutine test_momentum_eq2()
    real(dp), parameter :: h = 1.0e-2_dp, k = 3.0e3_dp
    real(dp), parameter :: m(2, 2) = reshape([2.0_dp, 0.5_dp, 0.5_dp, 1.0_dp], [2, 2])
    real(dp), parameter :: kk(2, 2) = reshape([k, -k, -k, k], [2, 2])
    integer, parameter :: nsteps = 2000
    real(dp) :: u(2), v(2), p(2), du(2), s(2, 2), r(2), fn(2), f1(2), fint_n(2), fint(2), det, dev, impulse, pscale
    integer :: n
    u = [0.01_dp, -0.02_dp]
    v = [0.3_dp, -0.1_dp]
    p = matmul(m, v)
    fint_n = matmul(kk, u)
    fn = [5.0_dp, 0.0_dp]
    s = kk + 4.0_dp / h**2 * m
    det = s(1, 1) * s(2, 2) - s(1, 2) * s(2, 1)
    dev = 0.0_dp
    impulse = 0.0_dp
    pscale = 0.0_dp
    do n = 1, nsteps
      f1 = 0.0_dp
      if (n < nsteps / 2) f1(1) = 5.0_dp
      r = f1 + fn - 2.0_dp * fint_n + 4.0_dp / h * p
      du = [s(2, 2) * r(1) - s(1, 2) * r(2), s(1, 1) * r(2) - s(2, 1) * r(1)] / det
      call velocity_eq3(h, du, v)
      u = u + du
      fint = matmul(kk, u)
      call momentum_eq2(h, fn, f1, fint_n, fint, p)
      impulse = impulse + 0.5_dp * h * (fn(1) + f1(1))
      dev = max(dev, maxval(abs(p - matmul(m, v))))
      pscale = max(pscale, maxval(abs(p)))
      fint_n = fint
      fn = f1
    end do
    call check(dev <= 1.0e-12_dp * pscale, 'momentum_eq2: M v(n+1) of eq (3) to the solve''s rounding', &
      'max |p - M v| / max |p| = ' // fmt(dev / pscale))
    call check(dev > 0.0_dp, 'momentum_eq2: not the product itself (the comparison discriminates)')
    ! M v0 sums to 0.6; the load's impulse is h/2 (5 + 2 x 5 x 999) = 49.975.
    call check_close(impulse, 49.975_dp, 1.0e-12_dp, 'momentum_eq2: the load''s impulse as counted')
    call check_close(sum(p), 0.6_dp + 49.975_dp, 1.0e-14_dp, 'momentum_eq2: total momentum = initial + the load''s impulse')
  end subroutine test_momentum_eq2

  function fmt(x) result(s)
    real(dp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: buf
    write (buf, '(es10.3)') x
    s = trim(adjustl(buf))
  end function fmt
end program test_newmark
