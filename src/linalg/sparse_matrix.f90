!> Symmetric sparse matrices stored as their upper triangle (row <= col) in 1-based CSC.
!>
!> Invariants of a built pattern (relied upon by matvec, diagonal and the CHOLMOD binding):
!> rows are strictly increasing within each column, every diagonal entry is present (even if
!> its value is zero), so the diagonal of column j sits at colptr(j+1)-1. One pattern serves
!> K, M and S = K + c*M; each matrix is just a separate values(nnz) array.
module sparse_matrix
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str, check_alloc
  implicit none
  private
  public :: sym_csc_t, element_positions, scatter_add, to_dense

  type :: sym_csc_t
    integer :: n = 0, nnz = 0
    integer, allocatable :: colptr(:)   !< (n+1)
    integer, allocatable :: rowind(:)   !< (nnz)
  contains
    procedure :: build => sym_csc_build
    procedure :: locate => sym_csc_locate
    procedure :: add_element => sym_csc_add_element
    procedure :: matvec => sym_csc_matvec
    procedure :: anti_matvec => sym_csc_anti_matvec
    procedure :: diagonal => sym_csc_diagonal
    procedure :: isolated_diagonal => sym_csc_isolated_diagonal
    procedure :: compact => sym_csc_compact
    procedure :: element_positions
  end type sym_csc_t

