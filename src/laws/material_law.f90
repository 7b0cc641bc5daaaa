!> Constitutive laws behind one interface. A law integrates the stress along the straight
!> strain path eps(s) = eps_n + s*deps, s in [0,1], in N sub-increments, and returns the
!> end stress, the path-mean stress (trapezoid over the sub-increments, method.md section 2),
!> the new internal variables, the work per unit weight and its dissipated part.
!> Material-point kinds: PK_1D (springs: force/elongation, bars: axial stress/strain),
!> PK_BEAM (section resultants N, M against axial strain and curvature), PK_PSTRAIN and
!> PK_PSTRESS (quads: xx, yy, zz, xy with engineering shear), PK_SOLID (3D solids: xx, yy, zz, xy,
!> yz, xz, engineering shears).
!> Laws and where they apply (law_check rejects the other pairs):
!>   ELASTIC            every kind; beams with sec%layers > 0 use the fibre-integrated D
!>   NONLINEAR_ELASTIC  PK_1D, PK_BEAM with layers > 0   sigma = E eps (1 + nl_b eps^2)
!>   ELASTOPLASTIC      PK_1D, PK_BEAM with layers > 0   bilinear, yield, h_iso, h_kin
!>   VON_MISES          PK_PSTRAIN, PK_PSTRESS, PK_SOLID J2, yield, h_iso, h_kin
!>   HYPERELASTIC       PK_PSTRAIN, PK_PSTRESS, PK_SOLID compressible neo-Hookean, LARGE (law_hyperelastic;
!>                      its stress is formed by the large-displacement kernel, not by law_update)
!> User documentation: docs/materials.md.
module material_law
  use kinds, only: dp
  use section, only: section_t
  use law_types, only: law_params_t, law_step_t, NSUB_EXACT, law_step_reset
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use law_elastic, only: elastic_update
  use law_nonlinear_elastic, only: nle_path, nle_exact, nle_auto_nsub, nle_energy, nle_stress
  use law_plastic_1d, only: P1D_NSTATE, plastic_1d_path, plastic_auto_nsub
  use law_hyperelastic, only: nh_lame, nh_energy, nh_solid_energy
  use law_von_mises, only: vm_state_size, vm_path, vm_trial_ratio, vm_stored, vm_d3, vm_dps
  use beam_fibre, only: FIB_ELASTIC, FIB_NONLINEAR, FIB_PLASTIC, fibre_update, fibre_stored, &
                        fibre_elastic_matrix, fibre_nstate
  implicit none
  private
  public :: material_t, law_step_t, law_update, law_is_linear, law_nstate, law_name, law_code, law_check
  public :: law_stored, law_elastic_matrix, law_nearly_isochoric
  public :: LAW_ELASTIC, LAW_NONLINEAR_ELASTIC, LAW_ELASTOPLASTIC, LAW_VON_MISES, LAW_HYPERELASTIC
  public :: PK_1D, PK_BEAM, PK_PSTRAIN, PK_PSTRESS, PK_SOLID, pk_nstrain

  integer, parameter :: LAW_ELASTIC = 1, LAW_NONLINEAR_ELASTIC = 2, LAW_ELASTOPLASTIC = 3, LAW_VON_MISES = 4, &
    LAW_HYPERELASTIC = 5
  integer, parameter :: PK_1D = 1, PK_BEAM = 2, PK_PSTRAIN = 3, PK_PSTRESS = 4, PK_SOLID = 5

  !> A scene's material: its name, its law and density, and the law's constants (law_params_t:
  !> young, poisson, nl_b, yield, h_iso, h_kin), which the laws receive as mat%law_params_t.
  type, extends(law_params_t) :: material_t
    character(len=:), allocatable :: name
    integer :: law = LAW_ELASTIC
    real(dp) :: density = 0.0_dp   !< [kg/m3]
  end type material_t

