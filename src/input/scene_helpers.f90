!> Getters shared by the statement families of the scene (scene_mesh … scene_run): an element
!> type, a node group, a word among choices, a pair of reals, the model size.
module scene_helpers
  use kinds, only: dp
  use array_utils, only: stable_order
  use errors, only: STAT_OK, STAT_INPUT, set_error, str, upper
  use mesh, only: mesh_t, MAX_COORD
  use element_traits, only: etype_from_name, etype_name
  use statement, only: statement_t, token_t, stmt_error, find_param, get_real, get_word, get
  use scene, only: scene_t
  implicit none
  private
  public :: on_models, modelled_group, get_restitution
  public :: get_etype, node_group, get_choice, get_pair, get_point, model_size, get_unit, check_modelled, resolve_path, &
    get_function, check_count

contains

  !> Element type named by parameter key; allowed(:) restricts the choice.
  subroutine get_etype(st, key, allowed, et, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    integer, intent(in) :: allowed(:)
    integer, intent(out) :: et
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: w, names
    integer :: k, i
    call get_word(st, key, w, stat, errmsg)
    if (stat /= STAT_OK) return
    et = etype_from_name(upper(w))
    if (any(allowed == et)) return
    names = ''
    do i = 1, size(allowed)
      names = names // merge(', ', '  ', i > 1) // etype_name(allowed(i))
    end do
    names = adjustl(names)
    k = find_param(st, key)
    call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'element type not allowed here (expected one of: ' // &
      trim(names) // ')', st%params(k)%values(1)))
  end subroutine get_etype

  !> Index of the node group named by a token, with an error naming it when unknown and listing
  !> the groups there are, the closest spellings first.
  subroutine node_group(scn, st, tok, ig, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    type(token_t), intent(in) :: tok
    integer, intent(out) :: ig
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    ig = scn%mesh%find_node_group(tok%text)
    if (ig == 0) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'unknown node group (' // &
      group_list(scn%mesh, tok%text) // ')', tok))
  end subroutine node_group

  !> "existing groups: a, b, …": the node groups of the mesh, those closest to name (edit distance,
  !> case ignored) first, at most 12 named.
  function group_list(m, name) result(s)
    type(mesh_t), intent(in) :: m
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: s
    real(dp), allocatable :: d(:)
    integer, allocatable :: order(:)
    integer :: i, n
    n = m%nngroup
    if (n == 0) then
      s = 'the mesh has no node group'
      return
    end if
    allocate (d(n), order(n))
    do i = 1, n
      d(i) = edit_distance(upper(name), upper(m%ngroups(i)%name))
      order(i) = i
    end do
    call stable_order(d, order)                   ! stable: file order among ties
    s = 'existing groups: ' // m%ngroups(order(1))%name
    do i = 2, min(n, 12)
      s = s // ', ' // m%ngroups(order(i))%name
    end do
    if (n > 12) s = s // ', … (' // str(n) // ' in all)'
  end function group_list

  !> Levenshtein distance between a and b (insertions, deletions, substitutions).
  pure integer function edit_distance(a, b) result(dist)
    character(len=*), intent(in) :: a, b
    integer :: row(0:len(b)), prev, tmp, i, j
    row = [(j, j = 0, len(b))]
    do i = 1, len(a)
      prev = row(0)
      row(0) = i
      do j = 1, len(b)
        tmp = row(j)
        row(j) = min(row(j) + 1, row(j - 1) + 1, prev + merge(0, 1, a(i:i) == b(j:j)))
        prev = tmp
      end do
    end do
    dist = row(len(b))
  end function edit_distance

  !> RESTITUTION e of an OBSTACLE or GAP: 0 <= e <= 1, default 1 (elastic).
  subroutine get_restitution(st, e, stat, errmsg)
    type(statement_t), intent(in) :: st
    real(dp), intent(out) :: e
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call get(st, 'RESTITUTION', e, stat, errmsg, default=1.0_dp, lower=0.0_dp, lower_inclusive=.true., &
      upper=1.0_dp, upper_inclusive=.true.)
  end subroutine get_restitution

  !> The node group named by tok (node_group) whose every node is on a modelled element
  !> (check_modelled): a contact statement's groups.
  subroutine modelled_group(scn, st, tok, ig, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    type(token_t), intent(in) :: tok
    integer, intent(out) :: ig
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call node_group(scn, st, tok, ig, stat, errmsg)
    if (stat == STAT_OK) call check_modelled(scn, st, tok, scn%mesh%ngroups(ig)%items, stat, errmsg)
  end subroutine modelled_group

  !> Every node of nodes must carry an element of some MODEL (scn%modelled, set after the models
  !> are read): a node of no model has no degree of freedom, and as a contact or load node it
  !> would silently be a fixed point. The error names the first such node and the group (tok).
  subroutine check_modelled(scn, st, tok, nodes, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    type(token_t), intent(in) :: tok
    integer, intent(in) :: nodes(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: i
    stat = STAT_OK
    if (.not. allocated(scn%modelled)) return
    do i = 1, size(nodes)
      if (scn%modelled(nodes(i))) cycle
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'node ' // str(scn%mesh%node_tag(nodes(i))) // &
        ' of group ' // tok%text // ' carries no element of any MODEL (it has no degree of freedom: a contact or ' // &
        'load there would act on a fixed point); give its elements a MODEL or leave it out', tok))
      return
    end do
  end subroutine check_modelled

  !> Index in choices(:) of the word given to parameter key (default when absent).
  subroutine get_choice(st, key, choices, default, k, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key, choices(:), default
    integer, intent(out) :: k
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: w, names
    integer :: i
    call get_word(st, key, w, stat, errmsg, default=default)
    if (stat /= STAT_OK) return
    do k = 1, size(choices)
      if (upper(w) == trim(choices(k))) return
    end do
    names = trim(choices(1))
    do i = 2, size(choices)
      names = names // ' or ' // trim(choices(i))
    end do
    call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, key // ': expected ' // names, &
      st%params(find_param(st, key))%values(1)))
  end subroutine get_choice

  !> size(p) numbers of a parameter (2, or 3 in a DIMENSION 3 scene): another count is an error
  !> naming the parameter.
  subroutine get_pair(st, key, p, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    real(dp), intent(out) :: p(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k
    call check_count(st, key, size(p), stat, errmsg)
    if (stat /= STAT_OK) return
    do k = 1, size(p)
      call get_real(st, key, p(k), stat, errmsg, index=k)
      if (stat /= STAT_OK) return
    end do
  end subroutine get_pair

  !> A parameter's values are n numbers (2 in 2D, 3 in 3D: the coordinates of a point or vector).
  subroutine check_count(st, key, n, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    integer, intent(in) :: n
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k
    stat = STAT_OK
    k = find_param(st, key)
    if (k == 0) return
    if (size(st%params(k)%values) == n) return
    if (size(st%params(k)%values) > n) then           ! (the first word too many is the one at fault)
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, key // ' takes ' // str(n) // ' numbers in a ' // &
        str(n) // 'D scene, not ' // str(size(st%params(k)%values)), st%params(k)%values(n + 1)))
      return
    end if
    call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, key // ' takes ' // str(n) // ' numbers in a ' // &
      str(n) // 'D scene, not ' // str(size(st%params(k)%values)), st%params(k)%keytok))
  end subroutine check_count

  !> A point (x y) of parameter key, each coordinate within ±MAX_COORD.
  subroutine get_point(st, key, p, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    real(dp), intent(out) :: p(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k
    call check_count(st, key, size(p), stat, errmsg)
    if (stat /= STAT_OK) return
    do k = 1, size(p)
      call get_real(st, key, p(k), stat, errmsg, index=k, lower=-MAX_COORD, lower_inclusive=.true., upper=MAX_COORD, &
        upper_inclusive=.true.)
      if (stat /= STAT_OK) return
    end do
  end subroutine get_point

  !> Largest extent of the mesh, the length scale of the gap tolerance.
  pure real(dp) function model_size(m)
    type(mesh_t), intent(in) :: m
    integer :: d
    model_size = 1.0_dp
    if (m%nnode == 0) return
    model_size = max(maxval(m%x(1, 1:m%nnode)) - minval(m%x(1, 1:m%nnode)), &
      maxval(m%x(2, 1:m%nnode)) - minval(m%x(2, 1:m%nnode)), tiny(1.0_dp))
    do d = 3, m%ndim                           ! (3D: z too)
      model_size = max(model_size, maxval(m%x(d, 1:m%nnode)) - minval(m%x(d, 1:m%nnode)))
    end do
  end function model_size

  !> A unit vector from parameter key.
  subroutine get_unit(st, key, n, stat, errmsg)
    type(statement_t), intent(in) :: st
    character(len=*), intent(in) :: key
    real(dp), intent(out) :: n(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call get_pair(st, key, n, stat, errmsg)
    if (stat /= STAT_OK) return
    if (norm2(n) <= 0.0_dp) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, key // ' must be a non-zero vector', &
        st%params(find_param(st, key))%keytok))
      return
    end if
    n = n / norm2(n)
  end subroutine get_unit

  !> A path relative to the directory of the scene file (absolute paths unchanged).
  pure function resolve_path(scene_path, file) result(full)
    character(len=*), intent(in) :: scene_path, file
    character(len=:), allocatable :: full
    integer :: k
    if (len(file) > 0) then
      if (file(1:1) == '/') then
        full = file
        return
      end if
    end if
    k = index(scene_path, '/', back=.true.)
    full = scene_path(1:k) // file
  end function resolve_path

  !> Index of the function named by parameter FUNCTION (0 when absent).
  subroutine get_function(scn, st, ifn, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: ifn
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: w
    integer :: i
    ifn = 0
    stat = STAT_OK
    if (find_param(st, 'FUNCTION') == 0) return
    call get_word(st, 'FUNCTION', w, stat, errmsg)
    if (stat /= STAT_OK) return
    do i = 1, size(scn%functions)
      if (scn%functions(i)%name == w) ifn = i
    end do
    if (ifn == 0) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'unknown function', &
      st%params(find_param(st, 'FUNCTION'))%values(1)))
  end subroutine get_function

  !> Whether one of the nodes is on an element of a model with sel(model) (KINEMATICS LARGE:
  !> scn%models%large).
  logical function on_models(scn, nodes, sel) result(found)
    type(scene_t), intent(in) :: scn
    integer, intent(in) :: nodes(:)
    logical, intent(in) :: sel(:)
    logical, allocatable :: in(:)
    integer :: e, im
    allocate (in(scn%mesh%nnode))
    in = .false.
    in(nodes) = .true.
    found = .false.
    do e = 1, scn%mesh%nelem
      im = scn%elem_model(e)
      if (im == 0) cycle
      if (.not. sel(im)) cycle
      if (any(in(scn%mesh%conn(1:scn%mesh%nen(e), e)))) then
        found = .true.
        return
      end if
    end do
  end function on_models
end module scene_helpers
