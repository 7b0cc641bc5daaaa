!> Unit tests of the TRI3 and TRI6 elements through the dispatcher (elements): on a distorted
!> triangle, a linear displacement field gives its constant strain at every stress point (TRI3
!> and TRI6) and a quadratic field its linear strain (TRI6); the weights add up to t A; the
!> stiffness is symmetric, positive semi-definite with exactly 3 zero eigenvalues, and for TRI3
!> equals the closed-form constant-strain triangle t A B'DB; the consistent masses equal the
!> closed forms rho t A/12 [2 1 1; ..] (TRI3) and rho t A/180 [6 -1 -1 0 -4 0; ..] (TRI6); the
!> HRZ lumped masses are 1/3 (TRI3) and 3/57, 16/57 (TRI6) of rho t A, all positive; a clockwise
!> or collapsed triangle is refused.
program test_element_tri
  use kinds, only: dp
  use testing, only: check, check_close, test_summary
  use errors, only: STAT_OK
  use element_traits, only: ET_TRI3, ET_TRI6
  use section, only: section_t
  use elements, only: MAX_EDOF, MAX_NSTRAIN, elem_ngauss, elem_gauss_b, elem_mass, elem_elastic_d, elem_stiffness, &
    elem_check_geometry
  use lapack_pure, only: dsyev
  implicit none

  real(dp), parameter :: young = 2.0e11_dp, nu = 0.3_dp, rho = 7800.0_dp
  type(section_t) :: sec
  real(dp) :: x(2, 6), area

  sec%thickness = 0.05_dp
  ! A distorted triangle, corners counter-clockwise, straight sides (mid-side nodes halfway).
  x = 0.0_dp
  x(:, 1:3) = reshape([0.2_dp, 0.1_dp, 1.7_dp, 0.4_dp, 0.6_dp, 1.3_dp], [2, 3])
  x(:, 4) = 0.5_dp * (x(:, 1) + x(:, 2))
  x(:, 5) = 0.5_dp * (x(:, 2) + x(:, 3))
  x(:, 6) = 0.5_dp * (x(:, 3) + x(:, 1))
  area = 0.5_dp * ((x(1, 2) - x(1, 1)) * (x(2, 3) - x(2, 1)) - (x(1, 3) - x(1, 1)) * (x(2, 2) - x(2, 1)))

  call test_fields()
  call test_stiffness()
  call test_mass()
  call test_check()
  call test_summary('test_element_tri')

