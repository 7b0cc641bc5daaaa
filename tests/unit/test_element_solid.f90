!> Unit tests of the 3D solids HEX8 and TET4 through the element dispatcher (elements) on
!> distorted geometries: the patch test (a linear displacement gives its constant strain exactly at
!> every point), the six rigid-body modes (exactly six zero eigenvalues of the stiffness, the others
!> positive), the mass rho V (consistent, lumped and their translations), the elastic D, and the
!> zero-volume and inverted elements refused. Tolerances: a few hundred ulps of the data scale.
program test_element_solid
  use kinds, only: dp
  use testing, only: check, check_close, test_summary
  use errors, only: STAT_OK, STAT_INPUT
  use element_traits, only: ET_HEX8, ET_TET4, DOF_UX, DOF_UY, DOF_UZ, DOF_RZ, etype_dimension
  use section, only: section_t
  use lapack_pure, only: dsyev
  use elements, only: MAX_EDOF, MAX_NSTRAIN, elem_dof_mask, elem_ndof, elem_nstrain, elem_ngauss, elem_gauss_b, &
    elem_mass, elem_elastic_d, elem_check_geometry, elem_stiffness
  implicit none

  real(dp), parameter :: rho = 7800.0_dp, e = 2.1e11_dp, nu = 0.3_dp
  !> A distorted hexahedron: the unit cube through an affine map (volume det A = 1.9) ...
  real(dp), parameter :: amap(3, 3) = reshape([1.2_dp, 0.1_dp, -0.2_dp, 0.3_dp, 1.1_dp, 0.05_dp, 0.0_dp, 0.2_dp, &
    1.5_dp], [3, 3])
  real(dp), parameter :: cube(3, 8) = reshape([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1], &
    [3, 8]) * 1.0_dp

  call test_sizes()
  call test_patch(ET_HEX8, hex_affine())
  call test_patch(ET_HEX8, hex_warped())
  call test_patch(ET_TET4, tet())
  call test_rigid(ET_HEX8, hex_warped())
  call test_rigid(ET_TET4, tet())
  call test_mass()
  call test_checks()
  call test_summary('element_solid')

