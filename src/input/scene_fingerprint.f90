!> What a checkpoint's state means: one line per statement of the scene ("item<TAB>text") and
!> one for the mesh, stored in every checkpoint and compared at --restart, so that a state is
!> never continued under another scene (issue 12). Numbers are compared by value (1.3e-3 and
!> 0.0013 are the same), words in upper case. Left out, because they are meant to change
!> between a run and its restart: OUTPUT, TITLE and TIME END.
module scene_fingerprint
  use kinds, only: dp
  use errors, only: upper, str
  use statement, only: statement_t, token_t
  use number_text, only: parse_real_text, real_text, NUM_OK
  use mesh, only: mesh_t
  implicit none
  private
  public :: fingerprint_text, fingerprint_mismatch

  character(len=*), parameter :: TAB = achar(9), NL = new_line('a')
  !> Lists longer than this enter the fingerprint by count and digest (list_digest).
  integer, parameter :: LIST_MAX = 64

contains

  !> The fingerprint of statements st (after --set) and of the mesh they built.
  function fingerprint_text(st, msh) result(fp)
    type(statement_t), intent(in) :: st(:)
    type(mesh_t), intent(in) :: msh
    character(len=:), allocatable :: fp
    character(len=:), allocatable :: head, buf, text
    integer :: i, p, v, n, nt
    ! Built in buffers that double when full: a FUNCTION of 2e5 points or a scene of 1e5
    ! statements cost linear time (concatenating piece by piece was quadratic: 154 s for 2e5).
    head = 'mesh' // TAB // str(msh%nnode) // ' nodes, ' // str(msh%nelem) // ' elements, digest ' // &
      mesh_digest(msh) // NL
    allocate (character(len=max(1024, 2 * len(head))) :: buf)
    allocate (character(len=1024) :: text)
    n = 0
    call append(buf, n, head)
    do i = 1, size(st)
      if (st(i)%keyword == 'OUTPUT' .or. st(i)%keyword == 'TITLE') cycle
      call append(buf, n, st(i)%keyword)
      if (size(st(i)%lead) > 0) call append(buf, n, ' ' // st(i)%lead(1)%text)
      nt = 0
      do p = 2, size(st(i)%lead)
        call append(text, nt, ' ' // canonical(st(i)%lead(p)))
      end do
      do p = 1, size(st(i)%params)
        if (st(i)%keyword == 'TIME' .and. st(i)%params(p)%key == 'END') cycle
        call append(text, nt, ' ' // st(i)%params(p)%key)
        if (size(st(i)%params(p)%values) > LIST_MAX) then
          ! A long list (a FUNCTION's table) by its count and a digest of its values' bits: the
          ! canonical text of 2e5 numbers cost seconds, and a change is still caught.
          call append(text, nt, ' (' // str(size(st(i)%params(p)%values)) // ' values, digest ' // &
            list_digest(st(i)%params(p)%values) // ')')
          cycle
        end if
        do v = 1, size(st(i)%params(p)%values)
          call append(text, nt, ' ' // canonical(st(i)%params(p)%values(v)))
        end do
      end do
      call append(buf, n, TAB // trim(adjustl(text(1:nt))) // NL)
    end do
    fp = buf(1:n)
  end function fingerprint_text

  !> A number as the shortest text that reads back to it (equal texts: equal values; 0.0013
  !> and 1.3e-3 both give 0.0013); a quoted word as it is; a word in upper case.
  !> buf(n+1:n+len(piece)) = piece, n advanced; buf doubles when full (amortized linear time).
  subroutine append(buf, n, piece)
    character(len=:), allocatable, intent(inout) :: buf
    integer, intent(inout) :: n
    character(len=*), intent(in) :: piece
    character(len=:), allocatable :: tmp
    if (n + len(piece) > len(buf)) then
      allocate (character(len=max(2 * len(buf), n + len(piece))) :: tmp)
      tmp(1:n) = buf(1:n)
      call move_alloc(tmp, buf)
    end if
    buf(n + 1:n + len(piece)) = piece
    n = n + len(piece)
  end subroutine append

  !> FNV-1a digest of a list of values: the upper-case text of each (numbers as written: a long
  !> table written anew in another notation counts as changed; parsing 2e5 numbers a second time
  !> would double the load).
  function list_digest(toks) result(s)
    type(token_t), intent(in) :: toks(:)
    character(len=:), allocatable :: s
    integer(8), parameter :: PRIME = 1099511628211_8
    integer(8) :: h
    integer :: i, k, c
    character(len=16) :: buf
    h = -3750763034362895579_8
    do i = 1, size(toks)
      do k = 1, len(toks(i)%text)
        c = iachar(toks(i)%text(k:k))
        if (c >= 97 .and. c <= 122) c = c - 32      ! (upper case)
        h = ieor(h, int(c, 8)) * PRIME
      end do
      h = ieor(h, merge(34_8, 59_8, toks(i)%quoted)) * PRIME   ! (a separator; quoted or not)
    end do
    write (buf, '(z16.16)') h
    s = buf
  end function list_digest

  function canonical(tok) result(s)
    type(token_t), intent(in) :: tok
    character(len=:), allocatable :: s
    real(dp) :: x
    integer :: ierr
    call parse_real_text(tok%text, x, ierr)
    if (ierr == NUM_OK .and. .not. tok%quoted) then
      s = real_text(x)
    else if (tok%quoted) then
      s = '"' // tok%text // '"'
    else
      s = upper(tok%text)
    end if
  end function canonical

  !> 64-bit FNV-1a over the bits of the coordinates, element types and connectivity.
  function mesh_digest(msh) result(s)
    type(mesh_t), intent(in) :: msh
    character(len=:), allocatable :: s
    integer(8), parameter :: PRIME = 1099511628211_8
    integer(8) :: h
    integer :: i, k
    character(len=16) :: buf
    h = -3750763034362895579_8   ! the FNV offset basis 0xcbf29ce484222325 as a signed integer
    do i = 1, msh%nnode
      do k = 1, size(msh%x, 1)
        h = ieor(h, transfer(msh%x(k, i), h)) * PRIME
      end do
    end do
    do i = 1, msh%nelem
      h = ieor(h, int(msh%etype(i), 8)) * PRIME
      do k = 1, size(msh%conn, 1)
        h = ieor(h, int(msh%conn(k, i), 8)) * PRIME
      end do
    end do
    write (buf, '(z16.16)') h
    s = buf
  end function mesh_digest

  !> '' when the scene of a checkpoint (saved) is this one (current); else the first item that
  !> differs, both ways.
  function fingerprint_mismatch(saved, current) result(msg)
    character(len=*), intent(in) :: saved, current
    character(len=:), allocatable :: msg
    integer :: ps, pc
    character(len=:), allocatable :: ls, lc
    msg = ''
    ps = 1
    pc = 1
    do
      ls = next_line(saved, ps)
      lc = next_line(current, pc)
      if (ls == lc) then
        if (len(ls) == 0) return
        cycle
      end if
      if (len(ls) == 0) then
        msg = describe(lc) // ' here is not in the checkpoint''s scene'
      else if (len(lc) == 0) then
        msg = describe(ls) // ' of the checkpoint''s scene is not in this one'
      else if (head(ls) == head(lc)) then
        msg = head(lc) // ' is "' // tail(lc) // '" here, "' // tail(ls) // '" in the checkpoint''s scene'
      else
        msg = 'this scene has ' // describe(lc) // ' where the checkpoint''s has ' // describe(ls)
      end if
      return
    end do
  end function fingerprint_mismatch

  !> The line starting at p (without its newline); p moves past it. '' at the end.
  function next_line(s, p) result(line)
    character(len=*), intent(in) :: s
    integer, intent(inout) :: p
    character(len=:), allocatable :: line
    integer :: k
    if (p > len(s)) then
      line = ''
      return
    end if
    k = index(s(p:), NL)
    if (k == 0) k = len(s) - p + 2
    line = s(p:p + k - 2)
    p = p + k
  end function next_line

  pure function head(line) result(s)
    character(len=*), intent(in) :: line
    character(len=:), allocatable :: s
    s = line(1:index(line // TAB, TAB) - 1)
  end function head

  pure function tail(line) result(s)
    character(len=*), intent(in) :: line
    character(len=:), allocatable :: s
    s = line(min(index(line // TAB, TAB) + 1, len(line) + 1):)
  end function tail

  pure function describe(line) result(s)
    character(len=*), intent(in) :: line
    character(len=:), allocatable :: s
    s = head(line) // ' "' // tail(line) // '"'
  end function describe
end module scene_fingerprint
