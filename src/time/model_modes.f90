!> The rigid modes of a model on its free equations (translations and rotations about the origin,
!> reference configuration), whose products with M v are history.csv's momenta and about which the
!> impact corrections scale a group's velocity (impact_space).
module model_modes
  use kinds, only: dp
  use scene, only: scene_t
  use assembly, only: system_t, mass_times
  use mesh, only: DOF_UX, DOF_UY, DOF_UZ, DOF_RZ
  implicit none
  private
  public :: rigid_modes, rotation_mode

contains

  !> The rigid modes of the model on the free equations: in 2D the translations x and y and the
  !> rotation about the origin (-y, x on the translations, 1 on RZ); in 3D those, then the
  !> translation z and the rotations about the x and y axes (reference configuration: the kinematics
  !> are linearized), with M times them. Their products with M v are the linear and angular momenta
  !> (history.csv); PERSIST scales a group about its rigid motion.
  subroutine rigid_modes(scn, sys, rig, mrig)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), allocatable, intent(out) :: rig(:, :), mrig(:, :)   !< (neq, 3 or 6): the modes, M times them
    integer :: j, k, nrig
    nrig = merge(6, 3, scn%mesh%ndim == 3)
    allocate (rig(sys%dofs%neq, nrig), mrig(sys%dofs%neq, nrig))
    rig = 0.0_dp
    do j = 1, scn%mesh%nnode
      associate (e => sys%dofs%eqn(:, j))
        if (e(DOF_UX) > 0) rig(e(DOF_UX), 1) = 1.0_dp
        if (e(DOF_UY) > 0) rig(e(DOF_UY), 2) = 1.0_dp
        if (nrig == 6 .and. e(DOF_UZ) > 0) rig(e(DOF_UZ), 4) = 1.0_dp
      end associate
    end do
    call rotation_mode(scn, sys, rig(:, 3))
    if (nrig == 6) call axis_rotations(scn, sys, rig(:, 5), rig(:, 6))
    do k = 1, nrig
      call mass_times(sys, rig(:, k), mrig(:, k))
    end do
  end subroutine rigid_modes

  !> The rotation about the origin on the free equations, r (neq): -y on UX, x on UY, 1 on RZ, at the
  !> positions X, or X + u + du when given (end_geometry: the end of a step). Other entries untouched.
  pure subroutine rotation_mode(scn, sys, r, u, du)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(inout) :: r(:)
    real(dp), intent(in), optional :: u(:), du(:)
    real(dp) :: p(2)
    integer :: j, d
    do j = 1, scn%mesh%nnode
      associate (e => sys%dofs%eqn(:, j))
        p = scn%mesh%x(1:2, j)
        if (present(u) .and. present(du)) then
          do d = 1, 2
            if (e(d) > 0) p(d) = p(d) + (u(e(d)) + du(e(d)))
          end do
        end if
        if (e(DOF_UX) > 0) r(e(DOF_UX)) = -p(2)
        if (e(DOF_UY) > 0) r(e(DOF_UY)) = p(1)
        if (e(DOF_RZ) > 0) r(e(DOF_RZ)) = 1.0_dp
      end associate
    end do
  end subroutine rotation_mode

  !> 3D: the rotations about the x axis (rx: -z on UY, y on UZ) and the y axis (ry: z on UX, -x on
  !> UZ) through the origin, on the free equations at the reference positions.
  pure subroutine axis_rotations(scn, sys, rx, ry)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(inout) :: rx(:), ry(:)
    integer :: j
    do j = 1, scn%mesh%nnode
      associate (e => sys%dofs%eqn(:, j), p => scn%mesh%x(:, j))
        if (e(DOF_UY) > 0) rx(e(DOF_UY)) = -p(3)
        if (e(DOF_UZ) > 0) rx(e(DOF_UZ)) = p(2)
        if (e(DOF_UX) > 0) ry(e(DOF_UX)) = p(3)
        if (e(DOF_UZ) > 0) ry(e(DOF_UZ)) = -p(1)
      end associate
    end do
  end subroutine axis_rotations
end module model_modes
