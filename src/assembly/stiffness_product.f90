!> Bσ of a linear elastic, small-strain model as the sparse product K0 u (issue 14): the vector
!> the element loop computes, at the cost of one pass over K0 instead of every integration point.
!>
!> Why not the bare product: K0 u rounds at about eps |K0| |u|, like the element loop, but its
!> rounding is not self-equilibrated (the loop's Bᵀσ sums to zero whatever σ is) and grows with
!> the body's rigid motion, which has no bound on a free body. Measured with the bare product:
!> momentum drifting by 2e-9 of m v0 on two blocks in contact, the balance of a falling beam at
!> 1e-9 to 3e-8 of its energy instead of round-off. So, for each body (mesh-connected component)
!> and each rigid mode it can make freely (the translations x and y, the infinitesimal rotation; in
!> 3D the translations x, y, z and the rotations about x, y, z: not held by a support, assembly's
!> held_modes, and annihilated by K0, checked numerically at setup, so an axisymmetric hoop term or
!> a misaligned spring also removes the mode), exact in exact arithmetic:
!> - the body's mean translation is taken out of u first (K0 t = 0; a constant shift, so the
!>   shifted u rounds at the deformation's size, not the motion's), and
!> - the product is projected orthogonally to the modes (t'K0 u = 0: the net force and moment a
!>   free body's elasticity exerts on itself are zero), which equilibrates the rounding.
!> Near-mechanisms (a rigid motion the supports leave that is none of the modes, or supports far
!> softer than the body) leave the product off: the element loop is used. apply also returns
!> ½ u'·K0 u', which rounds at eps x cond(K0): the energy the balance is judged on is the points'
!> (internal_forces' linear_strain_energy). No allocation after setup.
module stiffness_product
  use kinds, only: dp
  use sparse_matrix, only: sym_csc_t
  use pair_blocks, only: pair_block_t
  use mesh, only: DOF_AXIS, rigid_mode_row
  implicit none
  private
  public :: k0_product_t

  !> Relative size of K0 r, against |K0| |r|, below which a rigid mode r counts as K0's kernel.
  real(dp), parameter :: KERNEL_TOL = 1.0e-9_dp
  !> Below this relative K0 r a mode held by a support is nearly free (the support much softer than
  !> the body): the product is not used.
  real(dp), parameter :: SOFT_TOL = 1.0e-4_dp

  type :: k0_product_t
    private
    logical :: on = .false.
    integer :: nb = 0                       !< bodies with at least one kernel mode
    integer :: ntr = 2, nrot = 1            !< translations and rotations: 2 and 1 in 2D, 3 and 3 in 3D
    integer, allocatable :: eq(:)           !< their equations
    integer, allocatable :: bod(:)          !< (size(eq)) the body of eq(k), 1..nb
    integer, allocatable :: comp(:)         !< (size(eq)) the axis eq(k) translates along (1 x, 2 y, 3 z), 0 for RZ
    real(dp), allocatable :: q(:, :)        !< (size(eq), nrot) the unit rotation modes, orthogonal to the translations
    logical, allocatable :: kern(:, :)      !< (ntr + nrot, nb) mode k (translations, rotations) is in K0's kernel on b
    real(dp), allocatable :: rn(:, :)       !< (ntr, nb) 1 / number of equations of body b along each axis
    real(dp), allocatable :: s(:, :)        !< (ntr + nrot, nb) workspace: means, then projections
    real(dp), allocatable :: ur(:)          !< (neq) workspace: u without its translations
    type(pair_block_t) :: blk               !< K0 by node blocks, where they pay (pair_blocks)
  contains
    procedure :: setup => k0p_setup
    procedure :: apply => k0p_apply
    procedure :: active => k0p_active
    procedure :: disable => k0p_disable
    procedure :: enable => k0p_enable
  end type k0_product_t

contains

  !> The bodies' kernel modes of K0 (values kval on pat). eqn(NODE_DOFS, nnode): the equation of each
  !> node DOF (> 0 free); x(ndim, nnode) the reference coordinates; body(neq) the component of each
  !> equation (equation_bodies); held(k, b), k = 1..nm (nm = 3 in 2D, 6 in 3D): mode k of body b is
  !> held by a support (assembly's held_modes), which the numerical test alone would miss for a
  !> support through a spring much softer than the body; held(nm + 1, b): a rigid motion the supports
  !> leave free that is none of the modes. Returns with the product off (active() false) on a
  !> near-mechanism.
  subroutine k0p_setup(self, pat, kval, eqn, x, body, held)
    class(k0_product_t), intent(inout) :: self
    type(sym_csc_t), intent(in) :: pat
    real(dp), intent(in) :: kval(:), x(:, :)
    integer, intent(in) :: eqn(:, :), body(:)
    logical, intent(in) :: held(:, :)
    real(dp), allocatable :: r(:, :), g(:, :), a(:, :), kabs(:), gmax(:, :), amax(:, :)
    integer, allocatable :: comp(:), local(:)
    integer :: n, nbody, i, j, d, k, b, m, nd, nm
    real(dp) :: rowm(6)
    n = pat%n
    nd = size(x, 1)
    self%ntr = nd
    self%nrot = merge(3, 1, nd == 3)
    nm = self%ntr + self%nrot
    nbody = 0
    if (n > 0) nbody = maxval(body)
    allocate (r(n, nm), g(n, nm), a(n, nm), comp(n), gmax(nm, nbody), amax(nm, nbody), local(nbody))
    ! The rigid modes about the origin: 2D UX = 1; UY = 1; UX = -y, UY = x, RZ = 1; 3D the three
    ! translations and the rotations e_k x X.
    r = 0.0_dp
    comp = 0
    do j = 1, size(eqn, 2)
      do d = 1, size(eqn, 1)
        i = eqn(d, j)
        if (i <= 0) cycle
        comp(i) = DOF_AXIS(d)
        rowm = rigid_mode_row(d, x(:, j))
        r(i, :) = rowm(1:nm)
      end do
    end do
    kabs = abs(kval)
    gmax = 0.0_dp
    amax = 0.0_dp
    do k = 1, nm
      call pat%matvec(kval, r(:, k), g(:, k))
      call pat%matvec(kabs, abs(r(:, k)), a(:, k))
      do i = 1, n
        b = body(i)
        gmax(k, b) = max(gmax(k, b), abs(g(i, k)))
        amax(k, b) = max(amax(k, b), a(i, k))
      end do
    end do
    ! Near-mechanisms stay with the element loop: a body free to move rigidly in a way the modes
    ! do not describe (held(nm + 1)), or held only by supports far softer than itself (a spring to the
    ! ground: K0 r below 1e-4 |K0||r|). The product would round at eps |K0| |u| on a motion without
    ! bound, which the loop's equilibrated Bᵀσ does not (a soft-spring plate: balance 3e-7 against
    ! 1.3e-9).
    if (any(held(nm + 1, 1:nbody)) .or. any(held(1:nm, 1:nbody) .and. gmax < SOFT_TOL * amax)) then
      self%on = .false.
      return
    end if
    ! A body keeps the modes K0 annihilates to round-off and no support holds; a mode it has no DOF
    ! of is dropped.
    where (held(1:nm, 1:nbody)) gmax = huge(1.0_dp)
    local = 0
    self%nb = 0
    do b = 1, nbody
      if (any(gmax(:, b) <= KERNEL_TOL * amax(:, b))) then
        self%nb = self%nb + 1
        local(b) = self%nb
      end if
    end do
    allocate (self%kern(nm, self%nb), self%rn(self%ntr, self%nb), self%s(nm, self%nb), self%ur(n))
    do b = 1, nbody
      if (local(b) > 0) self%kern(:, local(b)) = gmax(:, b) <= KERNEL_TOL * amax(:, b)
    end do
    m = count(local(body) > 0)
    allocate (self%eq(m), self%bod(m), self%comp(m), self%q(m, self%nrot))
    m = 0
    do i = 1, n
      if (local(body(i)) == 0) cycle
      m = m + 1
      self%eq(m) = i
      self%bod(m) = local(body(i))
      self%comp(m) = comp(i)
      self%q(m, :) = r(i, self%ntr + 1:nm)
    end do
    call count_translations(self)
    do k = 1, self%nrot
      call rotation_unit(self, k)
    end do
    call self%blk%build(pat, kval)
    self%on = .true.
  end subroutine k0p_setup

  !> rn(d, b) = 1 / (number of equations along axis d in body b); an axis the body has no equation
  !> of is not a mode.
  subroutine count_translations(self)
    type(k0_product_t), intent(inout) :: self
    integer :: k, d, b
    self%rn = 0.0_dp
    do k = 1, size(self%eq)
      d = self%comp(k)
      if (d > 0) self%rn(d, self%bod(k)) = self%rn(d, self%bod(k)) + 1.0_dp
    end do
    do b = 1, self%nb
      do d = 1, self%ntr
        if (self%rn(d, b) > 0.0_dp) then
          self%rn(d, b) = 1.0_dp / self%rn(d, b)
        else
          self%kern(d, b) = .false.
        end if
      end do
    end do
  end subroutine count_translations

  !> q(:, jr): rotation mode jr made orthogonal to the body's kernel translations and to the rotations
  !> before it (twice: the coordinates may be far from the origin) and of unit length; a body whose
  !> rotation jr is not a kernel mode, or is a combination of the others (one node without RZ), has
  !> none.
  subroutine rotation_unit(self, jr)
    type(k0_product_t), intent(inout) :: self
    integer, intent(in) :: jr
    real(dp) :: nrm0(self%nb)
    integer :: k, b, pass, kr, i
    kr = self%ntr + jr
    do k = 1, size(self%eq)
      if (.not. self%kern(kr, self%bod(k))) self%q(k, jr) = 0.0_dp
    end do
    nrm0 = 0.0_dp
    do k = 1, size(self%eq)
      nrm0(self%bod(k)) = nrm0(self%bod(k)) + self%q(k, jr)**2
    end do
    do pass = 1, 2
      self%s = 0.0_dp
      do k = 1, size(self%eq)
        if (self%comp(k) > 0) self%s(self%comp(k), self%bod(k)) = self%s(self%comp(k), self%bod(k)) + self%q(k, jr)
      end do
      do k = 1, size(self%eq)
        b = self%bod(k)
        if (self%comp(k) == 0) cycle
        if (self%kern(self%comp(k), b)) self%q(k, jr) = self%q(k, jr) - self%s(self%comp(k), b) * self%rn(self%comp(k), b)
      end do
      if (jr == 1) cycle
      self%s = 0.0_dp                       ! (the earlier rotations: unit and orthogonal already)
      do k = 1, size(self%eq)
        do i = 1, jr - 1
          self%s(self%ntr + i, self%bod(k)) = self%s(self%ntr + i, self%bod(k)) + self%q(k, i) * self%q(k, jr)
        end do
      end do
      do k = 1, size(self%eq)
        do i = 1, jr - 1
          self%q(k, jr) = self%q(k, jr) - self%s(self%ntr + i, self%bod(k)) * self%q(k, i)
        end do
      end do
    end do
    self%s = 0.0_dp
    do k = 1, size(self%eq)
      self%s(kr, self%bod(k)) = self%s(kr, self%bod(k)) + self%q(k, jr)**2
    end do
    do b = 1, self%nb
      if (self%kern(kr, b)) self%kern(kr, b) = self%s(kr, b) > 1.0e-20_dp * nrm0(b)
    end do
    do k = 1, size(self%eq)
      b = self%bod(k)
      if (self%kern(kr, b)) then
        self%q(k, jr) = self%q(k, jr) / sqrt(self%s(kr, b))
      else
        self%q(k, jr) = 0.0_dp
      end if
    end do
  end subroutine rotation_unit

  !> f = K0 u on the kernel-shifted u (above), projected off the bodies' kernel modes; energy
  !> = ½ u'·f, the strain energy.
  subroutine k0p_apply(self, pat, kval, u, f, energy)
    class(k0_product_t), intent(inout) :: self
    type(sym_csc_t), intent(in) :: pat
    real(dp), intent(in) :: kval(:), u(:)
    real(dp), intent(out) :: f(:), energy
    integer :: k, i, d, b, jr
    if (self%nb == 0) then                   ! every body held: the bare product
      call product(self, pat, kval, u, f)
      energy = 0.5_dp * dot_product(u, f)
      return
    end if
    self%ur = u
    ! The bodies' mean translations, out of u.
    self%s = 0.0_dp
    do k = 1, size(self%eq)
      d = self%comp(k)
      if (d > 0) self%s(d, self%bod(k)) = self%s(d, self%bod(k)) + u(self%eq(k))
    end do
    do k = 1, size(self%eq)
      d = self%comp(k)
      b = self%bod(k)
      if (d == 0) cycle
      if (self%kern(d, b)) self%ur(self%eq(k)) = u(self%eq(k)) - self%s(d, b) * self%rn(d, b)
    end do
    call product(self, pat, kval, self%ur, f)
    ! The net force and moment of each body's elastic forces, out of f.
    self%s = 0.0_dp
    do k = 1, size(self%eq)
      i = self%eq(k)
      b = self%bod(k)
      d = self%comp(k)
      if (d > 0) self%s(d, b) = self%s(d, b) + f(i)
      do jr = 1, self%nrot
        self%s(self%ntr + jr, b) = self%s(self%ntr + jr, b) + self%q(k, jr) * f(i)
      end do
    end do
    do k = 1, size(self%eq)
      i = self%eq(k)
      b = self%bod(k)
      d = self%comp(k)
      if (d > 0) then
        if (self%kern(d, b)) f(i) = f(i) - self%s(d, b) * self%rn(d, b)
      end if
      do jr = 1, self%nrot
        f(i) = f(i) - self%s(self%ntr + jr, b) * self%q(k, jr)
      end do
    end do
    energy = 0.5_dp * dot_product(self%ur, f)
  end subroutine k0p_apply

  !> f = K0 x, by node blocks where they were built.
  subroutine product(self, pat, kval, x, f)
    type(k0_product_t), intent(in) :: self
    type(sym_csc_t), intent(in) :: pat
    real(dp), intent(in) :: kval(:), x(:)
    real(dp), intent(out) :: f(:)
    if (self%blk%active()) then
      call self%blk%matvec(x, f)
    else
      call pat%matvec(kval, x, f)
    end if
  end subroutine product

  pure logical function k0p_active(self)
    class(k0_product_t), intent(in) :: self
    k0p_active = self%on
  end function k0p_active

  !> Back to the element loop (check_k0_product: while it measures, or for good if the product does
  !> not reproduce the loop).
  pure subroutine k0p_disable(self)
    class(k0_product_t), intent(inout) :: self
    self%on = .false.
  end subroutine k0p_disable

  !> After a disable: the product again (set up already).
  pure subroutine k0p_enable(self)
    class(k0_product_t), intent(inout) :: self
    self%on = allocated(self%eq)
  end subroutine k0p_enable
end module stiffness_product
