!> A symmetric sparse matrix stored by 2 × 2 blocks on the equation pairs (2b-1, 2b), for the
!> products a linear step forms (K0 u, M v; issue 14). Equations are numbered node by node
!> (dof_map), so on a 2D solid whose nodes have both UX and UY free a pair is a node and a block
!> is the node-node coupling: one index read per four values instead of one per value, and the
!> symmetric product's scatter touches y two entries at a time. Measured on the QUAD4 plates of
!> `make bench` (minimum CPU time of the product alone, docs/performance.md): K0 u 101–139 → 47–77
!> µs at 1e4 DOFs, 1.26–1.54 → 0.84–0.88 ms at 1e5.
!>
!> Where the pairs are not nodes (a roller shifts the numbering, beams carry RZ) blocks hold
!> zeros: build leaves the matrix off (active() false, the caller keeps sym_csc_t%matvec) when the
!> blocks would store more than MAX_FILL times the matrix's entries. A matrix whose every block is
!> m I (a consistent mass of surface or bar elements: no x-y coupling, the same m for UX and UY)
!> keeps one value per block, and its product is the scalar one bit for bit (the same terms in
!> the same order). An odd last equation is one scalar column. No allocation after build.
module pair_blocks
  use kinds, only: dp
  use sparse_matrix, only: sym_csc_t
  implicit none
  private
  public :: pair_block_t

  !> Stored values over the matrix's own entries (upper triangle) above which blocks are not used.
  real(dp), parameter :: MAX_FILL = 1.25_dp

  type :: pair_block_t
    private
    logical :: on = .false.
    logical :: iso = .false.               !< every block is m I: one value per block
    integer :: n = 0, nb = 0               !< equations; pairs (n/2)
    integer, allocatable :: bptr(:)        !< (nb+1) blocks of block column J; the diagonal block last
    integer, allocatable :: brow(:)        !< block rows I <= J, increasing
    real(dp), allocatable :: a(:, :)       !< (4, nblocks) column-major 2 × 2 blocks (A(I, J)), or (1, :) with iso
    integer, allocatable :: trow(:)        !< the last column's rows and values when n is odd
    real(dp), allocatable :: tval(:)
  contains
    procedure :: build => pb_build
    procedure :: matvec => pb_matvec
    procedure :: active => pb_active
  end type pair_block_t

