!> Gmsh's binary MSH 4.1 ($MeshFormat "4.1 1 8", Mesh.Binary = 1): the whole file read at once
!> (one unformatted stream read, linear in its size), then the sections at a cursor. Text lines
!> ($-headers, $MeshFormat, $PhysicalNames) and binary blocks ($Entities, $Nodes, $Elements:
!> int = 4 bytes, size_t = 8 bytes (data size 8), double = 8 bytes, in the machine's byte order,
!> which the int 1 after the format line confirms). The parsed content goes into the same gmsh_t
!> as the ASCII readers, which gmsh_reader turns into the mesh. Messages name the file and the
!> byte offset.
module gmsh_binary
  use, intrinsic :: iso_fortran_env, only: int32, int64
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use mesh, only: MAX_COORD
  use number_text, only: parse_int_text, NUM_OK
  use array_utils, only: grow
  use words, only: is_blank, word_end
  use gmsh_state, only: gmsh_t, pname_t, node_of, element_kind, store_element, index_tags, repeated_name
  use element_traits, only: MAX_NEN
  implicit none
  private
  public :: read_msh41_binary

  !> The file's bytes and the cursor (the next byte to read).
  type :: cursor_t
    character(len=:), allocatable :: b
    integer(int64) :: pos = 1
  end type cursor_t

