!> STATIC (docs/input.md, "Static preload"): the structure at rest under the loads and gravity of
!> the start time before the dynamics. The loads are applied in STEPS equal increments; each is
!> solved by Newton on the static residual r = F - Bσ(u) - C'Λ with the laws along the increment
!> (plasticity, LARGE), the contact conditions as exact multipliers (the LCP of the step solver,
!> unilateral, with S the static tangent) and the tangent refactorized at each iterate.
!>
!> A rigid mode of a body that no support holds must be held by contact conditions (a beam lying
!> on the ground): the tangent is then singular along it, and the iteration matrix is Kt + εM with
!> ε = 1e-8 × the mean Σdiag K / Σdiag M. The shift only shapes the iterates; the converged state
!> solves the static equations (the residual has no inertia). A mode held by nothing is bad input,
!> named. The increments commit the laws' states; their work (Σ W_N at the nonlinear points) and
!> the loads' trapezoid work are reported, and the dynamics books the stored energy as its
!> initial internal energy, so its balance starts at zero.
module static_preload
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str
  use scene, only: scene_t, condition_row, condition_tangent, COND_NODES
  use scene_helpers, only: model_size
  use assembly, only: system_t, external_force, commit_state
  use internal_forces, only: internal_force, work_increment_t
  use dof_map, only: equation_bodies, body_rigid_freedom
  use spd_factor, only: spd_factor_t
  use contact, only: contact_set_t, contact_prepare, contact_solve_step, contact_add_force, contact_gaps, &
    contact_set_resting, contact_schur_only
  use dense_solve, only: spsd_solve
  use contact_geometry, only: following_t
  use newmark_step, only: residual_history
  implicit none
  private
  public :: static_report_t, static_solve

  !> What the preload did (stdout of the run).
  type :: static_report_t
    integer :: increments = 0
    integer :: iterations = 0            !< Newton iterations over all increments
    integer :: factorizations = 0
    real(dp) :: residual = 0.0_dp        !< the last increment's |r + C'Λ| / force scale
    real(dp) :: work_loads = 0.0_dp      !< Σ ½ Δu'(F(k-1) + F(k)) over the increments
    real(dp) :: work_internal = 0.0_dp   !< Σ W_N at the nonlinear points (their stored + dissipated work)
    real(dp) :: dissipated = 0.0_dp      !< plastic work of the preload
    real(dp) :: contact_force = 0.0_dp   !< Σ Λ of the contact conditions at equilibrium
    logical :: shifted = .false.         !< some rigid mode was held by contact only (Kt + εM)
  end type static_report_t

  !> The rigid modes in model_modes' order: 2D x, y, the rotation; 3D then z and the rotations about x and y.
  character(len=*), parameter :: MODE_NAMES(6) = [character(len=25) :: 'free translation along x', &
    'free translation along y', 'free rotation about z', 'free translation along z', 'free rotation about x', &
    'free rotation about y']

