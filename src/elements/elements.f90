!> Element dispatcher: what the assembly sees of an element, whatever its type.
!> Every element gives, at each integration point ig, a strain-displacement matrix B
!> (nstrain x ndof, global element DOFs) and a weight wt such that
!>   strain = B u_e,   f_int_e = sum_ig B^T sigma wt,   K_e = sum_ig B^T D B wt,
!> so internal forces always come from stresses (never K u) and nonlinear laws use the same
!> path as elastic ones. Element DOFs are node-major, per node in the order of the element's
!> mask (UX, UY[, RZ]). Strain measures are documented in each element module:
!> MASS (none), SPRING (elongation, wt 1), BAR2 (axial strain, wt A L), BEAM2 (axial strain and
!> curvature, wt w L/2), QUAD4/QUAD8/TRI3/TRI6 (exx, eyy, ezz = 0 row, gxy; wt w det J thickness;
!> axisymmetric: x = r, y the axis, ezz the hoop strain u_r/r, wt w det J 2 pi r: element_iso's iso_ring),
!> HEX8/TET4 (exx, eyy, ezz, gxy, gyz, gxz; wt w det J: element_solid).
!> Output arrays may be larger than needed: the leading block is filled, the rest zeroed.
module elements
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use element_traits, only: ET_MASS, ET_SPRING, ET_BAR2, ET_BEAM2, ET_QUAD4, ET_QUAD8, ET_TRI3, ET_TRI6, MAX_NEN, &
    ET_HEX8, ET_TET4, ET_HEX20, ET_TET10, ET_WEDGE6, etype_nen, etype_name, etype_dimension, NODE_DOFS, DOF_UX, &
    DOF_UY, DOF_UZ, DOF_RZ
  use section, only: section_t
  use element_mass, only: mass_mass
  use element_spring, only: spring_b, spring_check
  use element_bar2, only: bar2_b, bar2_mass, bar2_check
  use element_beam2, only: beam2_ngauss, beam2_b, beam2_mass, BEAM2_MAX_GAUSS
  use element_quad, only: quad_ngauss, quad_b, quad_mass, quad_check, quad_elastic_d, quad_point_shape
  use element_tri, only: tri_ngauss, tri_b, tri_mass, tri_check, tri_point_shape
  use element_solid, only: solid_ngauss, solid_b, solid_mass, solid_check, solid_point_shape
  use law_von_mises, only: vm_d3
  implicit none
  private
  public :: MAX_EDOF, MAX_NSTRAIN, MAX_GAUSS
  public :: elem_dof_mask, elem_nen, elem_ndof, elem_nstrain, elem_ngauss
  public :: elem_gauss_b, elem_gauss_shape, elem_mass, elem_elastic_d, elem_check_geometry, elem_check_section, elem_stiffness

  integer, parameter :: MAX_EDOF = 60     !< HEX20: 20 nodes x 3
  integer, parameter :: MAX_NSTRAIN = 6   !< solids
  integer, parameter :: MAX_GAUSS = 27    !< HEX20 3 x 3 x 3

contains

  !> Which of the node DOF slots (mesh's UX, UY, RZ, UZ) each node of an element of type et carries:
  !> a volume's UX UY UZ, a planar element's UX UY (and RZ for BEAM2); a MASS carries the
  !> translations of its space, UZ too in a scene of dimension ndim = 3 (absent: its own dimension).
  pure function elem_dof_mask(et, ndim) result(mask)
    integer, intent(in) :: et
    integer, intent(in), optional :: ndim
    logical :: mask(NODE_DOFS)
    mask = .false.
    mask(DOF_UX) = .true.
    mask(DOF_UY) = .true.
    mask(DOF_RZ) = et == ET_BEAM2
    mask(DOF_UZ) = etype_dimension(et) == 3
    if (present(ndim) .and. et == ET_MASS) mask(DOF_UZ) = ndim == 3
  end function elem_dof_mask

  !> Number of nodes.
  pure integer function elem_nen(et)
    integer, intent(in) :: et
    elem_nen = etype_nen(et)
  end function elem_nen

  !> Number of element DOFs: nen * count(mask) (ndim: as elem_dof_mask).
  pure integer function elem_ndof(et, ndim)
    integer, intent(in) :: et
    integer, intent(in), optional :: ndim
    elem_ndof = etype_nen(et) * count(elem_dof_mask(et, ndim))
  end function elem_ndof

  !> Number of (generalized) strain components.
  pure integer function elem_nstrain(et)
    integer, intent(in) :: et
    select case (et)
    case (ET_SPRING, ET_BAR2)
      elem_nstrain = 1
    case (ET_BEAM2)
      elem_nstrain = 2
    case (ET_QUAD4, ET_QUAD8, ET_TRI3, ET_TRI6)
      elem_nstrain = 4
    case (ET_HEX8, ET_TET4, ET_HEX20, ET_TET10, ET_WEDGE6)
      elem_nstrain = 6
    case default
      elem_nstrain = 0
    end select
  end function elem_nstrain

  !> Number of integration points.
  pure integer function elem_ngauss(et, sec)
    integer, intent(in) :: et
    type(section_t), intent(in) :: sec
    select case (et)
    case (ET_SPRING, ET_BAR2)
      elem_ngauss = 1
    case (ET_BEAM2)
      elem_ngauss = beam2_ngauss(sec)
    case (ET_QUAD4)
      elem_ngauss = quad_ngauss(4)
    case (ET_QUAD8)
      elem_ngauss = quad_ngauss(8)
    case (ET_TRI3)
      elem_ngauss = tri_ngauss(3)
    case (ET_TRI6)
      elem_ngauss = tri_ngauss(6)
    case (ET_HEX8, ET_TET4, ET_HEX20, ET_TET10, ET_WEDGE6)
      elem_ngauss = solid_ngauss(etype_nen(et))
    case default
      elem_ngauss = 0
    end select
  end function elem_ngauss

  !> Node coordinates into a fixed-size local array (x(1:2) in 2D, x(1:3) for a solid).
  pure subroutine local_coords(et, x, xl)
    integer, intent(in) :: et
    real(dp), intent(in) :: x(:, :)
    real(dp), intent(out) :: xl(2, MAX_NEN)
    integer :: nen
    nen = etype_nen(et)
    xl = 0.0_dp
    xl(:, 1:nen) = x(1:2, 1:nen)
  end subroutine local_coords

  !> A solid's node coordinates into a fixed-size local array.
  pure subroutine local_coords_3(et, x, xl)
    integer, intent(in) :: et
    real(dp), intent(in) :: x(:, :)
    real(dp), intent(out) :: xl(3, MAX_NEN)
    integer :: nen
    nen = etype_nen(et)
    xl = 0.0_dp
    xl(:, 1:nen) = x(1:3, 1:nen)
  end subroutine local_coords_3

  !> The shape functions n(1:nen) of a surface element (QUAD4, QUAD8, TRI3, TRI6) at its
  !> integration point ig (1..elem_ngauss); ok false for the other types (n = 0).
  pure subroutine elem_gauss_shape(et, ig, n, ok)
    integer, intent(in) :: et, ig
    real(dp), intent(out) :: n(:)
    logical, intent(out) :: ok
    real(dp) :: nq(8), nt(6), ns(20)
    n = 0.0_dp
    ok = .true.
    select case (et)
    case (ET_QUAD4, ET_QUAD8)
      call quad_point_shape(etype_nen(et), ig, nq)
      n(1:etype_nen(et)) = nq(1:etype_nen(et))
    case (ET_TRI3, ET_TRI6)
      call tri_point_shape(etype_nen(et), ig, nt)
      n(1:etype_nen(et)) = nt(1:etype_nen(et))
    case (ET_HEX8, ET_TET4, ET_HEX20, ET_TET10, ET_WEDGE6)
      call solid_point_shape(etype_nen(et), ig, ns)
      n(1:etype_nen(et)) = ns(1:etype_nen(et))
    case default
      ok = .false.
    end select
  end subroutine elem_gauss_shape

  !> B (at least nstrain x ndof) and weight at integration point ig (1..elem_ngauss);
  !> x(1:ndim, 1:nen) are the node coordinates.
  pure subroutine elem_gauss_b(et, x, sec, ig, b, wt)
    integer, intent(in) :: et, ig
    real(dp), intent(in) :: x(:, :)
    type(section_t), intent(in) :: sec
    real(dp), intent(out) :: b(:, :), wt
    real(dp) :: xl(2, MAX_NEN), bl(MAX_NSTRAIN, MAX_EDOF), b1(1, 4), b2(2, 6), x3(3, MAX_NEN), b4(4, 16)
    integer :: ns, nd
    bl = 0.0_dp
    wt = 0.0_dp
    if (etype_dimension(et) == 3) then
      call local_coords_3(et, x, x3)
      call solid_b(etype_nen(et), x3, ig, bl, wt)
      ns = elem_nstrain(et)
      nd = elem_ndof(et)
      b = 0.0_dp
      b(1:ns, 1:nd) = bl(1:ns, 1:nd)
      return
    end if
    call local_coords(et, x, xl)
    ! Exact-shape locals for the small elements: sections of bl would need temporaries.
    select case (et)
    case (ET_SPRING)
      call spring_b(xl(:, 1:2), sec, b1, wt)
      bl(1:1, 1:4) = b1
    case (ET_BAR2)
      call bar2_b(xl(:, 1:2), sec%area, b1, wt)
      bl(1:1, 1:4) = b1
    case (ET_BEAM2)
      call beam2_b(xl(:, 1:2), sec, ig, b2, wt)
      bl(1:2, 1:6) = b2
    case (ET_QUAD4)
      call quad_b(4, xl, sec%thickness, sec%axisymmetric, ig, b4, wt)
      bl(1:4, 1:16) = b4
    case (ET_QUAD8)
      call quad_b(8, xl, sec%thickness, sec%axisymmetric, ig, b4, wt)
      bl(1:4, 1:16) = b4
    case (ET_TRI3)
      call tri_b(3, xl(:, 1:6), sec%thickness, sec%axisymmetric, ig, bl(1:4, 1:12), wt)
    case (ET_TRI6)
      call tri_b(6, xl(:, 1:6), sec%thickness, sec%axisymmetric, ig, bl(1:4, 1:12), wt)
    end select
    ns = elem_nstrain(et)
    nd = elem_ndof(et)
    b = 0.0_dp
    b(1:ns, 1:nd) = bl(1:ns, 1:nd)
  end subroutine elem_gauss_b

  !> Element mass matrix (at least ndof x ndof, full symmetric). rho is the material density
  !> (unused by MASS, which takes sec%mass, and by SPRING, which is massless). large: the model
  !> has KINEMATICS LARGE (a BEAM2 then takes the mass that is the same in every frame).
  pure subroutine elem_mass(et, x, sec, rho, lumped, me, large)
    integer, intent(in) :: et
    real(dp), intent(in) :: x(:, :), rho
    type(section_t), intent(in) :: sec
    logical, intent(in) :: lumped
    real(dp), intent(out) :: me(:, :)
    logical, intent(in), optional :: large
    real(dp) :: xl(2, MAX_NEN), ml(MAX_EDOF, MAX_EDOF), m3(3, 3), m4(4, 4), m6(6, 6), x3(3, MAX_NEN), m16(16, 16)
    integer :: nd
    nd = elem_ndof(et, size(x, 1))       ! (a MASS in a 3D scene: x, y, z)
    ml(1:nd, 1:nd) = 0.0_dp              ! (the element's block: a 60 x 60 zero per element cost more than its mass)
    if (etype_dimension(et) == 3) then
      call local_coords_3(et, x, x3)
      call solid_mass(etype_nen(et), x3, rho, lumped, ml(1:nd, 1:nd))
    else
      call local_coords(et, x, xl)
    end if
    select case (et)
    case (ET_MASS)
      call mass_mass(sec, nd, m3)
      ml(1:nd, 1:nd) = m3(1:nd, 1:nd)
    case (ET_BAR2)
      call bar2_mass(xl(:, 1:2), sec%area, rho, lumped, m4)
      ml(1:4, 1:4) = m4
    case (ET_BEAM2)
      call beam2_mass(xl(:, 1:2), sec%area, rho, lumped, m6, large)
      ml(1:6, 1:6) = m6
    case (ET_QUAD4)
      call quad_mass(4, xl, sec%thickness, sec%axisymmetric, rho, lumped, m16)
      ml(1:16, 1:16) = m16
    case (ET_QUAD8)
      call quad_mass(8, xl, sec%thickness, sec%axisymmetric, rho, lumped, m16)
      ml(1:16, 1:16) = m16
    case (ET_TRI3)
      call tri_mass(3, xl(:, 1:6), sec%thickness, sec%axisymmetric, rho, lumped, ml(1:12, 1:12))
    case (ET_TRI6)
      call tri_mass(6, xl(:, 1:6), sec%thickness, sec%axisymmetric, rho, lumped, ml(1:12, 1:12))
    end select
    me = 0.0_dp
    me(1:nd, 1:nd) = ml(1:nd, 1:nd)
  end subroutine elem_mass

  !> Elastic D (at least nstrain x nstrain). SPRING: k = young (for springs YOUNG is the
  !> stiffness in N/m); BAR2: young; BEAM2: diag(E A, E I); quads: 4 x 4 plane strain (3D
  !> isotropic law with ezz = 0, szz = nu (sxx + syy)) or plane stress (sec%plane_stress:
  !> szz = 0, row and column zz zero).
  pure subroutine elem_elastic_d(et, young, poisson, sec, d)
    integer, intent(in) :: et
    real(dp), intent(in) :: young, poisson
    type(section_t), intent(in) :: sec
    real(dp), intent(out) :: d(:, :)
    real(dp) :: dq(4, 4), ds(6, 6)
    d = 0.0_dp
    select case (et)
    case (ET_SPRING, ET_BAR2)
      d(1, 1) = young
    case (ET_BEAM2)
      d(1, 1) = young * sec%area
      d(2, 2) = young * sec%inertia
    case (ET_QUAD4, ET_QUAD8, ET_TRI3, ET_TRI6)
      call quad_elastic_d(young, poisson, sec%plane_stress, dq)
      d(1:4, 1:4) = dq
    case (ET_HEX8, ET_TET4, ET_HEX20, ET_TET10, ET_WEDGE6)   ! (isotropic 3D: the laws' own D)
      call vm_d3(young, poisson, ds)
      d(1:6, 1:6) = ds
    end select
  end subroutine elem_elastic_d

  !> Reject an element whose geometry makes it singular: zero-length BAR2/BEAM2, coincident
  !> SPRING nodes without a direction, degenerate or inverted quads, and a BEAM2 section asking
  !> for more than 5 Gauss points. Lengths count as zero below zero_tol * ref, ref being
  !> size_ref (the model size, e.g. its bounding-box diagonal) or at least the element's largest
  !> coordinate. The message says what is wrong; the caller adds where.
  pure subroutine elem_check_geometry(et, x, sec, stat, errmsg, size_ref)
    integer, intent(in) :: et
    real(dp), intent(in) :: x(:, :)
    type(section_t), intent(in) :: sec
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), intent(in), optional :: size_ref
    real(dp) :: xl(2, MAX_NEN), ref, x3(3, MAX_NEN)
    integer :: nen
    stat = STAT_OK
    nen = etype_nen(et)
    if (etype_dimension(et) == 3) then
      call local_coords_3(et, x, x3)
      ref = maxval(abs(x3(:, 1:nen)))
      if (present(size_ref)) ref = max(ref, size_ref)
      call solid_check(nen, x3, ref, stat, errmsg)
      return
    end if
    call local_coords(et, x, xl)
    ref = maxval(abs(xl(:, 1:nen)))
    if (present(size_ref)) ref = max(ref, size_ref)
    select case (et)
    case (ET_SPRING)
      call spring_check(xl(:, 1:2), sec, ref, stat, errmsg)
    case (ET_BAR2)
      call bar2_check(xl(:, 1:2), ref, 'BAR2', stat, errmsg)
    case (ET_BEAM2)
      call bar2_check(xl(:, 1:2), ref, 'BEAM2', stat, errmsg)
      if (stat /= STAT_OK) return
      if (sec%gauss > BEAM2_MAX_GAUSS) then
        call set_error(stat, errmsg, STAT_INPUT, 'BEAM2 accepts 1 to ' // str(BEAM2_MAX_GAUSS) // &
          ' Gauss points, the section asks for ' // str(sec%gauss))
      end if
    case (ET_QUAD4)
      call quad_check(4, xl, ref, stat, errmsg)
    case (ET_QUAD8)
      call quad_check(8, xl, ref, stat, errmsg)
    case (ET_TRI3)
      call tri_check(3, xl(:, 1:6), ref, stat, errmsg)
    case (ET_TRI6)
      call tri_check(6, xl(:, 1:6), ref, stat, errmsg)
    end select
  end subroutine elem_check_geometry

  !> Reject section data that leave the element without stiffness or mass where it needs them:
  !> BAR2/BEAM2 area <= 0, BEAM2 inertia <= 0, quad thickness <= 0, MASS mass < 0.
  pure subroutine elem_check_section(et, sec, stat, errmsg)
    integer, intent(in) :: et
    type(section_t), intent(in) :: sec
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    select case (et)
    case (ET_MASS)
      if (sec%mass < 0.0_dp) call set_error(stat, errmsg, STAT_INPUT, 'MASS element with negative mass ' // str(sec%mass))
    case (ET_BAR2, ET_BEAM2)
      if (sec%area <= 0.0_dp) then
        call set_error(stat, errmsg, STAT_INPUT, etype_name(et) // ' section needs a positive area (got ' // &
          str(sec%area) // ')')
      else if (et == ET_BEAM2 .and. sec%inertia <= 0.0_dp) then
        call set_error(stat, errmsg, STAT_INPUT, 'BEAM2 section needs a positive inertia (got ' // str(sec%inertia) // ')')
      end if
    case (ET_QUAD4, ET_QUAD8, ET_TRI3, ET_TRI6)
      if (sec%thickness <= 0.0_dp .and. .not. sec%axisymmetric) then
        call set_error(stat, errmsg, STAT_INPUT, etype_name(et) // ' needs a positive thickness (got ' // &
          str(sec%thickness) // ')')
      end if
    end select
  end subroutine elem_check_section

  !> Stiffness sum_ig B^T D B wt (at least ndof x ndof) for one D at every point, e.g. the
  !> elastic one. Used for the initial stiffness and in tests.
  pure subroutine elem_stiffness(et, x, sec, d, ke)
    integer, intent(in) :: et
    real(dp), intent(in) :: x(:, :), d(:, :)
    type(section_t), intent(in) :: sec
    real(dp), intent(out) :: ke(:, :)
    real(dp) :: b(MAX_NSTRAIN, MAX_EDOF), db(MAX_NSTRAIN, MAX_EDOF), kl(MAX_EDOF, MAX_EDOF), wt
    integer :: ig, ns, nd
    ns = elem_nstrain(et)
    nd = elem_ndof(et)
    kl = 0.0_dp
    do ig = 1, elem_ngauss(et, sec)
      call elem_gauss_b(et, x, sec, ig, b, wt)
      db(1:ns, 1:nd) = matmul(d(1:ns, 1:ns), b(1:ns, 1:nd))
      kl(1:nd, 1:nd) = kl(1:nd, 1:nd) + wt * matmul(transpose(b(1:ns, 1:nd)), db(1:ns, 1:nd))
    end do
    ke = 0.0_dp
    ke(1:nd, 1:nd) = kl(1:nd, 1:nd)
  end subroutine elem_stiffness
end module elements
