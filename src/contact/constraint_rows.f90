!> The constraint rows of unilateral contact, one home for C (method.md section 3): condition j
!> is the gap g_j(u) = g0_j + c_j'u >= 0 over the free equations, c_j sparse. The rows are
!> stored by rows (CSR), each sorted by equation with repeated equations merged, so that the
!> contact corrections and the multiplier system (Schur columns, augmented KKT pattern) read
!> the same C. Built by add (any order, linear time) then finalize; read through the
!> procedures below, never written from outside.
module constraint_rows
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  implicit none
  private
  public :: constraint_rows_t, LABEL_LEN, MAX_REWRITE

  integer, parameter :: LABEL_LEN = 48
  integer, parameter :: MAX_REWRITE = 16      !< entries of a rewritten row (a node-to-segment row has 6)

  type :: constraint_rows_t
    private
    integer :: nc = 0                        !< conditions
    integer :: neq = 0                       !< free equations (set by finalize)
    logical :: final = .false.
    integer, allocatable :: ptr(:), eq(:)    !< c_j = Σ_{p = ptr(j)}^{ptr(j+1)-1} coef(p) e_eq(p)
    real(dp), allocatable :: coef(:), g0(:)
    real(dp), allocatable :: rest(:)         !< restitution coefficient e of each condition (1: elastic)
    integer, allocatable :: node(:, :)       !< (2, nc) node_a, node_b (0: rigid obstacle)
    character(len=LABEL_LEN), allocatable :: name(:)
  contains
    procedure :: add => rows_add
    procedure :: finalize => rows_finalize
    procedure :: n => rows_n
    procedure :: n_equations => rows_neq
    procedure :: first => rows_first
    procedure :: last => rows_last
    procedure :: eq_at => rows_eq_at
    procedure :: coef_at => rows_coef_at
    procedure :: gap0 => rows_gap0
    procedure :: set_gap0 => rows_set_gap0
    procedure :: rewrite => rows_rewrite
    procedure :: restitution => rows_restitution
    procedure :: nodes => rows_nodes
    procedure :: label => rows_label
    procedure :: dot => rows_dot
    procedure :: times => rows_times
    procedure :: gaps => rows_gaps
    procedure :: add_transpose => rows_add_transpose
    procedure :: scatter => rows_scatter
    procedure :: norm2_sq => rows_norm2_sq
  end type constraint_rows_t

