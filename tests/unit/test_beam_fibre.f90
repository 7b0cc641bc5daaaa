!> Fibre section of a BEAM2: exact midpoint-rule sums (sum A_f = A, sum y_f^2 A_f =
!> b h^3/12 (1 - 1/n^2)), the elastic-perfectly-plastic moment-curvature curve of a rectangle
!> M = M_e (3/2) (1 - (kappa_e/kappa)^2 / 3) converging with the number of layers, N = 0 in pure
!> bending, sigma_c = 0 bit for bit on elastic steps, tangent vs finite differences, the energy
!> balance, and nonlinear-elastic layers whose work error is the exact Euler-Maclaurin sum.
program test_beam_fibre
  use kinds, only: dp
  use testing, only: check, check_close, test_summary
  use section, only: section_t
  use beam_fibre, only: FIB_PLASTIC, FIB_NONLINEAR, fibre_layer, fibre_elastic_matrix, fibre_nstate, fibre_update, &
                        fibre_stored
  use law_nonlinear_elastic, only: nle_energy, nle_tangent
  use law_types, only: law_params_t, law_step_t
  implicit none

  real(dp), parameter :: e = 200.0e9_dp, sy = 250.0e6_dp, hgt = 0.2_dp, wid = 0.1_dp
  real(dp), parameter :: me = sy * wid * hgt**2 / 6, ke = 2 * sy / (e * hgt)
  type(section_t) :: sec
  real(dp) :: d(2, 2), sig(2), sbar(2), dt(2, 2), dis, s(2), eps(2), kap, err, errs(5), fd(2, 2), sp(2), sm(2)
  real(dp) :: de(2), h, w, pred, y, a, st0, st1
  real(dp), allocatable :: q(:), qn(:)
  integer :: il, i, k, nused, nl, n
  character(len=80) :: nm

  sec%area = wid * hgt
  sec%height = hgt
  do il = 1, 3
    sec%layers = 4**il
    call fibre_elastic_matrix(e, sec, d)
    call check_close(d(1, 1), e * sec%area, 1.0e-14_dp, 'fibre: sum E A_f = E A')
    call check_close(d(2, 2), e * wid * hgt**3 / 12 * (1 - 1.0_dp / sec%layers**2), 1.0e-13_dp, &
      'fibre: sum E y^2 A_f = E b h^3/12 (1 - 1/n^2) (midpoint rule)')
  end do

  ! Moment-curvature, perfectly plastic, kappa from 0 to 5 kappa_e in 50 steps (N = 1).
  write (*, '(a)') '# fibre M-kappa: layers, max |M - M_exact| / M_p over kappa in [0, 5 kappa_e]'
  do il = 1, 5
    nl = 5 * 2**il
    sec%layers = nl
    if (allocated(q)) deallocate (q, qn)
    allocate (q(fibre_nstate(FIB_PLASTIC, sec)), qn(fibre_nstate(FIB_PLASTIC, sec)))
    qn = 0.0_dp
    s = 0.0_dp
    eps = 0.0_dp
    err = 0.0_dp
    do i = 1, 50
      de = [0.0_dp, 0.1_dp * ke]
      call fibre_update_args(FIB_PLASTIC, e, 0.0_dp, sy, 0.0_dp, 0.0_dp, sec, 1, eps, de, s, qn, sig, sbar, q, dis, nused, dt)
      eps = eps + de
      s = sig
      qn = q
      kap = eps(2)
      err = max(err, abs(s(2) - m_exact(kap)) / (1.5_dp * me))
    end do
    errs(il) = err
    write (*, '(a,i6,es12.4)') '#   ', nl, err
    call check(abs(s(1)) <= 1.0e-12_dp * sy * sec%area, 'fibre: pure bending keeps N = 0')
  end do
  write (*, '(a,4f7.3)') '#   observed rates log2(e_n/e_2n): ', (log(errs(k) / errs(k + 1)) / log(2.0_dp), k = 1, 4)
  call check(errs(5) < 1.0e-3_dp, 'fibre: M-kappa within 1e-3 M_p with 160 layers')
  call check(log(errs(1) / errs(5)) / log(16.0_dp) >= 1.5_dp, 'fibre: M-kappa error converges with layers (rate >= 1.5)')

  ! Tangent vs FD and energy balance, hardening, axial + bending, from a plastic state.
  sec%layers = 16
  deallocate (q, qn)
  allocate (q(fibre_nstate(FIB_PLASTIC, sec)), qn(fibre_nstate(FIB_PLASTIC, sec)))
  qn = 0.0_dp
  call fibre_update_args(FIB_PLASTIC, e, 0.0_dp, sy, 4.0e9_dp, 6.0e9_dp, sec, 1, [0.0_dp, 0.0_dp], [0.3_dp * sy / e, 2 * ke], &
    [0.0_dp, 0.0_dp], qn, s, sbar, q, dis, nused, dt)
  qn = q
  eps = [0.3_dp * sy / e, 2 * ke]
  de = [-0.1_dp * sy / e, 1.3_dp * ke]
  st0 = fibre_stored(FIB_PLASTIC, e, 0.0_dp, sec, eps, qn)
  do n = 1, 64, 9
    call fibre_update_args(FIB_PLASTIC, e, 0.0_dp, sy, 4.0e9_dp, 6.0e9_dp, sec, n, eps, de, s, qn, sig, sbar, q, dis, nused, dt)
    st1 = fibre_stored(FIB_PLASTIC, e, 0.0_dp, sec, eps + de, q)
    w = dot_product(sbar, de)
    write (nm, '(a,i0)') 'fibre: work = dstored + dissip, N=', n
    call check_close(w, st1 - st0 + dis, 1.0e-12_dp, trim(nm))
  end do
  h = 1.0e-7_dp
  call fibre_update_args(FIB_PLASTIC, e, 0.0_dp, sy, 4.0e9_dp, 6.0e9_dp, sec, 1, eps, de, s, qn, sig, sbar, q, dis, nused, dt)
  do k = 1, 2
    de(k) = de(k) * (1 + h)
    call fibre_update_args(FIB_PLASTIC, e, 0.0_dp, sy, 4.0e9_dp, 6.0e9_dp, sec, 1, eps, de, s, qn, sp, sbar, q, dis, nused, fd)
    de(k) = de(k) / (1 + h) * (1 - h)
    call fibre_update_args(FIB_PLASTIC, e, 0.0_dp, sy, 4.0e9_dp, 6.0e9_dp, sec, 1, eps, de, s, qn, sm, sbar, q, dis, nused, fd)
    de(k) = de(k) / (1 - h)
    fd(:, k) = (sp - sm) / (2 * h * de(k))
  end do
  call fibre_update_args(FIB_PLASTIC, e, 0.0_dp, sy, 4.0e9_dp, 6.0e9_dp, sec, 1, eps, de, s, qn, sig, sbar, q, dis, nused, dt)
  call check(abs(fd(1, 1) - dt(1, 1)) <= 1.0e-6_dp * dt(1, 1) .and. abs(fd(2, 2) - dt(2, 2)) <= 1.0e-6_dp * dt(2, 2) &
    .and. abs(fd(1, 2) - dt(1, 2)) <= 1.0e-6_dp * sqrt(dt(1, 1) * dt(2, 2)) &
    .and. abs(fd(2, 1) - dt(2, 1)) <= 1.0e-6_dp * sqrt(dt(1, 1) * dt(2, 2)), 'fibre: consistent tangent vs FD')

  ! Elastic step from the plastic state (small unloading): sigma_c == 0 bit for bit, nused = 0.
  call fibre_update_args(FIB_PLASTIC, e, 0.0_dp, sy, 4.0e9_dp, 6.0e9_dp, sec, 7, eps + de, [0.0_dp, -0.05_dp * ke], sig, q, &
    s, sbar, qn, dis, nused, dt)
  call fibre_elastic_matrix(e, sec, d)
  call check(all(2 * sbar - (sig + s) == 0.0_dp) .and. nused == 0 .and. all(s == sig + matmul(d, [0.0_dp, -0.05_dp * ke])), &
    'fibre: elastic step: sig = sig_n + D deps, sigma_c == 0 exactly, nused = 0')

  ! Nonlinear-elastic layers: exact work error sum_f A_f (deps_f/N)^2/12 (sigma'(e1) - sigma'(e0)).
  sec%layers = 8
  eps = [0.002_dp, 0.1_dp]
  de = [0.01_dp, 0.3_dp]
  call check(fibre_nstate(FIB_NONLINEAR, sec) == 0, 'fibre: nonlinear elastic layers have no state')
  do n = 1, 16, 5
    pred = 0.0_dp
    do i = 1, sec%layers
      call fibre_layer(sec, i, y, a)
      pred = pred + a * ((nle_energy(e, 300.0_dp, eps(1) + de(1) - y * (eps(2) + de(2))) &
        - nle_energy(e, 300.0_dp, eps(1) - y * eps(2))) + ((de(1) - y * de(2)) / n)**2 / 12 &
        * (nle_tangent(e, 300.0_dp, eps(1) + de(1) - y * (eps(2) + de(2))) - nle_tangent(e, 300.0_dp, eps(1) - y * eps(2))))
    end do
    s = 0.0_dp
    call fibre_update_args(FIB_NONLINEAR, e, 300.0_dp, sy, 0.0_dp, 0.0_dp, sec, n, eps, de, s, qn, sig, sbar, q, dis, nused, dt)
    write (nm, '(a,i0)') 'fibre: nonlinear elastic W_N = dpsi + exact trapezoid error, N=', n
    call check_close(dot_product(sbar, de), pred, 1.0e-10_dp, trim(nm))
  end do

  call test_summary('beam_fibre')

