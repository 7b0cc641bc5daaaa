!> Cubic nonlinear elasticity sigma = E eps (1 + b eps^2): energy and tangent are the exact
!> integral and derivative of the stress; the sub-incremented work W_N obeys the exact
!> Euler-Maclaurin error W_N - dpsi = (deps/N)^2/12 (sigma'(eps1) - sigma'(eps0)) (cubic
!> integrand), i.e. converges at rate exactly 2; the AUTO rule meets its tolerance; SUBSTEPS EXACT's
!> discrete gradient does the work psi1 - psi0 to round-off, softening and stiffening, and tends to
!> sigma(eps0) as deps -> 0.
program test_law_nonlinear_elastic
  use kinds, only: dp, qp
  use testing, only: check, check_close, test_summary
  use law_nonlinear_elastic, only: nle_stress, nle_tangent, nle_energy, nle_path, nle_exact, nle_auto_nsub, NLE_RTOL
  implicit none

  real(dp), parameter :: e = 2.0e9_dp, b = 300.0_dp
  real(dp) :: eps0, deps, sig, sbar, et, w, dpsi, pred, err(0:8), h, sp, sm, bp, bm, sc, worst, bb, r(2)
  real(qp) :: e0q, e1q, dpsiq
  integer :: k, n
  integer, allocatable :: seed(:)
  character(len=64) :: nm

  ! psi' = sigma, sigma' = tangent (central differences, error O(h^2) ~ 1e-10 relative).
  eps0 = 0.037_dp
  h = 1.0e-6_dp
  call check_close((nle_energy(e, b, eps0 + h) - nle_energy(e, b, eps0 - h)) / (2 * h), nle_stress(e, b, eps0), &
    1.0e-8_dp, 'nle: dpsi/deps = sigma')
  call check_close((nle_stress(e, b, eps0 + h) - nle_stress(e, b, eps0 - h)) / (2 * h), nle_tangent(e, b, eps0), &
    1.0e-8_dp, 'nle: dsigma/deps = tangent')

  ! Exact trapezoid error for every N, and rate 2 (error ratio exactly 4 per halving).
  eps0 = -0.01_dp
  deps = 0.06_dp
  dpsi = nle_energy(e, b, eps0 + deps) - nle_energy(e, b, eps0)
  sc = abs(deps) * max(abs(nle_stress(e, b, eps0)), abs(nle_stress(e, b, eps0 + deps)))
  write (*, '(a)') '# nonlinear elastic: N, W_N - (psi1 - psi0), relative to |deps| max|sigma|'
  do k = 0, 8
    n = 2**k
    call nle_path(e, b, n, eps0, deps, nle_stress(e, b, eps0), sig, sbar, et)
    w = sbar * deps
    err(k) = w - dpsi
    pred = (deps / n)**2 / 12.0_dp * (nle_tangent(e, b, eps0 + deps) - nle_tangent(e, b, eps0))
    write (*, '(a,i5,2es12.4)') '#   ', n, err(k), err(k) / sc
    write (nm, '(a,i0)') 'nle: W_N error = Euler-Maclaurin closed form, N=', n
    call check_close(err(k), pred, 1.0e-7_dp, trim(nm), atol=1.0e-13_dp * sc)
  end do
  call check_close(err(3) / err(4), 4.0_dp, 1.0e-6_dp, 'nle: work converges at rate 2 (ratio 4 per halving)')
  call check_close(sig, nle_stress(e, b, eps0 + deps), 0.0_dp, 'nle: end stress exact whatever N')
  call check_close(et, nle_tangent(e, b, eps0 + deps), 0.0_dp, 'nle: tangent = sigma''(eps1)')

  ! Tangent of the algorithm: d sig / d deps by central differences.
  h = 1.0e-7_dp
  call nle_path(e, b, 4, eps0, deps + h, 0.0_dp, sp, bp, et)
  call nle_path(e, b, 4, eps0, deps - h, 0.0_dp, sm, bm, et)
  call nle_path(e, b, 4, eps0, deps, 0.0_dp, sig, sbar, et)
  call check_close((sp - sm) / (2 * h), et, 1.0e-7_dp, 'nle: consistent tangent vs finite differences')

  ! AUTO: the chosen N meets the relative tolerance; N - 1 would not (smallest such N).
  n = nle_auto_nsub(e, b, eps0, deps)
  call nle_path(e, b, n, eps0, deps, nle_stress(e, b, eps0), sig, sbar, et)
  write (*, '(a,i0,a,es10.3)') '# AUTO N = ', n, ', relative error ', abs(sbar * deps - dpsi) / sc
  call check(abs(sbar * deps - dpsi) <= NLE_RTOL * sc, 'nle: AUTO N meets NLE_RTOL')
  call nle_path(e, b, n - 1, eps0, deps, nle_stress(e, b, eps0), sig, sbar, et)
  call check(n == 1 .or. abs(sbar * deps - dpsi) > NLE_RTOL * sc, 'nle: AUTO N is the smallest meeting NLE_RTOL')
  call check(nle_auto_nsub(e, 0.0_dp, eps0, deps) == 1, 'nle: AUTO N = 1 for a linear law (b = 0)')


  ! SUBSTEPS EXACT: sbar deps = psi(eps1) - psi(eps0) to round-off (relative to |deps| max|sigma|),
  ! over random strains and both signs of b; the quotient's limit sigma(eps0) for a vanishing deps.
  ! (The reference Δψ in quadruple precision: ψ1 − ψ0 in double loses |ε|/|Δε| ulps to cancellation.)
  call random_seed(size=n)
  allocate (seed(n))
  seed = 20261202
  call random_seed(put=seed)
  worst = 0.0_dp
  do k = 1, 2000
    call random_number(r)
    eps0 = 0.1_dp * (2 * r(1) - 1)
    deps = 0.1_dp * (2 * r(2) - 1)
    bb = merge(b, -b / 4, mod(k, 2) == 0)
    call nle_exact(e, bb, eps0, deps, sig, sbar, et)
    e0q = real(eps0, qp)
    e1q = real(eps0 + deps, qp)
    dpsiq = real(e, qp) * ((e1q**2 - e0q**2) / 2 + real(bb, qp) * (e1q**4 - e0q**4) / 4)
    sc = abs(deps) * max(abs(nle_stress(e, bb, eps0)), abs(nle_stress(e, bb, eps0 + deps)), abs(sbar))
    if (sc > 0.0_dp) worst = max(worst, real(abs(real(sbar, qp) * real(eps0 + deps - eps0, qp) - dpsiq), dp) / sc)
  end do
  write (*, '(a,es10.2)') '# nle_exact: worst |sbar deps - dpsi| / (|deps| max|sigma|) over 2000 steps:', worst
  call check(worst <= 1.0e-13_dp, 'nle: EXACT work = psi1 - psi0 to round-off (2000 random steps, b > 0 and < 0)')
  call nle_exact(e, b, 0.037_dp, 0.0_dp, sig, sbar, et)
  call check_close(sbar, nle_stress(e, b, 0.037_dp), 1.0e-15_dp, 'nle: EXACT sbar -> sigma(eps0) as deps -> 0')
  call check_close(sig, nle_stress(e, b, 0.037_dp), 0.0_dp, 'nle: EXACT end stress sigma(eps1)')

  call test_summary('law_nonlinear_elastic')
end program test_law_nonlinear_elastic
