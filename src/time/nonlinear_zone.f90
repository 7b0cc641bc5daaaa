!> The nonlinear zone of eq (9)'s iteration (SCHEME ZONE, issue 14): model only what the scene
!> requires, in the solver too. Write the internal forces as K0 u plus what the nonlinear
!> elements add, q(u), nonzero only on Z, the equations of the nonlinear elements (laws that are
!> not linear elastic, KINEMATICS LARGE). With S = K0 + 4M/h² (+ 2C/h) and W = S⁻¹ P_Z (the
!> columns of S⁻¹ at Z, computed once per factorization), every iterate of eq (9) is
!>     du = a + W y,   a = S⁻¹ r(0) (one solve per step),
!> and its residual is zero off Z (to round-off): r = P_Z ρ, with ρ the residual's Z rows. So
!> the iteration runs on Z: the elements touching Z evaluated at du on their equations (Z'),
!> ρ from Z's rows of eq (9), and y += ρ (ELASTIC: du += S⁻¹ r) or y += (I + D W_Z)⁻¹ ρ with
!> D = Kt - K0 on Z × Z (TANGENT and AUTO: Newton, S + P_Z D P_Z' inverted by Woodbury's
!> identity, no refactorization; where its dense LU is costly, kept over the iterates while they
!> contract). With contact rows (or IMPOSE) every iterate also takes the multipliers of the contact
!> solve, du = a + W y + S⁻¹C'Λ, and the zone iterates with S. The converged du is formed once
!> on all equations. In exact
!> arithmetic these are the iterates of the whole-system iteration; docs/nonlinear-performance.md
!> ("The nonlinear zone") measures what it saves and where it stops paying.
module nonlinear_zone
  use kinds, only: dp
  use errors, only: STAT_OK, str
  use scene, only: scene_t
  use assembly, only: system_t
  use internal_forces, only: internal_force
  use spd_factor, only: spd_factor_t
  use step_state, only: step_state_t
  use lapack_pure, only: dgetrf, dgetrs
  implicit none
  private
  public :: zone_t

  !> SCHEME ZONE's choices, as scene_t%zone holds them (the order of scene_run's get_choice).
  integer, parameter :: ZONE_AUTO = 1, ZONE_OFF = 3
  !> AUTO's cost model, in flops per step of ITERATIONS iterations (docs/nonlinear-performance.md,
  !> "The nonlinear zone", where it is checked against measured steps): the zone's, per iteration
  !> its rows of W (2 nz nz'), its elements (ELEMENT_FLOPS each) and Newton's G = I + D W_Z with
  !> its LU (4 nz per entry of D, 2/3 nz³ at DENSE_SPEEDUP times the flop rate of the sparse work:
  !> LAPACK's blocked LU; once per step where it is kept over the iterates), plus the final du
  !> (2 n nz); the whole system's, per iteration a solve (4 nnz(L), CHOLMOD's analysis) and an
  !> element loop (ELEMENT_FLOPS per element). The same count of iterations for both (the whole system's
  !> iteration with S in fact needs more than Newton's on the zone). And Z at most half the
  !> equations: the zone is for a part of the model.
  real(dp), parameter :: ITERATIONS = 3.0_dp, DENSE_SPEEDUP = 4.0_dp, ELEMENT_FLOPS = 1000.0_dp
  !> W at most 2.5e7 entries (200 MB), whatever ZONE says.
  integer(8), parameter :: MAX_W_ENTRIES = 25000000_8

  type :: zone_t
    private
    logical, public :: on = .false.
    character(len=:), allocatable, public :: why   !< the decision, for the run's stdout
    integer, public :: nz = 0                      !< equations in Z
    integer :: n = 0, nzp = 0
    integer, allocatable :: eqs(:)                 !< Z
    integer, allocatable :: eqp(:)                 !< Z': the equations of the elements touching Z
    integer, allocatable :: elist(:)               !< the elements touching Z
    integer, allocatable :: row_ptr(:), row_col(:), row_k(:)   !< Z's rows of the pattern (column, entry)
    integer, allocatable :: zz_k(:), zz_i(:), zz_j(:)          !< entries with row and column in Z
    integer, allocatable :: pp_k(:)                !< entries with row and column in Z' (the tangent's)
    real(dp), allocatable :: wt(:, :)              !< (nz, n): wt(:, i) is row i of W
    real(dp), allocatable :: wzt(:, :)             !< W_Zᵀ = (P_Z' W)ᵀ (nz, nz): wzt(:, j) is row j of W_Z
    real(dp), allocatable :: g(:, :), rho(:), y(:), dy(:), e(:), x(:)
    integer, allocatable :: ipiv(:)
    logical :: newton = .false.                    !< Newton on the zone (TANGENT, AUTO; no contact rows)
    logical :: lu_cheap = .true.                   !< G's LU costs no more than an iteration: at every iterate
    logical :: have_lu = .false.                   !< G's LU of this step is in g, ipiv
    logical, public :: contact = .false.           !< contact rows (or IMPOSE): du comes from the contact solve
    real(dp), allocatable, public :: dfree(:)      !< with contact: the free iterate a + W y on every equation
  contains
    procedure :: build => zone_build
    procedure :: columns => zone_columns
    procedure :: begin_step => zone_begin_step
    procedure :: trial => zone_trial
    procedure :: residual => zone_residual
    procedure :: update => zone_update
    procedure :: full_du => zone_full_du
    procedure :: free_du => zone_free_du
    procedure :: uses_tangent => zone_uses_tangent
    procedure :: newton_on => zone_newton_on
  end type zone_t

contains

  !> Decide whether the iteration runs on the zone (SCHEME ZONE ON, or AUTO where the cost model
  !> above says it pays; not with PRECISION EXTENDED, whose quadruple-precision residual is the
  !> whole system's) and build its maps.
  subroutine zone_build(self, scn, sys, solve_flops)
    class(zone_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: solve_flops          !< of S's factor (CHOLMOD's analysis)
    logical, allocatable :: inz(:), inp(:), touch(:)
    logical :: pays
    integer :: e, k, j, n
    self%on = .false.
    n = sys%dofs%neq
    self%n = n
    if (sys%elems%linear) then
      self%why = 'linear'
      return
    else if (scn%zone == ZONE_OFF) then
      self%why = 'off (SCHEME ZONE OFF)'
      return
    else if (scn%extended) then
      self%why = 'off (PRECISION EXTENDED)'
      return
    else if (sys%loads%fol%n > 0) then
      ! (A follower pressure changes F(n+1) with the iterate: the zone's residual is not written for it.)
      self%why = 'off (a PRESSURE follows a KINEMATICS LARGE model)'
      return
    end if
    allocate (inz(n), inp(n), touch(scn%mesh%nelem))
    inz = .false.
    do e = 1, scn%mesh%nelem
      if (scn%elem_model(e) == 0) cycle
      if (sys%elems%model_linear(scn%elem_model(e))) cycle
      call mark(e, inz)
    end do
    self%nz = count(inz)
    if (self%nz == 0) then
      self%why = 'off (the nonlinear elements have no free equation)'
      return
    else if (int(self%nz, 8) * n > MAX_W_ENTRIES) then
      self%why = 'off (the S^-1 columns would be too large: ' // str(self%nz) // ' x ' // str(n) // ')'
      return
    end if
    ! The elements touching Z and their equations Z'.
    inp = .false.
    touch = .false.
    do e = 1, scn%mesh%nelem
      if (scn%elem_model(e) == 0) cycle
      do k = sys%elems%edof_ptr(e), sys%elems%edof_ptr(e + 1) - 1
        j = sys%elems%edof(k)
        if (j > 0) touch(e) = touch(e) .or. inz(j)
      end do
      if (touch(e)) call mark(e, inp)
    end do
    self%eqs = pack([(j, j = 1, n)], inz)
    self%eqp = pack([(j, j = 1, n)], inp)
    self%elist = pack([(e, e = 1, scn%mesh%nelem)], touch)
    self%nzp = size(self%eqp)
    ! With contact rows (or IMPOSE) the multipliers are solved with S's Schur complement, so the
    ! zone iterates with S too (its iterates are then the whole system's ELASTIC ones, each also
    ! forming the free du on every equation for the contact solve).
    self%contact = size(scn%conditions) > 0 .or. size(scn%imposes) > 0
    self%newton = allocated(sys%ops%tval) .and. .not. self%contact
    call pattern_maps(self, sys, inz, inp)
    ! (zone_pays also sets lu_cheap, which ZONE ON needs too: called whatever ZONE says.)
    pays = zone_pays(self, count(scn%elem_model > 0), solve_flops)
    if (scn%zone == ZONE_AUTO .and. 2 * self%nz > n) then
      self%why = 'off (AUTO: ' // str(self%nz) // ' of ' // str(n) // ' equations nonlinear, more than half the model)'
      return
    else if (scn%zone == ZONE_AUTO .and. .not. pays) then
      self%why = 'off (AUTO: ' // str(self%nz) // ' of ' // str(n) // ' equations nonlinear, an iteration on them would ' // &
        'cost more than on the whole)'
      return
    end if
    allocate (self%wt(self%nz, n), self%wzt(self%nz, self%nz), self%g(self%nz, self%nz), &
      self%rho(self%nz), self%y(self%nz), self%dy(self%nz), self%e(n), self%x(n), self%ipiv(self%nz))
    if (self%contact) allocate (self%dfree(n))
    self%on = .true.
    self%why = str(self%nz) // ' of ' // str(n) // ' equations, ' // str(size(self%elist)) // ' elements'
  contains
    subroutine mark(el, flag)
      integer, intent(in) :: el
      logical, intent(inout) :: flag(:)
      integer :: kk, jj
      do kk = sys%elems%edof_ptr(el), sys%elems%edof_ptr(el + 1) - 1
        jj = sys%elems%edof(kk)
        if (jj > 0) flag(jj) = .true.
      end do
    end subroutine mark
  end subroutine zone_build

  !> AUTO's cost model (above) for this zone of nelem elements in all: true when the zone's step
  !> costs fewer flops than the whole system's. Sets lu_cheap (G's LU at every iterate).
  logical function zone_pays(self, nelem, solve_flops)
    type(zone_t), intent(inout) :: self
    integer, intent(in) :: nelem
    real(dp), intent(in) :: solve_flops
    real(dp) :: zone_flops, full_flops, lu_flops
    zone_flops = 2.0_dp * self%nz * self%nzp
    if (self%contact) zone_flops = zone_flops + 2.0_dp * self%nz * real(self%n, dp)
    ! G = I + D W_Z (4 nz flops per entry of D) and its LU.
    lu_flops = 2.0_dp / 3.0_dp * real(self%nz, dp)**3 / DENSE_SPEEDUP + 4.0_dp * real(self%nz, dp) * size(self%zz_k)
    zone_flops = zone_flops + ELEMENT_FLOPS * size(self%elist)
    self%lu_cheap = lu_flops <= zone_flops
    if (self%newton .and. self%lu_cheap) zone_flops = zone_flops + lu_flops
    zone_flops = ITERATIONS * zone_flops + 2.0_dp * self%nz * real(self%n, dp)
    ! (A costly LU is kept over the step's iterates: counted once per step.)
    if (self%newton .and. .not. self%lu_cheap) zone_flops = zone_flops + lu_flops
    full_flops = ITERATIONS * (solve_flops + ELEMENT_FLOPS * nelem)
    zone_pays = zone_flops <= full_flops
  end function zone_pays

  !> From the symmetric pattern (upper triangle by columns): Z's full rows (entry, column as a
  !> position in Z'), the Z × Z entries, the Z' × Z' entries.
  subroutine pattern_maps(self, sys, inz, inp)
    type(zone_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    logical, intent(in) :: inz(:), inp(:)
    integer, allocatable :: zpos(:), ppos(:), cnt(:)
    integer :: i, j, k, nrow, nzz, npp, pass
    allocate (zpos(self%n), ppos(self%n), cnt(self%nz + 1))
    zpos = 0
    ppos = 0
    zpos(self%eqs) = [(i, i = 1, self%nz)]
    ppos(self%eqp) = [(i, i = 1, self%nzp)]
    do pass = 1, 2
      cnt = 0
      nzz = 0
      npp = 0
      do j = 1, sys%ops%pat%n
        do k = sys%ops%pat%colptr(j), sys%ops%pat%colptr(j + 1) - 1
          i = sys%ops%pat%rowind(k)
          if (inz(i)) call add_row(zpos(i), ppos(j), k)
          if (inz(j) .and. i /= j) call add_row(zpos(j), ppos(i), k)
          if (inz(i) .and. inz(j)) then
            nzz = nzz + 1
            if (pass == 2) then
              self%zz_k(nzz) = k
              self%zz_i(nzz) = zpos(i)
              self%zz_j(nzz) = zpos(j)
            end if
          end if
          if (inp(i) .and. inp(j)) then
            npp = npp + 1
            if (pass == 2) self%pp_k(npp) = k
          end if
        end do
      end do
      if (pass == 1) then
        allocate (self%row_ptr(self%nz + 1))
        self%row_ptr(1) = 1
        do i = 1, self%nz
          self%row_ptr(i + 1) = self%row_ptr(i) + cnt(i)
        end do
        nrow = self%row_ptr(self%nz + 1) - 1
        allocate (self%row_col(nrow), self%row_k(nrow), self%zz_k(nzz), self%zz_i(nzz), self%zz_j(nzz), self%pp_k(npp))
      end if
    end do
  contains
    subroutine add_row(zi, pcol, kk)
      integer, intent(in) :: zi, pcol, kk
      integer :: slot
      cnt(zi) = cnt(zi) + 1
      if (pass == 1) return
      slot = self%row_ptr(zi) + cnt(zi) - 1
      self%row_col(slot) = pcol
      self%row_k(slot) = kk
    end subroutine add_row
  end subroutine pattern_maps

  !> W = S⁻¹ P_Z for the factor of S (after each factorization of K0 + 4M/h², h changed).
  subroutine zone_columns(self, factor, stat, errmsg)
    class(zone_t), intent(inout) :: self
    type(spd_factor_t), intent(inout) :: factor
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: c, i
    stat = STAT_OK
    if (.not. self%on) return
    self%e = 0.0_dp
    do c = 1, self%nz
      self%e(self%eqs(c)) = 1.0_dp
      call factor%solve(self%e, self%x, stat, errmsg)
      if (stat /= STAT_OK) then
        errmsg = 'nonlinear zone: ' // errmsg
        return
      end if
      self%e(self%eqs(c)) = 0.0_dp
      self%wt(c, :) = self%x
    end do
    do i = 1, self%nz
      self%wzt(:, i) = self%wt(:, self%eqs(i))
    end do
  end subroutine zone_columns

  !> A step's iteration starts at du = a (a = S⁻¹ r(0), the caller's solve): y = 0, and no LU
  !> of G yet.
  pure subroutine zone_begin_step(self)
    class(zone_t), intent(inout) :: self
    self%y = 0.0_dp
    self%have_lu = .false.
  end subroutine zone_begin_step

  !> Whether the iteration is Newton's (TANGENT and AUTO without contact rows, unless the step
  !> fell back to S's iteration).
  pure logical function zone_newton_on(self, fallback)
    class(zone_t), intent(in) :: self
    logical, intent(in) :: fallback
    zone_newton_on = self%newton .and. .not. fallback
  end function zone_newton_on

  !> Whether the trial of iterate iter assembles the tangent (TANGENT and AUTO, unless the step
  !> fell back; res: the residual norms so far). Where G's LU costs more than an iteration it is
  !> kept over the step's iterates (a modified Newton, as AUTO keeps S) and taken afresh only when
  !> the last iterate contracted the residual by less than REFRESH.
  pure logical function zone_uses_tangent(self, fallback, res, iter)
    class(zone_t), intent(in) :: self
    logical, intent(in) :: fallback
    real(dp), intent(in) :: res(:)
    integer, intent(in) :: iter
    real(dp), parameter :: REFRESH = 0.1_dp
    zone_uses_tangent = zone_newton_on(self, fallback)
    if (.not. zone_uses_tangent .or. self%lu_cheap .or. .not. self%have_lu .or. iter < 3) return
    zone_uses_tangent = res(iter - 1) > REFRESH * res(iter - 2)
  end function zone_uses_tangent

  !> The iterate du = a + W y on Z' (a in st%ddu; with contact rows du is the contact solve's,
  !> already in st%du), its trial state: the elements touching Z (their fint, fcorr and, with
  !> tangent, tangent entries; Z' rows zeroed first).
  subroutine zone_trial(self, scn, sys, st, tangent)
    class(zone_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    type(step_state_t), intent(inout) :: st
    logical, intent(in) :: tangent
    integer :: p, i
    do p = 1, self%nzp
      i = self%eqp(p)
      if (.not. self%contact) st%du(i) = w_row(self%wt, self%y, st%ddu, i)
      st%utrial(i) = st%u(i) + st%du(i)
      st%fint(i) = 0.0_dp
      st%fcorr(i) = 0.0_dp
    end do
    if (tangent) sys%ops%tval(self%pp_k) = 0.0_dp
    ! (The Jacobian's antisymmetric part, which the zone's Newton leaves out: its entries of Z' are
    ! formed afresh too, so that aval stays the tangent's.)
    if (tangent .and. allocated(sys%ops%aval)) sys%ops%aval(self%pp_k) = 0.0_dp
    call internal_force(scn, sys, st%utrial, st%fint, st%fcorr, scn%energy_correction, tangent, st%inc, un=st%u, &
      elist=self%elist)
  end subroutine zone_trial

  !> du(i) = a(i) + Σ_c W(i, c) y(c): the one formula for Z' and for the whole (bit for bit the
  !> same on Z', so the converged state is the one the iteration judged).
  pure real(dp) function w_row(wt, y, a, i)
    real(dp), intent(in) :: wt(:, :), y(:), a(:)
    integer, intent(in) :: i
    integer :: c
    w_row = 0.0_dp
    do c = 1, size(y)
      w_row = w_row + wt(c, i) * y(c)
    end do
    w_row = a(i) + w_row
  end function w_row

  !> du = a + W y on every equation.
  pure subroutine w_all(wt, y, a, du)
    real(dp), intent(in) :: wt(:, :), y(:), a(:)
    real(dp), intent(out) :: du(:)
    integer :: i
    do i = 1, size(du)
      du(i) = w_row(wt, y, a, i)
    end do
  end subroutine w_all

  !> ρ = Z's rows of eq (9)'s residual, rhs - 4/h² (M du + h/2 C du) - Bσ(n+1) - Bσc (into st%r
  !> at Z) with the contact forces C'Λ on the right (in self%rho: zero off Z); returns its norm,
  !> its work on du (r·du: zero off Z), the step's exchanged work (on Z; with contact rows, where
  !> du is known everywhere, on the whole model), ‖du_Z‖, and Σ_Z (Bσ(n+1)² - Bσ(n)²) for the
  !> force scale.
  subroutine zone_residual(self, sys, st, rnorm, rwork, work, dunorm, dfint2, contact_force)
    class(zone_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    type(step_state_t), intent(inout) :: st
    real(dp), intent(out) :: rnorm, rwork, work, dunorm, dfint2
    real(dp), intent(in), optional :: contact_force(:)   !< C'Λ on every equation
    real(dp) :: m, c, wf, wi
    integer :: z, i, s, j
    logical :: damped
    damped = allocated(sys%ops%cval)
    rwork = 0.0_dp
    wf = 0.0_dp
    wi = 0.0_dp
    dunorm = 0.0_dp
    dfint2 = 0.0_dp
    do z = 1, self%nz
      i = self%eqs(z)
      m = 0.0_dp
      c = 0.0_dp
      do s = self%row_ptr(z), self%row_ptr(z + 1) - 1
        j = self%eqp(self%row_col(s))
        m = m + sys%ops%mval(self%row_k(s)) * st%du(j)
        if (damped) c = c + sys%ops%cval(self%row_k(s)) * st%du(j)
      end do
      if (damped) m = m + (0.5_dp * st%h) * c
      self%rho(z) = st%rhs(i) - st%c4 * m - st%fint(i) - st%fcorr(i)
      st%r(i) = self%rho(z)
      if (present(contact_force)) self%rho(z) = self%rho(z) + contact_force(i)
      rwork = rwork + self%rho(z) * st%du(i)
      wf = wf + st%du(i) * (st%f_n(i) + st%f_np1(i))
      wi = wi + st%du(i) * (st%fint_n(i) + st%fint(i) + st%fcorr(i))
      dunorm = dunorm + st%du(i)**2
      dfint2 = dfint2 + st%fint(i)**2 - st%fint_n(i)**2
    end do
    if (self%contact) then
      ! du is known on every equation (the contact solve's): the external work and, off Z
      ! (linear elements), the internal work to first order, du·2Bσ(n), over the whole model.
      wf = 0.0_dp
      do i = 1, self%n
        wf = wf + st%du(i) * (st%f_n(i) + st%f_np1(i))
        wi = wi + 2.0_dp * st%du(i) * st%fint_n(i)
      end do
      do z = 1, self%nz
        i = self%eqs(z)
        wi = wi - 2.0_dp * st%du(i) * st%fint_n(i)
      end do
    end if
    rnorm = norm2(self%rho)
    rwork = abs(rwork)
    work = 0.5_dp * (abs(wf) + abs(wi))
    dunorm = sqrt(dunorm)
  end subroutine zone_residual

  !> The next iterate: y += ρ (S's iteration), or Newton with S + P_Z D P_Z' (Woodbury):
  !> y += (I + D W_Z)⁻¹ ρ, D = Kt - K0 on Z × Z, G = I + D W_Z factorized afresh when the tangent
  !> was assembled at this iterate (tangent), else G's LU of an earlier iterate of the step.
  !> newton_ok = .false. when G is singular or not finite, or there is no LU (then y += ρ).
  subroutine zone_update(self, sys, newton, tangent, newton_ok)
    class(zone_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    logical, intent(in) :: newton, tangent
    logical, intent(out) :: newton_ok
    integer :: info
    newton_ok = .false.
    if (newton .and. tangent) call factor_g(self, sys)
    if (newton .and. self%have_lu) then
      self%dy = self%rho
      call dgetrs('T', self%nz, 1, self%g, self%nz, self%ipiv, self%dy, self%nz, info)
      newton_ok = info == 0
    end if
    if (newton_ok) then
      self%y = self%y + self%dy
    else
      self%y = self%y + self%rho
    end if
  end subroutine zone_update

  !> G = I + D W_Z from D's entries (as sparse as the zone's elements: no dense product), and its
  !> LU (of Gᵀ); have_lu unless G is singular (a pivot below eps max|G|) or not finite.
  subroutine factor_g(self, sys)
    type(zone_t), intent(inout) :: self
    type(system_t), intent(in) :: sys
    integer :: k, info, i, j
    real(dp) :: gmax, dij
    ! Gᵀ = I + W_Zᵀ D (D symmetric) by columns: column i of Gᵀ gathers D(j, i) times column j of
    ! W_Zᵀ, both contiguous; solved transposed below.
    self%g = 0.0_dp
    do i = 1, self%nz
      self%g(i, i) = 1.0_dp
    end do
    do k = 1, size(self%zz_k)
      dij = sys%ops%tval(self%zz_k(k)) - sys%ops%kval(self%zz_k(k))
      if (dij == 0.0_dp) cycle
      i = self%zz_i(k)
      j = self%zz_j(k)
      self%g(:, i) = self%g(:, i) + dij * self%wzt(:, j)
      if (i /= j) self%g(:, j) = self%g(:, j) + dij * self%wzt(:, i)
    end do
    gmax = maxval(abs(self%g))
    self%have_lu = .false.
    if (.not. (gmax <= huge(1.0_dp))) return
    call dgetrf(self%nz, self%nz, self%g, self%nz, self%ipiv, info)
    if (info /= 0) return
    do i = 1, self%nz
      if (.not. (abs(self%g(i, i)) > epsilon(1.0_dp) * gmax)) return
    end do
    self%have_lu = .true.
  end subroutine factor_g

  !> With contact rows: the free iterate a + W y on every equation (a in st%ddu), into dfree.
  subroutine zone_free_du(self, st)
    class(zone_t), intent(inout) :: self
    type(step_state_t), intent(in) :: st
    call w_all(self%wt, self%y, st%ddu, self%dfree)
  end subroutine zone_free_du

  !> The converged iterate on every equation: du = a + W y (a in ddu).
  subroutine zone_full_du(self, st)
    class(zone_t), intent(in) :: self
    type(step_state_t), intent(inout) :: st
    call w_all(self%wt, self%y, st%ddu, st%du)
  end subroutine zone_full_du
end module nonlinear_zone