contains

  pure real(dp) function m_exact(k)
    real(dp), intent(in) :: k
    if (abs(k) <= ke) then
      m_exact = e * wid * hgt**3 / 12 * k
    else
      m_exact = me * 1.5_dp * (1 - (ke / k)**2 / 3)
    end if
  end function m_exact
  !> fibre_update with the constants given one by one and its result unpacked.
  subroutine fibre_update_args(kind, e, b, sy, hi, hk, sec, nsub, eps_n, deps, sig_n, q_n, sig, sigbar, q, dissip, nused, dtan)
    integer, intent(in) :: kind, nsub
    real(dp), intent(in) :: e, b, sy, hi, hk, eps_n(2), deps(2), sig_n(2), q_n(:)
    type(section_t), intent(in) :: sec
    real(dp), intent(out) :: sig(2), sigbar(2), q(:), dissip, dtan(2, 2)
    integer, intent(out) :: nused
    type(law_step_t) :: r
    call fibre_update(kind, law_params_t(young=e, nl_b=b, yield=sy, h_iso=hi, h_kin=hk), sec, nsub, eps_n, deps, sig_n, &
      q_n, q, r)
    sig = r%sig(1:2)
    sigbar = r%sigbar(1:2)
    dissip = r%dissip
    nused = r%nused
    dtan = r%dtan(1:2, 1:2)
  end subroutine fibre_update_args
end program test_beam_fibre
