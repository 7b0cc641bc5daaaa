!> Unit tests of the Euler-Bernoulli BEAM2 element against closed forms: the classic 6 x 6
!> stiffness and consistent mass rotated to an arbitrary angle, HRZ lumped mass, exact
!> axial strain and curvature for polynomial deflections, Gauss-Legendre exactness.
!> Entry (i, j) of a matrix is compared with 1e-12 * sqrt(|A_ii A_jj|), the natural scale of a
!> symmetric positive matrix, so that entries mixing EA/L and EI/L^3 are judged fairly.
program test_element_beam2
  use kinds, only: dp
  use testing, only: check, check_close, test_summary
  use element_traits, only: ET_BEAM2
  use section, only: section_t
  use element_beam2, only: gauss_legendre
  use elements, only: MAX_EDOF, MAX_NSTRAIN, elem_ngauss, elem_gauss_b, elem_mass, elem_elastic_d, elem_stiffness
  implicit none

  real(dp), parameter :: e = 2.1e11_dp, rho = 7850.0_dp, th = 2.3_dp, len = 2.7_dp
  type(section_t) :: sec
  real(dp) :: x(2, 2), t(6, 6), c, s

  sec%area = 3.0e-3_dp
  sec%inertia = 4.5e-6_dp
  c = cos(th)
  s = sin(th)
  x(:, 1) = [0.4_dp, -1.3_dp]
  x(:, 2) = x(:, 1) + len * [c, s]
  t = 0.0_dp
  t(1, 1:2) = [c, s]
  t(2, 1:2) = [-s, c]
  t(3, 3) = 1.0_dp
  t(4:6, 4:6) = t(1:3, 1:3)

  call test_gauss_rules()
  call test_stiffness()
  call test_mass()
  call test_strains()
  call test_summary('element_beam2')

