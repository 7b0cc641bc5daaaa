!> Bilinear 1D elastoplasticity against closed forms: monotonic curves with isotropic, kinematic
!> and mixed hardening (return mapping exact for linear hardening, any step size), cyclic
!> reversal (reverse yield at sigma_max - 2 sy for kinematic hardening, Bauschinger; at
!> -sigma_max for isotropic), consistent tangent vs finite differences, sigma_c = 0 bit for bit
!> on elastic steps, convergence of the sub-incremented work and dissipation across the yield
!> point (kink error bounded by E (deps/N)^2 / 8), and the energy balance work = dstored + dissip.
program test_law_plastic_1d
  use kinds, only: dp
  use testing, only: check, check_close, test_summary
  use law_plastic_1d, only: P1D_NSTATE, plastic_1d_path, plastic_1d_return, plastic_auto_nsub, AUTO_ALPHA
  use law_types, only: law_params_t
  implicit none

  real(dp), parameter :: e = 200.0e9_dp, sy = 250.0e6_dp, ey = sy / e
  real(dp) :: q(P1D_NSTATE), qn(P1D_NSTATE), sig, sigbar, dissip, et, s, eps, h
  real(dp) :: hard(2, 3), sp, sm, bar, w, wex, dex, errw(0:7), errd(0:7), dst, s1
  integer :: i, k, nused, n, j
  character(len=80) :: nm

  hard(:, 1) = [10.0e9_dp, 0.0_dp]       ! isotropic
  hard(:, 2) = [0.0_dp, 10.0e9_dp]       ! kinematic
  hard(:, 3) = [4.0e9_dp, 6.0e9_dp]      ! mixed

  ! Monotonic loading in uneven steps (one straddles the yield point): exact bilinear curve.
  do j = 1, 3
    qn = 0.0_dp
    s = 0.0_dp
    eps = 0.0_dp
    do i = 1, 7
      h = ey * (0.3_dp + 0.45_dp * i)
      call plastic_1d_path(lp(e, sy, hard(1, j), hard(2, j)), 1, s, qn, h, sig, sigbar, q, dissip, nused, et)
      eps = eps + h
      s = sig
      qn = q
    end do
    write (nm, '(a,i0)') 'p1d: monotonic bilinear curve, hardening case ', j
    call check_close(s, bilinear(eps, sum(hard(:, j))), 1.0e-13_dp, trim(nm))
    write (nm, '(a,i0)') 'p1d: alpha = (sigma - sy)/H, hardening case ', j
    call check_close(q(2), (s - sy) / sum(hard(:, j)), 1.0e-12_dp, trim(nm))
  end do

  ! Cyclic: load to eps1 = 5 ey, then reverse to -5 ey in small steps; find reverse yield.
  do j = 1, 2
    qn = 0.0_dp
    call plastic_1d_path(lp(e, sy, hard(1, j), hard(2, j)), 1, 0.0_dp, qn, 5 * ey, s1, bar, q, dissip, nused, et)
    qn = q
    s = s1
    eps = 5 * ey
    ! reverse elastically to the predicted reverse-yield stress in one step, then a bit further
    if (j == 1) then
      h = (-s1 - s1) / e          ! isotropic: reverse yield at -sigma_max
    else
      h = (s1 - 2 * sy - s1) / e  ! kinematic: reverse yield at sigma_max - 2 sy
    end if
    call plastic_1d_path(lp(e, sy, hard(1, j), hard(2, j)), 1, s, qn, h * (1 - 1.0e-9_dp), sig, bar, q, dissip, nused, et)
    call check(nused == 0, 'p1d: unloading stays elastic up to the reverse yield point, case ' // achar(48 + j))
    qn = q
    s = sig
    call plastic_1d_path(lp(e, sy, hard(1, j), hard(2, j)), 1, s, qn, -2 * ey, sig, bar, q, dissip, nused, et)
    ! After reverse yield the slope is Et = E H/(E+H); the first delta = (s - s_ry)/E of the
    ! strain is still elastic (the unloading stopped 1e-9 short of the reverse-yield point).
    bar = s + h * 1.0e-9_dp * e   ! s_ry
    call check_close(sig, bar - e * sum(hard(:, j)) / (e + sum(hard(:, j))) * (2 * ey - (s - bar) / e), 1.0e-12_dp, &
      'p1d: reverse yield and plastic branch (Bauschinger for kinematic), case ' // achar(48 + j))
  end do

  ! Consistent tangent vs central finite differences, from the virgin state across yield, N = 1
  ! and N = 5 (the last sub-increment is plastic: its tangent is the curve's slope).
  do n = 1, 5, 4
    qn = 0.0_dp
    h = 1.0e-6_dp * ey
    call plastic_1d_path(lp(e, sy, 4.0e9_dp, 6.0e9_dp), n, 0.0_dp, qn, 3 * ey + h, sp, bar, q, dissip, nused, et)
    call plastic_1d_path(lp(e, sy, 4.0e9_dp, 6.0e9_dp), n, 0.0_dp, qn, 3 * ey - h, sm, bar, q, dissip, nused, et)
    call plastic_1d_path(lp(e, sy, 4.0e9_dp, 6.0e9_dp), n, 0.0_dp, qn, 3 * ey, sig, bar, q, dissip, nused, et)
    call check_close((sp - sm) / (2 * h), et, 1.0e-6_dp, 'p1d: consistent tangent vs FD, N=' // achar(48 + n))
  end do
  call check_close(et, e * 10.0e9_dp / (e + 10.0e9_dp), 1.0e-14_dp, 'p1d: plastic tangent = E H / (E + H)')

  ! sigma_c = 2 sigbar - (sigma_n + sigma) = 0 bit for bit when the step stays elastic, from a
  ! hardened state, whatever nsub; nused = 0.
  qn = 0.0_dp
  call plastic_1d_path(lp(e, sy, 4.0e9_dp, 6.0e9_dp), 1, 0.0_dp, qn, 3.3_dp * ey, s, bar, q, dissip, nused, et)
  qn = q
  do n = 1, 16, 5
    call plastic_1d_path(lp(e, sy, 4.0e9_dp, 6.0e9_dp), n, s, qn, -0.77_dp * ey, sig, sigbar, q, dissip, nused, et)
    call check(2 * sigbar - (s + sig) == 0.0_dp .and. nused == 0 .and. dissip == 0.0_dp .and. all(q == qn), &
      'p1d: elastic step, sigma_c == 0 exactly, nused = 0, N=' // achar(48 + mod(n, 10)))
  end do

  ! Work and dissipation across the yield point, perfectly plastic, deps = 2.7 ey from 0:
  ! exact W = sy ey/2 + sy (deps - ey), D = sy (deps - ey). Kink error <= E (deps/N)^2 / 8.
  h = 2.7_dp * ey
  wex = 0.5_dp * sy * ey + sy * (h - ey)
  dex = sy * (h - ey)
  write (*, '(a)') '# perfectly plastic 1D, deps = 2.7 ey: N, (W_N - W)/W, (D_N - D)/D, balance residual'
  do k = 0, 7
    n = 2**k
    qn = 0.0_dp
    call plastic_1d_path(lp(e, sy, 0.0_dp, 0.0_dp), n, 0.0_dp, qn, h, sig, sigbar, q, dissip, nused, et)
    w = sigbar * h
    dst = 0.5_dp * sig**2 / e
    errw(k) = abs(w - wex)
    errd(k) = abs(dissip - dex)
    write (*, '(a,i5,3es12.4)') '#   ', n, (w - wex) / wex, (dissip - dex) / dex, (w - dst - dissip) / wex
    write (nm, '(a,i0)') 'p1d: work error within the kink bound E (deps/N)^2/8, N=', n
    call check(errw(k) <= e * (h / n)**2 / 8 * (1 + 1.0e-12_dp) + 1.0e-15_dp * wex, trim(nm))
    write (nm, '(a,i0)') 'p1d: work = dstored + dissip (trapezoid identity), N=', n
    call check_close(w, dst + dissip, 1.0e-13_dp, trim(nm))
    call check_close(sig, sy, 1.0e-15_dp, 'p1d: perfectly plastic end stress = sy')
  end do
  call check(errw(7) < 1.0e-3_dp * errw(0) .and. errd(7) < 1.0e-3_dp * errd(0), &
    'p1d: work and dissipation errors shrink > 1000x from N=1 to N=128 (rate 2 on average)')

  ! AUTO rule: r = E deps / sy, N = ceil(r / alpha).
  call check(plastic_auto_nsub(2.7_dp) == ceiling(2.7_dp / AUTO_ALPHA), 'p1d: AUTO rule N = ceil(r/alpha)')
  call check(plastic_auto_nsub(0.0_dp) == 1 .and. plastic_auto_nsub(1.0e9_dp) == 100, 'p1d: AUTO clamps to 1..100')
  call auto_table()

  ! One increment: trial exactly on the yield surface is elastic.
  qn = 0.0_dp
  call plastic_1d_return(lp(e, sy, 0.0_dp, 0.0_dp), 0.0_dp, qn, ey, sig, q, h, et)
  call check(h == 0.0_dp .and. et == e, 'p1d: trial on the yield surface is elastic')

  call test_summary('law_plastic_1d')

contains

  pure real(dp) function bilinear(x, hh)
    real(dp), intent(in) :: x, hh
    if (x <= ey) then
      bilinear = e * x
    else
      bilinear = sy + e * hh / (e + hh) * (x - ey)
    end if
  end function bilinear

  !> Relative work error of fixed N and AUTO for steps of r yield strains from the virgin state
  !> (mixed hardening), exact work from the bilinear curve. Printed for docs/materials.md.
  subroutine auto_table()
    real(dp) :: rs(6), r, hh, s_end, wx, wn, qa(P1D_NSTATE), q0(P1D_NSTATE), sg, sb, ds, tg
    integer :: ir, nn(6), m, nu
    rs = [0.5_dp, 1.2_dp, 2.7_dp, 6.3_dp, 15.5_dp, 40.1_dp]
    nn = [1, 2, 4, 8, 16, 0]
    hh = 10.0e9_dp
    write (*, '(a)') '# AUTO table 1D (h_iso=4e9, h_kin=6e9): r, |W_N-W|/W for N=1,2,4,8,16, AUTO (N)'
    do ir = 1, 6
      r = rs(ir)
      s_end = bilinear(r * ey, hh)
      wx = 0.5_dp * sy * ey + 0.5_dp * (sy + s_end) * (r * ey - ey)
      if (r <= 1.0_dp) wx = 0.5_dp * e * (r * ey)**2
      write (*, '(a,f6.1)', advance='no') '#   ', r
      do m = 1, 6
        q0 = 0.0_dp
        call plastic_1d_path(lp(e, sy, 4.0e9_dp, 6.0e9_dp), merge(nn(m), plastic_auto_nsub(r), nn(m) > 0), 0.0_dp, q0, &
          r * ey, sg, sb, qa, ds, nu, tg)
        wn = sb * r * ey
        write (*, '(es10.2)', advance='no') abs(wn - wx) / wx
      end do
      write (*, '(a,i0,a)') ' (', plastic_auto_nsub(r), ')'
      call check(abs(wn - wx) / wx <= 0.5_dp * AUTO_ALPHA**2 / max(r, 1.0_dp), 'p1d: AUTO work error within alpha^2/(2 max(r,1))')
    end do
  end subroutine auto_table
  !> The constants of a 1D plastic law, given one by one.
  pure function lp(e, sy, hi, hk) result(p)
    real(dp), intent(in) :: e, sy, hi, hk
    type(law_params_t) :: p
    p = law_params_t(young=e, yield=sy, h_iso=hi, h_kin=hk)
  end function lp
end program test_law_plastic_1d
