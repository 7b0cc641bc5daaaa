!> Checks of the contact setup before the first step (newmark's prepare_run): IMPACT MASSLESS
!> needs contact nodes whose mass can move to their neighbours, and the initial state
!> (INITIAL DISPLACEMENT, STATIC) must not put a node inside an obstacle.
module contact_checks
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use scene, only: scene_t, condition_nodes, condition_keyword, TRANSLATION_SLOT, COND_NODES
  use assembly, only: system_t
  use contact, only: contact_set_t, contact_gaps
  implicit none
  private
  public :: check_massless, check_initial_gaps

contains

  !> IMPACT MASSLESS moves the contact nodes' mass to their neighbours: a contact node whose
  !> elements have contact nodes only (a point mass, a body touching with every node) keeps it,
  !> and would then need a velocity correction MASSLESS does not make: bad input, named.
  !> eqs: the contact nodes' equations (massless), each once.
  subroutine check_massless(scn, sys, eqs, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    integer, allocatable, intent(out) :: eqs(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), allocatable :: dm(:)
    logical, allocatable :: mark(:)
    real(dp) :: w(COND_NODES)
    integer :: j, n, k, i, nodes(COND_NODES)
    stat = STAT_OK
    allocate (mark(sys%dofs%neq))
    mark = .false.
    allocate (dm(sys%dofs%neq))
    call sys%ops%pat%diagonal(sys%ops%mval, dm)
    do j = 1, size(scn%conditions)
      associate (c => scn%conditions(j))
        call condition_nodes(c, nodes, w)
        do k = 1, COND_NODES
          n = nodes(k)
          if (n <= 0) cycle
          if (any(dm(pack(sys%dofs%eqn(TRANSLATION_SLOT, n), sys%dofs%eqn(TRANSLATION_SLOT, n) > 0)) > 0.0_dp)) then
            call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(c%line) // ': ' // &
              condition_keyword(c) // ' ' // c%source // ': SCHEME IMPACT MASSLESS ' // &
              'cannot move the mass of node ' // str(n) // ' (its elements have contact nodes only: a point mass, or ' // &
              'a body touching with all its nodes); use IMPACT PAPER or PERSIST' // ", at '" // c%source // "'")
            return
          end if
          do i = 1, 3                                  ! UX, UY[, UZ]
            if (sys%dofs%eqn(TRANSLATION_SLOT(i), n) > 0) mark(sys%dofs%eqn(TRANSLATION_SLOT(i), n)) = .true.
          end do
        end do
      end associate
    end do
    eqs = pack([(i, i = 1, sys%dofs%neq)], mark)
  end subroutine check_massless

  !> The initial state (INITIAL DISPLACEMENT, STATIC) must not put a node inside an obstacle or
  !> two nodes of a GAP through each other (the mesh itself is checked by the scene): bad input,
  !> naming the statement and the nodes (at most 5 of them).
  subroutine check_initial_gaps(scn, cs, u, lscale, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(contact_set_t), intent(in) :: cs
    real(dp), intent(in) :: u(:), lscale
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), allocatable :: g(:)
    character(len=:), allocatable :: list
    integer :: j, nbad, first
    stat = STAT_OK
    allocate (g(cs%n_conditions()))
    call contact_gaps(cs, u, g)
    nbad = 0
    first = 0
    list = ''
    do j = 1, size(scn%conditions)               ! (the IMPOSE rows after them are equalities)
      if (.not. g(j) < -1.0e-10_dp * lscale) cycle
      nbad = nbad + 1
      if (first == 0) first = j
      if (nbad > 5) cycle
      associate (c => scn%conditions(j))
        if (c%node_a > 0) list = list // merge('; ', '  ', nbad > 1) // 'node ' // str(scn%mesh%node_tag(c%node_a)) // ' and'
        list = list // merge('; ', '  ', nbad > 1 .and. c%node_a == 0) // ' node ' // str(scn%mesh%node_tag(c%node_b)) // &
          ' (x = ' // &
          str(scn%mesh%x(1, c%node_b)) // ', y = ' // str(scn%mesh%x(2, c%node_b)) // ') by ' // str(-g(j))
      end associate
    end do
    if (nbad == 0) return
    associate (c => scn%conditions(first))
      call set_error(stat, errmsg, STAT_INPUT, scn%path // ':' // str(c%line) // ': ' // &
        condition_keyword(c) // ' ' // c%source // ': the initial displacement puts ' // &
        str(nbad) // ' contact node(s) inside: ' // trim(adjustl(list)) // trim(merge(' ...', '    ', nbad > 5)) // &
        ", at '" // c%source // "'")
    end associate
  end subroutine check_initial_gaps
end module contact_checks
