!> pair_blocks: y = A x by 2 × 2 blocks on the equation pairs, against the dense product and the
!> scalar sym_csc_t%matvec. Patterns of two-DOF nodes coupled by elements (a chain, whose block
!> column J holds rows J-1 and J, and a grid), an odd last equation, a pattern whose pairs are not
!> nodes (left to the scalar product), and a matrix of m I blocks (one value per block, the scalar
!> product bit for bit).
program test_pair_blocks
  use kinds, only: dp
  use testing, only: check, check_close, test_summary
  use errors, only: STAT_OK
  use sparse_matrix, only: sym_csc_t, to_dense
  use pair_blocks, only: pair_block_t
  implicit none

  call test_chain()
  call test_grid(odd=.false.)
  call test_grid(odd=.true.)
  call test_shifted()
  call test_iso()
  call test_summary('pair_blocks')

contains

  !> A pattern from elements given by their nodes (two DOFs each, equations 2a-1, 2a), plus, when
  !> extra > 0, one last equation coupled to the equations extra(:).
  subroutine pattern(nnode, conn, pat, extra)
    integer, intent(in) :: nnode, conn(:, :)
    type(sym_csc_t), intent(out) :: pat
    integer, intent(in), optional :: extra(:)
    integer, allocatable :: eptr(:), edofs(:)
    integer :: e, a, nen, nel, n, stat
    character(len=:), allocatable :: errmsg
    nen = size(conn, 1)
    nel = size(conn, 2)
    n = 2 * nnode
    allocate (eptr(nel + 2), edofs(2 * nen * nel))
    do e = 1, nel
      eptr(e) = 2 * nen * (e - 1) + 1
      do a = 1, nen
        edofs(eptr(e) + 2 * a - 2) = 2 * conn(a, e) - 1
        edofs(eptr(e) + 2 * a - 1) = 2 * conn(a, e)
      end do
    end do
    eptr(nel + 1) = 2 * nen * nel + 1
    eptr(nel + 2) = eptr(nel + 1)
    if (present(extra)) then
      n = n + 1
      edofs = [edofs, extra, n]
      eptr(nel + 2) = eptr(nel + 1) + size(extra) + 1
    else
      eptr = eptr(1:nel + 1)
    end if
    call pat%build(n, eptr, edofs, stat, errmsg)
    call check(stat == STAT_OK, 'pattern built')
  end subroutine pattern

  !> Random values on the pattern; the product against the dense one and the scalar one.
  subroutine compare(pat, name, expect_on)
    type(sym_csc_t), intent(in) :: pat
    character(len=*), intent(in) :: name
    logical, intent(in) :: expect_on
    type(pair_block_t) :: pb
    real(dp), allocatable :: v(:), x(:), y(:), ys(:), a(:, :)
    allocate (v(pat%nnz), x(pat%n), y(pat%n), ys(pat%n), a(pat%n, pat%n))
    call random_number(v)
    call random_number(x)
    v = v - 0.5_dp
    x = x - 0.5_dp
    call pb%build(pat, v)
    call check(pb%active() .eqv. expect_on, name // ': blocks used where they pay')
    if (.not. pb%active()) return
    call to_dense(pat, v, a)
    call pb%matvec(x, y)
    call pat%matvec(v, x, ys)
    call check(maxval(abs(y - matmul(a, x))) <= 1.0e-14_dp * maxval(abs(matmul(abs(a), abs(x)))), &
      name // ': A x as the dense product')
    call check(maxval(abs(y - ys)) <= 1.0e-14_dp * maxval(abs(ys)), name // ': as the scalar product')
  end subroutine compare

  !> Bars a-a+1 on a chain of nodes: block column J holds the block rows J-1 and J.
  subroutine test_chain()
    type(sym_csc_t) :: pat
    integer :: conn(2, 9), e
    do e = 1, 9
      conn(:, e) = [e, e + 1]
    end do
    call pattern(10, conn, pat)
    call compare(pat, 'chain', .true.)
  end subroutine test_chain

  !> QUAD4-like grid of 5 x 4 cells; odd: one more equation coupled to a few DOFs of both parities.
  subroutine test_grid(odd)
    logical, intent(in) :: odd
    type(sym_csc_t) :: pat
    if (odd) then
      call pattern(30, grid_conn(), pat, extra=[3, 8, 60])
      call check(mod(pat%n, 2) == 1, 'odd grid: an odd number of equations')
      call compare(pat, 'grid with an odd last equation', .true.)
    else
      call pattern(30, grid_conn(), pat)
      call compare(pat, 'grid', .true.)
    end if
  end subroutine test_grid

  !> The nodes of the 5 x 4 cells of a 6 x 5 grid of nodes, counter-clockwise.
  pure function grid_conn() result(conn)
    integer :: conn(4, 20), i, j, e, n0
    e = 0
    do j = 0, 3
      do i = 0, 4
        e = e + 1
        n0 = j * 6 + i + 1
        conn(:, e) = [n0, n0 + 1, n0 + 7, n0 + 6]
      end do
    end do
  end function grid_conn

  !> The same grid with one equation first (a roller's lone DOF): every pair straddles two nodes,
  !> the blocks would store zeros, the scalar product is kept.
  subroutine test_shifted()
    type(sym_csc_t) :: pat
    integer, allocatable :: eptr(:), edofs(:)
    integer :: i, j, e, n0, a, stat, conn(4)
    character(len=:), allocatable :: errmsg
    allocate (eptr(22), edofs(162))
    eptr(1) = 1                              ! the lone equation, coupled to node 1's UX
    edofs(1:2) = [1, 2]
    e = 0
    do j = 0, 3
      do i = 0, 4
        e = e + 1
        n0 = j * 6 + i + 1
        conn = [n0, n0 + 1, n0 + 7, n0 + 6]
        eptr(e + 1) = 8 * (e - 1) + 3
        do a = 1, 4
          edofs(eptr(e + 1) + 2 * a - 2) = 2 * conn(a)   ! node k: equations 2k, 2k+1
          edofs(eptr(e + 1) + 2 * a - 1) = 2 * conn(a) + 1
        end do
      end do
    end do
    eptr(22) = 163
    call pat%build(61, eptr, edofs, stat, errmsg)
    call check(stat == STAT_OK, 'shifted pattern built')
    call compare(pat, 'pairs that are not nodes', .false.)
  end subroutine test_shifted

  !> m I blocks (a consistent mass): one value per block, the scalar product bit for bit, on the
  !> full pattern (x-y entries stored as zeros) and on its compacted one.
  subroutine test_iso()
    type(sym_csc_t) :: pat, cpat
    type(pair_block_t) :: pb
    integer :: i, j, k
    real(dp), allocatable :: v(:), cv(:), x(:), y(:), ys(:)
    call pattern(30, grid_conn(), pat)
    allocate (v(pat%nnz), x(pat%n), y(pat%n), ys(pat%n))
    do j = 1, pat%n
      do k = pat%colptr(j), pat%colptr(j + 1) - 1
        i = pat%rowind(k)
        v(k) = 0.0_dp
        if (mod(i, 2) == mod(j, 2)) v(k) = 1.0_dp / (3.0_dp + (i + 1) / 2 + (j + 1) / 2) + merge(1.0_dp, 0.0_dp, i == j)
      end do
    end do
    call random_number(x)
    call pat%matvec(v, x, ys)
    call pb%build(pat, v)
    call check(pb%active(), 'm I blocks: used')
    call pb%matvec(x, y)
    call check(all(y == ys), 'm I blocks on the full pattern: the scalar product bit for bit')
    call pat%compact(v, cpat, cv)
    call pb%build(cpat, cv)
    call check(pb%active(), 'm I blocks on the compacted pattern (half the entries of the full one): used')
    if (pb%active()) call pb%matvec(x, y)
    call check(all(y == ys), 'm I blocks on the compacted pattern: bit for bit')
    ! A different m for UY than for UX: not m I, four values per block, still the product.
    v(pat%colptr(pat%n + 1) - 1) = 2.0_dp
    call pat%matvec(v, x, ys)
    call pb%build(pat, v)
    call check(pb%active(), 'unequal diagonal: blocks on the full pattern used')
    if (pb%active()) call pb%matvec(x, y)
    call check_close(norm2(y - ys), 0.0_dp, 0.0_dp, 'unequal diagonal: the product', atol=1.0e-14_dp * norm2(ys))
  end subroutine test_iso
end program test_pair_blocks
