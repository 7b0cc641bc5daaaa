!> The step multipliers of the contact conditions (docs/contact.md, "Multipliers"). For a trial
!> active set A the pivoting of lcp_pivot asks for Λ_A with g_A = 0 and the gaps
!> g = q + W Λ, W = C S⁻¹C' (S = K0 + 4M/h², the driver's iteration matrix), two ways:
!>   SCHUR      W_AA Λ_A = -q_A, dense (LAPACK pivoted Cholesky), from the columns
!>              z_j = S⁻¹c_j of the conditions of A. A column is computed (one solve with the
!>              driver's factor) when its condition first enters an active set and kept until S
!>              changes: the cost follows the contact zone, not the candidate set.
!>   AUGMENTED  [S  C_A'; C_A  0] [x; -Λ_A] = [0; -q_A] with a sparse LU (UMFPACK) of the KKT
!>              matrix. Its pattern holds every candidate (an inactive row has a zero coupling
!>              and a unit diagonal, so Λ_j = 0) and is analysed once; the numeric factorization
!>              is redone when the active set or S changes. No dense block, no column per
!>              condition: the choice for large active sets.
!>   AUTO       SCHUR while |A| <= switch_size, AUGMENTED above (switch measured in
!>              docs/performance.md).
!> Both give x = S⁻¹C'Λ, the correction of the step update. Dependent conditions make the KKT
!> matrix singular: that solve falls back to SCHUR, whose pivoted Cholesky drops them.
module contact_multipliers
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str
  use sparse_matrix, only: sym_csc_t
  use cholmod_binding, only: umfpack_factor_t
  use inverse_ops, only: inverse_op_t
  use lcp, only: active_system_t
  use dense_solve, only: spsd_solve_ws
  use constraint_rows, only: constraint_rows_t
  use contact_modes, only: SOLVER_AUTO, SOLVER_SCHUR, SOLVER_AUGMENTED, SWITCH_DEFAULT
  implicit none
  private
  public :: multiplier_system_t

  type, extends(active_system_t) :: multiplier_system_t
    integer :: nc = 0, neq = 0
    integer :: mode = SOLVER_AUTO
    integer :: switch_size = SWITCH_DEFAULT
    ! C and S⁻¹ are the contact set's: bound by the caller around each use (bind / unbind).
    type(constraint_rows_t), pointer :: c => null()
    class(inverse_op_t), pointer :: s => null()
    ! Schur columns: slot(j) holds z_j = zcol(:, slot(j)) and W(:, j) = wcol(:, slot(j)).
    integer :: cap = 0, nslot = 0, clock = 0
    real(dp), allocatable :: zcol(:, :), wcol(:, :)
    integer, allocatable :: slot(:), owner(:), used(:)
    ! Augmented system (order neq + nc): full CSC pattern and value positions.
    logical :: kkt_built = .false., kkt_factored = .false.
    type(umfpack_factor_t) :: lu
    integer, allocatable :: kptr(:), krow(:)
    real(dp), allocatable :: kval(:)
    integer, allocatable :: pos_s(:, :)             !< (2, nnz(S)): the upper and lower copies
    integer, allocatable :: pos_cr(:), pos_cc(:)    !< C entry p in row neq+j / in column neq+j
    integer, allocatable :: pos_d(:)                !< diagonal of row neq+j
    real(dp), allocatable :: dscale(:)              !< inactive diagonal: c'Sc / c'c (a stiffness)
    real(dp), allocatable :: wlow(:)                !< (c'c)²/(c'Sc) <= W_jj (tolerance scale)
    logical, allocatable :: kkt_set(:)              !< active set of the current factorization
    ! FRICTION (coulomb): pair(j) the tangential row of condition j (0: none), its entry (row neq +
    ! pair(j), column neq + j) at pos_p(j): a slipping row's equation Λ_t = ρ_t Λ_j; kkt_rho the ρ
    ! of the current factorization, no_rho all zero (no row slipping: the frictionless system).
    ! In 3D pair2(j), pos_p2(j): the second tangential row, likewise.
    integer, allocatable :: pair(:), pos_p(:), pair2(:), pos_p2(:)
    real(dp), allocatable :: kkt_rho(:), no_rho(:)
    ! The last solution.
    logical :: x_ok = .false.                       !< x = S⁻¹C'Λ of the last Λ
    real(dp), allocatable :: x(:)
    ! Workspaces.
    integer, allocatable :: ia(:), piv(:)
    real(dp), allocatable :: b(:), kb(:), kx(:), waa(:, :), ra(:), work(:)
    logical, allocatable :: dropped(:)
    ! Counters (docs/performance.md).
    integer(8) :: n_columns = 0, n_lu = 0, n_kkt = 0, n_schur = 0, n_singular = 0
  contains
    procedure :: bind => ms_bind
    procedure :: unbind => ms_unbind
    procedure :: init => ms_init
    procedure :: prepare => ms_prepare
    procedure :: solve_active => ms_solve_active
    procedure :: gaps => ms_gaps
    procedure :: correction => ms_correction
    procedure :: column => ms_column
    procedure :: ensure => ms_ensure
    procedure :: w_entry => ms_w_entry
    procedure :: w_block => ms_w_block
    procedure :: add_columns => ms_add_columns
    procedure :: set_pairs => ms_set_pairs
    procedure :: solve_coulomb => ms_solve_coulomb
    procedure :: destroy => ms_destroy
  end type multiplier_system_t

contains

  !> C and S⁻¹ for the calls that follow (rows must be finalized); unbind when done.
  subroutine ms_bind(self, rows, s)
    class(multiplier_system_t), intent(inout) :: self
    type(constraint_rows_t), intent(in), target :: rows
    class(inverse_op_t), intent(in), target, optional :: s
    self%c => rows
    if (present(s)) self%s => s
  end subroutine ms_bind

  subroutine ms_unbind(self)
    class(multiplier_system_t), intent(inout) :: self
    nullify (self%c, self%s)
  end subroutine ms_unbind

  !> The workspaces for the rows bound by ms_bind. cap0 = initial number of cached Schur
  !> columns (grows when an active set needs more).
  subroutine ms_init(self, cap0)
    class(multiplier_system_t), intent(inout) :: self
    integer, intent(in) :: cap0
    integer :: nc, neq
    type(constraint_rows_t), pointer :: c
    c => self%c
    call self%destroy()
    self%c => c
    nc = c%n()
    neq = c%n_equations()
    self%nc = nc
    self%neq = neq
    self%cap = max(1, min(nc, cap0))
    allocate (self%zcol(neq, self%cap), self%wcol(nc, self%cap), self%owner(self%cap), self%used(self%cap))
    allocate (self%slot(nc), self%ia(nc), self%ra(nc), self%dropped(nc), self%x(neq), self%b(neq))
    allocate (self%wlow(nc), self%dscale(nc), self%kkt_set(nc), self%piv(nc), self%work(2 * nc))
    self%slot = 0
    self%nslot = 0
    self%b = 0.0_dp
    self%x = 0.0_dp
    self%wlow = 1.0_dp
    allocate (self%waa(min(nc, 64), min(nc, 64)))   ! grows with the largest Schur active set
  end subroutine ms_init

  !> A new S: the Schur columns are dropped. With the pattern and values of S (upper CSC) the
  !> augmented system is built (once) and loaded, and the tolerance scales wlow are computed;
  !> without them only SCHUR is available.
  subroutine ms_prepare(self, stat, errmsg, pat, sval)
    class(multiplier_system_t), intent(inout) :: self
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(sym_csc_t), intent(in), optional :: pat
    real(dp), intent(in), optional :: sval(:)
    integer :: j, q
    real(dp) :: csc, cc
    stat = STAT_OK
    self%slot = 0
    self%nslot = 0
    self%x_ok = .false.
    self%kkt_factored = .false.
    if (.not. (present(pat) .and. present(sval))) then
      if (self%mode == SOLVER_AUGMENTED) call set_error(stat, errmsg, STAT_INPUT, &
        'contact: the augmented multiplier system needs the matrix S (pattern and values)')
      return
    end if
    ! SCHUR never reads the augmented system (and rows that follow the geometry change its pattern).
    if (.not. self%kkt_built .and. self%mode /= SOLVER_SCHUR) then
      call build_kkt(self, pat, stat, errmsg)
      if (stat /= STAT_OK) return
    end if
    if (self%kkt_built) then
      do q = 1, pat%nnz
        self%kval(self%pos_s(1, q)) = sval(q)
        self%kval(self%pos_s(2, q)) = sval(q)
      end do
    end if
    do j = 1, self%nc
      csc = c_s_c(self%c, pat, sval, j)
      cc = self%c%norm2_sq(j)
      self%dscale(j) = 1.0_dp
      self%wlow(j) = 1.0_dp
      if (cc > 0.0_dp .and. csc > 0.0_dp) then
        self%dscale(j) = csc / cc
        self%wlow(j) = cc**2 / csc
      end if
    end do
  end subroutine ms_prepare

  !> c_j' S c_j from the upper triangle of S (binary search in each column).
  pure real(dp) function c_s_c(c, pat, sval, j) result(r)
    type(constraint_rows_t), intent(in) :: c
    type(sym_csc_t), intent(in) :: pat
    real(dp), intent(in) :: sval(:)
    integer, intent(in) :: j
    integer :: p, q, a, b, k
    r = 0.0_dp
    do p = c%first(j), c%last(j)
      do q = c%first(j), c%last(j)
        a = min(c%eq_at(p), c%eq_at(q))
        b = max(c%eq_at(p), c%eq_at(q))
        k = find_row(pat%rowind, pat%colptr(b), pat%colptr(b + 1) - 1, a)
        if (k > 0) r = r + c%coef_at(p) * c%coef_at(q) * sval(k)
      end do
    end do
  end function c_s_c

  !> Position of row r in rowind(lo:hi) (sorted), 0 if absent.
  pure integer function find_row(rowind, lo, hi, r) result(k)
    integer, intent(in) :: rowind(:), lo, hi, r
    integer :: a, b, m
    k = 0
    a = lo
    b = hi
    do while (a <= b)
      m = (a + b) / 2
      if (rowind(m) == r) then
        k = m
        return
      else if (rowind(m) < r) then
        a = m + 1
      else
        b = m - 1
      end if
    end do
  end function find_row

  !> Full CSC pattern of [S C'; C D] (S from its upper triangle, every candidate row), the value
  !> positions, and the symbolic analysis.
  subroutine build_kkt(self, pat, stat, errmsg)
    class(multiplier_system_t), intent(inout) :: self
    type(sym_csc_t), intent(in) :: pat
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, allocatable :: cnt(:), fill(:), cptr(:), crow(:), cown(:)
    integer :: n, neq, nc, i, k, q, r, j, p, nnz, nzc
    neq = self%neq
    nc = self%nc
    n = neq + nc
    if (pat%n /= neq) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact: S has ' // str(pat%n) // ' equations, C ' // str(neq))
      return
    end if
    ! C' by columns of the equations: the conditions touching each equation, in order.
    nzc = 0
    if (nc > 0) nzc = self%c%last(nc)
    allocate (cnt(neq + 1))
    cnt = 0
    do p = 1, nzc
      cnt(self%c%eq_at(p) + 1) = cnt(self%c%eq_at(p) + 1) + 1
    end do
    allocate (cptr(neq + 1), crow(nzc), cown(nzc))
    cptr(1) = 1
    do i = 1, neq
      cptr(i + 1) = cptr(i) + cnt(i + 1)
    end do
    fill = cptr(1:neq)
    do j = 1, nc
      do p = self%c%first(j), self%c%last(j)
        crow(fill(self%c%eq_at(p))) = p
        cown(fill(self%c%eq_at(p))) = j
        fill(self%c%eq_at(p)) = fill(self%c%eq_at(p)) + 1
      end do
    end do
    ! Column counts: upper part + lower part (transposed) + C' entries; then C rows + diagonal.
    allocate (self%kptr(n + 1))
    self%kptr = 0
    do k = 1, neq
      do q = pat%colptr(k), pat%colptr(k + 1) - 1
        r = pat%rowind(q)
        self%kptr(k + 1) = self%kptr(k + 1) + 1
        if (r /= k) self%kptr(r + 1) = self%kptr(r + 1) + 1
      end do
      self%kptr(k + 1) = self%kptr(k + 1) + (cptr(k + 1) - cptr(k))
    end do
    if (.not. allocated(self%pair)) then
      allocate (self%pair(nc))
      self%pair = 0
    end if
    if (.not. allocated(self%pair2)) then
      allocate (self%pair2(nc))
      self%pair2 = 0
    end if
    do j = 1, nc
      self%kptr(neq + j + 1) = self%c%last(j) - self%c%first(j) + 2 + merge(1, 0, self%pair(j) > 0) + &
        merge(1, 0, self%pair2(j) > 0)
    end do
    self%kptr(1) = 1
    do i = 1, n
      self%kptr(i + 1) = self%kptr(i) + self%kptr(i + 1)
    end do
    nnz = self%kptr(n + 1) - 1
    allocate (self%krow(nnz), self%kval(nnz), self%pos_s(2, pat%nnz), self%pos_cr(nzc), &
      self%pos_cc(nzc), self%pos_d(nc), self%pos_p(nc), self%pos_p2(nc), self%kkt_rho(nc), self%no_rho(nc))
    self%pos_p = 0
    self%pos_p2 = 0
    self%kkt_rho = 0.0_dp
    self%no_rho = 0.0_dp
    self%kval = 0.0_dp
    fill = self%kptr(1:neq)
    ! Column r: its upper rows (<= r, ascending in sym_csc_t) are placed when k = r, its lower
    ! rows k > r later in ascending k, then the conditions (rows > neq): sorted, as UMFPACK needs.
    do k = 1, neq
      do q = pat%colptr(k), pat%colptr(k + 1) - 1
        r = pat%rowind(q)
        self%krow(fill(k)) = r
        self%pos_s(1, q) = fill(k)
        fill(k) = fill(k) + 1
        if (r /= k) then
          self%krow(fill(r)) = k
          self%pos_s(2, q) = fill(r)
          fill(r) = fill(r) + 1
        else
          self%pos_s(2, q) = self%pos_s(1, q)
        end if
      end do
    end do
    do i = 1, neq
      do k = cptr(i), cptr(i + 1) - 1
        p = crow(k)
        self%krow(fill(i)) = neq + cown(k)
        self%pos_cr(p) = fill(i)
        fill(i) = fill(i) + 1
      end do
    end do
    do j = 1, nc
      k = self%kptr(neq + j)
      do p = self%c%first(j), self%c%last(j)
        self%krow(k) = self%c%eq_at(p)
        self%pos_cc(p) = k
        k = k + 1
      end do
      self%krow(k) = neq + j
      self%pos_d(j) = k
      if (self%pair(j) > 0) then               ! (a tangential row comes after every contact's)
        self%krow(k + 1) = neq + self%pair(j)
        self%pos_p(j) = k + 1
      end if
      if (self%pair2(j) > 0) then              ! (3D: the second, right after the first)
        self%krow(k + 2) = neq + self%pair2(j)
        self%pos_p2(j) = k + 2
      end if
    end do
    call self%lu%analyze(n, self%kptr, self%krow, stat, errmsg)
    if (stat /= STAT_OK) then
      errmsg = 'contact: augmented system: ' // errmsg
      return
    end if
    allocate (self%kb(n), self%kx(n))
    self%kkt_built = .true.
  end subroutine build_kkt

  !> lcp_pivot's trial solve (see active_system_t).
  subroutine ms_solve_active(self, q, active, lam, g, wdiag, stat, errmsg)
    class(multiplier_system_t), intent(inout) :: self
    real(dp), intent(in) :: q(:)
    logical, intent(inout) :: active(:)
    real(dp), intent(out) :: lam(:), g(:)
    real(dp), intent(inout) :: wdiag(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical :: singular
    integer :: na
    stat = STAT_OK
    na = count(active)
    if (na == 0) then
      lam = 0.0_dp
      g = q
      self%x = 0.0_dp
      self%x_ok = .true.
      return
    end if
    if (self%kkt_built .and. (self%mode == SOLVER_AUGMENTED .or. &
      (self%mode == SOLVER_AUTO .and. na > self%switch_size))) then
      call kkt_solve(self, q, active, lam, g, wdiag, singular, stat, errmsg)
      if (stat /= STAT_OK .or. .not. singular) return
      self%n_singular = self%n_singular + 1           ! dependent conditions: SCHUR drops them
    end if
    call schur_solve(self, q, active, lam, g, wdiag, stat, errmsg)
  end subroutine ms_solve_active

  !> SCHUR: W_AA Λ_A = -q_A from the cached columns; dependent rows leave A.
  subroutine schur_solve(self, q, active, lam, g, wdiag, stat, errmsg)
    class(multiplier_system_t), intent(inout) :: self
    real(dp), intent(in) :: q(:)
    logical, intent(inout) :: active(:)
    real(dp), intent(out) :: lam(:), g(:)
    real(dp), intent(inout) :: wdiag(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: na, j, k, l, rank, m
    na = 0
    do j = 1, self%nc
      if (.not. active(j)) cycle
      na = na + 1
      self%ia(na) = j
    end do
    call ensure_columns(self, active, na, stat, errmsg)
    if (stat /= STAT_OK) return
    self%n_schur = self%n_schur + 1
    if (size(self%waa, 1) < na) then                   ! grow past the high-water mark
      m = max(na, 2 * size(self%waa, 1))
      deallocate (self%waa)
      allocate (self%waa(m, m))
    end if
    do l = 1, na
      do k = 1, na
        self%waa(k, l) = 0.5_dp * (self%wcol(self%ia(k), self%slot(self%ia(l))) + &
          self%wcol(self%ia(l), self%slot(self%ia(k))))
      end do
      self%ra(l) = -q(self%ia(l))
    end do
    call spsd_solve_ws(na, self%waa, self%ra, rank, self%piv, self%work, self%dropped)
    lam = 0.0_dp
    g = q
    do k = 1, na
      j = self%ia(k)
      wdiag(j) = self%wcol(j, self%slot(j))
      if (self%dropped(k)) then
        active(j) = .false.
        cycle
      end if
      lam(j) = self%ra(k)
      g = g + lam(j) * self%wcol(:, self%slot(j))
    end do
    self%x_ok = .false.
  end subroutine schur_solve

  !> Columns z_j = S⁻¹c_j and W(:, j) = C z_j for the conditions ia(1:na). A free slot, or the
  !> least recently used one of an inactive condition; the cache grows when A needs more.
  subroutine ensure_columns(self, active, na, stat, errmsg)
    class(multiplier_system_t), intent(inout) :: self
    logical, intent(in) :: active(:)
    integer, intent(in) :: na
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, j, sl, m
    stat = STAT_OK
    self%clock = self%clock + 1
    do k = 1, na
      j = self%ia(k)
      if (self%slot(j) > 0) then
        self%used(self%slot(j)) = self%clock
        cycle
      end if
      if (self%nslot < self%cap) then
        self%nslot = self%nslot + 1
        sl = self%nslot
      else
        sl = 0
        do m = 1, self%cap
          if (active(self%owner(m))) cycle
          if (sl == 0) then
            sl = m
          else if (self%used(m) < self%used(sl)) then
            sl = m
          end if
        end do
        if (sl == 0) then
          call grow_cache(self)
          self%nslot = self%nslot + 1
          sl = self%nslot
        else
          self%slot(self%owner(sl)) = 0
        end if
      end if
      call self%column(j, self%zcol(:, sl), stat, errmsg)
      if (stat /= STAT_OK) return
      call self%c%times(self%zcol(:, sl), self%wcol(:, sl))
      self%slot(j) = sl
      self%owner(sl) = j
      self%used(sl) = self%clock
    end do
  end subroutine ensure_columns

  !> The columns W(:, j) of the rows rows(1:n) in the cache (one solve each that is not there
  !> yet), not evicting those of keep (coulomb's solver reads them through w_entry).
  subroutine ms_ensure(self, rows, n, keep, stat, errmsg)
    class(multiplier_system_t), intent(inout) :: self
    integer, intent(in) :: rows(:), n
    logical, intent(in) :: keep(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    self%ia(1:n) = rows(1:n)
    call ensure_columns(self, keep, n, stat, errmsg)
    self%x_ok = .false.
  end subroutine ms_ensure

  !> W_ij for a row j whose column is in the cache (ms_ensure).
  pure real(dp) function ms_w_entry(self, i, j) result(w)
    class(multiplier_system_t), intent(in) :: self
    integer, intent(in) :: i, j
    w = self%wcol(i, self%slot(j))
  end function ms_w_entry

  !> w(1:n, l) = W(rows(1:n), cols(l)), l = 1..m, for rows whose columns are in the cache.
  pure subroutine ms_w_block(self, rows, n, cols, m, w)
    class(multiplier_system_t), intent(in) :: self
    integer, intent(in) :: rows(:), n, cols(:), m
    real(dp), intent(inout) :: w(:, :)
    integer :: k, l, sl
    do l = 1, m
      sl = self%slot(cols(l))
      do k = 1, n
        w(k, l) = self%wcol(rows(k), sl)
      end do
    end do
  end subroutine ms_w_block

  !> g <- g + Σ_l lam(cols(l)) W(:, cols(l)) over cached columns.
  pure subroutine ms_add_columns(self, cols, m, lam, g)
    class(multiplier_system_t), intent(in) :: self
    integer, intent(in) :: cols(:), m
    real(dp), intent(in) :: lam(:)
    real(dp), intent(inout) :: g(:)
    integer :: l, sl
    do l = 1, m
      if (lam(cols(l)) == 0.0_dp) cycle
      sl = self%slot(cols(l))
      g = g + lam(cols(l)) * self%wcol(:, sl)
    end do
  end subroutine ms_add_columns

  !> z = S⁻¹c_j (one solve with the driver's factor).
  subroutine ms_column(self, j, z, stat, errmsg)
    class(multiplier_system_t), intent(inout) :: self
    integer, intent(in) :: j
    real(dp), intent(out), contiguous :: z(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    if (.not. associated(self%s)) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact: no S operator for the multipliers')
      return
    end if
    call self%c%scatter(j, 1.0_dp, self%b)
    call self%s%apply(self%b, z, stat, errmsg)
    call self%c%scatter(j, 0.0_dp, self%b)
    self%n_columns = self%n_columns + 1
  end subroutine ms_column

  subroutine grow_cache(self)
    class(multiplier_system_t), intent(inout) :: self
    real(dp), allocatable :: z(:, :), w(:, :)
    integer, allocatable :: o(:), u(:)
    integer :: c
    c = min(self%nc, 2 * self%cap)
    allocate (z(self%neq, c), w(self%nc, c), o(c), u(c))
    z(:, 1:self%cap) = self%zcol
    w(:, 1:self%cap) = self%wcol
    o(1:self%cap) = self%owner
    u(1:self%cap) = self%used
    call move_alloc(z, self%zcol)
    call move_alloc(w, self%wcol)
    call move_alloc(o, self%owner)
    call move_alloc(u, self%used)
    self%cap = c
  end subroutine grow_cache

  !> AUGMENTED: refactorize if A or S changed, then one solve. singular: the factorization
  !> found dependent conditions (nothing computed; the caller falls back).
  subroutine kkt_solve(self, q, active, lam, g, wdiag, singular, stat, errmsg)
    class(multiplier_system_t), intent(inout) :: self
    real(dp), intent(in) :: q(:)
    logical, intent(inout) :: active(:)
    real(dp), intent(out) :: lam(:), g(:)
    real(dp), intent(inout) :: wdiag(:)
    logical, intent(out) :: singular
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call ms_solve_coulomb(self, q, active, self%no_rho, lam, g, singular, stat, errmsg)
    if (stat == STAT_OK .and. .not. singular) wdiag = self%wlow
  end subroutine kkt_solve

  !> The numeric factorization of the augmented system with its values loaded (kkt_solve,
  !> solve_coulomb); singular: dependent rows (stat OK, nothing factorized).
  subroutine kkt_factorize(self, singular, stat, errmsg)
    class(multiplier_system_t), intent(inout) :: self
    logical, intent(out) :: singular
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    self%kkt_factored = .false.
    call self%lu%factorize(self%kval, stat, errmsg, singular)
    self%n_lu = self%n_lu + 1
    if (singular) then
      stat = STAT_OK
    else if (stat /= STAT_OK) then
      errmsg = 'contact: augmented system: ' // errmsg
    end if
  end subroutine kkt_factorize

  !> FRICTION: pair(j), the tangential row of condition j (0: none), and in 3D pair2(j) the second,
  !> for the augmented system's pattern (before its first prepare).
  subroutine ms_set_pairs(self, pair, pair2)
    class(multiplier_system_t), intent(inout) :: self
    integer, intent(in) :: pair(:)
    integer, intent(in), optional :: pair2(:)
    if (allocated(self%pair)) deallocate (self%pair)
    if (allocated(self%pair2)) deallocate (self%pair2)
    allocate (self%pair, source=pair)
    allocate (self%pair2(size(pair)))
    self%pair2 = 0
    if (present(pair2)) self%pair2 = pair2
  end subroutine ms_set_pairs

  !> The step on the augmented system (kkt_solve: no row slipping; FRICTION's coulomb on large
  !> contact zones): the rows on(j) hold
  !> their gap (g_j = 0), a row with rho(t) /= 0 carries Λ_t = rho(t) Λ_j of its contact j (its
  !> force acts, its gap is free: [d, -rho d] in its row), the others Λ = 0; refactorized (UMFPACK,
  !> nonsymmetric) when on or rho changed. lam, g = q + C x, x = S⁻¹C'Λ kept for ms_correction;
  !> singular: dependent rows (nothing computed, the caller falls back to the Schur columns).
  !> force: known multipliers of rows neither on nor tied (3D friction's slipping rows with their
  !> forces given: the right-hand side C'force, the factor of on and rho kept); lam = force there.
  subroutine ms_solve_coulomb(self, q, on, rho, lam, g, singular, stat, errmsg, force)
    class(multiplier_system_t), intent(inout) :: self
    real(dp), intent(in) :: q(:), rho(:)
    logical, intent(in) :: on(:)
    real(dp), intent(out) :: lam(:), g(:)
    logical, intent(out) :: singular
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), intent(in), optional :: force(:)
    integer :: j, p, neq
    logical :: same, acts
    neq = self%neq
    singular = .false.
    stat = STAT_OK
    same = self%kkt_factored
    if (same) same = all(on .eqv. self%kkt_set) .and. all(rho == self%kkt_rho)
    if (.not. same) then
      do j = 1, self%nc
        acts = on(j) .or. rho(j) /= 0.0_dp
        do p = self%c%first(j), self%c%last(j)
          self%kval(self%pos_cr(p)) = merge(self%c%coef_at(p), 0.0_dp, on(j))
          self%kval(self%pos_cc(p)) = merge(self%c%coef_at(p), 0.0_dp, acts)
        end do
        self%kval(self%pos_d(j)) = merge(0.0_dp, self%dscale(j), on(j))
        if (self%pos_p(j) > 0) self%kval(self%pos_p(j)) = -rho(self%pair(j)) * self%dscale(self%pair(j))
        if (self%pos_p2(j) > 0) self%kval(self%pos_p2(j)) = -rho(self%pair2(j)) * self%dscale(self%pair2(j))
      end do
      call kkt_factorize(self, singular, stat, errmsg)
      if (singular .or. stat /= STAT_OK) return
      self%kkt_set = on
      self%kkt_rho = rho
      self%kkt_factored = .true.
    end if
    self%kb(1:neq) = 0.0_dp
    if (present(force)) call self%c%add_transpose(force, self%kb(1:neq))
    do j = 1, self%nc
      self%kb(neq + j) = merge(-q(j), 0.0_dp, on(j))
    end do
    call self%lu%solve(self%kb, self%kx, stat, errmsg)
    if (stat /= STAT_OK) return
    self%n_kkt = self%n_kkt + 1
    self%x = self%kx(1:neq)
    self%x_ok = .true.
    do j = 1, self%nc
      lam(j) = merge(-self%kx(neq + j), 0.0_dp, on(j) .or. rho(j) /= 0.0_dp)
    end do
    if (present(force)) then                   ! (a loop: a WHERE would allocate its mask)
      do j = 1, self%nc
        if (.not. on(j) .and. rho(j) == 0.0_dp) lam(j) = force(j)
      end do
    end if
    call self%c%times(self%x, g)
    g = q + g
  end subroutine ms_solve_coulomb

  !> g = q + W lam, with x = S⁻¹C'lam kept for ms_correction.
  subroutine ms_gaps(self, q, lam, g, stat, errmsg)
    class(multiplier_system_t), intent(inout) :: self
    real(dp), intent(in) :: q(:), lam(:)
    real(dp), intent(out) :: g(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call apply_minv_ct(self, lam, stat, errmsg)
    if (stat /= STAT_OK) return
    call self%c%times(self%x, g)
    g = q + g
  end subroutine ms_gaps

  !> x = S⁻¹C'lam for the multiplier lcp_pivot accepted last.
  subroutine ms_correction(self, lam, x, stat, errmsg)
    class(multiplier_system_t), intent(inout) :: self
    real(dp), intent(in) :: lam(:)
    real(dp), intent(out) :: x(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    if (.not. self%x_ok) call apply_minv_ct(self, lam, stat, errmsg)
    if (stat /= STAT_OK) return
    x = self%x
  end subroutine ms_correction

  !> self%x = S⁻¹C'lam: from the cached columns when they cover lam, else one solve.
  subroutine apply_minv_ct(self, lam, stat, errmsg)
    class(multiplier_system_t), intent(inout) :: self
    real(dp), intent(in) :: lam(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: j
    logical :: cached
    stat = STAT_OK
    cached = .true.
    do j = 1, self%nc
      if (lam(j) /= 0.0_dp .and. self%slot(j) == 0) cached = .false.
    end do
    self%x = 0.0_dp
    if (cached) then
      do j = 1, self%nc
        if (lam(j) /= 0.0_dp) self%x = self%x + lam(j) * self%zcol(:, self%slot(j))
      end do
    else
      if (.not. associated(self%s)) then
        call set_error(stat, errmsg, STAT_INPUT, 'contact: no S operator for the multipliers')
        return
      end if
      self%b = 0.0_dp
      call self%c%add_transpose(lam, self%b)
      call self%s%apply(self%b, self%x, stat, errmsg)
      self%b = 0.0_dp
      if (stat /= STAT_OK) return
    end if
    self%x_ok = .true.
  end subroutine apply_minv_ct

  subroutine ms_destroy(self)
    class(multiplier_system_t), intent(inout) :: self
    call self%lu%destroy()
    if (allocated(self%zcol)) deallocate (self%zcol, self%wcol, self%owner, self%used)
    if (allocated(self%slot)) deallocate (self%slot, self%ia, self%ra, self%dropped, self%x, self%b, &
      self%wlow, self%dscale, self%kkt_set, self%piv, self%work)
    if (allocated(self%waa)) deallocate (self%waa)
    if (allocated(self%kptr)) deallocate (self%kptr)
    if (allocated(self%krow)) deallocate (self%krow, self%kval, self%pos_s, self%pos_cr, self%pos_cc, self%pos_d, &
      self%pos_p, self%pos_p2, self%kkt_rho, self%no_rho)
    if (allocated(self%kb)) deallocate (self%kb, self%kx)
    if (allocated(self%pair)) deallocate (self%pair)
    if (allocated(self%pair2)) deallocate (self%pair2)
    self%kkt_built = .false.
    self%kkt_factored = .false.
    self%nc = 0
    self%cap = 0
    self%nslot = 0
    call self%unbind()
  end subroutine ms_destroy
end module contact_multipliers
