!> J2 plasticity (plane strain, plane stress) against closed forms: pure shear in plane strain
!> (yield at tau = sy/sqrt(3), hardening slope G H/(3G + H), H = h_iso + h_kin; zero normal
!> stresses), the uniaxial-stress path in plane stress against the 1D bilinear curve (same
!> slope E H/(E + H)) and its lateral strains, consistent tangents vs finite differences,
!> sigma_c = 0 bit for bit on elastic steps, the energy balance, and the convergence of the
!> sub-incremented work on a non-proportional path (measured rate, AUTO table).
program test_law_von_mises
  use kinds, only: dp
  use testing, only: check, check_close, test_summary
  use law_von_mises, only: VM_NSTATE, vm_d3, vm_dps, vm_path, vm_stored, vm_trial_ratio
  use law_plastic_1d, only: plastic_auto_nsub
  use law_types, only: law_params_t, law_step_t
  implicit none

  real(dp), parameter :: e = 200.0e9_dp, nu = 0.3_dp, sy = 250.0e6_dp, hi = 4.0e9_dp, hk = 6.0e9_dp
  real(dp), parameter :: g = e / (2 * (1 + nu)), hh = hi + hk, ey = sy / e
  real(dp) :: d3(4, 4), dps(4, 4), q(VM_NSTATE), qn(VM_NSTATE), sig(4), sbar(4), dt(4, 4), dis, gam, gy, s(4)
  real(dp) :: tau, ep, sx, de(4), fd(4, 4), sp(4), sm(4), h, w, werr(0:9), wref, st0, st1, qq(VM_NSTATE)
  integer :: i, k, nused, n, j
  logical :: ps
  character(len=80) :: nm

  call vm_d3(e, nu, d3)
  call vm_dps(e, nu, dps)

  ! Plane strain pure shear, two big steps (proportional path: radial return exact).
  gy = sy / (sqrt(3.0_dp) * g)
  qn = 0.0_dp
  s = 0.0_dp
  gam = 0.0_dp
  do i = 1, 2
    de = [0.0_dp, 0.0_dp, 0.0_dp, 2.5_dp * gy]
    call vm_path_args(e, nu, sy, hi, hk, .false., 1, d3, s, qn, de, sig, sbar, q, dis, nused, dt)
    s = sig
    qn = q
    gam = gam + de(4)
  end do
  tau = sy / sqrt(3.0_dp) + g * hh / (3 * g + hh) * (gam - gy)
  call check_close(s(4), tau, 1.0e-13_dp, 'vm: plane strain pure shear tau = sy/sqrt3 + G H/(3G+H) (gamma - gamma_y)')
  call check(maxval(abs(s(1:3))) <= 1.0e-12_dp * sy, 'vm: pure shear keeps zero normal stresses')
  call check_close(dt(4, 4), g * hh / (3 * g + hh), 1.0e-12_dp, 'vm: shear tangent = G H/(3G+H)')
  ! perfectly plastic: plateau at sy/sqrt(3)
  qn = 0.0_dp
  call vm_path_args(e, nu, sy, 0.0_dp, 0.0_dp, .false., 1, d3, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], qn, &
    [0.0_dp, 0.0_dp, 0.0_dp, 7 * gy], sig, sbar, q, dis, nused, dt)
  call check_close(sig(4), sy / sqrt(3.0_dp), 1.0e-14_dp, 'vm: perfectly plastic shear yields at sy/sqrt(3)')

  ! Plane stress uniaxial stress: follow the exact strain path of the 1D bilinear law, elastic
  ! branch to yield then a straight plastic branch (both proportional): exx = s/E + ep,
  ! eyy = -nu s/E - ep/2; expect sxx = s, syy = sxy = 0, ezz = eyy.
  qn = 0.0_dp
  s = 0.0_dp
  de = [ey, -nu * ey, 0.0_dp, 0.0_dp]
  call vm_path_args(e, nu, sy, hi, hk, .true., 1, dps, s, qn, de, sig, sbar, q, dis, nused, dt)
  call check(nused == 0, 'vm: plane stress uniaxial path elastic up to yield')
  s = sig
  qn = q
  sx = sy + 3.0e8_dp
  ep = (sx - sy) / hh
  de = [(sx - sy) / e + ep, -nu * (sx - sy) / e - 0.5_dp * ep, 0.0_dp, 0.0_dp]
  call vm_path_args(e, nu, sy, hi, hk, .true., 1, dps, s, qn, de, sig, sbar, q, dis, nused, dt)
  call check_close(sig(1), sx, 1.0e-12_dp, 'vm: plane stress uniaxial stress = 1D bilinear curve')
  call check(abs(sig(2)) + abs(sig(3)) + abs(sig(4)) <= 1.0e-9_dp * sy, 'vm: plane stress uniaxial: syy = szz = sxy = 0')
  call check_close(q(10), -nu * sx / e - 0.5_dp * ep, 1.0e-10_dp, 'vm: plane stress ezz = -nu s/E - ep/2')
  call check_close(q(1), ep, 1.0e-10_dp, 'vm: plane stress plastic strain exx_p = (s - sy)/H')
  ! uniaxial tangent: d sxx/d exx at fixed syy = 0 is 1/(C^-1)_11 of the 2x2 normal block = E H/(E+H)
  call check_close(dt(2, 2) / (dt(1, 1) * dt(2, 2) - dt(1, 2) * dt(2, 1)), (e + hh) / (e * hh), 1.0e-10_dp, &
    'vm: plane stress uniaxial tangent = E H/(E+H)')

  ! Consistent tangents vs central finite differences: from a hardened state (pure shear, plane
  ! strain / plane stress), a non-proportional increment, N = 1.
  do j = 1, 2
    ps = j == 2
    qn = 0.0_dp
    s = 0.0_dp
    call vm_path_args(e, nu, sy, hi, hk, ps, 1, merge(dps, d3, ps), s, qn, [0.0_dp, 0.0_dp, 0.0_dp, 2 * gy], &
      sig, sbar, q, dis, nused, dt)
    s = sig
    qn = q
    de = [1.1_dp * ey, -0.4_dp * ey, 0.0_dp, 0.6_dp * gy]
    call vm_path_args(e, nu, sy, hi, hk, ps, 1, merge(dps, d3, ps), s, qn, de, sig, sbar, q, dis, nused, dt)
    fd = 0.0_dp
    h = 1.0e-7_dp * ey
    do k = 1, 4
      if (k == 3) cycle
      de(k) = de(k) + h
      call vm_path_args(e, nu, sy, hi, hk, ps, 1, merge(dps, d3, ps), s, qn, de, sp, sbar, qq, dis, nused, fd)
      de(k) = de(k) - 2 * h
      call vm_path_args(e, nu, sy, hi, hk, ps, 1, merge(dps, d3, ps), s, qn, de, sm, sbar, qq, dis, nused, fd)
      de(k) = de(k) + h
      fd(:, k) = (sp - sm) / (2 * h)
    end do
    fd(:, 3) = dt(:, 3)
    write (nm, '(a,l1)') 'vm: consistent tangent vs FD, plane stress = ', ps
    call check(maxval(abs(fd - dt)) <= 1.0e-6_dp * e, trim(nm))
  end do

  ! sigma_c == 0 bit for bit on an elastic step from a hardened state.
  do j = 1, 2
    ps = j == 2
    call vm_path_args(e, nu, sy, hi, hk, ps, 8, merge(dps, d3, ps), sig, q, [-0.3_dp * ey, 0.1_dp * ey, 0.0_dp, -0.2_dp * gy], &
      s, sbar, qq, dis, nused, dt)
    write (nm, '(a,l1)') 'vm: elastic step, sigma_c == 0 exactly, nused = 0, plane stress = ', ps
    call check(all(2 * sbar - (sig + s) == 0.0_dp) .and. nused == 0 .and. all(qq(1:9) == q(1:9)), trim(nm))
  end do

  ! Non-proportional path from the virgin state (crosses yield, then turns): W_N against a
  ! reference N = 4096; the balance work = dstored + dissip; measured rate.
  do j = 1, 2
    ps = j == 2
    de = [3.0_dp * ey, -0.5_dp * ey, 0.0_dp, 4.0_dp * gy]
    qn = 0.0_dp
    s = 0.0_dp
    ! pre-shear to yield so the increment is non-proportional
    call vm_path_args(e, nu, sy, hi, hk, ps, 1, merge(dps, d3, ps), s, qn, [0.0_dp, 0.0_dp, 0.0_dp, 1.5_dp * gy], &
      sig, sbar, q, dis, nused, dt)
    s = sig
    qn = q
    st0 = vm_stored(e, nu, s)
    call vm_path_args(e, nu, sy, hi, hk, ps, 4096, merge(dps, d3, ps), s, qn, de, sig, sbar, q, dis, nused, dt)
    wref = dot_product(sbar, de)
    write (*, '(a,l1,a)') '# J2 non-proportional step (plane stress = ', ps, '): N, (W_N - W_4096)/W, balance residual'
    do k = 0, 9
      n = 2**k
      call vm_path_args(e, nu, sy, hi, hk, ps, n, merge(dps, d3, ps), s, qn, de, sig, sbar, q, dis, nused, dt)
      w = dot_product(sbar, de)
      st1 = vm_stored(e, nu, sig)
      werr(k) = abs(w - wref)
      write (*, '(a,i6,2es12.4)') '#   ', n, (w - wref) / wref, (w - (st1 - st0) - dis) / wref
      write (nm, '(a,l1,a,i0)') 'vm: work = dstored + dissip, plane stress = ', ps, ', N=', n
      call check_close(w, st1 - st0 + dis, 1.0e-11_dp, trim(nm))
    end do
    write (*, '(a,5f7.3)') '#   observed rates log2(e_N/e_2N), N = 16..256: ', (log(werr(k) / werr(k + 1)) / log(2.0_dp), k = 4, 8)
    write (nm, '(a,l1)') 'vm: non-proportional work converges at rate >= 1, plane stress = ', ps
    call check(log(werr(5) / werr(8)) / log(8.0_dp) >= 0.95_dp, trim(nm))
    ! AUTO
    n = plastic_auto_nsub(vm_trial_ratio(merge(dps, d3, ps), de, sy))
    call vm_path_args(e, nu, sy, hi, hk, ps, n, merge(dps, d3, ps), s, qn, de, sig, sbar, q, dis, nused, dt)
    write (*, '(a,i0,a,es10.3)') '#   AUTO N = ', n, ', relative work error ', abs(dot_product(sbar, de) - wref) / wref
    ! First-order convergence: the AUTO error is about c alpha / r; 5e-3 bounds it here with margin 1.6.
    write (nm, '(a,l1)') 'vm: AUTO relative work error < 5e-3, plane stress = ', ps
    call check(abs(dot_product(sbar, de) - wref) / wref < 5.0e-3_dp, trim(nm))
  end do

  call test_summary('law_von_mises')
contains

  !> vm_path with the constants given one by one and its result unpacked.
  subroutine vm_path_args(e, nu, sy, hi, hk, plane_stress, nsub, d_el, sig_n, q_n, deps, sig, sigbar, q, dissip, nused, dtan)
    real(dp), intent(in) :: e, nu, sy, hi, hk, d_el(4, 4), sig_n(4), q_n(:), deps(4)
    logical, intent(in) :: plane_stress
    integer, intent(in) :: nsub
    real(dp), intent(out) :: sig(4), sigbar(4), q(:), dissip, dtan(4, 4)
    integer, intent(out) :: nused
    type(law_step_t) :: r
    call vm_path(law_params_t(young=e, poisson=nu, yield=sy, h_iso=hi, h_kin=hk), plane_stress, nsub, 4, d_el, sig_n, &
      q_n, deps, q, r)
    sig = r%sig(1:4)
    sigbar = r%sigbar(1:4)
    dissip = r%dissip
    nused = r%nused
    dtan = r%dtan(1:4, 1:4)
  end subroutine vm_path_args
end program test_law_von_mises
