!> The element table of a scene: each element's equations, its integration points' weights and
!> B matrices (or, for linear elastic surface elements in small strain, only the shape-function
!> gradients B is made of), per model the elastic matrix, the point kind and the linearity of its
!> law. Built once by build_element_table (the per-model data by assembly's model_data).
module element_table
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, set_error, str, check_alloc
  use element_traits, only: etype_family, FAMILY_SURFACE, FAMILY_VOLUME, NODE_DOFS, MAX_NEN
  use scene, only: scene_t
  use elements, only: elem_dof_mask, elem_ndof, elem_nstrain, elem_ngauss, elem_gauss_b, MAX_EDOF, MAX_NSTRAIN
  implicit none
  private
  public :: element_table_t, build_element_table, add_btdb, add_anti

  !> The element table: every element's equations and integration points (B, weights), per model
  !> the elastic matrix, the point kind and the linearity of its law. Computed once.
  type :: element_table_t
    integer :: ngp = 0                       !< integration points
    integer, allocatable :: edof_ptr(:), edof(:)  !< equations of the element DOFs (0: fixed or absent)
    integer, allocatable :: gp_ptr(:)        !< (nelem+1) integration points of each element
    integer, allocatable :: b_ptr(:)         !< (ngp+1) offsets of each B in bmat (none for gradient points)
    integer, allocatable :: nstr(:)          !< (nelem) strain components of each element's points
    real(dp), allocatable :: bmat(:), wt(:)
    real(dp), allocatable :: bref(:)         !< KINEMATICS LARGE surface elements: the reference B (bmat then holds the current one)
    !> Linear elastic surface elements (small strain): each point's shape-function gradients
    !> (dN_a/dx, dN_a/dy by node), the quarter of B its zeros leave, which the element loop streams
    !> instead of B (docs/performance.md); gr_ptr(igp) its offset in grad, 0 for other points.
    !> Those points store no B: point_b rebuilds it where a B is needed (K0, tangent, reactions).
    integer, allocatable :: gr_ptr(:)
    real(dp), allocatable :: grad(:)
    real(dp), allocatable :: dmat(:, :, :)   !< (MAX_NSTRAIN, MAX_NSTRAIN, nmodel) elastic matrices
    integer, allocatable :: pk(:)            !< (nmodel) material-point kind
    logical, allocatable :: model_linear(:)  !< (nmodel) law linear: no sub-increments, sigma_c = 0
    logical :: linear = .true.               !< every law linear: one solve per step, no iteration
    logical :: any_large = .false.           !< some model has KINEMATICS LARGE (K0 holds only the reference axes)
    integer :: inverted = 0                  !< the first LARGE element of the last trial that inverted (0: none)
    !> Round-off floor of the last trial's residual from its LARGE axial members: the force one ulp
    !> of the nodal positions makes in each (k ulp(|x|), k the axial stiffness), summed in squares.
    real(dp) :: round_floor = 0.0_dp
  contains
    procedure :: point_b
  end type element_table_t

contains

  !> The table of scn's elements: equations of each element's DOFs (eqn: the DOF map), its
  !> integration points, their weights and B matrices or gradients (plane_gradients); elems' per-model
  !> data (model_linear) must be set. A gradient point's B is checked to be the one point_b rebuilds.
  subroutine build_element_table(scn, eqn, elems, stat, errmsg)
    type(scene_t), intent(in) :: scn
    integer, intent(in) :: eqn(:, :)
    type(element_table_t), intent(inout) :: elems
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: e, et, im, nen, ndof, nstr, ngp, ig, igp, nb, ngr, k, a, d, n, ast, nd
    logical :: mask(NODE_DOFS)
    real(dp) :: x(3, MAX_NEN), b(MAX_NSTRAIN, MAX_EDOF), w, bl(MAX_NSTRAIN * MAX_EDOF)
    allocate (elems%edof_ptr(scn%mesh%nelem + 1), elems%gp_ptr(scn%mesh%nelem + 1))
    elems%edof_ptr(1) = 1
    elems%gp_ptr(1) = 1
    nb = 0
    ngr = 0
    do e = 1, scn%mesh%nelem
      ndof = 0
      ngp = 0
      im = scn%elem_model(e)
      if (im > 0) then
        et = scn%mesh%etype(e)
        ndof = elem_ndof(et, scn%mesh%ndim)
        ngp = elem_ngauss(et, scn%models(im)%sec)
        if (plane_gradients(scn, elems, im, et)) then
          ngr = ngr + ngp * ndof
        else
          nb = nb + ngp * elem_nstrain(et) * ndof
        end if
      end if
      elems%edof_ptr(e + 1) = elems%edof_ptr(e) + ndof
      elems%gp_ptr(e + 1) = elems%gp_ptr(e) + ngp
    end do
    elems%ngp = elems%gp_ptr(scn%mesh%nelem + 1) - 1
    stat = STAT_OK
    allocate (elems%edof(elems%edof_ptr(scn%mesh%nelem + 1) - 1), elems%b_ptr(elems%ngp + 1), &
      elems%nstr(scn%mesh%nelem), elems%bmat(nb), elems%wt(elems%ngp), elems%gr_ptr(elems%ngp), &
      elems%grad(ngr), stat=ast)
    call check_alloc(ast, 'the element table of ' // str(scn%mesh%nelem) // ' elements', &
      8.0_dp * (nb + ngr) + 16.0_dp * elems%ngp + 4.0_dp * elems%edof_ptr(scn%mesh%nelem + 1), stat, errmsg)
    if (stat /= STAT_OK) return
    elems%b_ptr(1) = 1
    elems%gr_ptr = 0
    elems%nstr = 0
    ngr = 0
    do e = 1, scn%mesh%nelem
      im = scn%elem_model(e)
      if (im == 0) cycle
      et = scn%mesh%etype(e)
      elems%nstr(e) = elem_nstrain(et)
      nen = scn%mesh%nen(e)
      mask = elem_dof_mask(et, scn%mesh%ndim)
      k = elems%edof_ptr(e)
      do a = 1, nen
        n = scn%mesh%conn(a, e)
        do d = 1, NODE_DOFS
          if (.not. mask(d)) cycle
          elems%edof(k) = max(eqn(d, n), 0)
          k = k + 1
        end do
      end do
      nd = scn%mesh%ndim
      x(1:nd, 1:nen) = scn%mesh%x(:, scn%mesh%conn(1:nen, e))
      ndof = elem_ndof(et, scn%mesh%ndim)
      nstr = elem_nstrain(et)
      do ig = 1, elems%gp_ptr(e + 1) - elems%gp_ptr(e)
        igp = elems%gp_ptr(e) + ig - 1
        call elem_gauss_b(et, x(1:nd, 1:nen), scn%models(im)%sec, ig, b(1:nstr, 1:ndof), w)
        elems%wt(igp) = w
        elems%b_ptr(igp + 1) = elems%b_ptr(igp)
        if (plane_gradients(scn, elems, im, et)) then
          elems%gr_ptr(igp) = ngr + 1
          if (nstr == 6) then               ! B(1, 3a-2) = dN_a/dx, B(2, 3a-1) = dN_a/dy, B(3, 3a) = dN_a/dz
            do a = 1, nen
              elems%grad(ngr + 3 * a - 2) = b(1, 3 * a - 2)
              elems%grad(ngr + 3 * a - 1) = b(2, 3 * a - 1)
              elems%grad(ngr + 3 * a) = b(3, 3 * a)
            end do
          else
            do a = 1, nen                   ! B(1, 2a-1) = dN_a/dx, B(2, 2a) = dN_a/dy (element_iso)
              elems%grad(ngr + 2 * a - 1) = b(1, 2 * a - 1)
              elems%grad(ngr + 2 * a) = b(2, 2 * a)
            end do
          end if
          ngr = ngr + ndof
          call elems%point_b(igp, nstr, ndof, bl)
          if (any(reshape(bl(1:nstr * ndof), [nstr, ndof]) /= b(1:nstr, 1:ndof))) then
            call set_error(stat, errmsg, STAT_RUN, 'element ' // str(e) // ': its B is not made of its shape-function ' // &
              'gradients (internal error: report it)')
            return
          end if
        else
          elems%bmat(elems%b_ptr(igp):elems%b_ptr(igp) + nstr * ndof - 1) = reshape(b(1:nstr, 1:ndof), &
            [nstr * ndof])
          elems%b_ptr(igp + 1) = elems%b_ptr(igp) + nstr * ndof
        end if
      end do
    end do
    do k = 1, size(scn%models)        ! (once, whatever the number of such models)
      if (scn%models(k)%large .and. (etype_family(scn%models(k)%etype) == FAMILY_SURFACE .or. &
          etype_family(scn%models(k)%etype) == FAMILY_VOLUME)) then
        elems%bref = elems%bmat
        exit
      end if
    end do
    ! FORMULATION BBAR: the mean dilatation (after bref, which keeps the points' own gradients;
    ! a LARGE model's bmat is then its B at the reference, for K0).
    do e = 1, scn%mesh%nelem
      im = scn%elem_model(e)
      if (im == 0) cycle
      if (.not. scn%models(im)%bbar) cycle
      call mean_dilatation_b(elems, elems%gp_ptr(e), elems%gp_ptr(e + 1) - elems%gp_ptr(e), elem_ndof(scn%mesh%etype(e)), &
        merge(3, 2, scn%models(im)%sec%axisymmetric .or. elem_nstrain(scn%mesh%etype(e)) == 6), &
        elem_nstrain(scn%mesh%etype(e)))
    end do
  end subroutine build_element_table

  !> B-bar (FORMULATION BBAR): at each of the element's ng points (from g0; B nstr x ndof in bmat, 4
  !> rows in 2D, 6 for a solid) the volumetric row b_v = B(1, :) + … + B(ntr, :) (ntr = 2 in plane
  !> strain, 3 with the hoop row of an axisymmetric model or in 3D) replaced by its volume mean over
  !> the element, <b_v> = Σ w b_v / Σ w:
  !> B̄ = B + (1/ntr) [1 … 1, 0]' (<b_v> - b_v). The strain B̄ u keeps each point's deviator and takes
  !> the element's mean dilatation (Hughes' B-bar; docs/locking.md).
  pure subroutine mean_dilatation_b(elems, g0, ng, ndof, ntr, nstr)
    type(element_table_t), intent(inout) :: elems
    integer, intent(in) :: g0, ng, ndof, ntr, nstr
    real(dp) :: m(MAX_EDOF), wsum, dv, bv
    integer :: igp, a, p, r
    m(1:ndof) = 0.0_dp
    wsum = 0.0_dp
    do igp = g0, g0 + ng - 1
      p = elems%b_ptr(igp) - 1
      do a = 1, ndof
        bv = 0.0_dp
        do r = 1, ntr
          bv = bv + elems%bmat(p + nstr * a - nstr + r)
        end do
        m(a) = m(a) + elems%wt(igp) * bv
      end do
      wsum = wsum + elems%wt(igp)
    end do
    m(1:ndof) = m(1:ndof) / wsum
    do igp = g0, g0 + ng - 1
      p = elems%b_ptr(igp) - 1
      do a = 1, ndof
        bv = 0.0_dp
        do r = 1, ntr
          bv = bv + elems%bmat(p + nstr * a - nstr + r)
        end do
        dv = (m(a) - bv) / ntr
        do r = 1, ntr
          elems%bmat(p + nstr * a - nstr + r) = elems%bmat(p + nstr * a - nstr + r) + dv
        end do
      end do
    end do
  end subroutine mean_dilatation_b

  !> Point igp's B (nstr x ndof, column-major) into b: from bmat, or rebuilt from the gradients of
  !> a point that keeps only those (B(1,2a-1) = B(4,2a) = dN_a/dx, B(2,2a) = B(4,2a-1) = dN_a/dy; a
  !> solid's, nstr = 6, element_solid's solid_b from dN_a/dx, dN_a/dy, dN_a/dz).
  pure subroutine point_b(self, igp, nstr, ndof, b)
    class(element_table_t), intent(in) :: self
    integer, intent(in) :: igp, nstr, ndof
    real(dp), intent(out) :: b(nstr, ndof)
    integer :: a, k, g
    if (self%gr_ptr(igp) == 0) then
      do k = 1, ndof
        b(:, k) = self%bmat(self%b_ptr(igp) + (k - 1) * nstr:self%b_ptr(igp) + k * nstr - 1)
      end do
      return
    end if
    b = 0.0_dp
    g = self%gr_ptr(igp) - 1
    if (nstr == 6) then
      do a = 1, ndof / 3
        k = 3 * (a - 1)
        b(1, k + 1) = self%grad(g + k + 1)
        b(2, k + 2) = self%grad(g + k + 2)
        b(3, k + 3) = self%grad(g + k + 3)
        b(4, k + 1) = self%grad(g + k + 2)
        b(4, k + 2) = self%grad(g + k + 1)
        b(5, k + 2) = self%grad(g + k + 3)
        b(5, k + 3) = self%grad(g + k + 2)
        b(6, k + 1) = self%grad(g + k + 3)
        b(6, k + 3) = self%grad(g + k + 1)
      end do
      return
    end if
    do a = 1, ndof / 2
      b(1, 2 * a - 1) = self%grad(g + 2 * a - 1)
      b(4, 2 * a) = self%grad(g + 2 * a - 1)
      b(2, 2 * a) = self%grad(g + 2 * a)
      b(4, 2 * a - 1) = self%grad(g + 2 * a)
    end do
  end subroutine point_b

  !> Whether the points of model im's elements of type et keep their gradients (gr_ptr): linear
  !> elastic surface elements in small strain (not B-bar, not axisymmetric: the hoop row is not made
  !> of gradients), the ones the element loop's plane kernel serves, and linear elastic solids (its
  !> solid kernel; B is 6 x 3 nen with three entries a column).
  pure logical function plane_gradients(scn, elems, im, et)
    type(scene_t), intent(in) :: scn
    type(element_table_t), intent(in) :: elems
    integer, intent(in) :: im, et
    plane_gradients = (etype_family(et) == FAMILY_SURFACE .or. etype_family(et) == FAMILY_VOLUME) .and. &
      elems%model_linear(im) .and. .not. scn%models(im)%large .and. .not. scn%models(im)%bbar .and. &
      .not. scn%models(im)%sec%axisymmetric
  end function plane_gradients

  !> ke(1:ndof, 1:ndof) += w B' D B, B nstr x ndof, D the leading nstr x nstr block of d.
  pure subroutine add_btdb(nstr, ndof, b, d, w, ke)
    integer, intent(in) :: nstr, ndof
    real(dp), intent(in) :: b(nstr, ndof), d(MAX_NSTRAIN, MAX_NSTRAIN), w
    real(dp), intent(inout) :: ke(MAX_EDOF, MAX_EDOF)
    real(dp) :: db(MAX_NSTRAIN, MAX_EDOF)
    integer :: k, m
    do k = 1, ndof
      db(1:nstr, k) = matmul(d(1:nstr, 1:nstr), b(:, k))
    end do
    do k = 1, ndof
      do m = 1, ndof
        ke(m, k) = ke(m, k) + w * dot_product(b(:, m), db(1:nstr, k))
      end do
    end do
  end subroutine add_btdb

  !> ka += w × the antisymmetric part of bl' D br (bl, br: nstr x ndof; D nstr x nstr, not symmetric in
  !> general): the part of eq (9)'s Jacobian that the symmetric iteration matrix leaves out, kept
  !> apart for iterate_eq9's anti_sweep (a law's path-mean tangent, the step force's B at F_mid).
  pure subroutine add_anti(nstr, ndof, bl, d, br, w, ka)
    integer, intent(in) :: nstr, ndof
    real(dp), intent(in) :: bl(nstr, ndof), d(:, :), br(nstr, ndof), w
    real(dp), intent(inout) :: ka(:, :)
    real(dp) :: db(MAX_NSTRAIN, MAX_EDOF), t(MAX_EDOF, MAX_EDOF)
    integer :: i, k, l
    do l = 1, ndof
      do i = 1, nstr
        db(i, l) = dot_product(d(i, 1:nstr), br(1:nstr, l))
      end do
    end do
    do l = 1, ndof
      do k = 1, ndof
        t(k, l) = dot_product(bl(1:nstr, k), db(1:nstr, l))
      end do
    end do
    do l = 1, ndof
      do k = 1, ndof
        ka(k, l) = ka(k, l) + 0.5_dp * w * (t(k, l) - t(l, k))
      end do
    end do
  end subroutine add_anti
end module element_table