contains

  function hex_affine() result(x)
    real(dp) :: x(3, 8)
    x = matmul(amap, cube) + spread([0.5_dp, -1.0_dp, 2.0_dp], 2, 8)
  end function hex_affine

  !> Not affine: corner 7 pulled out (the faces through it warped).
  function hex_warped() result(x)
    real(dp) :: x(3, 8)
    x = hex_affine()
    x(:, 7) = x(:, 7) + [0.15_dp, 0.1_dp, 0.2_dp]
  end function hex_warped

  function tet() result(x)
    real(dp) :: x(3, 4)
    x = reshape([0.1_dp, 0.0_dp, 0.2_dp, 1.3_dp, 0.1_dp, 0.0_dp, 0.2_dp, 0.9_dp, -0.1_dp, 0.3_dp, 0.2_dp, 1.1_dp], [3, 4])
  end function tet

  subroutine test_sizes()
    type(section_t) :: sec
    call check(all(elem_dof_mask(ET_HEX8) .eqv. [.true., .true., .false., .true.]), 'mask HEX8: UX UY UZ')
    call check(all(elem_dof_mask(ET_TET4) .eqv. [.true., .true., .false., .true.]), 'mask TET4: UX UY UZ')
    call check(DOF_UX == 1 .and. DOF_UY == 2 .and. DOF_RZ == 3 .and. DOF_UZ == 4, 'DOF slots')
    call check(elem_ndof(ET_HEX8) == 24 .and. elem_ndof(ET_TET4) == 12, 'ndof')
    call check(elem_nstrain(ET_HEX8) == 6 .and. elem_nstrain(ET_TET4) == 6, 'nstrain')
    call check(elem_ngauss(ET_HEX8, sec) == 8 .and. elem_ngauss(ET_TET4, sec) == 1, 'ngauss')
    call check(etype_dimension(ET_HEX8) == 3 .and. etype_dimension(ET_TET4) == 3, 'dimension 3')
  end subroutine test_sizes

  !> u = G x + c: eps = (Gxx, Gyy, Gzz, Gxy + Gyx, Gyz + Gzy, Gxz + Gzx) at every point.
  subroutine test_patch(et, x)
    integer, intent(in) :: et
    real(dp), intent(in) :: x(:, :)
    type(section_t) :: sec
    real(dp), parameter :: g(3, 3) = reshape([1.0e-3_dp, -2.0e-4_dp, 3.0e-4_dp, 5.0e-4_dp, -7.0e-4_dp, 1.0e-4_dp, &
      -4.0e-4_dp, 2.5e-4_dp, 6.0e-4_dp], [3, 3])
    real(dp) :: u(MAX_EDOF), b(MAX_NSTRAIN, MAX_EDOF), wt, eps(6), exact(6), err, wsum
    integer :: a, ig, nd, nen
    nen = size(x, 2)
    nd = elem_ndof(et)
    do a = 1, nen
      u(3 * a - 2:3 * a) = matmul(g, x(:, a)) + [1.0e-2_dp, -3.0e-3_dp, 2.0e-3_dp]
    end do
    exact = [g(1, 1), g(2, 2), g(3, 3), g(1, 2) + g(2, 1), g(2, 3) + g(3, 2), g(1, 3) + g(3, 1)]
    err = 0.0_dp
    wsum = 0.0_dp
    do ig = 1, elem_ngauss(et, sec)
      call elem_gauss_b(et, x, sec, ig, b, wt)
      eps = matmul(b(1:6, 1:nd), u(1:nd))
      err = max(err, maxval(abs(eps - exact)))
      wsum = wsum + wt
    end do
    call check(err <= 1.0e-15_dp, 'patch test ' // trim(merge('HEX8', 'TET4', et == ET_HEX8)) // &
      ': constant strain exact at every point')
    if (et == ET_TET4) then
      call check_close(wsum, tet_volume(x), 1.0e-14_dp, 'TET4 weights sum to the volume')
    else if (all(x == hex_affine())) then
      call check_close(wsum, det3(amap), 1.0e-14_dp, 'HEX8 weights sum to the volume (affine)')
    end if
  end subroutine test_patch

  !> K = Σ B'DB w: six zero eigenvalues (relative 1e-12 of the largest), the others positive.
  subroutine test_rigid(et, x)
    integer, intent(in) :: et
    real(dp), intent(in) :: x(:, :)
    type(section_t) :: sec
    real(dp) :: d(MAX_NSTRAIN, MAX_NSTRAIN), k(MAX_EDOF, MAX_EDOF), lam(MAX_EDOF), work(512)
    integer :: nd, info, nzero
    nd = elem_ndof(et)
    call elem_elastic_d(et, e, nu, sec, d)
    call elem_stiffness(et, x, sec, d, k)
    call dsyev('N', 'U', nd, k, MAX_EDOF, lam, work, size(work), info)
    nzero = count(abs(lam(1:nd)) <= 1.0e-12_dp * maxval(lam(1:nd)))
    call check(info == 0 .and. nzero == 6 .and. all(lam(1:nd) > -1.0e-12_dp * maxval(lam(1:nd))), &
      trim(merge('HEX8', 'TET4', et == ET_HEX8)) // ': six rigid-body modes, the other eigenvalues positive', &
      'zero eigenvalues ' // char(48 + nzero))
  end subroutine test_rigid

  !> rho V in each direction, consistent and lumped; the consistent mass's translation sum exact.
  subroutine test_mass()
    type(section_t) :: sec
    real(dp) :: me(MAX_EDOF, MAX_EDOF), t(MAX_EDOF), x(3, 8), v
    integer :: dir, a
    logical :: lumped
    integer :: l
    x = hex_affine()
    v = det3(amap)
    do l = 0, 1
      lumped = l == 1
      call elem_mass(ET_HEX8, x, sec, rho, lumped, me)
      do dir = 1, 3
        t = 0.0_dp
        do a = 1, 8
          t(3 * a - 3 + dir) = 1.0_dp
        end do
        call check_close(dot_product(t(1:24), matmul(me(1:24, 1:24), t(1:24))), rho * v, 1.0e-13_dp, &
          'HEX8 mass rho V, direction ' // char(48 + dir) // merge(' lumped    ', ' consistent', lumped))
      end do
      call elem_mass(ET_TET4, tet(), sec, rho, lumped, me)
      t = 0.0_dp
      t(3:12:3) = 1.0_dp
      call check_close(dot_product(t(1:12), matmul(me(1:12, 1:12), t(1:12))), rho * tet_volume(tet()), 1.0e-13_dp, &
        'TET4 mass rho V' // merge(' lumped    ', ' consistent', lumped))
    end do
    ! The consistent TET4 mass is rho V (1 + δij)/20 per direction.
    call elem_mass(ET_TET4, tet(), sec, rho, .false., me)
    call check_close(me(1, 1), rho * tet_volume(tet()) / 10.0_dp, 1.0e-14_dp, 'TET4 consistent diagonal rho V/10')
    call check_close(me(1, 4), rho * tet_volume(tet()) / 20.0_dp, 1.0e-14_dp, 'TET4 consistent coupling rho V/20')
    call check(me(1, 2) == 0.0_dp, 'TET4 directions uncoupled')
  end subroutine test_mass

  subroutine test_checks()
    type(section_t) :: sec
    real(dp) :: x(3, 8), xt(3, 4)
    integer :: stat
    character(len=:), allocatable :: msg
    call elem_check_geometry(ET_HEX8, hex_warped(), sec, stat, msg)
    call check(stat == STAT_OK, 'a warped HEX8 accepted')
    x = hex_affine()
    x(:, [1, 2, 3, 4, 5, 6, 7, 8]) = x(:, [5, 6, 7, 8, 1, 2, 3, 4])      ! top and bottom swapped: inverted
    call elem_check_geometry(ET_HEX8, x, sec, stat, msg)
    call check(stat == STAT_INPUT .and. index(msg, 'inverted') > 0, 'an inverted HEX8 refused')
    x = hex_affine()
    x(:, 5:8) = x(:, 1:4)                                                 ! flat
    call elem_check_geometry(ET_HEX8, x, sec, stat, msg)
    call check(stat == STAT_INPUT, 'a flat HEX8 refused')
    xt = tet()
    xt(:, [3, 4]) = xt(:, [4, 3])
    call elem_check_geometry(ET_TET4, xt, sec, stat, msg)
    call check(stat == STAT_INPUT, 'an inverted TET4 refused')
    xt = tet()
    xt(:, 4) = 0.5_dp * (xt(:, 2) + xt(:, 3))
    call elem_check_geometry(ET_TET4, xt, sec, stat, msg)
    call check(stat == STAT_INPUT, 'a flat TET4 refused')
  end subroutine test_checks

  pure real(dp) function det3(a)
    real(dp), intent(in) :: a(3, 3)
    det3 = a(1, 1) * (a(2, 2) * a(3, 3) - a(2, 3) * a(3, 2)) - a(1, 2) * (a(2, 1) * a(3, 3) - a(2, 3) * a(3, 1)) + &
      a(1, 3) * (a(2, 1) * a(3, 2) - a(2, 2) * a(3, 1))
  end function det3

  pure real(dp) function tet_volume(x)
    real(dp), intent(in) :: x(3, 4)
    real(dp) :: a(3, 3)
    a(:, 1) = x(:, 2) - x(:, 1)
    a(:, 2) = x(:, 3) - x(:, 1)
    a(:, 3) = x(:, 4) - x(:, 1)
    tet_volume = det3(a) / 6.0_dp
  end function tet_volume
end program test_element_solid
