!> AXISYMMETRIC surface elements (issue 32, item 3; docs/input.md, "Axisymmetric models"), x = r,
!> y the axis. Per element type (QUAD4, QUAD8, TRI3, TRI6, distorted, at r from 1 to 2.3):
!> - patch test: u_r = a r, u_y = b y + d gives every point the strain (a, b, a, 0) (the hoop
!>   strain u_r/r = a);
!> - one rigid mode only: K (elem_stiffness, plane-strain D) has exactly one zero eigenvalue, the
!>   axial translation (a radial translation stretches the hoops); TRI3, one point, a second one;
!> - mass = ρ V exactly, V = 2π ∫ r dA (the element's area times the circumference of its centroid).
!> KINEMATICS LARGE (one QUAD4, STRAIN_MEASURE LOG, FORMULATION BBAR and STANDARD, ELASTIC and J2):
!> f(n+1) = dW/du (central differences), eq (9)'s step force f̄ does the laws' path work exactly, the
!> tangent is symmetric, a uniform stretch (u_r = a r, u_y = b y) gives ℓ = (ln(1+a), ln(1+b), ln(1+a), 0)
!> at every point, and an axial translation no strain and no force.
program test_axisymmetric
  use kinds, only: dp
  use errors, only: STAT_OK
  use section, only: section_t
  use element_traits, only: ET_QUAD4, ET_QUAD8, ET_TRI3, ET_TRI6, etype_name
  use elements, only: elem_gauss_b, elem_ngauss, elem_ndof, elem_mass, elem_elastic_d, elem_stiffness, MAX_EDOF, &
    MAX_NSTRAIN
  use lapack_pure, only: dsyev
  use scene, only: scene_t
  use scene_loader, only: load_scene
  use assembly, only: system_t, build_system, commit_state
  use internal_forces, only: internal_force, work_increment_t
  use sparse_matrix, only: to_dense
  use testing, only: check, check_close, test_summary
  implicit none
  real(dp), parameter :: PI = 3.14159265358979323846264338327950288_dp
  ! Corners (counter-clockwise) of the quadrilateral and of the triangle, at r > 0.
  real(dp), parameter :: XQ(2, 4) = reshape([1.0_dp, 0.0_dp, 2.1_dp, 0.1_dp, 2.3_dp, 1.2_dp, 0.9_dp, 1.0_dp], [2, 4])
  real(dp), parameter :: XT(2, 3) = reshape([1.0_dp, 0.0_dp, 2.2_dp, 0.3_dp, 1.4_dp, 1.1_dp], [2, 3])
  type(scene_t) :: scn
  type(system_t) :: sys

  call test_element(ET_QUAD4)
  call test_element(ET_QUAD8)
  call test_element(ET_TRI3)
  call test_element(ET_TRI6)
  call open_scene('ELASTIC YOUNG 1e4 POISSON 0.45', 'FORMULATION BBAR')
  call test_stretch('LOG BBAR')
  call test_gradient('LOG BBAR')
  call test_path_work('LOG BBAR, ELASTIC')
  call test_tangent('LOG BBAR', 1.0_dp)
  call test_axial('LOG BBAR')
  call open_scene('ELASTIC YOUNG 1e4 POISSON 0.3', 'FORMULATION STANDARD')
  call test_stretch('LOG')
  call test_gradient('LOG')
  call test_path_work('LOG, ELASTIC')
  call test_tangent('LOG', 0.2_dp)
  call open_scene('VON_MISES YOUNG 1e4 POISSON 0.3 YIELD 20 H_ISO 100', '')
  call check(scn%models(1)%bbar, 'axisymmetric VON_MISES QUAD4: FORMULATION AUTO takes BBAR')
  call test_path_work('LOG BBAR, J2')
  call test_summary('axisymmetric')

contains

  !> The nodes of a straight-sided element of type et: the corners, then the mid-side nodes.
  subroutine element_nodes(et, x, nen)
    integer, intent(in) :: et
    real(dp), intent(out) :: x(2, 8)
    integer, intent(out) :: nen
    integer :: k, nc
    x = 0.0_dp
    if (et == ET_QUAD4 .or. et == ET_QUAD8) then
      nc = 4
      x(:, 1:4) = XQ
    else
      nc = 3
      x(:, 1:3) = XT
    end if
    nen = nc
    if (et == ET_QUAD8 .or. et == ET_TRI6) then
      do k = 1, nc
        x(:, nc + k) = 0.5_dp * (x(:, k) + x(:, mod(k, nc) + 1))
      end do
      nen = 2 * nc
    end if
  end subroutine element_nodes

  subroutine test_element(et)
    integer, intent(in) :: et
    type(section_t) :: sec
    real(dp) :: x(2, 8), b(MAX_NSTRAIN, MAX_EDOF), w, u(MAX_EDOF), eps(4), d(4, 4), k(MAX_EDOF, MAX_EDOF), &
      me(MAX_EDOF, MAX_EDOF), ev(MAX_EDOF), work(200), area, rbar, tx(MAX_EDOF), worst, kmax
    integer :: nen, nd, ig, a, info, nzero
    character(len=:), allocatable :: name
    name = etype_name(et)
    sec%axisymmetric = .true.
    call element_nodes(et, x, nen)
    nd = elem_ndof(et)
    do a = 1, nen                                  ! u_r = a r, u_y = b y + d
      u(2 * a - 1) = 1e-3_dp * x(1, a)
      u(2 * a) = -4e-4_dp * x(2, a) + 0.7_dp
    end do
    worst = 0.0_dp
    do ig = 1, elem_ngauss(et, sec)
      call elem_gauss_b(et, x(:, 1:nen), sec, ig, b, w)
      eps = matmul(b(1:4, 1:nd), u(1:nd))
      worst = max(worst, maxval(abs(eps - [1e-3_dp, -4e-4_dp, 1e-3_dp, 0.0_dp])))
    end do
    write (*, '(a, es10.2)') '# ' // name // ' patch: largest strain error', worst
    ! (the round-off of the translation d = 0.7 through the gradients: a few ulps of 0.7)
    call check(worst <= 2e-15_dp, name // ' axisymmetric: u_r = a r, u_y = b y + d gives (a, b, a, 0) at every point ' // &
      '(patch test)')
    call elem_elastic_d(et, 2e11_dp, 0.3_dp, sec, d)
    call elem_stiffness(et, x(:, 1:nen), sec, d, k)
    call dsyev('N', 'U', nd, k(1:nd, 1:nd), nd, ev(1:nd), work, size(work), info)
    kmax = maxval(abs(ev(1:nd)))
    nzero = count(abs(ev(1:nd)) <= 1e-10_dp * kmax)
    ! TRI3's one point also leaves the rotation about its centroid free (its hoop strain vanishes there;
    ! neighbours hold it in a mesh: the Lamé cylinder of tests/scenes/axisymmetric converges)
    call check(info == 0 .and. nzero == merge(2, 1, et == ET_TRI3) .and. minval(ev(1:nd)) > -1e-10_dp * kmax, name // &
      ' axisymmetric: the zero eigenvalues of K: the axial translation (and on TRI3 the rotation about its centroid)')
    call elem_mass(et, x(:, 1:nen), sec, 7800.0_dp, .false., me)
    ! V = 2π r̄ A (Pappus), the polygon's area and centroid (straight sides)
    call polygon(x, merge(4, 3, et == ET_QUAD4 .or. et == ET_QUAD8), area, rbar)
    tx = 0.0_dp
    tx(1:nd:2) = 1.0_dp
    call check_close(dot_product(tx(1:nd), matmul(me(1:nd, 1:nd), tx(1:nd))), 7800.0_dp * 2 * PI * rbar * area, &
      1e-13_dp, name // ' axisymmetric: mass = ρ 2π r̄ A (consistent)')
    call elem_mass(et, x(:, 1:nen), sec, 7800.0_dp, .true., me)
    call check_close(dot_product(tx(1:nd), matmul(me(1:nd, 1:nd), tx(1:nd))), 7800.0_dp * 2 * PI * rbar * area, &
      1e-13_dp, name // ' axisymmetric: mass = ρ 2π r̄ A (lumped)')
  end subroutine test_element

  !> Area and centroid radius of the polygon x(:, 1:n).
  pure subroutine polygon(x, n, area, rbar)
    real(dp), intent(in) :: x(:, :)
    integer, intent(in) :: n
    real(dp), intent(out) :: area, rbar
    real(dp) :: c
    integer :: i, j
    area = 0.0_dp
    rbar = 0.0_dp
    do i = 1, n
      j = mod(i, n) + 1
      c = x(1, i) * x(2, j) - x(1, j) * x(2, i)
      area = area + 0.5_dp * c
      rbar = rbar + (x(1, i) + x(1, j)) * c / 6.0_dp
    end do
    rbar = rbar / area
  end subroutine polygon

  !> One free axisymmetric QUAD4 at XQ (KINEMATICS LARGE STRAIN_MEASURE LOG) with the given material
  !> and MODEL words, built.
  subroutine open_scene(material, model)
    character(len=*), intent(in) :: material, model
    character(len=*), parameter :: path = 'build/tests/axisymmetric_unit.dat'
    character(len=0) :: none(0)
    character(len=:), allocatable :: msg
    integer :: u, stat
    open (newunit=u, file=path, status='replace', action='write')
    write (u, '(a)') 'NODE a AT 1 0', 'NODE b AT 2.1 0.1', 'NODE c AT 2.3 1.2', 'NODE d AT 0.9 1', &
      'ELEMENT e TYPE QUAD4 NODES a b c d', 'MATERIAL m ' // material // ' DENSITY 1', &
      'MODEL e MATERIAL m AXISYMMETRIC KINEMATICS LARGE STRAIN_MEASURE LOG ' // model, 'TIME STEP 1e-2 END 1'
    close (u)
    call load_scene(path, none, scn, stat, msg)
    if (stat == STAT_OK) call build_system(scn, sys, stat, msg)
    call check(stat == STAT_OK, 'axisymmetric LARGE: a free QUAD4 scene builds (' // model // ')')
    if (stat /= STAT_OK) then
      write (*, '(a)') msg
      call test_summary('axisymmetric')
    end if
  end subroutine open_scene

  !> The trial at u from the committed state at un (the path from the reference to un first).
  subroutine trial(un, uu, fn, f, fc, correct, tangent, inc)
    real(dp), intent(in) :: un(:), uu(:)
    real(dp), intent(out) :: fn(:), f(:), fc(:)
    logical, intent(in) :: correct, tangent
    type(work_increment_t), intent(out) :: inc
    sys%pts%eps = 0.0_dp
    sys%pts%sig = 0.0_dp
    sys%pts%q = 0.0_dp
    call internal_force(scn, sys, un, fn, fc, .false., .false., inc)
    call commit_state(sys)
    call internal_force(scn, sys, uu, f, fc, correct, tangent, inc, un=un)
  end subroutine trial

  !> A deformed state of the ring element: a stretch, a shear, a radial bulge and a tilt (s scales it).
  function state(s) result(uu)
    real(dp), intent(in) :: s
    real(dp) :: uu(8), f(2, 2)
    integer :: a
    f = reshape([0.25_dp * s, 0.05_dp * s, 0.2_dp * s, -0.15_dp * s], [2, 2])
    do a = 1, 4
      uu(2 * a - 1:2 * a) = matmul(f, XQ(:, a)) + s * 0.04_dp * [sin(3.0_dp * a), cos(5.0_dp * a)]
    end do
  end function state

  subroutine test_stretch(tag)
    character(len=*), intent(in) :: tag
    real(dp) :: zero(8), uu(8), fn(8), f(8), fc(8), l(4)
    type(work_increment_t) :: inc
    integer :: a
    zero = 0.0_dp
    do a = 1, 4
      uu(2 * a - 1:2 * a) = [0.3_dp * XQ(1, a), -0.2_dp * XQ(2, a)]
    end do
    call trial(zero, uu, fn, f, fc, .false., .false., inc)
    l = [log(1.3_dp), log(0.8_dp), log(1.3_dp), 0.0_dp]
    call check(maxval(abs(sys%pts%eps_t(:, 1:4) - spread(l, 2, 4))) <= 1e-15_dp, 'axisymmetric LARGE (' // tag // &
      '): u_r = 0.3 r, u_y = -0.2 y gives ℓ = (ln 1.3, ln 0.8, ln 1.3, 0) at every point')
  end subroutine test_stretch

  !> f(n+1) = dW/du (W the path work from the reference).
  subroutine test_gradient(tag)
    character(len=*), intent(in) :: tag
    real(dp) :: zero(8), uu(8), up(8), fn(8), f(8), fc(8), fx(8), g(8), wp, wm
    type(work_increment_t) :: inc
    real(dp), parameter :: d = 1e-6_dp
    integer :: j
    zero = 0.0_dp
    uu = state(1.0_dp)
    call trial(zero, uu, fn, f, fc, .false., .false., inc)
    do j = 1, 8
      up = uu
      up(j) = uu(j) + d
      call trial(zero, up, fn, fx, fc, .false., .false., inc)
      wp = inc%work
      up(j) = uu(j) - d
      call trial(zero, up, fn, fx, fc, .false., .false., inc)
      wm = inc%work
      g(j) = (wp - wm) / (2 * d)
    end do
    call check(maxval(abs(f - g)) <= 1e-6_dp * maxval(abs(f)), 'axisymmetric LARGE (' // tag // &
      '): f(n+1) = dW/du (central differences)')
    call check(abs(sum(f(2:8:2))) <= 1e-12_dp * maxval(abs(f)), 'axisymmetric LARGE (' // tag // &
      '): no axial resultant')
  end subroutine test_gradient

  !> Eq (9)'s step force f̄ = (f(n) + f(n+1) + fc)/2 does the laws' path work on a large step.
  subroutine test_path_work(tag)
    character(len=*), intent(in) :: tag
    real(dp) :: un(8), uu(8), fn(8), f(8), fc(8), fb(8), kt(8, 8)
    type(work_increment_t) :: inc
    un = state(0.4_dp)
    uu = state(1.2_dp)
    call trial(un, uu, fn, f, fc, .true., .true., inc)
    fb = 0.5_dp * (fn + f + fc)
    call check_close(dot_product(fb, uu - un), inc%work, 1e-12_dp, 'axisymmetric LARGE (' // tag // &
      '): f̄·Δu = the laws'' path work on a large step')
    if (index(tag, 'J2') > 0) call check(inc%dissipated > 0.01_dp * inc%work, 'axisymmetric LARGE (' // tag // &
      '): the step flows plastically')
    call check(abs(sum(fb(2:8:2))) <= 1e-12_dp * maxval(abs(fb)), 'axisymmetric LARGE (' // tag // &
      '): f̄ has no axial resultant')
    call to_dense(sys%ops%pat, sys%ops%tval, kt)
    call check(maxval(abs(kt - transpose(kt))) <= 1e-12_dp * maxval(abs(kt)), 'axisymmetric LARGE (' // tag // &
      '): the tangent is symmetric')
  end subroutine test_path_work

  !> The tangent (its positive part and the rest, tval + gval) = df(n+1)/du by central differences, at
  !> state(s). (STANDARD keeps only the positive part of the Hencky tangent, log_tangent: exact where
  !> that is positive, s = 0.2; with BBAR the rest goes to gval, exact at s = 1.)
  subroutine test_tangent(tag, s)
    character(len=*), intent(in) :: tag
    real(dp), intent(in) :: s
    real(dp) :: zero(8), uu(8), up(8), fn(8), f(8), fc(8), fp(8), fm(8), kt(8, 8), kg(8, 8), kd(8, 8)
    type(work_increment_t) :: inc
    real(dp), parameter :: d = 1e-6_dp
    integer :: j
    zero = 0.0_dp
    do j = 1, 8
      up = state(s)
      up(j) = up(j) + d
      call trial(zero, up, fn, fp, fc, .false., .false., inc)
      up(j) = up(j) - 2 * d
      call trial(zero, up, fn, fm, fc, .false., .false., inc)
      kd(:, j) = (fp - fm) / (2 * d)
    end do
    uu = state(s)
    call trial(zero, uu, fn, f, fc, .false., .true., inc)
    call to_dense(sys%ops%pat, sys%ops%tval, kt)
    kg = 0.0_dp
    if (allocated(sys%ops%gval)) call to_dense(sys%ops%pat, sys%ops%gval, kg)
    write (*, '(a, es10.2)') '# ' // tag // ' tangent error', maxval(abs(kt + kg - kd)) / maxval(abs(kd))
    call check(maxval(abs(kt + kg - kd)) <= 1e-6_dp * maxval(abs(kd)), 'axisymmetric LARGE (' // tag // &
      '): the tangent (its two parts) = df/du (central differences)')
  end subroutine test_tangent

  subroutine test_axial(tag)
    character(len=*), intent(in) :: tag
    real(dp) :: zero(8), uu(8), fn(8), f(8), fc(8)
    type(work_increment_t) :: inc
    zero = 0.0_dp
    uu = 0.0_dp
    uu(2:8:2) = 3.7_dp
    call trial(zero, uu, fn, f, fc, .false., .false., inc)
    ! (to the round-off of the strain, a few ulps of the translation 3.7, times the modulus λ + 2μ)
    call check(maxval(abs(sys%pts%eps_t(:, 1:4))) <= 1e-15_dp .and. maxval(abs(f)) <= 1e-14_dp * sys%elems%dmat(1, 1, 1), &
      'axisymmetric LARGE (' // tag // '): an axial translation by 3.7, no strain, no force (1e-14 of λ + 2μ)')
  end subroutine test_axial
end program test_axisymmetric
