!> KINEMATICS LARGE element kernels (large_kinematics) against finite differences and identities:
!> the corotational BEAM2's forces are the gradient of its strain energy, its tangent is their
!> Jacobian where the kernel keeps the exact terms, the step force of eq (9) does the exact path
!> work (f̄·Δu = the laws' work, any step), and a rigid motion leaves no strain.
program test_large_kinematics
  use kinds, only: dp
  use errors, only: STAT_OK
  use scene, only: scene_t
  use scene_loader, only: load_scene
  use assembly, only: system_t, build_system, commit_state
  use internal_forces, only: internal_force, work_increment_t
  use sparse_matrix, only: to_dense
  use testing, only: check, check_close, test_summary
  implicit none
  character(len=*), parameter :: path = 'build/tests/large_beam_unit.dat'
  type(scene_t) :: scn
  type(system_t) :: sys
  integer :: stat, u
  character(len=:), allocatable :: msg
  character(len=0) :: none(0)

  open (newunit=u, file=path, status='replace', action='write')
  write (u, '(a)') 'NODE a AT 0.1 0.2', 'NODE b AT 0.9 0.5', 'ELEMENT e TYPE BEAM2 NODES a b', &
    'MATERIAL m ELASTIC YOUNG 1e4 DENSITY 1', 'SECTION s AREA 0.01 INERTIA 1e-3 HEIGHT 0.3', &
    'MODEL e MATERIAL m SECTION s KINEMATICS LARGE', 'TIME STEP 1e-2 END 1'
  close (u)
  call load_scene(path, none, scn, stat, msg)
  if (stat == STAT_OK) call build_system(scn, sys, stat, msg)
  call check(stat == STAT_OK, 'large: a free LARGE BEAM2 scene builds')
  if (stat /= STAT_OK) then
    write (*, '(a)') msg
    call test_summary('large_kinematics')
  end if
  call check(count(sys%dofs%cayley) == 2 .and. all(sys%dofs%cayley([3, 6])), &
    'large: both rotations of a free LARGE BEAM2 take the Cayley update (cayley_rotations)')
  ! The kernel's own identities first, rotations additive (the path from the reference).
  sys%dofs%cayley = .false.
  call test_gradient()
  call test_tangent()
  call test_path_work(.false.)
  call test_rigid()
  ! The rotations of a time step turned by the Cayley angle of their increments (cayley_rotations).
  sys%dofs%cayley = .false.
  sys%dofs%cayley([3, 6]) = .true.
  call test_path_work(.true.)
  call test_cayley_rigid()
  call test_summary('large_kinematics')

contains

  !> The committed state at un (path from the reference), then the trial at u.
  subroutine trial(un, uu, f, fc, correct, tangent, inc)
    real(dp), intent(in) :: un(:), uu(:)
    real(dp), intent(out) :: f(:), fc(:)
    logical, intent(in) :: correct, tangent
    type(work_increment_t), intent(out) :: inc
    sys%pts%eps = 0.0_dp
    sys%pts%sig = 0.0_dp
    call internal_force(scn, sys, un, f, fc, .false., .false., inc)
    call commit_state(sys)
    call internal_force(scn, sys, uu, f, fc, correct, tangent, inc, un=un)
  end subroutine trial

  !> The element rotated rigidly by phi about node a (translations and both rotations), plus w.
  function rotated(phi, w) result(uu)
    real(dp), intent(in) :: phi, w(6)
    real(dp) :: uu(6), x(2)
    x = [0.8_dp, 0.3_dp]   ! node b from node a
    uu = [0.0_dp, 0.0_dp, phi, cos(phi) * x(1) - sin(phi) * x(2) - x(1), sin(phi) * x(1) + cos(phi) * x(2) - x(2), phi] + w
  end function rotated

  !> f(n+1) is the gradient of the strain energy (the path work from the reference, elastic),
  !> by central differences, at a rotated, stretched and bent state.
  subroutine test_gradient()
    real(dp) :: zero(6), uu(6), f(6), fc(6), up(6), g(6), wp, wm, fx(6)
    type(work_increment_t) :: inc
    integer :: j
    real(dp), parameter :: d = 1e-6_dp
    zero = 0.0_dp
    uu = rotated(0.7_dp, [0.01_dp, -0.02_dp, 0.05_dp, 0.03_dp, 0.01_dp, -0.08_dp])
    call trial(zero, uu, f, fc, .false., .false., inc)
    do j = 1, 6
      up = uu
      up(j) = uu(j) + d
      call trial(zero, up, fx, fc, .false., .false., inc)
      wp = inc%work
      up(j) = uu(j) - d
      call trial(zero, up, fx, fc, .false., .false., inc)
      wm = inc%work
      g(j) = (wp - wm) / (2 * d)
    end do
    call check(maxval(abs(f - g)) <= 1e-6_dp * maxval(abs(f)), 'large BEAM2: f(n+1) = dW/du (central differences)')
    call check(abs(sum(f([1, 4]))) + abs(sum(f([2, 5]))) <= 1e-12_dp * maxval(abs(f)), 'large BEAM2: f(n+1) has no resultant')
  end subroutine test_gradient

  !> The tangent without the correction is the Jacobian of f(n+1) where the kernel keeps every
  !> term: a rotated element in antisymmetric bending (no axial force, M1 + M2 = 0).
  subroutine test_tangent()
    real(dp) :: zero(6), uu(6), f(6), fc(6), fp(6), fm(6), kt(6, 6), kfd(6, 6), up(6)
    type(work_increment_t) :: inc
    integer :: j
    real(dp), parameter :: d = 1e-6_dp
    zero = 0.0_dp
    uu = rotated(1.1_dp, [0.0_dp, 0.0_dp, 0.1_dp, 0.0_dp, 0.0_dp, -0.1_dp])
    call trial(zero, uu, f, fc, .false., .true., inc)
    call to_dense(sys%ops%pat, sys%ops%tval, kt)
    do j = 1, 6
      up = uu
      up(j) = uu(j) + d
      call trial(zero, up, fp, fc, .false., .false., inc)
      up(j) = uu(j) - d
      call trial(zero, up, fm, fc, .false., .false., inc)
      kfd(:, j) = (fp - fm) / (2 * d)
    end do
    call check(maxval(abs(kt - kfd)) <= 1e-6_dp * maxval(abs(kfd)), 'large BEAM2: tangent = Jacobian of f(n+1) (bending)')
  end subroutine test_tangent

  !> Eq (9)'s step force f̄ = (f(n) + f(n+1) + fc)/2 does the laws' path work exactly, however
  !> large the step (0.6 rad of rotation, 2 % stretch, bending): f̄·Δu = W_N to round-off; it has no
  !> resultant (linear momentum). Its moment about the step's middle configuration: with additive
  !> rotations the O(Δα²) of the end moments; with the Cayley update, zero to round-off
  !> (docs/large-displacements.md).
  subroutine test_path_work(cayley)
    logical, intent(in) :: cayley
    real(dp) :: zero(6), un(6), uu(6), fn(6), f(6), fc(6), fb(6), xm(2, 2), mom
    character(len=:), allocatable :: tag
    type(work_increment_t) :: inc
    zero = 0.0_dp
    un = rotated(0.3_dp, [0.01_dp, 0.0_dp, 0.04_dp, 0.0_dp, 0.0_dp, -0.02_dp])
    uu = rotated(0.9_dp, [0.0_dp, 0.02_dp, -0.05_dp, 0.015_dp, 0.0_dp, 0.06_dp])
    tag = trim(merge('Cayley  ', 'additive', cayley))
    call reference_state(un, fn)
    call internal_force(scn, sys, uu, f, fc, .true., .false., inc, un=un)
    fb = 0.5_dp * (fn + f + fc)
    call check_close(dot_product(fb, uu - un), inc%work, 1e-13_dp, 'large BEAM2 (' // tag // &
      '): f̄·Δu = the path work, step of 0.6 rad')
    call check(abs(fb(1) + fb(4)) + abs(fb(2) + fb(5)) <= 1e-12_dp * maxval(abs(fb)), 'large BEAM2 (' // tag // &
      '): f̄ has no resultant')
    xm(:, 1) = [0.1_dp, 0.2_dp] + 0.5_dp * (un(1:2) + uu(1:2))
    xm(:, 2) = [0.9_dp, 0.5_dp] + 0.5_dp * (un(4:5) + uu(4:5))
    mom = xm(1, 1) * fb(2) - xm(2, 1) * fb(1) + xm(1, 2) * fb(5) - xm(2, 2) * fb(4) + fb(3) + fb(6)
    if (cayley) then
      call check(abs(mom) <= 1e-13_dp * maxval(abs(fb)), 'large BEAM2 (Cayley): f̄ has no moment about the middle ' // &
        'configuration (angular momentum kept)')
    else
      call check(abs(mom) <= 0.05_dp * maxval(abs(fb(3:6:3))) .and. abs(mom) > 1e-6_dp * maxval(abs(fb)), &
        'large BEAM2 (additive): f̄''s moment about the middle configuration small (O(Δα²) of the end moments), not zero')
    end if
  end subroutine test_path_work

  !> The committed state at un along the path from the reference (the rotations as given).
  subroutine reference_state(un, fn)
    real(dp), intent(in) :: un(:)
    real(dp), intent(out) :: fn(:)
    real(dp) :: fc(6)
    type(work_increment_t) :: inc
    sys%pts%eps = 0.0_dp
    sys%pts%sig = 0.0_dp
    call internal_force(scn, sys, un, fn, fc, .false., .false., inc)
    call commit_state(sys)
  end subroutine reference_state

  !> With the Cayley update a rigid rotation by φ is a step that moves the nodes by the rotation and
  !> the rotation DOFs by Δw = 2 tan(φ/2): no strain, no step force, for φ up to 170 degrees, from a
  !> state turned by 1000 revolutions.
  subroutine test_cayley_rigid()
    real(dp) :: un(6), uu(6), fn(6), f(6), fc(6), fb(6), phi
    real(dp), parameter :: pi = acos(-1.0_dp), phis(3) = [0.3_dp, 1.5_dp, 2.97_dp]
    type(work_increment_t) :: inc
    integer :: k
    do k = 1, 3
      phi = phis(k)
      un = rotated(2000.0_dp * pi + 0.2_dp, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp])
      call reference_state(un, fn)
      uu = rotated(2000.0_dp * pi + 0.2_dp + phi, [0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp])
      uu([3, 6]) = un([3, 6]) + 2.0_dp * tan(0.5_dp * phi)
      call internal_force(scn, sys, uu, f, fc, .true., .false., inc, un=un)
      fb = 0.5_dp * (fn + f + fc)
      call check(maxval(abs(sys%pts%eps_t(1:2, :))) <= 1e-11_dp .and. maxval(abs(fb)) <= 1e-7_dp, &
        'large BEAM2 (Cayley): a rigid step of ' // trim(real_text(phi)) // ' rad leaves no strain, no force')
    end do
  end subroutine test_cayley_rigid

  pure function real_text(x) result(s)
    real(dp), intent(in) :: x
    character(len=16) :: s
    write (s, '(f6.2)') x
  end function real_text

  !> A rigid rotation by 90 degrees, and by 1000 revolutions and 90 degrees, leaves no strain and
  !> no force (the rotations relative to the chord are taken modulo 2 pi).
  subroutine test_rigid()
    real(dp) :: zero(6), f(6), fc(6)
    real(dp), parameter :: pi = acos(-1.0_dp)
    type(work_increment_t) :: inc
    zero = 0.0_dp
    call trial(zero, rotated(0.5_dp * pi, zero), f, fc, .false., .false., inc)
    call check(maxval(abs(sys%pts%eps_t(1:2, :))) <= 1e-15_dp .and. maxval(abs(f)) <= 1e-10_dp, &
      'large BEAM2: rigid rotation by 90 degrees, no strain, no force')
    call trial(zero, rotated(2000.5_dp * pi, zero), f, fc, .false., .false., inc)
    call check(maxval(abs(sys%pts%eps_t(1:2, :))) <= 1e-11_dp .and. maxval(abs(f)) <= 1e-7_dp, &
      'large BEAM2: rigid rotation by 1000 turns + 90 degrees, no strain (round-off of 6283 rad)')
  end subroutine test_rigid
end program test_large_kinematics
