!> MODES n [ABOVE f0] (docs/input.md, "Modes"; docs/modes.md): the natural frequencies and mode
!> shapes of the supported structure, K0 φ = ω² M φ on the free equations (FIX and the axis of an
!> axisymmetric model eliminated; contacts open; the reference configuration), the n lowest (or
!> the n lowest above f0 Hz). Above DENSE_BELOW equations: ARPACK's shift-invert Lanczos with
!> CHOLMOD's factor of K0 - σM; below: LAPACK's dense solver on the pencil (M, K0 - σM), every
!> eigenpair. σ = -1e-3 min(K_ii / M_ii) < 0: K0 - σM is positive definite even for a free body,
!> whose rigid modes come out as zeros. ABOVE f0: the modes from the lowest, more of them until n
!> are above f0 (a shift inside the spectrum would need an indefinite factorization). Each shape
!> is scaled to a largest translation of 1 (its sign: that entry positive); with it the generalized
!> mass φ'Mφ and the effective mass of each direction, (φ'M r_d)² / φ'Mφ (r_d the unit translation
!> along d; their sums over every mode are the structure's mass: none along x in an axisymmetric
!> model, whose rings have no net radial motion).
!> Outputs: OUTDIR/modes.csv (mode, frequency, period, generalized_mass, effective_mass_x,
!> effective_mass_y) and the shapes as OUTDIR/modes.h5 and modes.xmf (one step per mode, its time
!> the frequency), which ParaView steps through.
module modes
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str, check_alloc
  use scene, only: scene_t, scene_axisymmetric
  use mesh, only: mesh_t
  use assembly, only: system_t
  use sparse_matrix, only: sym_csc_t, to_dense
  use cholmod_binding, only: cholmod_factor_t
  use arpack_binding, only: shift_invert_t, lanczos_shift_invert
  use dense_solve, only: generalized_eigen
  use history_writer, only: csv_file_t
  use fields_hdf5, only: fields_writer_t
  use mesh, only: DOF_UX, DOF_UY, DOF_UZ, DOF_RZ
  implicit none
  private
  public :: modes_t, compute_modes, write_modes, DENSE_BELOW, MODES_HEADER

  integer, parameter :: DENSE_BELOW = 200            !< equations: LAPACK's dense solver up to this size
  real(dp), parameter :: TWO_PI = 6.283185307179586476925286766559_dp
  character(len=*), parameter :: MODES_HEADER = 'mode,frequency,period,generalized_mass,effective_mass_x,' // &
    'effective_mass_y,effective_mass_z'
  integer, parameter :: TRANSLATIONS(3) = [DOF_UX, DOF_UY, DOF_UZ]   !< the DOF slots of x, y, z

  !> The modes found: ω², the shapes on the free equations, their masses.
  type :: modes_t
    integer :: n = 0                              !< modes found (the MODES count unless the solver fell short)
    real(dp), allocatable :: omega2(:)            !< ω² (rad²/s²), ascending
    real(dp), allocatable :: phi(:, :)            !< (neq, n) shapes, largest translation 1
    real(dp), allocatable :: genmass(:)           !< φ'Mφ (kg)
    real(dp), allocatable :: effmass(:, :)        !< (3, n) effective masses along x, y, z (kg; z: 3D)
    real(dp) :: sigma = 0.0_dp                    !< the shift (< 0)
    real(dp) :: residual = 0.0_dp                 !< max over the modes of |K0 φ - ω² M φ| / (|K0 φ| + ω² |M φ|)
    character(len=:), allocatable :: method       !< how they were computed (stdout)
  contains
    procedure :: frequency => modes_frequency
  end type modes_t

  !> The pencil's operations for ARPACK: M x, and (K0 - σM)⁻¹ x by CHOLMOD's factor.
  type, extends(shift_invert_t) :: pencil_t
    type(sym_csc_t), pointer :: pat => null()
    real(dp), pointer :: mval(:) => null()
    type(cholmod_factor_t) :: chol
  contains
    procedure :: apply_b => pencil_b
    procedure :: solve_shifted => pencil_solve
  end type pencil_t

