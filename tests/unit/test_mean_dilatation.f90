!> FORMULATION BBAR (docs/locking.md) on one distorted QUAD4: the points' strains take the
!> element's mean dilatation. Checked: the in-plane traces of the points' strains are equal; an
!> affine motion gives every point the exact strain of the standard element (the patch test); in
!> KINEMATICS LARGE STRAIN_MEASURE LOG the forces are the gradient of the stored energy (central
!> differences) and the step force of eq (9) does the laws' exact path work (elastic and plastic,
!> a large step), a rigid rotation leaves no strain and no force; in small strain B-bar's forces
!> are K u with K symmetric.
program test_mean_dilatation
  use kinds, only: dp
  use errors, only: STAT_OK
  use scene, only: scene_t
  use scene_loader, only: load_scene
  use assembly, only: system_t, build_system, commit_state
  use internal_forces, only: internal_force, work_increment_t
  use sparse_matrix, only: to_dense
  use testing, only: check, check_close, test_summary
  implicit none
  real(dp), parameter :: X(2, 4) = reshape([0.0_dp, 0.0_dp, 1.1_dp, 0.1_dp, 0.9_dp, 0.8_dp, -0.1_dp, 1.2_dp], [2, 4])
  type(scene_t) :: scn
  type(system_t) :: sys

  call open_scene('ELASTIC YOUNG 1e4 POISSON 0.45', 'KINEMATICS LARGE STRAIN_MEASURE LOG FORMULATION BBAR')
  call test_traces()
  call test_patch('LARGE LOG')
  call test_gradient('LARGE LOG')
  call test_path_work('Hencky')
  call test_rigid('LARGE LOG')
  call open_scene('HYPERELASTIC YOUNG 1e4 POISSON 0.495', 'KINEMATICS LARGE')
  call check(scn%models(1)%bbar, 'BBAR: the default of a plane-strain HYPERELASTIC QUAD4 at POISSON 0.495')
  call test_patch('neo-Hookean')
  call test_gradient('neo-Hookean')
  call test_path_work('neo-Hookean')
  call test_rigid('neo-Hookean')
  call open_scene('VON_MISES YOUNG 1e4 POISSON 0.3 YIELD 20 H_ISO 100', 'KINEMATICS LARGE STRAIN_MEASURE LOG')
  call check(scn%models(1)%bbar, 'BBAR: the default of a plane-strain VON_MISES QUAD4 (FORMULATION AUTO)')
  call test_path_work('J2')
  call open_scene('ELASTIC YOUNG 1e4 POISSON 0.49', 'FORMULATION BBAR')
  call test_small()
  call test_summary('mean_dilatation')

