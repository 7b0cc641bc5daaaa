!> The grammar of a keyword file (scene, sweep): which keywords exist, how many lead words
!> each takes, which parameters with how many values, whether a statement may be repeated
!> (once) and must be given (required). Built by the caller (scene_schema, sweep_schema), read
!> by scene_parser, which splits the statements with it.
module statement_schema
  use errors, only: upcase => upper, str
  use statement, only: token_t
  implicit none
  private
  public :: schema_t, kwdef_t, pdef_t, find_kw, find_pdef, param_of_token, pdef_list, arity_text, plural

  type :: pdef_t
    character(len=:), allocatable :: name
    integer :: nmin = 0, nmax = 0             ! nmax = -1: unbounded
    logical :: repeatable = .false.
  end type pdef_t

  type :: kwdef_t
    character(len=:), allocatable :: name
    character(len=:), allocatable :: hint     !< for a missing required statement, e.g. 'TIME STEP h END t'
    logical :: once = .false.                 !< may be given once at most
    logical :: required = .false.             !< must be given (check_required)
    integer :: nlead_min = 0, nlead_max = 0
    integer :: np = 0
    type(pdef_t), allocatable :: params(:)
  end type kwdef_t

  !> What each keyword accepts. A mistake while building it (duplicate, unknown keyword, bad
  !> counts) is remembered in `defect` and reported by every parse, since add_* has no stat.
  type :: schema_t
    ! Read by scene_parser; written by add_keyword and add_param only.
    integer :: nkw = 0
    type(kwdef_t), allocatable :: kws(:)
    character(len=:), allocatable :: defect
  contains
    procedure :: add_keyword => schema_add_keyword
    procedure :: add_param => schema_add_param
    procedure :: param_names => schema_param_names
    procedure :: keyword_names => schema_keyword_names
    procedure :: has_keyword => schema_has_keyword
  end type schema_t

