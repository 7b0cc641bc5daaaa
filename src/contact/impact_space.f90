!> What every impact mode works with (method.md sections 3 and 6, docs/contact.md): the inverse
!> mass M⁻¹ and the model's rigid modes, and the operations the modes share on the rows C of the
!> conditions (given by the caller, read only):
!>   am_block            A M⁻¹A' for a set of conditions A;
!>   add_minv_ct         v <- v + α M⁻¹C'μ, M v with it;
!>   hzero_step          (16): the hzero step with gains, which returns its multiplier ν;
!>   rigid_motion        the rigid motion of a group a scaling must keep (rigid_motion module);
!>   scale_about_rigid   a group's velocity scaled about it, with the momenta the scaling gave;
!>   book_scaling        those momenta as normal impulses at the group's conditions.
!> Its scratch is private: nothing a mode computes leaves through it.
module impact_space
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use sparse_matrix, only: sym_csc_t
  use inverse_ops, only: inverse_op_t, diag_inverse_t, chol_inverse_t
  use dense_solve, only: spsd_solve_ws
  use rigid_motion, only: invariant_rigid_motion, normal_impulses, MAX_RIGID
  use constraint_rows, only: constraint_rows_t
  implicit none
  private
  public :: MAX_RIGID, TRANSLATION_MODE

  !> The rigid mode of the translation along x, y, z (the modes' order: x, y, the rotation about z,
  !> then in 3D z and the rotations about x and y).
  integer, parameter :: TRANSLATION_MODE(3) = [1, 2, 4]

  type, public :: impact_space_t
    private
    class(inverse_op_t), allocatable :: minv
    ! Rigid modes t_k (neq, 2, 3 or 6: translations x, y, the rotation about z[, z, rotations about x, y]) on the
    ! free equations and
    ! M t_k (set_rigid_modes); body_free(k, b): mode k is free on body b (no support).
    logical :: has_rigid = .false.
    real(dp), allocatable :: rig(:, :), mrig(:, :)
    logical, allocatable :: body_free(:, :)
    ! Scratch: erig(j, k) = c_j't_k of the last group's active rows, cnorm(j) = |c_j|, rig_scale
    ! = max |t_k| over its equations (rigid_motion, for book_scaling).
    real(dp), allocatable :: f(:), xw(:), amat(:, :), sv(:), work2(:), erig(:, :), cnorm(:)
    integer, allocatable :: ipiv(:)
    real(dp) :: rig_scale = 0.0_dp
  contains
    procedure :: init => space_init
    procedure :: set_mass_op => space_set_mass_op
    procedure :: set_mass_chol => space_set_mass_chol
    procedure :: destroy_mass => space_destroy_mass
    procedure :: mass_diagonal => space_mass_diagonal
    procedure :: set_rigid_modes => space_set_rigid_modes
    procedure :: am_block => space_am_block
    procedure :: add_minv_ct => space_add_minv_ct
    procedure :: hzero_step => space_hzero_step
    procedure :: translation => space_translation
    procedure :: rigid_motion => space_rigid_motion
    procedure :: scale_about_rigid => space_scale_about_rigid
    procedure :: book_scaling => space_book_scaling
  end type impact_space_t

