!> Unit tests of the element dispatcher (module elements) and the simple elements:
!> sizes and masks, elastic D, BAR2 and SPRING closed-form stiffness and mass, MASS element,
!> rigid-body motions of every element type on distorted geometries, geometry checks.
!> Tolerances: results are a handful of flops from the closed forms, so 1e-13 relative
!> (a few hundred ulps) is ample; zero strains are compared with 1e-12 times the data scale.
program test_elements
  use kinds, only: dp
  use testing, only: check, check_close, test_summary
  use errors, only: STAT_OK, STAT_INPUT
  use element_traits, only: ET_MASS, ET_SPRING, ET_BAR2, ET_BEAM2, ET_QUAD4, ET_QUAD8
  use section, only: section_t
  use elements, only: MAX_EDOF, MAX_NSTRAIN, MAX_GAUSS, elem_dof_mask, elem_nen, elem_ndof, elem_nstrain, &
    elem_ngauss, elem_gauss_b, elem_mass, elem_elastic_d, elem_check_geometry, elem_check_section, elem_stiffness
  implicit none

  call test_sizes()
  call test_elastic_d()
  call test_bar2()
  call test_spring()
  call test_point_mass()
  call test_rigid_body()
  call test_geometry_checks()
  call test_section_checks()
  call test_summary('elements')