contains

  !> Frequency of mode k in Hz (0 for a rigid mode, whose ω² is zero to round-off).
  pure real(dp) function modes_frequency(self, k) result(f)
    class(modes_t), intent(in) :: self
    integer, intent(in) :: k
    f = sqrt(max(self%omega2(k), 0.0_dp)) / TWO_PI
  end function modes_frequency

  !> The scene's MODES on its system (K0 and M assembled): md.
  subroutine compute_modes(scn, sys, md, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in), target :: sys
    type(modes_t), intent(out) :: md
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), allocatable :: kd(:), mdg(:)
    real(dp) :: ratio
    integer :: neq, i
    stat = STAT_OK
    neq = sys%dofs%neq
    if (scn%modes > neq .or. (scn%modes == neq .and. neq > DENSE_BELOW)) then
      call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(scn%modes_line) // ': MODES: ' // str(scn%modes) // &
        ' modes of a structure with ' // str(neq) // ' free equations (at most ' // &
        str(merge(neq, neq - 1, neq <= DENSE_BELOW)) // "), at '" // str(scn%modes) // "'")
      return
    end if
    allocate (kd(neq), mdg(neq))
    call sys%ops%pat%diagonal(sys%ops%kval, kd)
    call sys%ops%pat%diagonal(sys%ops%mval, mdg)
    ratio = huge(1.0_dp)
    do i = 1, neq
      if (mdg(i) > 0.0_dp .and. kd(i) > 0.0_dp) ratio = min(ratio, kd(i) / mdg(i))
    end do
    if (ratio == huge(1.0_dp)) then
      call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(scn%modes_line) // ': MODES: the structure has ' // &
        "no degree of freedom with both mass and stiffness, at 'MODES'")
      return
    end if
    md%sigma = -1.0e-3_dp * ratio
    if (neq <= DENSE_BELOW) then
      call dense_modes(scn, sys, md, stat, errmsg)
    else
      call lanczos_modes(scn, sys, md, stat, errmsg)
    end if
    if (stat /= STAT_OK) return
    call mode_masses(scn, sys, md)
  end subroutine compute_modes

  !> Every eigenpair of the pencil (M, K0 - σM) (σ < 0: positive definite), λ = σ + 1/μ for μ > 0
  !> (μ = 0: a massless direction, an infinite frequency), the n lowest (above f0 with ABOVE).
  subroutine dense_modes(scn, sys, md, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    type(modes_t), intent(inout) :: md
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), allocatable :: k(:, :), m(:, :), mu(:), vecs(:, :)
    real(dp) :: sd
    integer :: neq, j, c
    neq = sys%dofs%neq
    sd = md%sigma
    allocate (k(neq, neq), m(neq, neq), mu(neq))
    call to_dense(sys%ops%pat, sys%ops%kval, k)
    call to_dense(sys%ops%pat, sys%ops%mval, m)
    call generalized_eigen(m, k - sd * m, mu, vecs, stat, errmsg)
    if (stat /= STAT_OK) then
      errmsg = 'MODES: ' // errmsg // ' (K0 - σM is not positive definite: a mechanism without mass?)'
      return
    end if
    allocate (md%omega2(scn%modes), md%phi(neq, scn%modes))
    c = 0
    do j = neq, 1, -1                              ! μ descending: λ ascending
      if (.not. (mu(j) > 1.0e-14_dp * mu(neq))) exit
      if (sd + 1.0_dp / mu(j) < lambda_above(scn)) cycle    ! (ABOVE f0)
      c = c + 1
      md%omega2(c) = sd + 1.0_dp / mu(j)
      md%phi(:, c) = vecs(:, j)
      if (c == scn%modes) exit
    end do
    md%n = c
    md%method = 'LAPACK dsygvd (dense, ' // str(neq) // ' equations)'
  end subroutine dense_modes

  !> ARPACK's shift-invert Lanczos on K0 - σM, CHOLMOD's factor. ABOVE f0: the lowest nev modes,
  !> nev from n + 10 doubled until n of them are above f0 (or every mode but one is asked).
  subroutine lanczos_modes(scn, sys, md, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in), target :: sys
    type(modes_t), intent(inout) :: md
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(pencil_t) :: op
    real(dp), allocatable :: lam(:), x(:, :)
    integer :: neq, nconv, ast, nev, first, k
    first = 1
    neq = sys%dofs%neq
    op%pat => sys%ops%pat
    op%mval => sys%ops%mval
    call op%chol%factorize(sys%ops%pat, sys%ops%kval - md%sigma * sys%ops%mval, stat, errmsg)
    if (stat /= STAT_OK) then
      errmsg = 'MODES: K0 - σM (σ = ' // str(md%sigma) // '): ' // errmsg // ' (a mechanism without mass?)'
      call op%chol%destroy()
      return
    end if
    nev = scn%modes
    if (scn%modes_above > 0.0_dp) nev = min(neq - 1, scn%modes + 10)
    do
      if (allocated(lam)) deallocate (lam, x)
      allocate (lam(nev), x(neq, nev), stat=ast)
      call check_alloc(ast, 'the mode shapes', 8.0_dp * neq * nev, stat, errmsg)
      if (stat == STAT_OK) call lanczos_shift_invert(op, neq, nev, md%sigma, lam, x, nconv, stat, errmsg)
      if (stat /= STAT_OK) exit
      first = nconv + 1                          ! the first mode above f0
      do k = 1, nconv
        if (lam(k) >= lambda_above(scn)) then
          first = k
          exit
        end if
      end do
      if (nconv - first + 1 >= scn%modes .or. nev == neq - 1 .or. nconv < nev) exit
      nev = min(neq - 1, 2 * nev)
    end do
    call op%chol%destroy()
    if (stat /= STAT_OK) return
    md%n = min(scn%modes, nconv - first + 1)
    allocate (md%omega2(md%n), md%phi(neq, md%n))
    md%omega2 = lam(first:first + md%n - 1)
    md%phi = x(:, first:first + md%n - 1)
    md%method = 'ARPACK shift-invert Lanczos, CHOLMOD factor of K0 - σM (' // str(neq) // ' equations)'
  end subroutine lanczos_modes

  !> ω² of the ABOVE f0 limit (-huge without ABOVE).
  pure real(dp) function lambda_above(scn)
    type(scene_t), intent(in) :: scn
    lambda_above = -huge(1.0_dp)
    if (scn%modes_above > 0.0_dp) lambda_above = (TWO_PI * scn%modes_above)**2
  end function lambda_above

  subroutine pencil_b(self, x, y, stat, errmsg)
    class(pencil_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: x(:)
    real(dp), intent(out), contiguous :: y(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    call self%pat%matvec(self%mval, x, y)
  end subroutine pencil_b

  subroutine pencil_solve(self, x, y, stat, errmsg)
    class(pencil_t), intent(inout) :: self
    real(dp), intent(in), contiguous :: x(:)
    real(dp), intent(out), contiguous :: y(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call self%chol%solve(x, y, stat, errmsg)
  end subroutine pencil_solve

  !> Each shape scaled to a largest translation of 1 (that entry positive), its generalized mass and
  !> effective masses.
  subroutine mode_masses(scn, sys, md)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    type(modes_t), intent(inout) :: md
    real(dp), allocatable :: mphi(:), kphi(:), r(:, :)
    integer :: k, n, d, j, big
    real(dp) :: amax
    allocate (mphi(sys%dofs%neq), kphi(sys%dofs%neq), r(sys%dofs%neq, 3), md%genmass(md%n), md%effmass(3, md%n))
    md%residual = 0.0_dp
    r = 0.0_dp
    do n = 1, scn%mesh%nnode
      do d = 1, 3
        j = sys%dofs%eqn(TRANSLATIONS(d), n)
        if (j > 0) r(j, d) = 1.0_dp
      end do
    end do
    do k = 1, md%n
      big = 0
      amax = -1.0_dp
      do n = 1, scn%mesh%nnode
        do d = 1, 3
          j = sys%dofs%eqn(TRANSLATIONS(d), n)
          if (j <= 0) cycle
          if (abs(md%phi(j, k)) > amax) then
            amax = abs(md%phi(j, k))
            big = j
          end if
        end do
      end do
      if (big == 0) big = maxloc(abs(md%phi(:, k)), 1)     ! rotations only
      if (md%phi(big, k) /= 0.0_dp) md%phi(:, k) = md%phi(:, k) / md%phi(big, k)
      call sys%ops%pat%matvec(sys%ops%mval, md%phi(:, k), mphi)
      call sys%ops%pat%matvec(sys%ops%kval, md%phi(:, k), kphi)
      md%residual = max(md%residual, norm2(kphi - md%omega2(k) * mphi) / &
        (norm2(kphi) + abs(md%omega2(k)) * norm2(mphi) + tiny(1.0_dp)))
      md%genmass(k) = dot_product(md%phi(:, k), mphi)
      do d = 1, 3
        md%effmass(d, k) = dot_product(r(:, d), mphi)**2 / md%genmass(k)
      end do
      if (scene_axisymmetric(scn)) md%effmass(1, k) = 0.0_dp
    end do
  end subroutine mode_masses

  !> OUTDIR/modes.csv and the shapes in OUTDIR/modes.h5 (+ modes.xmf): one step per mode, its
  !> displacement the shape (stresses not computed: zero), its time the frequency.
  subroutine write_modes(scn, sys, md, outdir, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    type(modes_t), intent(in) :: md
    character(len=*), intent(in) :: outdir
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(csv_file_t) :: csv
    type(fields_writer_t) :: fw
    type(mesh_t) :: shown
    real(dp), allocatable :: u(:, :), v(:, :), sig(:, :)
    integer, allocatable :: kept(:)
    integer :: k, n, d, i, slots(3)
    real(dp) :: f, period
    call csv%open(outdir // '/modes.csv', MODES_HEADER, stat, errmsg)
    if (stat /= STAT_OK) return
    do k = 1, md%n
      f = md%frequency(k)
      period = 0.0_dp
      if (f > 0.0_dp) period = 1.0_dp / f
      call csv%write_row(k, [f, period, md%genmass(k), md%effmass(1, k), md%effmass(2, k), md%effmass(3, k)], &
        [integer ::], stat, errmsg)
      if (stat /= STAT_OK) return
    end do
    call csv%close(stat, errmsg)
    if (stat /= STAT_OK .or. md%n == 0) return
    kept = pack([(i, i = 1, scn%mesh%nelem)], scn%elem_model(1:scn%mesh%nelem) > 0)
    call scn%mesh%subset_elements(kept, shown)
    call fw%open(outdir, shown, stat, errmsg, basename='modes', axisymmetric=scene_axisymmetric(scn))
    if (stat /= STAT_OK) return
    allocate (u(3, scn%mesh%nnode), v(3, scn%mesh%nnode), sig(merge(6, 4, scn%mesh%ndim == 3), size(kept)))
    v = 0.0_dp
    sig = 0.0_dp
    slots = [DOF_UX, DOF_UY, merge(DOF_UZ, DOF_RZ, scn%mesh%ndim == 3)]   ! (fields: UX UY RZ, 3D UX UY UZ)
    do k = 1, md%n
      u = 0.0_dp
      do n = 1, scn%mesh%nnode
        do d = 1, 3
          if (sys%dofs%eqn(slots(d), n) > 0) u(d, n) = md%phi(sys%dofs%eqn(slots(d), n), k)
        end do
      end do
      call fw%write_step(k, md%frequency(k), u, v, sig, stat, errmsg)
      if (stat /= STAT_OK) return
    end do
    call fw%close(stat, errmsg)
  end subroutine write_modes
end module modes
