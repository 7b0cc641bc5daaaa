!> Unit tests of the QUAD4 and QUAD8 elements: patch tests (one distorted element and a
!> 5-element distorted patch solved densely), nodal forces of a constant stress, stiffness
!> spectrum (symmetric, positive semi-definite, exactly 3 rigid-body modes), mass matrices
!> (total mass rho t A, classic rectangle matrices, positive HRZ lumping).
!> Tolerances: the patch solves are well conditioned (cond(K_ff) < 1e4), so 1e-10 relative
!> leaves a wide margin over rounding; eigenvalues count as zero below 1e-10 lambda_max, far
!> under the smallest genuine one (> 1e-3 lambda_max here) and far over rounding (~1e-15).
program test_element_quad
  use kinds, only: dp
  use testing, only: check, check_close, test_summary
  use errors, only: STAT_OK
  use element_traits, only: ET_QUAD4, ET_QUAD8
  use section, only: section_t
  use elements, only: MAX_EDOF, MAX_NSTRAIN, elem_ngauss, elem_gauss_b, elem_mass, elem_elastic_d, elem_stiffness, &
    elem_check_geometry
  use lapack_pure, only: dsyev, dposv
  implicit none

  real(dp), parameter :: young = 2.0e11_dp, nu = 0.3_dp, rho = 7800.0_dp
  ! Linear displacement u = a + G x and its strain (exx, eyy, ezz, gxy).
  real(dp), parameter :: ua(2) = [1.0e-3_dp, -2.0e-3_dp]
  real(dp), parameter :: ug(2, 2) = reshape([1.0e-3_dp, -3.0e-4_dp, 4.0e-4_dp, 2.0e-3_dp], [2, 2])
  real(dp), parameter :: eps_lin(4) = [ug(1, 1), ug(2, 2), 0.0_dp, ug(1, 2) + ug(2, 1)]
  type(section_t) :: sec
  real(dp) :: xq8(2, 8)

  sec%thickness = 0.15_dp
  ! A distorted QUAD8 with curved sides: corners, then mid-sides offset outward (+) or inward
  ! (-) along the side normal by the heights in bulge_heights().
  xq8(:, 1:4) = reshape([0.1_dp, -0.2_dp, 2.3_dp, 0.4_dp, 1.9_dp, 1.7_dp, -0.3_dp, 1.2_dp], [2, 4])
  call add_midsides(xq8, bulge_heights())

  call test_single_element_patch()
  call test_constant_stress_forces()
  call test_patch(ET_QUAD4, .false.)
  call test_patch(ET_QUAD4, .true.)
  call test_patch(ET_QUAD8, .false.)
  call test_patch(ET_QUAD8, .true.)
  call test_spectrum()
  call test_mass()
  call test_summary('element_quad')

