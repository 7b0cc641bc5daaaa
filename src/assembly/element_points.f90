!> The material points of an element seen through their model: which law, how many internal
!> variables and sub-increments, which kinematics; and one point taken through its law along the
!> step (point_update), shared by the small- and large-displacement element kernels.
module element_points
  use kinds, only: dp
  use scene, only: scene_t
  use assembly, only: system_t
  use element_traits, only: ET_BAR2, ET_BEAM2
  use material_law, only: law_update, law_nstate, law_step_t, LAW_HYPERELASTIC, LAW_VON_MISES, PK_PSTRESS
  use law_hyperelastic, only: nh_lame
  implicit none
  private
  public :: model_view_t, view_model, point_update

  !> What the points of one element need to know of their model.
  type :: model_view_t
    integer :: im = 0, mat = 0, nq = 0, nsub = 0
    logical :: linear = .true.
    logical :: large = .false.       !< KINEMATICS LARGE
    logical :: beam = .false.        !< BEAM2 (corotational when large)
    logical :: hyper = .false.       !< HYPERELASTIC (neo-Hookean; surface elements, large)
    real(dp) :: lame(2) = 0.0_dp     !< its Lamé constants (lambda, mu)
    logical :: von_mises = .false.   !< VON_MISES (with large: on the Green-Lagrange strain, PK2 stress)
    logical :: log_strain = .false.  !< STRAIN_MEASURE LOG: the points' pair is the Hencky strain and its stress
    logical :: pstress = .false.     !< plane stress (surface elements)
    logical :: bbar = .false.        !< FORMULATION BBAR: the element's mean dilatation at its points
    logical :: axi = .false.         !< AXISYMMETRIC: the hoop stretch F_θθ = 1 + u_r/R (surface elements)
    logical :: per_length = .false.  !< the strain is an elongation over the length (BAR2), not an elongation (SPRING)
  end type model_view_t

contains

  !> The model im as its points see it.
  subroutine view_model(scn, sys, im, mv)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    integer, intent(in) :: im
    type(model_view_t), intent(out) :: mv
    mv%im = im
    mv%linear = sys%elems%model_linear(im)
    mv%nsub = scn%models(im)%substeps
    mv%large = scn%models(im)%large
    mv%beam = scn%models(im)%etype == ET_BEAM2
    mv%per_length = scn%models(im)%etype == ET_BAR2
    mv%mat = scn%models(im)%material
    mv%nq = 0
    if (mv%mat > 0) mv%nq = law_nstate(scn%materials(mv%mat), sys%elems%pk(im), scn%models(im)%sec)
    mv%hyper = .false.
    if (mv%mat > 0) mv%hyper = scn%materials(mv%mat)%law == LAW_HYPERELASTIC
    if (mv%hyper) mv%lame = nh_lame(scn%materials(mv%mat)%young, scn%materials(mv%mat)%poisson)
    mv%von_mises = .false.
    if (mv%mat > 0) mv%von_mises = scn%materials(mv%mat)%law == LAW_VON_MISES
    mv%pstress = sys%elems%pk(im) == PK_PSTRESS
    mv%log_strain = scn%models(im)%log_strain
    mv%bbar = scn%models(im)%bbar
    mv%axi = scn%models(im)%sec%axisymmetric
  end subroutine view_model

  !> One point through its law (material_law's law_update, sub-incremented along the step from
  !> the committed state eps_n with the increment deps). SUBSTEPS AUTO (nsub = 0): the count may
  !> only grow during the iterations of a step; a count that changes back and forth makes the
  !> residual of eq (9) jump and cycle. So a point that asks for fewer sub-increments than before
  !> in this step is redone with them.
  subroutine point_update(scn, sys, mv, igp, eps_n, deps, r)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(model_view_t), intent(in) :: mv
    integer, intent(in) :: igp
    real(dp), intent(in) :: eps_n(:), deps(:)
    type(law_step_t), intent(out) :: r
    integer :: n, pass, nstr
    nstr = size(deps)
    n = mv%nsub
    do pass = 1, 2
      call law_update(scn%materials(mv%mat), scn%models(mv%im)%sec, sys%elems%pk(mv%im), &
        sys%elems%dmat(1:nstr, 1:nstr, mv%im), n, eps_n, deps, sys%pts%sig(1:nstr, igp), &
        sys%pts%q(1:mv%nq, igp), sys%pts%q_t(1:mv%nq, igp), r)
      if (mv%nsub /= 0 .or. pass == 2) exit      ! N given, or EXACT (NSUB_EXACT)
      if (r%nused >= sys%pts%nsub_pt(igp)) then
        sys%pts%nsub_pt(igp) = r%nused
        exit
      end if
      n = sys%pts%nsub_pt(igp)
    end do
  end subroutine point_update
end module element_points
