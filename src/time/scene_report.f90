!> A report of the scene before its first step (issue 37, item 5): what a user checks before
!> trusting a run. The total mass and each model's, estimates of the highest and the lowest
!> natural frequency, each model's wave speed and c h/dx, and warnings where the step is longer
!> than the lowest period or a wave speed falls outside 10 to 20 000 m/s ("check the units").
!>
!> The frequencies are of the linearized, undamped scene at rest (K0 and M, supports eliminated):
!> - highest: power iterations on M⁻¹K0 (M⁻¹ by conjugate gradients, or its diagonal): the
!>   Rayleigh quotient after them is a lower bound of ω_max², close to it after a few iterations;
!> - lowest: inverse iterations x <- (K0 + σM)⁻¹ M x (σ tiny: K0's own convergence) where that
!>   factorization costs at most 3 % of the run's solves (or 1e8 flops), else x <- S⁻¹ M x with the step's
!>   factor; each body's free rigid motions (the translations and the rotation no support holds)
!>   taken out: the Rayleigh quotient x'K0x / x'Mx is an upper bound of ω_1², exact once converged.
!> The report's CPU time is measured (docs/performance.md, "The scene report").
module scene_report
  use kinds, only: dp
  use errors, only: STAT_OK, str
  use text_file, only: say
  use scene, only: scene_t
  use assembly, only: system_t, mass_times
  use spd_factor, only: spd_factor_t
  use elements, only: elem_mass, elem_dof_mask, elem_ndof, MAX_EDOF
  use element_traits, only: ET_BAR2, ET_BEAM2, ET_QUAD4, ET_QUAD8, ET_TRI3, ET_TRI6, ET_HEX8, ET_TET4, NODE_DOFS, MAX_NEN, &
    ET_HEX20, ET_TET10, ET_WEDGE6
  use dof_map, only: equation_bodies, body_rigid_freedom
  use lapack_pure, only: dsyev
  use material_law, only: law_nearly_isochoric
  implicit none
  private
  public :: report_t, measure_scene, say_report, report_warnings

  real(dp), parameter :: PI = 3.141592653589793_dp
  integer, parameter :: HIGH_ITER = 12, LOW_ITER = 25, LOW_ITER_S = 12
  real(dp), parameter :: LOW_RTOL = 1.0e-6_dp        !< inverse iteration: converged at this change
  real(dp), parameter :: SIGMA_REL = 1.0e-10_dp      !< the shift of the lowest's factor, relative to ω_max²
  !> The lowest frequency factorizes K0 + σM when that costs at most this share of the run's solves.
  real(dp), parameter :: FACTOR_SHARE = 0.03_dp
  real(dp), parameter :: FACTOR_FLOOR = 1.0e8_dp       !< ... or at most these flops (a small model, any run)
  real(dp), parameter :: WAVE_MIN = 10.0_dp, WAVE_MAX = 2.0e4_dp

  type :: report_t
    real(dp) :: total_mass = 0.0_dp
    real(dp), allocatable :: model_mass(:)
    real(dp), allocatable :: wave(:)             !< each model's wave speed (m/s), 0 without one
    real(dp), allocatable :: chdx(:, :)          !< (2, model) smallest and largest c h/dx of its elements
    real(dp) :: f_high = -1.0_dp                 !< Hz; -1: not estimated (massless DOFs)
    real(dp) :: f_low = -1.0_dp                  !< Hz; -1: not estimated (no deformable mode)
    logical :: low_converged = .false.
    logical :: shifted = .false.                 !< the lowest from K0 + σM (else from S = K0 + 4M/h²)
    real(dp) :: h = 0.0_dp
    real(dp) :: cpu = 0.0_dp                     !< CPU seconds the report took
  end type report_t

contains

  !> The report of the scene scn with its system sys; s: the factor of S = K0 + 4M/h² at h =
  !> scn%dt, nsteps the run's steps; rig (neq, 3): the rigid modes of the model on the free
  !> equations.
  subroutine measure_scene(scn, sys, s, nsteps, rig, rep, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    type(spd_factor_t), intent(inout) :: s
    integer, intent(in) :: nsteps
    real(dp), intent(in) :: rig(:, :)
    type(report_t), intent(out) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: t0, t1
    stat = STAT_OK
    call cpu_time(t0)
    rep%h = scn%dt
    call masses_and_waves(scn, rep)
    if (sys%dofs%neq > 0) then
      call highest(sys, rep)
      call lowest(scn, sys, s, nsteps, rig, rep, stat, errmsg)
    end if
    call cpu_time(t1)
    rep%cpu = t1 - t0
  end subroutine measure_scene

  !> Model masses (consistent element masses, before any redistribution), wave speeds and c h/dx
  !> (dx: the shortest distance between two nodes of an element).
  subroutine masses_and_waves(scn, rep)
    type(scene_t), intent(in) :: scn
    type(report_t), intent(inout) :: rep
    real(dp) :: me(MAX_EDOF, MAX_EDOF), tx(MAX_EDOF), rho, c, dx, x(3, MAX_NEN)
    logical :: mask(NODE_DOFS)
    integer :: e, im, nen, nd, a, d, k, i, j, nm, ns
    nm = size(scn%models)
    allocate (rep%model_mass(nm), rep%wave(nm), rep%chdx(2, nm))
    rep%model_mass = 0.0_dp
    rep%chdx(1, :) = huge(1.0_dp)
    rep%chdx(2, :) = 0.0_dp
    do im = 1, nm
      rep%wave(im) = wave_speed(scn, im)
    end do
    do e = 1, scn%mesh%nelem
      im = scn%elem_model(e)
      if (im == 0) cycle
      nen = scn%mesh%nen(e)
      ns = scn%mesh%ndim
      x(1:ns, 1:nen) = scn%mesh%x(:, scn%mesh%conn(1:nen, e))
      rho = 0.0_dp
      if (scn%models(im)%material > 0) rho = scn%materials(scn%models(im)%material)%density
      nd = elem_ndof(scn%mesh%etype(e), scn%mesh%ndim)
      call elem_mass(scn%mesh%etype(e), x(1:ns, 1:nen), scn%models(im)%sec, rho, .false., me(1:nd, 1:nd))
      mask = elem_dof_mask(scn%mesh%etype(e), scn%mesh%ndim)
      tx(1:nd) = 0.0_dp
      k = 0
      do a = 1, nen
        do d = 1, NODE_DOFS
          if (.not. mask(d)) cycle
          k = k + 1
          if (d == 1) tx(k) = 1.0_dp
        end do
      end do
      rep%model_mass(im) = rep%model_mass(im) + dot_product(tx(1:nd), matmul(me(1:nd, 1:nd), tx(1:nd)))
      c = rep%wave(im)
      if (c > 0.0_dp .and. nen >= 2) then
        dx = huge(1.0_dp)
        do i = 1, nen
          do j = i + 1, nen
            dx = min(dx, norm2(x(1:ns, j) - x(1:ns, i)))
          end do
        end do
        if (dx > 0.0_dp) then
          rep%chdx(1, im) = min(rep%chdx(1, im), c * scn%dt / dx)
          rep%chdx(2, im) = max(rep%chdx(2, im), c * scn%dt / dx)
        end if
      end if
    end do
    rep%total_mass = sum(rep%model_mass)
  end subroutine masses_and_waves

  !> The dilatational wave speed of model im (m/s): sqrt(E/ρ) in bars and beams, the plane
  !> strain or plane stress P wave in surface elements, the P wave in solids; 0 for masses, springs, ρ = 0.
  pure real(dp) function wave_speed(scn, im) result(c)
    type(scene_t), intent(in) :: scn
    integer, intent(in) :: im
    real(dp) :: e, nu, rho
    c = 0.0_dp
    if (scn%models(im)%material == 0) return
    e = scn%materials(scn%models(im)%material)%young
    nu = scn%materials(scn%models(im)%material)%poisson
    rho = scn%materials(scn%models(im)%material)%density
    if (.not. (rho > 0.0_dp .and. e > 0.0_dp)) return
    select case (scn%models(im)%etype)
    case (ET_BAR2, ET_BEAM2)
      c = sqrt(e / rho)
    case (ET_QUAD4, ET_QUAD8, ET_TRI3, ET_TRI6, ET_HEX8, ET_TET4, ET_HEX20, ET_TET10, ET_WEDGE6)
      if (scn%models(im)%sec%plane_stress) then
        c = sqrt(e / (rho * (1.0_dp - nu * nu)))
      else if (nu < 0.5_dp) then
        c = sqrt(e * (1.0_dp - nu) / (rho * (1.0_dp + nu) * (1.0_dp - 2.0_dp * nu)))
      end if
    end select
  end function wave_speed

  !> ω_max² by HIGH_ITER power iterations x <- M⁻¹K0 x, M⁻¹ by Jacobi-preconditioned conjugate
  !> gradients (a consistent mass is well conditioned: a few matrix products, no factorization),
  !> or its diagonal. A DOF without mass (IMPACT MASSLESS's contact nodes, a SPRING's node): -1.
  subroutine highest(sys, rep)
    type(system_t), intent(in) :: sys
    type(report_t), intent(inout) :: rep
    real(dp), allocatable :: x(:), kx(:), mx(:), d(:), r(:), z(:), p(:), q(:)
    real(dp) :: lam
    integer :: it, n
    logical :: ok
    n = sys%dofs%neq
    allocate (x(n), kx(n), mx(n), d(n), r(n), z(n), p(n), q(n))
    if (sys%ops%mass_diagonal) then
      d = sys%ops%mdiag
    else
      call sys%ops%pat%diagonal(sys%ops%mval, d)
    end if
    if (any(.not. (d > 0.0_dp))) return
    call start_vector(x)
    lam = 0.0_dp
    do it = 1, HIGH_ITER
      call sys%ops%pat%matvec(sys%ops%kval, x, kx)
      if (sys%ops%mass_diagonal) then
        x = kx / d
      else
        call mass_solve(sys, d, kx, x, r, z, p, q, ok)
        if (.not. ok) return
      end if
      call mass_times(sys, x, mx)
      if (.not. (dot_product(x, mx) > 0.0_dp)) exit
      call sys%ops%pat%matvec(sys%ops%kval, x, kx)
      lam = dot_product(x, kx) / dot_product(x, mx)
      x = x / sqrt(dot_product(x, mx))
    end do
    rep%f_high = sqrt(max(lam, 0.0_dp)) / (2.0_dp * PI)      ! (0: no stiffness, a point mass)
  end subroutine highest

  !> x = M⁻¹b by conjugate gradients with the preconditioner diag(M)⁻¹ = 1/d, to 1e-8 of |b|
  !> (ok false when it does not get there in 500 iterations); r, z, p, q: work.
  subroutine mass_solve(sys, d, b, x, r, z, p, q, ok)
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: d(:), b(:)
    real(dp), intent(out) :: x(:), r(:), z(:), p(:), q(:)
    logical, intent(out) :: ok
    real(dp) :: rz, rz_new, alpha, bnorm
    integer :: it
    x = 0.0_dp
    r = b
    z = r / d
    p = z
    rz = dot_product(r, z)
    bnorm = norm2(b)
    ok = .true.
    if (.not. (bnorm > 0.0_dp)) return
    do it = 1, 500
      call mass_times(sys, p, q)
      alpha = rz / dot_product(p, q)
      x = x + alpha * p
      r = r - alpha * q
      if (norm2(r) <= 1.0e-8_dp * bnorm) return
      z = r / d
      rz_new = dot_product(r, z)
      p = z + (rz_new / rz) * p
      rz = rz_new
    end do
    ok = .false.
  end subroutine mass_solve

  !> ω_1² by inverse iterations with F = K0 + σM, σ = SIGMA_REL x ω_max² (the free rigid motions of
  !> each body taken out; σ > 0 keeps F positive definite with them): the convergence ratio
  !> (ω_1² + σ)/(ω_2² + σ) is that of K0 itself. The step's factor S = K0 + 4M/h² would serve
  !> without a factorization, but its shift 4/h² dwarfs ω_1² wherever the step resolves the
  !> first mode (measured: 25 iterations on the cantilever of inputs/ left 88.7 Hz for 8.4 Hz).
  subroutine lowest(scn, sys, s, nsteps, rig, rep, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    type(spd_factor_t), intent(inout), target :: s
    integer, intent(in) :: nsteps
    real(dp), intent(in) :: rig(:, :)
    type(report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(spd_factor_t), target :: f
    type(spd_factor_t), pointer :: op
    integer, allocatable :: body(:)
    logical, allocatable :: free(:, :)
    real(dp), allocatable :: x(:), mx(:), kx(:), mrig(:, :), fval(:)
    real(dp) :: lam, lam_old, xmx, sigma
    integer :: it, n, k
    stat = STAT_OK
    n = sys%dofs%neq
    if (rep%f_high > 0.0_dp) then
      sigma = SIGMA_REL * (2.0_dp * PI * rep%f_high)**2
    else
      sigma = SIGMA_REL * 4.0_dp / rep%h**2
    end if
    ! A factorization of F where it costs at most FACTOR_SHARE of the run's solves (the S
    ! factor's cost ratio, CHOLMOD's flop counts); else S itself: an upper bound where h << T_1,
    ! exact where it matters (h near or above T_1, where 4/h² no longer dwarfs ω_1²).
    rep%shifted = s%cost_ratio() * s%solve_flops() <= max(FACTOR_SHARE * nsteps * s%solve_flops(), FACTOR_FLOOR)
    op => s
    if (rep%shifted) then
      fval = sys%ops%kval + sigma * sys%ops%mval
      call f%factorize(sys%ops%pat, fval, stat, errmsg)
      if (stat /= STAT_OK) then                 ! (not positive definite: a DOF with neither mass nor stiffness)
        stat = STAT_OK
        call f%destroy()
        return
      end if
      op => f
    end if
    call equation_bodies(scn, sys%dofs%eqn, n, body)
    call body_rigid_freedom(scn, sys%dofs%eqn, free)
    allocate (x(n), mx(n), kx(n), mrig(n, size(rig, 2)))
    do k = 1, size(rig, 2)
      call mass_times(sys, rig(:, k), mrig(:, k))
    end do
    call start_vector(x)
    call remove_rigid(body, free, rig, mrig, x)
    lam_old = huge(1.0_dp)
    lam = -1.0_dp
    do it = 1, merge(LOW_ITER, LOW_ITER_S, rep%shifted)
      call mass_times(sys, x, mx)
      call op%solve(mx, x, stat, errmsg)
      if (stat /= STAT_OK) exit
      call remove_rigid(body, free, rig, mrig, x)
      call mass_times(sys, x, mx)
      xmx = dot_product(x, mx)
      if (.not. (xmx > 0.0_dp)) exit             ! nothing but rigid motion
      call sys%ops%pat%matvec(sys%ops%kval, x, kx)
      lam = max(dot_product(x, kx), 0.0_dp) / xmx
      x = x / sqrt(xmx)
      if (abs(lam - lam_old) <= LOW_RTOL * lam) then
        rep%low_converged = .true.
        exit
      end if
      lam_old = lam
    end do
    if (rep%shifted) call f%destroy()
    if (stat /= STAT_OK) return
    if (lam >= 0.0_dp) rep%f_low = sqrt(lam) / (2.0_dp * PI)
  end subroutine lowest

  !> x <- x minus its M-projection on each body's free rigid modes (body_rigid_freedom).
  subroutine remove_rigid(body, free, rig, mrig, x)
    integer, intent(in) :: body(:)
    logical, intent(in) :: free(:, :)
    real(dp), intent(in) :: rig(:, :), mrig(:, :)
    real(dp), intent(inout) :: x(:)
    real(dp), allocatable :: g(:, :, :), p(:, :), a(:, :)
    real(dp) :: gb(6, 6), lam(6), work(64), c
    integer :: nb, i, k, l, b, info, nm
    nb = size(free, 2)
    nm = size(rig, 2)                            ! (3 in 2D, 6 in 3D)
    allocate (g(nm, nm, nb), p(nm, nb), a(nm, nb))
    g = 0.0_dp
    p = 0.0_dp
    do i = 1, size(x)
      b = body(i)
      if (b <= 0) cycle
      do k = 1, nm
        if (.not. free(k, b)) cycle
        p(k, b) = p(k, b) + mrig(i, k) * x(i)
        do l = 1, nm
          if (free(l, b)) g(k, l, b) = g(k, l, b) + rig(i, k) * mrig(i, l)
        end do
      end do
    end do
    a = 0.0_dp
    do b = 1, nb
      if (.not. any(free(1:nm, b))) cycle
      gb(1:nm, 1:nm) = g(:, :, b)
      call dsyev('V', 'U', nm, gb, 6, lam, work, size(work), info)
      if (info /= 0) cycle
      do l = 1, nm                               ! pseudo-inverse: dependent modes (a lone node) dropped
        if (.not. (lam(l) > 1.0e-12_dp * maxval(lam(1:nm)))) cycle
        c = dot_product(gb(1:nm, l), p(1:nm, b)) / lam(l)
        a(1:nm, b) = a(1:nm, b) + c * gb(1:nm, l)
      end do
    end do
    do i = 1, size(x)
      b = body(i)
      if (b <= 0) cycle
      do k = 1, nm
        if (free(k, b)) x(i) = x(i) - a(k, b) * rig(i, k)
      end do
    end do
  end subroutine remove_rigid

  !> A start vector with a component on every mode (deterministic).
  pure subroutine start_vector(x)
    real(dp), intent(out) :: x(:)
    integer :: i
    do i = 1, size(x)
      x(i) = 1.0_dp + 0.5_dp * sin(1.7_dp * i)
    end do
  end subroutine start_vector

  !> The report on stdout, a line at a time (say: checked writes).
  subroutine say_report(scn, rep)
    type(scene_t), intent(in) :: scn
    type(report_t), intent(in) :: rep
    character(len=:), allocatable :: txt
    integer :: im
    call say('  mass ' // fmt(rep%total_mass) // ' kg')
    txt = '  natural frequencies (estimates): highest '
    if (rep%f_high > 0.0_dp) then
      txt = txt // fmt(rep%f_high) // ' Hz (ω h = ' // fmt(2.0_dp * PI * rep%f_high * rep%h) // ')'
    else if (rep%f_high == 0.0_dp) then
      txt = txt // 'none (no stiffness)'
    else
      txt = txt // 'unbounded (a degree of freedom without mass)'
    end if
    txt = txt // ', lowest '
    if (rep%f_low > 0.0_dp) then
      txt = txt // fmt(rep%f_low) // ' Hz (period ' // fmt(1.0_dp / rep%f_low) // ' s, ' // &
        fmt(1.0_dp / (rep%f_low * rep%h)) // ' steps' // trim(merge('                ', &
        '; an upper bound', rep%low_converged)) // ')'
    else
      txt = txt // 'none (rigid motion only)'
    end if
    call say(txt // '; report ' // fmt(rep%cpu) // ' s CPU')
    do im = 1, size(scn%models)                  ! (one line a model: nothing cut)
      txt = '  MODEL ' // scn%models(im)%group // ': mass ' // fmt(rep%model_mass(im)) // ' kg'
      if (rep%wave(im) > 0.0_dp .and. rep%chdx(2, im) > 0.0_dp) txt = txt // ', wave speed ' // fmt(rep%wave(im)) // &
        ' m/s, c h/dx ' // fmt(rep%chdx(1, im)) // ' to ' // fmt(rep%chdx(2, im))
      if (scn%models(im)%sec%axisymmetric) txt = txt // ' (axisymmetric: the whole ring)'
      call say(txt)
    end do
    do im = 1, scn%mesh%nngroup              ! the supports AXISYMMETRIC put on the axis (scene_models)
      if (index(scn%mesh%ngroups(im)%name, '(axis of ') /= 1) cycle
      call say('  ' // str(size(scn%mesh%ngroups(im)%items)) // ' nodes on the axis (x = 0) of ' // &
        scn%mesh%ngroups(im)%name(10:len(scn%mesh%ngroups(im)%name) - 1) // ': u_r = UX = 0 imposed')
    end do
  end subroutine say_report

  !> The warnings of the report ('' entries are none): a step longer than the lowest period, a
  !> wave speed outside WAVE_MIN .. WAVE_MAX m/s.
  function report_warnings(scn, rep) result(w)
    type(scene_t), intent(in) :: scn
    type(report_t), intent(in) :: rep
    character(len=:), allocatable :: w
    integer :: im
    w = ''
    if (rep%f_low > 0.0_dp) then
      if (rep%h > 1.0_dp / rep%f_low) w = w // 'TIME STEP ' // fmt(rep%h) // ' s is longer than the lowest natural ' // &
        'period, ' // fmt(1.0_dp / rep%f_low) // ' s (' // fmt(rep%f_low) // ' Hz): the run cannot follow any ' // &
        'vibration of the structure' // new_line('a')
    end if
    do im = 1, size(scn%models)
      if (.not. (rep%wave(im) > 0.0_dp)) cycle
      if (rep%wave(im) < WAVE_MIN .or. rep%wave(im) > WAVE_MAX) w = w // 'MODEL ' // scn%models(im)%group // &
        ': wave speed ' // fmt(rep%wave(im)) // ' m/s, outside 10 to 20 000 m/s: check the units (YOUNG in Pa, ' // &
        'DENSITY in kg/m3)' // new_line('a')
      if (tri3_locks(scn, im)) w = w // 'MODEL ' // scn%models(im)%group // ': ' // &
        trim(merge('TRI3 in plane strain', 'TET4                ', scn%models(im)%etype == ET_TRI3)) // ' locks under ' // &
        'isochoric flow or a nearly incompressible law (its one point must keep its volume; FORMULATION BBAR has ' // &
        'nothing to average there): mesh with QUAD4 or HEX8, which take BBAR, or TRI6 (docs/locking.md)' // new_line('a')
    end do
  end function report_warnings

  !> Model im is TRI3 in plane strain or TET4 with a law that keeps the volume (law_nearly_isochoric).
  logical function tri3_locks(scn, im)
    type(scene_t), intent(in) :: scn
    integer, intent(in) :: im
    tri3_locks = .false.
    if ((scn%models(im)%etype /= ET_TRI3 .and. scn%models(im)%etype /= ET_TET4) .or. scn%models(im)%material == 0) return
    if (scn%models(im)%sec%plane_stress) return
    tri3_locks = law_nearly_isochoric(scn%materials(scn%models(im)%material))
  end function tri3_locks

  !> x with 4 significant digits: 12.35, 0.01235, 1235, 1.235e+07.
  function fmt(x) result(s)
    real(dp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: buf
    integer :: e, d
    if (x == 0.0_dp) then
      s = '0'
      return
    end if
    e = floor(log10(abs(x)))
    e = floor(log10(abs(anint(x / 10.0_dp**(e - 3)) * 10.0_dp**(e - 3))))   ! (after rounding to 4 digits)
    if (e >= 5 .or. e < -3) then
      write (buf, '(es10.3e2)') x
      s = trim(adjustl(buf))
      return
    end if
    d = max(3 - e, 0)
    if (d == 0) then
      write (buf, '(i0)') nint(x)
    else
      write (buf, '(f0.' // achar(48 + d) // ')') x
    end if
    s = trim(adjustl(buf))
    if (s(1:1) == '.') s = '0' // s
    if (len(s) > 1) then
      if (s(1:2) == '-.') s = '-0' // s(2:)
    end if
  end function fmt
end module scene_report
