!> Scene input: node-to-face contact in 3D, `GAP name NODES ga FACES gf [RESTITUTION e]
!> [FRICTION mu] [PAIRING START]` (docs/input.md, "GAP … FACES"): each node b of ga paired at t = 0
!> with the closest free face of gf it projects onto (face_projection), g = n·((x_b + u_b) −
!> Σ N_k(ξ, η) (x_k + u_k)) >= 0, n the face's outward unit normal at b's foot, N_k its shape
!> functions there. The pairing is made once (PAIRING START); a pairing that follows the
!> configuration (STEP) is not available in 3D and is refused by name, as is the default on a
!> KINEMATICS LARGE model (which in 2D follows).
module scene_gap_faces
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_INPUT, set_error, str
  use statement, only: statement_t, stmt_error, find_param
  use scene, only: scene_t, condition_t
  use scene_helpers, only: model_size, get_choice, on_models, modelled_group, get_restitution
  use mesh_faces, only: face_set_t, group_faces
  use face_projection, only: project_on_face
  implicit none
  private
  public :: do_gap_faces

  !> How far outside a face's parameter range a foot may fall and still pair with it (the seams
  !> between faces: a node above an edge projects onto both).
  real(dp), parameter :: EDGE_TOL = 1.0e-9_dp

contains

  subroutine do_gap_faces(scn, st, stat, errmsg)
    type(scene_t), intent(inout) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(face_set_t) :: faces
    type(condition_t) :: c
    integer :: ga, gf, kn, kf, i, k
    real(dp) :: tol
    kn = find_param(st, 'NODES')
    kf = find_param(st, 'FACES')
    stat = STAT_OK
    if (scn%mesh%ndim /= 3) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'FACES (node-to-face contact) needs DIMENSION 3 ' // &
        '(in 2D: SEGMENTS)', st%params(kf)%keytok))
      return
    end if
    if (kn == 0 .or. find_param(st, 'WITH') > 0 .or. find_param(st, 'PAIRS') > 0 .or. find_param(st, 'NORMAL') > 0 .or. &
        find_param(st, 'SEGMENTS') > 0) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'FACES goes with NODES ga only (no WITH, PAIRS, ' // &
        'SEGMENTS or NORMAL: the faces give the normal)', st%params(kf)%keytok))
      return
    end if
    call get_restitution(st, c%restitution, stat, errmsg)
    if (stat /= STAT_OK) return
    call modelled_group(scn, st, st%params(kn)%values(1), ga, stat, errmsg)
    if (stat == STAT_OK) call modelled_group(scn, st, st%params(kf)%values(1), gf, stat, errmsg)
    if (stat /= STAT_OK) return
    call pairing_start(scn, st, [scn%mesh%ngroups(ga)%items, scn%mesh%ngroups(gf)%items], stat, errmsg)
    if (stat /= STAT_OK) return
    call group_faces(scn%mesh, scn%mesh%ngroups(gf)%items, faces, stat, errmsg)
    if (stat /= STAT_OK) then
      errmsg = stmt_error(st, 'FACES ' // scn%mesh%ngroups(gf)%name // ': ' // errmsg, st%params(kf)%values(1))
      return
    end if
    tol = 1.0e-10_dp * model_size(scn%mesh)
    c%source = st%lead(1)%text
    c%line = st%line
    k = 0
    do i = 1, size(scn%mesh%ngroups(ga)%items)
      c%node_b = scn%mesh%ngroups(ga)%items(i)
      call pair_node(scn, faces, c, stat, errmsg)
      if (stat /= STAT_OK) then
        errmsg = stmt_error(st, errmsg, st%params(kf)%values(1))
        return
      end if
      if (c%face(1) == 0) cycle                ! (facing no face: no condition)
      if (c%g0 < -tol) then
        call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'node ' // str(scn%mesh%node_tag(c%node_b)) // &
          ' starts ' // str(-c%g0) // ' inside the face of ' // scn%mesh%ngroups(gf)%name // ' it faces', st%lead(1)))
        return
      end if
      scn%conditions = [scn%conditions, c]
      k = k + 1
    end do
    if (k == 0) call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'no node of ' // scn%mesh%ngroups(ga)%name // &
      ' faces a face of ' // scn%mesh%ngroups(gf)%name, st%params(kf)%values(1)))
  end subroutine do_gap_faces

  !> PAIRING: START only in 3D (given, or the default where no node is on a LARGE model).
  subroutine pairing_start(scn, st, nodes, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(statement_t), intent(in) :: st
    integer, intent(in) :: nodes(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, kp
    call get_choice(st, 'PAIRING', ['AUTO ', 'START', 'STEP '], 'AUTO', k, stat, errmsg)
    if (stat /= STAT_OK) return
    kp = find_param(st, 'PAIRING')
    if (k == 3) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'PAIRING STEP (a pairing that follows the ' // &
        'configuration) is not available with FACES in DIMENSION 3 yet: PAIRING START pairs once, at t = 0', &
        st%params(kp)%values(1)))
    else if (k == 1 .and. on_models(scn, nodes, scn%models%large)) then
      call set_error(stat, errmsg, STAT_INPUT, stmt_error(st, 'a node of FACES or NODES is on a KINEMATICS LARGE ' // &
        'model, where the pairing would follow the configuration (PAIRING STEP, not available in DIMENSION 3 yet): ' // &
        'give PAIRING START to pair once, at t = 0', st%params(find_param(st, 'FACES'))%keytok))
    end if
  end subroutine pairing_start

  !> c's face: the face of faces that b's foot falls on (to EDGE_TOL in its parameters) with the
  !> smallest |distance| (a face holding b is skipped, and one b is behind by more than half its
  !> size: b is then on the body's other side); its weights, normal and gap (negative: b starts
  !> inside, an input error of the caller). c%face(1) = 0 where b faces none.
  subroutine pair_node(scn, faces, c, stat, errmsg)
    type(scene_t), intent(in) :: scn
    type(face_set_t), intent(in) :: faces
    type(condition_t), intent(inout) :: c
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: f, nfn, best
    real(dp) :: w(8), normal(3), dist, xf(3, 8), xb(3), dbest
    logical :: inside, ok
    stat = STAT_OK
    xb = scn%mesh%x(:, c%node_b)
    best = 0
    dbest = huge(1.0_dp)
    c%face = 0
    c%face_w = 0.0_dp
    do f = 1, faces%n
      nfn = faces%nfn(f)
      if (any(faces%node(1:nfn, f) == c%node_b)) cycle
      xf(:, 1:nfn) = scn%mesh%x(:, faces%node(1:nfn, f))
      call project_on_face(nfn, xf, xb, EDGE_TOL, w, normal, dist, inside, ok)
      if (.not. (ok .and. inside)) cycle
      ! Behind the face by more than half its size: b is on the body's other side, not inside it.
      if (dist < -0.5_dp * face_size(xf(:, 1:nfn))) cycle
      if (abs(dist) >= dbest) cycle
      dbest = abs(dist)
      best = f
      c%face = 0
      c%face(1:nfn) = faces%node(1:nfn, f)
      c%face_w = w
      c%normal = normal
      c%g0 = dist
    end do
    if (best == 0) return
    nfn = faces%nfn(best)
    c%node_a = c%face(maxloc(c%face_w(1:nfn), 1))
    c%node_c = 0
    c%xi = 0.0_dp
    if (.not. all(abs(c%normal) <= 1.0_dp)) then
      call set_error(stat, errmsg, STAT_INPUT, 'the face paired with node ' // str(scn%mesh%node_tag(c%node_b)) // &
        ' is degenerate')
    end if
  end subroutine pair_node

  !> The largest distance between two nodes of a face.
  pure real(dp) function face_size(xf) result(d)
    real(dp), intent(in) :: xf(:, :)
    integer :: i, j
    d = 0.0_dp
    do j = 2, size(xf, 2)
      do i = 1, j - 1
        d = max(d, norm2(xf(:, j) - xf(:, i)))
      end do
    end do
  end function face_size
end module scene_gap_faces