contains

  !> Parse the binary file g%path into g (nodes, entities, physical names, elements).
  subroutine read_msh41_binary(g, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(cursor_t) :: c
    character(len=:), allocatable :: line
    call slurp(g%path, c%b, stat, errmsg)
    if (stat /= STAT_OK) return
    call text_line(c, line)                                   ! $MeshFormat
    call text_line(c, line)                                   ! 4.1 1 8
    if (c%pos + 4 > len(c%b, int64)) then
      call bad(g, c, 'truncated after the format line', stat, errmsg)
      return
    end if
    if (int_at(c) /= 1) then
      call bad(g, c, 'the byte order of the file is not this machine''s (the int 1 after the format line)', stat, errmsg)
      return
    end if
    call text_line(c, line)                                   ! the rest of that line
    do
      call text_line(c, line)
      if (len_trim(line) == 0 .and. c%pos > len(c%b, int64)) exit
      select case (trim(line))
      case ('', '$EndMeshFormat')
      case ('$PhysicalNames')
        call physical_names(g, c, stat, errmsg)
      case ('$Entities')
        call entities(g, c, stat, errmsg)
      case ('$Nodes')
        call nodes(g, c, stat, errmsg)
      case ('$Elements')
        call elements(g, c, stat, errmsg)
      case default
        if (line(1:1) /= '$' .or. index(line, '$End') == 1) then
          call bad(g, c, 'expected a section header, found "' // line(1:min(len(line), 40)) // '"', stat, errmsg)
        else
          call skip_to(c, '$End' // line(2:), stat)
          if (stat /= STAT_OK) call bad(g, c, 'no $End' // line(2:) // ' closing ' // line, stat, errmsg)
        end if
      end select
      if (stat /= STAT_OK) return
    end do
    if (.not. g%have_nodes) then
      call set_error(stat, errmsg, STAT_INPUT, g%path // ': missing $Nodes section')
    else if (.not. g%have_elements) then
      call set_error(stat, errmsg, STAT_INPUT, g%path // ': missing $Elements section')
    end if
  end subroutine read_msh41_binary

  !> The whole file as bytes.
  subroutine slurp(path, b, stat, errmsg)
    character(len=*), intent(in) :: path
    character(len=:), allocatable, intent(out) :: b
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: u, ios
    integer(int64) :: sz
    character(len=256) :: iom
    stat = STAT_OK
    iom = ''
    open (newunit=u, file=path, access='stream', form='unformatted', status='old', action='read', iostat=ios, iomsg=iom)
    if (ios /= 0) then
      call set_error(stat, errmsg, STAT_INPUT, path // ':0: cannot open the mesh file: ' // trim(iom))
      return
    end if
    inquire (unit=u, size=sz)
    allocate (character(len=max(sz, 0_int64)) :: b, stat=ios)
    if (ios == 0 .and. sz > 0) read (u, iostat=ios, iomsg=iom) b
    close (u)
    if (ios /= 0) call set_error(stat, errmsg, STAT_INPUT, path // ': cannot read the mesh file: ' // trim(iom))
  end subroutine slurp

  !> The text up to the next LF (without it and a CR before it); the cursor after it.
  subroutine text_line(c, line)
    type(cursor_t), intent(inout) :: c
    character(len=:), allocatable, intent(out) :: line
    integer(int64) :: e
    e = c%pos
    do while (e <= len(c%b, int64))
      if (c%b(e:e) == achar(10)) exit
      e = e + 1
    end do
    line = c%b(c%pos:e - 1)
    if (len(line) > 0) then
      if (line(len(line):len(line)) == achar(13)) line = line(1:len(line) - 1)
    end if
    c%pos = e + 1
  end subroutine text_line

  !> Move the cursor past the line that starts with endname.
  subroutine skip_to(c, endname, stat)
    type(cursor_t), intent(inout) :: c
    character(len=*), intent(in) :: endname
    integer, intent(out) :: stat
    integer :: k
    k = index(c%b(c%pos:), achar(10) // endname)
    stat = STAT_INPUT
    if (k == 0) return
    c%pos = c%pos + k
    block
      character(len=:), allocatable :: line
      call text_line(c, line)
    end block
    stat = STAT_OK
  end subroutine skip_to

  integer function int_at(c) result(v)
    type(cursor_t), intent(inout) :: c
    v = transfer(c%b(c%pos:c%pos + 3), 0_int32)
    c%pos = c%pos + 4
  end function int_at

  !> A tag (a size_t): 1 to huge(1), else an error naming it "out of range", as the ASCII reader
  !> says (a tag of 2^32 + 4 must not be read as 4).
  subroutine tag_at(g, c, what, tag, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    type(cursor_t), intent(inout) :: c
    character(len=*), intent(in) :: what
    integer, intent(out) :: tag
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer(int64) :: v
    character(len=24) :: txt
    stat = STAT_OK
    tag = 0
    v = size_at(c)
    if (v < 1_int64 .or. v > int(huge(1), int64)) then
      write (txt, '(i0)') v
      call bad(g, c, 'a ' // what // ' tag out of range (1 to ' // str(huge(1)) // '): ' // trim(txt), stat, errmsg)
      return
    end if
    tag = int(v)
  end subroutine tag_at

  integer(int64) function size_at(c) result(v)
    type(cursor_t), intent(inout) :: c
    v = transfer(c%b(c%pos:c%pos + 7), 0_int64)
    c%pos = c%pos + 8
  end function size_at

  real(dp) function real_at(c) result(v)
    type(cursor_t), intent(inout) :: c
    v = transfer(c%b(c%pos:c%pos + 7), 0.0_dp)
    c%pos = c%pos + 8
  end function real_at

  !> Whether n more bytes are there.
  pure logical function has(c, n)
    type(cursor_t), intent(in) :: c
    integer(int64), intent(in) :: n
    has = n >= 0 .and. c%pos - 1 + n <= len(c%b, int64)
  end function has

  subroutine bad(g, c, msg, stat, errmsg)
    type(gmsh_t), intent(in) :: g
    type(cursor_t), intent(in) :: c
    character(len=*), intent(in) :: msg
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call set_error(stat, errmsg, STAT_INPUT, g%path // ': byte ' // str(int(min(c%pos, int(huge(1), int64)))) // &
      ' (binary MSH 4.1): ' // msg)
  end subroutine bad

  !> The end of a binary block: the newline, then the $End line.
  subroutine end_block(g, c, endname, stat, errmsg)
    type(gmsh_t), intent(in) :: g
    type(cursor_t), intent(inout) :: c
    character(len=*), intent(in) :: endname
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: line
    stat = STAT_OK
    call text_line(c, line)
    if (len_trim(line) == 0) call text_line(c, line)
    if (trim(line) /= endname) call bad(g, c, 'expected ' // endname // ' after the binary data (a wrong count?)', &
      stat, errmsg)
  end subroutine end_block

  !> $PhysicalNames (text): the count, then "dim tag "name"" lines.
  subroutine physical_names(g, c, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    type(cursor_t), intent(inout) :: c
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: line
    type(pname_t), allocatable :: tmp(:)
    integer :: n, i, q1, q2, ierr, d, t, k
    stat = STAT_OK
    d = 0
    t = 0
    call text_line(c, line)
    call parse_int_text(trim(adjustl(line)), n, ierr)
    if (ierr /= NUM_OK .or. n < 0 .or. .not. has(c, int(n, int64) * 6)) then
      call bad(g, c, 'expected the number of physical names, found "' // line(1:min(len(line), 40)) // '"', stat, errmsg)
      return
    end if
    if (.not. allocated(g%pn)) allocate (g%pn(0))
    allocate (tmp(g%npn + n))
    tmp(1:g%npn) = g%pn(1:g%npn)
    call move_alloc(tmp, g%pn)
    do i = 1, n
      call text_line(c, line)
      q1 = index(line, '"')
      q2 = index(line, '"', back=.true.)
      if (q1 > 1) then
        call first_two(line(1:q1 - 1), d, t, ierr)
      else
        ierr = 1
      end if
      if (ierr /= NUM_OK .or. q2 <= q1) then
        call bad(g, c, 'expected a physical name line: dim tag "name", found "' // line(1:min(len(line), 40)) // '"', &
          stat, errmsg)
        return
      end if
      g%npn = g%npn + 1
      g%pn(g%npn)%dim = d
      g%pn(g%npn)%tag = t
      g%pn(g%npn)%name = line(q1 + 1:q2 - 1)
      k = repeated_name(g)
      if (k > 0) then
        call bad(g, c, 'physical name "' // g%pn(g%npn)%name // '" given twice (dimension ' // str(d) // ' tag ' // &
          str(t) // ', and dimension ' // str(g%pn(k)%dim) // ' tag ' // str(g%pn(k)%tag) // &
          '): rebond would merge the two groups; give each its own name', stat, errmsg)
        return
      end if
    end do
    call text_line(c, line)
    if (trim(line) /= '$EndPhysicalNames') call bad(g, c, 'expected $EndPhysicalNames', stat, errmsg)
  end subroutine physical_names

  !> The first two integers of a text (words split by words' splitter).
  pure subroutine first_two(s, a, b, ierr)
    character(len=*), intent(in) :: s
    integer, intent(out) :: a, b, ierr
    integer :: i, j, k, v(2)
    i = 1
    v = 0
    a = 0
    b = 0
    ierr = 1
    do k = 1, 2
      do while (i <= len(s))
        if (.not. is_blank(s(i:i))) exit
        i = i + 1
      end do
      if (i > len(s)) return
      j = word_end(s, i)
      call parse_int_text(s(i:j - 1), v(k), ierr)
      if (ierr /= NUM_OK) return
      i = j
    end do
    a = v(1)
    b = v(2)
  end subroutine first_two

  !> $Entities (binary): counts (size_t x 4); points: tag, x y z, nphys, tags; curves, surfaces,
  !> volumes: tag, 6 bounds, nphys, tags, nbound, bounding tags.
  subroutine entities(g, c, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    type(cursor_t), intent(inout) :: c
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer(int64) :: counts(4), np, nb
    integer :: dim, k, j, ntot
    stat = STAT_OK
    if (.not. has(c, 32_int64)) then
      call bad(g, c, 'truncated $Entities', stat, errmsg)
      return
    end if
    do k = 1, 4
      counts(k) = size_at(c)
    end do
    if (any(counts < 0) .or. .not. has(c, sum(counts) * 20)) then
      call bad(g, c, 'entity counts beyond the file', stat, errmsg)
      return
    end if
    ntot = int(sum(counts))
    allocate (g%ent_dim(ntot), g%ent_tag(ntot), g%ent_ptr(ntot + 1), g%ent_phys(16))
    g%ent_ptr(1) = 1
    g%nent = 0
    g%nphys = 0
    do dim = 0, 3
      do k = 1, int(counts(dim + 1))
        if (.not. has(c, merge(36_int64, 60_int64, dim == 0))) then
          call bad(g, c, 'truncated $Entities', stat, errmsg)
          return
        end if
        g%nent = g%nent + 1
        g%ent_dim(g%nent) = dim
        g%ent_tag(g%nent) = int_at(c)
        c%pos = c%pos + merge(24_int64, 48_int64, dim == 0)    ! coordinates or bounding box
        np = size_at(c)
        if (np < 0 .or. .not. has(c, 4 * np + merge(0_int64, 8_int64, dim == 0))) then
          call bad(g, c, 'physical tag count beyond the file', stat, errmsg)
          return
        end if
        call grow(g%ent_phys, g%nphys + int(np))
        do j = 1, int(np)
          g%ent_phys(g%nphys + j) = abs(int_at(c))
        end do
        g%nphys = g%nphys + int(np)
        g%ent_ptr(g%nent + 1) = g%nphys + 1
        if (dim > 0) then
          nb = size_at(c)
          if (nb < 0 .or. .not. has(c, 4 * nb)) then
            call bad(g, c, 'bounding entity count beyond the file', stat, errmsg)
            return
          end if
          c%pos = c%pos + 4 * nb
        end if
      end do
    end do
    g%have_entities = .true.
    call end_block(g, c, '$EndEntities', stat, errmsg)
  end subroutine entities

  !> $Nodes (binary): numBlocks numNodes minTag maxTag (size_t); per block: dim, tag, parametric
  !> (int), n (size_t), n tags (size_t), n x y z (double). Parametric blocks are refused.
  subroutine nodes(g, c, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    type(cursor_t), intent(inout) :: c
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer(int64) :: nblock, nnode, nb, b, k
    integer, allocatable :: tags(:)
    integer :: param, i0, dup
    real(dp) :: xyz(3), z0
    stat = STAT_OK
    if (.not. has(c, 32_int64)) then
      call bad(g, c, 'truncated $Nodes', stat, errmsg)
      return
    end if
    nblock = size_at(c)
    nnode = size_at(c)
    c%pos = c%pos + 16                                        ! min and max tags: the map is built below
    if (nblock < 0 .or. nnode < 0 .or. nnode > huge(1) .or. .not. has(c, 32 * nnode + 20 * nblock)) then
      call bad(g, c, 'node counts beyond the file', stat, errmsg)
      return
    end if
    allocate (g%x(3, nnode), g%tag_of(nnode), tags(nnode))
    g%nnode = 0
    z0 = 0.0_dp
    do b = 1, nblock
      if (.not. has(c, 20_int64)) then
        call bad(g, c, 'truncated node block header', stat, errmsg)
        return
      end if
      c%pos = c%pos + 8                                       ! entity dim and tag
      param = int_at(c)
      nb = size_at(c)
      if (param /= 0 .or. nb < 0 .or. g%nnode + nb > nnode .or. .not. has(c, 32 * nb)) then
        call bad(g, c, 'a node block with parametric coordinates or beyond the announced nodes', stat, errmsg)
        return
      end if
      i0 = g%nnode
      do k = 1, nb
        call tag_at(g, c, 'node', tags(i0 + k), stat, errmsg)
        if (stat /= STAT_OK) return
      end do
      do k = 1, nb
        xyz = [real_at(c), real_at(c), real_at(c)]
        if (.not. all(abs(xyz) <= MAX_COORD)) then
          call bad(g, c, 'node ' // str(tags(i0 + k)) // ': a coordinate beyond ±1e100', stat, errmsg)
          return
        end if
        if (i0 + k == 1) z0 = xyz(3)
        if (abs(xyz(3) - z0) > 1.0e-9_dp * max(1.0_dp, maxval(abs(xyz(1:2)))) .and. g%ndim == 2) then
          call bad(g, c, 'node ' // str(tags(i0 + k)) // ' out of the xy plane (a 3D mesh needs DIMENSION 3)', stat, errmsg)
          return
        end if
        g%x(:, i0 + k) = xyz
      end do
      g%nnode = g%nnode + int(nb)
    end do
    if (g%nnode /= nnode) then
      call bad(g, c, 'the node blocks hold ' // str(g%nnode) // ' nodes, the header announced ' // str(int(nnode)), &
        stat, errmsg)
      return
    end if
    g%tag_of = tags
    call index_tags(g, dup)
    if (dup /= 0) then
      call bad(g, c, 'duplicate node tag ' // str(dup), stat, errmsg)
      return
    end if
    g%have_nodes = .true.
    call end_block(g, c, '$EndNodes', stat, errmsg)
  end subroutine nodes

  !> $Elements (binary): numBlocks numElements minTag maxTag (size_t); per block: dim, tag, type
  !> (int), n (size_t), then n x (element tag, node tags) (size_t).
  subroutine elements(g, c, stat, errmsg)
    type(gmsh_t), intent(inout) :: g
    type(cursor_t), intent(inout) :: c
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer(int64) :: nblock, nelem, nb, b, k
    integer :: edim, etag, gtype, et, nen, dim, ent, j, tag, nd(MAX_NEN)
    stat = STAT_OK
    if (.not. g%have_nodes) then
      call bad(g, c, '$Elements before $Nodes', stat, errmsg)
      return
    end if
    if (.not. has(c, 32_int64)) then
      call bad(g, c, 'truncated $Elements', stat, errmsg)
      return
    end if
    nblock = size_at(c)
    nelem = size_at(c)
    c%pos = c%pos + 16
    if (nblock < 0 .or. nelem < 0 .or. nelem > huge(1) .or. .not. has(c, 16 * nelem + 20 * nblock)) then
      call bad(g, c, 'element counts beyond the file', stat, errmsg)
      return
    end if
    allocate (g%etype(nelem), g%edim(nelem), g%eent(nelem), g%conn(MAX_NEN, nelem), g%enen(nelem))
    g%nelem = 0
    do b = 1, nblock
      if (.not. has(c, 20_int64)) then
        call bad(g, c, 'truncated element block header', stat, errmsg)
        return
      end if
      edim = int_at(c)
      etag = int_at(c)
      gtype = int_at(c)
      nb = size_at(c)
      g%lineno = 0
      call element_kind(g, gtype, et, nen, dim, stat, errmsg)
      if (stat /= STAT_OK) then
        call bad(g, c, 'unsupported element type ' // str(gtype), stat, errmsg)
        return
      end if
      if (edim /= dim .or. nb < 0 .or. g%nelem + nb > nelem .or. .not. has(c, 8 * (nen + 1) * nb)) then
        call bad(g, c, 'an element block of the wrong dimension or beyond the announced elements', stat, errmsg)
        return
      end if
      ent = 0
      do j = 1, g%nent
        if (g%ent_dim(j) == edim .and. g%ent_tag(j) == etag) then
          ent = j
          exit
        end if
      end do
      do k = 1, nb
        c%pos = c%pos + 8                                     ! the element tag
        do j = 1, nen
          call tag_at(g, c, 'node', tag, stat, errmsg)
          if (stat /= STAT_OK) return
          nd(j) = node_of(g, tag)
          if (nd(j) == 0) then
            call bad(g, c, 'unknown node tag ' // str(tag), stat, errmsg)
            return
          end if
        end do
        call store_element(g, gtype, et, dim, ent, nd(1:nen), stat, errmsg)
        if (stat /= STAT_OK) return
      end do
    end do
    if (g%nelem /= nelem) then
      call bad(g, c, 'the element blocks hold ' // str(g%nelem) // ' elements, the header announced ' // &
        str(int(nelem)), stat, errmsg)
      return
    end if
    g%have_elements = .true.
    call end_block(g, c, '$EndElements', stat, errmsg)
  end subroutine elements
end module gmsh_binary
