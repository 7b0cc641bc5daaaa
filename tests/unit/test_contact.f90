!> contact: the kernels of eqs (10)-(16) and PERSIST against closed forms and exact identities,
!> the hand check of method.md section 4 through the whole API, energy conservation of a
!> spring-mass chain bouncing on a wall (PAPER and PERSIST), the exact elastic collision of two
!> point masses, and W = C S⁻¹C' / the constrained update with a real CHOLMOD factor.
module test_contact_ops
  use kinds, only: dp
  use errors, only: STAT_OK
  use dense_solve, only: spd_solve
  use contact, only: inverse_op_t
  implicit none
  private
  public :: dense_inverse_t

  !> Test double of a factor: x = A⁻¹ b by LAPACK on a copy of the dense SPD matrix.
  type, extends(inverse_op_t) :: dense_inverse_t
    real(dp), allocatable :: a(:, :)
  contains
    procedure :: apply => dense_apply
  end type dense_inverse_t

contains

  subroutine dense_apply(self, b, x, stat, errmsg)
    class(dense_inverse_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: b(:)
    real(dp), intent(out), contiguous :: x(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), allocatable :: a(:, :)
    allocate (a, source=self%a)
    x = b
    call spd_solve(a, x, stat, errmsg)
  end subroutine dense_apply
end module test_contact_ops

program test_contact
  use kinds, only: dp
  use errors, only: STAT_OK
  use testing, only: check, check_close, test_summary
  use dense_solve, only: spd_solve
  use sparse_matrix, only: sym_csc_t, to_dense
  use spd_factor, only: spd_factor_t
  use inverse_ops, only: chol_ref_t
  use contact, only: contact_set_t, contact_event_t, contact_report_t, IMPACT_OFF, IMPACT_PAPER, IMPACT_PERSIST, &
    EVENT_ESTABLISH, EVENT_RELEASE, contact_add, contact_finalize, contact_set_mass, contact_prepare, &
    contact_solve_step, contact_end_step, contact_add_force, contact_gaps, contact_destroy, contact_w_matrix, &
    contact_am_block, SOLVER_AUTO, SOLVER_AUGMENTED, SOLVER_SCHUR, contact_events, hzero_reflection, multiplier_counters_t, &
    IMPACT_SYMMETRIC
  use impact_kernels, only: impact_energy_error, lambda_root, impulse_fixed_point, normal_multiplier, &
    hzero_reflection_dense, persist_projection_dense, persist_scale
  use test_contact_ops, only: dense_inverse_t
  use lcp, only: lcp_solve
  implicit none
  integer, allocatable :: seed(:)
  integer :: ns

  call random_seed(size=ns)
  allocate (seed(ns))
  seed = 314159
  call random_seed(put=seed)
  call test_energy_error()
  call test_lambda_root()
  call test_fixed_point()
  call test_reflection()
  call test_projection()
  call test_hzero_sparse()
  call test_hand_check(IMPACT_PAPER)
  call test_hand_check(IMPACT_PERSIST)
  call test_chain_single_step()
  call test_chain_run(IMPACT_PAPER, .true.)
  call test_chain_run(IMPACT_PERSIST, .true.)
  call test_chain_run(IMPACT_PAPER, .false.)
  call test_chain_run(IMPACT_PERSIST, .false.)
  call test_collision()
  call test_two_bodies_persist()
  call test_chain_symmetric()
  call test_cholmod()
  call test_local_rows()
  call test_column_cache()
  call test_summary('contact')

contains

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

  function itoa(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(len=12) :: buf
    write (buf, '(i0)') i
    s = trim(buf)
  end function itoa

  ! ---------------------------------------------------------------- kernels

  subroutine test_energy_error()
    call check_close(impact_energy_error(40.0_dp, 0.1_dp), 2.0_dp, 1.0e-15_dp, '(10) E = 1/2 40 0.1 = 2')
    call check(impact_energy_error(0.0_dp, 0.3_dp) == 0.0_dp, '(10) no multiplier, no energy error')
  end subroutine test_energy_error

  subroutine test_lambda_root()
    real(dp) :: a, b, e, y, yp, r(3)
    integer :: k
    logical :: ok_sign, ok_prod, ok_res
    ! Hand check: 800 y^2 - 2 = 0 -> y = -0.05 (sqrt(0.0025) is correctly rounded).
    call check_close(lambda_root(1600.0_dp, 0.0_dp, 2.0_dp), -0.05_dp, 1.0e-15_dp, '(13) hand check y = -0.05')
    ok_sign = .true.; ok_prod = .true.; ok_res = .true.
    do k = 1, 1000
      call random_number(r)
      a = 10.0_dp**(4 * r(1) - 2)
      b = (r(2) - 0.5_dp) * 10.0_dp**(4 * r(3) - 2)
      call random_number(e)
      y = lambda_root(a, b, e)
      yp = (-b + sqrt(b * b + 2 * a * e)) / a          ! the other root (naive is fine for a check)
      if (b > 0.0_dp) yp = -2.0_dp * e / (a * y)
      ok_sign = ok_sign .and. y < 0.0_dp .and. yp > 0.0_dp
      ok_prod = ok_prod .and. abs(y * yp + 2.0_dp * e / a) <= 1.0e-13_dp * 2.0_dp * e / a
      ok_res = ok_res .and. abs(0.5_dp * a * y * y + b * y - e) <= 1.0e-14_dp * (0.5_dp * a * y * y + abs(b * y) + e)
    end do
    call check(ok_sign, '(13) the roots have opposite signs and the chosen one is negative (1000 draws)')
    call check(ok_prod, '(13) product of the roots = -2e/a to 1e-13')
    call check(ok_res, '(13) residual <= 1e-14 of the terms')
    ! e -> 0: b < 0 gives y ~ -e/|b| (the naive formula would cancel to 0), b > 0 gives -2b/a.
    call check_close(lambda_root(2.0_dp, -3.0_dp, 1.0e-20_dp), -1.0e-20_dp / 3.0_dp, 1.0e-15_dp, &
      '(13) e -> 0 with b < 0: y = -e/|b|')
    call check_close(lambda_root(2.0_dp, 3.0_dp, 1.0e-20_dp), -3.0_dp - 1.0e-20_dp / 3.0_dp, 1.0e-15_dp, &
      '(13) e -> 0 with b > 0: y = -2b/a')
    call check(lambda_root(2.0_dp, -3.0_dp, 0.0_dp) == 0.0_dp, '(13) e = 0, b < 0: y = 0')
    call check_close(lambda_root(1.0_dp, 1.0e200_dp, 1.0_dp), -2.0e200_dp, 1.0e-15_dp, '(13) no overflow for huge b > 0')
    call check_close(lambda_root(1.0_dp, -1.0e200_dp, 1.0_dp), -1.0e-200_dp, 1.0e-15_dp, &
      '(13) no overflow for huge b < 0')
  end subroutine test_lambda_root

  !> (14): for n = 1..20 points with random SPD M, rows C, multipliers and velocities, the total
  !> kinetic energy added by Δv = M⁻¹ Σ y_j Λ_j c_j is Σ E_j, and every y_j <= 0.
  subroutine test_fixed_point()
    integer, parameter :: ndof = 30
    real(dp) :: m(ndof, ndof), v1(ndof), dv(ndof), mv(ndof)
    real(dp), allocatable :: c(:, :), mic(:, :), g(:, :), b(:), e(:), lam(:), y(:), a(:, :)
    integer :: n, j, k, iters, stat, maxit
    real(dp) :: change, sume, dt, t1, quad, res
    logical :: conv, ok_sum, ok_vec, ok_neg, ok_res
    integer :: nconv
    real(dp) :: maxrel, maxvec, scale
    character(len=:), allocatable :: errmsg
    nconv = 0; maxrel = 0.0_dp; maxvec = 0.0_dp; ok_sum = .true.; ok_vec = .true.; ok_neg = .true.; ok_res = .true.
    maxit = 0
    do n = 1, 20
      m = random_spd(ndof)
      allocate (c(n, ndof), lam(n), e(n), y(n), b(n))
      ! Sparse-ish rows: each condition on 2 DOFs (a node and its neighbour), overlapping.
      c = 0.0_dp
      do j = 1, n
        call random_number(c(j, j:j + 1))
        c(j, j:j + 1) = c(j, j:j + 1) - 0.5_dp
      end do
      call random_number(lam)
      lam = 1.0_dp + 10.0_dp * lam
      call random_number(e)
      call random_number(v1)
      v1 = v1 - 0.5_dp
      a = m
      mic = transpose(c)
      call spd_solve(a, mic, stat, errmsg)                 ! M⁻¹ C'
      g = matmul(c, mic)
      do k = 1, n
        do j = 1, n
          g(j, k) = g(j, k) * lam(j) * lam(k)
        end do
      end do
      b = lam * matmul(c, v1)
      call impulse_fixed_point(g, b, e, y, iters, change, conv, 1.0e-14_dp, 500)
      maxit = max(maxit, iters)
      if (conv) nconv = nconv + 1
      ok_neg = ok_neg .and. all(y <= 0.0_dp)
      sume = sum(e)
      quad = 0.5_dp * dot_product(y, matmul(g, y)) + dot_product(b, y)
      ! Round-off of the identity is relative to the size of its terms, |y|'|G||y|/2 + |b|'|y| + ΣE:
      ! near-parallel opposed rows give large impulses whose energies cancel (up to 5000 ΣE here).
      ok_sum = ok_sum .and. abs(quad - sume) <= 1.0e-13_dp * (0.5_dp * dot_product(abs(y), matmul(abs(g), abs(y))) + &
        dot_product(abs(b), abs(y)) + sume)
      maxrel = max(maxrel, abs(quad - sume) / sume)
      ! Each (14) holds to the fixed-point tolerance (relative to its largest term).
      do j = 1, merge(n, 0, conv)
        res = 0.5_dp * y(j) * dot_product(g(j, :), y) + b(j) * y(j) - e(j)
        ok_res = ok_res .and. abs(res) <= 1.0e-12_dp * (abs(0.5_dp * y(j) * dot_product(g(j, :), y)) + &
          abs(b(j) * y(j)) + e(j))
      end do
      ! The same with vectors: ΔT = ½(v1+Δv)'M(v1+Δv) - ½v1'Mv1 computed as v1'MΔv + ½Δv'MΔv.
      dv = matmul(mic, y * lam)
      mv = matmul(m, dv)
      dt = dot_product(v1, mv) + 0.5_dp * dot_product(dv, mv)
      t1 = 0.5_dp * dot_product(v1, matmul(m, v1))
      ! Its round-off is relative to the size of its terms (as for the summed identity above):
      ! |v1|'|M||Δv| + ½|Δv|'|M||Δv| + ΣE, at least the kinetic energy involved.
      scale = max(dot_product(abs(v1), matmul(abs(m), abs(dv))) + 0.5_dp * dot_product(abs(dv), &
        matmul(abs(m), abs(dv))) + sume, sume, t1)
      ok_vec = ok_vec .and. abs(dt - sume) <= 1.0e-13_dp * scale
      maxvec = max(maxvec, abs(dt - sume) / scale)
      deallocate (c, lam, e, y, b)
    end do
    ! Random C has strongly opposed rows: a few draws have no all-negative solution of (14).
    call check(nconv >= 15, '(14) fixed point converges for most random draws (' // itoa(nconv) // '/20, max ' // &
      itoa(maxit) // ' iterations)')
    call check(ok_neg, '(14) every y_j <= 0, converged or not')
    call check(ok_sum, '(14) summed: 1/2 y''Gy + b''y = sum E_j to 1e-13 of its terms (n = 1..20, converged or not)', &
      'max error relative to sum E: ' // rtoa(maxrel))
    call check(maxrel <= 1.0e-12_dp, '(14) summed: relative to sum E_j the error is <= 1e-12 (worst ' // &
      trim(adjustl(rtoa(maxrel))) // ')')
    call check(ok_res, '(14) each equation holds to 1e-12 of its terms when converged')
    call check(ok_vec, '(12)+(14) kinetic energy added by dv = sum E_j to 1e-13 of its terms (n = 1..20)', &
      'worst relative error ' // rtoa(maxvec))
    ! No all-negative solution (found by multistart Newton: the 7 real solutions all have a
    ! positive y_j): non-convergence is reported, the total energy is still exact, y <= 0.
    g = reshape([2.1971957196294598_dp, -1.7944955496505282_dp, -0.13246150530373049_dp, &
      -1.7944955496505282_dp, 1.6262018276212706_dp, -0.23816076008268211_dp, &
      -0.13246150530373046_dp, -0.23816076008268203_dp, 0.97617429664693800_dp], [3, 3])
    b = [1.1558201197982609_dp, -0.54529954643906065_dp, -0.53990898871581205_dp]
    e = [0.25634661158750305_dp, 0.21036945472215696_dp, 0.31291339682065167_dp]
    allocate (y(3))
    call impulse_fixed_point(g, b, e, y, iters, change, conv)
    quad = 0.5_dp * dot_product(y, matmul(g, y)) + dot_product(b, y)
    call check(.not. conv, '(14) no all-negative solution: non-convergence reported')
    call check(all(y <= 0.0_dp) .and. abs(quad - sum(e)) <= 1.0e-14_dp * sum(e), &
      '(14) no all-negative solution: y <= 0 and total energy exact')
    deallocate (y)
    ! Strongly coupled pair (two conditions on the same DOF, nearly parallel): still exact.
    g = reshape([1.0_dp, 0.99_dp, 0.99_dp, 1.0_dp], [2, 2])
    allocate (y(2))
    call impulse_fixed_point(g, [-0.3_dp, 0.2_dp], [1.0_dp, 2.0_dp], y, iters, change, conv)
    quad = 0.5_dp * dot_product(y, matmul(g, y)) + dot_product([-0.3_dp, 0.2_dp], y)
    call check(conv .and. abs(quad - 3.0_dp) <= 1.0e-14_dp * 3.0_dp, '(14) strongly coupled pair converges, sum exact (' &
      // itoa(iters) // ' iterations)')
  end subroutine test_fixed_point

  !> (16) with a consistent (full) mass: kinetic energy kept, normal velocities reversed,
  !> M-orthogonal tangential part kept, involution.
  subroutine test_reflection()
    integer, parameter :: n = 6, p = 2
    real(dp) :: m(n, n), amat(p, p), v(n), v0(n), av(p), vt0(n), vt(n)
    real(dp), allocatable :: a(:, :), minv_at(:, :), tmp(:, :)
    integer :: stat, rank
    character(len=:), allocatable :: errmsg
    real(dp) :: t0, t1
    m = random_spd(n)
    allocate (a(p, n))
    call random_number(a)
    a = a - 0.5_dp
    tmp = m
    minv_at = transpose(a)
    call spd_solve(tmp, minv_at, stat, errmsg)
    amat = matmul(a, minv_at)
    call random_number(v0)
    v0 = v0 - 0.5_dp
    v = v0
    av = matmul(a, v)
    call hzero_reflection_dense(minv_at, amat, av, v, rank)
    t0 = dot_product(v0, matmul(m, v0))
    t1 = dot_product(v, matmul(m, v))
    call check(rank == p, '(16) A M-1 A'' has full rank')
    call check_close(t1, t0, 1.0e-14_dp, '(16) v''Mv unchanged to 1e-14')
    call check(maxval(abs(matmul(a, v) + av)) <= 1.0e-14_dp * maxval(abs(av)) * 10, &
      '(16) normal velocities A v change sign')
    vt0 = v0
    call persist_projection_dense(minv_at, amat, matmul(a, v0), vt0)
    vt = v
    call persist_projection_dense(minv_at, amat, matmul(a, v), vt)
    call check(maxval(abs(vt - vt0)) <= 1.0e-14_dp * maxval(abs(v0)) * 10, '(16) M-orthogonal tangential part unchanged')
    call hzero_reflection_dense(minv_at, amat, matmul(a, v), v)
    call check(maxval(abs(v - v0)) <= 1.0e-14_dp * maxval(abs(v0)) * 10, '(16) reflecting twice is the identity')
    ! Lumped mass, one DOF: the local flip of the hand check.
    v(1:1) = [-2.0_dp]
    call hzero_reflection_dense(reshape([1.0_dp], [1, 1]), reshape([1.0_dp], [1, 1]), [-2.0_dp], v(1:1))
    call check(v(1) == 2.0_dp, '(16) one DOF: v = -2 is flipped to +2 exactly')
  end subroutine test_reflection

  !> The run's sparse (16), hzero_reflection, against the dense oracle: factor 2 (reflection)
  !> and factor 1 (PERSIST's projection), with a consistent and a lumped mass; mv stays M v.
  subroutine test_hzero_sparse()
    integer, parameter :: n = 6, p = 3
    real(dp) :: m(n, n), a(p, n), amat(p, p), v0(n), v(n), mv(n), vd(n), factor
    real(dp), allocatable :: minv_at(:, :), tmp(:, :)
    integer :: stat, rank, j, pass, f, k
    character(len=:), allocatable :: errmsg, tag
    character(len=16) :: buf
    do pass = 1, 2
      block
      type(contact_set_t) :: cs
      type(dense_inverse_t) :: mop
      m = random_spd(n)
      if (pass == 2) then                    ! lumped
        do j = 1, n
          m(:, j) = merge(m(j, j), 0.0_dp, [(k == j, k = 1, n)])
        end do
      end if
      tag = merge(' [consistent M]', ' [lumped M]    ', pass == 1)
      call random_number(a)
      a = a - 0.5_dp
      a(1, 1) = 0.0_dp                       ! sparse rows, one with a zero entry
      do j = 1, p
        call contact_add(cs, 1.0_dp, [(k, k = 1, n)], a(j, :))
      end do
      call contact_finalize(cs, n, 1.0_dp, stat, errmsg)
      if (pass == 1) then
        mop%a = m
        call contact_set_mass(cs, mop, stat, errmsg)
      else
        call contact_set_mass(cs, [(m(j, j), j = 1, n)], stat, errmsg)
      end if
      tmp = m
      minv_at = transpose(a)
      call spd_solve(tmp, minv_at, stat, errmsg)
      amat = matmul(a, minv_at)
      call random_number(v0)
      v0 = v0 - 0.5_dp
      do f = 1, 2
        factor = real(f, dp)
        v = v0
        mv = matmul(m, v0)
        call hzero_reflection(cs, [1, 2, 3], [factor, factor, factor], v, mv, rank, stat, errmsg)
        vd = v0
        if (f == 2) then
          call hzero_reflection_dense(minv_at, amat, matmul(a, v0), vd)
        else
          call persist_projection_dense(minv_at, amat, matmul(a, v0), vd)
        end if
        write (buf, '(es10.3)') maxval(abs(v - vd))
        call check(stat == STAT_OK .and. rank == p .and. maxval(abs(v - vd)) <= 1.0e-13_dp * maxval(abs(v0)), &
          '(16) sparse hzero_reflection = dense oracle, factor ' // itoa(f) // tag, 'max diff ' // buf)
        call check(maxval(abs(mv - matmul(m, v))) <= 1.0e-13_dp * maxval(abs(matmul(m, v0))), &
          '(16) sparse hzero_reflection keeps mv = M v, factor ' // itoa(f) // tag)
      end do
      call contact_destroy(cs)
      end block
    end do
  end subroutine test_hzero_sparse

  subroutine test_projection()
    integer, parameter :: n = 7, p = 3
    real(dp) :: m(n, n), amat(p, p), v(n), v0(n), mvp(n), vp(n)
    real(dp), allocatable :: a(:, :), minv_at(:, :), tmp(:, :)
    integer :: stat
    character(len=:), allocatable :: errmsg
    real(dp) :: t1, tp, tstar, s
    m = random_spd(n)
    allocate (a(p, n))
    call random_number(a)
    tmp = m
    minv_at = transpose(a)
    call spd_solve(tmp, minv_at, stat, errmsg)
    amat = matmul(a, minv_at)
    call random_number(v0)
    v = v0
    call persist_projection_dense(minv_at, amat, matmul(a, v0), v)
    call check(maxval(abs(matmul(a, v))) <= 1.0e-14_dp * maxval(abs(matmul(a, v0))) * 10, &
      'PERSIST projection: normal velocities zero')
    vp = v
    mvp = matmul(m, vp)
    t1 = 0.5_dp * dot_product(v0, matmul(m, v0))
    tp = 0.5_dp * dot_product(vp, mvp)
    call check(tp <= t1, 'PERSIST projection: kinetic energy does not grow')
    call check_close(t1 - tp, 0.5_dp * dot_product(v0 - vp, matmul(m, v0 - vp)), 1.0e-12_dp, &
      'PERSIST projection is M-orthogonal (Pythagoras)')
    tstar = t1 + 0.37_dp
    s = persist_scale(tstar, 0.0_dp, tp)
    call check_close(0.5_dp * dot_product(s * vp, matmul(m, s * vp)), tstar, 1.0e-14_dp, &
      'PERSIST scaling: kinetic energy = T* to 1e-14')
    call check(persist_scale(1.0_dp, 0.0_dp, 0.0_dp) == 0.0_dp, 'PERSIST scaling: no body energy -> 0 (fallback)')
  end subroutine test_projection

  ! ---------------------------------------------------------------- the API on dense systems

  !> One DOF, m = 1, k = 0, h = 0.1, v = -2, gap 0.1 (method.md section 4).
  subroutine test_hand_check(mode)
    integer, intent(in) :: mode
    type(contact_set_t) :: cs
    type(dense_inverse_t) :: sop, mop
    type(contact_event_t), allocatable :: ev(:)
    type(contact_report_t) :: rep
    real(dp) :: h, u(1), v(1), du(1), dufree(1), lam(1), mv(1), er
    integer :: stat
    character(len=:), allocatable :: errmsg, tag
    tag = merge(' [PAPER]  ', ' [PERSIST]', mode == IMPACT_PAPER)
    h = 0.1_dp
    call contact_add(cs, 0.1_dp, [1], [1.0_dp], [0, 1], 'node 1 on the wall')
    call contact_finalize(cs, 1, 1.0_dp, stat, errmsg)
    sop%a = reshape([4.0_dp / h**2], [1, 1])
    mop%a = reshape([1.0_dp], [1, 1])
    call contact_set_mass(cs, mop, stat, errmsg)
    call contact_prepare(cs, sop, stat, errmsg)
    call check(stat == STAT_OK, 'hand check: prepared' // tag)
    u = 0.0_dp
    v = -2.0_dp
    dufree = (4.0_dp / h) * v / (4.0_dp / h**2)          ! S du = 4 M v / h
    call contact_solve_step(cs, sop, u, dufree, du, lam, stat, errmsg)
    call check_close(lam(1), 40.0_dp, 1.0e-15_dp, 'hand check: Λ = 40' // tag)
    call check_close(du(1), -0.1_dp, 1.0e-15_dp, 'hand check: du = -gap' // tag)
    v = 2.0_dp * du / h - v                                ! eq (3)
    call check(abs(v(1)) <= 1.0e-14_dp, 'hand check: v(n+1) = 0 by (3)' // tag)
    mv = v
    call contact_end_step(cs, mode, u, du, v, mv, er, stat, errmsg, body=[1], report=rep)
    ev = contact_events(cs)
    call check(stat == STAT_OK, 'hand check: end of step' // tag)
    call check(size(ev) == 1, 'hand check: one event' // tag)
    if (size(ev) == 1) then
      call check(ev(1)%kind == EVENT_ESTABLISH .and. ev(1)%index == 1, 'hand check: establish event' // tag)
      call check_close(ev(1)%energy, 2.0_dp, 1.0e-15_dp, 'hand check: E = 2' // tag)
      call check_close(ev(1)%y, -0.05_dp, 1.0e-15_dp, 'hand check: y = -0.05' // tag)
      call check_close(ev(1)%reaction, 40.0_dp, 1.0e-15_dp, 'hand check: R(n+1) = Λ - 0' // tag)
    end if
    call check_close(v(1), 2.0_dp, 1.0e-15_dp, 'hand check: v = +2 after (16)' // tag)
    call check_close(er, 2.0_dp, 1.0e-15_dp, 'hand check: energy restored = 2' // tag)
    call check_close(mv(1), v(1), 1.0e-15_dp, 'hand check: mv kept equal to M v' // tag)
    if (mode == IMPACT_PERSIST) call check(rep%persist_fallbacks == 1, &
      'hand check: a lone point mass falls back to (13)-(16)' // tag)
    ! Next step: the point leaves, the condition is released (event, no energy, R = 0).
    u = u + du
    dufree = (4.0_dp / h) * v / (4.0_dp / h**2)
    call contact_solve_step(cs, sop, u, dufree, du, lam, stat, errmsg)
    call check(lam(1) == 0.0_dp .and. abs(du(1) - 0.2_dp) <= 1.0e-15_dp, 'hand check: next step free flight' // tag)
    v = 2.0_dp * du / h - v
    mv = v
    call contact_end_step(cs, mode, u, du, v, mv, er, stat, errmsg, body=[1])
    ev = contact_events(cs)
    call check(size(ev) == 1 .and. er == 0.0_dp .and. abs(v(1) - 2.0_dp) <= 1.0e-14_dp, &
      'hand check: release, nothing restored' // tag)
    if (size(ev) == 1) call check(ev(1)%kind == EVENT_RELEASE .and. ev(1)%reaction == 0.0_dp, &
      'hand check: release event with zero reaction' // tag)
    call contact_destroy(cs)
  end subroutine test_hand_check

  !> 3-DOF chain m1 - k - m2 - k - m3, m1 against a wall at gap g0, all moving at -1.
  subroutine chain(consistent, h, k, m, s, c0, g0)
    logical, intent(in) :: consistent
    real(dp), intent(in) :: h
    real(dp), intent(out) :: k(3, 3), m(3, 3), s(3, 3)
    real(dp), intent(out) :: c0(3), g0
    real(dp), parameter :: kk = 400.0_dp, ms(3) = [1.0_dp, 2.0_dp, 1.5_dp]
    integer :: i
    k = 0.0_dp
    k(1:2, 1:2) = k(1:2, 1:2) + kk * reshape([1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp], [2, 2])
    k(2:3, 2:3) = k(2:3, 2:3) + kk * reshape([1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp], [2, 2])
    m = 0.0_dp
    do i = 1, 3
      m(i, i) = ms(i)
    end do
    if (consistent) then                                   ! bar-like coupling, still SPD
      m(1, 2) = 0.2_dp; m(2, 1) = 0.2_dp
      m(2, 3) = 0.25_dp; m(3, 2) = 0.25_dp
    end if
    s = k + (4.0_dp / h**2) * m
    c0 = [1.0_dp, 0.0_dp, 0.0_dp]
    g0 = 0.05_dp
  end subroutine chain

  !> The chain's contact set: its left end against the wall at g0, S and the consistent M.
  subroutine chain_set(cs, sop, mop, s, m, g0)
    type(contact_set_t), intent(inout) :: cs
    type(dense_inverse_t), intent(inout) :: sop, mop
    real(dp), intent(in) :: s(3, 3), m(3, 3), g0
    integer :: stat
    character(len=:), allocatable :: errmsg
    call contact_add(cs, g0, [1], [1.0_dp], [0, 1], 'left end')
    call contact_finalize(cs, 3, 1.0_dp, stat, errmsg)
    sop%a = s
    mop%a = m
    call contact_set_mass(cs, mop, stat, errmsg)
    call contact_prepare(cs, sop, stat, errmsg)
    call check(stat == STAT_OK, 'chain: contact set prepared')
  end subroutine chain_set

  !> One step of the chain: the free increment S du = 4 M v / h - 2 K u, the contact solve, eq (3).
  subroutine chain_step(cs, sop, s, m, k, h, u, v, du, lam)
    type(contact_set_t), intent(inout) :: cs
    type(dense_inverse_t), intent(inout) :: sop
    real(dp), intent(in) :: s(3, 3), m(3, 3), k(3, 3), h, u(3)
    real(dp), intent(inout) :: v(3)
    real(dp), intent(out) :: du(3), lam(1)
    real(dp) :: a(3, 3), dufree(3)
    integer :: stat
    character(len=:), allocatable :: errmsg
    a = s
    dufree = matmul((4.0_dp / h) * m, v) - 2.0_dp * matmul(k, u)
    call spd_solve(a, dufree, stat, errmsg)
    call contact_solve_step(cs, sop, u, dufree, du, lam, stat, errmsg)
    v = 2.0_dp * du / h - v
  end subroutine chain_step

  !> One impact step of the chain: PAPER restores Σ E_j; PERSIST zeroes the normal velocity and
  !> brings the kinetic energy to T* = ½v1'Mv1 + E.
  subroutine test_chain_single_step()
    integer :: imode, mode
    type(contact_set_t) :: cs
    type(dense_inverse_t) :: sop, mop
    type(contact_event_t), allocatable :: ev(:)
    type(contact_report_t) :: rep
    real(dp) :: k(3, 3), m(3, 3), s(3, 3), c0(3), g0, h, u(3), v(3), du(3), lam(1), mv(3), er, t1
    integer :: stat, step
    character(len=:), allocatable :: errmsg, tag
    h = 0.02_dp
    call chain(.true., h, k, m, s, c0, g0)
    do imode = 1, 2
      mode = merge(IMPACT_PAPER, IMPACT_PERSIST, imode == 1)
      tag = merge(' [PAPER]  ', ' [PERSIST]', mode == IMPACT_PAPER)
      call chain_set(cs, sop, mop, s, m, g0)
      u = 0.0_dp
      v = -1.0_dp
      do step = 1, 10
        call chain_step(cs, sop, s, m, k, h, u, v, du, lam)
        mv = matmul(m, v)
        t1 = 0.5_dp * dot_product(v, mv)
        call contact_end_step(cs, mode, u, du, v, mv, er, stat, errmsg, body=[1, 1, 1], report=rep)
        ev = contact_events(cs)
        u = u + du
        if (rep%n_establish > 0) exit
      end do
      call check(rep%n_establish == 1 .and. stat == STAT_OK, 'chain: contact established in step ' // itoa(step) // tag)
      call check(rep%energy_error > 0.0_dp, 'chain: E > 0' // tag)
      call check_close(er, rep%energy_error, 1.0e-13_dp, 'chain: energy restored = E' // tag, atol=1.0e-13_dp * t1)
      call check_close(0.5_dp * dot_product(v, matmul(m, v)), t1 + rep%energy_error, 1.0e-14_dp, &
        'chain: kinetic energy after = T1 + E' // tag)
      call check(maxval(abs(mv - matmul(m, v))) <= 1.0e-13_dp * maxval(abs(mv)), 'chain: mv = M v kept' // tag)
      if (mode == IMPACT_PERSIST) then
        call check(abs(v(1)) <= 1.0e-14_dp * maxval(abs(v)), 'chain PERSIST: contact normal velocity zero')
        call check(rep%persist_fallbacks == 0 .and. rep%persist_groups == 1, 'chain PERSIST: body scaled, no fallback')
      else
        call check(v(1) > 0.0_dp, 'chain PAPER: the contact point leaves the wall after (16)')
      end if
      call contact_destroy(cs)
      cs = contact_set_t()
    end do
  end subroutine test_chain_single_step

  !> IMPACT SYMMETRIC on the chain (consistent coupling): at the establishment the contact point's
  !> normal velocity is stopped and the energy taken, ½ v1'M v1 - ½ v'M v, plus the step's loss E (10),
  !> is held (reported as held, impact_dissipated untouched); at the release it comes back whole as
  !> a repulsive impulse on the contact point (the kinetic energy rises by the held energy, -held);
  !> kinetic + strain + held is constant to round-off over the bounce.
  subroutine test_chain_symmetric()
    type(contact_set_t) :: cs
    type(dense_inverse_t) :: sop, mop
    type(contact_report_t) :: rep
    real(dp) :: k(3, 3), m(3, 3), s(3, 3), c0(3), g0, h, u(3), v(3), du(3), lam(1), mv(3), er
    real(dp) :: t1, held, e0, dev, vn, mvdev
    integer :: stat, step, nest, nrel
    character(len=:), allocatable :: errmsg
    h = 0.01_dp
    call chain(.true., h, k, m, s, c0, g0)
    call chain_set(cs, sop, mop, s, m, g0)
    u = 0.0_dp
    v = -1.0_dp
    e0 = 0.5_dp * dot_product(v, matmul(m, v))
    held = 0.0_dp
    dev = 0.0_dp
    mvdev = 0.0_dp
    nest = 0
    nrel = 0
    do step = 1, 400
      call chain_step(cs, sop, s, m, k, h, u, v, du, lam)
      mv = matmul(m, v)
      t1 = 0.5_dp * dot_product(v, mv)
      vn = v(1)
      call contact_end_step(cs, IMPACT_SYMMETRIC, u, du, v, mv, er, stat, errmsg, body=[1, 1, 1], report=rep)
      u = u + du
      if (rep%n_establish > 0) then
        nest = nest + 1
        call check(abs(v(1)) <= 1.0e-14_dp * maxval(abs(v)), 'chain SYMMETRIC: the contact point stopped')
        call check_close(rep%held, t1 - 0.5_dp * dot_product(v, mv) + rep%energy_error, 1.0e-13_dp, &
          'chain SYMMETRIC: held = kinetic energy taken + E (10)')
        call check(rep%impact_dissipated == 0.0_dp, 'chain SYMMETRIC: nothing dissipated at the establishment')
        call check(rep%held > rep%energy_error .and. rep%energy_error >= 0.0_dp, &
          'chain SYMMETRIC: the stop takes energy (and the step E >= 0)')
      end if
      if (rep%n_release > 0) then
        nrel = nrel + 1
        call check_close(0.5_dp * dot_product(v, mv) - t1, held, 1.0e-13_dp, &
          'chain SYMMETRIC: the release gives back what was held')
        call check_close(rep%held, -held, 1.0e-15_dp, 'chain SYMMETRIC: reported as -held')
        call check(rep%impact_dissipated == 0.0_dp, 'chain SYMMETRIC: nothing dissipated at the release')
        call check(v(1) > vn, 'chain SYMMETRIC: the impulse at the release pushes the point away')
      end if
      held = held + rep%held
      dev = max(dev, abs(0.5_dp * dot_product(v, matmul(m, v)) + 0.5_dp * dot_product(u, matmul(k, u)) + held - e0))
      mvdev = max(mvdev, maxval(abs(mv - matmul(m, v))) / max(maxval(abs(mv)), 1.0_dp))
    end do
    call check(mvdev <= 1.0e-13_dp, 'chain SYMMETRIC: mv = M v kept')
    call check(nest >= 1 .and. nrel == nest, 'chain SYMMETRIC: every contact established was released')
    call check(dev <= 1.0e-12_dp * e0, 'chain SYMMETRIC: kinetic + strain + held constant (1e-12)')
    call contact_destroy(cs)
  end subroutine test_chain_symmetric

  !> 400 steps of the chain bouncing on the wall: kinetic + strain energy is constant to
  !> round-off in PAPER and PERSIST (without correction it drops by Σ E_j), no penetration, and
  !> the chain leaves with a positive momentum.
  subroutine test_chain_run(mode, consistent)
    integer, intent(in) :: mode
    logical, intent(in) :: consistent
    type(contact_set_t) :: cs
    type(dense_inverse_t) :: sop, mop
    type(contact_event_t), allocatable :: ev(:)
    type(contact_report_t) :: rep
    real(dp) :: k(3, 3), m(3, 3), s(3, 3), c0(3), g0, h, u(3), v(3), du(3), dufree(3), lam(1), mv(3), er
    real(dp) :: e0, en, maxdev, ming, restored, eoff, g(1)
    real(dp), allocatable :: a(:, :)
    integer :: stat, step, nest, nrel, pass
    character(len=:), allocatable :: errmsg, tag
    logical :: ok
    h = 0.01_dp
    call chain(consistent, h, k, m, s, c0, g0)
    tag = merge(' [PAPER]  ', ' [PERSIST]', mode == IMPACT_PAPER) // merge(' consistent M', ' lumped M    ', consistent)
    eoff = 0.0_dp
    do pass = 1, 2                                         ! pass 2: IMPACT_OFF reference
      call contact_add(cs, g0, [1], [1.0_dp], [0, 1], 'left end')
      call contact_finalize(cs, 3, 1.0_dp, stat, errmsg)
      sop%a = s
      if (consistent) then
        mop%a = m
        call contact_set_mass(cs, mop, stat, errmsg)
      else
        call contact_set_mass(cs, [m(1, 1), m(2, 2), m(3, 3)], stat, errmsg)
      end if
      call contact_prepare(cs, sop, stat, errmsg)
      u = 0.0_dp
      v = -1.0_dp
      e0 = 0.5_dp * dot_product(v, matmul(m, v))
      maxdev = 0.0_dp
      ming = huge(1.0_dp)
      nest = 0
      nrel = 0
      restored = 0.0_dp
      ok = .true.
      do step = 1, 400
        a = s
        dufree = matmul((4.0_dp / h) * m, v) - 2.0_dp * matmul(k, u)
        call spd_solve(a, dufree, stat, errmsg)
        call contact_solve_step(cs, sop, u, dufree, du, lam, stat, errmsg)
        ok = ok .and. stat == STAT_OK
        v = 2.0_dp * du / h - v
        mv = matmul(m, v)
        call contact_end_step(cs, merge(mode, IMPACT_OFF, pass == 1), u, du, v, mv, er, stat, errmsg, &
          body=[1, 1, 1], report=rep)
        ev = contact_events(cs)
        ok = ok .and. stat == STAT_OK
        u = u + du
        nest = nest + rep%n_establish
        nrel = nrel + rep%n_release
        restored = restored + er
        call contact_gaps(cs, u, g)
        ming = min(ming, g(1))
        en = 0.5_dp * dot_product(v, matmul(m, v)) + 0.5_dp * dot_product(u, matmul(k, u))
        maxdev = max(maxdev, abs(en - e0))
      end do
      if (pass == 2) then
        eoff = en
        exit
      end if
      call check(ok, 'chain run: every step solved' // tag)
      call check(nest >= 1 .and. nrel >= 1, 'chain run: contacts established (' // itoa(nest) // ') and released (' // &
        itoa(nrel) // ')' // tag)
      ! Round-off of 400 steps of O(1) energies, plus maintained contacts closing to 1e-12.
      call check(maxdev <= 1.0e-12_dp * e0, 'chain run: total energy constant to 1e-12' // tag, 'max deviation ' // &
        trim(rtoa(maxdev)))
      call check(ming >= -1.0e-12_dp, 'chain run: no penetration' // tag)
      call check(dot_product(sum(m, 1), v) > 0.0_dp, 'chain run: the chain bounces back' // tag)
      call contact_destroy(cs)
      cs = contact_set_t()
    end do
    call check(e0 - eoff > 1.0e-3_dp * e0, 'chain run: IMPACT OFF loses energy at impacts (the error (10) is real)' // tag)
    call contact_destroy(cs)
  end subroutine test_chain_run

  function rtoa(x) result(s)
    real(dp), intent(in) :: x
    character(len=24) :: s
    write (s, '(es12.4)') x
  end function rtoa

  !> Node-to-node: masses 1 and 3 at +1 and -0.5 collide (g = g0 + u2 - u1). Momentum and energy
  !> conservation in 1D leave the elastic collision as the only outcome:
  !> v1' = ((m1-m2)v1 + 2 m2 v2)/(m1+m2) = -1.25, v2' = ((m2-m1)v2 + 2 m1 v1)/(m1+m2) = 0.25.
  subroutine test_collision()
    type(contact_set_t) :: cs
    type(contact_event_t), allocatable :: ev(:)
    type(contact_report_t) :: rep
    type(dense_inverse_t) :: sop
    real(dp) :: m(2), h, u(2), v(2), du(2), dufree(2), lam(1), mv(2), er
    integer :: stat, step, nest
    character(len=:), allocatable :: errmsg
    m = [1.0_dp, 3.0_dp]
    h = 0.01_dp
    call contact_add(cs, 0.02_dp, [1, 2], [-1.0_dp, 1.0_dp], [1, 2], 'nodes 1-2')
    call contact_finalize(cs, 2, 1.0_dp, stat, errmsg)
    call contact_set_mass(cs, m, stat, errmsg)
    sop%a = reshape([4.0_dp * m(1) / h**2, 0.0_dp, 0.0_dp, 4.0_dp * m(2) / h**2], [2, 2])
    call contact_prepare(cs, sop, stat, errmsg)
    u = 0.0_dp
    v = [1.0_dp, -0.5_dp]
    nest = 0
    do step = 1, 5
      dufree = h * v                                       ! S du = 4 M v / h, no stiffness
      call contact_solve_step(cs, sop, u, dufree, du, lam, stat, errmsg)
      v = 2.0_dp * du / h - v
      mv = m * v
      call contact_end_step(cs, IMPACT_PAPER, u, du, v, mv, er, stat, errmsg, report=rep)
      ev = contact_events(cs)
      nest = nest + rep%n_establish
      u = u + du
    end do
    call check(nest == 1, 'collision: one contact established')
    call check_close(v(1), -1.25_dp, 1.0e-14_dp, 'collision: v1 = elastic result -1.25')
    call check_close(v(2), 0.25_dp, 1.0e-14_dp, 'collision: v2 = elastic result 0.25')
    call contact_destroy(cs)
  end subroutine test_collision

  !> PERSIST with two separate chains (bodies 1 and 2), only body 1 hits the wall: body 2's
  !> velocity is left bit for bit; the energy of body 1 is exact.
  subroutine test_two_bodies_persist()
    type(contact_set_t) :: cs
    type(dense_inverse_t) :: sop, mop
    type(contact_event_t), allocatable :: ev(:)
    type(contact_report_t) :: rep
    real(dp) :: k(3, 3), m(3, 3), s(3, 3), c0(3), g0, h
    real(dp) :: kk(6, 6), mm(6, 6), ss(6, 6), u(6), v(6), du(6), dufree(6), lam(1), mv(6), er, v2(3), t1
    real(dp), allocatable :: a(:, :)
    integer :: stat, step
    character(len=:), allocatable :: errmsg
    h = 0.02_dp
    call chain(.true., h, k, m, s, c0, g0)
    kk = 0.0_dp; mm = 0.0_dp; ss = 0.0_dp
    kk(1:3, 1:3) = k; kk(4:6, 4:6) = k
    mm(1:3, 1:3) = m; mm(4:6, 4:6) = m
    ss(1:3, 1:3) = s; ss(4:6, 4:6) = s
    call contact_add(cs, g0, [1], [1.0_dp])
    call contact_finalize(cs, 6, 1.0_dp, stat, errmsg)
    sop%a = ss
    mop%a = mm
    call contact_set_mass(cs, mop, stat, errmsg)
    call contact_prepare(cs, sop, stat, errmsg)
    u = 0.0_dp
    v = [-1.0_dp, -1.0_dp, -1.0_dp, 0.3_dp, -0.2_dp, 0.1_dp]
    do step = 1, 10
      a = ss
      dufree = matmul((4.0_dp / h) * mm, v) - 2.0_dp * matmul(kk, u)
      call spd_solve(a, dufree, stat, errmsg)
      call contact_solve_step(cs, sop, u, dufree, du, lam, stat, errmsg)
      v = 2.0_dp * du / h - v
      mv = matmul(mm, v)
      v2 = v(4:6)
      t1 = 0.5_dp * dot_product(v(1:3), mv(1:3))
      call contact_end_step(cs, IMPACT_PERSIST, u, du, v, mv, er, stat, errmsg, body=[1, 1, 1, 2, 2, 2], &
        report=rep)
      ev = contact_events(cs)
      u = u + du
      if (rep%n_establish > 0) exit
    end do
    call check(rep%n_establish == 1 .and. rep%persist_groups == 1, 'two bodies PERSIST: one group scaled')
    call check(all(v(4:6) == v2), 'two bodies PERSIST: the other body is untouched')
    call check_close(0.5_dp * dot_product(v(1:3), matmul(m, v(1:3))), t1 + rep%energy_error, 1.0e-14_dp, &
      'two bodies PERSIST: body 1 kinetic energy = T1 + E')
    call contact_destroy(cs)
  end subroutine test_two_bodies_persist

  ! ---------------------------------------------------------------- CHOLMOD

  !> A consistent mass whose row of equation 1 has no coupling (the contact rows IMPACT SYMMETRIC
  !> lumps): C M⁻¹ C' and the reflection (16) about a condition on it are taken from the row
  !> (no solve), about a coupled one by solves; both equal the dense LAPACK values, and mv stays M v.
  subroutine test_local_rows()
    integer, parameter :: n = 30
    type(sym_csc_t) :: pat
    type(contact_set_t) :: cs
    real(dp), allocatable :: kval(:), mval(:), md(:, :), cd(:, :), z(:, :), amd(:, :)
    real(dp) :: mdiag(n), am(2, 2), v(n), mv(n), vref(n), w(n), a(1, 1), nu(1)
    integer :: i, k, stat, rank
    character(len=:), allocatable :: errmsg
    character(len=8) :: tag
    do i = 1, n
      mdiag(i) = 1.0_dp + 0.01_dp * i
    end do
    call chain_matrices(n, mdiag, pat, kval, mval)
    do i = 2, n - 1                                   ! consistent couplings, none on equation 1
      call pat%add_element(mval, [i, i + 1], reshape([0.0_dp, 0.2_dp, 0.2_dp, 0.0_dp], [2, 2]))
    end do
    call contact_add(cs, 1.0e-4_dp, [1], [1.0_dp], [0, 1], 'node 1 wall')
    call contact_add(cs, 2.0e-5_dp, [10, 11], [-1.0_dp, 1.0_dp], [10, 11], 'nodes 10-11')
    call contact_finalize(cs, n, 1.0_dp, stat, errmsg)
    call contact_set_mass(cs, pat, mval, stat, errmsg)
    call check(stat == STAT_OK, 'local rows: M factorized')
    allocate (md(n, n), cd(2, n))
    call to_dense(pat, mval, md)
    cd = 0.0_dp
    cd(1, 1) = 1.0_dp; cd(2, 10) = -1.0_dp; cd(2, 11) = 1.0_dp
    z = transpose(cd)
    call spd_solve(md, z, stat, errmsg)               ! z = M⁻¹ C'
    call to_dense(pat, mval, md)
    amd = matmul(cd, z)
    call contact_am_block(cs, [1, 2], 2, am, stat, errmsg)
    call check(stat == STAT_OK .and. maxval(abs(am - amd)) <= 1.0e-14_dp * maxval(abs(amd)), &
      'local rows: C M-1 C'' (one local, one coupled) matches LAPACK')
    call contact_am_block(cs, [1], 1, a, stat, errmsg)
    call check_close(a(1, 1), 1.0_dp / mdiag(1), 1.0e-15_dp, 'local rows: the local condition alone, 1/m_11')
    do k = 1, 2
      do i = 1, n
        v(i) = cos(0.3_dp * i) - 0.5_dp
      end do
      mv = matmul(md, v)
      nu(1) = dot_product(cd(k, :), v) / amd(k, k)
      vref = v - 2.0_dp * nu(1) * z(:, k)
      call hzero_reflection(cs, [k], [2.0_dp], v, mv, rank, stat, errmsg)
      w = matmul(md, v)
      tag = merge('local  ', 'coupled', k == 1)
      call check(stat == STAT_OK .and. maxval(abs(v - vref)) <= 1.0e-13_dp * maxval(abs(vref)), &
        'local rows: reflection (16) about the ' // trim(tag) // ' condition matches LAPACK')
      call check(maxval(abs(mv - w)) <= 1.0e-13_dp * maxval(abs(w)), 'local rows: mv = M v after the ' // trim(tag) // &
        ' reflection')
    end do
    call contact_destroy(cs)
  end subroutine test_local_rows

  !> Chain of n equations (springs between neighbours, lumped masses, no support): S = K + 4M/h²
  !> factorized by CHOLMOD. Conditions: equation 1 on a wall (twice: a duplicated condition),
  !> equations 20/21 node-to-node, equation n on a second wall.
  subroutine test_cholmod()
    integer, parameter :: n = 40
    type(sym_csc_t) :: pat
    type(spd_factor_t), target :: f
    type(contact_set_t) :: cs
    type(contact_event_t), allocatable :: ev(:)
    real(dp), allocatable :: kval(:), mval(:), sval(:), sd(:, :), zd(:, :), cd(:, :), wd(:, :), md(:, :), amd(:, :)
    real(dp) :: r(n), dufree(n), du(n), du2(n), u(n), lam(4), lam2(4), g(4), res(n), mdiag(n), h, er, v(n), mv(n)
    real(dp) :: am_diag(4, 4), wfull(4, 4)
    type(chol_ref_t) :: fop
    integer :: i, stat
    character(len=:), allocatable :: errmsg
    h = 1.0e-3_dp
    do i = 1, n
      mdiag(i) = 1.0_dp + 0.01_dp * i
    end do
    call chain_matrices(n, mdiag, pat, kval, mval)
    sval = kval + (4.0_dp / h**2) * mval
    call f%factorize(pat, sval, stat, errmsg)
    call check(stat == STAT_OK, 'CHOLMOD: S factorized')

    call contact_add(cs, 1.0e-4_dp, [1], [1.0_dp], [0, 1], 'node 1 wall')
    call contact_add(cs, 1.0e-4_dp, [1], [1.0_dp], [0, 1], 'node 1 wall again')
    call contact_add(cs, 2.0e-5_dp, [20, 21], [-1.0_dp, 1.0_dp], [20, 21], 'nodes 20-21')
    call contact_add(cs, 5.0e-5_dp, [n], [-1.0_dp], [0, n], 'node n wall')
    call contact_finalize(cs, n, 1.0_dp, stat, errmsg)
    call contact_set_mass(cs, pat, mval, stat, errmsg)
    call check(stat == STAT_OK, 'CHOLMOD: consistent-mass path factorizes M')
    call contact_am_block(cs, [1, 2, 3, 4], 4, am_diag, stat, errmsg)
    call contact_prepare(cs, f, stat, errmsg, pat, sval)
    call check(stat == STAT_OK, 'CHOLMOD: S prepared (Schur columns and augmented system)')
    fop%f => f
    call contact_w_matrix(cs, fop, wfull, stat, errmsg)

    ! Dense reference W = C S⁻¹ C' and C M⁻¹ C' by LAPACK.
    allocate (sd(n, n), md(n, n), cd(4, n))
    call to_dense(pat, sval, sd)
    call to_dense(pat, mval, md)
    cd = 0.0_dp
    cd(1, 1) = 1.0_dp; cd(2, 1) = 1.0_dp; cd(3, 20) = -1.0_dp; cd(3, 21) = 1.0_dp; cd(4, n) = -1.0_dp
    zd = transpose(cd)
    call spd_solve(sd, zd, stat, errmsg)
    wd = matmul(cd, zd)
    call check(maxval(abs(wfull - wd)) <= 1.0e-12_dp * maxval(abs(wd)), 'CHOLMOD: W = C S-1 C'' matches LAPACK to 1e-12')
    amd = transpose(cd)
    call spd_solve(md, amd, stat, errmsg)
    amd = matmul(cd, amd)
    call check(maxval(abs(am_diag - amd)) <= 1.0e-14_dp * maxval(abs(amd)), 'CHOLMOD: C M-1 C'' matches LAPACK')
    call contact_set_mass(cs, mdiag, stat, errmsg)
    call contact_am_block(cs, [1, 2, 3, 4], 4, am_diag, stat, errmsg)
    call check(stat == STAT_OK .and. maxval(abs(am_diag - amd)) <= 1.0e-15_dp * maxval(abs(amd)), &
      'lumped-mass path gives the same C M-1 C''')

    ! A step: the chain pushed towards the first wall, squeezed at 20/21, pulled off the last.
    do i = 1, n
      r(i) = -2.0e3_dp * cos(0.1_dp * i) - 1.0e3_dp
    end do
    r(21) = r(21) - 4.0e4_dp
    r(20) = r(20) + 4.0e4_dp
    call f%solve(r, dufree, stat, errmsg)
    u = 0.0_dp
    call contact_solve_step(cs, f, u, dufree, du, lam, stat, errmsg)
    call check(stat == STAT_OK, 'CHOLMOD step: LCP solved (' // itoa(cs%lcp_iterations()) // ' pivots)')
    call contact_gaps(cs, u + du, g)
    call check(all(lam >= 0.0_dp) .and. all(g >= -1.0e-12_dp), 'CHOLMOD step: lam >= 0, g >= -tol')
    call check(abs(dot_product(lam, g)) <= 1.0e-12_dp * maxval(lam), 'CHOLMOD step: complementarity')
    call check(lam(1) + lam(2) > 0.0_dp .and. lam(1) * lam(2) == 0.0_dp .and. lam(3) > 0.0_dp .and. lam(4) > 0.0_dp, &
      'CHOLMOD step: walls and node pair active, one copy of the duplicated condition dropped', &
      'lam = ' // rtoa(lam(1)) // rtoa(lam(2)) // rtoa(lam(3)) // rtoa(lam(4)))
    ! S du = r + C'Λ: the constrained update solves the step equation with the contact force.
    call pat%matvec(sval, du, res)
    call contact_add_force(cs, r)
    call check(maxval(abs(res - r)) <= 1.0e-10_dp * maxval(abs(r)), 'CHOLMOD step: S du = r + C''Λ')
    r = r - matmul(transpose(cd), lam)
    ! The augmented sparse system (UMFPACK) from a cold start: the same du and Λ. Both copies of
    ! the duplicated condition in one active set make it singular: that solve falls back to Schur.
    call cs%set_solver(SOLVER_AUGMENTED)
    call cs%warm_start(spread(.true., 1, cs%n_conditions()))
    call contact_solve_step(cs, f, u, dufree, du2, lam2, stat, errmsg)
    ! Both are backward stable solves of the same system, cond(W) ~ 1e3: 1e-12 relative.
    call check(stat == STAT_OK .and. maxval(abs(du2 - du)) <= 1.0e-12_dp * maxval(abs(du)) .and. &
      maxval(abs(lam2 - lam)) <= 1.0e-12_dp * maxval(lam), 'CHOLMOD: augmented system gives the same du and Λ', &
      'lam2 = ' // rtoa(lam2(1)) // rtoa(lam2(2)) // rtoa(lam2(3)) // rtoa(lam2(4)))
    call check(counter(cs, 'factorizations') >= 1 .and. counter(cs, 'singular') >= 1, &
      'CHOLMOD: dependent conditions: singular KKT detected, ' // &
      'Schur fallback (' // itoa(int(counter(cs, 'factorizations'))) // ' LU, ' // &
      itoa(int(counter(cs, 'singular'))) // ' singular)')
    call cs%warm_start([.true., spread(.false., 1, cs%n_conditions() - 1)])
    call contact_solve_step(cs, f, u, dufree, du2, lam2, stat, errmsg)
    call check(stat == STAT_OK .and. maxval(abs(du2 - du)) <= 1.0e-12_dp * maxval(abs(du)) .and. &
      counter(cs, 'augmented_solves') >= 1, 'CHOLMOD: augmented system from the warm start, no fallback needed')
    call cs%set_solver(SOLVER_AUTO)
    ! End of step (PAPER, lumped mass): energy restored = Σ E_j, events for the 3 closed ones.
    v = 2.0_dp * du / h
    mv = mdiag * v
    call contact_end_step(cs, IMPACT_PAPER, u, du, v, mv, er, stat, errmsg)
    ev = contact_events(cs)
    call check(stat == STAT_OK .and. size(ev) == cs%n_active(), 'CHOLMOD end of step: one event per established')
    call check_close(er, sum(ev%energy), 1.0e-13_dp, 'CHOLMOD end of step: energy restored = sum E_j', &
      atol=1.0e-13_dp * 0.5_dp * dot_product(v, mv))
    call contact_destroy(cs)
    call f%destroy()
  end subroutine test_cholmod
  !> The Schur column cache at its limits: 20 wall conditions on a 40-equation chain, a cache of
  !> 8 columns (z_max_entries = 0), SCHUR only. Steps that close 12 conditions (the cache must
  !> grow), then 5 others, then the first ones again (least recently used columns reused):
  !> every Λ matches the dense LCP on the full W = C S⁻¹C' (contact_w_matrix, then lcp_solve
  !> from a cold start), every update solves S du = r + C'Λ, and columns kept in the cache are
  !> not computed again.
  subroutine test_column_cache()
    integer, parameter :: n = 40, nw = 20
    type(sym_csc_t) :: pat
    type(spd_factor_t), target :: f
    type(contact_set_t) :: cs
    type(chol_ref_t) :: fop
    real(dp), allocatable :: kval(:), mval(:), sval(:)
    real(dp) :: r(n), dufree(n), du(n), u(n), lam(nw), res(n), w(nw, nw), q(nw), lamd(nw), gd(nw), push(n), mdiag(n)
    logical :: actd(nw)
    integer :: i, stat, it, k, cols_before
    integer :: sets(3, 2)
    character(len=:), allocatable :: errmsg
    mdiag = 1.0_dp
    call chain_matrices(n, mdiag, pat, kval, mval)
    sval = kval + 4.0e6_dp * mval
    call f%factorize(pat, sval, stat, errmsg)
    do i = 1, nw
      call contact_add(cs, 1.0e-6_dp * i, [i], [-1.0_dp], [0, i])     ! u_i <= 1e-6 i
    end do
    cs%settings%z_max_entries = 0
    cs%settings%switch_size = 0
    cs%settings%solver = SOLVER_SCHUR
    call contact_finalize(cs, n, 1.0_dp, stat, errmsg)
    call contact_prepare(cs, f, stat, errmsg, pat, sval)
    call check(stat == STAT_OK .and. counter(cs, 'cache_columns') == 8, 'cache: starts with 8 columns (z_max_entries = 0)', &
      'cap = ' // itoa(int(counter(cs, 'cache_columns'))))
    fop%f => f
    call contact_w_matrix(cs, fop, w, stat, errmsg)
    cols_before = int(counter(cs, 'columns'))
    u = 0.0_dp
    sets(1, :) = [1, 12]       ! push nodes 1..12 past their walls, then 13..17, then 1..12 again
    sets(2, :) = [13, 17]
    sets(3, :) = [1, 12]
    do it = 1, 3
      push = 0.0_dp
      push(sets(it, 1):sets(it, 2)) = 1.0_dp
      r = 1.0e3_dp * push
      call f%solve(r, dufree, stat, errmsg)
      call contact_solve_step(cs, f, u, dufree, du, lam, stat, errmsg)
      ! Reference: the dense LCP on the full W, from a cold start.
      do k = 1, nw
        q(k) = 1.0e-6_dp * k - dufree(k)
      end do
      actd = .false.
      call lcp_solve(w, q, 1.0e-14_dp, lamd, gd, actd, k, stat, errmsg)
      call check(stat == STAT_OK .and. maxval(abs(lam - lamd)) <= 1.0e-12_dp * maxval(abs(lamd)), &
        'cache step ' // itoa(it) // ': Λ = dense LCP on C S-1 C'' to 1e-12 (' // itoa(count(lam > 0.0_dp)) // &
        ' active, cache ' // itoa(int(counter(cs, 'cache_columns'))) // ' columns)')
      call pat%matvec(sval, du, res)
      call contact_add_force(cs, r)
      call check(maxval(abs(res - r)) <= 1.0e-10_dp * maxval(abs(r)), 'cache step ' // itoa(it) // ': S du = r + C''Λ')
      if (it == 1) call check(counter(cs, 'cache_columns') >= 12, 'cache: grew to hold the 12-condition active set')
    end do
    ! Columns: 20 for the reference W, 12 + 5 for the first two steps; the third step finds
    ! the 12 first columns evicted only as far as room was needed for the 5 others.
    call check(int(counter(cs, 'columns')) - cols_before <= 12 + 5 + 5, 'cache: no more columns than evictions require (' // &
      itoa(int(counter(cs, 'columns')) - cols_before) // ' computed for 29 activations)')
    call contact_destroy(cs)
    call f%destroy()
  end subroutine test_column_cache
  !> Chain of n equations: springs of stiffness 1e4 between neighbours, masses mdiag, no
  !> support; the pattern and the values of K and M.
  subroutine chain_matrices(n, mdiag, pat, kval, mval)
    integer, intent(in) :: n
    real(dp), intent(in) :: mdiag(n)
    type(sym_csc_t), intent(out) :: pat
    real(dp), allocatable, intent(out) :: kval(:), mval(:)
    integer, allocatable :: eptr(:), edofs(:)
    integer :: i, ne, p, stat
    character(len=:), allocatable :: errmsg
    allocate (eptr(2 * n), edofs(3 * n))
    ne = 0
    p = 1
    do i = 1, n
      ne = ne + 1; eptr(ne) = p; edofs(p) = i; p = p + 1
      if (i < n) then
        ne = ne + 1; eptr(ne) = p; edofs(p:p + 1) = [i, i + 1]; p = p + 2
      end if
    end do
    eptr(ne + 1) = p
    call pat%build(n, eptr(1:ne + 1), edofs(1:p - 1), stat, errmsg)
    call check(stat == STAT_OK, 'chain pattern built')
    allocate (kval(pat%nnz), mval(pat%nnz))
    kval = 0.0_dp
    mval = 0.0_dp
    do i = 1, n
      call pat%add_element(mval, [i], reshape([mdiag(i)], [1, 1]))
      if (i < n) call pat%add_element(kval, [i, i + 1], 1.0e4_dp * reshape([1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp], [2, 2]))
    end do
  end subroutine chain_matrices
  !> One counter of the multiplier system (contact_set_t%counters).
  integer(8) function counter(cs, what)
    type(contact_set_t), intent(in) :: cs
    character(len=*), intent(in) :: what
    type(multiplier_counters_t) :: k
    k = cs%counters()
    select case (what)
    case ('factorizations')
      counter = k%factorizations
    case ('singular')
      counter = k%singular
    case ('augmented_solves')
      counter = k%augmented_solves
    case ('columns')
      counter = k%columns
    case ('cache_columns')
      counter = k%cache_columns
    case default
      counter = -1
    end select
  end function counter
end program test_contact