contains

  !> Build the pattern of the matrix assembled from elements: element e couples the equations
  !> edofs(eptr(e):eptr(e+1)-1); 0 entries are eliminated DOFs and are skipped. Duplicate DOFs
  !> inside an element are allowed. Cost O(sum over elements of ndof^2 + nnz log) time and
  !> O(n + nnz + size(edofs)) memory, via an equation -> element incidence list.
  !> Invalid input (entries < 0 or > n, bad eptr) leaves an empty pattern and sets stat.
  subroutine sym_csc_build(self, n, eptr, edofs, stat, errmsg)
    class(sym_csc_t), intent(inout) :: self
    integer, intent(in) :: n
    integer, intent(in) :: eptr(:)
    integer, intent(in) :: edofs(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer, allocatable :: dptr(:), delem(:), mark(:)
    integer :: nel, e, p, q, i, j, cnt, pos, ast
    character(len=:), allocatable :: msg

    self%n = 0
    self%nnz = 0
    if (allocated(self%colptr)) deallocate (self%colptr)
    if (allocated(self%rowind)) deallocate (self%rowind)
    stat = STAT_OK

    nel = max(size(eptr) - 1, 0)
    msg = check_input(n, nel, eptr, edofs)
    if (len(msg) > 0) then
      stat = STAT_INPUT
      errmsg = msg
      return
    end if

    ! Equation -> elements incidence (CSR); an element appears twice for a duplicated DOF,
    ! which the per-column marker below makes harmless.
    allocate (dptr(n + 1), mark(n), stat=ast)
    if (out_of_memory(ast, 8.0_dp * n)) return
    dptr = 0
    do e = 1, nel
      do p = eptr(e), eptr(e + 1) - 1
        i = edofs(p)
        if (i > 0) dptr(i) = dptr(i) + 1
      end do
    end do
    call counts_to_starts(dptr)
    allocate (delem(dptr(n + 1) - 1), stat=ast)
    if (out_of_memory(ast, 4.0_dp * dptr(n + 1))) return
    mark(1:n) = dptr(1:n)           ! fill cursor
    do e = 1, nel
      do p = eptr(e), eptr(e + 1) - 1
        i = edofs(p)
        if (i > 0) then
          delem(mark(i)) = e
          mark(i) = mark(i) + 1
        end if
      end do
    end do

    ! Pass 1: count the distinct rows i <= j of column j (the diagonal always counts).
    allocate (self%colptr(n + 1), stat=ast)
    if (out_of_memory(ast, 4.0_dp * n)) return
    self%colptr(1) = 1
    mark = 0
    do j = 1, n
      mark(j) = j
      cnt = 1
      do p = dptr(j), dptr(j + 1) - 1
        e = delem(p)
        do q = eptr(e), eptr(e + 1) - 1
          i = edofs(q)
          if (i > 0 .and. i < j) then
            if (mark(i) /= j) then
              mark(i) = j
              cnt = cnt + 1
            end if
          end if
        end do
      end do
      self%colptr(j + 1) = self%colptr(j) + cnt
    end do

    ! Pass 2: fill the strictly upper rows, sort them, put the diagonal last.
    self%n = n
    self%nnz = self%colptr(n + 1) - 1
    allocate (self%rowind(self%nnz), stat=ast)
    if (out_of_memory(ast, 4.0_dp * self%nnz)) return
    mark = 0
    do j = 1, n
      mark(j) = j
      pos = self%colptr(j)
      do p = dptr(j), dptr(j + 1) - 1
        e = delem(p)
        do q = eptr(e), eptr(e + 1) - 1
          i = edofs(q)
          if (i > 0 .and. i < j) then
            if (mark(i) /= j) then
              mark(i) = j
              self%rowind(pos) = i
              pos = pos + 1
            end if
          end if
        end do
      end do
      call sort_int(self%rowind(self%colptr(j):pos - 1))
      self%rowind(pos) = j
    end do
  contains
    !> A failed allocation: an empty pattern and the message.
    logical function out_of_memory(ast, nbytes)
      integer, intent(in) :: ast
      real(dp), intent(in) :: nbytes
      out_of_memory = ast /= 0
      if (.not. out_of_memory) return
      call check_alloc(ast, 'the sparse pattern of ' // str(n) // ' equations', nbytes, stat, errmsg)
      self%n = 0
      self%nnz = 0
    end function out_of_memory
  end subroutine sym_csc_build

  !> Empty string if the element list is consistent, else the reason.
  pure function check_input(n, nel, eptr, edofs) result(msg)
    integer, intent(in) :: n, nel
    integer, intent(in) :: eptr(:), edofs(:)
    character(len=:), allocatable :: msg
    integer :: e, p
    msg = ''
    if (n < 0) then
      msg = 'sparse pattern: negative number of equations ' // str(n)
      return
    end if
    if (nel == 0) return
    if (eptr(1) < 1) then
      msg = 'sparse pattern: eptr(1) must be >= 1, got ' // str(eptr(1))
      return
    end if
    do e = 1, nel
      if (eptr(e + 1) < eptr(e) .or. eptr(e + 1) - 1 > size(edofs)) then
        msg = 'sparse pattern: bad element pointer eptr(' // str(e + 1) // ') = ' // str(eptr(e + 1))
        return
      end if
    end do
    do e = 1, nel
      do p = eptr(e), eptr(e + 1) - 1
        if (edofs(p) < 0 .or. edofs(p) > n) then
          msg = 'sparse pattern: element ' // str(e) // ' references equation ' // str(edofs(p)) // &
                ' outside 0..' // str(n)
          return
        end if
      end do
    end do
  end function check_input

  !> counts(i) (i = 1..n, counts(n+1) ignored) -> start positions, counts(n+1) = total + 1.
  pure subroutine counts_to_starts(c)
    integer, intent(inout) :: c(:)
    integer :: i, s, t
    s = 1
    do i = 1, size(c)
      t = c(i)
      c(i) = s
      if (i < size(c)) s = s + t
    end do
  end subroutine counts_to_starts

  !> In-place ascending sort: insertion sort for short columns (the usual case), heapsort
  !> otherwise so a dense column stays O(k log k).
  pure subroutine sort_int(a)
    integer, intent(inout) :: a(:)
    integer :: i, j, v, n, last
    n = size(a)
    if (n <= 32) then
      do i = 2, n
        v = a(i)
        j = i - 1
        do while (j >= 1)
          if (a(j) <= v) exit
          a(j + 1) = a(j)
          j = j - 1
        end do
        a(j + 1) = v
      end do
      return
    end if
    do i = n / 2, 1, -1            ! heapify
      call sift_down(a, i, n)
    end do
    do last = n, 2, -1
      v = a(1); a(1) = a(last); a(last) = v
      call sift_down(a, 1, last - 1)
    end do
  end subroutine sort_int

  !> Restore the max-heap property of a(r:hi) below root r.
  pure subroutine sift_down(a, root, hi)
    integer, intent(inout) :: a(:)
    integer, intent(in) :: root, hi
    integer :: r, child, tmp
    r = root
    do
      child = 2 * r
      if (child > hi) exit
      if (child < hi) then
        if (a(child + 1) > a(child)) child = child + 1
      end if
      if (a(r) >= a(child)) exit
      tmp = a(r); a(r) = a(child); a(child) = tmp
      r = child
    end do
  end subroutine sift_down

  !> Position k in values of entry (i,j) or (j,i) (swapped to the upper triangle); 0 if absent.
  pure integer function sym_csc_locate(self, i, j) result(k)
    class(sym_csc_t), intent(in) :: self
    integer, intent(in) :: i, j
    integer :: r, c, lo, hi, mid
    k = 0
    r = min(i, j)
    c = max(i, j)
    if (r < 1 .or. c > self%n) return
    lo = self%colptr(c)
    hi = self%colptr(c + 1) - 1
    do while (lo <= hi)
      mid = (lo + hi) / 2
      if (self%rowind(mid) == r) then
        k = mid
        return
      else if (self%rowind(mid) < r) then
        lo = mid + 1
      else
        hi = mid - 1
      end if
    end do
  end function sym_csc_locate

  !> values += ke scattered at (dofs(a), dofs(b)), upper triangle only (dofs(a) <= dofs(b));
  !> ke is the full symmetric element matrix, so a duplicated DOF correctly collects both
  !> ke(a,b) and ke(b,a) on the diagonal. DOFs 0 are skipped. stat = STAT_INPUT if an entry
  !> is missing from the pattern (it is then dropped).
  pure subroutine sym_csc_add_element(self, values, dofs, ke, stat)
    class(sym_csc_t), intent(in) :: self
    real(dp), intent(inout) :: values(:)
    integer, intent(in) :: dofs(:)
    real(dp), intent(in) :: ke(:, :)
    integer, intent(out), optional :: stat
    integer :: a, b, i, j, k
    if (present(stat)) stat = STAT_OK
    do b = 1, size(dofs)
      j = dofs(b)
      if (j <= 0) cycle
      do a = 1, size(dofs)
        i = dofs(a)
        if (i <= 0 .or. i > j) cycle
        k = self%locate(i, j)
        if (k > 0) then
          values(k) = values(k) + ke(a, b)
        else if (present(stat)) then
          stat = STAT_INPUT
        end if
      end do
    end do
  end subroutine sym_csc_add_element

  !> pos(a,b) = position of (dofs(a), dofs(b)) in values when dofs(a) <= dofs(b), else 0
  !> (eliminated DOF or lower triangle). Precomputed scatter map for scatter_add.
  pure subroutine element_positions(pat, dofs, pos)
    class(sym_csc_t), intent(in) :: pat
    integer, intent(in) :: dofs(:)
    integer, intent(out) :: pos(:, :)
    integer :: a, b
    pos = 0
    do b = 1, size(dofs)
      if (dofs(b) <= 0) cycle
      do a = 1, size(dofs)
        if (dofs(a) <= 0 .or. dofs(a) > dofs(b)) cycle
        pos(a, b) = pat%locate(dofs(a), dofs(b))
      end do
    end do
  end subroutine element_positions

  !> values(pos(a,b)) += ke(a,b) wherever pos(a,b) > 0 (same result as add_element).
  pure subroutine scatter_add(values, pos, ke)
    real(dp), intent(inout) :: values(:)
    integer, intent(in) :: pos(:, :)
    real(dp), intent(in) :: ke(:, :)
    integer :: a, b
    do b = 1, size(pos, 2)
      do a = 1, size(pos, 1)
        if (pos(a, b) > 0) values(pos(a, b)) = values(pos(a, b)) + ke(a, b)
      end do
    end do
  end subroutine scatter_add

  !> y = A x for the symmetric A whose upper triangle is values. No allocation.
  pure subroutine sym_csc_matvec(self, values, x, y)
    class(sym_csc_t), intent(in) :: self
    real(dp), intent(in) :: values(:)
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: y(:)
    integer :: i, j, k, kd
    real(dp) :: xj, s
    y(1:self%n) = 0.0_dp
    do j = 1, self%n
      xj = x(j)
      s = 0.0_dp
      kd = self%colptr(j + 1) - 1          ! diagonal is the last entry of column j
      do k = self%colptr(j), kd - 1
        i = self%rowind(k)
        y(i) = y(i) + values(k) * xj
        s = s + values(k) * x(i)
      end do
      y(j) = y(j) + s + values(kd) * xj
    end do
  end subroutine sym_csc_matvec

  !> y = A x for the antisymmetric A (A' = -A) whose upper triangle is values (the diagonal entries,
  !> zero for an antisymmetric matrix, are not read). add_element assembles it from antisymmetric
  !> element matrices as it does the symmetric ones. No allocation.
  pure subroutine sym_csc_anti_matvec(self, values, x, y)
    class(sym_csc_t), intent(in) :: self
    real(dp), intent(in) :: values(:)
    real(dp), intent(in) :: x(:)
    real(dp), intent(out) :: y(:)
    integer :: i, j, k
    real(dp) :: xj, s
    y(1:self%n) = 0.0_dp
    do j = 1, self%n
      xj = x(j)
      s = 0.0_dp
      do k = self%colptr(j), self%colptr(j + 1) - 2    ! the diagonal, last in its column, left out
        i = self%rowind(k)
        y(i) = y(i) + values(k) * xj
        s = s - values(k) * x(i)
      end do
      y(j) = y(j) + s
    end do
  end subroutine sym_csc_anti_matvec

  !> The pattern cpat and values cval of the matrix values on self without its off-diagonal exact
  !> zeros (the diagonal kept: the invariants hold). A consistent mass on the stiffness's pattern is
  !> half zeros (no x-y coupling in a surface element's mass): its products on cpat read half the
  !> memory, and give the same results bit for bit (a zero term adds ±0 to a sum).
  pure subroutine sym_csc_compact(self, values, cpat, cval)
    class(sym_csc_t), intent(in) :: self
    real(dp), intent(in) :: values(:)
    type(sym_csc_t), intent(out) :: cpat
    real(dp), allocatable, intent(out) :: cval(:)
    integer :: j, k, c
    c = 0
    do j = 1, self%n
      do k = self%colptr(j), self%colptr(j + 1) - 1
        if (values(k) /= 0.0_dp .or. k == self%colptr(j + 1) - 1) c = c + 1
      end do
    end do
    cpat%n = self%n
    cpat%nnz = c
    allocate (cpat%colptr(self%n + 1), cpat%rowind(c), cval(c))
    c = 0
    cpat%colptr(1) = 1
    do j = 1, self%n
      do k = self%colptr(j), self%colptr(j + 1) - 1
        if (values(k) /= 0.0_dp .or. k == self%colptr(j + 1) - 1) then
          c = c + 1
          cpat%rowind(c) = self%rowind(k)
          cval(c) = values(k)
        end if
      end do
      cpat%colptr(j + 1) = c + 1
    end do
  end subroutine sym_csc_compact

  !> d(i) = A(i,i).
  pure subroutine sym_csc_diagonal(self, values, d)
    class(sym_csc_t), intent(in) :: self
    real(dp), intent(in) :: values(:)
    real(dp), intent(out) :: d(:)
    integer :: j
    do j = 1, self%n
      d(j) = values(self%colptr(j + 1) - 1)
    end do
  end subroutine sym_csc_diagonal

  !> d(j) = the diagonal entry of the equations whose row has no nonzero off the diagonal (the matrix's
  !> inverse acts on them as 1/d(j)), 0 on the others: where a solve can be skipped.
  pure subroutine sym_csc_isolated_diagonal(self, values, d)
    class(sym_csc_t), intent(in) :: self
    real(dp), intent(in) :: values(:)
    real(dp), intent(out) :: d(:)
    integer :: j, p
    call self%diagonal(values, d)
    do j = 1, self%n
      do p = self%colptr(j), self%colptr(j + 1) - 2      ! (the diagonal is the column's last entry)
        if (values(p) == 0.0_dp) cycle
        d(j) = 0.0_dp
        d(self%rowind(p)) = 0.0_dp
      end do
    end do
  end subroutine sym_csc_isolated_diagonal

  !> Full dense copy a(n,n) of the symmetric matrix (for small problems and checks).
  pure subroutine to_dense(pat, values, a)
    type(sym_csc_t), intent(in) :: pat
    real(dp), intent(in) :: values(:)
    real(dp), intent(out) :: a(:, :)
    integer :: j, k
    a = 0.0_dp
    do j = 1, pat%n
      do k = pat%colptr(j), pat%colptr(j + 1) - 1
        a(pat%rowind(k), j) = values(k)
        a(j, pat%rowind(k)) = values(k)
      end do
    end do
  end subroutine to_dense
end module sparse_matrix