contains

  !> The blocks of the matrix values on pat. Leaves the matrix off when blocks do not pay (fill).
  subroutine pb_build(self, pat, values)
    class(pair_block_t), intent(out) :: self
    type(sym_csc_t), intent(in) :: pat
    real(dp), intent(in) :: values(:)
    integer, allocatable :: mark(:)
    integer :: nblk, bj, j, k, bi, nsq, covered
    self%n = pat%n
    self%nb = pat%n / 2
    if (self%nb == 0) return
    allocate (mark(self%nb), self%bptr(self%nb + 1))
    ! Block pattern: the distinct pairs of the rows of columns 2J-1 and 2J (increasing: the rows
    ! of a column are, and the two columns' merge is taken in order below).
    mark = 0
    nblk = 0
    covered = 0
    self%bptr(1) = 1
    do bj = 1, self%nb
      do j = 2 * bj - 1, 2 * bj
        do k = pat%colptr(j), pat%colptr(j + 1) - 1
          bi = (pat%rowind(k) + 1) / 2
          covered = covered + 1
          if (mark(bi) /= bj) then
            mark(bi) = bj
            nblk = nblk + 1
          end if
        end do
      end do
      self%bptr(bj + 1) = nblk + 1
    end do
    allocate (self%brow(nblk), self%a(4, nblk))
    call fill_blocks(self, pat, values, mark)
    call make_iso(self)
    ! Values stored against the matrix's: 1 per m I block, else 4 per block (3 on the diagonal).
    nsq = nblk
    if (.not. self%iso) nsq = 4 * (nblk - self%nb) + 3 * self%nb
    if (real(nsq, dp) > MAX_FILL * real(covered, dp)) then
      deallocate (self%bptr, self%brow, self%a)
      return
    end if
    call odd_column(self, pat, values)
    self%on = .true.
  end subroutine pb_build

  !> Block rows and values. mark(I) is reused as the position of block row I in the current
  !> block column.
  subroutine fill_blocks(self, pat, values, mark)
    type(pair_block_t), intent(inout) :: self
    type(sym_csc_t), intent(in) :: pat
    real(dp), intent(in) :: values(:)
    integer, intent(inout) :: mark(:)
    integer :: bj, j, k, i, bi, p, q
    mark = 0
    self%a = 0.0_dp
    do bj = 1, self%nb
      ! Rows of the pair, in increasing block row: merge of the two columns' block rows.
      p = self%bptr(bj) - 1
      call merge_rows(pat, 2 * bj - 1, 2 * bj, self%brow, p)
      do q = self%bptr(bj), self%bptr(bj + 1) - 1
        mark(self%brow(q)) = q
      end do
      do j = 2 * bj - 1, 2 * bj
        do k = pat%colptr(j), pat%colptr(j + 1) - 1
          i = pat%rowind(k)
          bi = (i + 1) / 2
          q = mark(bi)
          self%a(1 + (1 - mod(i, 2)) + 2 * (1 - mod(j, 2)), q) = values(k)
          ! The diagonal block holds both triangles: (2J, 2J-1) mirrors (2J-1, 2J).
          if (bi == bj .and. i /= j) self%a(2, q) = values(k)
        end do
      end do
    end do
  end subroutine fill_blocks

  !> The increasing block rows of columns j1 and j2 (each increasing), appended after brow(p).
  pure subroutine merge_rows(pat, j1, j2, brow, p)
    type(sym_csc_t), intent(in) :: pat
    integer, intent(in) :: j1, j2
    integer, intent(inout) :: brow(:), p
    integer :: k1, k2, e1, e2, b, p0
    p0 = p
    k1 = pat%colptr(j1)
    e1 = pat%colptr(j1 + 1) - 1
    k2 = pat%colptr(j2)
    e2 = pat%colptr(j2 + 1) - 1
    do while (k1 <= e1 .or. k2 <= e2)
      if (k2 > e2) then
        b = (pat%rowind(k1) + 1) / 2
        k1 = k1 + 1
      else if (k1 > e1) then
        b = (pat%rowind(k2) + 1) / 2
        k2 = k2 + 1
      else if (pat%rowind(k1) <= pat%rowind(k2)) then
        b = (pat%rowind(k1) + 1) / 2
        k1 = k1 + 1
      else
        b = (pat%rowind(k2) + 1) / 2
        k2 = k2 + 1
      end if
      if (p > p0) then
        if (brow(p) == b) cycle
      end if
      p = p + 1
      brow(p) = b
    end do
  end subroutine merge_rows

  !> An odd n: the last equation's column (every entry of that equation, upper triangle).
  subroutine odd_column(self, pat, values)
    type(pair_block_t), intent(inout) :: self
    type(sym_csc_t), intent(in) :: pat
    real(dp), intent(in) :: values(:)
    integer :: k0, k1
    if (mod(self%n, 2) == 0) return
    k0 = pat%colptr(self%n)
    k1 = pat%colptr(self%n + 1) - 1
    self%trow = pat%rowind(k0:k1)
    self%tval = values(k0:k1)
  end subroutine odd_column

  !> One value per block when every block is m I (exact comparison: a consistent mass's blocks are).
  subroutine make_iso(self)
    type(pair_block_t), intent(inout) :: self
    real(dp), allocatable :: m(:, :)
    integer :: q
    do q = 1, size(self%brow)
      if (self%a(2, q) /= 0.0_dp .or. self%a(3, q) /= 0.0_dp .or. self%a(1, q) /= self%a(4, q)) return
    end do
    allocate (m(1, size(self%brow)))
    m(1, :) = self%a(1, :)
    call move_alloc(m, self%a)
    self%iso = .true.
  end subroutine make_iso

  !> y = A x (active() only). No allocation.
  subroutine pb_matvec(self, x, y)
    class(pair_block_t), intent(in) :: self
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: y(:)
    integer :: k
    real(dp) :: s, xn
    y(1:self%n) = 0.0_dp
    if (self%iso) then
      call product_iso(self%nb, self%bptr, self%brow, self%a, x, y)
    else
      call product_full(self%nb, self%bptr, self%brow, self%a, x(1:2 * self%nb), y(1:2 * self%nb))
    end if
    if (mod(self%n, 2) == 0) return
    xn = x(self%n)
    s = 0.0_dp
    do k = 1, size(self%trow) - 1
      y(self%trow(k)) = y(self%trow(k)) + self%tval(k) * xn
      s = s + self%tval(k) * x(self%trow(k))
    end do
    k = size(self%trow)
    y(self%n) = y(self%n) + s + self%tval(k) * xn
  end subroutine pb_matvec

  !> y += A x over the pairs, A's blocks a(1:4, :) = (A11, A21, A12, A22); x and y seen as (2, nb)
  !> (pair b in column b), which lets the compiler do each block's two rows together (measured 25 %
  !> faster than the scalar-indexed loop on the 1e4-DOF plate, the same sums).
  pure subroutine product_full(nb, bptr, brow, a, x, y)
    integer, intent(in) :: nb, bptr(:), brow(:)
    real(dp), intent(in) :: a(:, :), x(2, nb)
    real(dp), intent(inout) :: y(2, nb)
    integer :: bj, q, i, kd
    real(dp) :: xj(2), s(2)
    do bj = 1, nb
      xj = x(:, bj)
      s = 0.0_dp
      kd = bptr(bj + 1) - 1                 ! the diagonal block is the column's last
      do q = bptr(bj), kd - 1
        i = brow(q)
        y(:, i) = y(:, i) + a(1:2, q) * xj(1) + a(3:4, q) * xj(2)
        s(1) = s(1) + a(1, q) * x(1, i) + a(2, q) * x(2, i)
        s(2) = s(2) + a(3, q) * x(1, i) + a(4, q) * x(2, i)
      end do
      y(:, bj) = y(:, bj) + s + (a(1:2, kd) * xj(1) + a(3:4, kd) * xj(2))
    end do
  end subroutine product_full

  !> The same for blocks m I, a(1, :) = m.
  pure subroutine product_iso(nb, bptr, brow, a, x, y)
    integer, intent(in) :: nb, bptr(:), brow(:)
    real(dp), intent(in) :: a(:, :), x(:)
    real(dp), intent(inout) :: y(:)
    integer :: bj, q, i, kd
    real(dp) :: x1, x2, s1, s2, m
    do bj = 1, nb
      x1 = x(2 * bj - 1)
      x2 = x(2 * bj)
      s1 = 0.0_dp
      s2 = 0.0_dp
      kd = bptr(bj + 1) - 1
      do q = bptr(bj), kd - 1
        i = 2 * brow(q)
        m = a(1, q)
        y(i - 1) = y(i - 1) + m * x1
        y(i) = y(i) + m * x2
        s1 = s1 + m * x(i - 1)
        s2 = s2 + m * x(i)
      end do
      y(2 * bj - 1) = y(2 * bj - 1) + s1 + a(1, kd) * x1
      y(2 * bj) = y(2 * bj) + s2 + a(1, kd) * x2
    end do
  end subroutine product_iso

  pure logical function pb_active(self)
    class(pair_block_t), intent(in) :: self
    pb_active = self%on
  end function pb_active
end module pair_blocks