contains

  !> Declare a keyword taking between nlead_min and nlead_max lead tokens (both default 0).
  !> once: the statement may be given once at most (parse_string refuses a repeat); required:
  !> it must be given (check_required, hint: what it looks like, for the message).
  subroutine schema_add_keyword(self, name, nlead_min, nlead_max, once, required, hint)
    class(schema_t), intent(inout) :: self
    character(len=*), intent(in) :: name
    integer, intent(in), optional :: nlead_min, nlead_max
    logical, intent(in), optional :: once, required
    character(len=*), intent(in), optional :: hint
    type(kwdef_t), allocatable :: tmp(:)
    character(len=:), allocatable :: u
    u = upcase(trim(adjustl(name)))
    if (.not. allocated(self%kws)) allocate (self%kws(16))
    if (len(u) == 0) then
      call note_defect(self, 'empty keyword name')
      return
    end if
    if (find_kw(self, u) > 0) then
      call note_defect(self, 'keyword ' // u // ' declared twice')
      return
    end if
    if (self%nkw == size(self%kws)) then
      allocate (tmp(2 * size(self%kws)))
      tmp(1:self%nkw) = self%kws(1:self%nkw)
      call move_alloc(tmp, self%kws)
    end if
    self%nkw = self%nkw + 1
    associate (k => self%kws(self%nkw))
      k%name = u
      k%nlead_min = 0
      k%nlead_max = 0
      if (present(nlead_min)) k%nlead_min = nlead_min
      if (present(nlead_max)) k%nlead_max = nlead_max
      if (present(nlead_min) .and. .not. present(nlead_max)) k%nlead_max = k%nlead_min
      k%np = 0
      if (present(once)) k%once = once
      if (present(required)) k%required = required
      k%hint = ''
      if (present(hint)) k%hint = hint
      allocate (k%params(8))
      if (k%nlead_min < 0 .or. k%nlead_max < k%nlead_min) &
        call note_defect(self, 'keyword ' // u // ': bad nlead_min/nlead_max')
    end associate
  end subroutine schema_add_keyword

  !> Declare parameter `name` of `keyword` taking nmin..nmax values (nmax = -1: unbounded;
  !> both default 0, a flag). A non-repeatable parameter may appear once per statement.
  subroutine schema_add_param(self, keyword, name, nmin, nmax, repeatable)
    class(schema_t), intent(inout) :: self
    character(len=*), intent(in) :: keyword, name
    integer, intent(in), optional :: nmin, nmax
    logical, intent(in), optional :: repeatable
    type(pdef_t), allocatable :: tmp(:)
    character(len=:), allocatable :: u
    integer :: k
    k = find_kw(self, upcase(trim(adjustl(keyword))))
    if (k == 0) then
      call note_defect(self, 'parameter ' // trim(name) // ' added to undeclared keyword ' // trim(keyword))
      return
    end if
    u = upcase(trim(adjustl(name)))
    associate (kd => self%kws(k))
      if (len(u) == 0) then
        call note_defect(self, 'empty parameter name for ' // kd%name)
        return
      end if
      if (find_pdef(kd, u) > 0) then
        call note_defect(self, 'parameter ' // u // ' of ' // kd%name // ' declared twice')
        return
      end if
      if (kd%np == size(kd%params)) then
        allocate (tmp(2 * size(kd%params)))
        tmp(1:kd%np) = kd%params(1:kd%np)
        call move_alloc(tmp, kd%params)
      end if
      kd%np = kd%np + 1
      kd%params(kd%np)%name = u
      kd%params(kd%np)%nmin = 0
      kd%params(kd%np)%nmax = 0
      if (present(nmin)) kd%params(kd%np)%nmin = nmin
      if (present(nmax)) kd%params(kd%np)%nmax = nmax
      if (present(nmin) .and. .not. present(nmax)) kd%params(kd%np)%nmax = nmin
      kd%params(kd%np)%repeatable = .false.
      if (present(repeatable)) kd%params(kd%np)%repeatable = repeatable
      associate (pd => kd%params(kd%np))
        if (pd%nmin < 0 .or. (pd%nmax >= 0 .and. pd%nmax < pd%nmin) .or. pd%nmax < -1) &
          call note_defect(self, 'parameter ' // u // ' of ' // kd%name // ': bad nmin/nmax')
      end associate
    end associate
  end subroutine schema_add_param

  !> Comma-separated parameter names of a keyword, in declaration order ('' if none or unknown).
  function schema_param_names(self, keyword) result(s)
    class(schema_t), intent(in) :: self
    character(len=*), intent(in) :: keyword
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    k = find_kw(self, upcase(keyword))
    if (k > 0) s = pdef_list(self%kws(k))
  end function schema_param_names

  !> Comma-separated keyword names, in declaration order.
  function schema_keyword_names(self) result(s)
    class(schema_t), intent(in) :: self
    character(len=:), allocatable :: s
    integer :: k
    s = ''
    do k = 1, self%nkw
      if (k > 1) s = s // ', '
      s = s // self%kws(k)%name
    end do
  end function schema_keyword_names

  !> Whether a keyword (any case) is declared.
  logical function schema_has_keyword(self, keyword)
    class(schema_t), intent(in) :: self
    character(len=*), intent(in) :: keyword
    schema_has_keyword = find_kw(self, upcase(keyword)) > 0
  end function schema_has_keyword

  subroutine note_defect(self, msg)
    type(schema_t), intent(inout) :: self
    character(len=*), intent(in) :: msg
    if (.not. allocated(self%defect)) self%defect = msg   ! keep the first: later ones may follow from it
  end subroutine note_defect

  pure integer function find_kw(sch, uname)
    type(schema_t), intent(in) :: sch
    character(len=*), intent(in) :: uname
    integer :: k
    find_kw = 0
    do k = 1, sch%nkw
      if (sch%kws(k)%name == uname .and. len(sch%kws(k)%name) == len(uname)) then
        find_kw = k
        return
      end if
    end do
  end function find_kw

  pure integer function find_pdef(kd, uname)
    type(kwdef_t), intent(in) :: kd
    character(len=*), intent(in) :: uname
    integer :: p
    find_pdef = 0
    do p = 1, kd%np
      if (kd%params(p)%name == uname .and. len(kd%params(p)%name) == len(uname)) then
        find_pdef = p
        return
      end if
    end do
  end function find_pdef

  !> Index of the parameter named by token `t`, 0 if `t` is not one (quoted tokens never are).
  !> Lengths are compared first so long value tokens are never upper-cased.
  pure integer function param_of_token(kd, t)
    type(kwdef_t), intent(in) :: kd
    type(token_t), intent(in) :: t
    integer :: p
    param_of_token = 0
    if (t%quoted) return
    do p = 1, kd%np
      if (len(kd%params(p)%name) /= len(t%text)) cycle
      if (kd%params(p)%name == upcase(t%text)) then
        param_of_token = p
        return
      end if
    end do
  end function param_of_token

  pure function pdef_list(kd) result(s)
    type(kwdef_t), intent(in) :: kd
    character(len=:), allocatable :: s
    integer :: p
    s = ''
    do p = 1, kd%np
      if (p > 1) s = s // ', '
      s = s // kd%params(p)%name
    end do
  end function pdef_list

  !> "2 values", "at least 1 value", "1 to 3 values", "no value".
  pure function arity_text(nmin, nmax) result(s)
    integer, intent(in) :: nmin, nmax
    character(len=:), allocatable :: s
    if (nmax == nmin) then
      if (nmin == 0) then
        s = 'no value'
      else
        s = str(nmin) // plural(nmin)
      end if
    else if (nmax < 0) then
      s = 'at least ' // str(nmin) // plural(nmin)
    else
      s = str(nmin) // ' to ' // str(nmax) // ' values'
    end if
  end function arity_text

  pure function plural(n) result(s)
    integer, intent(in) :: n
    character(len=:), allocatable :: s
    if (n == 1) then
      s = ' value'
    else
      s = ' values'
    end if
  end function plural
end module statement_schema
