!> The material_law dispatcher: names and codes, state sizes, parameter checks, the elastic
!> matrix (identical to elements' elem_elastic_d, fibre-integrated for layered beams),
!> ELASTIC sigma_c == 0 bit for bit for any N, dispatch to the kernels (same numbers as calling
!> them directly), AUTO resolution (nused follows the documented rule), recoverable energies
!> against closed forms, and the work/balance identities through the interface.
program test_material_law
  use kinds, only: dp
  use testing, only: check, check_close, test_summary
  use section, only: section_t
  use element_traits, only: ET_BAR2, ET_BEAM2, ET_QUAD4
  use elements, only: elem_elastic_d
  use errors, only: STAT_OK
  use material_law, only: material_t, law_update, law_is_linear, law_nstate, law_name, law_code, law_check, &
                          law_stored, law_elastic_matrix, LAW_ELASTIC, LAW_NONLINEAR_ELASTIC, LAW_ELASTOPLASTIC, &
                          LAW_VON_MISES, PK_1D, PK_BEAM, PK_PSTRAIN, PK_PSTRESS
  use law_plastic_1d, only: plastic_1d_path, plastic_auto_nsub
  use law_nonlinear_elastic, only: nle_energy, nle_auto_nsub
  use law_von_mises, only: vm_trial_ratio
  use law_types, only: law_params_t, law_step_t
  implicit none

  type(material_t) :: mat
  type(section_t) :: sec, fib
  real(dp) :: d(4, 4), d2(4, 4), sig(4), sbar(4), dt(4, 4), work, dis, q(64), qn(64), s1, sb1, q1(3), dis1, et
  real(dp) :: eps(4), de(4), sn(4)
  integer :: k, nused, n1, stat
  character(len=:), allocatable :: msg

  mat%young = 2.0e11_dp
  mat%poisson = 0.3_dp
  sec%area = 0.02_dp
  sec%inertia = 7.0e-5_dp
  sec%height = 0.2_dp
  fib = sec
  fib%layers = 10

  ! Names.
  do k = LAW_ELASTIC, LAW_VON_MISES
    call check(law_code(law_name(k)) == k, 'ml: law_code(law_name(k)) = k for ' // law_name(k))
  end do
  call check(law_code('PLASTIC') == 0, 'ml: unknown law name -> 0')

  ! Elastic matrix = elem_elastic_d bit for bit; fibre beam integrated.
  call law_elastic_matrix(mat, sec, PK_1D, d)
  call elem_elastic_d(ET_BAR2, mat%young, mat%poisson, sec, d2)
  call check(all(d(1:1, 1:1) == d2(1:1, 1:1)), 'ml: elastic matrix PK_1D = elem_elastic_d')
  call law_elastic_matrix(mat, sec, PK_BEAM, d)
  call elem_elastic_d(ET_BEAM2, mat%young, mat%poisson, sec, d2)
  call check(all(d(1:2, 1:2) == d2(1:2, 1:2)), 'ml: elastic matrix PK_BEAM (layers = 0) = elem_elastic_d')
  call law_elastic_matrix(mat, sec, PK_PSTRAIN, d)
  call elem_elastic_d(ET_QUAD4, mat%young, mat%poisson, sec, d2)
  call check(all(d == d2), 'ml: elastic matrix PK_PSTRAIN = elem_elastic_d')
  sec%plane_stress = .true.
  call law_elastic_matrix(mat, sec, PK_PSTRESS, d)
  call elem_elastic_d(ET_QUAD4, mat%young, mat%poisson, sec, d2)
  call check(all(d == d2), 'ml: elastic matrix PK_PSTRESS = elem_elastic_d')
  sec%plane_stress = .false.
  call law_elastic_matrix(mat, fib, PK_BEAM, d)
  call check_close(d(2, 2), mat%young * fib%area * fib%height**2 / 12 * (1 - 1.0_dp / 100), 1.0e-13_dp, &
    'ml: fibre beam elastic matrix E b h^3/12 (1 - 1/n^2)')

  ! ELASTIC: sigma_c == 0 exactly for any nsub; linear; no state; nused = 0; tangent = D.
  call check(law_is_linear(mat) .and. law_nstate(mat, PK_PSTRAIN, sec) == 0, 'ml: ELASTIC linear, no state')
  call law_elastic_matrix(mat, sec, PK_PSTRAIN, d)
  sn = [1.0e6_dp, -3.0e5_dp, 2.0e5_dp, 7.0e5_dp]
  de = [1.0e-4_dp, 3.0e-5_dp, 0.0_dp, -2.0e-4_dp]
  do k = 0, 3
    call law_update_args(mat, sec, PK_PSTRAIN, d, k, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], de, sn, qn(1:0), sig, sbar, q(1:0), &
      work, dis, nused, dt)
    call check(all(2 * sbar - (sn + sig) == 0.0_dp) .and. nused == 0 .and. all(dt == d) .and. dis == 0.0_dp, &
      'ml: ELASTIC sigma_c == 0 bit for bit, nsub = ' // achar(48 + k))
  end do
  call check_close(work, dot_product(sn + 0.5_dp * matmul(d, de), de), 1.0e-14_dp, 'ml: ELASTIC work = sigbar . deps')
  ! old call form (no nused, no dtan) still works
  call law_elastic_matrix(mat, sec, PK_1D, d)
  call law_update_args(mat, sec, PK_1D, d, 1, [0.0_dp], [1.0e-3_dp], [0.0_dp], qn(1:0), sig(1:1), sbar(1:1), q(1:0), work, dis)
  call check_close(work, 0.5_dp * mat%young * 1.0e-6_dp, 1.0e-14_dp, 'ml: legacy call without nused/dtan')

  ! ELASTOPLASTIC 1D: same as the kernel; AUTO resolves to the documented rule.
  mat%law = LAW_ELASTOPLASTIC
  mat%yield = 2.5e8_dp
  mat%h_iso = 2.0e9_dp
  mat%h_kin = 3.0e9_dp
  call check(.not. law_is_linear(mat) .and. law_nstate(mat, PK_1D, sec) == 3 .and. law_nstate(mat, PK_BEAM, fib) == 30, &
    'ml: ELASTOPLASTIC state sizes 3 (1D) and 3 per layer (beam)')
  qn = 0.0_dp
  call law_update_args(mat, sec, PK_1D, d, 0, [0.0_dp], [4.0e-3_dp], [0.0_dp], qn(1:3), sig(1:1), sbar(1:1), q(1:3), &
    work, dis, nused, dt)
  n1 = plastic_auto_nsub(mat%young * 4.0e-3_dp / mat%yield)
  call plastic_1d_path(lp(mat%young, mat%yield, mat%h_iso, mat%h_kin), n1, 0.0_dp, qn(1:3), 4.0e-3_dp, s1, sb1, q1, dis1, &
    k, et)
  call check(nused == n1 .and. sig(1) == s1 .and. sbar(1) == sb1 .and. dis == dis1 .and. dt(1, 1) == et, &
    'ml: ELASTOPLASTIC PK_1D AUTO = kernel with N = ceil(E deps / (alpha sy))')
  call check_close(law_stored(mat, sec, PK_1D, d, [4.0e-3_dp], sig, q), 0.5_dp * sig(1)**2 / mat%young, 1.0e-15_dp, &
    'ml: ELASTOPLASTIC stored = sigma^2/(2E)')
  call check_close(work, law_stored(mat, sec, PK_1D, d, [4.0e-3_dp], sig, q) + dis, 1.0e-13_dp, &
    'ml: ELASTOPLASTIC work = dstored + dissip from the virgin state')

  ! Fibre beam through the interface: elastic step gives sigma_c == 0, nused = 0.
  call law_elastic_matrix(mat, fib, PK_BEAM, d)
  qn = 0.0_dp
  call law_update_args(mat, fib, PK_BEAM, d, 4, [0.0_dp, 0.0_dp], [1.0e-4_dp, 1.0e-3_dp], [0.0_dp, 0.0_dp], qn(1:30), &
    sig(1:2), sbar(1:2), q(1:30), work, dis, nused, dt)
  call check(all(2 * sbar(1:2) - sig(1:2) == 0.0_dp) .and. nused == 0 .and. all(dt(1:2, 1:2) == d(1:2, 1:2)), &
    'ml: fibre beam elastic step, sigma_c == 0 bit for bit')
  call law_update_args(mat, fib, PK_BEAM, d, 4, [0.0_dp, 0.0_dp], [1.0e-3_dp, 0.1_dp], [0.0_dp, 0.0_dp], qn(1:30), &
    sig(1:2), sbar(1:2), q(1:30), work, dis, nused, dt)
  call check(nused == 4 .and. dis > 0.0_dp, 'ml: fibre beam plastic step uses the fixed N and dissipates')
  call check_close(work, law_stored(mat, fib, PK_BEAM, d, [1.0e-3_dp, 0.1_dp], sig, q) + dis, 1.0e-12_dp, &
    'ml: fibre beam work = stored + dissip from the virgin state')

  ! NONLINEAR_ELASTIC 1D: stored = psi; AUTO = nle rule.
  mat%law = LAW_NONLINEAR_ELASTIC
  mat%nl_b = 200.0_dp
  call law_update_args(mat, sec, PK_1D, d, 0, [0.01_dp], [0.04_dp], [0.0_dp], qn(1:0), sig(1:1), sbar(1:1), q(1:0), &
    work, dis, nused)
  call check(nused == nle_auto_nsub(mat%young, mat%nl_b, 0.01_dp, 0.04_dp), 'ml: NONLINEAR_ELASTIC AUTO = nle rule')
  call check_close(law_stored(mat, sec, PK_1D, d, [0.05_dp], sig, q), nle_energy(mat%young, mat%nl_b, 0.05_dp), &
    1.0e-15_dp, 'ml: NONLINEAR_ELASTIC stored = psi(eps)')

  ! VON_MISES: AUTO = plastic rule on the von Mises trial ratio; stored energy = 1/2 sigma.eps
  ! on an elastic state (plane strain).
  mat%law = LAW_VON_MISES
  call check(law_nstate(mat, PK_PSTRAIN, sec) == 10 .and. law_nstate(mat, PK_PSTRESS, sec) == 10, 'ml: VON_MISES 10 states')
  call law_elastic_matrix(mat, sec, PK_PSTRAIN, d)
  qn = 0.0_dp
  de = [3.0e-3_dp, -1.0e-3_dp, 0.0_dp, 2.0e-3_dp]
  call law_update_args(mat, sec, PK_PSTRAIN, d, 0, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], de, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], &
    qn(1:10), sig, sbar, q(1:10), work, dis, nused)
  call check(nused == plastic_auto_nsub(vm_trial_ratio(d, de, mat%yield)), 'ml: VON_MISES AUTO = plastic rule')
  eps = [1.0e-4_dp, -2.0e-4_dp, 0.0_dp, 3.0e-4_dp]
  sig = matmul(d, eps)
  call check_close(law_stored(mat, sec, PK_PSTRAIN, d, eps, sig, q), 0.5_dp * dot_product(sig, eps), 1.0e-13_dp, &
    'ml: VON_MISES stored = 1/2 sigma.eps on an elastic state (plane strain)')
  sec%plane_stress = .true.
  call law_elastic_matrix(mat, sec, PK_PSTRESS, d)
  sig = matmul(d, eps)
  call check_close(law_stored(mat, sec, PK_PSTRESS, d, eps, sig, q), 0.5_dp * dot_product(sig, eps), 1.0e-13_dp, &
    'ml: VON_MISES stored = 1/2 sigma.eps on an elastic state (plane stress)')
  sec%plane_stress = .false.

  ! law_check.
  call law_check(mat, PK_1D, sec, stat, msg)
  call check(stat /= STAT_OK, 'ml: law_check rejects VON_MISES on a bar: ' // msg)
  mat%law = LAW_ELASTOPLASTIC
  call law_check(mat, PK_BEAM, sec, stat, msg)
  call check(stat /= STAT_OK, 'ml: law_check rejects ELASTOPLASTIC beam without layers: ' // msg)
  call law_check(mat, PK_BEAM, fib, stat, msg)
  call check(stat == STAT_OK, 'ml: law_check accepts ELASTOPLASTIC layered beam')
  mat%yield = 0.0_dp
  call law_check(mat, PK_1D, sec, stat, msg)
  call check(stat /= STAT_OK, 'ml: law_check rejects YIELD = 0: ' // msg)
  mat%law = LAW_ELASTIC
  call law_check(mat, PK_PSTRESS, sec, stat, msg)
  call check(stat == STAT_OK, 'ml: law_check accepts ELASTIC on quads')
  mat%poisson = 0.5_dp
  call law_check(mat, PK_PSTRAIN, sec, stat, msg)
  call check(stat /= STAT_OK, 'ml: law_check rejects POISSON = 0.5 on quads: ' // msg)

  call test_summary('material_law')
contains

  !> The constants of a 1D plastic law, given one by one.
  pure function lp(e, sy, hi, hk) result(p)
    real(dp), intent(in) :: e, sy, hi, hk
    type(law_params_t) :: p
    p = law_params_t(young=e, yield=sy, h_iso=hi, h_kin=hk)
  end function lp

  !> law_update with its result unpacked (r%sig, r%sigbar, r%work, r%dissip, r%nused, r%dtan).
  subroutine law_update_args(mat, sec, pk, d, nsub, eps_n, deps, sig_n, q_n, sig, sigbar, q, work, dissip, nused, dtan)
    type(material_t), intent(in) :: mat
    type(section_t), intent(in) :: sec
    integer, intent(in) :: pk, nsub
    real(dp), intent(in) :: d(:, :), eps_n(:), deps(:), sig_n(:), q_n(:)
    real(dp), intent(out) :: sig(:), sigbar(:), q(:), work, dissip
    integer, intent(out), optional :: nused
    real(dp), intent(out), optional :: dtan(:, :)
    type(law_step_t) :: r
    call law_update(mat, sec, pk, d, nsub, eps_n, deps, sig_n, q_n, q, r)
    sig = r%sig(1:size(sig))
    sigbar = r%sigbar(1:size(sigbar))
    work = r%work
    dissip = r%dissip
    if (present(nused)) nused = r%nused
    if (present(dtan)) dtan = r%dtan(1:size(dtan, 1), 1:size(dtan, 2))
  end subroutine law_update_args
end program test_material_law
