!> sparse_matrix: pattern invariants, assembly and matvec against an independently assembled
!> dense matrix, duplicate/eliminated DOFs, and the exact nnz of a structured QUAD4 grid.
program test_sparse_matrix
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT
  use testing, only: check, check_close, test_summary
  use sparse_matrix, only: sym_csc_t, element_positions, scatter_add, to_dense
  implicit none

  call test_small_assembly()
  call test_bad_input()
  call test_quad4_grid_nnz()
  call test_dense_element()
  call test_summary('sparse_matrix')

contains

  !> Deterministic symmetric element matrix with entries of both signs.
  pure function element_matrix(nd, seed) result(ke)
    integer, intent(in) :: nd, seed
    real(dp) :: ke(nd, nd)
    integer :: a, b
    do b = 1, nd
      do a = 1, b
        ke(a, b) = sin(real(seed * 7 + a * 3 + b * 11, dp)) + merge(2.0_dp, 0.0_dp, a == b)
        ke(b, a) = ke(a, b)
      end do
    end do
  end function element_matrix

  !> Rows strictly increasing, row <= col, diagonal last in each column.
  logical function pattern_ok(pat)
    type(sym_csc_t), intent(in) :: pat
    integer :: j, k
    pattern_ok = size(pat%colptr) == pat%n + 1 .and. pat%colptr(1) == 1 .and. pat%colptr(pat%n + 1) == pat%nnz + 1
    if (.not. pattern_ok) return
    do j = 1, pat%n
      if (pat%colptr(j + 1) <= pat%colptr(j)) pattern_ok = .false.
      if (.not. pattern_ok) return
      if (pat%rowind(pat%colptr(j + 1) - 1) /= j) pattern_ok = .false.
      do k = pat%colptr(j), pat%colptr(j + 1) - 2
        if (pat%rowind(k) >= pat%rowind(k + 1) .or. pat%rowind(k) < 1) pattern_ok = .false.
      end do
    end do
  end function pattern_ok

  subroutine test_small_assembly()
    ! 8 equations; equation 7 is touched by no element (its diagonal must still exist);
    ! element 3 repeats DOF 2; zeros are eliminated DOFs; element 5 lists DOFs out of order.
    integer, parameter :: n = 8
    integer, parameter :: eptr(6) = [1, 5, 8, 12, 14, 17]
    integer, parameter :: edofs(16) = [1, 3, 0, 5, 2, 3, 8, 2, 4, 2, 0, 6, 5, 8, 0, 1]
    type(sym_csc_t) :: pat
    real(dp), allocatable :: v(:), v2(:), ke(:, :), dense(:, :), back(:, :)
    real(dp) :: x(n), y(n), yd(n), d(n)
    logical :: conn(n, n)
    integer, allocatable :: pos(:, :)
    integer :: e, a, b, i, j, nd, stat, nexp
    character(len=:), allocatable :: errmsg

    call pat%build(n, eptr, edofs, stat, errmsg)
    call check(stat == STAT_OK, 'build small pattern succeeds')
    call check(pat%n == n, 'pattern order')
    call check(pattern_ok(pat), 'pattern invariants (sorted rows, upper, diagonal last)')

    ! Expected structure: union of element couplings plus every diagonal.
    conn = .false.
    do i = 1, n
      conn(i, i) = .true.
    end do
    allocate (dense(n, n))
    dense = 0.0_dp
    allocate (v(pat%nnz), v2(pat%nnz))
    v = 0.0_dp
    v2 = 0.0_dp
    do e = 1, size(eptr) - 1
      nd = eptr(e + 1) - eptr(e)
      ke = element_matrix(nd, e)
      associate (dofs => edofs(eptr(e):eptr(e + 1) - 1))
        do b = 1, nd
          do a = 1, nd
            if (dofs(a) > 0 .and. dofs(b) > 0) then
              conn(dofs(a), dofs(b)) = .true.
              dense(dofs(a), dofs(b)) = dense(dofs(a), dofs(b)) + ke(a, b)
            end if
          end do
        end do
        call pat%add_element(v, dofs, ke, stat)
        call check(stat == STAT_OK, 'add_element finds every entry, element ' // achar(48 + e))
        if (allocated(pos)) deallocate (pos)
        allocate (pos(nd, nd))
        call element_positions(pat, dofs, pos)
        call scatter_add(v2, pos, ke)
      end associate
    end do
    nexp = 0
    do j = 1, n
      do i = 1, j
        if (conn(i, j)) nexp = nexp + 1
      end do
    end do
    call check(pat%nnz == nexp, 'nnz equals the number of coupled upper pairs plus diagonals')
    call check(pat%locate(7, 7) > 0, 'untouched equation keeps its diagonal')
    call check(pat%locate(1, 2) == 0 .and. pat%locate(7, 1) == 0, 'locate returns 0 for uncoupled pairs')
    call check(pat%locate(3, 1) == pat%locate(1, 3) .and. pat%locate(1, 3) > 0, 'locate is symmetric')
    call check(pat%locate(0, 3) == 0 .and. pat%locate(3, n + 1) == 0, 'locate rejects out-of-range indices')

    ! Duplicate DOF 2 in element 3: A(2,2) collects ke(1,1)+ke(1,3)+ke(3,1)+ke(3,3) of that element.
    allocate (back(n, n))
    call to_dense(pat, v, back)
    call check(maxval(abs(back - dense)) <= 1.0e-14_dp * maxval(abs(dense)), &
               'assembled sparse equals dense assembly (duplicate and eliminated DOFs)')
    call check(maxval(abs(v2 - v)) <= 1.0e-15_dp * maxval(abs(v)), 'element_positions + scatter_add = add_element')

    do i = 1, n
      x(i) = cos(real(i, dp)) + 0.1_dp * i
    end do
    call pat%matvec(v, x, y)
    yd = matmul(dense, x)
    ! Each y(i) sums <= n products of O(1) numbers: rounding <= n * eps * max|A| * max|x|.
    call check(maxval(abs(y - yd)) <= real(n, dp) * epsilon(1.0_dp) * maxval(abs(dense)) * maxval(abs(x)) * 4, &
               'matvec equals dense matmul')
    call pat%diagonal(v, d)
    do i = 1, n
      call check_close(d(i), dense(i, i), 0.0_dp, 'diagonal entry', atol=1.0e-14_dp)
    end do
    ! Last element has dofs [8, 0, 1]: (8,1) is lower -> 0, (1,8) upper -> found, DOF 0 -> 0.
    call check(pos(1, 3) == 0 .and. pos(3, 1) == pat%locate(1, 8) .and. pos(3, 1) > 0 .and. &
               all(pos(2, :) == 0) .and. all(pos(:, 2) == 0), 'element_positions: lower and eliminated give 0')
  end subroutine test_small_assembly

  subroutine test_bad_input()
    type(sym_csc_t) :: pat
    integer :: stat
    character(len=:), allocatable :: errmsg
    call pat%build(3, [1, 3], [1, 4], stat, errmsg)
    call check(stat == STAT_INPUT, 'DOF beyond n is rejected')
    call check(pat%n == 0, 'rejected build leaves an empty pattern')
    call pat%build(3, [1, 3], [1, -1], stat, errmsg)
    call check(stat == STAT_INPUT, 'negative DOF is rejected')
    call pat%build(3, [1, 5], [1, 2], stat, errmsg)
    call check(stat == STAT_INPUT, 'eptr beyond edofs is rejected')
    call pat%build(4, [integer ::], [integer ::], stat, errmsg)
    call check(stat == STAT_OK .and. pat%nnz == 4, 'no elements: diagonal-only pattern')
  end subroutine test_bad_input

  !> Structured nx x ny QUAD4 grid, 2 DOFs per node, left edge clamped (DOFs 0). Nodes couple
  !> with their 8 neighbours: upper nnz = 3 per free node (2x2 diagonal block) + 4 per coupled
  !> pair of free nodes (horizontal, vertical and two diagonal pairs per cell).
  subroutine test_quad4_grid_nnz()
    integer, parameter :: nx = 60, ny = 40
    type(sym_csc_t) :: pat
    integer, allocatable :: eq(:, :, :), eptr(:), edofs(:)
    integer :: ix, iy, e, neq, p, c, stat, nexp, nfree
    integer :: corner(2, 4)
    character(len=:), allocatable :: errmsg

    allocate (eq(2, 0:nx, 0:ny))
    neq = 0
    do iy = 0, ny
      do ix = 0, nx
        if (ix == 0) then
          eq(:, ix, iy) = 0
        else
          eq(1, ix, iy) = neq + 1
          eq(2, ix, iy) = neq + 2
          neq = neq + 2
        end if
      end do
    end do
    allocate (eptr(nx * ny + 1), edofs(8 * nx * ny))
    e = 0
    p = 1
    do iy = 0, ny - 1
      do ix = 0, nx - 1
        e = e + 1
        eptr(e) = p
        corner = reshape([ix, iy, ix + 1, iy, ix + 1, iy + 1, ix, iy + 1], [2, 4])
        do c = 1, 4
          edofs(p:p + 1) = eq(:, corner(1, c), corner(2, c))
          p = p + 2
        end do
      end do
    end do
    eptr(e + 1) = p
    call pat%build(neq, eptr, edofs, stat, errmsg)
    call check(stat == STAT_OK, 'QUAD4 grid pattern builds')
    call check(pattern_ok(pat), 'QUAD4 grid pattern invariants')
    ! Free nodes: columns ix = 1..nx. Pairs among free nodes only.
    nfree = nx * (ny + 1)
    nexp = 3 * nfree + 4 * ((nx - 1) * (ny + 1) + nx * ny + 2 * (nx - 1) * ny)
    call check(pat%nnz == nexp, 'QUAD4 grid nnz matches the closed form')
  end subroutine test_quad4_grid_nnz

  !> One element over 50 DOFs listed in scrambled order: a full upper triangle, n(n+1)/2
  !> entries, sorted (exercises the heapsort path for long columns).
  subroutine test_dense_element()
    integer, parameter :: n = 50
    type(sym_csc_t) :: pat
    integer :: dofs(n), i, stat
    character(len=:), allocatable :: errmsg
    do i = 1, n
      dofs(i) = modulo(17 * i, n) + 1       ! 17 coprime with 50: a permutation of 1..50
    end do
    call pat%build(n, [1, n + 1], dofs, stat, errmsg)
    call check(stat == STAT_OK .and. pat%nnz == n * (n + 1) / 2, 'single dense element gives a full triangle')
    call check(pattern_ok(pat), 'dense element pattern invariants (long columns sorted)')
  end subroutine test_dense_element
end program test_sparse_matrix