contains

  !> u(x) = a + G x (+ the quadratic term q for TRI6): strains at the stress points.
  subroutine test_fields()
    real(dp), parameter :: g(2, 2) = reshape([1.0e-3_dp, -3.0e-4_dp, 4.0e-4_dp, 2.0e-3_dp], [2, 2])
    real(dp), parameter :: q = 2.0e-3_dp                  ! quadratic: u_x += q x y, u_y += q x^2
    real(dp) :: b(MAX_NSTRAIN, MAX_EDOF), ue(12), wt, wsum, eps(4), exact(4), xg(2), err
    integer :: k, n, et, ig, i
    do k = 1, 3
      et = merge(ET_TRI3, ET_TRI6, k == 1)
      n = merge(3, 6, k == 1)
      do i = 1, n
        ue(2 * i - 1:2 * i) = [1.0e-3_dp, -2.0e-3_dp] + matmul(g, x(:, i))
        if (k == 3) ue(2 * i - 1:2 * i) = ue(2 * i - 1:2 * i) + q * [x(1, i) * x(2, i), x(1, i)**2]
      end do
      wsum = 0.0_dp
      err = 0.0_dp
      do ig = 1, elem_ngauss(et, sec)
        call elem_gauss_b(et, x(:, 1:n), sec, ig, b, wt)
        wsum = wsum + wt
        eps = matmul(b(1:4, 1:2 * n), ue(1:2 * n))
        exact = [g(1, 1), g(2, 2), 0.0_dp, g(1, 2) + g(2, 1)]
        if (k == 3) then                 ! exx += q y, gxy += q x + 2 q x at the point
          xg = point_of(ig)
          exact = exact + q * [xg(2), 0.0_dp, 0.0_dp, 3 * xg(1)]
        end if
        err = max(err, maxval(abs(eps - exact)))
      end do
      call check(err <= 1.0e-12_dp * maxval(abs(g)), trim(merge('TRI3 linear field          ', &
        'TRI6 linear field          ', k == 1)) // trim(merge(' (+ quadratic: TRI6)', '                    ', k == 3)) // &
        ': exact strain at every stress point')
      call check_close(wsum, sec%thickness * area, 1.0e-13_dp, 'weights add up to t A')
    end do
  end subroutine test_fields

  !> The position of TRI6 stress point ig (3-point rule: (1/6, 1/6), (2/3, 1/6), (1/6, 2/3)).
  function point_of(ig) result(xg)
    integer, intent(in) :: ig
    real(dp) :: xg(2), xi, eta
    xi = 1.0_dp / 6.0_dp
    eta = xi
    if (ig == 2) xi = 2.0_dp / 3.0_dp
    if (ig == 3) eta = 2.0_dp / 3.0_dp
    xg = matmul(x(:, 1:3), [1.0_dp - xi - eta, xi, eta])   ! straight sides: the corners' linear map
  end function point_of

  subroutine test_stiffness()
    real(dp) :: ke(MAX_EDOF, MAX_EDOF), d(MAX_NSTRAIN, MAX_NSTRAIN), a(12, 12), w(12), work(400), lmax
    real(dp) :: bc(4, 6), kc(6, 6), bi(3), ci(3)
    integer :: k, n, info, nzero, et, i
    do k = 1, 2
      et = merge(ET_TRI3, ET_TRI6, k == 1)
      n = merge(6, 12, k == 1)
      call elem_elastic_d(et, young, nu, sec, d)
      call elem_stiffness(et, x(:, 1:n / 2), sec, d, ke)
      call check(maxval(abs(ke(1:n, 1:n) - transpose(ke(1:n, 1:n)))) <= 1.0e-14_dp * maxval(abs(ke)), &
        merge('TRI3', 'TRI6', k == 1) // ' K symmetric')
      a(1:n, 1:n) = ke(1:n, 1:n)
      call dsyev('N', 'U', n, a, 12, w, work, size(work), info)
      lmax = w(n)
      nzero = count(abs(w(1:n)) <= 1.0e-10_dp * lmax)
      call check(info == 0 .and. nzero == 3 .and. w(1) >= -1.0e-10_dp * lmax, &
        merge('TRI3', 'TRI6', k == 1) // ' K PSD with exactly 3 zero eigenvalues')
    end do
    ! The constant-strain triangle: B = 1/(2A) [b1 0 b2 0 b3 0; 0 c1 0 c2 0 c3; 0; c1 b1 c2 b2 c3 b3],
    ! b_i = y_j - y_k, c_i = x_k - x_j (i, j, k cyclic), K = t A B'DB.
    do i = 1, 3
      bi(i) = x(2, mod(i, 3) + 1) - x(2, mod(i + 1, 3) + 1)
      ci(i) = x(1, mod(i + 1, 3) + 1) - x(1, mod(i, 3) + 1)
    end do
    bc = 0.0_dp
    do i = 1, 3
      bc(1, 2 * i - 1) = bi(i)
      bc(2, 2 * i) = ci(i)
      bc(4, 2 * i - 1) = ci(i)
      bc(4, 2 * i) = bi(i)
    end do
    bc = bc / (2 * area)
    call elem_elastic_d(ET_TRI3, young, nu, sec, d)
    kc = sec%thickness * area * matmul(transpose(bc), matmul(d(1:4, 1:4), bc))
    call elem_stiffness(ET_TRI3, x(:, 1:3), sec, d, ke)
    call check(maxval(abs(ke(1:6, 1:6) - kc)) <= 1.0e-13_dp * maxval(abs(kc)), 'TRI3 K = t A B''DB (closed form)')
  end subroutine test_stiffness

  subroutine test_mass()
    real(dp) :: me(MAX_EDOF, MAX_EDOF), m, m3(3, 3), m6(6, 6)
    integer :: i
    m = rho * sec%thickness * area
    m3 = m / 12 * reshape([2, 1, 1, 1, 2, 1, 1, 1, 2], [3, 3])
    call elem_mass(ET_TRI3, x(:, 1:3), sec, rho, .false., me)
    call check(maxval(abs(me(1:6:2, 1:6:2) - m3)) <= 1.0e-14_dp * m .and. maxval(abs(me(2:6:2, 2:6:2) - m3)) <= &
      1.0e-14_dp * m .and. all(me(1:6:2, 2:6:2) == 0.0_dp), 'TRI3 consistent mass = rho t A/12 [2 1 1; ..]')
    call elem_mass(ET_TRI3, x(:, 1:3), sec, rho, .true., me)
    call check(all([(abs(me(i, i) - m / 3) <= 1.0e-14_dp * m, i = 1, 6)]) .and. count(me /= 0.0_dp) == 6, &
      'TRI3 lumped mass m/3 per node')
    m6 = m / 180 * reshape([6, -1, -1, 0, -4, 0, -1, 6, -1, 0, 0, -4, -1, -1, 6, -4, 0, 0, &
                            0, 0, -4, 32, 16, 16, -4, 0, 0, 16, 32, 16, 0, -4, 0, 16, 16, 32], [6, 6])
    call elem_mass(ET_TRI6, x, sec, rho, .false., me)
    call check(maxval(abs(me(1:12:2, 1:12:2) - m6)) <= 1.0e-13_dp * m .and. &
      maxval(abs(me(2:12:2, 2:12:2) - m6)) <= 1.0e-13_dp * m, 'TRI6 consistent mass = rho t A/180 [6 -1 -1 0 -4 0; ..]')
    call elem_mass(ET_TRI6, x, sec, rho, .true., me)
    call check(all([(abs(me(i, i) - 3 * m / 57) <= 1.0e-13_dp * m, i = 1, 6)]) .and. &
      all([(abs(me(i, i) - 16 * m / 57) <= 1.0e-13_dp * m, i = 7, 12)]) .and. count(me /= 0.0_dp) == 12, &
      'TRI6 HRZ lumped mass: corners 3/57, mid-sides 16/57 of rho t A, all positive')
    call check_close(sum(me(1:12:2, 1:12:2)), m, 1.0e-14_dp, 'TRI6 lumped total mass rho t A')
  end subroutine test_mass

  subroutine test_check()
    real(dp) :: xc(2, 6)
    integer :: stat
    character(len=:), allocatable :: errmsg
    call elem_check_geometry(ET_TRI6, x, sec, stat, errmsg)
    call check(stat == STAT_OK, 'TRI6 valid element accepted')
    xc = x
    xc(:, 2) = x(:, 3)
    xc(:, 3) = x(:, 2)
    call elem_check_geometry(ET_TRI3, xc(:, 1:3), sec, stat, errmsg)
    call check(stat /= STAT_OK .and. index(errmsg, 'TRI3') > 0, 'TRI3 clockwise corners refused')
    xc = x
    xc(:, 4) = x(:, 2) + 0.05_dp * (x(:, 1) - x(:, 2))   ! mid-side node next to a corner
    call elem_check_geometry(ET_TRI6, xc, sec, stat, errmsg)
    call check(stat /= STAT_OK, 'TRI6 misplaced mid-side node refused')
  end subroutine test_check
end program test_element_tri
