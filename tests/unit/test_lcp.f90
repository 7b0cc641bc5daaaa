!> lcp: pivoted Cholesky of semidefinite matrices, and the contact LCP
!> (lam >= 0, g = q + W lam >= 0, lam'g = 0) against a brute-force enumeration of the active
!> sets (the solution is unique for W SPD), warm starts, redundant, grazing and infeasible cases.
program test_lcp
  use kinds, only: dp
  use errors, only: STAT_OK
  use testing, only: check, check_close, test_summary
  use dense_solve, only: spd_solve, spsd_solve
  use lcp, only: lcp_solve
  implicit none
  integer, allocatable :: seed(:)
  integer :: ns

  call random_seed(size=ns)
  allocate (seed(ns))
  seed = 20240611
  call random_seed(put=seed)
  call test_spsd()
  call test_brute_force()
  call test_large_warm()
  call test_degenerate()
  call test_summary('lcp')

contains

  !> Random SPD matrix: R'R + n I (condition number ~ 10).
  function random_spd(n) result(a)
    integer, intent(in) :: n
    real(dp) :: a(n, n), r(n, n)
    integer :: i
    call random_number(r)
    r = r - 0.5_dp
    a = matmul(transpose(r), r)
    do i = 1, n
      a(i, i) = a(i, i) + 0.1_dp * n
    end do
  end function random_spd

  subroutine test_spsd()
    real(dp), allocatable :: a(:, :), b(:), x(:), c(:, :)
    logical, allocatable :: dropped(:)
    integer :: rank, n
    n = 10
    allocate (a(n, n))
    a = random_spd(n)
    allocate (b(n), x(n), dropped(n))
    call random_number(b)
    call spsd_solve(a, b, x, rank, dropped)
    ! cond ~ 10: a backward-stable Cholesky leaves a residual of a few ulps of |a||x|.
    call check(rank == n .and. .not. any(dropped), 'spsd_solve: SPD matrix has full rank')
    call check(maxval(abs(matmul(a, x) - b)) <= 1.0e-13_dp * maxval(abs(b)), 'spsd_solve: SPD residual <= 1e-13')
    ! Semidefinite: rows 3 and 7 duplicated (same constraint twice), consistent right-hand side.
    c = a
    c(7, :) = c(3, :)
    c(:, 7) = c(:, 3)
    b(7) = b(3)
    call spsd_solve(c, b, x, rank, dropped)
    call check(rank == n - 1 .and. count(dropped) == 1 .and. (dropped(3) .or. dropped(7)), &
      'spsd_solve: a duplicated row is detected and dropped')
    call check(maxval(abs(matmul(c, x) - b)) <= 1.0e-12_dp * maxval(abs(b)), &
      'spsd_solve: consistent semidefinite system solved')
    ! Zero matrix: rank 0, x = 0.
    c = 0.0_dp
    call spsd_solve(c, b, x, rank)
    call check(rank == 0 .and. all(x == 0.0_dp), 'spsd_solve: zero matrix has rank 0')
  end subroutine test_spsd

  !> The unique solution by enumeration of the 2^n active sets (LAPACK for each subsystem).
  subroutine brute_force(w, q, lam, nsol)
    real(dp), intent(in) :: w(:, :), q(:)
    real(dp), intent(out) :: lam(:)
    integer, intent(out) :: nsol
    integer :: n, mask, i, na, stat
    integer, allocatable :: ia(:)
    real(dp), allocatable :: a(:, :), x(:), g(:), l(:)
    character(len=:), allocatable :: errmsg
    logical :: act(size(q))
    n = size(q)
    nsol = 0
    lam = 0.0_dp
    allocate (l(n), g(n))
    do mask = 0, 2**n - 1
      do i = 1, n
        act(i) = btest(mask, i - 1)
      end do
      ia = pack([(i, i = 1, n)], act)
      na = size(ia)
      l = 0.0_dp
      if (na > 0) then
        a = w(ia, ia)
        x = -q(ia)
        call spd_solve(a, x, stat, errmsg)
        if (stat /= STAT_OK) cycle
        l(ia) = x
      end if
      g = q + matmul(w, l)
      if (all(l >= -1.0e-12_dp) .and. all(g >= -1.0e-12_dp .or. act)) then
        nsol = nsol + 1
        lam = l
      end if
    end do
  end subroutine brute_force

  subroutine test_brute_force()
    real(dp), allocatable :: w(:, :), q(:), lam(:), g(:), lref(:)
    logical, allocatable :: active(:)
    integer :: n, trial, iters, stat, nsol
    character(len=:), allocatable :: errmsg, tag
    logical :: ok_sign, ok_gap, ok_comp, ok_ref, ok_stat, ok_unique
    ok_sign = .true.; ok_gap = .true.; ok_comp = .true.; ok_ref = .true.; ok_stat = .true.; ok_unique = .true.
    do n = 1, 8
      do trial = 1, 25
        allocate (w(n, n), q(n), lam(n), g(n), active(n), lref(n))
        w = random_spd(n)
        call random_number(q)
        q = q - 0.6_dp                      ! a mix of open and violated free gaps
        active = .false.
        if (mod(trial, 2) == 0) call random_active(active)   ! arbitrary warm starts too
        call lcp_solve(w, q, 1.0e-14_dp, lam, g, active, iters, stat, errmsg)
        ok_stat = ok_stat .and. stat == STAT_OK
        ok_sign = ok_sign .and. all(lam >= 0.0_dp)
        ! Gaps of O(1) data: round-off of the active subsystem is a few 1e-16.
        ok_gap = ok_gap .and. all(g >= -1.0e-13_dp)
        ok_comp = ok_comp .and. abs(dot_product(lam, g)) <= 1.0e-13_dp
        call brute_force(w, q, lref, nsol)
        ok_unique = ok_unique .and. nsol == 1
        ! cond(W) ~ 10: both solutions agree to a few ulps of their size.
        ok_ref = ok_ref .and. maxval(abs(lam - lref)) <= 1.0e-12_dp * max(1.0_dp, maxval(abs(lref)))
        deallocate (w, q, lam, g, active, lref)
      end do
    end do
    tag = ' (n = 1..8, 25 random SPD problems each)'
    call check(ok_stat, 'LCP: solved' // tag)
    call check(ok_sign, 'LCP: lam >= 0' // tag)
    call check(ok_gap, 'LCP: g >= -1e-13' // tag)
    call check(ok_comp, 'LCP: |lam.g| <= 1e-13' // tag)
    call check(ok_unique, 'LCP: brute force finds exactly one solution' // tag)
    call check(ok_ref, 'LCP: lam equals the brute-force solution' // tag)
  end subroutine test_brute_force

  subroutine random_active(active)
    logical, intent(inout) :: active(:)
    real(dp) :: r(size(active))
    call random_number(r)
    active = r > 0.5_dp
  end subroutine random_active

  !> 200 conditions: cold start, then a warm start from the solution after a small change of q.
  subroutine test_large_warm()
    integer, parameter :: n = 200
    real(dp), allocatable :: w(:, :), q(:), lam(:), g(:), dq(:)
    logical :: active(n)
    integer :: iters, iters_warm, stat
    character(len=:), allocatable :: errmsg
    allocate (w(n, n), q(n), lam(n), g(n), dq(n))
    w = random_spd(n)
    call random_number(q)
    q = q - 0.5_dp
    active = .false.
    call lcp_solve(w, q, 1.0e-13_dp, lam, g, active, iters, stat, errmsg)
    call check(stat == STAT_OK, 'LCP n = 200: solved (' // itoa(iters) // ' pivots)')
    call check(all(lam >= 0.0_dp) .and. all(g >= -1.0e-12_dp) .and. abs(dot_product(lam, g)) <= 1.0e-11_dp, &
      'LCP n = 200: complementary solution')
    call random_number(dq)
    q = q + 1.0e-3_dp * (dq - 0.5_dp)
    call lcp_solve(w, q, 1.0e-13_dp, lam, g, active, iters_warm, stat, errmsg)
    call check(stat == STAT_OK .and. all(lam >= 0.0_dp) .and. all(g >= -1.0e-12_dp) .and. &
      abs(dot_product(lam, g)) <= 1.0e-11_dp, 'LCP n = 200: warm start from the previous set solves')
    call check(iters_warm <= iters, 'LCP n = 200: warm start needs no more pivots (' // itoa(iters_warm) // ' <= ' // &
      itoa(iters) // ')')
  end subroutine test_large_warm

  subroutine test_degenerate()
    real(dp) :: w(3, 3), q(3), lam(3), g(3), w2(2, 2), q2(2), lam2(2), g2(2)
    logical :: active(3), act2(2)
    integer :: iters, stat
    character(len=:), allocatable :: errmsg

    ! Two identical conditions (rows 1 and 2) plus an independent one: the pair behaves as one
    ! condition of multiplier -q1/w11 shared between the copies; the gaps are unique.
    w = reshape([2.0_dp, 2.0_dp, 0.5_dp, 2.0_dp, 2.0_dp, 0.5_dp, 0.5_dp, 0.5_dp, 3.0_dp], [3, 3])
    q = [-1.0_dp, -1.0_dp, 0.8_dp]
    active = .false.
    call lcp_solve(w, q, 1.0e-14_dp, lam, g, active, iters, stat, errmsg)
    call check(stat == STAT_OK, 'LCP duplicated condition: solved')
    call check_close(lam(1) + lam(2), 0.5_dp, 1.0e-15_dp, 'LCP duplicated condition: total multiplier -q/w')
    call check(all(lam >= 0.0_dp) .and. abs(g(1)) <= 1.0e-15_dp .and. abs(g(2)) <= 1.0e-15_dp, &
      'LCP duplicated condition: both gaps closed, multipliers >= 0')
    call check_close(g(3), 0.8_dp + 0.5_dp * 0.5_dp, 1.0e-15_dp, 'LCP duplicated condition: third gap')
    ! Same with a warm start holding both copies active (the dependent one must be dropped).
    active = [.true., .true., .false.]
    call lcp_solve(w, q, 1.0e-14_dp, lam, g, active, iters, stat, errmsg)
    call check(stat == STAT_OK .and. abs(lam(1) + lam(2) - 0.5_dp) <= 1.0e-15_dp .and. all(g >= -1.0e-15_dp), &
      'LCP duplicated condition, both active at start: solved')

    ! Grazing: a condition exactly at zero gap with nothing pushing it (q = 0, no coupling to the
    ! loaded one): lam = 0 and g = 0, whatever the warm start.
    w2 = reshape([1.0_dp, 0.0_dp, 0.0_dp, 4.0_dp], [2, 2])
    q2 = [0.0_dp, -2.0_dp]
    act2 = .false.
    call lcp_solve(w2, q2, 1.0e-14_dp, lam2, g2, act2, iters, stat, errmsg)
    call check(stat == STAT_OK .and. lam2(1) == 0.0_dp .and. g2(1) == 0.0_dp .and. lam2(2) == 0.5_dp .and. &
      g2(2) == 0.0_dp, 'LCP grazing condition (cold): lam = g = 0')
    act2 = .true.
    call lcp_solve(w2, q2, 1.0e-14_dp, lam2, g2, act2, iters, stat, errmsg)
    call check(stat == STAT_OK .and. lam2(1) == 0.0_dp .and. g2(1) == 0.0_dp .and. lam2(2) == 0.5_dp, &
      'LCP grazing condition (warm, active): lam = g = 0')

    ! Infeasible: g1 = -1 + l1 - l2, g2 = -1 - l1 + l2 (a point between two walls closer than its
    ! size): g1 + g2 = -2 for any lam. The failure is reported, not hidden.
    w2 = reshape([1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp], [2, 2])
    q2 = [-1.0_dp, -1.0_dp]
    act2 = .false.
    call lcp_solve(w2, q2, 1.0e-14_dp, lam2, g2, act2, iters, stat, errmsg)
    call check(stat /= STAT_OK, 'LCP infeasible: failure reported')
    if (stat /= STAT_OK) call check(index(errmsg, 'no complementary solution') > 0, 'LCP infeasible: message', errmsg)
  end subroutine test_degenerate

  function itoa(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(len=12) :: buf
    write (buf, '(i0)') i
    s = trim(buf)
  end function itoa
end program test_lcp
