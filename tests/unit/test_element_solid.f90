!> Unit tests of the 3D solids HEX8, HEX20, TET4, TET10 and WEDGE6 through the element dispatcher (elements) on
!> distorted geometries: the patch test (a linear displacement gives its constant strain exactly at
!> every point), the six rigid-body modes (exactly six zero eigenvalues of the stiffness, the others
!> positive), the mass rho V (consistent, lumped and their translations), the elastic D, and the
!> zero-volume and inverted elements refused. Tolerances: a few hundred ulps of the data scale.
program test_element_solid
  use kinds, only: dp
  use testing, only: check, check_close, test_summary
  use errors, only: STAT_OK, STAT_INPUT
  use element_traits, only: ET_HEX8, ET_TET4, ET_HEX20, ET_TET10, ET_WEDGE6, DOF_UX, DOF_UY, DOF_UZ, DOF_RZ, etype_dimension, &
    etype_name
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
  call test_patch(ET_HEX20, hex20())
  call test_patch(ET_TET10, tet10())
  call test_rigid(ET_HEX20, hex20())
  call test_rigid(ET_TET10, tet10())
  call test_patch(ET_WEDGE6, wedge_affine())
  call test_patch(ET_WEDGE6, wedge_warped())
  call test_rigid(ET_WEDGE6, wedge_warped())
  call test_mass()
  call test_mass_quadratic()
  call test_mass_wedge()
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

  !> A HEX20: the affine hexahedron with its mid-edge nodes (Gmsh's edges) moved off the straight
  !> edges a little (curved edges: not affine).
  function hex20() result(x)
    real(dp) :: x(3, 20)
    integer, parameter :: ed(2, 12) = reshape([1, 2, 1, 4, 1, 5, 2, 3, 2, 6, 3, 4, 3, 7, 4, 8, 5, 6, 5, 8, 6, 7, 7, 8], &
      [2, 12])
    integer :: a
    x(:, 1:8) = hex_affine()
    do a = 1, 12
      x(:, 8 + a) = 0.5_dp * (x(:, ed(1, a)) + x(:, ed(2, a))) + 0.01_dp * [sin(1.0_dp * a), cos(2.0_dp * a), 0.5_dp]
    end do
  end function hex20

  !> A straight-sided TET10 (its mid-edge nodes at the middles, Gmsh's edges).
  function tet10() result(x)
    real(dp) :: x(3, 10)
    integer, parameter :: ed(2, 6) = reshape([1, 2, 2, 3, 3, 1, 4, 1, 4, 3, 4, 2], [2, 6])
    integer :: a
    x(:, 1:4) = tet()
    do a = 1, 6
      x(:, 4 + a) = 0.5_dp * (x(:, ed(1, a)) + x(:, ed(2, a)))
    end do
  end function tet10

  !> A WEDGE6: the prism (0,0,0) (1,0,0) (0,1,0) and the same at z = 1 through the affine map (volume
  !> det A / 2).
  function wedge_affine() result(x)
    real(dp) :: x(3, 6)
    x = matmul(amap, cube(:, [1, 2, 4, 5, 6, 8])) + spread([0.5_dp, -1.0_dp, 2.0_dp], 2, 6)
  end function wedge_affine

  !> Not affine: corner 6 pulled out (its two quadrangles warped).
  function wedge_warped() result(x)
    real(dp) :: x(3, 6)
    x = wedge_affine()
    x(:, 6) = x(:, 6) + [0.1_dp, 0.15_dp, -0.1_dp]
  end function wedge_warped

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
    call check(err <= 1.0e-15_dp, 'patch test ' // etype_name(et) // ': constant strain exact at every point')
    if (et == ET_TET4 .or. et == ET_TET10) then
      call check_close(wsum, tet_volume(x), 1.0e-14_dp, 'TET4 weights sum to the volume')
    else if (et == ET_WEDGE6) then
      if (all(x == wedge_affine())) call check_close(wsum, 0.5_dp * det3(amap), 1.0e-14_dp, &
        'WEDGE6 weights sum to the volume (affine)')
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
      etype_name(et) // ': six rigid-body modes, the other eigenvalues positive', &
      'zero eigenvalues ' // char(48 + nzero))
  end subroutine test_rigid

  !> rho V in each direction, consistent and lumped; the consistent mass's translation sum exact.
  subroutine test_mass()
    type(section_t) :: sec
    real(dp) :: me(MAX_EDOF, MAX_EDOF), x(3, 8), v
    x = hex_affine()
    v = det3(amap)
    call check_rho_v(ET_HEX8, x, v)
    call check_rho_v(ET_TET4, tet(), tet_volume(tet()))
    ! The consistent TET4 mass is rho V (1 + δij)/20 per direction.
    call elem_mass(ET_TET4, tet(), sec, rho, .false., me)
    call check_close(me(1, 1), rho * tet_volume(tet()) / 10.0_dp, 1.0e-14_dp, 'TET4 consistent diagonal rho V/10')
    call check_close(me(1, 4), rho * tet_volume(tet()) / 20.0_dp, 1.0e-14_dp, 'TET4 consistent coupling rho V/20')
    call check(me(1, 2) == 0.0_dp, 'TET4 directions uncoupled')
  end subroutine test_mass

  subroutine test_checks()
    type(section_t) :: sec
    real(dp) :: x(3, 8), xt(3, 4), xw(3, 6)
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
    call elem_check_geometry(ET_WEDGE6, wedge_warped(), sec, stat, msg)
    call check(stat == STAT_OK, 'a warped WEDGE6 accepted')
    xw = wedge_affine()
    xw(:, [2, 3, 5, 6]) = xw(:, [3, 2, 6, 5])                             ! the triangles run the other way
    call elem_check_geometry(ET_WEDGE6, xw, sec, stat, msg)
    call check(stat == STAT_INPUT .and. index(msg, 'WEDGE6') > 0, 'an inverted WEDGE6 refused, named')
  end subroutine test_checks

  !> t'M t = rho V for the rigid translation t along each direction, consistent and lumped.
  subroutine check_rho_v(et, x, v)
    integer, intent(in) :: et
    real(dp), intent(in) :: x(:, :), v
    type(section_t) :: sec
    real(dp) :: me(MAX_EDOF, MAX_EDOF), t(MAX_EDOF)
    integer :: l, dir, n
    n = 3 * size(x, 2)
    do l = 0, 1
      call elem_mass(et, x, sec, rho, l == 1, me)
      do dir = 1, 3
        t = 0.0_dp
        t(dir:n:3) = 1.0_dp
        call check_close(dot_product(t(1:n), matmul(me(1:n, 1:n), t(1:n))), rho * v, 1.0e-13_dp, &
          etype_name(et) // ' mass rho V, direction ' // char(48 + dir) // merge(' lumped    ', ' consistent', l == 1))
      end do
    end do
  end subroutine check_rho_v

  !> WEDGE6: rho V in each direction, consistent and lumped, and the consistent mass of an affine prism
  !> against its closed form rho V Mt x Ml (the triangle's (1 + δ)/12, the segment's (1 + δ)/6).
  subroutine test_mass_wedge()
    type(section_t) :: sec
    real(dp) :: me(MAX_EDOF, MAX_EDOF), t(MAX_EDOF), v
    integer :: l, dir
    logical :: lumped
    v = 0.5_dp * det3(amap)
    do l = 0, 1
      lumped = l == 1
      call elem_mass(ET_WEDGE6, wedge_warped(), sec, rho, lumped, me)
      do dir = 1, 3
        t = 0.0_dp
        t(dir:18:3) = 1.0_dp
        call check(dot_product(t(1:18), matmul(me(1:18, 1:18), t(1:18))) > 0.0_dp, 'WEDGE6 warped mass positive')
      end do
    end do
    call check_rho_v(ET_WEDGE6, wedge_affine(), v)
    call elem_mass(ET_WEDGE6, wedge_affine(), sec, rho, .false., me)
    call check_close(me(1, 1), rho * v / 18, 1.0e-13_dp, 'WEDGE6 consistent: diagonal rho V/18')
    call check_close(me(1, 4), rho * v / 36, 1.0e-13_dp, 'WEDGE6 consistent: corners of a triangle rho V/36')
    call check_close(me(1, 10), rho * v / 36, 1.0e-13_dp, 'WEDGE6 consistent: corners of an edge along zeta rho V/36')
    call check_close(me(1, 13), rho * v / 72, 1.0e-13_dp, 'WEDGE6 consistent: opposite corners rho V/72')
    call check(me(1, 2) == 0.0_dp, 'WEDGE6 directions uncoupled')
  end subroutine test_mass_wedge

  !> HEX20 and TET10: rho V in each direction (the straight TET10 and the affine HEX20 corners'
  !> volume: a curved HEX20 moves it), consistent and lumped; TET10's consistent mass against the
  !> closed form rho V/420 (6, 1 corner pairs; -4, -6 corner-edge, adjacent or not; 32, 16, 8 edge
  !> pairs: the same edge, sharing a corner, opposite).
  subroutine test_mass_quadratic()
    type(section_t) :: sec
    real(dp) :: me(MAX_EDOF, MAX_EDOF), t(MAX_EDOF), v, x(3, 20)
    integer :: a
    integer, parameter :: he1(12) = [1, 1, 1, 2, 2, 3, 3, 4, 5, 5, 6, 7], he2(12) = [2, 4, 5, 3, 6, 4, 7, 8, 6, 8, 7, 8]
    v = tet_volume(tet())
    call check_rho_v(ET_TET10, tet10(), v)
    call elem_mass(ET_TET10, tet10(), sec, rho, .false., me)
    call check_close(me(1, 1), 6 * rho * v / 420, 1.0e-13_dp, 'TET10 consistent: corner diagonal 6/420')
    call check_close(me(1, 4), rho * v / 420, 1.0e-13_dp, 'TET10 consistent: corner pair 1/420')
    call check_close(me(1, 13), -4 * rho * v / 420, 1.0e-13_dp, 'TET10 consistent: corner 1, its edge 1-2: -4/420')
    call check_close(me(1, 16), -6 * rho * v / 420, 1.0e-13_dp, 'TET10 consistent: corner 1, edge 2-3: -6/420')
    call check_close(me(13, 13), 32 * rho * v / 420, 1.0e-13_dp, 'TET10 consistent: edge diagonal 32/420')
    call check_close(me(13, 16), 16 * rho * v / 420, 1.0e-13_dp, 'TET10 consistent: edges sharing a corner 16/420')
    call check_close(me(13, 25), 8 * rho * v / 420, 1.0e-13_dp, 'TET10 consistent: opposite edges 8/420')
    x = hex20()
    x(:, 9:20) = 0.0_dp
    do a = 1, 12                                 ! straight edges: the affine volume det A
      x(:, 8 + a) = 0.5_dp * (x(:, he1(a)) + x(:, he2(a)))
    end do
    call elem_mass(ET_HEX20, x, sec, rho, .true., me)
    t = 0.0_dp
    t(1:60:3) = 1.0_dp
    call check_close(dot_product(t(1:60), matmul(me(1:60, 1:60), t(1:60))), rho * det3(amap), 1.0e-13_dp, &
      'HEX20 lumped mass rho V (positive diagonal)')
    call check(all([(me(a, a) > 0.0_dp, a = 1, 60)]), 'HEX20 lumped: every diagonal term positive')
  end subroutine test_mass_quadratic

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
