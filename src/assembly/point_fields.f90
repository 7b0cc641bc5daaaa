!> Fields of the integration points and equations as the outputs show them (fields.h5): element
!> means of the stresses, the von Mises stress and the plastic strain per element, nodal values of
!> a free-DOF vector. Read-only views of the system's state.
module point_fields
  use law_von_mises, only: vm_alpha_index
  use kinds, only: dp
  use scene, only: scene_t
  use assembly, only: system_t
  use element_traits, only: ET_BAR2, etype_family, FAMILY_SURFACE, FAMILY_VOLUME
  use material_law, only: LAW_VON_MISES, LAW_ELASTOPLASTIC, PK_1D
  implicit none
  private
  public :: element_stress, element_scalars, nodal_values, von_mises

contains

  !> Element means of the integration-point stresses, (MAX_NSTRAIN, nelem).
  subroutine element_stress(sys, s)
    type(system_t), intent(in) :: sys
    real(dp), intent(out) :: s(:, :)
    integer :: e, n, nc
    nc = size(s, 1)                           ! (4 in 2D, 6 in 3D: the leading rows of the points')
    do e = 1, size(s, 2)
      n = sys%elems%gp_ptr(e + 1) - sys%elems%gp_ptr(e)
      if (n == 0) then
        s(:, e) = 0.0_dp
      else
        s(:, e) = sum(sys%pts%sig(1:nc, sys%elems%gp_ptr(e):sys%elems%gp_ptr(e + 1) - 1), dim=2) / n
      end if
    end do
  end subroutine element_stress

  !> Per element (fields.h5): es(e, 1) the von Mises stress of the element-mean stress s (surface
  !> elements, with sigma_zz; |sigma| for BAR2; 0 otherwise), es(e, 2) the element mean of the
  !> equivalent plastic strain (VON_MISES: alpha) or of the plastic strain (ELASTOPLASTIC on
  !> springs and bars: eps_p); 0 for the other laws and for fibre beams.
  subroutine element_scalars(scn, sys, s, es)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: s(:, :)
    real(dp), intent(out) :: es(:, :)
    integer :: e, im, g0, g1, k, law
    es = 0.0_dp
    do e = 1, size(es, 1)
      if (etype_family(scn%mesh%etype(e)) == FAMILY_SURFACE) then
        es(e, 1) = von_mises(s(1:4, e))
      else if (etype_family(scn%mesh%etype(e)) == FAMILY_VOLUME) then
        es(e, 1) = von_mises_3d(s(1:6, e))
      else if (scn%mesh%etype(e) == ET_BAR2) then
        es(e, 1) = abs(s(1, e))
      end if
      im = scn%elem_model(e)
      g0 = sys%elems%gp_ptr(e)
      g1 = sys%elems%gp_ptr(e + 1) - 1
      if (im == 0 .or. g1 < g0) cycle
      if (scn%models(im)%material == 0) cycle
      law = scn%materials(scn%models(im)%material)%law
      k = 0
      if (law == LAW_VON_MISES) k = vm_alpha_index(sys%elems%nstr(e))   ! (alpha: q(5) in 2D, q(7) in 3D)
      if (law == LAW_ELASTOPLASTIC .and. sys%elems%pk(im) == PK_1D) k = 1
      if (k > 0) es(e, 2) = sum(sys%pts%q(k, g0:g1)) / (g1 - g0 + 1)
    end do
  end subroutine element_scalars

  !> The von Mises stress of (sxx, syy, szz, sxy).
  pure real(dp) function von_mises(s)
    real(dp), intent(in) :: s(4)
    von_mises = sqrt(max(0.0_dp, s(1)**2 + s(2)**2 + s(3)**2 - s(1) * s(2) - s(2) * s(3) - s(3) * s(1) + 3.0_dp * s(4)**2))
  end function von_mises

  !> The von Mises stress of (sxx, syy, szz, sxy, syz, sxz).
  pure real(dp) function von_mises_3d(s)
    real(dp), intent(in) :: s(6)
    von_mises_3d = sqrt(max(0.0_dp, s(1)**2 + s(2)**2 + s(3)**2 - s(1) * s(2) - s(2) * s(3) - s(3) * s(1) + &
      3.0_dp * (s(4)**2 + s(5)**2 + s(6)**2)))
  end function von_mises_3d

  !> Free-DOF vector to nodal values out(k, n), k = 1..size(out, 1), of the DOF slots slots(k) (2D:
  !> UX, UY, RZ; 3D: UX, UY, UZ); fixed and absent DOFs are zero.
  pure subroutine nodal_values(sys, u, slots, out)
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: u(:)
    integer, intent(in) :: slots(:)
    real(dp), intent(out) :: out(:, :)
    integer :: n, k, j
    do n = 1, size(out, 2)
      do k = 1, size(out, 1)
        out(k, n) = 0.0_dp
        j = sys%dofs%eqn(slots(k), n)
        if (j > 0) out(k, n) = u(j)
      end do
    end do
  end subroutine nodal_values
end module point_fields
