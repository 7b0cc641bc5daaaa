!> Stresses where users read them (fields.h5): at the integration points, and as smoothed nodal
!> values by the L2 projection of the integration-point values onto the surface elements' shape
!> functions,
!>     M s = Σ_e Σ_g w_g N(ξ_g) σ_g,   M = Σ_e ∫ N N' dV
!> (w_g the point's weight, thickness or 2πr included; M the consistent scalar mass of density 1 of
!> the surface elements' nodes, with the element's mass rule, exact for N N'). It reproduces a stress field in the elements'
!> span exactly (a patch in uniform stress: every node), and converges at the element's order
!> (docs/input.md, "Output"). M is factorized once (CHOLMOD) when the outputs open; each written
!> step solves it for sigma_xx, sigma_yy, sigma_zz (hoop: sigma_tt), sigma_xy, von Mises and the
!> equivalent plastic strain. The projection averages across elements of different models where
!> they share nodes (a material interface shows a smoothed jump); nodes of no surface element get 0.
module stress_recovery
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, set_error, str
  use scene, only: scene_t
  use assembly, only: system_t
  use elements, only: elem_gauss_shape, elem_mass
  use point_fields, only: von_mises
  use element_traits, only: etype_nen, etype_family, FAMILY_SURFACE
  use material_law, only: LAW_VON_MISES
  use sparse_matrix, only: sym_csc_t
  use cholmod_binding, only: cholmod_factor_t
  implicit none
  private
  public :: recovery_t, NREC

  integer, parameter :: NREC = 6   !< recovered fields: 4 stresses, von Mises, equivalent plastic strain

  type :: recovery_t
    private
    integer, public :: ngp = 0                !< integration points of the surface elements
    integer :: nloc = 0                       !< nodes of the surface elements
    integer, allocatable :: loc(:)            !< mesh node -> projection unknown (0: none)
    integer, allocatable :: node(:)           !< projection unknown -> mesh node
    integer, allocatable :: gp(:)             !< (ngp) the system's point index
    integer, allocatable :: gp_elem(:)        !< (ngp) its element
    real(dp), allocatable :: shp(:, :)        !< (8, ngp) shape functions at the point
    real(dp), allocatable :: w(:)             !< (ngp) its weight (reference: thickness or 2πr and det J in)
    real(dp), allocatable, public :: x(:, :)  !< (3, ngp) reference positions of the points
    logical, allocatable :: plastic(:)        !< (ngp) the point's law has an equivalent plastic strain (q(5))
    type(sym_csc_t) :: pat
    real(dp), allocatable :: mval(:)
    type(cholmod_factor_t) :: fac
    real(dp), allocatable :: rhs(:, :), sol(:)
  contains
    procedure :: build => rec_build
    procedure :: points => rec_points
    procedure :: nodal => rec_nodal
    procedure :: destroy => rec_destroy
  end type recovery_t

contains

  !> The points and the projection matrix of the scene's surface elements, M factorized.
  subroutine rec_build(self, scn, sys, stat, errmsg)
    class(recovery_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, allocatable :: eptr(:), edofs(:)
    integer :: e, ig, igp, k, nen, a, b, ne, p
    real(dp) :: n(8), me(8, 8), m2(16, 16)
    logical :: ok
    stat = STAT_OK
    allocate (self%loc(scn%mesh%nnode))
    self%loc = 0
    self%ngp = 0
    ne = 0
    do e = 1, scn%mesh%nelem
      if (.not. surface(scn, e)) cycle
      ne = ne + 1
      self%ngp = self%ngp + sys%elems%gp_ptr(e + 1) - sys%elems%gp_ptr(e)
      nen = etype_nen(scn%mesh%etype(e))
      do a = 1, nen
        if (self%loc(scn%mesh%conn(a, e)) == 0) then
          self%nloc = self%nloc + 1
          self%loc(scn%mesh%conn(a, e)) = self%nloc
        end if
      end do
    end do
    allocate (self%node(self%nloc), self%gp(self%ngp), self%gp_elem(self%ngp), self%shp(8, self%ngp), &
      self%w(self%ngp), self%x(3, self%ngp), self%plastic(self%ngp), eptr(ne + 1), edofs(8 * ne), self%rhs(self%nloc, NREC), &
      self%sol(self%nloc))
    do a = 1, scn%mesh%nnode
      if (self%loc(a) > 0) self%node(self%loc(a)) = a
    end do
    eptr(1) = 1
    ne = 0
    k = 0
    do e = 1, scn%mesh%nelem
      if (.not. surface(scn, e)) cycle
      ne = ne + 1
      nen = etype_nen(scn%mesh%etype(e))
      edofs(eptr(ne):eptr(ne) + nen - 1) = self%loc(scn%mesh%conn(1:nen, e))
      eptr(ne + 1) = eptr(ne) + nen
      do ig = 1, sys%elems%gp_ptr(e + 1) - sys%elems%gp_ptr(e)
        k = k + 1
        igp = sys%elems%gp_ptr(e) + ig - 1
        call elem_gauss_shape(scn%mesh%etype(e), ig, n, ok)
        self%gp(k) = igp
        self%gp_elem(k) = e
        self%shp(:, k) = n
        self%w(k) = sys%elems%wt(igp)
        self%x(:, k) = 0.0_dp
        self%x(1:2, k) = matmul(scn%mesh%x(1:2, scn%mesh%conn(1:nen, e)), n(1:nen))
        self%plastic(k) = .false.
        if (scn%models(scn%elem_model(e))%material > 0) &
          self%plastic(k) = scn%materials(scn%models(scn%elem_model(e))%material)%law == LAW_VON_MISES
      end do
    end do
    if (self%nloc == 0) return
    call self%pat%build(self%nloc, eptr(1:ne + 1), edofs(1:eptr(ne + 1) - 1), stat, errmsg)
    if (stat /= STAT_OK) return
    allocate (self%mval(self%pat%nnz))
    self%mval = 0.0_dp
    k = 0
    do e = 1, scn%mesh%nelem
      if (.not. surface(scn, e)) cycle
      ! The element's consistent mass of density 1 (its x-x block): a rule exact for N N', where
      ! the stiffness points may be too few (TRI3's one point, TRI6's three).
      nen = etype_nen(scn%mesh%etype(e))
      call elem_mass(scn%mesh%etype(e), scn%mesh%x(1:2, scn%mesh%conn(1:nen, e)), scn%models(scn%elem_model(e))%sec, &
        1.0_dp, .false., m2(1:2 * nen, 1:2 * nen))
      do b = 1, nen
        do a = 1, nen
          me(a, b) = m2(2 * a - 1, 2 * b - 1)
        end do
      end do
      call self%pat%add_element(self%mval, self%loc(scn%mesh%conn(1:nen, e)), me(1:nen, 1:nen), p)
    end do
    call self%fac%factorize(self%pat, self%mval, stat, errmsg)
    if (stat /= STAT_OK) call set_error(stat, errmsg, STAT_RUN, 'stress recovery: the projection matrix ' // &
      'of the surface elements does not factorize (' // errmsg // ')')
  end subroutine rec_build

  logical function surface(scn, e)
    type(scene_t), intent(in) :: scn
    integer, intent(in) :: e
    surface = .false.
    if (scn%elem_model(e) == 0) return
    surface = etype_family(scn%mesh%etype(e)) == FAMILY_SURFACE
  end function surface

  !> The points' values: vals(1:4, k) the stresses, vals(5, k) von Mises, vals(6, k) the equivalent
  !> plastic strain (VON_MISES; 0 otherwise); disp(3, k) the displacement there (from the nodal
  !> displacements nodal_u(3, nnode)), for ParaView's Warp By Vector of the point set.
  subroutine rec_points(self, scn, sys, nodal_u, vals, disp)
    class(recovery_t), intent(in) :: self
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: nodal_u(:, :)
    real(dp), intent(out) :: vals(:, :), disp(:, :)
    integer :: k, igp, e, a, nen
    do k = 1, self%ngp
      igp = self%gp(k)
      vals(1:4, k) = sys%pts%sig(1:4, igp)
      vals(5, k) = von_mises(sys%pts%sig(1:4, igp))
      vals(6, k) = 0.0_dp
      if (self%plastic(k)) vals(6, k) = sys%pts%q(5, igp)
      e = self%gp_elem(k)
      nen = etype_nen(scn%mesh%etype(e))
      disp(:, k) = 0.0_dp
      do a = 1, nen
        disp(:, k) = disp(:, k) + self%shp(a, k) * nodal_u(:, scn%mesh%conn(a, e))
      end do
    end do
  end subroutine rec_points

  !> The smoothed nodal values nodal(NREC, nnode) of the point values vals (rec_points'), by the
  !> L2 projection; 0 at the nodes of no surface element.
  subroutine rec_nodal(self, scn, vals, nodal, stat, errmsg)
    class(recovery_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    real(dp), intent(in) :: vals(:, :)
    real(dp), intent(out) :: nodal(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, a, c, e, nen, i
    real(dp) :: w
    stat = STAT_OK
    nodal = 0.0_dp
    if (self%nloc == 0) return
    self%rhs = 0.0_dp
    do k = 1, self%ngp
      e = self%gp_elem(k)
      nen = etype_nen(scn%mesh%etype(e))
      do a = 1, nen
        i = self%loc(scn%mesh%conn(a, e))
        w = self%w(k) * self%shp(a, k)
        do c = 1, NREC
          self%rhs(i, c) = self%rhs(i, c) + w * vals(c, k)
        end do
      end do
    end do
    do c = 1, NREC
      call self%fac%solve(self%rhs(:, c), self%sol, stat, errmsg)
      if (stat /= STAT_OK) return
      do i = 1, self%nloc
        nodal(c, self%node(i)) = self%sol(i)
      end do
    end do
  end subroutine rec_nodal

  subroutine rec_destroy(self)
    class(recovery_t), intent(inout) :: self
    call self%fac%destroy()
  end subroutine rec_destroy
end module stress_recovery
