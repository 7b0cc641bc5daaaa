!> The logarithmic strain of STRAIN_MEASURE LOG (log_strain) against closed forms and finite differences:
!> ℓ = ½ ln C on a stretch and on a stretch turned (ℓ turns with it), a small strain keeping its
!> digits, P = dℓ/dE, the material tangent of the Hencky law (dS/dE with S = P' D ℓ), and the
!> step stress of Gonzalez's term (S̄·ΔE = w exactly; round-off left out).
program test_log_strain
  use kinds, only: dp
  use log_strain, only: hencky_strain, log_tangent
  use law_hyperelastic, only: gonzalez_stress
  use testing, only: check, check_close, test_summary
  use lapack_pure, only: dsyev
  implicit none
  real(dp) :: d(4, 4)

  ! Plane-strain elastic D (E = 200, nu = 0.3) on [xx, yy, zz, 2xy].
  d = 0.0_dp
  d(1:3, 1:3) = 115.38461538461539_dp
  d(1, 1) = 269.23076923076923_dp
  d(2, 2) = d(1, 1)
  d(3, 3) = d(1, 1)
  d(4, 4) = 76.923076923076923_dp
  call test_closed_forms()
  call test_derivative()
  call test_tangent()
  call test_hoop()
  call test_gonzalez()
  call test_summary('log_strain')

contains

  !> The Green-Lagrange strain of the stretch diag(a, b) turned by phi, as Voigt [xx, yy, 0, 2xy].
  pure function green_of(a, b, phi) result(e)
    real(dp), intent(in) :: a, b, phi
    real(dp) :: e(4), c, s, cm(2, 2), r(2, 2)
    c = cos(phi)
    s = sin(phi)
    r = reshape([c, s, -s, c], [2, 2])
    cm = matmul(r, matmul(reshape([a * a, 0.0_dp, 0.0_dp, b * b], [2, 2]), transpose(r)))
    e = [0.5_dp * (cm(1, 1) - 1.0_dp), 0.5_dp * (cm(2, 2) - 1.0_dp), 0.0_dp, cm(1, 2)]
  end function green_of

  !> ℓ of diag(2, 0.6) is diag(ln 2, ln 0.6); turned by 0.7 rad it turns with it; a strain of 1e-9
  !> keeps its digits (ℓ = E - E² + ...).
  subroutine test_closed_forms()
    real(dp) :: l(4), p(4, 4), c, s, lx(4)
    logical :: ok
    call hencky_strain(green_of(2.0_dp, 0.6_dp, 0.0_dp), l, p, ok)
    call check(ok .and. abs(l(1) - log(2.0_dp)) <= 1e-15_dp .and. abs(l(2) - log(0.6_dp)) <= 1e-15_dp .and. &
      abs(l(4)) <= 1e-15_dp, 'hencky: stretch diag(2, 0.6) -> diag(ln 2, ln 0.6)')
    call hencky_strain(green_of(2.0_dp, 0.6_dp, 0.7_dp), l, p, ok)
    c = cos(0.7_dp)
    s = sin(0.7_dp)
    lx = [c * c * log(2.0_dp) + s * s * log(0.6_dp), s * s * log(2.0_dp) + c * c * log(0.6_dp), 0.0_dp, &
      2.0_dp * c * s * (log(2.0_dp) - log(0.6_dp))]
    call check(ok .and. maxval(abs(l - lx)) <= 1e-15_dp, 'hencky: the stretch turned by 0.7 rad, ℓ turned with it')
    call hencky_strain([1e-9_dp, -3e-9_dp, 0.0_dp, 2e-9_dp], l, p, ok)
    call check(maxval(abs(l - [1e-9_dp - 2e-18_dp, -3e-9_dp - 1e-17_dp, 0.0_dp, 2e-9_dp + 4e-18_dp])) <= 1e-24_dp, &
      'hencky: a strain of 1e-9 keeps its digits (ℓ = E - E² to 1e-15 relative)')
    call hencky_strain([1.0_dp, -0.5_dp, 0.0_dp, 0.0_dp], l, p, ok)
    call check(.not. ok .and. all(l == 0.0_dp), 'hencky: C singular (a stretch of 0) is reported, no NaN')
  end subroutine test_closed_forms

  !> P = dℓ/dE by central differences, at a sheared and stretched state and at an isotropic one
  !> (equal eigenvalues: the divided difference's limit).
  subroutine test_derivative()
    real(dp) :: e(4), l(4), p(4, 4), lp(4), lm(4), pd(4, 4), q(4, 4), h
    logical :: ok
    integer :: k, m
    h = 1e-6_dp
    do m = 1, 2
      if (m == 1) e = green_of(1.7_dp, 0.8_dp, 0.4_dp)
      if (m == 2) e = green_of(1.3_dp, 1.3_dp, 0.0_dp)
      call hencky_strain(e, l, p, ok)
      do k = 1, 4
        if (k == 3) cycle
        call hencky_strain(e + h * unit(k), lp, q, ok)
        call hencky_strain(e - h * unit(k), lm, q, ok)
        pd(:, k) = (lp - lm) / (2.0_dp * h)
      end do
      pd(:, 3) = p(:, 3)
      call check(maxval(abs(p - pd)) <= 1e-9_dp, merge('hencky: P = dℓ/dE (central differences), sheared  ', &
        'hencky: P = dℓ/dE, equal eigenvalues              ', m == 1))
    end do
  end subroutine test_derivative

  !> The Hencky law's S = P'D ℓ: log_tangent = dS/dE by central differences at a moderate stretch
  !> (the log map's term softens the tension); at a large
  !> stretch the Hencky material's own tangent is indefinite, and log_tangent keeps its positive part.
  subroutine test_tangent()
    real(dp) :: e(4), l(4), p(4, 4), dm(4, 4), dfd(4, 4), w(3)
    logical :: ok
    integer :: m
    do m = 1, 2
      e = green_of(merge(1.1_dp, 1.6_dp, m == 1), merge(0.95_dp, 1.2_dp, m == 1), 0.3_dp)
      call hencky_strain(e, l, p, ok)
      dm = d
      call log_tangent(e, matmul(d, l), p, dm, .false.)
      dfd = jacobian(e)
      if (m == 1) then
        call check(maxval(abs(dm([1, 2, 4], [1, 2, 4]) - dfd([1, 2, 4], [1, 2, 4]))) <= 1e-7_dp * maxval(abs(dfd)), &
          'log_tangent = dS/dE of the Hencky law (central differences), stretch diag(1.1, 0.95) turned')
      else
        w = eigenvalues(dfd([1, 2, 4], [1, 2, 4]))
        call check(minval(w) < 0.0_dp .and. minval(eigenvalues(dm([1, 2, 4], [1, 2, 4]))) >= -1e-12_dp * maxval(w), &
          'log_tangent: at diag(1.6, 1.2) the Hencky tangent is indefinite, its positive part is kept')
      end if
    end do
  end subroutine test_tangent

  !> An axisymmetric point's hoop stretch λ_θ (E_θθ = (λ_θ² - 1)/2, its own eigenvalue): ℓ_θθ = ln λ_θ,
  !> P_θθθθ = 1/λ_θ², and log_tangent with the hoop row (axi) = dS/dE over the four components.
  subroutine test_hoop()
    real(dp) :: e(4), l(4), p(4, 4), dm(4, 4), dfd(4, 4)
    logical :: ok
    e = green_of(1.1_dp, 0.95_dp, 0.3_dp)
    e(3) = 0.5_dp * (1.3_dp**2 - 1.0_dp)
    call hencky_strain(e, l, p, ok)
    call check(ok .and. abs(l(3) - log(1.3_dp)) <= 1e-15_dp .and. abs(p(3, 3) - 1.0_dp / 1.69_dp) <= 1e-15_dp .and. &
      all(p(3, [1, 2, 4]) == 0.0_dp), 'hencky: the hoop stretch 1.3, ℓ_θθ = ln 1.3 and P_θθθθ = 1/1.69, uncoupled')
    e(3) = 0.5_dp * (1.05_dp**2 - 1.0_dp)
    call hencky_strain(e, l, p, ok)
    dm = d
    call log_tangent(e, matmul(d, l), p, dm, .true.)
    dfd = jacobian(e)
    call check(maxval(abs(dm - dfd)) <= 1e-7_dp * maxval(abs(dfd)), 'log_tangent (axisymmetric) = dS/dE of the ' // &
      'Hencky law over the four components, hoop stretch 1.05')
  end subroutine test_hoop

  function jacobian(e) result(j)
    real(dp), intent(in) :: e(4)
    real(dp) :: j(4, 4), h
    integer :: k
    h = 1e-6_dp
    do k = 1, 4
      j(:, k) = (stress(e + h * unit(k)) - stress(e - h * unit(k))) / (2.0_dp * h)
    end do
  end function jacobian

  function eigenvalues(a) result(w)
    real(dp), intent(in) :: a(3, 3)
    real(dp) :: w(3), b(3, 3), work(16)
    integer :: info
    b = 0.5_dp * (a + transpose(a))
    call dsyev('N', 'U', 3, b, 3, w, work, size(work), info)
  end function eigenvalues

  function stress(e) result(s)
    real(dp), intent(in) :: e(4)
    real(dp) :: s(4), l(4), p(4, 4)
    logical :: ok
    call hencky_strain(e, l, p, ok)
    s = matmul(matmul(d, l), p)
  end function stress

  pure function unit(k) result(v)
    integer, intent(in) :: k
    real(dp) :: v(4)
    v = 0.0_dp
    v(k) = 1.0_dp
  end function unit

  !> S̄·ΔE = w exactly and S̄ symmetric; a gap below the noise leaves S̄ = sa.
  subroutine test_gonzalez()
    real(dp) :: sa(4), de(4), sb(4)
    sa = [3.0_dp, -1.0_dp, 0.5_dp, 2.0_dp]
    de = [1e-3_dp, 2e-3_dp, 0.0_dp, -4e-3_dp]
    sb = gonzalez_stress(sa, de, 1.0e-2_dp, 0.0_dp)
    call check_close(dot_product(sb, de), 1.0e-2_dp, 1e-14_dp, 'gonzalez: S̄·ΔE = w')
    sb = gonzalez_stress(sa, 1e-20_dp * de, dot_product(sa, 1e-20_dp * de) + 1e-30_dp, 1e-25_dp)
    call check(all(sb == sa), 'gonzalez: a gap below the round-off leaves the mean stress')
  end subroutine test_gonzalez
end program test_log_strain
