!> Small array helpers shared by the readers: an in-place heap sort (of keys, or of keys with
!> values carried along, O(n log n) without allocation), a stable ordering of a few indices by a
!> key, and the doubling growth of an integer array.
module array_utils
  use kinds, only: dp
  implicit none
  private
  public :: heap_sort, sort_by_key, stable_order, bracket, grow

  !> Room for n entries (doubling), the content kept: integer or real arrays.
  interface grow
    module procedure grow_int, grow_real
  end interface grow

contains

  !> idx reordered so that key(idx) ascends, equal keys in their given order (an insertion sort:
  !> its callers order a few tens of entries, and stability keeps their file or run order).
  pure subroutine stable_order(key, idx)
    real(dp), intent(in) :: key(:)
    integer, intent(inout) :: idx(:)
    integer :: i, j, t
    do i = 2, size(idx)
      t = idx(i)
      j = i - 1
      do while (j >= 1)
        if (key(idx(j)) <= key(t)) exit
        idx(j + 1) = idx(j)
        j = j - 1
      end do
      idx(j + 1) = t
    end do
  end subroutine stable_order

  !> The interval of the increasing values tt that holds t, by bisection: i with tt(i) <= t < tt(i+1)
  !> (0 before the first value, size(tt) from the last): the tables of FUNCTION and of the sweeps.
  pure integer function bracket(tt, t) result(i)
    real(dp), intent(in) :: tt(:), t
    integer :: hi, mid
    if (t < tt(1)) then
      i = 0
      return
    end if
    i = 1
    hi = size(tt) + 1
    do while (hi - i > 1)                       ! tt(i) <= t < tt(hi) (tt(n+1) = +inf)
      mid = (i + hi) / 2
      if (tt(mid) <= t) then
        i = mid
      else
        hi = mid
      end if
    end do
  end function bracket

  !> In-place ascending heap sort.
  pure subroutine heap_sort(a)
    integer, intent(inout) :: a(:)
    integer :: dummy(size(a))
    dummy = 0
    call sort_by_key(a, dummy)
  end subroutine heap_sort

  !> In-place ascending heap sort of key, applying the same permutation to val. O(n log n).
  pure subroutine sort_by_key(key, val)
    integer, intent(inout) :: key(:), val(:)
    integer :: n, i
    n = size(key)
    do i = n / 2, 1, -1
      call sift(key, val, i, n)
    end do
    do i = n, 2, -1
      call swap(key, val, 1, i)
      call sift(key, val, 1, i - 1)
    end do
  end subroutine sort_by_key

  pure subroutine sift(key, val, start, n)
    integer, intent(inout) :: key(:), val(:)
    integer, intent(in) :: start, n
    integer :: root, child
    root = start
    do while (2 * root <= n)
      child = 2 * root
      if (child < n) then
        if (key(child + 1) > key(child)) child = child + 1
      end if
      if (key(root) >= key(child)) return
      call swap(key, val, root, child)
      root = child
    end do
  end subroutine sift

  pure subroutine swap(key, val, i, j)
    integer, intent(inout) :: key(:), val(:)
    integer, intent(in) :: i, j
    integer :: t
    t = key(i)
    key(i) = key(j)
    key(j) = t
    t = val(i)
    val(i) = val(j)
    val(j) = t
  end subroutine swap

  pure subroutine grow_int(a, n)
    integer, allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    integer, allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate (tmp(max(n, 2 * size(a))))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_int

  pure subroutine grow_real(a, n)
    real(dp), allocatable, intent(inout) :: a(:)
    integer, intent(in) :: n
    real(dp), allocatable :: tmp(:)
    if (size(a) >= n) return
    allocate (tmp(max(n, 2 * size(a))))
    tmp(1:size(a)) = a
    call move_alloc(tmp, a)
  end subroutine grow_real
end module array_utils