contains

  !> Upper-case name of a law.
  pure function law_name(law) result(name)
    integer, intent(in) :: law
    character(len=:), allocatable :: name
    select case (law)
    case (LAW_ELASTIC)
      name = 'ELASTIC'
    case (LAW_NONLINEAR_ELASTIC)
      name = 'NONLINEAR_ELASTIC'
    case (LAW_ELASTOPLASTIC)
      name = 'ELASTOPLASTIC'
    case (LAW_VON_MISES)
      name = 'VON_MISES'
    case (LAW_HYPERELASTIC)
      name = 'HYPERELASTIC'
    case default
      name = '?'
    end select
  end function law_name

  !> Law code of an upper-case name (law_name's inverse); 0 when unknown.
  pure integer function law_code(name)
    character(len=*), intent(in) :: name
    integer :: k
    law_code = 0
    do k = LAW_ELASTIC, LAW_HYPERELASTIC
      if (trim(name) == law_name(k)) law_code = k
    end do
  end function law_code

  !> Number of generalized strain components of a material-point kind.
  pure integer function pk_nstrain(pk)
    integer, intent(in) :: pk
    select case (pk)
    case (PK_1D)
      pk_nstrain = 1
    case (PK_BEAM)
      pk_nstrain = 2
    case (PK_SOLID)
      pk_nstrain = 6
    case default
      pk_nstrain = 4
    end select
  end function pk_nstrain

  !> True when the stress is a linear function of the strain (no iteration, no correction).
  !> The law keeps (nearly) the volume of a point: VON_MISES (isochoric flow), ELASTIC or
  !> HYPERELASTIC from POISSON 0.49 (bulk over shear modulus >= 50). Low-order plane-strain elements
  !> lock under it: FORMULATION AUTO takes BBAR for QUAD4 (scene_models), a TRI3 is warned (scene_report).
  pure logical function law_nearly_isochoric(mat)
    type(material_t), intent(in) :: mat
    law_nearly_isochoric = mat%law == LAW_VON_MISES .or. &
      ((mat%law == LAW_ELASTIC .or. mat%law == LAW_HYPERELASTIC) .and. mat%poisson >= 0.49_dp)
  end function law_nearly_isochoric

  pure logical function law_is_linear(mat)
    type(material_t), intent(in) :: mat
    law_is_linear = mat%law == LAW_ELASTIC
  end function law_is_linear

  !> Fibre kind of a beam material.
  pure integer function fibre_kind(mat)
    type(material_t), intent(in) :: mat
    select case (mat%law)
    case (LAW_NONLINEAR_ELASTIC)
      fibre_kind = FIB_NONLINEAR
    case (LAW_ELASTOPLASTIC)
      fibre_kind = FIB_PLASTIC
    case default
      fibre_kind = FIB_ELASTIC
    end select
  end function fibre_kind

  !> Number of internal variables per material point: ELASTOPLASTIC PK_1D 3 ([eps_p, alpha,
  !> beta]); fibre beams 3 per layer (layer f at q(3f-2:3f)), i.e. 3 * sec%layers per Gauss point;
  !> VON_MISES 10 (see law_von_mises); 0 otherwise.
  pure integer function law_nstate(mat, pk, sec)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: pk
    type(section_t), intent(in) :: sec
    law_nstate = 0
    select case (mat%law)
    case (LAW_ELASTOPLASTIC)
      if (pk == PK_1D) law_nstate = P1D_NSTATE
      if (pk == PK_BEAM .and. sec%layers > 0) law_nstate = fibre_nstate(FIB_PLASTIC, sec)
    case (LAW_VON_MISES)
      if (pk == PK_PSTRAIN .or. pk == PK_PSTRESS .or. pk == PK_SOLID) law_nstate = vm_state_size(pk_nstrain(pk))
    end select
  end function law_nstate

  !> The elastic matrix of a point (nstr x nstr, at least): the one the laws use and K0 should
  !> use. PK_1D: young; PK_BEAM: diag(E A, E I), or for sec%layers > 0 the fibre-integrated
  !> diag(sum E A_f, sum E y_f^2 A_f); PK_PSTRAIN / PK_PSTRESS / PK_SOLID: as elements' elem_elastic_d.
  pure subroutine law_elastic_matrix(mat, sec, pk, d)
    type(material_t), intent(in) :: mat
    type(section_t), intent(in) :: sec
    integer, intent(in) :: pk
    real(dp), intent(out) :: d(:, :)
    real(dp) :: d4(4, 4), d6(6, 6)
    d = 0.0_dp
    select case (pk)
    case (PK_1D)
      d(1, 1) = mat%young
    case (PK_BEAM)
      if (sec%layers > 0) then
        call fibre_elastic_matrix(mat%young, sec, d)
      else
        d(1, 1) = mat%young * sec%area
        d(2, 2) = mat%young * sec%inertia
      end if
    case (PK_PSTRAIN)
      call vm_d3(mat%young, mat%poisson, d4)
      d(1:4, 1:4) = d4
    case (PK_PSTRESS)
      call vm_dps(mat%young, mat%poisson, d4)
      d(1:4, 1:4) = d4
    case (PK_SOLID)
      call vm_d3(mat%young, mat%poisson, d6)
      d(1:6, 1:6) = d6
    end select
  end subroutine law_elastic_matrix

  !> Reject a material that cannot be used on a kind of point (pk, sec): non-positive YOUNG,
  !> POISSON outside (-1, 1/2) on quads, a law not defined for the kind, YIELD <= 0 or negative
  !> hardening for the plastic laws, a nonlinear beam without layers or height.
  pure subroutine law_check(mat, pk, sec, stat, errmsg)
    type(material_t), intent(in) :: mat
    integer, intent(in) :: pk
    type(section_t), intent(in) :: sec
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (.not. mat%young > 0.0_dp) then
      call set_error(stat, errmsg, STAT_INPUT, 'YOUNG must be > 0 (got ' // str(mat%young) // ')')
    else if ((pk == PK_PSTRAIN .or. pk == PK_PSTRESS .or. pk == PK_SOLID) .and. &
             .not. (mat%poisson > -1.0_dp .and. mat%poisson < 0.5_dp)) then
      call set_error(stat, errmsg, STAT_INPUT, 'POISSON must be in (-1, 0.5) (got ' // str(mat%poisson) // ')')
    else if (pk == PK_SOLID .and. mat%law /= LAW_ELASTIC .and. mat%law /= LAW_VON_MISES .and. mat%law /= LAW_HYPERELASTIC) &
      then
      call set_error(stat, errmsg, STAT_INPUT, law_name(mat%law) // ' is not available on 3D solids yet (ELASTIC, ' // &
        'VON_MISES, HYPERELASTIC)')
    else if (mat%law < LAW_ELASTIC .or. mat%law > LAW_HYPERELASTIC) then
      call set_error(stat, errmsg, STAT_INPUT, 'unknown law code ' // str(mat%law))
    else if (mat%law == LAW_HYPERELASTIC .and. pk /= PK_PSTRAIN .and. pk /= PK_PSTRESS .and. pk /= PK_SOLID) then
      call set_error(stat, errmsg, STAT_INPUT, 'HYPERELASTIC applies to surface and solid elements only')
    else if (mat%law /= LAW_HYPERELASTIC .and. pk /= PK_SOLID .and. &
             (mat%law == LAW_VON_MISES .neqv. (pk == PK_PSTRAIN .or. pk == PK_PSTRESS))) then
      if (mat%law == LAW_VON_MISES) then
        call set_error(stat, errmsg, STAT_INPUT, 'VON_MISES applies to QUAD4, QUAD8, TRI3 and TRI6 only')
      else if (mat%law /= LAW_ELASTIC) then
        call set_error(stat, errmsg, STAT_INPUT, law_name(mat%law) // &
          ' applies to SPRING, BAR2 and layered BEAM2 only (quads: VON_MISES, HYPERELASTIC)')
      end if
    end if
    if (stat /= STAT_OK) return
    if (mat%law == LAW_ELASTOPLASTIC .or. mat%law == LAW_VON_MISES) then
      if (.not. mat%yield > 0.0_dp) then
        call set_error(stat, errmsg, STAT_INPUT, 'YIELD must be > 0 (got ' // str(mat%yield) // ')')
      else if (.not. (mat%h_iso >= 0.0_dp .and. mat%h_kin >= 0.0_dp)) then
        call set_error(stat, errmsg, STAT_INPUT, 'hardening moduli must be >= 0')
      end if
    end if
    if (stat /= STAT_OK) return
    if (pk == PK_BEAM .and. (mat%law == LAW_ELASTOPLASTIC .or. mat%law == LAW_NONLINEAR_ELASTIC)) then
      if (sec%layers <= 0) then
        call set_error(stat, errmsg, STAT_INPUT, law_name(mat%law) // ' BEAM2 needs a fibre section (LAYERS > 0)')
      end if
    end if
    if (pk == PK_BEAM .and. sec%layers > 0 .and. .not. sec%height > 0.0_dp) then
      call set_error(stat, errmsg, STAT_INPUT, 'a fibre section (LAYERS > 0) needs HEIGHT > 0')
    end if
  end subroutine law_check

  !> Integrate the law over one step (see the module header) into r (law_types' law_step_t).
  !> d: elastic matrix of the point (nstr x nstr), law_elastic_matrix's (ELASTIC and VON_MISES
  !> use it; the 1D and fibre laws take E from the material). nsub >= 1: N fixed sub-increments;
  !> nsub = 0: AUTO (docs/materials.md); NSUB_EXACT: the discrete gradient of NONLINEAR_ELASTIC (the
  !> scene allows it for laws with a potential only). q_n, q: law_nstate internal variables.
  !> r%work = sigbar . deps and r%dissip (trapezoid of sigma . deps_p over the sub-increments) are
  !> per unit weight. r%nused: sub-increments used, 0 when no sub-incrementation was needed
  !> (ELASTIC, or a step of a plastic law that stayed elastic: then sig = sig_n + D deps and
  !> sigbar = (sig_n + sig)/2 exactly, so sigma_c = 0 bit for bit). r%dtan: consistent tangent
  !> d sig / d deps of the last sub-increment, for VON_MISES of one return over the whole increment
  !> (exact for N = 1, and for any N when the whole step is elastic or, 1D laws, on one branch).
  pure subroutine law_update(mat, sec, pk, d, nsub, eps_n, deps, sig_n, q_n, q, r)
    type(material_t), intent(in) :: mat
    type(section_t), intent(in) :: sec
    integer, intent(in) :: pk, nsub
    real(dp), intent(in) :: d(:, :), eps_n(:), deps(:), sig_n(:), q_n(:)
    real(dp), intent(out) :: q(:)
    type(law_step_t), intent(out) :: r
    real(dp) :: dl4(4, 4), dl6(6, 6)
    integer :: n, ns, nst
    ns = pk_nstrain(pk)
    nst = law_nstate(mat, pk, sec)
    call law_step_reset(r)
    if (size(q) > 0) q = 0.0_dp
    select case (mat%law)
    case (LAW_NONLINEAR_ELASTIC, LAW_ELASTOPLASTIC)
      if (pk == PK_BEAM .and. sec%layers > 0) then
        call fibre_update(fibre_kind(mat), mat%law_params_t, sec, nsub, eps_n(1:2), deps(1:2), sig_n(1:2), q_n, q, r)
      else if (mat%law == LAW_NONLINEAR_ELASTIC .and. nsub == NSUB_EXACT) then
        call nle_exact(mat%young, mat%nl_b, eps_n(1), deps(1), r%sig(1), r%sigbar(1), r%dtan(1, 1))
        r%nused = 1
      else if (mat%law == LAW_NONLINEAR_ELASTIC) then
        n = nsub
        if (n <= 0) n = nle_auto_nsub(mat%young, mat%nl_b, eps_n(1), deps(1))
        call nle_path(mat%young, mat%nl_b, n, eps_n(1), deps(1), sig_n(1), r%sig(1), r%sigbar(1), r%dtan(1, 1))
        r%nused = n
      else
        n = nsub
        if (n <= 0) n = plastic_auto_nsub(mat%young * deps(1) / mat%yield)
        call plastic_1d_path(mat%law_params_t, n, sig_n(1), q_n, deps(1), r%sig(1), r%sigbar(1), q, r%dissip, r%nused, &
          r%dtan(1, 1))
      end if
    case (LAW_VON_MISES)
      n = nsub                      ! the caller's D is law_elastic_matrix's (not rebuilt at every point),
      if (ns == 4) then             ! here as a whole contiguous array of the point's size
        dl4 = d(1:4, 1:4)
        if (n <= 0) n = plastic_auto_nsub(vm_trial_ratio(dl4, deps(1:4), mat%yield))
        call vm_path(mat%law_params_t, pk == PK_PSTRESS, n, 4, dl4, sig_n(1:4), q_n, deps(1:4), q, r)
      else
        dl6 = d(1:6, 1:6)
        if (n <= 0) n = plastic_auto_nsub(vm_trial_ratio(dl6, deps(1:6), mat%yield))
        call vm_path(mat%law_params_t, .false., n, 6, dl6, sig_n(1:6), q_n, deps(1:6), q, r)
      end if
    case default
      call elastic_update(d(1:ns, 1:ns), deps(1:ns), sig_n(1:ns), r%sig(1:ns), r%sigbar(1:ns))
      if (nst > 0) q(1:nst) = q_n(1:nst)
      r%dtan(1:ns, 1:ns) = d(1:ns, 1:ns)
    end select
    r%work = dot_product(r%sigbar(1:ns), deps(1:ns))
  end subroutine law_update

  !> Recoverable (elastic) energy per unit weight of a state: 1/2 sigma . eps for ELASTIC,
  !> psi(eps) = E (eps^2/2 + b eps^4/4) for NONLINEAR_ELASTIC, 1/2 sigma . D^-1 sigma for the
  !> plastic laws; fibre beams sum their layers.
  pure real(dp) function law_stored(mat, sec, pk, d, eps, sig, q) result(w)
    type(material_t), intent(in) :: mat
    type(section_t), intent(in) :: sec
    integer, intent(in) :: pk
    real(dp), intent(in) :: d(:, :), eps(:), sig(:), q(:)
    integer :: ns
    ns = pk_nstrain(pk)
    select case (mat%law)
    case (LAW_NONLINEAR_ELASTIC, LAW_ELASTOPLASTIC)
      if (pk == PK_BEAM .and. sec%layers > 0) then
        w = fibre_stored(fibre_kind(mat), mat%young, mat%nl_b, sec, eps(1:2), q)
      else if (mat%law == LAW_NONLINEAR_ELASTIC) then
        w = nle_energy(mat%young, mat%nl_b, eps(1))
      else
        w = 0.5_dp * sig(1)**2 / mat%young
      end if
    case (LAW_VON_MISES)
      w = vm_stored(mat%young, mat%poisson, sig(1:ns))
    case (LAW_HYPERELASTIC)
      if (pk == PK_SOLID) then
        w = nh_solid_energy(nh_lame(mat%young, mat%poisson), eps(1:6))
      else
        w = nh_energy(nh_lame(mat%young, mat%poisson), eps(1:4), pk == PK_PSTRESS)
      end if
    case default
      w = 0.5_dp * dot_product(sig(1:ns), eps(1:ns))
    end select
  end function law_stored
end module material_law
