!> The result files of a run (README "Outputs"): history.csv, probes.csv, events.csv (contact
!> scenes) and fields.h5/.xmf, opened together (or resumed after a checkpoint), written per
!> step, closed together. The column names are public contracts: extended at the end only.
!> Rows are built without allocation (text_format): they are written in the time loop.
module run_outputs
  use kinds, only: dp
  use errors, only: STAT_OK
  use scene, only: scene_t, condition_nodes, condition_tangent, scene_axisymmetric, COND_NODES
  use mesh, only: mesh_t, DOF_UX, DOF_UY, DOF_UZ, DOF_RZ
  use assembly, only: system_t, stored_energy
  use point_fields, only: element_stress, element_scalars, nodal_values
  use stress_recovery, only: recovery_t, NREC
  use energy, only: energy_t
  use contact, only: contact_set_t, contact_event_t, EVENT_ESTABLISH, row_geometry_t
  use history_writer, only: csv_file_t
  use fields_hdf5, only: fields_writer_t
  use text_format, only: put_es, put_int, put_text, put_csv, csv_field
  use os_utils, only: remove_file
  implicit none
  private
  public :: output_set_t, HISTORY_HEADER, EVENTS_HEADER, CONTACTS_HEADER

  character(len=*), parameter :: HISTORY_HEADER = &
    'step,time,kinetic,internal,external,correction,balance,iterations,active_contacts,dissipated,stored,' // &
    'impact_dissipated,momentum_x,momentum_y,angular_momentum,damping,substeps,contact_held,h,friction_dissipated,' // &
    'momentum_z,angular_momentum_x,angular_momentum_y'
  character(len=*), parameter :: EVENTS_HEADER = 'step,time,constraint,nodes,event,gap_start,multiplier,energy_restored,' &
    // 'contact'
  character(len=*), parameter :: CONTACTS_HEADER = 'step,time,contact,active,force_x,force_y,impulse_x,impulse_y,' // &
    'min_gap,moment,impulse_moment,slip,force_z,impulse_z'

  type :: output_set_t
    private
    type(csv_file_t) :: hist, probes, ev, contacts
    type(fields_writer_t) :: fields
    logical :: with_events = .false., with_fields = .false.
    logical :: axisymmetric = .false.   !< the scene is axisymmetric (momentum_x, angular_momentum: 0)
    integer :: ndim = 2                 !< the scene's dimension
    integer :: ncomp = 4                !< stress components of fields.h5 (4; 6 in 3D)
    integer :: slots(3) = [1, 2, 3]     !< the DOF slots of the nodal fields' rows (UX UY RZ; 3D: UX UY UZ)
    integer :: last_step = 0                 !< the run's last step: always written
    ! contacts.csv: the contact statements (names, in order of appearance), the statement of
    ! each condition, the impulse each gave its NODES group since the last row, that row's time.
    real(dp) :: h = 0.0_dp, t_row = 0.0_dp
    character(len=:), allocatable :: cnames(:)
    character(len=:), allocatable :: row     !< a contacts.csv or events.csv line (sized for the longest name)
    integer, allocatable :: cstat(:)
    real(dp), allocatable :: cimp(:, :), cforce(:, :), cslip(:)   !< cslip: Σ slip since the last row
    real(dp), allocatable :: nodal_u(:, :), nodal_v(:, :), estress(:, :), reaction(:, :), escalar(:, :)
    integer, allocatable :: kept(:)                   !< the elements fields.h5 shows: those of a MODEL
    real(dp), allocatable :: wstress(:, :), wscalar(:, :)   !< their stresses and scalars
    real(dp), allocatable :: support(:, :)                  !< (3, nnode) the supports' reactions
    type(recovery_t) :: rec                                 !< integration points and nodal stresses
    logical :: rec_built = .false.
    real(dp), allocatable :: nodal(:, :), pvals(:, :), pdisp(:, :)   !< (NREC, nnode), (NREC, npt), (3, npt)
    real(dp) :: h_row = 0.0_dp               !< the length of the step the next row ends (history.csv h)
    !> contact_held, h, friction_dissipated, momentum_z, angular_momentum_x, angular_momentum_y
    real(dp) :: htail2(6) = 0.0_dp
    real(dp), allocatable :: preals(:), hreals(:), htail(:)   !< htail: dissipated, stored, impact_dissipated, momenta, damping
  contains
    procedure :: open => outputs_open
    procedure :: write_step => outputs_write_step
    procedure :: write_events => outputs_write_events
    procedure :: add_contact_impulses => outputs_add_contact_impulses
    procedure :: set_step => outputs_set_step
    procedure :: set_last => outputs_set_last
    procedure :: set_row_step => outputs_set_row_step
    procedure :: close => outputs_close
    procedure :: writes_fields => outputs_writes_fields
    procedure :: writes_history => outputs_writes_history
  end type output_set_t

