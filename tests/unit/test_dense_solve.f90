!> dense_solve: spring-mass chain eigenvalues against the closed form, eigenvector
!> M-orthonormality, SPD and symmetric indefinite solves against known solutions; the pure
!> kernels spsd_solve (rank, dropped rows, tolerance, degenerate input) and gen_solve.
program test_dense_solve
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT
  use testing, only: check, check_close, test_summary
  use dense_solve, only: generalized_eigen, spd_solve, sym_solve, spsd_solve, gen_solve, PIVOT_RTOL
  implicit none

  call test_chain(12, 1000.0_dp, 2.5_dp)
  call test_chain(24, 3.0e7_dp, 7.8e-3_dp)
  call test_eigen_errors()
  call test_spd()
  call test_sym()
  call test_spsd_full()
  call test_spsd_dependent()
  call test_spsd_rtol()
  call test_spsd_degenerate()
  call test_gen()
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
  !> SPD, full rank, diagonal spread over 3 decades so that the pivoting permutes: A = D C D with
  !> C = I + 0.3 S (S symmetric, |S| <= 1/n: C within [0.7, 1.3] by Gershgorin), cond(A) ~ 1e6.
  !> Backward stability of Cholesky: |A x - b| <~ c n eps |A| |x| componentwise, so the residual
  !> is compared with |A| |x| (that bound), 1e-13 being ~ 40 n eps for n = 12.
  subroutine test_spsd_full()
    integer, parameter :: n = 12
    real(dp) :: a(n, n), d(n), xt(n), b(n), x(n)
    logical :: dropped(n)
    integer :: i, j, rank
    do i = 1, n
      d(i) = 10.0_dp**(1.5_dp * cos(real(7 * i, dp)))
      xt(i) = sin(real(5 * i, dp)) + 0.2_dp
    end do
    do j = 1, n
      do i = 1, n
        a(i, j) = d(i) * d(j) * (merge(1.0_dp, 0.0_dp, i == j) + 0.3_dp / n * cos(real(i * j + i + j, dp)))
      end do
    end do
    b = matmul(a, xt)
    call spsd_solve(a, b, x, rank, dropped)
    call check(rank == n .and. .not. any(dropped), 'spsd_solve: SPD matrix has full rank')
    call check(maxval(abs(matmul(a, x) - b)) <= 1.0e-13_dp * maxval(matmul(abs(a), abs(x))), &
               'spsd_solve: SPD relative residual <= 1e-13')
    ! Well-conditioned variant (D = I): the residual also bounds the error, relative to |x| ~ 1.
    a = identity(n)
    do j = 1, n
      do i = 1, n
        a(i, j) = a(i, j) + 0.3_dp / n * cos(real(i * j + i + j, dp))
      end do
    end do
    b = matmul(a, xt)
    call spsd_solve(a, b, x, rank)
    call check(rank == n .and. maxval(abs(x - xt)) <= 1.0e-13_dp * maxval(abs(xt)), &
               'spsd_solve: well-conditioned SPD recovers the known solution')
  end subroutine test_spsd_full

  !> A = G G' (n = 8) with G's rows h1, h2, h3, h1 + h2, h4, h5, h6, h3 for h1..h6 independent
  !> (H = 2 I + 0.3 S, nonsingular by diagonal dominance): rank 6, row 4 = row 1 + row 2 and
  !> row 8 = row 3 of A (up to the rounding of G G', a few ulps). A maximal independent subset
  !> keeps all of rows 5-7 and drops exactly one of {3, 8} and one of {1, 2, 4}. b = A xt is in
  !> the range, so the returned x (0 on dropped rows) solves the full system; the residual is
  !> compared with |A| |x| (backward error of the kept block plus the ulp-level inconsistency).
  subroutine test_spsd_dependent()
    integer, parameter :: n = 8, k = 6
    real(dp) :: h(k, k), g(n, k), a(n, n), xt(n), b(n), x(n), scale
    logical :: dropped(n)
    integer :: i, j, rank
    do j = 1, k
      do i = 1, k
        h(i, j) = 0.3_dp / k * sin(real(3 * i + 7 * j, dp))
      end do
      h(j, j) = h(j, j) + 2.0_dp
    end do
    g(1:3, :) = h(1:3, :)
    g(4, :) = h(1, :) + h(2, :)
    g(5:7, :) = h(4:6, :)
    g(8, :) = h(3, :)
    a = matmul(g, transpose(g))
    do i = 1, n
      xt(i) = cos(real(2 * i, dp))
    end do
    b = matmul(a, xt)
    call spsd_solve(a, b, x, rank, dropped)
    call check(rank == k .and. count(dropped) == n - k, 'spsd_solve: dependent rows give rank 6 of 8')
    call check(count(dropped([3, 8])) == 1, 'spsd_solve: one of a duplicated pair is dropped')
    call check(count(dropped([1, 2, 4])) == 1, 'spsd_solve: one of rows 1, 2, 1+2 is dropped')
    call check(.not. any(dropped(5:7)), 'spsd_solve: independent rows are kept')
    call check(all(pack(x, dropped) == 0.0_dp), 'spsd_solve: dropped unknowns are zero')
    scale = maxval(matmul(abs(a), abs(x)) + matmul(abs(a), abs(xt)))
    call check(maxval(abs(matmul(a, x) - b)) <= 1.0e-13_dp * scale, &
               'spsd_solve: consistent semidefinite system solved (relative residual <= 1e-13)')
    ! Without dropped: same rank and solution.
    block
      real(dp) :: x2(n)
      integer :: rank2
      call spsd_solve(a, b, x2, rank2)
      call check(rank2 == rank .and. all(x2 == x), 'spsd_solve: dropped is optional')
    end block
  end subroutine test_spsd_dependent

  !> diag(1, 1e-6, 1e-14): the default rtol (1e-12) drops the 1e-14 pivot only, rtol = 1e-5 also
  !> the 1e-6 one, rtol = 0 none; a pivot exactly equal to rtol * max(diag) is dropped (<=).
  !> x_i = b_i / d_i through sqrt(d_i) twice: a few ulps.
  subroutine test_spsd_rtol()
    real(dp) :: a(3, 3), b(3), x(3), a2(2, 2), x2(2)
    logical :: dropped(3), dr2(2)
    integer :: rank
    real(dp), parameter :: e = 4 * epsilon(1.0_dp)
    a = 0.0_dp
    a(1, 1) = 1.0_dp
    a(2, 2) = 1.0e-6_dp
    a(3, 3) = 1.0e-14_dp
    b = [2.0_dp, 3.0e-6_dp, 5.0e-14_dp]
    call spsd_solve(a, b, x, rank, dropped)
    call check(PIVOT_RTOL == 1.0e-12_dp .and. rank == 2 .and. all(dropped .eqv. [.false., .false., .true.]), &
               'spsd_solve: default rtol drops a pivot 1e-14 below the largest')
    call check(abs(x(1) - 2.0_dp) <= e * 2.0_dp .and. abs(x(2) - 3.0_dp) <= e * 3.0_dp .and. x(3) == 0.0_dp, &
               'spsd_solve: kept block solved exactly, dropped unknown 0')
    call spsd_solve(a, b, x, rank, dropped, rtol=1.0e-5_dp)
    call check(rank == 1 .and. all(dropped .eqv. [.false., .true., .true.]) .and. abs(x(1) - 2.0_dp) <= e * 2.0_dp &
               .and. all(x(2:3) == 0.0_dp), 'spsd_solve: rtol = 1e-5 also drops the 1e-6 pivot')
    call spsd_solve(a, b, x, rank, dropped, rtol=0.0_dp)
    call check(rank == 3 .and. .not. any(dropped) .and. maxval(abs(x - [2.0_dp, 3.0_dp, 5.0_dp])) <= e * 5.0_dp, &
               'spsd_solve: rtol = 0 keeps every positive pivot')
    call spsd_solve(a, b, x, rank, dropped, rtol=-1.0_dp)
    call check(rank == 3, 'spsd_solve: negative rtol acts as 0')
    a2 = reshape([0.5_dp, 0.0_dp, 0.0_dp, 1.0_dp], [2, 2])     ! pivots 1 then 0.5 (permuted)
    call spsd_solve(a2, [1.0_dp, 1.0_dp], x2, rank, dr2, rtol=0.5_dp)
    call check(rank == 1 .and. all(dr2 .eqv. [.true., .false.]) .and. all(x2 == [0.0_dp, 1.0_dp]), &
               'spsd_solve: pivot equal to rtol * max(diag) is dropped; pivoting picks the largest first')
    call spsd_solve(a2, [1.0_dp, 1.0_dp], x2, rank, dr2, rtol=0.25_dp)
    call check(rank == 2 .and. .not. any(dr2) .and. maxval(abs(x2 - [2.0_dp, 1.0_dp])) <= e * 2.0_dp, &
               'spsd_solve: pivot above rtol * max(diag) is kept')
  end subroutine test_spsd_rtol

  !> n = 0, zero matrix, non-positive diagonal, NaN and Inf entries: rank 0, x = 0, all dropped.
  subroutine test_spsd_degenerate()
    real(dp) :: a0(0, 0), b0(0), x0(0), a(3, 3), x(3), nan, inf
    logical :: d0(0), dropped(3)
    integer :: rank
    nan = ieee_value(1.0_dp, ieee_quiet_nan)
    inf = ieee_value(1.0_dp, ieee_positive_inf)
    rank = -1
    call spsd_solve(a0, b0, x0, rank, d0)
    call check(rank == 0, 'spsd_solve: n = 0 gives rank 0')
    a = 0.0_dp
    call spsd_solve(a, [1.0_dp, 2.0_dp, 3.0_dp], x, rank, dropped)
    call check(rank == 0 .and. all(x == 0.0_dp) .and. all(dropped), 'spsd_solve: zero matrix has rank 0')
    a = -identity(3)
    call spsd_solve(a, [1.0_dp, 2.0_dp, 3.0_dp], x, rank, dropped)
    call check(rank == 0 .and. all(x == 0.0_dp) .and. all(dropped), 'spsd_solve: negative diagonal has rank 0')
    a = identity(3)
    a(2, 3) = nan
    a(3, 2) = nan
    call spsd_solve(a, [1.0_dp, 2.0_dp, 3.0_dp], x, rank, dropped)
    call check(rank == 0 .and. all(x == 0.0_dp) .and. all(dropped), 'spsd_solve: NaN off the diagonal gives rank 0')
    a = identity(3)
    a(1, 1) = nan
    call spsd_solve(a, [1.0_dp, 2.0_dp, 3.0_dp], x, rank, dropped)
    call check(rank == 0 .and. all(x == 0.0_dp) .and. all(dropped), 'spsd_solve: NaN on the diagonal gives rank 0')
    a = identity(3)
    a(2, 2) = inf
    call spsd_solve(a, [1.0_dp, 2.0_dp, 3.0_dp], x, rank, dropped)
    call check(rank == 0 .and. all(x == 0.0_dp) .and. all(dropped), 'spsd_solve: Inf entry gives rank 0')
    call spsd_solve(identity(3), [1.0_dp, 2.0_dp], x, rank, dropped)
    call check(rank == 0 .and. all(x == 0.0_dp), 'spsd_solve: size mismatch gives rank 0')
  end subroutine test_spsd_degenerate

  !> gen_solve: a nonsymmetric 3x3 with a zero (1,1) entry (needs a row swap), det = -5, integer
  !> solution, error a few ulps; a diagonally dominant nonsymmetric 10x10 (cond <~ 3) with known
  !> x to 1e-13; exactly and numerically singular matrices, NaN, n = 0.
  subroutine test_gen()
    integer, parameter :: n = 10
    real(dp) :: a3(3, 3), x3(3), a(n, n), xt(n), x(n), nan, c
    real(dp) :: s3(3, 3), a0(0, 0), x0(0), b0(0)
    logical :: ok
    integer :: i, j
    a3 = transpose(reshape([0.0_dp, 2.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 0.0_dp, 3.0_dp, 0.0_dp, 1.0_dp], [3, 3]))
    call gen_solve(a3, [-1.0_dp, -1.0_dp, 6.0_dp], x3, ok)
    call check(ok .and. maxval(abs(x3 - [1.0_dp, -2.0_dp, 3.0_dp])) <= 16 * epsilon(1.0_dp), &
               'gen_solve: nonsymmetric 3x3 needing a row swap, known solution')
    do j = 1, n
      do i = 1, n
        a(i, j) = 0.5_dp / n * sin(real(2 * i + 3 * j * j, dp))   ! |row sum| <= 0.5, nonsymmetric
      end do
      a(j, j) = a(j, j) + 1.0_dp
      xt(j) = real(j, dp) - 4.5_dp
    end do
    call gen_solve(a, matmul(a, xt), x, ok)
    call check(ok .and. maxval(abs(x - xt)) <= 1.0e-13_dp * maxval(abs(xt)), &
               'gen_solve: diagonally dominant nonsymmetric 10x10, known solution')
    call gen_solve(reshape([1.0_dp, 2.0_dp, 2.0_dp, 4.0_dp], [2, 2]), [1.0_dp, 1.0_dp], x3(1:2), ok)
    call check(.not. ok .and. all(x3(1:2) == 0.0_dp), 'gen_solve: exactly singular matrix is reported')
    c = 0.1_dp                                   ! row 3 = row 1 + row 2, not exact in binary
    s3(1, :) = [c, 0.7_dp, 0.3_dp]
    s3(2, :) = [0.9_dp, c / 3, 1.3_dp]
    s3(3, :) = s3(1, :) + s3(2, :)
    call gen_solve(s3, [1.0_dp, 2.0_dp, 3.0_dp], x3, ok)
    call check(.not. ok, 'gen_solve: numerically singular matrix (pivot <= eps max|a|) is reported')
    nan = ieee_value(1.0_dp, ieee_quiet_nan)
    a3(2, 2) = nan
    call gen_solve(a3, [1.0_dp, 2.0_dp, 3.0_dp], x3, ok)
    call check(.not. ok, 'gen_solve: NaN entry is reported')
    call gen_solve(a0, b0, x0, ok)
    call check(ok, 'gen_solve: n = 0 is ok')
  end subroutine test_gen
end program test_dense_solve