contains

  !> The static equilibrium under the loads at scn%t_start from u (in: the initial displacement;
  !> out: the equilibrium), the laws' states committed. rig: the rigid modes on the free
  !> equations (translations x, y, rotation about the origin). With cs, the contact conditions
  !> (their multipliers in lam on return, and the set left holding them: contact_set_resting);
  !> the caller prepares cs again with the dynamics' matrix. Bad input (a free rigid mode) is
  !> STAT_INPUT, an increment that does not converge STAT_RUN with its residuals.
  subroutine static_solve(scn, sys, u, rig, rep, stat, errmsg, cs, lam, follow)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(inout) :: sys
    real(dp), intent(inout) :: u(:)
    real(dp), intent(in) :: rig(:, :)
    type(static_report_t), intent(out) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(contact_set_t), intent(inout), optional :: cs
    real(dp), intent(inout), optional :: lam(:)
    !> rows that follow the configuration (curved obstacles, GAP … SEGMENTS PAIRING STEP): linearized
    !> at each iterate, the contact solved about it (Newton on the gaps)
    type(following_t), intent(inout), optional :: follow
    type(spd_factor_t) :: fac
    type(work_increment_t) :: inc
    real(dp), allocatable :: f(:), fprev(:), fint(:), fcorr(:), r(:), du(:), ddu(:), un(:), sval(:), res(:), uk(:), &
      dcorr(:)
    real(dp) :: eps_m, kappa, s, fscale, lscale
    integer :: k, it, n, nc
    logical :: conv, tangent, constant, moving, refactor
    logical, allocatable :: held(:), held_f(:)

    n = sys%dofs%neq
    call fac%choose(scn%linear_solver, scn%out_of_core)      ! (SCHEME SOLVER)
    call held_modes_check(scn, sys, rig, rep%shifted, stat, errmsg, cs)
    if (stat /= STAT_OK) return
    eps_m = 0.0_dp
    kappa = 0.0_dp
    call shifts(sys, eps_m, kappa)               ! (κ also for IMPOSE's rows)
    if (.not. rep%shifted) eps_m = 0.0_dp
    nc = size(scn%conditions)
    allocate (held(nc), held_f(nc))
    if (present(lam)) then
      deallocate (held, held_f)
      allocate (held(size(lam)), held_f(size(lam)))    ! the conditions, then IMPOSE's rows
    end if
    held_f = .false.
    allocate (f(n), fprev(n), fint(n), fcorr(n), r(n), du(n), ddu(n), un(n), res(scn%static_max_iter), uk(n), dcorr(n))
    moving = .false.
    if (present(follow) .and. present(cs)) moving = follow%count() > 0
    lscale = max(model_size(scn%mesh), maxval(abs(scn%mesh%x(:, 1:scn%mesh%nnode))), &
      maxval(scn%conditions%radius, mask=scn%conditions%curved /= 0))
    if (.not. lscale > 1.0e3_dp * tiny(1.0_dp)) lscale = 1.0_dp   ! (a single node at the origin: no length)
    tangent = allocated(sys%ops%tval)
    constant = .not. tangent .and. .not. moving  ! linear elastic: K0 + εM factorized once
    if (present(cs)) call contact_schur_only(cs, .true.)
    fprev = 0.0_dp                               ! the loads grow from zero
    fscale = 1.0_dp
    if (present(lam)) lam = 0.0_dp
    do k = 1, scn%static_steps
      s = real(k, dp) / real(scn%static_steps, dp)
      un = u
      du = 0.0_dp
      conv = .false.
      do it = 1, scn%static_max_iter
        uk = un + du
        call internal_force(scn, sys, uk, fint, fcorr, .false., tangent, inc, un=un)
        call external_force(scn, sys, scn%t_start, f, uk)
        if (moving) call follow%update(scn%mesh%x, sys%dofs%eqn, uk, cs, stat, errmsg)   ! rows at the iterate
        if (stat /= STAT_OK) return
        f = s * f
        r = f - fint
        ddu = r
        if (present(cs)) call contact_add_force(cs, ddu)
        res(it) = norm2(ddu)
        fscale = max(norm2(f), norm2(fint), tiny(1.0_dp))
        rep%iterations = rep%iterations + 1
        if (.not. (res(it) <= huge(1.0_dp))) exit
        if (it > 1 .and. res(it) <= scn%static_tol * fscale) then
          conv = .true.
          exit
        end if
        ! A residual at the attainable floor (round-off of the forces, or of the stiffness times the
        ! displacement where no force loads the structure: a linear increment solved exactly;
        ! LARGE members' rounding, round_floor) stops falling: converged.
        if (it > 2 .and. res(it) <= max(1.0e3_dp * epsilon(1.0_dp) * max(fscale, kappa * maxval(abs(uk))), &
          4.0_dp * sys%elems%round_floor) .and. res(it) >= 0.5_dp * res(it - 1)) then
          conv = .true.
          exit
        end if
        ! The contacts that hold rigid modes: once the LCP has an active set, κ C_A'C_A instead of
        ! εM (the same minimizer on C_A u = g: the iterate is Newton's again).
        ! IMPOSE's rows are held always: κ c c' keeps their Schur complement C S⁻¹C' conditioned
        ! like the dynamics' (with K alone it is not: many imposed DOFs stagnated at 1e-7 of the
        ! force scale).
        held = .false.
        if (present(lam)) then
          if (rep%shifted) held(1:nc) = lam(1:nc) > 0.0_dp
          call held_rows_after(scn, nc, held)
        end if
        refactor = .not. (constant .and. fac%is_factored() .and. all(held .eqv. held_f))
        if (refactor) then
          if (moving) then
            call static_matrix(scn, sys, eps_m, kappa, held, sval, fac, rep, stat, errmsg, uk, lam)
          else
            call static_matrix(scn, sys, eps_m, kappa, held, sval, fac, rep, stat, errmsg)
          end if
          if (stat /= STAT_OK) return
          held_f = held
        end if
        if (present(cs) .and. (refactor .or. moving)) call contact_prepare(cs, fac, stat, errmsg, sys%ops%pat, sval)
        if (stat /= STAT_OK) return
        call fac%solve(r, ddu, stat, errmsg)
        if (stat /= STAT_OK) return
        if (moving) then
          ! Newton about the iterate: the gaps of the rows linearized there, g(u_k + d) >= 0
          call contact_solve_step(cs, fac, uk, ddu, dcorr, lam, stat, errmsg)
          if (stat /= STAT_OK) then
            errmsg = 'STATIC: contact: ' // errmsg
            return
          end if
          du = du + dcorr
        else if (present(cs)) then
          ddu = du + ddu
          call contact_solve_step(cs, fac, un, ddu, du, lam, stat, errmsg)
          if (stat /= STAT_OK) then
            errmsg = 'STATIC: contact: ' // errmsg
            return
          end if
        else
          du = du + ddu
        end if
        if (.not. (maxval(abs(du)) <= 1.0e3_dp * lscale)) exit   ! no equilibrium within reach
      end do
      if (.not. conv) then
        it = min(it, scn%static_max_iter)           ! (the last six residuals)
        call set_error(stat, errmsg, STAT_RUN, scn%path // ':' // str(scn%static_line) // ': STATIC: increment ' // &
          str(k) // ' of ' // str(scn%static_steps) // ' did not converge: residual ' // &
          residual_history(res(max(1, it - 5):it)) // ' against ' // str(scn%static_tol * fscale) // &
          ' (more STEPS, a larger MAX_ITERATIONS, or loads the supports and contacts cannot carry)')
        call fac%destroy()
        return
      end if
      rep%residual = res(it) / fscale
      rep%work_loads = rep%work_loads + 0.5_dp * dot_product(du, fprev + f)
      fprev = f
      u = un + du
      call commit_state(sys)
      rep%work_internal = rep%work_internal + inc%work
      rep%dissipated = rep%dissipated + inc%dissipated
      rep%increments = k
    end do
    if (present(cs)) then
      call contact_set_resting(cs, lam)
      call contact_schur_only(cs, .false.)
      rep%contact_force = sum(lam(1:nc))
    end if
    call fac%destroy()
  end subroutine static_solve

  !> S = Kt + κ Σ_held c_j c_j' when the held conditions (active, holding rigid modes) make it
  !> definite, Kt + εM otherwise (Kt: the tangent with its compressive geometric part, without it
  !> when that is not positive definite; K0 when there is no tangent), factorized.
  subroutine static_matrix(scn, sys, eps_m, kappa, held, sval, fac, rep, stat, errmsg, uk, lam)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: eps_m, kappa
    logical, intent(in) :: held(:)
    real(dp), allocatable, intent(inout) :: sval(:)
    type(spd_factor_t), intent(inout) :: fac
    type(static_report_t), intent(inout) :: rep
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), intent(in), optional :: uk(:), lam(:)   !< the iterate and the multipliers: the curved contacts' stiffness
    integer :: minor, pass
    real(dp), allocatable :: kt(:)
    if (allocated(sys%ops%tval)) then
      kt = sys%ops%tval
      if (allocated(sys%ops%gval)) kt = kt + sys%ops%gval
    else
      kt = sys%ops%kval
    end if
    if (present(uk) .and. present(lam)) call add_curvature(scn, sys, uk, lam, kt)
    do pass = 1, 4
      ! 1: with the held rows, 2: with εM; 3, 4: the same without the compressive geometric part.
      if (pass == 1 .or. pass == 3) then
        if (.not. any(held)) cycle
        sval = kt
        call add_held_rows(scn, sys, kappa, held, sval)
      else
        sval = kt + eps_m * sys%ops%mval
      end if
      call fac%factorize(sys%ops%pat, sval, stat, errmsg, minor)
      rep%factorizations = rep%factorizations + 1
      if (stat == STAT_OK) return
      if (pass == 2) then
        if (.not. allocated(sys%ops%gval)) exit
        kt = sys%ops%tval
      end if
    end do
    errmsg = 'STATIC: the tangent does not factorize (' // errmsg // '): a structure that buckles or a mechanism; more STEPS'
  end subroutine static_matrix

  !> The curved obstacles' part of the Newton matrix: -Λ ∇²g = -s Λ (I - n n')/r on the node of
  !> each active condition (g = s(|x - c| - r)), at the iterate uk: a bowl (INSIDE) holds its
  !> node along the tangent, a dome (OUTSIDE) pushes it off.
  subroutine add_curvature(scn, sys, uk, lam, kt)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: uk(:), lam(:)
    real(dp), intent(inout) :: kt(:)
    integer :: j, b, eqs(2), d
    real(dp) :: x(2), r, nn(2), ke(2, 2)
    do j = 1, size(scn%conditions)
      associate (c => scn%conditions(j))
        if (c%curved == 0 .or. lam(j) <= 0.0_dp) cycle
        b = c%node_b
        eqs = max(sys%dofs%eqn(1:2, b), 0)
        x = scn%mesh%x(:, b)
        do d = 1, 2
          if (eqs(d) > 0) x(d) = x(d) + uk(eqs(d))
        end do
        r = norm2(x - c%center)
        if (r <= 0.0_dp) cycle
        nn = (x - c%center) / r
        ke(:, 1) = [1.0_dp - nn(1)**2, -nn(1) * nn(2)]
        ke(:, 2) = [-nn(1) * nn(2), 1.0_dp - nn(2)**2]
        ke = -c%curved * lam(j) / r * ke
        call sys%ops%pat%add_element(kt, eqs, ke)
      end associate
    end do
  end subroutine add_curvature

  !> sval += κ c_j c_j' for the held conditions whose rows fit the pattern (an obstacle's node; a
  !> GAP's two nodes when an element joins them; an imposed DOF), held(j) over the contact set's
  !> rows: the conditions, then IMPOSE's rows (a row per node of each IMPOSE, in order).
  subroutine add_held_rows(scn, sys, kappa, held, sval)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: kappa
    logical, intent(in) :: held(:)
    real(dp), intent(inout) :: sval(:)
    integer :: j, k, l, eqs(3 * COND_NODES), ki, ii, nimp, jc, nt, kt
    real(dp) :: coefs(3 * COND_NODES), ke(3 * COND_NODES, 3 * COND_NODES)
    logical :: fits
    ki = 1
    ii = 0
    jc = 0
    nt = scn%mesh%ndim - 1                          ! (FRICTION's tangential rows per condition)
    nimp = size(held) - size(scn%conditions) - nt * count(scn%conditions%friction > 0.0_dp)
    kt = nt
    do j = 1, size(held)
      eqs = 0
      coefs = 0.0_dp
      if (j > size(scn%conditions) + nimp) then   ! FRICTION: the next tangent (t1, t2 in 3D) of a condition
        kt = kt + 1
        if (kt > nt) then
          kt = 1
          jc = jc + 1
          do while (scn%conditions(jc)%friction <= 0.0_dp)
            jc = jc + 1
          end do
        end if
      else if (j > size(scn%conditions)) then       ! IMPOSE k's i-th node: u_i on its DOF
        ii = ii + 1
        do while (ii > size(scn%mesh%ngroups(scn%imposes(ki)%ngroup)%items))
          ii = 1
          ki = ki + 1
        end do
        eqs(1) = max(sys%dofs%eqn(scn%imposes(ki)%dof, scn%mesh%ngroups(scn%imposes(ki)%ngroup)%items(ii)), 0)
        coefs(1) = 1.0_dp
      end if
      if (.not. held(j)) cycle
      if (j <= size(scn%conditions) .or. j > size(scn%conditions) + nimp) then
        associate (c => scn%conditions(merge(j, jc, j <= size(scn%conditions))))
          if (j <= size(scn%conditions)) then
            call condition_row(c, c%normal, sys%dofs%eqn, eqs, coefs)
          else
            call condition_row(c, condition_tangent(c, scn%mesh%ndim, kt), sys%dofs%eqn, eqs, coefs)
          end if
        end associate
      end if
      fits = .true.
      do k = 1, size(eqs)
        do l = 1, size(eqs)
          if (eqs(k) > 0 .and. eqs(l) > 0) fits = fits .and. sys%ops%pat%locate(eqs(k), eqs(l)) > 0
          ke(k, l) = kappa * coefs(k) * coefs(l)
        end do
      end do
      if (fits) call sys%ops%pat%add_element(sval, eqs, ke)
    end do
  end subroutine add_held_rows

  !> The rows after the conditions: IMPOSE's (held always), then FRICTION's tangential rows, one per
  !> condition with friction in order (two in 3D; held with their condition).
  pure subroutine held_rows_after(scn, nc, held)
    type(scene_t), intent(in) :: scn
    integer, intent(in) :: nc
    logical, intent(inout) :: held(:)
    integer :: j, t, nt
    nt = scn%mesh%ndim - 1
    t = size(held) - nt * count(scn%conditions%friction > 0.0_dp)
    held(nc + 1:t) = .true.
    do j = 1, nc
      if (scn%conditions(j)%friction <= 0.0_dp) cycle
      held(t + 1:t + nt) = held(j)
      t = t + nt
    end do
  end subroutine held_rows_after

  !> ε = 1e-8 Σdiag K / Σdiag M: small against the structure's stiffness, large enough to make
  !> Kt + εM definite along the modes the contacts hold; κ = the mean diagonal stiffness.
  subroutine shifts(sys, eps_m, kappa)
    type(system_t), intent(in) :: sys
    real(dp), intent(out) :: eps_m, kappa
    real(dp), allocatable :: dk(:), dm(:)
    allocate (dk(sys%dofs%neq), dm(sys%dofs%neq))
    call sys%ops%pat%diagonal(sys%ops%kval, dk)
    call sys%ops%pat%diagonal(sys%ops%mval, dm)
    eps_m = 1.0_dp
    if (sum(dm) > 0.0_dp .and. sum(dk) > 0.0_dp) eps_m = 1.0e-8_dp * sum(dk) / sum(dm)
    kappa = 1.0_dp
    if (any(dk > 0.0_dp)) kappa = sum(dk, dk > 0.0_dp) / count(dk > 0.0_dp)
  end subroutine shifts

  !> Each body's rigid modes that no support holds (body_rigid_freedom) must be held by the
  !> contact conditions: the columns C t_k of those modes independent (a pivoted Cholesky of their
  !> normalized Gram matrix). shifted: some mode is held by contact only. A mode held by nothing
  !> is bad input naming the body and the mode.
  subroutine held_modes_check(scn, sys, rig, shifted, stat, errmsg, cs)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: rig(:, :)
    logical, intent(out) :: shifted
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(contact_set_t), intent(in), optional :: cs
    integer, allocatable :: body(:)
    logical, allocatable :: free(:, :)
    real(dp), allocatable :: ct(:, :), g0(:), tm(:, :)
    logical :: dropped(6)
    integer :: ib, k, l, nf, rank, idx(6), nc, nin, j, e2(2)
    stat = STAT_OK
    shifted = .false.
    call equation_bodies(scn, sys%dofs%eqn, sys%dofs%neq, body)
    call body_rigid_freedom(scn, sys%dofs%eqn, free)
    nc = 0
    if (present(cs)) nc = cs%n_conditions()
    ! A bowl (a curved obstacle, INSIDE) also holds its node along the tangent (its curvature):
    ! one more row each, t'u at the node.
    nin = count(scn%conditions%curved == -1)
    allocate (ct(nc + nin, 6), g0(nc), tm(sys%dofs%neq, 6))
    tm = 0.0_dp                                  ! (g0 from u = 0: 0 x an unset value may be a NaN)
    if (nc > 0) call contact_gaps(cs, tm(:, 1), g0)
    do ib = 1, size(free, 2)
      if (.not. any(body == ib)) cycle
      nf = 0
      do k = 1, size(rig, 2)
        if (.not. free(k, ib)) cycle
        tm(:, nf + 1) = merge(rig(:, k), 0.0_dp, body == ib)
        if (norm2(tm(:, nf + 1)) == 0.0_dp) cycle   ! (a rotation of a body with no DOF it moves)
        call column_rank(tm(:, 1:nf + 1), rank)
        if (rank <= nf) cycle                    ! (a point's rotation: a translation)
        nf = nf + 1
        idx(nf) = k
        associate (t => tm(:, nf))
          if (nc > 0) then
            call contact_gaps(cs, t, ct(1:nc, nf))
            ct(1:nc, nf) = ct(1:nc, nf) - g0
          end if
          l = nc
          do j = 1, size(scn%conditions)
            if (scn%conditions(j)%curved /= -1) cycle
            l = l + 1
            e2 = max(sys%dofs%eqn(1:2, scn%conditions(j)%node_b), 0)
            ct(l, nf) = 0.0_dp
            if (e2(1) > 0) ct(l, nf) = ct(l, nf) - scn%conditions(j)%normal(2) * t(e2(1))
            if (e2(2) > 0) ct(l, nf) = ct(l, nf) + scn%conditions(j)%normal(1) * t(e2(2))
          end do
        end associate
      end do
      if (nf == 0) cycle
      shifted = .true.
      do k = 1, nf
        if (norm2(ct(:, k)) == 0.0_dp) then      ! (also with no contact row at all)
          call free_mode_error(scn, ib, MODE_NAMES(idx(k)), stat, errmsg)
          return
        end if
      end do
      call column_rank(ct(:, 1:nf), rank, dropped(1:nf))
      if (rank < nf) then
        do k = 1, nf
          if (dropped(k)) exit
        end do
        call free_mode_error(scn, ib, MODE_NAMES(idx(min(k, nf))) // ' (with the other rigid modes the contacts hold)', &
          stat, errmsg)
        return
      end if
    end do
  end subroutine held_modes_check

  !> The rank of the (at most 6, non-zero) columns of a: a pivoted Cholesky of their normalized Gram
  !> matrix (dense_solve's spsd_solve), dropped(k): column k depends on the others.
  subroutine column_rank(a, rank, dropped)
    real(dp), intent(in) :: a(:, :)
    integer, intent(out) :: rank
    logical, intent(out), optional :: dropped(:)
    real(dp) :: gram(6, 6), b(6), x(6), nrm(6)
    integer :: m, i, l
    m = size(a, 2)
    do i = 1, m
      nrm(i) = norm2(a(:, i))
    end do
    do i = 1, m
      do l = 1, m
        gram(i, l) = dot_product(a(:, i), a(:, l)) / (nrm(i) * nrm(l))
      end do
    end do
    b = 0.0_dp
    if (present(dropped)) then
      call spsd_solve(gram(1:m, 1:m), b(1:m), x(1:m), rank, dropped, rtol=1.0e-10_dp)
    else
      call spsd_solve(gram(1:m, 1:m), b(1:m), x(1:m), rank, rtol=1.0e-10_dp)
    end if
  end subroutine column_rank

  subroutine free_mode_error(scn, ib, what, stat, errmsg)
    type(scene_t), intent(in) :: scn
    integer, intent(in) :: ib
    character(len=*), intent(in) :: what
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(scn%static_line) // ': STATIC: body ' // str(ib) // &
      ' has a ' // trim(what) // ' that no support (FIX, IMPOSE) or contact condition holds: no static equilibrium ' // &
      "to solve for; fix it, at 'STATIC'")
  end subroutine free_mode_error
end module static_preload