contains

  subroutine test_sizes()
    type(section_t) :: sec
    call check(all(elem_dof_mask(ET_MASS) .eqv. [.true., .true., .false., .false.]), 'mask MASS')
    call check(all(elem_dof_mask(ET_BEAM2) .eqv. [.true., .true., .true., .false.]), 'mask BEAM2')
    call check(all(elem_dof_mask(ET_QUAD8) .eqv. [.true., .true., .false., .false.]), 'mask QUAD8')
    call check(elem_ndof(ET_MASS) == 2 .and. elem_ndof(ET_SPRING) == 4 .and. elem_ndof(ET_BAR2) == 4 .and. &
      elem_ndof(ET_BEAM2) == 6 .and. elem_ndof(ET_QUAD4) == 8 .and. elem_ndof(ET_QUAD8) == 16, 'ndof')
    call check(elem_nstrain(ET_MASS) == 0 .and. elem_nstrain(ET_SPRING) == 1 .and. elem_nstrain(ET_BAR2) == 1 .and. &
      elem_nstrain(ET_BEAM2) == 2 .and. elem_nstrain(ET_QUAD4) == 4 .and. elem_nstrain(ET_QUAD8) == 4, 'nstrain')
    call check(elem_ngauss(ET_MASS, sec) == 0 .and. elem_ngauss(ET_SPRING, sec) == 1 .and. &
      elem_ngauss(ET_BAR2, sec) == 1 .and. elem_ngauss(ET_BEAM2, sec) == 2 .and. elem_ngauss(ET_QUAD4, sec) == 4 .and. &
      elem_ngauss(ET_QUAD8, sec) == 9, 'ngauss defaults')
    sec%gauss = 5
    call check(elem_ngauss(ET_BEAM2, sec) == 5, 'ngauss BEAM2 from section')
    call check(elem_nen(ET_QUAD8) == 8 .and. elem_nen(ET_MASS) == 1, 'nen')
    call check(MAX_EDOF == 60 .and. MAX_NSTRAIN == 6 .and. MAX_GAUSS == 27, 'max parameters (HEX20: 60 DOFs, 27 points)')
  end subroutine test_sizes

  !> Plane strain: 3D isotropic law with ezz = 0; plane stress: szz = 0 and uniaxial stress.
  subroutine test_elastic_d()
    type(section_t) :: sec
    real(dp), parameter :: e = 2.0e11_dp, nu = 0.3_dp
    real(dp) :: d(MAX_NSTRAIN, MAX_NSTRAIN), sig(4), eps(4), lam, mu
    lam = e * nu / ((1 + nu) * (1 - 2 * nu))
    mu = e / (2 * (1 + nu))
    call elem_elastic_d(ET_QUAD4, e, nu, sec, d)
    eps = [1.0e-3_dp, -2.0e-4_dp, 0.0_dp, 5.0e-4_dp]
    sig = matmul(d(1:4, 1:4), eps)
    call check_close(sig(1), lam * (eps(1) + eps(2)) + 2 * mu * eps(1), 1.0e-13_dp, 'plane strain sxx')
    call check_close(sig(2), lam * (eps(1) + eps(2)) + 2 * mu * eps(2), 1.0e-13_dp, 'plane strain syy')
    call check_close(sig(3), nu * (sig(1) + sig(2)), 1.0e-13_dp, 'plane strain szz = nu (sxx + syy)')
    call check_close(sig(4), mu * eps(4), 1.0e-13_dp, 'plane strain sxy = G gxy')
    call check(all(d == transpose(d)), 'plane strain D symmetric')
    sec%plane_stress = .true.
    call elem_elastic_d(ET_QUAD8, e, nu, sec, d)
    eps = [1.0e-3_dp, -nu * 1.0e-3_dp, 0.0_dp, 0.0_dp]  ! uniaxial stress sxx = E * 1e-3
    sig = matmul(d(1:4, 1:4), eps)
    call check_close(sig(1), e * 1.0e-3_dp, 1.0e-13_dp, 'plane stress uniaxial sxx')
    call check_close(sig(2), 0.0_dp, 0.0_dp, 'plane stress uniaxial syy', atol=1.0e-13_dp * e * 1.0e-3_dp)
    call check(all(d(3, :) == 0.0_dp) .and. all(d(:, 3) == 0.0_dp), 'plane stress zz row/col zero')
    call check_close(d(4, 4), mu, 1.0e-14_dp, 'plane stress shear modulus')
    sec%area = 2.0e-3_dp
    sec%inertia = 3.0e-6_dp
    call elem_elastic_d(ET_BEAM2, e, nu, sec, d)
    call check_close(d(1, 1), e * sec%area, 1.0e-15_dp, 'beam D EA')
    call check_close(d(2, 2), e * sec%inertia, 1.0e-15_dp, 'beam D EI')
    call check(d(1, 2) == 0.0_dp .and. d(2, 1) == 0.0_dp, 'beam D diagonal')
    call elem_elastic_d(ET_SPRING, 1234.0_dp, nu, sec, d)
    call check(d(1, 1) == 1234.0_dp, 'spring D = k = YOUNG')
  end subroutine test_elastic_d

  !> BAR2 at an arbitrary angle: K = EA/L [nn^T -nn^T; -nn^T nn^T], mass closed forms.
  subroutine test_bar2()
    type(section_t) :: sec
    real(dp), parameter :: e = 7.0e10_dp, rho = 2700.0_dp, th = 0.61_dp, len = 1.7_dp
    real(dp) :: x(2, 2), n(2), d(MAX_NSTRAIN, MAX_NSTRAIN), ke(MAX_EDOF, MAX_EDOF), me(MAX_EDOF, MAX_EDOF)
    real(dp) :: kexp(4, 4), b(MAX_NSTRAIN, MAX_EDOF), wt, u(4), m
    integer :: i
    sec%area = 4.0e-4_dp
    n = [cos(th), sin(th)]
    x(:, 1) = [0.3_dp, -1.1_dp]
    x(:, 2) = x(:, 1) + len * n
    call elem_elastic_d(ET_BAR2, e, 0.3_dp, sec, d)
    call elem_stiffness(ET_BAR2, x, sec, d, ke)
    kexp(1:2, 1:2) = outer(n, n)
    kexp(3:4, 3:4) = outer(n, n)
    kexp(1:2, 3:4) = -outer(n, n)
    kexp(3:4, 1:2) = -outer(n, n)
    kexp = e * sec%area / len * kexp
    call check(maxval(abs(ke(1:4, 1:4) - kexp)) <= 1.0e-13_dp * maxval(abs(kexp)), 'bar K = EA/L [c2 cs; ..] at angle')
    call check(all(ke(5:, :) == 0.0_dp) .and. all(ke(:, 5:) == 0.0_dp), 'bar K padding zero')
    ! Stretch by 1e-3 along the axis: strain 1e-3, weight A L.
    u = 0.0_dp
    u(3:4) = 1.0e-3_dp * len * n
    call elem_gauss_b(ET_BAR2, x, sec, 1, b, wt)
    call check_close(dot_product(b(1, 1:4), u), 1.0e-3_dp, 1.0e-13_dp, 'bar axial strain')
    call check_close(wt, sec%area * len, 1.0e-14_dp, 'bar weight A L')
    m = rho * sec%area * len
    call elem_mass(ET_BAR2, x, sec, rho, .false., me)
    do i = 1, 2
      call check_close(me(i, i), m / 3, 1.0e-14_dp, 'bar consistent mass diagonal')
      call check_close(me(i, i + 2), m / 6, 1.0e-14_dp, 'bar consistent mass coupling')
    end do
    call check(me(1, 2) == 0.0_dp .and. me(1, 4) == 0.0_dp, 'bar consistent mass: x and y uncoupled')
    call check_close(sum(me([1, 3], [1, 3])), m, 1.0e-14_dp, 'bar consistent total mass rho A L')
    call elem_mass(ET_BAR2, x, sec, rho, .true., me)
    call check_close(sum(me([2, 4], [2, 4])), m, 1.0e-14_dp, 'bar lumped total mass rho A L')
    call check_close(me(4, 4), m / 2, 1.0e-14_dp, 'bar lumped mass rho A L / 2')
    call check(count(me(1:4, 1:4) /= 0.0_dp) == 4, 'bar lumped mass diagonal')
  end subroutine test_bar2

  !> SPRING: K = k [nn^T -nn^T; ..]; axis from the nodes or from the section's direction.
  subroutine test_spring()
    type(section_t) :: sec
    real(dp), parameter :: k = 3.5e5_dp
    real(dp) :: x(2, 2), n(2), d(MAX_NSTRAIN, MAX_NSTRAIN), ke(MAX_EDOF, MAX_EDOF), me(MAX_EDOF, MAX_EDOF)
    real(dp) :: kexp(4, 4), b(MAX_NSTRAIN, MAX_EDOF), wt
    x(:, 1) = [1.0_dp, 2.0_dp]
    x(:, 2) = [4.0_dp, -2.0_dp]
    n = [0.6_dp, -0.8_dp]
    call elem_elastic_d(ET_SPRING, k, 0.0_dp, sec, d)
    call elem_stiffness(ET_SPRING, x, sec, d, ke)
    kexp(1:2, 1:2) = k * outer(n, n)
    kexp(3:4, 3:4) = k * outer(n, n)
    kexp(1:2, 3:4) = -k * outer(n, n)
    kexp(3:4, 1:2) = -k * outer(n, n)
    call check(maxval(abs(ke(1:4, 1:4) - kexp)) <= 1.0e-14_dp * k, 'spring K from node axis')
    call elem_gauss_b(ET_SPRING, x, sec, 1, b, wt)
    call check(wt == 1.0_dp, 'spring weight 1')
    call check_close(dot_product(b(1, 1:4), [0.0_dp, 0.0_dp, 0.3_dp, -0.4_dp]), 0.5_dp, 1.0e-15_dp, &
      'spring elongation n . (u2 - u1)')
    ! Coincident nodes with a direction (not normalised on input).
    x(:, 2) = x(:, 1)
    sec%has_direction = .true.
    sec%direction = [-3.0_dp, 4.0_dp]
    n = [-0.6_dp, 0.8_dp]
    call elem_stiffness(ET_SPRING, x, sec, d, ke)
    kexp(1:2, 1:2) = k * outer(n, n)
    kexp(3:4, 3:4) = k * outer(n, n)
    kexp(1:2, 3:4) = -k * outer(n, n)
    kexp(3:4, 1:2) = -k * outer(n, n)
    call check(maxval(abs(ke(1:4, 1:4) - kexp)) <= 1.0e-14_dp * k, 'spring K from section direction')
    call elem_mass(ET_SPRING, x, sec, 7800.0_dp, .false., me)
    call check(all(me == 0.0_dp), 'spring massless')
  end subroutine test_spring

  subroutine test_point_mass()
    type(section_t) :: sec
    real(dp) :: x(2, 1), me(2, 2), ke(2, 2), d(1, 1)
    sec%mass = 12.5_dp
    x(:, 1) = [3.0_dp, 4.0_dp]
    call elem_mass(ET_MASS, x, sec, 0.0_dp, .false., me)
    call check(all(me == reshape([12.5_dp, 0.0_dp, 0.0_dp, 12.5_dp], [2, 2])), 'MASS consistent diag(m, m)')
    call elem_mass(ET_MASS, x, sec, 0.0_dp, .true., me)
    call check(all(me == reshape([12.5_dp, 0.0_dp, 0.0_dp, 12.5_dp], [2, 2])), 'MASS lumped diag(m, m)')
    d = 1.0_dp
    call elem_stiffness(ET_MASS, x, sec, d, ke)
    call check(all(ke == 0.0_dp), 'MASS has no stiffness')
  end subroutine test_point_mass

  !> Two translations and one small (linearised) rotation about an arbitrary centre give zero
  !> strain at every point of every element type, on distorted geometries.
  subroutine test_rigid_body()
    type(section_t) :: sec
    real(dp) :: xq8(2, 8), x(2, 8)
    xq8(:, 1:4) = reshape([0.1_dp, -0.2_dp, 2.3_dp, 0.4_dp, 1.9_dp, 1.7_dp, -0.3_dp, 1.2_dp], [2, 4])
    xq8(:, 5) = 0.5_dp * (xq8(:, 1) + xq8(:, 2)) + [0.05_dp, -0.1_dp]
    xq8(:, 6) = 0.5_dp * (xq8(:, 2) + xq8(:, 3)) + [0.12_dp, 0.03_dp]
    xq8(:, 7) = 0.5_dp * (xq8(:, 3) + xq8(:, 4)) + [-0.07_dp, 0.02_dp]
    xq8(:, 8) = 0.5_dp * (xq8(:, 4) + xq8(:, 1)) + [0.04_dp, 0.06_dp]
    sec%area = 1.0e-3_dp
    sec%thickness = 0.2_dp
    call rigid_check(ET_QUAD4, xq8, sec, .true., 'QUAD4')
    call rigid_check(ET_QUAD8, xq8, sec, .true., 'QUAD8')
    x(:, 1:2) = reshape([0.2_dp, 0.5_dp, -1.1_dp, 2.2_dp], [2, 2])
    call rigid_check(ET_BAR2, x, sec, .true., 'BAR2')
    call rigid_check(ET_SPRING, x, sec, .true., 'SPRING')
    sec%gauss = 3
    call rigid_check(ET_BEAM2, x, sec, .true., 'BEAM2 3 points')
    sec%gauss = 0
    call rigid_check(ET_BEAM2, x, sec, .true., 'BEAM2')
    ! A spring with a fixed direction is invariant under translations only, unless its
    ! nodes coincide.
    sec%has_direction = .true.
    sec%direction = [1.0_dp, 1.0_dp]
    call rigid_check(ET_SPRING, x, sec, .false., 'SPRING with direction')
    x(:, 2) = x(:, 1)
    call rigid_check(ET_SPRING, x, sec, .true., 'SPRING coincident nodes')
  end subroutine test_rigid_body

  subroutine rigid_check(et, x, sec, with_rotation, name)
    integer, intent(in) :: et
    real(dp), intent(in) :: x(:, :)
    type(section_t), intent(in) :: sec
    logical, intent(in) :: with_rotation
    character(len=*), intent(in) :: name
    real(dp), parameter :: x0(2) = [0.7_dp, -0.4_dp]
    real(dp) :: u(MAX_EDOF), b(MAX_NSTRAIN, MAX_EDOF), wt, t(2), om, worst
    integer :: mode, ig, a, k, nm
    logical :: mask(4)
    character(len=*), parameter :: mode_name(3) = [character(len=11) :: 'translate x', 'translate y', 'rotate']
    mask = elem_dof_mask(et)
    nm = count(mask)
    do mode = 1, merge(3, 2, with_rotation)
      t = 0.0_dp
      om = 0.0_dp
      if (mode <= 2) t(mode) = 1.0_dp
      if (mode == 3) om = 1.0_dp
      u = 0.0_dp
      do a = 1, elem_nen(et)
        k = (a - 1) * nm
        u(k + 1) = t(1) - om * (x(2, a) - x0(2))
        u(k + 2) = t(2) + om * (x(1, a) - x0(1))
        if (mask(3)) u(k + 3) = om
      end do
      worst = 0.0_dp
      do ig = 1, elem_ngauss(et, sec)
        call elem_gauss_b(et, x, sec, ig, b, wt)
        worst = max(worst, maxval(abs(matmul(b, u))))
      end do
      call check(worst <= 1.0e-12_dp, 'rigid body ' // name // ' ' // trim(mode_name(mode)) // ': zero strain')
    end do
  end subroutine rigid_check

  subroutine test_geometry_checks()
    type(section_t) :: sec
    real(dp) :: xq(2, 8), xb(2, 2)
    integer :: stat
    character(len=:), allocatable :: errmsg
    xq = 0.0_dp
    xq(:, 1:4) = reshape([0.0_dp, 0.0_dp, 2.0_dp, 0.3_dp, 2.2_dp, 1.5_dp, 0.1_dp, 1.1_dp], [2, 4])
    call elem_check_geometry(ET_QUAD4, xq, sec, stat, errmsg)
    call check(stat == STAT_OK, 'valid distorted QUAD4 accepted')
    xq(:, 1:4) = xq(:, [1, 4, 3, 2])
    call elem_check_geometry(ET_QUAD4, xq, sec, stat, errmsg)
    call check(stat == STAT_INPUT, 'inverted (clockwise) QUAD4 rejected')
    if (stat /= STAT_OK) call check(index(errmsg, 'inverted') > 0, 'inverted QUAD4 message', errmsg)
    xq(:, 1:4) = reshape([0.0_dp, 0.0_dp, 2.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 2.0_dp, 1.0_dp], [2, 4])
    call elem_check_geometry(ET_QUAD4, xq, sec, stat, errmsg)
    call check(stat == STAT_INPUT, 'bow-tie QUAD4 rejected')
    xq(:, 1:4) = reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [2, 4])
    call elem_check_geometry(ET_QUAD4, xq, sec, stat, errmsg)
    call check(stat == STAT_INPUT, 'QUAD4 with a collapsed side rejected')
    ! QUAD8: straight unit square is fine; a mid-side node outside the middle half of its side
    ! folds the element near a corner.
    xq(:, 1:4) = reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 0.0_dp, 1.0_dp], [2, 4])
    xq(:, 5:8) = reshape([0.5_dp, 0.0_dp, 1.0_dp, 0.5_dp, 0.5_dp, 1.0_dp, 0.0_dp, 0.5_dp], [2, 4])
    call elem_check_geometry(ET_QUAD8, xq, sec, stat, errmsg)
    call check(stat == STAT_OK, 'valid QUAD8 accepted')
    xq(:, 5) = [0.05_dp, 0.0_dp]
    call elem_check_geometry(ET_QUAD8, xq, sec, stat, errmsg)
    call check(stat == STAT_INPUT, 'QUAD8 with a misplaced mid-side node rejected')
    xq(:, 5) = [0.5_dp, 0.0_dp]
    xq(:, 5:8) = xq(:, [8, 7, 6, 5])
    xq(:, 1:4) = xq(:, [1, 4, 3, 2])
    call elem_check_geometry(ET_QUAD8, xq, sec, stat, errmsg)
    call check(stat == STAT_INPUT, 'inverted QUAD8 rejected')
    xb = reshape([1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], [2, 2])
    call elem_check_geometry(ET_BAR2, xb, sec, stat, errmsg)
    call check(stat == STAT_INPUT, 'zero-length BAR2 rejected')
    if (stat /= STAT_OK) call check(index(errmsg, 'zero-length') > 0, 'zero-length BAR2 message', errmsg)
    xb(:, 2) = [1.0_dp, 1.0_dp + 1.0e-13_dp]
    call elem_check_geometry(ET_BAR2, xb, sec, stat, errmsg, size_ref=10.0_dp)
    call check(stat == STAT_INPUT, 'BAR2 shorter than zero_tol * model size rejected')
    xb(:, 2) = [1.0_dp, 1.0_dp + 1.0e-6_dp]
    call elem_check_geometry(ET_BAR2, xb, sec, stat, errmsg, size_ref=10.0_dp)
    call check(stat == STAT_OK, 'short but genuine BAR2 accepted')
    xb(:, 2) = xb(:, 1)
    call elem_check_geometry(ET_BEAM2, xb, sec, stat, errmsg)
    call check(stat == STAT_INPUT, 'zero-length BEAM2 rejected')
    call elem_check_geometry(ET_SPRING, xb, sec, stat, errmsg)
    call check(stat == STAT_INPUT, 'coincident SPRING without direction rejected')
    sec%has_direction = .true.
    sec%direction = [0.0_dp, 1.0_dp]
    call elem_check_geometry(ET_SPRING, xb, sec, stat, errmsg)
    call check(stat == STAT_OK, 'coincident SPRING with direction accepted')
    sec%direction = 0.0_dp
    call elem_check_geometry(ET_SPRING, xb, sec, stat, errmsg)
    call check(stat == STAT_INPUT, 'SPRING with zero direction rejected')
    xb(:, 2) = [3.0_dp, 1.0_dp]
    sec%gauss = 6
    call elem_check_geometry(ET_BEAM2, xb, sec, stat, errmsg)
    call check(stat == STAT_INPUT, 'BEAM2 with 6 Gauss points rejected')
    sec%gauss = 5
    call elem_check_geometry(ET_BEAM2, xb, sec, stat, errmsg)
    call check(stat == STAT_OK, 'BEAM2 with 5 Gauss points accepted')
  end subroutine test_geometry_checks

  subroutine test_section_checks()
    type(section_t) :: sec
    integer :: stat
    character(len=:), allocatable :: errmsg
    call elem_check_section(ET_BAR2, sec, stat, errmsg)
    call check(stat == STAT_INPUT, 'BAR2 without area rejected')
    sec%area = 1.0_dp
    call elem_check_section(ET_BEAM2, sec, stat, errmsg)
    call check(stat == STAT_INPUT, 'BEAM2 without inertia rejected')
    sec%inertia = 1.0_dp
    call elem_check_section(ET_BEAM2, sec, stat, errmsg)
    call check(stat == STAT_OK, 'BEAM2 section accepted')
    sec%thickness = 0.0_dp
    call elem_check_section(ET_QUAD4, sec, stat, errmsg)
    call check(stat == STAT_INPUT, 'QUAD4 zero thickness rejected')
    sec%mass = -1.0_dp
    call elem_check_section(ET_MASS, sec, stat, errmsg)
    call check(stat == STAT_INPUT, 'negative MASS rejected')
  end subroutine test_section_checks

  pure function outer(a, b) result(m)
    real(dp), intent(in) :: a(:), b(:)
    real(dp) :: m(size(a), size(b))
    integer :: j
    do j = 1, size(b)
      m(:, j) = a * b(j)
    end do
  end function outer
end program test_elements