contains

  !> The step h of the impulses that follow (h/2 Λ_j): SCHEME RETRY's sub-steps, and back.
  pure subroutine outputs_set_step(self, h)
    class(output_set_t), intent(inout) :: self
    real(dp), intent(in) :: h
    self%h = h
  end subroutine outputs_set_step

  !> The length of the step whose end the next row writes (history.csv h; 0 at step 0).
  pure subroutine outputs_set_row_step(self, h)
    class(output_set_t), intent(inout) :: self
    real(dp), intent(in) :: h
    self%h_row = h
  end subroutine outputs_set_row_step

  !> The run's last step (always written): a located contact onset adds one.
  pure subroutine outputs_set_last(self, nsteps)
    class(output_set_t), intent(inout) :: self
    integer, intent(in) :: nsteps
    self%last_step = nsteps
  end subroutine outputs_set_last

  !> Open the files under outdir for a run of nsteps steps; step0 > 0 resumes after a
  !> checkpoint of step step0 at time t0 (lines written past it are dropped, the fields of the
  !> continued run go to fields_restart_NNNNNN.h5/.xmf). with_events: a contact scene.
  subroutine outputs_open(self, scn, outdir, step0, t0, nsteps, with_events, stat, errmsg)
    class(output_set_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    character(len=*), intent(in) :: outdir
    integer, intent(in) :: step0, nsteps
    real(dp), intent(in) :: t0
    logical, intent(in) :: with_events
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=:), allocatable :: header
    character(len=32) :: part
    type(mesh_t) :: shown
    integer :: i
    call remove_stale_temporaries(outdir, stat, errmsg)
    if (stat /= STAT_OK) return
    self%last_step = nsteps
    self%with_events = with_events
    self%with_fields = scn%fields_every /= 0
    self%axisymmetric = scene_axisymmetric(scn)
    self%ndim = scn%mesh%ndim
    header = 'step,time'
    do i = 1, size(scn%probes)
      header = header // ',' // csv_field(scn%probes(i)%label)
    end do
    allocate (self%escalar(scn%mesh%nelem, 2))
    self%ncomp = merge(6, 4, scn%mesh%ndim == 3)
    self%slots = [DOF_UX, DOF_UY, merge(DOF_UZ, DOF_RZ, scn%mesh%ndim == 3)]
    allocate (self%nodal_u(3, scn%mesh%nnode), self%nodal_v(3, scn%mesh%nnode), self%estress(self%ncomp, scn%mesh%nelem), &
      self%reaction(3, scn%mesh%nnode), self%preals(1 + size(scn%probes)), self%hreals(6), self%htail(7))
    self%reaction = 0.0_dp
    self%h = scn%dt
    self%t_row = t0
    if (with_events) call contact_statements(self, scn)
    if (step0 > 0) then
      call self%hist%resume(outdir // '/history.csv', HISTORY_HEADER, step0, stat, errmsg)
      if (stat == STAT_OK) call self%probes%resume(outdir // '/probes.csv', header, step0, stat, errmsg)
      if (stat == STAT_OK .and. with_events) &
        call self%ev%resume(outdir // '/events.csv', EVENTS_HEADER, step0, stat, errmsg)
      if (stat == STAT_OK .and. with_events) &
        call self%contacts%resume(outdir // '/contacts.csv', CONTACTS_HEADER, step0, stat, errmsg)
    else
      call self%hist%open(outdir // '/history.csv', HISTORY_HEADER, stat, errmsg)
      if (stat == STAT_OK) call self%probes%open(outdir // '/probes.csv', header, stat, errmsg)
      if (stat == STAT_OK .and. with_events) call self%ev%open(outdir // '/events.csv', EVENTS_HEADER, stat, errmsg)
      if (stat == STAT_OK .and. with_events) &
        call self%contacts%open(outdir // '/contacts.csv', CONTACTS_HEADER, stat, errmsg)
    end if
    if (stat /= STAT_OK .or. .not. self%with_fields) return
    ! Cells of no MODEL (Gmsh boundary lines and points, ...) are not shown as stress-free elements.
    self%kept = pack([(i, i = 1, scn%mesh%nelem)], scn%elem_model(1:scn%mesh%nelem) > 0)
    allocate (self%wstress(self%ncomp, size(self%kept)), self%wscalar(size(self%kept), 2), self%support(3, scn%mesh%nnode))
    self%support = 0.0_dp
    part = ''
    if (step0 > 0) write (part, '(a,i6.6)') 'fields_restart_', step0
    if (size(self%kept) == scn%mesh%nelem) then
      call open_fields(scn%mesh)
    else
      call scn%mesh%subset_elements(self%kept, shown)
      call open_fields(shown)
    end if
  contains
    subroutine open_fields(m)
      type(mesh_t), intent(in) :: m
      if (step0 > 0) then
        call self%fields%open(outdir, m, stat, errmsg, basename=trim(part), axisymmetric=self%axisymmetric)
      else
        call self%fields%open(outdir, m, stat, errmsg, axisymmetric=self%axisymmetric)
      end if
    end subroutine open_fields
  end subroutine outputs_open

  !> A run killed while it replaced a file (a checkpoint, a resumed CSV, fields.xmf) leaves
  !> NAME.tmp behind; the next run in the folder removes them.
  subroutine remove_stale_temporaries(outdir, stat, errmsg)
    character(len=*), intent(in) :: outdir
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=17), parameter :: names(7) = [character(len=17) :: 'history.csv', 'probes.csv', 'events.csv', &
      'contacts.csv', 'fields.xmf', 'checkpoint.h5', 'fields_points.xmf']
    integer :: k
    stat = STAT_OK
    do k = 1, size(names)
      call remove_file(outdir // '/' // trim(names(k)) // '.tmp', stat, errmsg)
      if (stat /= STAT_OK) return
    end do
  end subroutine remove_stale_temporaries

  !> Step `step` writes a line of history.csv (the energies are then read).
  pure logical function outputs_writes_history(self, scn, step) result(yes)
    class(output_set_t), intent(in) :: self
    type(scene_t), intent(in) :: scn
    integer, intent(in) :: step
    yes = .false.
    if (scn%history_every > 0) yes = mod(step, scn%history_every) == 0 .or. step == self%last_step
  end function outputs_writes_history

  !> Step `step` writes fields.h5 (the stresses of every point are then read).
  pure logical function outputs_writes_fields(self, scn, step) result(yes)
    class(output_set_t), intent(in) :: self
    type(scene_t), intent(in) :: scn
    integer, intent(in) :: step
    yes = .false.
    if (.not. self%with_fields) return
    yes = step == 0 .or. step == self%last_step .or. (scn%fields_every > 0 .and. mod(step, max(scn%fields_every, 1)) == 0)
  end function outputs_writes_fields

  !> The history and probe lines of a step (every HISTORY EVERY steps and the last one) and its
  !> fields (every FIELDS EVERY steps, the first and the last).
  subroutine outputs_write_step(self, scn, sys, step, t, iter, nactive, nsub, en, u, v, mv, rig, stat, errmsg, cs)
    class(output_set_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    integer, intent(in) :: step, iter, nactive
    integer, intent(in) :: nsub                  !< the sub-steps the step took (SCHEME RETRY; 1 without)
    real(dp), intent(in) :: t
    type(energy_t), intent(in) :: en
    real(dp), intent(in) :: u(:), v(:)
    real(dp), intent(in) :: mv(:), rig(:, :)   !< M v and the rigid modes: the momenta t_k'M v
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(contact_set_t), intent(in), optional :: cs
    integer :: k, r
    real(dp) :: lc(3)
    stat = STAT_OK
    if (self%writes_history(scn, step)) then
      self%hreals = [t, en%kinetic, en%internal(), en%external(), en%correction(), en%balance()]
      if (sys%elems%linear) then
        self%htail(1:3) = [0.0_dp, en%elastic, en%impact_dissipated()]
      else
        self%htail(1:3) = [en%dissipated(), stored_energy(scn, sys), en%impact_dissipated()]
      end if
      do k = 1, 3
        self%htail(3 + k) = dot_product(rig(:, k), mv)
      end do
      self%htail2(4:6) = 0.0_dp
      do k = 4, size(rig, 2)                   ! (3D: z, and the rotations about x and y)
        self%htail2(k) = dot_product(rig(:, k), mv)
      end do
      ! KINEMATICS LARGE: the angular momentum about the origin of the current configuration.
      if (any(scn%models%large)) then
        lc = current_angular_momentum(scn, sys, u, mv)
        self%htail(6) = lc(3)
        if (scn%mesh%ndim == 3) self%htail2(5:6) = lc(1:2)
      end if
      ! Axisymmetric: the whole ring's radial momentum and its angular momentum about z are zero
      ! (Σ M v_r over the nodes is not a momentum: each ring's points move in all radial directions).
      if (self%axisymmetric) self%htail([4, 6]) = 0.0_dp
      self%htail(7) = en%damping()
      self%htail2(1:3) = [en%contact_held(), self%h_row, en%friction()]
      call self%hist%write_row(step, self%hreals, [iter, nactive], stat, errmsg, self%htail, [nsub], self%htail2)
      if (stat /= STAT_OK) return
      self%preals(1) = t
      r = 0
      do k = 1, size(scn%probes)
        self%preals(k + 1) = 0.0_dp
        if (scn%probes(k)%reaction) then
          r = r + 1
          self%preals(k + 1) = sys%react%value(r)
          cycle
        end if
        associate (j => sys%dofs%eqn(scn%probes(k)%dof, scn%probes(k)%node))
          if (j > 0) self%preals(k + 1) = merge(v(j), u(j), scn%probes(k)%velocity)
        end associate
      end do
      call self%probes%write_row(step, self%preals, [integer ::], stat, errmsg)
      if (stat /= STAT_OK) return
      if (present(cs)) call write_contacts(self, step, t, cs, stat, errmsg)
      if (stat /= STAT_OK) return
    end if
    if (self%writes_fields(scn, step)) then
      if (.not. self%rec_built) call build_recovery(self, scn, sys, stat, errmsg)
      if (stat /= STAT_OK) return
      call nodal_values(sys, u, self%slots, self%nodal_u)
      call nodal_values(sys, v, self%slots, self%nodal_v)
      call element_stress(sys, self%estress)
      call element_scalars(scn, sys, self%estress, self%escalar)
      do k = 1, size(self%kept)                 ! (a loop: no temporary)
        self%wstress(:, k) = self%estress(:, self%kept(k))
        self%wscalar(k, :) = self%escalar(self%kept(k), :)
      end do
      do k = 1, sys%react%nslot - sys%react%nprobe   ! the support_reaction field's slots
        self%support(findloc(self%slots, sys%react%fdof(k), 1), sys%react%fnode(k)) = sys%react%value(sys%react%nprobe + k)
      end do
      if (self%ndim == 3) then                 ! (the recovered nodal and point fields: surfaces only)
        if (present(cs)) call contact_reactions(self, scn, cs)
        if (present(cs)) then
          call self%fields%write_step(step, t, self%nodal_u, self%nodal_v, self%wstress, stat, errmsg, &
            reaction=self%reaction, escalar=self%wscalar, support=self%support)
        else
          call self%fields%write_step(step, t, self%nodal_u, self%nodal_v, self%wstress, stat, errmsg, &
            escalar=self%wscalar, support=self%support)
        end if
        return
      end if
      call self%rec%points(scn, sys, self%nodal_u, self%pvals, self%pdisp)
      call self%rec%nodal(scn, self%pvals, self%nodal, stat, errmsg)
      if (stat /= STAT_OK) return
      if (present(cs)) then
        call contact_reactions(self, scn, cs)
        call self%fields%write_step(step, t, self%nodal_u, self%nodal_v, self%wstress, stat, errmsg, &
          reaction=self%reaction, escalar=self%wscalar, support=self%support, nodal=self%nodal, pvals=self%pvals, &
          pdisp=self%pdisp)
      else
        call self%fields%write_step(step, t, self%nodal_u, self%nodal_v, self%wstress, stat, errmsg, &
          escalar=self%wscalar, support=self%support, nodal=self%nodal, pvals=self%pvals, pdisp=self%pdisp)
      end if
    end if
  end subroutine outputs_write_step

  !> The integration points and the projection of the recovered stresses (stress_recovery), at the
  !> first written fields: their positions to fields.h5, fields_points.xmf opened.
  subroutine build_recovery(self, scn, sys, stat, errmsg)
    type(output_set_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    call self%rec%build(scn, sys, stat, errmsg)
    if (stat /= STAT_OK) return
    allocate (self%nodal(NREC, scn%mesh%nnode), self%pvals(NREC, self%rec%ngp), self%pdisp(3, self%rec%ngp))
    call self%fields%set_points(self%rec%x, stat, errmsg)
    self%rec_built = .true.
  end subroutine build_recovery

  !> Σ (x + u) × (M v) over the nodes' free translations, plus the rotations' M v: the angular
  !> momentum about the origin in the current configuration (KINEMATICS LARGE), its x, y and z
  !> components (x and y zero in 2D).
  pure function current_angular_momentum(scn, sys, u, mv) result(am)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: u(:), mv(:)
    real(dp) :: am(3)
    integer, parameter :: slot(3) = [DOF_UX, DOF_UY, DOF_UZ]
    real(dp) :: pos(3), p(3)
    integer :: n, d, j, nd
    am = 0.0_dp
    nd = scn%mesh%ndim
    do n = 1, scn%mesh%nnode
      pos = 0.0_dp
      pos(1:nd) = scn%mesh%x(1:nd, n)
      p = 0.0_dp
      do d = 1, 3
        j = sys%dofs%eqn(slot(d), n)
        if (j > 0) then
          pos(d) = pos(d) + u(j)
          p(d) = mv(j)
        end if
      end do
      am(1) = am(1) + pos(2) * p(3) - pos(3) * p(2)
      am(2) = am(2) + pos(3) * p(1) - pos(1) * p(3)
      am(3) = am(3) + pos(1) * p(2) - pos(2) * p(1)        ! (2D: the order of the sums as ever)
      j = sys%dofs%eqn(DOF_RZ, n)
      if (j > 0) am(3) = am(3) + mv(j)
    end do
  end function current_angular_momentum

  !> The contact force of a step on each node (docs/contact.md, "Contact force"): its impulse
  !> over the step, h/2 Λ_j (the step multiplier stands for R(n) + R(n+1)) plus the impulse of
  !> the end-of-step correction along c_j, divided by h; on node b along n, its opposite on a.
  subroutine contact_reactions(self, scn, cs)
    type(output_set_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    type(contact_set_t), intent(in) :: cs
    integer :: j, k, nodes(COND_NODES), nd
    real(dp) :: f, w(COND_NODES), ft, slip, imp_t, tg(3)
    self%reaction = 0.0_dp
    nd = self%ndim                             ! (rows x, y[, z]; row 3 is the moment in 2D)
    do j = 1, size(scn%conditions)
      if (cs%follows(j)) then                  ! the step's pairing, then the end's for the correction
        call spread_force(self, cs%step_geometry(j), 0.5_dp * cs%multiplier(j))
        call spread_force(self, cs%end_geometry(j), cs%correction_impulse(j) / self%h)
        cycle
      end if
      associate (c => scn%conditions(j))
        f = step_impulse(self, cs, j) / self%h
        call cs%tangential(j, ft, slip, imp_t)     ! (FRICTION: the tangential force along t, or t1 in 3D)
        ft = 0.5_dp * ft + imp_t / self%h
        tg = ft * condition_tangent(c, nd)
        if (nd == 3) then                        ! (3D: and along t2)
          call cs%tangential(j, ft, slip, imp_t, 2)
          tg = tg + (0.5_dp * ft + imp_t / self%h) * condition_tangent(c, 3, 2)
        end if
        call condition_nodes(c, nodes, w)
        do k = 1, COND_NODES
          if (nodes(k) > 0) self%reaction(1:nd, nodes(k)) = self%reaction(1:nd, nodes(k)) + w(k) * (f * c%normal(1:nd) &
            + tg(1:nd))
        end do
      end associate
    end do
  end subroutine contact_reactions

  !> The force f along a following row's pairing g on its nodes (weights w along the normal).
  pure subroutine spread_force(self, g, f)
    type(output_set_t), intent(inout) :: self
    type(row_geometry_t), intent(in) :: g
    real(dp), intent(in) :: f
    integer :: k
    do k = 1, 3
      if (g%nodes(k) > 0) self%reaction(1:2, g%nodes(k)) = self%reaction(1:2, g%nodes(k)) + g%w(k) * f * g%normal
    end do
  end subroutine spread_force

  !> Impulse of condition j over the last step along its normal, on node b: h/2 Λ_j plus the
  !> correction's impulse.
  pure real(dp) function step_impulse(self, cs, j)
    type(output_set_t), intent(in) :: self
    type(contact_set_t), intent(in) :: cs
    integer, intent(in) :: j
    step_impulse = 0.5_dp * self%h * cs%multiplier(j) + cs%correction_impulse(j)
  end function step_impulse

  !> The moment about the origin of the force f (x, y) on node n: (x_n + u_n - back du_n) × f where
  !> the node is in a KINEMATICS LARGE model (history.csv's angular momentum is about the current
  !> configuration; back = ½: the step's midpoint), the reference position x_n × f otherwise.
  pure real(dp) function moment_at(scn, sys, u, du, back, n, f) result(mz)
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: u(:), du(:), back
    integer, intent(in) :: n
    real(dp), intent(in) :: f(2)
    real(dp) :: p(2)
    integer :: d
    p = scn%mesh%x(1:2, n)                     ! (the moment about z: x, y)
    if (any(scn%models%large)) then
      do d = 1, 2
        if (sys%dofs%eqn(d, n) > 0) p(d) = p(d) + u(sys%dofs%eqn(d, n)) - back * du(sys%dofs%eqn(d, n))
      end do
    end if
    mz = p(1) * f(2) - p(2) * f(1)
  end function moment_at

  !> The contact statements (OBSTACLE, GAP names) in order of appearance, and each condition's.
  subroutine contact_statements(self, scn)
    type(output_set_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    integer :: i, j, k, n, w
    n = size(scn%conditions)
    w = 1
    do j = 1, n
      w = max(w, len(scn%conditions(j)%source))
    end do
    allocate (character(len=w) :: self%cnames(n))
    allocate (character(len=2 * w + 400) :: self%row)
    allocate (self%cstat(n))
    k = 0
    do j = 1, n
      self%cstat(j) = 0
      do i = 1, k
        if (trim(self%cnames(i)) == scn%conditions(j)%source) self%cstat(j) = i
      end do
      if (self%cstat(j) == 0) then
        k = k + 1
        self%cnames(k) = scn%conditions(j)%source
        self%cstat(j) = k
      end if
    end do
    self%cnames = self%cnames(1:k)
    allocate (self%cimp(4, k), self%cforce(4, k), self%cslip(k))   ! x, y, the moment, z
    self%cimp = 0.0_dp
    self%cslip = 0.0_dp
  end subroutine contact_statements

  !> After each step: the impulse each contact statement gave its NODES group (for a GAP the
  !> nodes a, opposite to the normal; a scaling's momentum counted where it is booked), and its
  !> moment about the origin (third entry): at the nodes' positions, in the configuration of the
  !> step's end for KINEMATICS LARGE models (u: the displacement then), the reference otherwise.
  subroutine outputs_add_contact_impulses(self, scn, sys, u, du, cs)
    class(output_set_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    type(system_t), intent(in) :: sys
    real(dp), intent(in) :: u(:), du(:)
    type(contact_set_t), intent(in) :: cs
    type(row_geometry_t) :: gs, ge
    real(dp) :: istep(3), icorr(3), sgn, lam_t, slip, imp_t, lam_t2, slip2, imp_t2, tg(3), t2(3)
    integer :: j, node
    do j = 1, size(scn%conditions)
      associate (c => scn%conditions(j), s => self%cstat(j))
        if (cs%follows(j)) then                ! on b, along the step's normal, then the end's
          gs = cs%step_geometry(j)
          ge = cs%end_geometry(j)
          istep = [0.5_dp * self%h * cs%multiplier(j) * gs%normal(1:2), 0.0_dp]
          icorr = [cs%correction_impulse(j) * ge%normal(1:2), 0.0_dp] + cs%body_impulse(j)
          node = c%node_b
        else
          ! on the NODES group: node b of an OBSTACLE or GAP … SEGMENTS or FACES, node a of GAP … WITH or PAIRS
          sgn = merge(-1.0_dp, 1.0_dp, c%node_a > 0 .and. c%node_c == 0 .and. c%face(1) == 0)
          call cs%tangential(j, lam_t, slip, imp_t)   ! (FRICTION: along t = n turned by +90°; t1 in 3D)
          if (self%ndim == 3) then             ! (3D: the tangential force along t1 and t2, the slip's length)
            tg = condition_tangent(c, 3)
            call cs%tangential(j, lam_t2, slip2, imp_t2, 2)
            t2 = condition_tangent(c, 3, 2)
            istep = sgn * 0.5_dp * self%h * (cs%multiplier(j) * c%normal + lam_t * tg + lam_t2 * t2)
            self%cslip(s) = self%cslip(s) + hypot(slip, slip2)
            icorr = sgn * (cs%correction_impulse(j) * c%normal + imp_t * tg + imp_t2 * t2) + cs%body_impulse(j)
          else
            istep = sgn * 0.5_dp * self%h * (cs%multiplier(j) * c%normal + lam_t * condition_tangent(c, 2))   ! (x, y, z)
            self%cslip(s) = self%cslip(s) + slip
            icorr = sgn * (cs%correction_impulse(j) * c%normal + imp_t * condition_tangent(c, 2)) + cs%body_impulse(j)
          end if
          node = merge(c%node_a, c%node_b, c%node_a > 0 .and. c%node_c == 0 .and. c%face(1) == 0)
        end if
        self%cimp(1:2, s) = self%cimp(1:2, s) + istep(1:2) + icorr(1:2)
        self%cimp(4, s) = self%cimp(4, s) + istep(3) + icorr(3)
        ! The step's impulse acts at the step's midpoint configuration, the correction's at its end.
        self%cimp(3, s) = self%cimp(3, s) + moment_at(scn, sys, u, du, 0.5_dp, node, istep(1:2)) + &
          moment_at(scn, sys, u, du, 0.0_dp, node, icorr(1:2))
      end associate
    end do
  end subroutine outputs_add_contact_impulses

  !> contacts.csv: one row per contact statement: its active conditions, the mean force and the
  !> impulse since the previous row, its smallest gap.
  subroutine write_contacts(self, step, t, cs, stat, errmsg)
    type(output_set_t), intent(inout) :: self
    integer, intent(in) :: step
    real(dp), intent(in) :: t
    type(contact_set_t), intent(in) :: cs
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: k, j, pos, nact
    real(dp) :: gmin
    do k = 1, size(self%cnames)
      nact = 0
      gmin = huge(1.0_dp)
      do j = 1, size(self%cstat)
        if (self%cstat(j) /= k) cycle
        if (cs%is_active(j)) nact = nact + 1
        gmin = min(gmin, cs%gap(j))
      end do
      self%cforce(:, k) = 0.0_dp
      if (t > self%t_row) self%cforce(:, k) = self%cimp(:, k) / (t - self%t_row)
      pos = 0
      call put_int(self%row, pos, step)
      call put_text(self%row, pos, ',')
      call put_es(self%row, pos, t)
      call put_text(self%row, pos, ',')
      call put_csv(self%row, pos, trim(self%cnames(k)))
      call put_text(self%row, pos, ',')
      call put_int(self%row, pos, nact)
      call put_text(self%row, pos, ',')
      call put_es(self%row, pos, self%cforce(1, k))
      call put_text(self%row, pos, ',')
      call put_es(self%row, pos, self%cforce(2, k))
      call put_text(self%row, pos, ',')
      call put_es(self%row, pos, self%cimp(1, k))
      call put_text(self%row, pos, ',')
      call put_es(self%row, pos, self%cimp(2, k))
      call put_text(self%row, pos, ',')
      call put_es(self%row, pos, gmin)
      call put_text(self%row, pos, ',')
      call put_es(self%row, pos, self%cforce(3, k))
      call put_text(self%row, pos, ',')
      call put_es(self%row, pos, self%cimp(3, k))
      call put_text(self%row, pos, ',')
      call put_es(self%row, pos, self%cslip(k))
      call put_text(self%row, pos, ',')
      call put_es(self%row, pos, self%cforce(4, k))
      call put_text(self%row, pos, ',')
      call put_es(self%row, pos, self%cimp(4, k))
      call self%contacts%write_line(self%row(1:pos), stat, errmsg)
      if (stat /= STAT_OK) return
    end do
    self%cimp = 0.0_dp
    self%cslip = 0.0_dp
    self%t_row = t
  end subroutine write_contacts

  !> events.csv: one line per contact established or released in the step, built with
  !> text_format in a fixed buffer (no internal WRITE, no allocation: these are in the loop).
  subroutine outputs_write_events(self, scn, step, t, cs, stat, errmsg)
    class(output_set_t), intent(inout) :: self
    type(scene_t), intent(in) :: scn
    integer, intent(in) :: step
    real(dp), intent(in) :: t
    type(contact_set_t), intent(in) :: cs
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(contact_event_t) :: event
    type(row_geometry_t) :: geo
    integer :: k, j, pos, i, nodes(3)
    stat = STAT_OK
    do k = 1, cs%n_events()
      event = cs%event(k)
      j = event%index
      pos = 0
      call put_int(self%row, pos, step)
      call put_text(self%row, pos, ',')
      call put_es(self%row, pos, t)
      call put_text(self%row, pos, ',')
      call put_int(self%row, pos, j)
      call put_text(self%row, pos, ',')
      nodes = [scn%conditions(j)%node_b, scn%conditions(j)%node_a, scn%conditions(j)%node_c]
      if (cs%follows(j)) then                             ! the partner of this step
        geo = cs%end_geometry(j)
        nodes = geo%nodes
      end if
      do i = 2, 3                                         ! a segment a-c (or a node a), then b
        if (nodes(i) <= 0) cycle
        call put_int(self%row, pos, scn%mesh%node_tag(nodes(i)))
        call put_text(self%row, pos, ' ')
      end do
      call put_int(self%row, pos, scn%mesh%node_tag(nodes(1)))
      if (event%kind == EVENT_ESTABLISH) then
        call put_text(self%row, pos, ',establish,')
      else
        call put_text(self%row, pos, ',release,')
      end if
      call put_es(self%row, pos, event%gap_start)
      call put_text(self%row, pos, ',')
      call put_es(self%row, pos, event%multiplier)
      call put_text(self%row, pos, ',')
      call put_es(self%row, pos, merge(event%energy, 0.0_dp, event%kind == EVENT_ESTABLISH))
      call put_text(self%row, pos, ',')
      call put_csv(self%row, pos, scn%conditions(j)%source)
      call self%ev%write_line(self%row(1:pos), stat, errmsg)
      if (stat /= STAT_OK) return
    end do
  end subroutine outputs_write_events

  !> Close every file (also after a failure: what was written stays). stat is sticky: an
  !> earlier error is kept, else the first failure to close is reported.
  subroutine outputs_close(self, stat, errmsg)
    class(output_set_t), intent(inout) :: self
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer :: st(5)
    type :: msg_t
      character(len=:), allocatable :: s
    end type msg_t
    type(msg_t) :: m(5)
    integer :: k
    st = STAT_OK
    if (self%with_events) call self%ev%close(st(1), m(1)%s)
    if (self%with_events) call self%contacts%close(st(2), m(2)%s)
    call self%hist%close(st(3), m(3)%s)
    call self%probes%close(st(4), m(4)%s)
    if (self%with_fields) call self%fields%close(st(5), m(5)%s)
    if (self%rec_built) call self%rec%destroy()
    if (stat /= STAT_OK) return
    do k = 1, 5
      if (st(k) /= STAT_OK) then
        stat = st(k)
        errmsg = m(k)%s
        return
      end if
    end do
  end subroutine outputs_close
end module run_outputs