contains

  !> Append the condition g0 + Σ coefs(k) u(eqs(k)) >= 0. Entries with eqs(k) <= 0 (supported
  !> or absent DOFs) or a zero coefficient are skipped. nodes = [node_a, node_b] and label name
  !> it in messages and results. Storage grows geometrically.
  pure subroutine rows_add(self, g0, eqs, coefs, nodes, label, restitution)
    class(constraint_rows_t), intent(inout) :: self
    real(dp), intent(in) :: g0
    integer, intent(in) :: eqs(:)
    real(dp), intent(in) :: coefs(:)
    integer, intent(in), optional :: nodes(2)
    character(len=*), intent(in), optional :: label
    real(dp), intent(in), optional :: restitution
    integer :: k, nz, nc
    if (.not. allocated(self%ptr)) call reserve(self, 16, 64)
    nc = self%nc + 1
    nz = self%ptr(self%nc + 1)
    call reserve(self, nc, nz - 1 + size(eqs))
    do k = 1, min(size(eqs), size(coefs))
      if (eqs(k) > 0 .and. coefs(k) /= 0.0_dp) then
        self%eq(nz) = eqs(k)
        self%coef(nz) = coefs(k)
        nz = nz + 1
      end if
    end do
    self%nc = nc
    self%ptr(nc + 1) = nz
    self%g0(nc) = g0
    self%rest(nc) = 1.0_dp
    if (present(restitution)) self%rest(nc) = restitution
    self%node(:, nc) = 0
    if (present(nodes)) self%node(:, nc) = nodes
    self%name(nc) = 'condition ' // str(nc)
    if (present(label)) self%name(nc) = label
    self%final = .false.
  end subroutine rows_add

  !> Room for nc conditions and nz entries (doubling).
  pure subroutine reserve(self, nc, nz)
    type(constraint_rows_t), intent(inout) :: self
    integer, intent(in) :: nc, nz
    integer, allocatable :: i1(:), i2(:, :)
    real(dp), allocatable :: r1(:)
    character(len=LABEL_LEN), allocatable :: l1(:)
    integer :: m
    if (.not. allocated(self%ptr)) then
      allocate (self%ptr(nc + 1), self%g0(nc), self%rest(nc), self%node(2, nc), self%name(nc), self%eq(nz), &
        self%coef(nz))
      self%ptr(1) = 1
      return
    end if
    if (size(self%g0) < nc) then
      m = max(nc, 2 * size(self%g0))
      allocate (i1(m + 1), r1(m), i2(2, m), l1(m))
      i1(1:self%nc + 1) = self%ptr(1:self%nc + 1)
      r1(1:self%nc) = self%g0(1:self%nc)
      i2(:, 1:self%nc) = self%node(:, 1:self%nc)
      l1(1:self%nc) = self%name(1:self%nc)
      call move_alloc(i1, self%ptr)
      call move_alloc(r1, self%g0)
      allocate (r1(m))
      r1(1:self%nc) = self%rest(1:self%nc)
      call move_alloc(r1, self%rest)
      call move_alloc(i2, self%node)
      call move_alloc(l1, self%name)
    end if
    if (size(self%eq) < nz) then
      m = max(nz, 2 * size(self%eq))
      allocate (i1(m), r1(m))
      i1(1:size(self%eq)) = self%eq
      r1(1:size(self%coef)) = self%coef
      call move_alloc(i1, self%eq)
      call move_alloc(r1, self%coef)
    end if
  end subroutine reserve

  !> Trim the growth reserve, sort each row by equation (merging repeats) and check the rows
  !> against neq free equations.
  pure subroutine rows_finalize(self, neq, stat, errmsg)
    class(constraint_rows_t), intent(inout) :: self
    integer, intent(in) :: neq
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: j, nz
    stat = STAT_OK
    if (.not. allocated(self%ptr)) call reserve(self, 0, 0)
    nz = self%ptr(self%nc + 1) - 1
    self%ptr = self%ptr(1:self%nc + 1)
    self%g0 = self%g0(1:self%nc)
    self%rest = self%rest(1:self%nc)
    self%node = self%node(:, 1:self%nc)
    self%name = self%name(1:self%nc)
    self%eq = self%eq(1:nz)
    self%coef = self%coef(1:nz)
    call sort_rows(self)
    do j = 1, self%nc
      if (any(self%eq(self%ptr(j):self%ptr(j + 1) - 1) > neq)) then
        call set_error(stat, errmsg, STAT_INPUT, 'contact: ' // trim(self%name(j)) // &
          ' refers to an equation beyond ' // str(neq))
        return
      end if
    end do
    self%neq = neq
    self%final = .true.
  end subroutine rows_finalize

  !> Each row sorted by equation, repeated equations summed (insertion sort: rows are short).
  pure subroutine sort_rows(self)
    type(constraint_rows_t), intent(inout) :: self
    integer :: j, p, q, n, k, start
    integer :: e
    real(dp) :: c
    integer, allocatable :: ptr(:)
    allocate (ptr(self%nc + 1))
    ptr(1) = 1
    do j = 1, self%nc
      start = ptr(j)
      n = 0
      do p = self%ptr(j), self%ptr(j + 1) - 1
        e = self%eq(p)
        c = self%coef(p)
        k = 0
        do q = start, start + n - 1
          if (self%eq(q) == e) k = q
        end do
        if (k > 0) then
          self%coef(k) = self%coef(k) + c
          cycle
        end if
        q = start + n - 1
        do while (q >= start)
          if (self%eq(q) < e) exit
          self%eq(q + 1) = self%eq(q)
          self%coef(q + 1) = self%coef(q)
          q = q - 1
        end do
        self%eq(q + 1) = e
        self%coef(q + 1) = c
        n = n + 1
      end do
      ptr(j + 1) = start + n
    end do
    call move_alloc(ptr, self%ptr)
    self%eq = self%eq(1:self%ptr(self%nc + 1) - 1)
    self%coef = self%coef(1:self%ptr(self%nc + 1) - 1)
  end subroutine sort_rows

  pure integer function rows_n(self)
    class(constraint_rows_t), intent(in) :: self
    rows_n = self%nc
  end function rows_n

  pure integer function rows_neq(self)
    class(constraint_rows_t), intent(in) :: self
    rows_neq = self%neq
  end function rows_neq

  !> Entries of row j are p = first(j) .. last(j).
  pure integer function rows_first(self, j)
    class(constraint_rows_t), intent(in) :: self
    integer, intent(in) :: j
    rows_first = self%ptr(j)
  end function rows_first

  pure integer function rows_last(self, j)
    class(constraint_rows_t), intent(in) :: self
    integer, intent(in) :: j
    rows_last = self%ptr(j + 1) - 1
  end function rows_last

  pure integer function rows_eq_at(self, p)
    class(constraint_rows_t), intent(in) :: self
    integer, intent(in) :: p
    rows_eq_at = self%eq(p)
  end function rows_eq_at

  pure real(dp) function rows_coef_at(self, p)
    class(constraint_rows_t), intent(in) :: self
    integer, intent(in) :: p
    rows_coef_at = self%coef(p)
  end function rows_coef_at

  !> A new g0_j (the bilateral rows of IMPOSE: minus the imposed value at the end of the step).
  pure subroutine rows_set_gap0(self, j, g0)
    class(constraint_rows_t), intent(inout) :: self
    integer, intent(in) :: j
    real(dp), intent(in) :: g0
    self%g0(j) = g0
  end subroutine rows_set_gap0

  !> Row j replaced by g0 + Σ coefs(k) u(eqs(k)), named by nodes (a contact whose geometry follows
  !> the configuration, contact_geometry): eqs(k) <= 0 or zero coefficients skipped, the entries
  !> sorted and merged as by finalize. Later rows move when the number of entries changes (the
  !> storage grows only past its largest size so far). At most MAX_REWRITE entries (fixed-size
  !> buffers: nothing allocated in the time loop).
  pure subroutine rows_rewrite(self, j, g0, eqs, coefs, nodes)
    class(constraint_rows_t), intent(inout) :: self
    integer, intent(in) :: j
    real(dp), intent(in) :: g0
    integer, intent(in) :: eqs(:)
    real(dp), intent(in) :: coefs(:)
    integer, intent(in) :: nodes(2)
    integer :: ne(MAX_REWRITE), k, q, n, shift, nz
    real(dp) :: nc(MAX_REWRITE)
    integer, allocatable :: i1(:)
    real(dp), allocatable :: r1(:)
    n = 0
    do k = 1, min(size(eqs), size(coefs), MAX_REWRITE)   ! insertion, merging repeats (rows are short)
      if (eqs(k) <= 0 .or. coefs(k) == 0.0_dp) cycle
      q = findloc(ne(1:n), eqs(k), 1)
      if (q > 0) then
        nc(q) = nc(q) + coefs(k)
        cycle
      end if
      q = n
      do while (q >= 1)
        if (ne(q) < eqs(k)) exit
        ne(q + 1) = ne(q)
        nc(q + 1) = nc(q)
        q = q - 1
      end do
      ne(q + 1) = eqs(k)
      nc(q + 1) = coefs(k)
      n = n + 1
    end do
    shift = n - (self%ptr(j + 1) - self%ptr(j))
    nz = self%ptr(self%nc + 1) - 1
    if (shift /= 0) then
      if (nz + shift > size(self%eq)) then
        allocate (i1(nz + shift + size(eqs)), r1(nz + shift + size(eqs)))
        i1(1:nz) = self%eq(1:nz)
        r1(1:nz) = self%coef(1:nz)
        call move_alloc(i1, self%eq)
        call move_alloc(r1, self%coef)
      end if
      if (shift > 0) then                  ! (element by element: no temporary for the overlap)
        do q = nz, self%ptr(j + 1), -1
          self%eq(q + shift) = self%eq(q)
          self%coef(q + shift) = self%coef(q)
        end do
      else
        do q = self%ptr(j + 1), nz
          self%eq(q + shift) = self%eq(q)
          self%coef(q + shift) = self%coef(q)
        end do
      end if
      self%ptr(j + 1:self%nc + 1) = self%ptr(j + 1:self%nc + 1) + shift
    end if
    self%eq(self%ptr(j):self%ptr(j + 1) - 1) = ne(1:n)
    self%coef(self%ptr(j):self%ptr(j + 1) - 1) = nc(1:n)
    self%g0(j) = g0
    self%node(:, j) = nodes
  end subroutine rows_rewrite

  pure real(dp) function rows_gap0(self, j)
    class(constraint_rows_t), intent(in) :: self
    integer, intent(in) :: j
    rows_gap0 = self%g0(j)
  end function rows_gap0

  pure real(dp) function rows_restitution(self, j)
    class(constraint_rows_t), intent(in) :: self
    integer, intent(in) :: j
    rows_restitution = self%rest(j)
  end function rows_restitution

  !> [node_a, node_b] of condition j (node_a = 0: a rigid obstacle).
  pure function rows_nodes(self, j) result(nodes)
    class(constraint_rows_t), intent(in) :: self
    integer, intent(in) :: j
    integer :: nodes(2)
    nodes = self%node(:, j)
  end function rows_nodes

  pure function rows_label(self, j) result(label)
    class(constraint_rows_t), intent(in) :: self
    integer, intent(in) :: j
    character(len=LABEL_LEN) :: label
    label = self%name(j)
  end function rows_label

  !> c_j'x.
  pure real(dp) function rows_dot(self, j, x) result(s)
    class(constraint_rows_t), intent(in) :: self
    integer, intent(in) :: j
    real(dp), intent(in) :: x(:)
    integer :: p
    s = 0.0_dp
    do p = self%ptr(j), self%ptr(j + 1) - 1
      s = s + self%coef(p) * x(self%eq(p))
    end do
  end function rows_dot

  !> cx = C x.
  pure subroutine rows_times(self, x, cx)
    class(constraint_rows_t), intent(in) :: self
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: cx(:)
    integer :: j
    do j = 1, self%nc
      cx(j) = self%dot(j, x)
    end do
  end subroutine rows_times

  !> g = g0 + C u.
  pure subroutine rows_gaps(self, u, g)
    class(constraint_rows_t), intent(in) :: self
    real(dp), intent(in) :: u(:)
    real(dp), intent(out) :: g(:)
    integer :: j
    do j = 1, self%nc
      g(j) = self%g0(j) + self%dot(j, u)
    end do
  end subroutine rows_gaps

  !> f <- f + C'mu (mu over all conditions; zero entries cost nothing).
  pure subroutine rows_add_transpose(self, mu, f)
    class(constraint_rows_t), intent(in) :: self
    real(dp), intent(in) :: mu(:)
    real(dp), intent(inout) :: f(:)
    integer :: j, p
    do j = 1, self%nc
      if (mu(j) == 0.0_dp) cycle
      do p = self%ptr(j), self%ptr(j + 1) - 1
        f(self%eq(p)) = f(self%eq(p)) + self%coef(p) * mu(j)
      end do
    end do
  end subroutine rows_add_transpose

  !> f(eq) = alpha * coef on the entries of row j (f elsewhere untouched): c_j into a zero
  !> vector, and alpha = 0 clears it again.
  pure subroutine rows_scatter(self, j, alpha, f)
    class(constraint_rows_t), intent(in) :: self
    integer, intent(in) :: j
    real(dp), intent(in) :: alpha
    real(dp), intent(inout) :: f(:)
    integer :: p
    do p = self%ptr(j), self%ptr(j + 1) - 1
      f(self%eq(p)) = merge(0.0_dp, alpha * self%coef(p), alpha == 0.0_dp)
    end do
  end subroutine rows_scatter

  !> c_j'c_j.
  pure real(dp) function rows_norm2_sq(self, j)
    class(constraint_rows_t), intent(in) :: self
    integer, intent(in) :: j
    rows_norm2_sq = sum(self%coef(self%ptr(j):self%ptr(j + 1) - 1)**2)
  end function rows_norm2_sq
end module constraint_rows