contains

  !> A free QUAD4 at X with the given material and MODEL words, built.
  subroutine open_scene(material, model)
    character(len=*), intent(in) :: material, model
    character(len=*), parameter :: path = 'build/tests/mean_dilatation_unit.dat'
    character(len=0) :: none(0)
    character(len=:), allocatable :: msg
    integer :: u, stat
    open (newunit=u, file=path, status='replace', action='write')
    write (u, '(a)') 'NODE a AT 0 0', 'NODE b AT 1.1 0.1', 'NODE c AT 0.9 0.8', 'NODE d AT -0.1 1.2', &
      'ELEMENT e TYPE QUAD4 NODES a b c d', 'MATERIAL m ' // material // ' DENSITY 1', 'SECTION s THICKNESS 1', &
      'MODEL e MATERIAL m SECTION s ' // model, 'TIME STEP 1e-2 END 1'
    close (u)
    call load_scene(path, none, scn, stat, msg)
    if (stat == STAT_OK) call build_system(scn, sys, stat, msg)
    call check(stat == STAT_OK, 'BBAR: a free QUAD4 scene builds (' // model // ')')
    if (stat /= STAT_OK) then
      write (*, '(a)') msg
      call test_summary('mean_dilatation')
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

  !> A stretched, sheared, compressed state (det F about 0.8), rotated by phi.
  function state(phi, s) result(uu)
    real(dp), intent(in) :: phi, s
    real(dp) :: uu(8), f(2, 2), r(2, 2)
    integer :: a
    r = reshape([cos(phi), sin(phi), -sin(phi), cos(phi)], [2, 2])
    f = matmul(r, reshape([1.0_dp - 0.2_dp * s, 0.05_dp * s, 0.3_dp * s, 1.0_dp + 0.05_dp * s], [2, 2]))
    do a = 1, 4
      uu(2 * a - 1:2 * a) = matmul(f, X(:, a)) - X(:, a) + s * 0.03_dp * [sin(3.0_dp * a), cos(5.0_dp * a)]
    end do
  end function state

  subroutine test_traces()
    real(dp) :: zero(8), fn(8), f(8), fc(8), tr(4)
    type(work_increment_t) :: inc
    zero = 0.0_dp
    call trial(zero, state(0.4_dp, 1.0_dp), fn, f, fc, .false., .false., inc)
    tr = sys%pts%eps_t(1, 1:4) + sys%pts%eps_t(2, 1:4)
    call check(maxval(abs(tr - tr(1))) <= 1e-15_dp * 4 .and. maxval(abs(sys%pts%eps_t(4, :) - sys%pts%eps_t(4, 1))) > &
      1e-3_dp, 'BBAR (LARGE LOG): the points share the in-plane trace of ℓ̄ (ln J, the mean), not their shear')
  end subroutine test_traces

  !> An affine motion u = (F - I) X: every point has the same F, the mean is each point's own, and
  !> the forces are those of the standard element.
  subroutine test_patch(tag)
    character(len=*), intent(in) :: tag
    real(dp) :: zero(8), fn(8), f(8), fc(8), fs(8), uu(8), f1(2, 2)
    type(work_increment_t) :: inc
    integer :: a
    zero = 0.0_dp
    f1 = reshape([0.8_dp, 0.1_dp, 0.25_dp, 1.1_dp], [2, 2])
    do a = 1, 4
      uu(2 * a - 1:2 * a) = matmul(f1, X(:, a)) - X(:, a)
    end do
    call trial(zero, uu, fn, f, fc, .false., .false., inc)
    scn%models(1)%bbar = .false.
    call trial(zero, uu, fn, fs, fc, .false., .false., inc)
    scn%models(1)%bbar = .true.
    call check(maxval(abs(f - fs)) <= 1e-12_dp * maxval(abs(fs)), 'BBAR (' // tag // '): an affine motion, the forces ' // &
      'of the standard element (patch test)')
  end subroutine test_patch

  !> f(n+1) = dW/du (W the path work from the reference: the Hencky energy of ℓ̄).
  subroutine test_gradient(tag)
    character(len=*), intent(in) :: tag
    real(dp) :: zero(8), uu(8), up(8), fn(8), f(8), fc(8), fx(8), g(8), wp, wm
    type(work_increment_t) :: inc
    real(dp), parameter :: d = 1e-6_dp
    integer :: j
    zero = 0.0_dp
    uu = state(0.7_dp, 1.0_dp)
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
    call check(maxval(abs(f - g)) <= 1e-6_dp * maxval(abs(f)), 'BBAR (' // tag // '): f(n+1) = dW/du (central differences)')
    call check(abs(sum(f(1:7:2))) + abs(sum(f(2:8:2))) <= 1e-12_dp * maxval(abs(f)), 'BBAR (' // tag // '): no resultant')
  end subroutine test_gradient

  !> Eq (9)'s step force f̄ = (f(n) + f(n+1) + fc)/2 does the laws' path work on a large step.
  subroutine test_path_work(tag)
    character(len=*), intent(in) :: tag
    real(dp) :: un(8), uu(8), fn(8), f(8), fc(8), fb(8), kt(8, 8)
    type(work_increment_t) :: inc
    un = state(0.2_dp, 0.5_dp)
    uu = state(0.9_dp, 1.2_dp)
    call trial(un, uu, fn, f, fc, .true., .true., inc)
    fb = 0.5_dp * (fn + f + fc)
    call check_close(dot_product(fb, uu - un), inc%work, 1e-12_dp, 'BBAR (LARGE LOG, ' // tag // &
      '): f̄·Δu = the laws'' path work, a step of 0.7 rad and 20 % strain')
    if (tag == 'J2') call check(inc%dissipated > 0.01_dp * inc%work, 'BBAR (LARGE LOG, J2): the step flows plastically')
    call check(abs(sum(fb(1:7:2))) + abs(sum(fb(2:8:2))) <= 1e-12_dp * maxval(abs(fb)), 'BBAR (LARGE LOG, ' // tag // &
      '): f̄ has no resultant')
    call to_dense(sys%ops%pat, sys%ops%tval, kt)
    call check(maxval(abs(kt - transpose(kt))) <= 1e-12_dp * maxval(abs(kt)), 'BBAR (LARGE LOG, ' // tag // &
      '): the tangent is symmetric')
  end subroutine test_path_work

  subroutine test_rigid(tag)
    character(len=*), intent(in) :: tag
    real(dp) :: zero(8), uu(8), fn(8), f(8), fc(8)
    type(work_increment_t) :: inc
    zero = 0.0_dp
    uu = state(2.0_dp, 0.0_dp)
    call trial(zero, uu, fn, f, fc, .false., .false., inc)
    ! (no force: to the round-off of the strain, a few ulps, times the modulus λ + 2μ, dmat(1, 1))
    call check(maxval(abs(sys%pts%eps_t(:, 1:4))) <= 1e-14_dp .and. maxval(abs(f)) <= 1e-14_dp * sys%elems%dmat(1, 1, 1), &
      'BBAR (' // tag // '): a rigid rotation by 2 rad, no strain, no force (1e-14 of λ + 2μ)')
  end subroutine test_rigid

  !> Small strain: B-bar. The points' strains B̄ u (point_b) share their in-plane trace, and an
  !> affine u gives each its exact strain; f = K0 u, K0 symmetric.
  subroutine test_small()
    real(dp) :: zero(8), uu(8), fn(8), f(8), fc(8), k0(8, 8), ep(4, 4), e0(4)
    type(work_increment_t) :: inc
    integer :: a
    zero = 0.0_dp
    uu = state(0.0_dp, 1e-3_dp)
    call trial(zero, uu, fn, f, fc, .false., .false., inc)
    call strains(uu, ep)
    call check(maxval(abs(ep(1, :) + ep(2, :) - ep(1, 1) - ep(2, 1))) <= 1e-18_dp .and. &
      maxval(abs(ep(4, :) - ep(4, 1))) > 1e-6_dp, 'B-bar: the points share the in-plane trace of ε̄, not their shear')
    call to_dense(sys%ops%pat, sys%ops%kval, k0)
    call check(maxval(abs(f - matmul(k0, uu))) <= 1e-12_dp * maxval(abs(f)) .and. &
      maxval(abs(k0 - transpose(k0))) <= 1e-12_dp * maxval(abs(k0)), 'B-bar: f = K0 u, K0 symmetric')
    do a = 1, 4
      uu(2 * a - 1:2 * a) = matmul(reshape([1e-3_dp, 2e-4_dp, -5e-4_dp, 3e-4_dp], [2, 2]), X(:, a))
    end do
    call strains(uu, ep)
    e0 = [1e-3_dp, 3e-4_dp, 0.0_dp, -3e-4_dp]
    call check(maxval(abs(ep - spread(e0, 2, 4))) <= 1e-18_dp, 'B-bar: an affine u gives every point its exact ' // &
      'strain (patch test)')
  end subroutine test_small

  !> The four points' strains B̄ u.
  subroutine strains(uu, ep)
    real(dp), intent(in) :: uu(8)
    real(dp), intent(out) :: ep(4, 4)
    real(dp) :: b(4, 8)
    integer :: g
    do g = 1, 4
      call sys%elems%point_b(g, 4, 8, b)
      ep(:, g) = matmul(b, uu)
    end do
  end subroutine strains
end program test_mean_dilatation
