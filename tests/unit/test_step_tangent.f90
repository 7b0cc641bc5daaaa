!> The iteration matrix of eq (9) against the Jacobian of its forces: J of the step's force
!> f(n+1) + fc by central differences on one distorted element over a large step (2 % strain at n,
!> 1 % more in the step), against the assembled symmetric tangent K (tval + gval) plus the
!> antisymmetric part A (aval) that iterate_eq9's anti_sweep takes in. KINEMATICS LARGE (large_plane's
!> and large_solid's step tangent: the force 2 B_NL(F_mid)' S̄), St Venant-Kirchhoff, Hencky with and
!> without B-bar, J2 on E and on the Hencky strain, plane strain, axisymmetric and HEX8; and the
!> small-strain J2 QUAD4 (the law's path-mean tangent dbar is not symmetric). Checked:
!> ‖J − K − A‖ ≤ 1e-4 ‖J‖ (St Venant) and 1e-3 ‖J‖ (the others); A is J's antisymmetric part to 1e-6
!> (St Venant), 1 % (J2) and 20 % (the log map's secant, left out of A); K + A is 2 to 100 times
!> closer to J than K alone (Newton's contraction per iterate is about ‖S⁻¹(J − K − A)‖: the Taylor
!> bar's 1/50 with K alone, docs/large-displacements.md "The step tangent").
program test_step_tangent
  use kinds, only: dp
  use errors, only: STAT_OK
  use scene, only: scene_t
  use scene_loader, only: load_scene
  use assembly, only: system_t, build_system, commit_state
  use internal_forces, only: internal_force, work_increment_t
  use sparse_matrix, only: to_dense
  use testing, only: check, test_summary
  implicit none
  character(len=*), parameter :: ELASTIC = 'ELASTIC YOUNG 1e4 POISSON 0.3 DENSITY 1', &
    J2 = 'VON_MISES YOUNG 1e4 POISSON 0.3 DENSITY 1 YIELD 50 H_ISO 10 H_KIN 0'
  integer, parameter :: PLANE = 1, AXI = 2, SOLID = 3, SMALL = 4
  type(scene_t) :: scn
  type(system_t) :: sys

  call case('St Venant', ELASTIC, 'FORMULATION STANDARD', PLANE, 1e-4_dp, 1e-6_dp, 0.02_dp)
  call case('St Venant, B-bar', ELASTIC, 'FORMULATION BBAR', PLANE, 1e-4_dp, 1e-6_dp, 0.02_dp)
  call case('Hencky, B-bar', ELASTIC, 'STRAIN_MEASURE LOG FORMULATION BBAR', PLANE, 1e-3_dp, 0.2_dp, 0.5_dp)
  call case('Hencky', ELASTIC, 'STRAIN_MEASURE LOG FORMULATION STANDARD', PLANE, 1e-3_dp, 0.2_dp, 0.5_dp)
  call case('J2 on E', J2, 'FORMULATION STANDARD SUBSTEPS 8', PLANE, 1e-3_dp, 1e-2_dp, 0.05_dp)
  call case('J2 on Hencky, B-bar', J2, 'STRAIN_MEASURE LOG FORMULATION BBAR', PLANE, 1e-3_dp, 1e-2_dp, 0.05_dp)
  call case('J2 on Hencky, axisymmetric', J2, 'STRAIN_MEASURE LOG AXISYMMETRIC', AXI, 1e-3_dp, 1e-2_dp, 0.05_dp)
  call case('St Venant, HEX8', ELASTIC, '', SOLID, 1e-4_dp, 1e-6_dp, 0.02_dp)
  call case('J2 on E, HEX8', J2, 'SUBSTEPS 8', SOLID, 1e-3_dp, 1e-2_dp, 0.05_dp)
  call case('J2 small strain, QUAD4', J2, 'SUBSTEPS 8', SMALL, 1e-3_dp, 1e-2_dp, 0.05_dp)
  call test_summary('step_tangent')

contains

  !> One element, the step's J by central differences against tval + gval + aval.
  !> tol: ‖J − K − A‖ / ‖J‖; tol_anti: ‖J_a − A‖ / ‖J_a‖ (J_a = ½(J − J')); gain: ‖J − K − A‖ / ‖J − K‖.
  subroutine case(label, material, model, kind, tol, tol_anti, gain)
    character(len=*), intent(in) :: label, material, model
    integer, intent(in) :: kind
    real(dp), intent(in) :: tol, tol_anti, gain
    real(dp), allocatable :: un(:), u1(:), f(:), fc(:), fp(:), fm(:), k(:, :), kg(:, :), ka(:, :), jfd(:, :), up(:), &
      ja(:, :)
    real(dp), parameter :: d = 1e-7_dp
    integer :: n, j, i, stat
    character(len=:), allocatable :: msg
    call open_scene(material, model, kind, stat, msg)
    call check(stat == STAT_OK, 'step tangent: ' // label // ': the one-element scene builds')
    if (stat /= STAT_OK) then
      write (*, '(a)') msg
      return
    end if
    call check(allocated(sys%ops%aval), 'step tangent: ' // label // ': the antisymmetric part is kept (aval)')
    if (.not. allocated(sys%ops%aval)) return
    n = sys%dofs%neq
    allocate (un(n), u1(n), f(n), fc(n), fp(n), fm(n), k(n, n), kg(n, n), ka(n, n), jfd(n, n), up(n), ja(n, n))
    do j = 1, n                             ! 2 % strain at n, 1 % more in the step (no symmetry)
      un(j) = 0.02_dp * sin(1.3_dp * j)
      u1(j) = un(j) + 0.009_dp * cos(0.7_dp * j + 0.2_dp)
    end do
    call trial(un, u1, f, fc, .true.)
    call to_dense(sys%ops%pat, sys%ops%tval, k)
    kg = 0.0_dp
    if (allocated(sys%ops%gval)) call to_dense(sys%ops%pat, sys%ops%gval, kg)
    call to_dense(sys%ops%pat, sys%ops%aval, ka)
    do j = 1, n                             ! to_dense mirrors: the lower triangle of A is -A'
      do i = j + 1, n
        ka(i, j) = -ka(j, i)
      end do
      ka(j, j) = 0.0_dp
    end do
    k = k + kg
    do j = 1, n
      up = u1
      up(j) = u1(j) + d
      call trial(un, up, fp, fc, .false.)
      fp = fp + fc
      up(j) = u1(j) - d
      call trial(un, up, fm, fc, .false.)
      fm = fm + fc
      jfd(:, j) = (fp - fm) / (2 * d)
    end do
    ja = 0.5_dp * (jfd - transpose(jfd))
    write (*, '(2x, a, ": |J| ", es9.2, ", |J - K| ", es9.2, ", |J - K - A| ", es9.2, ", |J_a - A| ", es9.2)') &
      label, maxval(abs(jfd)), maxval(abs(jfd - k)), maxval(abs(jfd - k - ka)), maxval(abs(ja - ka))
    call check(maxval(abs(jfd - k - ka)) <= tol * maxval(abs(jfd)), &
      'step tangent: ' // label // ': K + A is the Jacobian of eq (9)''s force')
    call check(maxval(abs(ja - ka)) <= tol_anti * maxval(abs(ja)), &
      'step tangent: ' // label // ': A is the Jacobian''s antisymmetric part')
    call check(maxval(abs(jfd - k - ka)) <= gain * maxval(abs(jfd - k)), &
      'step tangent: ' // label // ': A takes out most of the symmetric tangent''s error')
  end subroutine case

  subroutine open_scene(material, model, kind, stat, msg)
    character(len=*), intent(in) :: material, model
    integer, intent(in) :: kind
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: msg
    character(len=*), parameter :: path = 'build/tests/step_tangent.dat'
    character(len=0) :: none(0)
    integer :: u
    open (newunit=u, file=path, status='replace', action='write')
    if (kind == SOLID) then
      write (u, '(a)') 'DIMENSION 3', 'BOX e ORIGIN 0 0 0 SIZE 1 0.9 1.1 ELEMENTS 1 1 1 TYPE HEX8', &
        'MATERIAL m ' // material, 'TIME STEP 1e-2 END 1', 'MODEL e MATERIAL m KINEMATICS LARGE ' // model
    else
      write (u, '(a)') 'NODE a AT 0.1 0 ', 'NODE b AT 1.2 0.1', 'NODE c AT 1.0 0.8', 'NODE d AT 0.05 1.2', &
        'ELEMENT e TYPE QUAD4 NODES a b c d', 'MATERIAL m ' // material, 'TIME STEP 1e-2 END 1'
    end if
    if (kind == AXI) then
      write (u, '(a)') 'MODEL e MATERIAL m KINEMATICS LARGE ' // model
    else if (kind == PLANE) then
      write (u, '(a)') 'SECTION t THICKNESS 1', 'MODEL e MATERIAL m SECTION t KINEMATICS LARGE ' // model
    else if (kind == SMALL) then
      write (u, '(a)') 'SECTION t THICKNESS 1', 'MODEL e MATERIAL m SECTION t ' // model
    end if
    close (u)
    call load_scene(path, none, scn, stat, msg)
    if (stat == STAT_OK) call build_system(scn, sys, stat, msg)
  end subroutine open_scene

  !> The committed state at un (its path from the reference; the points' variables reset), then
  !> the trial at uu with eq (9)'s correction.
  subroutine trial(un, uu, f, fc, tangent)
    real(dp), intent(in) :: un(:), uu(:)
    real(dp), intent(out) :: f(:), fc(:)
    logical, intent(in) :: tangent
    type(work_increment_t) :: inc
    sys%pts%eps = 0.0_dp
    sys%pts%sig = 0.0_dp
    sys%pts%q = 0.0_dp
    sys%pts%nsub_pt = 0
    call internal_force(scn, sys, un, f, fc, .false., .false., inc)
    call commit_state(sys)
    call internal_force(scn, sys, uu, f, fc, .true., tangent, inc, un=un)
  end subroutine trial
end program test_step_tangent