contains

  !> Scratch for neq equations and nc conditions (the rigid modes and M⁻¹ are dropped).
  subroutine space_init(self, neq, nc)
    class(impact_space_t), intent(inout) :: self
    integer, intent(in) :: neq, nc
    if (allocated(self%f)) deallocate (self%f, self%xw, self%amat, self%sv, self%work2, self%erig, self%cnorm, self%ipiv)
    ! Dense block for up to 64 conditions together; it grows beyond (rarely).
    allocate (self%f(neq), self%xw(neq), self%amat(min(nc, 64), min(nc, 64)), self%sv(nc), self%work2(2 * nc), &
      self%erig(nc, MAX_RIGID), self%cnorm(nc), self%ipiv(nc))
    self%has_rigid = .false.
  end subroutine space_init

  !> Any M⁻¹ operator (a lumped mass's diagonal, tests); op is copied.
  subroutine space_set_mass_op(self, op)
    class(impact_space_t), intent(inout) :: self
    class(inverse_op_t), intent(in) :: op
    if (allocated(self%minv)) call self%destroy_mass()
    allocate (self%minv, source=op)
  end subroutine space_set_mass_op

  !> A consistent mass (pattern, values), factorized with CHOLMOD; dloc: the inverse where M has
  !> no coupling (pat%isolated_diagonal).
  subroutine space_set_mass_chol(self, pat, mval, stat, errmsg)
    class(impact_space_t), intent(inout) :: self
    type(sym_csc_t), intent(in) :: pat
    real(dp), intent(in), contiguous :: mval(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: minor
    character(len=:), allocatable :: msg
    if (allocated(self%minv)) call self%destroy_mass()
    allocate (chol_inverse_t :: self%minv)
    select type (op => self%minv)
    type is (chol_inverse_t)
      call op%f%factorize(pat, mval, stat, msg, minor)
      if (stat /= STAT_OK) then
        call set_error(stat, errmsg, STAT_INPUT, 'contact with a consistent mass needs M positive definite: ' // &
          'zero or negative mass pivot at equation ' // str(minor) // ' (' // msg // ')')
        return
      end if
      allocate (op%dloc(pat%n))
      call pat%isolated_diagonal(mval, op%dloc)
    end select
  end subroutine space_set_mass_chol

  subroutine space_destroy_mass(self)
    class(impact_space_t), intent(inout) :: self
    if (.not. allocated(self%minv)) return
    select type (op => self%minv)
    type is (chol_inverse_t)
      call op%f%destroy()
    end select
    deallocate (self%minv)
  end subroutine space_destroy_mass

  !> True when M⁻¹ is a diagonal (a lumped mass).
  logical function space_mass_diagonal(self)
    class(impact_space_t), intent(in) :: self
    space_mass_diagonal = .false.
    if (.not. allocated(self%minv)) return
    select type (op => self%minv)
    type is (diag_inverse_t)
      space_mass_diagonal = .true.
    end select
  end function space_mass_diagonal

  !> The rigid modes t (neq, 2, 3 or 6), M t, and free(modes, bodies) (absent: every mode free); see
  !> contact_set_rigid_modes.
  subroutine space_set_rigid_modes(self, t, mt, free)
    class(impact_space_t), intent(inout) :: self
    real(dp), intent(in) :: t(:, :), mt(:, :)
    logical, intent(in), optional :: free(:, :)
    self%rig = t
    self%mrig = mt
    if (present(free)) self%body_free = free
    self%has_rigid = .true.
  end subroutine space_set_rigid_modes

  !> a(1:n, 1:n) = C_idx M⁻¹ C_idx' for the conditions idx(1:n): the blocks of A M⁻¹A' that the
  !> impulse (14) and the reflection (16) need. From the sparse rows directly where M⁻¹ is 1/m on
  !> every equation of the conditions (a lumped mass; the contact rows SYMMETRIC lumps in a
  !> consistent one: no solve, the cost of the contact zone); otherwise one solve with M per
  !> condition, symmetrized.
  subroutine space_am_block(self, c, idx, n, a, stat, errmsg)
    class(impact_space_t), intent(inout) :: self
    type(constraint_rows_t), intent(in) :: c
    integer, intent(in) :: idx(:), n
    real(dp), intent(out) :: a(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, l
    stat = STAT_OK
    select type (op => self%minv)
    type is (diag_inverse_t)
      call local_block(c, idx, n, op%d, a, stat, errmsg)
      return
    type is (chol_inverse_t)
      if (rows_local(c, idx(1:n), op%dloc)) then
        call local_block(c, idx, n, op%dloc, a, stat, errmsg)
        return
      end if
    end select
    do l = 1, n
      self%f = 0.0_dp
      call c%scatter(idx(l), 1.0_dp, self%f)
      call self%minv%apply(self%f, self%xw, stat, errmsg)
      if (stat /= STAT_OK) return
      do k = 1, n
        a(k, l) = c%dot(idx(k), self%xw)
      end do
    end do
    do l = 1, n
      do k = 1, l - 1
        a(k, l) = 0.5_dp * (a(k, l) + a(l, k))
        a(l, k) = a(k, l)
      end do
    end do
  end subroutine space_am_block

  !> am_block where M⁻¹ is 1/d(eq) on every equation the conditions idx(1:n) touch.
  subroutine local_block(c, idx, n, d, a, stat, errmsg)
    type(constraint_rows_t), intent(in) :: c
    integer, intent(in) :: idx(:), n
    real(dp), intent(in) :: d(:)
    real(dp), intent(out) :: a(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, l, p, q, ep
    stat = STAT_OK
    do l = 1, n
      do k = 1, l
        a(k, l) = 0.0_dp
        do p = c%first(idx(k)), c%last(idx(k))
          ep = c%eq_at(p)
          do q = c%first(idx(l)), c%last(idx(l))
            if (ep /= c%eq_at(q)) cycle
            if (.not. (d(ep) > 0.0_dp)) then
              call set_error(stat, errmsg, STAT_INPUT, 'contact: equation ' // str(ep) // &
                ' carries a contact condition but has no mass (lumped mass diagonal ' // str(d(ep)) // ')')
              return
            end if
            a(k, l) = a(k, l) + c%coef_at(p) * c%coef_at(q) / d(ep)
          end do
        end do
        a(l, k) = a(k, l)
      end do
    end do
  end subroutine local_block

  !> Whether every equation of the conditions conds has a local inverse (d > 0: no coupling in M).
  pure logical function rows_local(c, conds, d) result(ok)
    type(constraint_rows_t), intent(in) :: c
    integer, intent(in) :: conds(:)
    real(dp), intent(in) :: d(:)
    integer :: k
    ok = .false.
    do k = 1, size(conds)
      if (.not. row_local(c, conds(k), d)) return
    end do
    ok = .true.
  end function rows_local

  pure logical function row_local(c, j, d) result(ok)
    type(constraint_rows_t), intent(in) :: c
    integer, intent(in) :: j
    real(dp), intent(in) :: d(:)
    integer :: p
    ok = .false.
    do p = c%first(j), c%last(j)
      if (.not. (d(c%eq_at(p)) > 0.0_dp)) return
    end do
    ok = .true.
  end function row_local

  !> v <- v + alpha M⁻¹C'mu and mv <- mv + alpha C'mu (mv stays M v without a product by M).
  subroutine space_add_minv_ct(self, c, mu, alpha, v, mv, stat, errmsg)
    class(impact_space_t), intent(inout) :: self
    type(constraint_rows_t), intent(in) :: c
    real(dp), intent(in) :: mu(:), alpha
    real(dp), intent(inout) :: v(:), mv(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: j, p, ep
    logical :: local
    stat = STAT_OK
    select type (op => self%minv)
    type is (chol_inverse_t)                     ! rows with a local inverse: no solve (am_block)
      local = .true.
      do j = 1, size(mu)
        if (mu(j) /= 0.0_dp) local = local .and. row_local(c, j, op%dloc)
      end do
      if (local) then
        do j = 1, size(mu)
          if (mu(j) == 0.0_dp) cycle
          do p = c%first(j), c%last(j)
            ep = c%eq_at(p)
            v(ep) = v(ep) + alpha * mu(j) * c%coef_at(p) / op%dloc(ep)
            mv(ep) = mv(ep) + alpha * mu(j) * c%coef_at(p)
          end do
        end do
        return
      end if
    end select
    self%f = 0.0_dp
    call c%add_transpose(mu, self%f)
    call self%minv%apply(self%f, self%xw, stat, errmsg)
    if (stat /= STAT_OK) return
    v = v + alpha * self%xw
    mv = mv + alpha * self%f
  end subroutine space_add_minv_ct

  !> The translation of each body b at velocity wb(:, b) (0 for a body absent from framed, and
  !> along a direction its supports hold) and M times it, on the free equations (body(i): the
  !> body of equation i; the rigid modes' translations): the frame of the obstacles a group
  !> touches (contact_frame).
  subroutine space_translation(self, body, framed, wb, x, mx)
    class(impact_space_t), intent(in) :: self
    integer, intent(in) :: body(:)
    logical, intent(in) :: framed(:)
    real(dp), intent(in) :: wb(:, :)
    real(dp), intent(out) :: x(:), mx(:)
    integer :: i, d, k
    x = 0.0_dp
    mx = 0.0_dp
    if (.not. self%has_rigid) return
    do i = 1, size(x)
      if (body(i) <= 0) cycle
      if (.not. framed(body(i))) cycle
      do d = 1, size(wb, 1)
        k = TRANSLATION_MODE(d)
        if (k > size(self%rig, 2)) cycle
        if (allocated(self%body_free)) then      ! (a translation the supports forbid: not a frame)
          if (.not. self%body_free(k, body(i))) cycle
        end if
        x(i) = x(i) + wb(d, body(i)) * self%rig(i, k)
        mx(i) = mx(i) + wb(d, body(i)) * self%mrig(i, k)
      end do
    end do
  end subroutine space_translation

  !> (16) The hzero step about the conditions A = conds: one Newmark step of length
  !> h0 -> 0 with A held as equalities leaves only the mass terms,
  !>     M w + A'ν = M v,  A w = 0,   then v <- 2 w - v by (3),
  !> i.e. v <- v - 2 M⁻¹A'ν with (A M⁻¹A') ν = A v: the M-orthogonal reflection of v about the
  !> tangent space of A (normal velocities reversed, v'Mv kept). With the gains g_k = 1 + e_k,
  !> (A M⁻¹A') ν = diag(g) A v and v <- v - M⁻¹A'ν give A v <- -diag(e) A v: g = 2 (e = 1) is
  !> (16); g = 1 (e = 0) stops at w, the M-orthogonal projection on A v = 0 that PERSIST uses
  !> (method.md section 6); 0 <= e < 1 is Newton's law of restitution (RESTITUTION e) in the
  !> M-metric. mv is updated with v (mv <- mv - A'ν). nu(1:nc): ν on conds, 0 elsewhere (the
  !> impulses -ν along c_j). With target, A v - target takes the place of A v (a moving
  !> obstacle's relative normal velocity). rank: independent rows of A (dependent ones, e.g. duplicated
  !> conditions, get ν = 0). The dense hzero_reflection_dense of impact_kernels is its test oracle.
  subroutine space_hzero_step(self, c, conds, gain, v, mv, nu, rank, stat, errmsg, target)
    class(impact_space_t), intent(inout) :: self
    type(constraint_rows_t), intent(in) :: c
    integer, intent(in) :: conds(:)
    real(dp), intent(in) :: gain(:)
    real(dp), intent(inout) :: v(:), mv(:)
    real(dp), intent(out) :: nu(:)
    integer, intent(out) :: rank
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), intent(in), optional :: target(:)   !< normal velocities A v is reflected about (0 without)
    integer :: k, n, m
    rank = 0
    n = size(conds)
    if (size(self%amat, 1) < n) then             ! (it only grows)
      m = max(n, 2 * size(self%amat, 1))
      deallocate (self%amat)
      allocate (self%amat(m, m))
    end if
    call self%am_block(c, conds, n, self%amat(1:n, 1:n), stat, errmsg)
    if (stat /= STAT_OK) return
    do k = 1, n
      self%sv(k) = gain(k) * c%dot(conds(k), v)
      if (present(target)) self%sv(k) = self%sv(k) - gain(k) * target(k)
    end do
    call spsd_solve_ws(n, self%amat, self%sv, rank, self%ipiv, self%work2)
    nu = 0.0_dp
    do k = 1, n
      nu(conds(k)) = self%sv(k)
    end do
    call self%add_minv_ct(c, nu, -1.0_dp, v, mv, stat, errmsg)
  end subroutine space_hzero_step

  !> The rigid motion v_r = Σ a_k t_k of a group (its equations rows, mvp = M vp its velocity
  !> after the projection) that a scaling must leave alone: its M-orthogonal projection on the
  !> free rigid modes of the group (translations, rotation about the origin; no support moves
  !> them) that its active conditions idx(1:n) leave invariant (c_j't = 0), and its kinetic energy
  !> tcm (invariant_rigid_motion). Scaling about v_r keeps every momentum the contact cannot
  !> change (the tangential one against a wall, the angular one about the contact normal) and the
  !> zero normal velocities; node-to-node groups keep all their momenta. nm, mk(1:nm): the free
  !> modes (kept for book_scaling). a = 0 without free mode.
  subroutine space_rigid_motion(self, c, body, rows, idx, n, mvp, a, tcm, nm, mk)
    class(impact_space_t), intent(inout) :: self
    type(constraint_rows_t), intent(in) :: c
    integer, intent(in) :: body(:)
    logical, intent(in) :: rows(:)
    integer, intent(in) :: idx(:), n
    real(dp), intent(in) :: mvp(:)
    real(dp), intent(out) :: a(MAX_RIGID), tcm
    integer, intent(out) :: nm, mk(MAX_RIGID)
    real(dp) :: g(MAX_RIGID, MAX_RIGID), pk(MAX_RIGID), rmax(MAX_RIGID), am(MAX_RIGID)
    logical :: free(MAX_RIGID)
    integer :: k, l, i, j
    a = 0.0_dp
    tcm = 0.0_dp
    nm = 0
    if (.not. self%has_rigid) return
    free = .false.
    free(1:size(self%rig, 2)) = .true.
    if (allocated(self%body_free)) then
      do i = 1, size(rows)
        if (rows(i) .and. body(i) > 0) free(1:size(self%rig, 2)) = free(1:size(self%rig, 2)) .and. &
          self%body_free(1:size(self%rig, 2), body(i))
      end do
    end if
    do k = 1, size(self%rig, 2)
      if (.not. free(k)) cycle
      nm = nm + 1
      mk(nm) = k
    end do
    if (nm == 0) return
    self%rig_scale = 0.0_dp
    do k = 1, nm
      pk(k) = sum(self%rig(:, mk(k)) * mvp, mask=rows)
      rmax(k) = maxval(abs(self%rig(:, mk(k))), mask=rows)
      self%rig_scale = max(self%rig_scale, rmax(k))
      do l = 1, nm
        g(k, l) = sum(self%rig(:, mk(k)) * self%mrig(:, mk(l)), mask=rows)
      end do
    end do
    do j = 1, n
      self%cnorm(j) = sqrt(c%norm2_sq(idx(j)))
      do k = 1, nm
        self%erig(j, k) = c%dot(idx(j), self%rig(:, mk(k)))
      end do
    end do
    call invariant_rigid_motion(g(1:nm, 1:nm), pk(1:nm), self%erig(1:n, 1:nm), self%cnorm(1:n), rmax(1:nm), am(1:nm), tcm)
    do k = 1, nm
      a(mk(k)) = am(k)
    end do
  end subroutine space_rigid_motion

  !> The group's velocity scaled by s about its rigid motion a (rigid_motion): on its equations
  !> rows, v = v_r + s (vp - v_r), mv likewise from mvp. dm(1:nm): the momenta the scaling gave
  !> along the free modes mk(1:nm); pb: its momentum (x, y, z).
  subroutine space_scale_about_rigid(self, rows, a, nm, mk, s, vp, mvp, v, mv, dm, pb)
    class(impact_space_t), intent(in) :: self
    logical, intent(in) :: rows(:)
    real(dp), intent(in) :: a(MAX_RIGID), s, vp(:), mvp(:)
    integer, intent(in) :: nm, mk(MAX_RIGID)
    real(dp), intent(inout) :: v(:), mv(:)
    real(dp), intent(out) :: dm(MAX_RIGID), pb(3)
    real(dp) :: vcm, mvcm
    integer :: i, k, d
    dm = 0.0_dp
    pb = 0.0_dp
    do i = 1, size(rows)                         ! (a loop: a WHERE block allocates its mask)
      if (.not. rows(i)) cycle
      vcm = 0.0_dp
      mvcm = 0.0_dp
      if (self%has_rigid) then
        do k = 1, size(self%rig, 2)
          if (a(k) == 0.0_dp) cycle
          vcm = vcm + a(k) * self%rig(i, k)
          mvcm = mvcm + a(k) * self%mrig(i, k)
        end do
      end if
      v(i) = vcm + s * (vp(i) - vcm)
      mv(i) = mvcm + s * (mvp(i) - mvcm)
      do k = 1, nm                               ! the momenta the scaling gave, by free mode
        dm(k) = dm(k) + self%rig(i, mk(k)) * (mv(i) - mvp(i))
      end do
      if (self%has_rigid) then
        do d = 1, 3
          if (TRANSLATION_MODE(d) <= size(self%rig, 2)) pb(d) = pb(d) + self%rig(i, TRANSLATION_MODE(d)) * (mv(i) - mvp(i))
        end do
      end if
    end do
  end subroutine space_scale_about_rigid

  !> The momentum a scaling gave a group, as impulses: dm(1:nm) along its free rigid modes (the
  !> last rigid_motion's, at its active conditions idx(1:n)) lies in what normal impulses at those
  !> rows can give; their least-norm impulses (normal_impulses, in z) join cimp along c_j, so
  !> that contacts.csv and the reaction count them where they act. A group without a free mode
  !> (held by supports, whose reactions take any momentum) books the momentum pb (x, y, z) on its
  !> first changing condition j0, as a body impulse bimp(:, j0).
  subroutine space_book_scaling(self, idx, n, nm, dm, pb, j0, z, cimp, bimp)
    class(impact_space_t), intent(in) :: self
    integer, intent(in) :: idx(:), n, nm, j0
    real(dp), intent(in) :: dm(MAX_RIGID), pb(3)
    real(dp), intent(inout) :: z(:), cimp(:), bimp(:, :)
    real(dp) :: resid
    integer :: j
    if (nm > 0 .and. n > 0) then
      call normal_impulses(self%erig(1:n, 1:nm), dm(1:nm), maxval(self%cnorm(1:n)) * self%rig_scale, z(1:n), resid)
      if (resid <= 1.0e-8_dp) then
        do j = 1, n
          cimp(idx(j)) = cimp(idx(j)) + z(j)
        end do
        return
      end if
    end if
    if (j0 > 0) bimp(:, j0) = bimp(:, j0) + pb
  end subroutine space_book_scaling
end module impact_space
