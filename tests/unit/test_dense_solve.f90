!> dense_solve: spring-mass chain eigenvalues against the closed form, eigenvector
!> M-orthonormality, SPD and symmetric indefinite solves against known solutions.
program test_dense_solve
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT
  use testing, only: check, check_close, test_summary
  use dense_solve, only: generalized_eigen, spd_solve, sym_solve
  implicit none

  call test_chain(12, 1000.0_dp, 2.5_dp)
  call test_chain(24, 3.0e7_dp, 7.8e-3_dp)
  call test_eigen_errors()
  call test_spd()
  call test_sym()
  call test_summary('dense_solve')

contains

  !> n equal masses m, n equal springs k, fixed at one end and free at the other:
  !> omega_j^2 = 4 k/m sin^2((2j-1) pi / (2(2n+1))). dsygvd's absolute error is ~ eps * 4 k/m;
  !> relative to the smallest eigenvalue ~ k/m (pi/(2n+1))^2 that is ~ eps (2n+1)^2/pi^2,
  !> i.e. ~1e-13 for n = 24 (the largest size used), within the 1e-12 tolerance.
  subroutine test_chain(n, k, m)
    integer, intent(in) :: n
    real(dp), intent(in) :: k, m
    real(dp), allocatable :: kk(:, :), mm(:, :), w(:), vecs(:, :), w2(:), r(:)
    real(dp) :: pi, expected
    integer :: i, j, stat
    character(len=:), allocatable :: errmsg
    character(len=8) :: tag

    write (tag, '(i0)') n
    pi = acos(-1.0_dp)
    allocate (kk(n, n), mm(n, n), w(n), w2(n), r(n))
    kk = 0.0_dp
    mm = 0.0_dp
    do i = 1, n
      kk(i, i) = 2.0_dp * k
      mm(i, i) = m
      if (i < n) then
        kk(i, i + 1) = -k
        kk(i + 1, i) = -k
      end if
    end do
    kk(n, n) = k                       ! free end: only one spring on the last mass
    call generalized_eigen(kk, mm, w, vecs, stat, errmsg)
    call check(stat == STAT_OK, 'chain eigenproblem solves, n=' // trim(tag))
    do j = 1, n
      expected = 4.0_dp * k / m * sin((2 * j - 1) * pi / (2.0_dp * (2 * n + 1)))**2
      call check_close(w(j), expected, 1.0e-12_dp, 'chain omega^2 closed form, n=' // trim(tag))
    end do
    ! M-orthonormal eigenvectors and K v = w M v; entries are O(1/sqrt(m)), tolerances ~ 1e3 eps.
    call check(maxval(abs(matmul(transpose(vecs), matmul(mm, vecs)) - identity(n))) <= 1.0e-12_dp, &
               'eigenvectors are M-orthonormal, n=' // trim(tag))
    do j = 1, n
      r = matmul(kk, vecs(:, j)) - w(j) * matmul(mm, vecs(:, j))
      call check(norm2(r) <= 1.0e-12_dp * w(n) * m * norm2(vecs(:, j)), 'eigenpair residual, n=' // trim(tag))
    end do
    ! Without vectors: same eigenvalues.
    call generalized_eigen(kk, mm, w2, stat=stat, errmsg=errmsg)
    call check(stat == STAT_OK .and. maxval(abs(w2 - w)) <= 1.0e-12_dp * w(n), &
               'eigenvalues without vectors agree, n=' // trim(tag))
  end subroutine test_chain

  pure function identity(n) result(a)
    integer, intent(in) :: n
    real(dp) :: a(n, n)
    integer :: i
    a = 0.0_dp
    do i = 1, n
      a(i, i) = 1.0_dp
    end do
  end function identity

  subroutine test_eigen_errors()
    real(dp) :: kk(2, 2), mm(2, 2), w(2), w3(3)
    integer :: stat
    character(len=:), allocatable :: errmsg
    kk = reshape([2.0_dp, -1.0_dp, -1.0_dp, 2.0_dp], [2, 2])
    mm = reshape([1.0_dp, 0.0_dp, 0.0_dp, -1.0_dp], [2, 2])
    call generalized_eigen(kk, mm, w, stat=stat, errmsg=errmsg)
    call check(stat == STAT_RUN, 'indefinite mass matrix is reported')
    mm = identity(2)
    call generalized_eigen(kk, mm, w3, stat=stat, errmsg=errmsg)
    call check(stat == STAT_INPUT, 'wrong eigenvalue array size is an input error')
  end subroutine test_eigen_errors

  !> A = B^T B + n I (SPD, cond <= ~ 1 + ||B||^2/n), known X; backward error ~ n eps cond.
  subroutine test_spd()
    integer, parameter :: n = 30, nrhs = 3
    real(dp) :: a(n, n), a0(n, n), bmat(n, n), x(n, nrhs), b(n, nrhs), b1(n)
    integer :: i, j, stat
    character(len=:), allocatable :: errmsg
    do j = 1, n
      do i = 1, n
        bmat(i, j) = sin(real(3 * i + 5 * j, dp))
      end do
      do i = 1, nrhs
        x(j, i) = cos(real(j * i, dp)) + 0.5_dp
      end do
    end do
    a0 = matmul(transpose(bmat), bmat) + n * identity(n)
    b = matmul(a0, x)
    a = a0
    call spd_solve(a, b, stat, errmsg)
    call check(stat == STAT_OK, 'spd_solve rank-2 succeeds')
    call check(maxval(abs(b - x)) <= 1.0e-12_dp * maxval(abs(x)), 'spd_solve rank-2 recovers the known solution')
    a = a0
    b1 = matmul(a0, x(:, 2))
    call spd_solve(a, b1, stat, errmsg)
    call check(stat == STAT_OK .and. maxval(abs(b1 - x(:, 2))) <= 1.0e-12_dp * maxval(abs(x)), &
               'spd_solve rank-1 recovers the known solution')
    a = a0
    a(n, n) = -1.0_dp
    b1 = 1.0_dp
    call spd_solve(a, b1, stat, errmsg)
    call check(stat == STAT_RUN, 'spd_solve reports a non-SPD matrix')
  end subroutine test_spd

  !> Symmetric indefinite (zero diagonal forces 2x2 pivots) with known solution.
  subroutine test_sym()
    integer, parameter :: n = 20
    real(dp) :: a(n, n), a0(n, n), x(n), b(n), xx(n, 2), bb(n, 2)
    integer :: i, stat
    character(len=:), allocatable :: errmsg
    a0 = 0.0_dp
    do i = 1, n - 1          ! tridiagonal with zero diagonal: eigenvalues 2 cos(j pi/(n+1)), n even -> nonsingular
      a0(i, i + 1) = 1.0_dp
      a0(i + 1, i) = 1.0_dp
    end do
    do i = 1, n
      x(i) = real(i, dp) - 0.3_dp * i**2 / n
    end do
    b = matmul(a0, x)
    a = a0
    call sym_solve(a, b, stat, errmsg)
    call check(stat == STAT_OK, 'sym_solve succeeds on an indefinite matrix')
    ! Smallest |eigenvalue| 2 sin(pi/(2(n+1))) ~ 0.15: cond ~ 14.
    call check(maxval(abs(b - x)) <= 1.0e-12_dp * maxval(abs(x)), 'sym_solve recovers the known solution')
    xx(:, 1) = x
    xx(:, 2) = -2.0_dp * x + 1.0_dp
    bb = matmul(a0, xx)
    a = a0
    call sym_solve(a, bb, stat, errmsg)
    call check(stat == STAT_OK .and. maxval(abs(bb - xx)) <= 1.0e-12_dp * maxval(abs(xx)), &
               'sym_solve rank-2 recovers the known solutions')
    a = 0.0_dp
    a(1, 1) = 1.0_dp
    b = 1.0_dp
    call sym_solve(a, b, stat, errmsg)
    call check(stat == STAT_RUN, 'sym_solve reports a singular matrix')
  end subroutine test_sym
end program test_dense_solve