contains

  !> n-point Gauss-Legendre integrates x^k exactly for k <= 2n - 1.
  subroutine test_gauss_rules()
    real(dp) :: xi(5), w(5), err
    integer :: n, k
    do n = 1, 5
      call gauss_legendre(n, xi, w)
      err = 0.0_dp
      do k = 0, 2 * n - 1
        err = max(err, abs(sum(w(1:n) * xi(1:n)**k) - merge(2.0_dp / (k + 1), 0.0_dp, mod(k, 2) == 0)))
      end do
      call check(err <= 1.0e-14_dp, 'Gauss-Legendre exact to degree 2n-1, n = ' // achar(48 + n))
    end do
  end subroutine test_gauss_rules

  !> Classic Euler-Bernoulli stiffness, exact for every rule with 2 to 5 points.
  subroutine test_stiffness()
    real(dp) :: kl(6, 6), kexp(6, 6), ke(MAX_EDOF, MAX_EDOF), d(MAX_NSTRAIN, MAX_NSTRAIN), ei, ea
    integer :: ng
    ea = e * sec%area
    ei = e * sec%inertia
    kl = 0.0_dp
    kl([1, 4], [1, 4]) = ea / len * reshape([1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp], [2, 2])
    kl([2, 3, 5, 6], [2, 3, 5, 6]) = ei / len**3 * reshape([ &
      12.0_dp, 6 * len, -12.0_dp, 6 * len, &
      6 * len, 4 * len**2, -6 * len, 2 * len**2, &
      -12.0_dp, -6 * len, 12.0_dp, -6 * len, &
      6 * len, 2 * len**2, -6 * len, 4 * len**2], [4, 4])
    kexp = matmul(transpose(t), matmul(kl, t))
    call elem_elastic_d(ET_BEAM2, e, 0.3_dp, sec, d)
    do ng = 0, 5
      if (ng == 1) cycle
      sec%gauss = ng
      call elem_stiffness(ET_BEAM2, x, sec, d, ke)
      call check(close_matrix(ke(1:6, 1:6), kexp, 1.0e-12_dp), &
        'beam K = classic rotated, gauss = ' // achar(48 + ng))
    end do
    sec%gauss = 0
  end subroutine test_stiffness

  subroutine test_mass()
    real(dp) :: ml(6, 6), mexp(6, 6), me(MAX_EDOF, MAX_EDOF), m, tr(6)
    integer :: i
    m = rho * sec%area * len
    ml = 0.0_dp
    ml([1, 4], [1, 4]) = m / 6 * reshape([2.0_dp, 1.0_dp, 1.0_dp, 2.0_dp], [2, 2])
    ml([2, 3, 5, 6], [2, 3, 5, 6]) = m / 420 * reshape([ &
      156.0_dp, 22 * len, 54.0_dp, -13 * len, &
      22 * len, 4 * len**2, 13 * len, -3 * len**2, &
      54.0_dp, 13 * len, 156.0_dp, -22 * len, &
      -13 * len, -3 * len**2, -22 * len, 4 * len**2], [4, 4])
    mexp = matmul(transpose(t), matmul(ml, t))
    call elem_mass(ET_BEAM2, x, sec, rho, .false., me)
    call check(close_matrix(me(1:6, 1:6), mexp, 1.0e-12_dp), 'beam consistent mass = classic rotated')
    call check(maxval(abs(me(1:6, 1:6) - transpose(me(1:6, 1:6)))) <= 1.0e-15_dp * m, 'beam consistent mass symmetric')
    ! A rigid translation carries the whole mass rho A L, in x and in y.
    tr = [1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp]
    call check_close(dot_product(tr, matmul(me(1:6, 1:6), tr)), m, 1.0e-13_dp, 'beam consistent mass: x total rho A L')
    tr = [0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp]
    call check_close(dot_product(tr, matmul(me(1:6, 1:6), tr)), m, 1.0e-13_dp, 'beam consistent mass: y total rho A L')
    call elem_mass(ET_BEAM2, x, sec, rho, .true., me)
    do i = 0, 3, 3
      call check_close(me(i + 1, i + 1), m / 2, 1.0e-14_dp, 'beam lumped mass rho A L / 2 (x)')
      call check_close(me(i + 2, i + 2), m / 2, 1.0e-14_dp, 'beam lumped mass rho A L / 2 (y)')
      call check_close(me(i + 3, i + 3), m * len**2 / 78, 1.0e-14_dp, 'beam lumped rotary mass rho A L^3 / 78')
    end do
    call check(count(me /= 0.0_dp) == 6, 'beam lumped mass diagonal')
  end subroutine test_mass

  !> Local fields u = eps0 x', v = k0 x'^2/2 + k1 x'^3/6 (plus a rigid motion) must give
  !> eps = eps0 and kappa = k0 + k1 x' exactly at every point (Hermite cubics are exact), and the
  !> strain energy of the constant part must be (EA eps0^2 + EI k0^2) L / 2.
  subroutine test_strains()
    real(dp), parameter :: eps0 = 1.3e-3_dp, k0 = 2.0e-3_dp, k1 = -7.0e-4_dp, om = 0.02_dp
    real(dp) :: ul(6), u(6), b(MAX_NSTRAIN, MAX_EDOF), wt, xi(5), w(5), xp, eg(2), wsum, energy
    real(dp) :: d(MAX_NSTRAIN, MAX_NSTRAIN), ke(MAX_EDOF, MAX_EDOF)
    integer :: ng, ig
    real(dp) :: errs
    ! Local DOFs (u, v, theta) at x' = 0 and x' = L, then to global (u_g = T^T u_l), plus a
    ! rigid rotation about node 1.
    ul = [0.0_dp, 0.0_dp, 0.0_dp, eps0 * len, k0 * len**2 / 2 + k1 * len**3 / 6, k0 * len + k1 * len**2 / 2]
    u = matmul(transpose(t), ul)
    u(4:5) = u(4:5) + om * [-(x(2, 2) - x(2, 1)), x(1, 2) - x(1, 1)]
    u([3, 6]) = u([3, 6]) + om
    do ng = 1, 5
      sec%gauss = ng
      call gauss_legendre(ng, xi, w)
      errs = 0.0_dp
      wsum = 0.0_dp
      do ig = 1, elem_ngauss(ET_BEAM2, sec)
        call elem_gauss_b(ET_BEAM2, x, sec, ig, b, wt)
        eg = matmul(b(1:2, 1:6), u)
        xp = 0.5_dp * (1.0_dp + xi(ig)) * len
        errs = max(errs, abs(eg(1) - eps0) / eps0, abs(eg(2) - (k0 + k1 * xp)) / k0)
        wsum = wsum + wt
      end do
      call check(errs <= 1.0e-10_dp, 'beam eps and kappa exact at the points, gauss = ' // achar(48 + ng))
      call check_close(wsum, len, 1.0e-14_dp, 'beam weights sum to L, gauss = ' // achar(48 + ng))
    end do
    sec%gauss = 0
    ul(5:6) = [k0 * len**2 / 2, k0 * len]
    u = matmul(transpose(t), ul)
    call elem_elastic_d(ET_BEAM2, e, 0.3_dp, sec, d)
    call elem_stiffness(ET_BEAM2, x, sec, d, ke)
    energy = 0.5_dp * dot_product(u, matmul(ke(1:6, 1:6), u))
    call check_close(energy, 0.5_dp * (e * sec%area * eps0**2 + e * sec%inertia * k0**2) * len, 1.0e-12_dp, &
      'beam strain energy (EA eps^2 + EI kappa^2) L / 2')
  end subroutine test_strains

  logical function close_matrix(a, b, rtol)
    real(dp), intent(in) :: a(:, :), b(:, :), rtol
    integer :: i, j
    close_matrix = .true.
    do j = 1, size(b, 2)
      do i = 1, size(b, 1)
        if (abs(a(i, j) - b(i, j)) > rtol * sqrt(abs(b(i, i) * b(j, j)))) then
          close_matrix = .false.
          write (*, '(a,2i3,2es24.16)') '  mismatch at ', i, j, a(i, j), b(i, j)
        end if
      end do
    end do
  end function close_matrix
end program test_element_beam2