contains

  pure function bulge_heights() result(h)
    real(dp) :: h(4)
    h = [0.08_dp, -0.05_dp, 0.11_dp, 0.03_dp]
  end function bulge_heights

  !> Mid-side nodes 5..8 on sides 1-2, 2-3, 3-4, 4-1, moved by h along the outward normal.
  pure subroutine add_midsides(x, h)
    real(dp), intent(inout) :: x(2, 8)
    real(dp), intent(in) :: h(4)
    real(dp) :: dx(2)
    integer :: k, k2
    do k = 1, 4
      k2 = mod(k, 4) + 1
      dx = x(:, k2) - x(:, k)
      x(:, 4 + k) = 0.5_dp * (x(:, k) + x(:, k2)) + h(k) * [dx(2), -dx(1)] / norm2(dx)
    end do
  end subroutine add_midsides

  !> Nodal values of the linear field, node-major (ux, uy).
  pure function linear_field(x, nen) result(u)
    real(dp), intent(in) :: x(:, :)
    integer, intent(in) :: nen
    real(dp) :: u(2 * nen)
    integer :: a
    do a = 1, nen
      u(2 * a - 1:2 * a) = ua + matmul(ug, x(:, a))
    end do
  end function linear_field

  !> The isoparametric interpolation reproduces a linear field on any geometry: B u equals
  !> its strain at every Gauss point; the weights sum to t * area.
  subroutine test_single_element_patch()
    real(dp) :: b(MAX_NSTRAIN, MAX_EDOF), wt, u(16), err, wsum, area
    integer :: ig, k, nen, et
    do k = 1, 2
      et = merge(ET_QUAD4, ET_QUAD8, k == 1)
      nen = merge(4, 8, k == 1)
      u(1:2 * nen) = linear_field(xq8, nen)
      err = 0.0_dp
      wsum = 0.0_dp
      do ig = 1, elem_ngauss(et, sec)
        call elem_gauss_b(et, xq8, sec, ig, b, wt)
        err = max(err, maxval(abs(matmul(b(:, 1:2 * nen), u(1:2 * nen)) - eps_lin)))
        wsum = wsum + wt
      end do
      call check(err <= 1.0e-13_dp * maxval(abs(eps_lin)), 'single distorted ' // merge('QUAD4', 'QUAD8', k == 1) // &
        ': linear field gives its constant strain at every point')
      area = shoelace(xq8(:, 1:4))
      if (k == 2) area = area + curved_area(xq8, bulge_heights())
      call check_close(wsum, sec%thickness * area, 1.0e-13_dp, 'distorted ' // merge('QUAD4', 'QUAD8', k == 1) // &
        ': weights sum to t * area')
    end do
  end subroutine test_single_element_patch

  !> f_int = sum B^T sigma wt for a constant stress equals the nodal loads of the tractions
  !> sigma n on the straight sides: f_a = t/2 sigma (y_{a+1} - y_{a-1}, x_{a-1} - x_{a+1}).
  subroutine test_constant_stress_forces()
    real(dp), parameter :: sig(4) = [3.0e6_dp, -1.0e6_dp, 5.0e5_dp, 2.0e6_dp]
    real(dp) :: b(MAX_NSTRAIN, MAX_EDOF), wt, f(8), fexp(8), nrm(2), s2(2, 2)
    integer :: ig, a, ap, am
    f = 0.0_dp
    do ig = 1, elem_ngauss(ET_QUAD4, sec)
      call elem_gauss_b(ET_QUAD4, xq8, sec, ig, b, wt)
      f = f + matmul(transpose(b(1:4, 1:8)), sig) * wt
    end do
    s2 = reshape([sig(1), sig(4), sig(4), sig(2)], [2, 2])
    do a = 1, 4
      ap = mod(a, 4) + 1
      am = mod(a + 2, 4) + 1
      nrm = [xq8(2, ap) - xq8(2, am), xq8(1, am) - xq8(1, ap)]
      fexp(2 * a - 1:2 * a) = 0.5_dp * sec%thickness * matmul(s2, nrm)
    end do
    call check(maxval(abs(f - fexp)) <= 1.0e-12_dp * maxval(abs(fexp)), &
      'QUAD4 constant stress: sum B^T sigma wt = traction nodal loads (szz ignored)')
  end subroutine test_constant_stress_forces

  !> Five distorted elements in a 0.24 x 0.12 rectangle (MacNeal-Harder patch). The linear
  !> field is imposed on the boundary nodes, the interior is solved: the nodal values must be
  !> the linear field and the stress constant, D eps, at every Gauss point.
  subroutine test_patch(et, plane_stress)
    integer, intent(in) :: et
    logical, intent(in) :: plane_stress
    integer, parameter :: conn4(4, 5) = reshape([1, 2, 6, 5, 2, 3, 7, 6, 3, 4, 8, 7, 4, 1, 5, 8, 5, 6, 7, 8], [4, 5])
    real(dp) :: xn(2, 40), ke(MAX_EDOF, MAX_EDOF), d(MAX_NSTRAIN, MAX_NSTRAIN), b(MAX_NSTRAIN, MAX_EDOF), wt
    real(dp), allocatable :: k(:, :), kff(:, :), rhs(:, :), uex(:), u(:)
    real(dp) :: xe(2, 8), ue(16), sig(4), sig_exact(4), dx(2), err_u, err_s
    integer :: conn(8, 5), edges(3, 20), nn, ned, nen, e, kk, a, b2, i, j, ig, info, nf, stat
    integer, allocatable :: dofs(:), free(:), fixed(:)
    logical :: boundary(40)
    character(len=:), allocatable :: errmsg, name
    logical :: ok
    name = merge('QUAD4', 'QUAD8', et == ET_QUAD4) // merge(' plane stress', ' plane strain', plane_stress)
    sec%plane_stress = plane_stress
    nen = merge(4, 8, et == ET_QUAD4)
    xn(:, 1:8) = reshape([0.0_dp, 0.0_dp, 0.24_dp, 0.0_dp, 0.24_dp, 0.12_dp, 0.0_dp, 0.12_dp, &
      0.04_dp, 0.02_dp, 0.18_dp, 0.03_dp, 0.16_dp, 0.08_dp, 0.08_dp, 0.08_dp], [2, 8])
    nn = 8
    boundary = .false.
    boundary(1:4) = .true.
    conn = 0
    conn(1:4, :) = conn4
    if (nen == 8) then
      ! One mid-side node per distinct side; interior sides are curved (offset 3% of their
      ! length along the normal of the side taken from its lower to its higher node number).
      ned = 0
      do e = 1, 5
        do kk = 1, 4
          a = conn4(kk, e)
          b2 = conn4(mod(kk, 4) + 1, e)
          j = 0
          do i = 1, ned
            if (edges(1, i) == min(a, b2) .and. edges(2, i) == max(a, b2)) j = i
          end do
          if (j == 0) then
            ned = ned + 1
            nn = nn + 1
            edges(:, ned) = [min(a, b2), max(a, b2), nn]
            dx = xn(:, max(a, b2)) - xn(:, min(a, b2))
            xn(:, nn) = 0.5_dp * (xn(:, a) + xn(:, b2))
            boundary(nn) = a <= 4 .and. b2 <= 4
            if (.not. boundary(nn)) xn(:, nn) = xn(:, nn) + 0.03_dp * [dx(2), -dx(1)]
            j = ned
          end if
          conn(4 + kk, e) = edges(3, j)
        end do
      end do
    end if
    ok = .true.
    do e = 1, 5
      xe(:, 1:nen) = xn(:, conn(1:nen, e))
      call elem_check_geometry(et, xe, sec, stat, errmsg)
      ok = ok .and. stat == STAT_OK
    end do
    call check(ok, 'patch ' // name // ': elements valid')
    allocate (k(2 * nn, 2 * nn), uex(2 * nn), u(2 * nn), dofs(2 * nen))
    k = 0.0_dp
    call elem_elastic_d(et, young, nu, sec, d)
    do e = 1, 5
      xe(:, 1:nen) = xn(:, conn(1:nen, e))
      call elem_stiffness(et, xe, sec, d, ke)
      do a = 1, nen
        dofs(2 * a - 1:2 * a) = [2 * conn(a, e) - 1, 2 * conn(a, e)]
      end do
      k(dofs, dofs) = k(dofs, dofs) + ke(1:2 * nen, 1:2 * nen)
    end do
    uex = linear_field(xn, nn)
    free = [(2 * i - 1, 2 * i, i = 1, nn)]
    fixed = pack(free, [(boundary(i), boundary(i), i = 1, nn)])
    free = pack(free, [(.not. boundary(i), .not. boundary(i), i = 1, nn)])
    nf = size(free)
    kff = k(free, free)
    allocate (rhs(nf, 1))
    rhs(:, 1) = -matmul(k(free, fixed), uex(fixed))
    call dposv('L', nf, 1, kff, nf, rhs, nf, info)
    call check(info == 0, 'patch ' // name // ': K_ff positive definite')
    u = uex
    u(free) = rhs(:, 1)
    err_u = maxval(abs(u - uex)) / maxval(abs(uex))
    call check(err_u <= 1.0e-10_dp, 'patch ' // name // ': interior nodes recover the linear field')
    sig_exact = matmul(d(1:4, 1:4), eps_lin)
    err_s = 0.0_dp
    do e = 1, 5
      xe(:, 1:nen) = xn(:, conn(1:nen, e))
      do a = 1, nen
        ue(2 * a - 1:2 * a) = u(2 * conn(a, e) - 1:2 * conn(a, e))
      end do
      do ig = 1, elem_ngauss(et, sec)
        call elem_gauss_b(et, xe, sec, ig, b, wt)
        sig = matmul(d(1:4, 1:4), matmul(b(1:4, 1:2 * nen), ue(1:2 * nen)))
        err_s = max(err_s, maxval(abs(sig - sig_exact)) / maxval(abs(sig_exact)))
      end do
    end do
    call check(err_s <= 1.0e-9_dp, 'patch ' // name // ': constant stress at every Gauss point')
    if (.not. plane_stress) then
      call check_close(sig_exact(3), nu * (sig_exact(1) + sig_exact(2)), 1.0e-13_dp, &
        'patch ' // name // ': szz = nu (sxx + syy)')
    end if
    sec%plane_stress = .false.
  end subroutine test_patch

  !> Element stiffness: symmetric, PSD, exactly 3 zero eigenvalues (full integration).
  subroutine test_spectrum()
    real(dp) :: ke(MAX_EDOF, MAX_EDOF), d(MAX_NSTRAIN, MAX_NSTRAIN), a(16, 16), w(16), work(200), lmax
    integer :: k, n, info, nzero
    character(len=:), allocatable :: name
    character(len=80) :: detail
    do k = 1, 4
      sec%plane_stress = k > 2
      n = merge(8, 16, mod(k, 2) == 1)
      name = merge('QUAD4', 'QUAD8', n == 8) // merge(' plane stress', ' plane strain', sec%plane_stress)
      call elem_elastic_d(merge(ET_QUAD4, ET_QUAD8, n == 8), young, nu, sec, d)
      call elem_stiffness(merge(ET_QUAD4, ET_QUAD8, n == 8), xq8, sec, d, ke)
      call check(maxval(abs(ke(1:n, 1:n) - transpose(ke(1:n, 1:n)))) <= 1.0e-14_dp * maxval(abs(ke)), &
        name // ' K symmetric')
      a(1:n, 1:n) = ke(1:n, 1:n)
      call dsyev('N', 'U', n, a, 16, w, work, size(work), info)
      lmax = w(n)
      nzero = count(abs(w(1:n)) <= 1.0e-10_dp * lmax)
      write (detail, '(a,es10.3,a,es10.3)') 'lambda_min/max = ', w(1) / lmax, ', lambda_4/max = ', w(4) / lmax
      call check(info == 0 .and. nzero == 3 .and. w(1) >= -1.0e-10_dp * lmax, &
        name // ' K PSD with exactly 3 zero eigenvalues', trim(detail))
    end do
    sec%plane_stress = .false.
  end subroutine test_spectrum

  subroutine test_mass()
    real(dp) :: me(MAX_EDOF, MAX_EDOF), xr(2, 8), m, area, mexp(4, 4)
    integer :: i, j, k, n
    character(len=:), allocatable :: name
    ! Total mass rho t A on the distorted (curved QUAD8) element, consistent and lumped: the
    ! sum of the x-x block of M is the mass carried by a unit x translation.
    do k = 1, 4
      n = merge(4, 8, k <= 2)
      area = shoelace(xq8(:, 1:4))
      if (n == 8) area = area + curved_area(xq8, bulge_heights())
      name = merge('QUAD4', 'QUAD8', n == 4) // merge(' consistent', ' lumped    ', mod(k, 2) == 1)
      call elem_mass(merge(ET_QUAD4, ET_QUAD8, n == 4), xq8, sec, rho, mod(k, 2) == 0, me)
      call check_close(sum(me(1:2 * n:2, 1:2 * n:2)), rho * sec%thickness * area, 1.0e-13_dp, &
        name // ' total x mass rho t A')
      call check_close(sum(me(2:2 * n:2, 2:2 * n:2)), rho * sec%thickness * area, 1.0e-13_dp, &
        name // ' total y mass rho t A')
      call check(all(me(1:2 * n:2, 2:2 * n:2) == 0.0_dp), name // ' x and y uncoupled')
      call check(maxval(abs(me - transpose(me))) <= 1.0e-15_dp * maxval(me), name // ' symmetric')
      if (mod(k, 2) == 0) then
        call check(count(me /= 0.0_dp) == 2 * n .and. all([(me(i, i) > 0.0_dp, i = 1, 2 * n)]), &
          name // ' diagonal and all positive')
      end if
    end do
    ! Rectangle a x b: classic QUAD4 consistent matrix rho t A/36 [4 2 1 2; ...], lumped 1/4;
    ! QUAD8 HRZ lumped: corners 3/76, mid-sides 16/76 of the mass.
    xr(:, 1:4) = reshape([1.0_dp, 2.0_dp, 3.5_dp, 2.0_dp, 3.5_dp, 3.2_dp, 1.0_dp, 3.2_dp], [2, 4])
    call add_midsides(xr, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp])
    m = rho * sec%thickness * 2.5_dp * 1.2_dp
    mexp = m / 36 * reshape([4, 2, 1, 2, 2, 4, 2, 1, 1, 2, 4, 2, 2, 1, 2, 4], [4, 4])
    call elem_mass(ET_QUAD4, xr, sec, rho, .false., me)
    call check(maxval(abs(me(1:8:2, 1:8:2) - mexp)) <= 1.0e-14_dp * m .and. &
      maxval(abs(me(2:8:2, 2:8:2) - mexp)) <= 1.0e-14_dp * m, 'QUAD4 rectangle consistent mass = rho t A/36 [4 2 1 2; ..]')
    call elem_mass(ET_QUAD4, xr, sec, rho, .true., me)
    call check(all([(abs(me(i, i) - m / 4) <= 1.0e-14_dp * m, i = 1, 8)]), 'QUAD4 rectangle lumped mass m/4')
    call elem_mass(ET_QUAD8, xr, sec, rho, .true., me)
    call check(all([(abs(me(i, i) - 3 * m / 76) <= 1.0e-14_dp * m, i = 1, 8)]) .and. &
      all([(abs(me(j, j) - 16 * m / 76) <= 1.0e-14_dp * m, j = 9, 16)]), 'QUAD8 rectangle HRZ mass 3/76, 16/76')
  end subroutine test_mass

  !> Area of a counter-clockwise polygon.
  pure real(dp) function shoelace(p)
    real(dp), intent(in) :: p(:, :)
    integer :: i, j
    shoelace = 0.0_dp
    do i = 1, size(p, 2)
      j = mod(i, size(p, 2)) + 1
      shoelace = shoelace + 0.5_dp * (p(1, i) * p(2, j) - p(1, j) * p(2, i))
    end do
  end function shoelace

  !> Area added by parabolic sides whose mid-point is pushed out by h: 2/3 * chord * h each.
  pure real(dp) function curved_area(x, h)
    real(dp), intent(in) :: x(2, 8), h(4)
    integer :: k
    curved_area = 0.0_dp
    do k = 1, 4
      curved_area = curved_area + 2.0_dp / 3.0_dp * norm2(x(:, mod(k, 4) + 1) - x(:, k)) * h(k)
    end do
  end function curved_area
end program test_element_quad
