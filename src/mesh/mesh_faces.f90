!> The free faces of a node group in a DIMENSION 3 mesh (PRESSURE and TRACTION on solids): the faces
!> of its solids (element_traits' etype_faces, outward; 3, 4, 6 or 8 nodes) whose nodes are all in the
!> group and that no other element shares (a face listed twice lies inside the body).
module mesh_faces
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use mesh, only: mesh_t
  use element_traits, only: etype_faces
  use array_utils, only: heap_sort
  implicit none
  private
  public :: face_set_t, group_faces

  !> Face k: nodes node(1:nfn(k), k) counter-clockwise seen from outside (the corners, then the
  !> mid-edge nodes of a quadratic face), of element elem(k).
  type :: face_set_t
    integer :: n = 0
    integer, allocatable :: node(:, :), nfn(:), elem(:)
  end type face_set_t

contains

  !> The free faces of the group items; a node of the group on none of them is an error naming it.
  subroutine group_faces(m, items, faces, stat, errmsg)
    type(mesh_t), intent(in) :: m
    integer, intent(in) :: items(:)
    type(face_set_t), intent(out) :: faces
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    logical, allocatable :: in(:), on(:), shared(:)
    integer, allocatable :: cn(:, :), key(:, :), ce(:), cnf(:), first(:), next(:)
    integer :: e, k, face(8, 6), nfn(6), nface, nc, i, j, lo
    stat = STAT_OK
    allocate (in(m%nnode), on(m%nnode))
    in = .false.
    in(items) = .true.
    nc = 0
    do e = 1, m%nelem                           ! count the candidates, then fill
      call etype_faces(m%etype(e), face, nfn, nface)
      do k = 1, nface
        if (all(in(m%conn(face(1:nfn(k), k), e)))) nc = nc + 1
      end do
    end do
    allocate (cn(8, nc), key(4, nc), ce(nc), cnf(nc), shared(nc), first(m%nnode), next(nc))
    nc = 0
    first = 0
    do e = 1, m%nelem
      call etype_faces(m%etype(e), face, nfn, nface)
      do k = 1, nface
        if (.not. all(in(m%conn(face(1:nfn(k), k), e)))) cycle
        nc = nc + 1
        cn(:, nc) = 0
        cn(1:nfn(k), nc) = m%conn(face(1:nfn(k), k), e)
        key(:, nc) = sorted4(cn(1:4, nc), merge(3, 4, nfn(k) == 3 .or. nfn(k) == 6))   ! (its corners)
        ce(nc) = e
        cnf(nc) = nfn(k)
        lo = key(1, nc)                         ! buckets by the smallest node: few faces each
        next(nc) = first(lo)
        first(lo) = nc
      end do
    end do
    shared = .false.
    do i = 1, nc
      j = next(i)
      do while (j > 0)
        if (all(key(:, j) == key(:, i))) then
          shared(i) = .true.
          shared(j) = .true.
        end if
        j = next(j)
      end do
    end do
    faces%n = count(.not. shared)
    allocate (faces%node(8, faces%n), faces%nfn(faces%n), faces%elem(faces%n))
    on = .false.
    j = 0
    do i = 1, nc
      if (shared(i)) cycle
      j = j + 1
      faces%node(:, j) = cn(:, i)
      faces%nfn(j) = cnf(i)
      faces%elem(j) = ce(i)
      on(cn(1:cnf(i), i)) = .true.
    end do
    do i = 1, size(items)
      if (.not. on(items(i))) then
        call set_error(stat, errmsg, STAT_INPUT, 'node ' // str(m%node_tag(items(i))) // &
          ' is on no free element face whose nodes are all in the group')
        return
      end if
    end do
  contains
    pure function sorted4(v, n) result(s)
      integer, intent(in) :: v(4), n
      integer :: s(4)
      s = 0
      s(1:n) = v(1:n)
      call heap_sort(s(1:n))
    end function sorted4
  end subroutine group_faces
end module mesh_faces
