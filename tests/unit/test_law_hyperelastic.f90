!> The neo-Hookean law (law_hyperelastic) against its definition: S = dpsi/dE and the tangent =
!> dS/dE by central differences, the small-strain limit (the ELASTIC law's plane-strain D), the
!> discrete stress's exact energy identity S̄ . ΔE = Δpsi at any increment, and psi -> infinity as
!> J -> 0.
program test_law_hyperelastic
  use kinds, only: dp
  use law_hyperelastic, only: nh_lame, nh_energy, nh_stress, nh_tangent, nh_discrete_stress, nh_c33
  use testing, only: check, check_close, test_summary
  implicit none
  real(dp), parameter :: young = 2.0e6_dp, poisson = 0.45_dp
  real(dp) :: lm(2)

  lm = nh_lame(young, poisson)
  call test_derivatives()
  call test_small_strain()
  call test_discrete()
  call test_compression()
  call test_plane_stress()
  call test_summary('law_hyperelastic')

contains

  subroutine test_derivatives()
    real(dp) :: e(4), s(4), g(4), d(4, 4), dfd(4, 4), ep(4), em(4)
    real(dp), parameter :: h = 1e-7_dp
    integer :: k, cols(3)
    cols = [1, 2, 4]
    e = [0.3_dp, -0.12_dp, 0.0_dp, 0.25_dp]   ! [xx, yy, zz, 2xy]
    s = nh_stress(lm, e)
    d = nh_tangent(lm, e)
    do k = 1, 3
      ep = e
      em = e
      ep(cols(k)) = e(cols(k)) + h
      em(cols(k)) = e(cols(k)) - h
      g(cols(k)) = (nh_energy(lm, ep) - nh_energy(lm, em)) / (2 * h)
      dfd(:, cols(k)) = (nh_stress(lm, ep) - nh_stress(lm, em)) / (2 * h)
    end do
    call check(maxval(abs(s([1, 2, 4]) - g([1, 2, 4]))) <= 1e-7_dp * maxval(abs(s)), &
      'neo-Hookean: S = dpsi/dE (xx, yy, 2xy: central differences)')
    call check(maxval(abs(d(:, [1, 2, 4]) - dfd(:, [1, 2, 4]))) <= 1e-6_dp * maxval(abs(d)), &
      'neo-Hookean: tangent = dS/dE (central differences)')
    call check(maxval(abs(d([1, 2, 4], [1, 2, 4]) - transpose(d([1, 2, 4], [1, 2, 4])))) <= 1e-9_dp * maxval(abs(d)), &
      'neo-Hookean: tangent symmetric')
  end subroutine test_derivatives

  !> At E = 0 the tangent is the plane-strain elastic D (lambda + 2 mu, lambda, mu), and at a
  !> strain of 1e-8 the stress is D E to 1e-7 relative and psi = ½ E.D E to 1e-7.
  subroutine test_small_strain()
    real(dp) :: d(4, 4), e(4), s(4)
    d = nh_tangent(lm, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp])
    call check(abs(d(1, 1) - (lm(1) + 2 * lm(2))) + abs(d(1, 2) - lm(1)) + abs(d(4, 4) - lm(2)) <= 1e-9_dp * lm(1), &
      'neo-Hookean: tangent at E = 0 = the ELASTIC plane-strain D')
    e = 1e-8_dp * [1.0_dp, -0.5_dp, 0.0_dp, 0.7_dp]
    s = nh_stress(lm, e)
    call check(maxval(abs(s - matmul(d, e))) <= 1e-7_dp * maxval(abs(s)), 'neo-Hookean: S = D E at a strain of 1e-8')
    call check_close(nh_energy(lm, e), 0.5_dp * dot_product(e, matmul(d, e)), 1e-7_dp, &
      'neo-Hookean: psi = ½ E.D E at a strain of 1e-8 (no cancellation)')
  end subroutine test_small_strain

  !> S̄ . ΔE = Δpsi for a large step, a small one and a tiny one, and S̄ -> S(E_mid).
  subroutine test_discrete()
    real(dp) :: en(4), e1(4), sb(4), dpsi
    real(dp) :: sizes(3) = [0.2_dp, 1e-4_dp, 1e-9_dp]
    integer :: k
    en = [0.1_dp, -0.05_dp, 0.0_dp, 0.08_dp]
    do k = 1, 3
      e1 = en + sizes(k) * [1.0_dp, 0.6_dp, 0.0_dp, -0.9_dp]
      sb = nh_discrete_stress(lm, en, e1)
      dpsi = nh_energy(lm, e1) - nh_energy(lm, en)
      call check(abs(dot_product(sb, e1 - en) - dpsi) <= 1e-13_dp * abs(nh_energy(lm, e1)) + 1e-12_dp * abs(dpsi), &
        'neo-Hookean: S̄ . ΔE = Δpsi, |ΔE| ~ ' // trim(adjustl(num(sizes(k)))))
    end do
    e1 = en + 1e-5_dp * [1.0_dp, 0.6_dp, 0.0_dp, -0.9_dp]
    sb = nh_discrete_stress(lm, en, e1)
    call check(maxval(abs(sb - nh_stress(lm, 0.5_dp * (en + e1)))) <= 1e-8_dp * maxval(abs(sb)), &
      'neo-Hookean: S̄ -> S(E_mid) for a small step (the correction is O(|ΔE|²))')
  end subroutine test_discrete

  !> Squashing to J = 1e-3 costs more energy than any finite amount the linear law would give.
  subroutine test_compression()
    real(dp) :: e(4), s(4)
    real(dp) :: stretch
    stretch = 1e-3_dp     ! uniaxial, plane strain: F = diag(stretch, 1)
    e = [0.5_dp * (stretch**2 - 1.0_dp), 0.0_dp, 0.0_dp, 0.0_dp]
    s = nh_stress(lm, e)
    call check(nh_energy(lm, e) > 20.0_dp * lm(2) .and. s(1) < -1e5_dp * lm(2), &
      'neo-Hookean: squashed to J = 1e-3, energy and compressive stress grow without bound')
  end subroutine test_compression

  !> Plane stress: C33 makes S33 = 0 (checked on the 3D stress mu (1 - 1/c) + lambda ln J / c),
  !> S = dpsi/dE and the tangent = dS/dE by central differences, the small-strain limit (the
  !> plane-stress elastic D), and the discrete stress's exact identity.
  subroutine test_plane_stress()
    real(dp) :: e(4), s(4), g(4), d(4, 4), dfd(4, 4), ep(4), em(4), c, lnj, en(4), sb(4), e0
    real(dp), parameter :: h = 1e-7_dp
    integer :: k, cols(3)
    cols = [1, 2, 4]
    e = [0.3_dp, -0.12_dp, 0.0_dp, 0.25_dp]
    c = 1.0_dp + nh_c33(lm, e)
    lnj = 0.5_dp * log(((1 + 2 * e(1)) * (1 + 2 * e(2)) - e(4)**2) * c)
    call check(abs(lm(2) * (1 - 1 / c) + lm(1) * lnj / c) <= 1e-12_dp * lm(1), 'neo-Hookean plane stress: S33 = 0 at C33')
    s = nh_stress(lm, e, .true.)
    d = nh_tangent(lm, e, .true.)
    do k = 1, 3
      ep = e
      em = e
      ep(cols(k)) = e(cols(k)) + h
      em(cols(k)) = e(cols(k)) - h
      g(cols(k)) = (nh_energy(lm, ep, .true.) - nh_energy(lm, em, .true.)) / (2 * h)
      dfd(:, cols(k)) = (nh_stress(lm, ep, .true.) - nh_stress(lm, em, .true.)) / (2 * h)
    end do
    call check(maxval(abs(s([1, 2, 4]) - g([1, 2, 4]))) <= 1e-7_dp * maxval(abs(s)) .and. s(3) == 0.0_dp, &
      'neo-Hookean plane stress: S = dpsi/dE, S33 = 0')
    call check(maxval(abs(d(:, [1, 2, 4]) - dfd(:, [1, 2, 4]))) <= 1e-6_dp * maxval(abs(d)), &
      'neo-Hookean plane stress: tangent = dS/dE (central differences)')
    d = nh_tangent(lm, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp], .true.)
    e0 = young / (1 - poisson**2)
    call check(abs(d(1, 1) - e0) + abs(d(1, 2) - poisson * e0) + abs(d(4, 4) - lm(2)) <= 1e-9_dp * e0, &
      'neo-Hookean plane stress: tangent at E = 0 = E/(1 - nu^2) [1 nu; nu 1], mu')
    en = [0.1_dp, -0.05_dp, 0.0_dp, 0.08_dp]
    e = en + 0.2_dp * [1.0_dp, 0.6_dp, 0.0_dp, -0.9_dp]
    sb = nh_discrete_stress(lm, en, e, .true.)
    call check(abs(dot_product(sb, e - en) - (nh_energy(lm, e, .true.) - nh_energy(lm, en, .true.))) <= &
      1e-13_dp * nh_energy(lm, e, .true.), 'neo-Hookean plane stress: S̄ . ΔE = Δpsi for a large step')
  end subroutine test_plane_stress

  function num(x) result(t)
    real(dp), intent(in) :: x
    character(len=16) :: t
    write (t, '(es9.1)') x
  end function num
end program test_law_hyperelastic
