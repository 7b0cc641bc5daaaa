!> Field output: OUTDIR/fields.h5 (HDF5) plus OUTDIR/fields.xmf (XDMF 3, for ParaView).
!>
!> fields.h5 layout (HDF5 dimensions are the Fortran ones reversed):
!>   /mesh/coordinates   float64 (3, nnode) in Fortran = (nnode, 3) in HDF5: x, y, z (z = 0 in 2D)
!>   /mesh/topology      int32 XDMF Mixed array, 0-based node ids:
!>                       MASS -> 1 1 n; SPRING/BAR2/BEAM2 -> 2 2 a b; QUAD4 -> 5 a b c d;
!>                       QUAD8 -> 37 (Quadrilateral_8) with the 4 corners then the 4 mid-sides
!>   /mesh/element_type  int32 (nelem), ET_* codes of module element_traits, named by
!>   /mesh/element_type_names (strings, code k at index k) and described by
!>   /mesh/stress_components (strings: the stress columns of each type, with units)
!>   /groups/nodes/NAME, /groups/elements/NAME   int32, the groups' 0-based node and element ids
!>   /times, /steps      float64 / int32 (nsteps), one entry per written step (unlimited, chunked)
!>   /step_NNNNNN        group, attributes time (float64) and step (int32), datasets
!>                       displacement, velocity [, reaction] (3, nnode): (UX, UY, 0) per node,
!>                         z = 0 so that ParaView's "Warp By Vector" moves nodes in the plane only;
!>                       rotation, angular_velocity [, reaction_moment] (nnode): the RZ component
!>                         of u, v [, reaction];
!>                       (DIMENSION 3: displacement, velocity [, reaction] (3, nnode) are (UX, UY, UZ), no
!>                       rotation; stress (6, nelem) sxx, syy, szz, sxy, syz, sxz and its columns sigma_xx
!>                       … sigma_xz; HEX8 and TET4 cells are XDMF Hexahedron and Tetrahedron)
!>                       stress (4, nelem): element mean of Gauss-point values
!>                       (spring: force; bar: sigma; beam: N, M; quads: sxx, syy, szz, sxy);
!>                       every dataset has the string attributes `components` and `units`;
!>                       with the integration points (set_points): nodal_sigma_xx … nodal_plastic_strain
!>                       (nnode, stress_recovery's L2 projection) and the group points/ with
!>                       displacement (3, npt), sigma_xx … plastic_strain (npt)
!>   /points/coordinates float64 (3, npt): the integration points' reference positions
!>                       (OUTDIR/fields_points.xmf shows them as a Polyvertex set).
!> After each step the file is flushed and the step's grid added to fields.xmf in one write, so
!> a killed run leaves a readable pair holding every completed step. The file is created without HDF5 file
!> locking so that ParaView can open it while the run is going on.
!> Do not copy an open fields_writer_t: both copies would share (and close) the same file.
module fields_hdf5
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, set_error, str
  use mesh, only: mesh_t
  use element_traits, only: NUM_ETYPES, etype_nen, etype_xdmf_cell, etype_name, etype_stress_names, etype_xdmf_order, &
    MAX_NEN, &
    XDMF_POLYVERTEX, XDMF_POLYLINE, &
    XDMF_QUADRILATERAL, XDMF_QUADRILATERAL_8
  use xdmf_writer, only: xdmf_step_t, xdmf_head, xdmf_tail, xdmf_step_grid, step_group_name, write_text_atomic, SIGMA_NAMES, &
    SIGMA_AXI, SIGMA_3D, xdmf_points_grid, recovered_name
  use os_utils, only: make_directory, room_for
  use hdf5_file, only: h5_file_t
  use text_file, only: text_file_t
  implicit none
  private
  public :: fields_writer_t, mixed_topology
  public :: XDMF_POLYVERTEX, XDMF_POLYLINE, XDMF_QUADRILATERAL, XDMF_QUADRILATERAL_8


  character(len=*), parameter :: H5_NAME = 'fields.h5', XMF_NAME = 'fields.xmf'
  real(dp), parameter :: ROOM_MARGIN = 65536.0_dp   !< bytes kept free besides a step's data (check_room)

  type :: fields_writer_t
    private
    logical :: is_open = .false.
    type(h5_file_t) :: h5
    character(len=:), allocatable :: h5path, xmfpath, h5name
    integer :: nnode = 0, nelem = 0, ntopo = 0
    integer :: nsteps = 0
    logical :: axisymmetric = .false.        !< the hoop stress is named sigma_tt (x = r, y the axis)
    integer :: ndim = 2                      !< 3: vectors (x, y, z) without a rotation, 6 stresses
    ! fields.xmf stays open: each step's grid replaces the closing tail and is followed by it
    ! again, in one write (text_file replace_tail): the file is a complete document at every
    ! moment, and neither the file nor the memory is rewritten per step.
    type(text_file_t) :: xmf
    character(len=:), allocatable :: xtail
    ! Work arrays for splitting (UX, UY, RZ) fields, sized in open and reused by every step.
    real(dp), allocatable :: vec(:, :), rz(:)
    real(dp), allocatable :: col(:)          !< one stress column (sigma_xx ...), nelem
    ! The integration points (set_points): their count, OUTDIR/fields_points.xmf, a column of theirs
    ! and of the nodes.
    integer :: npt = 0
    type(text_file_t) :: pxmf
    character(len=:), allocatable :: pxmfpath
    real(dp), allocatable :: pcol(:), ncol(:)
  contains
    procedure :: open => fw_open
    procedure :: set_points => fw_set_points
    procedure :: write_step => fw_write_step
    procedure :: close => fw_close
    procedure :: opened => fw_opened
    final :: fw_final
  end type fields_writer_t

  !> fields.h5 is closed and opened again every this many written steps (fw_write_step).
  integer, parameter :: REOPEN_EVERY = 1000

contains

  !> The XDMF Mixed topology array of a mesh (0-based node ids), checking element types and
  !> node numbers.
  pure subroutine mixed_topology(msh, topo, stat, errmsg)
    type(mesh_t), intent(in) :: msh
    integer, allocatable, intent(out) :: topo(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: e, n, k, nen, head(2), nhead, order(MAX_NEN)
    stat = STAT_OK
    n = 0
    do e = 1, msh%nelem
      call cell_head(msh%etype(e), head, nhead, nen)
      if (nhead == 0) then
        call set_error(stat, errmsg, STAT_RUN, 'field output: element ' // str(e) // &
                       ' has unknown type ' // str(msh%etype(e)))
        return
      end if
      if (any(msh%conn(1:nen, e) < 1 .or. msh%conn(1:nen, e) > msh%nnode)) then
        call set_error(stat, errmsg, STAT_RUN, 'field output: element ' // str(e) // &
                       ' refers to a node outside 1..' // str(msh%nnode))
        return
      end if
      n = n + nhead + nen
    end do
    allocate (topo(n))
    k = 0
    do e = 1, msh%nelem
      call cell_head(msh%etype(e), head, nhead, nen)
      topo(k + 1:k + nhead) = head(1:nhead)
      call etype_xdmf_order(msh%etype(e), order)             ! (XDMF's node order: HEX20, TET10 differ)
      topo(k + nhead + 1:k + nhead + nen) = msh%conn(order(1:nen), e) - 1
      k = k + nhead + nen
    end do
  end subroutine mixed_topology

  !> Leading entries of an element's record in a Mixed array (cell code, and node count for the
  !> variable-size Polyvertex/Polyline), and its node count; nhead = 0 for an unknown type.
  pure subroutine cell_head(et, head, nhead, nen)
    integer, intent(in) :: et
    integer, intent(out) :: head(2), nhead, nen
    head = 0
    nen = 0
    nhead = 0
    if (et < 1 .or. et > NUM_ETYPES) return
    call etype_xdmf_cell(et, head, nhead)
    nen = etype_nen(et)
  end subroutine cell_head

  !> Split nodal (UX, UY, RZ) columns into the in-plane 3-vector (UX, UY, 0) and the scalar RZ:
  !> a rotation stored as a z component would lift nodes out of the plane in a viewer's warp.
  pure subroutine split_planar(a, vec, rz)
    real(dp), intent(in) :: a(:, :)
    real(dp), intent(out) :: vec(:, :), rz(:)
    vec(1:2, :) = a(1:2, :)
    vec(3, :) = 0.0_dp
    rz = a(3, :)
  end subroutine split_planar

  !> Write a (UX, UY, RZ) field a as the 3-vector dataset vname and the scalar dataset sname,
  !> through the writer's work arrays; in 3D a is (UX, UY, UZ), the vector alone.
  subroutine write_planar(self, grp, a, vname, sname, comps, units, stat, errmsg)
    class(fields_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: grp, vname, sname
    character(len=*), intent(in) :: comps(2), units(2)   !< component names and units (vector, scalar)
    real(dp), intent(in) :: a(:, :)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    if (stat /= STAT_OK) return
    if (self%ndim == 3) then                   ! (UX, UY, UZ): the vector itself
      call self%h5%write(grp // '/' // vname, a, stat, errmsg)
      call describe(self, grp // '/' // vname, trim(comps(1)), trim(units(1)), stat, errmsg)
      return
    end if
    call split_planar(a, self%vec, self%rz)
    call self%h5%write(grp // '/' // vname, self%vec, stat, errmsg)
    call describe(self, grp // '/' // vname, trim(comps(1)), trim(units(1)), stat, errmsg)
    call self%h5%write(grp // '/' // sname, self%rz, stat, errmsg)
    call describe(self, grp // '/' // sname, trim(comps(2)), trim(units(2)), stat, errmsg)
  end subroutine write_planar

  !> The attributes that make a dataset self-describing: its components and their units.
  subroutine describe(self, dset, components, units, stat, errmsg)
    class(fields_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: dset, components, units
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    call self%h5%write_attr(dset, 'components', stat, errmsg, text=components)
    call self%h5%write_attr(dset, 'units', stat, errmsg, text=units)
  end subroutine describe

  !> What the mesh's integers mean: the element type names (by the codes of element_type), the
  !> stress components of each type, and the node and element groups (0-based ids, as the
  !> topology), so that a reader of fields.h5 needs nothing else.
  subroutine write_mesh_meaning(self, mesh, stat, errmsg)
    class(fields_writer_t), intent(inout) :: self
    type(mesh_t), intent(in) :: mesh
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    character(len=8) :: names(NUM_ETYPES)
    character(len=80) :: comps(NUM_ETYPES)
    integer :: k
    do k = 1, NUM_ETYPES
      names(k) = etype_name(k)
    end do
    call self%h5%write_text('mesh/element_type_names', names, stat, errmsg)
    do k = 1, NUM_ETYPES
      comps(k) = etype_stress_names(k)
    end do
    call self%h5%write_text('mesh/stress_components', comps, stat, errmsg)
    call self%h5%create_group('groups', stat, errmsg)
    call self%h5%create_group('groups/nodes', stat, errmsg)
    call self%h5%create_group('groups/elements', stat, errmsg)
    do k = 1, mesh%nngroup
      call self%h5%write('groups/nodes/' // h5_safe(mesh%ngroups(k)%name), mesh%ngroups(k)%items - 1, stat, errmsg)
    end do
    do k = 1, mesh%negroup
      call self%h5%write('groups/elements/' // h5_safe(mesh%egroups(k)%name), mesh%egroups(k)%items - 1, stat, errmsg)
    end do
  end subroutine write_mesh_meaning

  !> A group name as an HDF5 link name ('/' would be a path separator; '.' alone is reserved).
  pure function h5_safe(name) result(s)
    character(len=*), intent(in) :: name
    character(len=:), allocatable :: s
    integer :: i
    s = name
    do i = 1, len(s)
      if (s(i:i) == '/') s(i:i) = '|'
    end do
    if (s == '.') s = '|'
  end function h5_safe

  !> dir/name, without doubling a trailing slash; an empty dir means the current directory.
  pure function join_path(dir, name) result(p)
    character(len=*), intent(in) :: dir, name
    character(len=:), allocatable :: p
    integer :: n
    n = len_trim(dir)
    if (n == 0) then
      p = name
    else if (dir(n:n) == '/') then
      p = dir(1:n) // name
    else
      p = dir(1:n) // '/' // name
    end if
  end function join_path

  !> Create OUTDIR (if needed), OUTDIR/fields.h5 with the mesh, and an empty OUTDIR/fields.xmf.
  !> An existing fields.h5 is overwritten.
  subroutine fw_open(self, outdir, mesh, stat, errmsg, basename, axisymmetric)
    class(fields_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: outdir
    type(mesh_t), intent(in) :: mesh
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=*), intent(in), optional :: basename
    logical, intent(in), optional :: axisymmetric   !< the scene is axisymmetric (sigma_tt)
    integer, allocatable :: topo(:)
    real(dp), allocatable :: xyz(:, :)
    integer :: st2
    character(len=:), allocatable :: msg2

    stat = STAT_OK
    if (self%is_open) then
      call set_error(stat, errmsg, STAT_RUN, 'field output: "' // self%h5path // '" is already open')
      return
    end if
    if (mesh%nnode < 1 .or. mesh%nelem < 1) then
      call set_error(stat, errmsg, STAT_RUN, 'field output: the mesh has no node or no element')
      return
    end if
    call mixed_topology(mesh, topo, stat, errmsg)
    if (stat /= STAT_OK) return
    call make_directory(outdir, stat, errmsg)
    if (stat /= STAT_OK) return
    self%h5name = H5_NAME
    self%xmfpath = join_path(outdir, XMF_NAME)
    self%axisymmetric = .false.
    if (present(axisymmetric)) self%axisymmetric = axisymmetric
    self%ndim = mesh%ndim
    if (present(basename)) then
      ! A restarted run writes its fields beside the first part (basename.h5 / basename.xmf).
      self%h5name = basename // '.h5'
      self%xmfpath = join_path(outdir, basename // '.xmf')
    end if
    self%h5path = join_path(outdir, self%h5name)
    self%nnode = mesh%nnode
    self%nelem = mesh%nelem
    self%ntopo = size(topo)
    self%nsteps = 0
    if (allocated(self%vec)) deallocate (self%vec)
    if (allocated(self%rz)) deallocate (self%rz)
    if (allocated(self%col)) deallocate (self%col)
    allocate (self%vec(3, self%nnode), self%rz(self%nnode), self%col(self%nelem))
    if (allocated(self%ncol)) deallocate (self%ncol)
    allocate (self%ncol(self%nnode))
    self%npt = 0

    ! No lock, so that a viewer can read the completed steps while the run goes on.
    call self%h5%create(self%h5path, 'field output', stat, errmsg, unlocked=.true.)
    if (stat /= STAT_OK) return
    self%is_open = .true.
    allocate (xyz(3, mesh%nnode))
    xyz(3, :) = 0.0_dp
    xyz(1:mesh%ndim, :) = mesh%x(1:mesh%ndim, 1:mesh%nnode)
    call self%h5%create_group('mesh', stat, errmsg)
    call self%h5%write('mesh/coordinates', xyz, stat, errmsg)
    call self%h5%write('mesh/topology', topo, stat, errmsg)
    call self%h5%write('mesh/element_type', mesh%etype(1:mesh%nelem), stat, errmsg)
    call self%h5%write_attr('mesh', 'nnode', stat, errmsg, i=mesh%nnode)
    call self%h5%write_attr('mesh', 'nelem', stat, errmsg, i=mesh%nelem)
    call write_mesh_meaning(self, mesh, stat, errmsg)
    if (self%axisymmetric) call self%h5%write_text('mesh/axisymmetric', [character(len=96) :: &
      'x = r, y the axis; sigma_zz of /stress is the hoop stress sigma_tt; whole ring'], stat, errmsg)
    call self%h5%create_series('times', .false., stat, errmsg)
    call self%h5%create_series('steps', .true., stat, errmsg)
    call self%h5%flush(stat, errmsg)
    ! An empty collection replaces any fields.xmf left by an earlier run of the same case.
    self%xtail = xdmf_tail()
    if (stat == STAT_OK) call write_text_atomic(self%xmfpath, xdmf_head() // self%xtail, stat, errmsg)
    if (stat == STAT_OK) call self%xmf%append(self%xmfpath, stat, errmsg)
    if (stat /= STAT_OK) call self%close(st2, msg2)   ! keep the first error
  end subroutine fw_open

  !> The integration points shown as a point set (after open): their positions xg(3, npt) in
  !> /points/coordinates, and OUTDIR/fields_points.xmf (basename_points.xmf after a restart),
  !> whose grids the steps written with pvals add.
  subroutine fw_set_points(self, xg, stat, errmsg)
    class(fields_writer_t), intent(inout) :: self
    real(dp), intent(in) :: xg(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    stat = STAT_OK
    self%npt = size(xg, 2)
    if (self%npt == 0 .or. .not. self%is_open) return
    if (allocated(self%pcol)) deallocate (self%pcol)
    allocate (self%pcol(self%npt))
    call self%h5%create_group('points', stat, errmsg)
    call self%h5%write('points/coordinates', xg, stat, errmsg)
    call self%h5%flush(stat, errmsg)
    self%pxmfpath = self%xmfpath(1:len(self%xmfpath) - 4) // '_points.xmf'
    if (stat == STAT_OK) call write_text_atomic(self%pxmfpath, xdmf_head() // self%xtail, stat, errmsg)
    if (stat == STAT_OK) call self%pxmf%append(self%pxmfpath, stat, errmsg)
  end subroutine fw_set_points

  !> Append one output step: group /step_NNNNNN in fields.h5, the /times and /steps series, a
  !> flush, then the rewritten fields.xmf. u, v, reaction are (3, nnode) holding UX, UY, RZ (each
  !> stored as an in-plane vector plus a scalar, see the module header); stress is (4, nelem).
  subroutine fw_write_step(self, step, time, u, v, stress, stat, errmsg, reaction, escalar, support, nodal, pvals, pdisp)
    class(fields_writer_t), intent(inout) :: self
    integer, intent(in) :: step
    real(dp), intent(in) :: time
    real(dp), intent(in) :: u(:, :), v(:, :), stress(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), intent(in), optional :: reaction(:, :)
    real(dp), intent(in), optional :: escalar(:, :)   !< (nelem, 2): von Mises stress, equivalent plastic strain
    real(dp), intent(in), optional :: support(:, :)   !< (3, nnode): the supports' mean reaction of the step
    real(dp), intent(in), optional :: nodal(:, :)     !< (6, nnode): the recovered nodal fields (stress_recovery)
    real(dp), intent(in), optional :: pvals(:, :)     !< (6, npt): the integration points' fields
    real(dp), intent(in), optional :: pdisp(:, :)     !< (3, npt): the displacement at the points
    integer :: k, ncomp
    character(len=:), allocatable :: grp

    stat = STAT_OK
    ncomp = merge(6, 4, self%ndim == 3)
    if (.not. self%is_open) then
      call set_error(stat, errmsg, STAT_RUN, 'field output: write_step before open')
      return
    end if
    if (.not. (has_shape(u, 3, self%nnode) .and. has_shape(v, 3, self%nnode))) then
      call set_error(stat, errmsg, STAT_RUN, 'field output: displacement and velocity must be (3, ' // &
                     str(self%nnode) // ') arrays')
      return
    end if
    if (.not. has_shape(stress, ncomp, self%nelem)) then
      call set_error(stat, errmsg, STAT_RUN, 'field output: stress must be a (' // str(ncomp) // ', ' // str(self%nelem) // &
        ') array')
      return
    end if
    if (present(reaction)) then
      if (.not. has_shape(reaction, 3, self%nnode)) then
        call set_error(stat, errmsg, STAT_RUN, 'field output: reaction must be a (3, ' // &
                       str(self%nnode) // ') array')
        return
      end if
    end if

    call check_room(self, step, present(reaction) .or. present(support), stat, errmsg)
    if (stat /= STAT_OK) return
    grp = step_group_name(step)
    if (self%h5%exists(grp, stat, errmsg)) then
      call set_error(stat, errmsg, STAT_RUN, 'field output: step ' // str(step) // ' is already in "' // &
                     self%h5path // '"')
      return
    end if
    call self%h5%create_group(grp, stat, errmsg)
    call self%h5%write_attr(grp, 'time', stat, errmsg, x=time)
    call self%h5%write_attr(grp, 'step', stat, errmsg, i=step)
    call write_planar(self, grp, u, 'displacement', 'rotation', ['ux uy uz', 'rz      '], ['m  ', 'rad'], stat, errmsg)
    call write_planar(self, grp, v, 'velocity', 'angular_velocity', ['vx vy vz', 'wz      '], ['m/s  ', 'rad/s'], &
      stat, errmsg)
    if (present(reaction)) call write_planar(self, grp, reaction, 'reaction', 'reaction_moment', ['fx fy fz', 'mz      '], &
      ['N  ', 'N m'], stat, errmsg)
    if (present(support)) call write_planar(self, grp, support, 'support_reaction', 'support_moment', &
      ['fx fy fz', 'mz      '], ['N  ', 'N m'], stat, errmsg)
    call self%h5%write(grp // '/stress', stress, stat, errmsg)
    call describe(self, grp // '/stress', 'per element type: /mesh/stress_components', &
      'per element type: /mesh/stress_components', stat, errmsg)
    ! Each column also as its own dataset, which both of ParaView's XDMF readers show by name
    ! (Xdmf3ReaderS, the default, skips a hyperslab of /stress: "unrecognized array type").
    do k = 1, ncomp
      self%col = stress(k, :)
      if (self%ndim == 3) then
        call self%h5%write(grp // '/' // trim(SIGMA_3D(k)), self%col, stat, errmsg)
      else if (self%axisymmetric) then
        call self%h5%write(grp // '/' // trim(SIGMA_AXI(k)), self%col, stat, errmsg)   ! (described by stress's)
      else
        call self%h5%write(grp // '/' // trim(SIGMA_NAMES(k)), self%col, stat, errmsg)
      end if
    end do
    if (present(escalar)) then
      call self%h5%write(grp // '/von_mises', escalar(:, 1), stat, errmsg)
      call describe(self, grp // '/von_mises', 'von Mises stress of the element-mean stress (surface elements; ' // &
        '|sigma| for BAR2, 0 otherwise)', 'Pa', stat, errmsg)
      call self%h5%write(grp // '/plastic_strain', escalar(:, 2), stat, errmsg)
      call describe(self, grp // '/plastic_strain', 'element mean of the equivalent plastic strain (VON_MISES), ' // &
        'of the plastic strain (ELASTOPLASTIC bars and springs); 0 otherwise', '1 (m for springs)', stat, errmsg)
    end if
    if (present(nodal)) then
      do k = 1, 6
        self%ncol = nodal(k, :)
        call self%h5%write(grp // '/nodal_' // recovered_name(k, self%axisymmetric), self%ncol, stat, errmsg)
      end do
      call describe(self, grp // '/nodal_' // recovered_name(1, self%axisymmetric), 'L2 projection of the integration ' // &
        'points'' values on the surface elements'' nodes (nodal_sigma_*, nodal_von_mises, nodal_plastic_strain)', &
        'Pa (plastic strain: 1)', stat, errmsg)
    end if
    if (present(pvals) .and. present(pdisp) .and. self%npt > 0) then
      call self%h5%create_group(grp // '/points', stat, errmsg)
      call self%h5%write(grp // '/points/displacement', pdisp, stat, errmsg)
      do k = 1, 6
        self%pcol = pvals(k, :)
        call self%h5%write(grp // '/points/' // recovered_name(k, self%axisymmetric), self%pcol, stat, errmsg)
      end do
    end if
    call self%h5%append_series('times', self%nsteps + 1, stat, errmsg, x=time)
    call self%h5%append_series('steps', self%nsteps + 1, stat, errmsg, i=step)
    ! Everything of this step reaches the disk before the .xmf announces it; every REOPEN_EVERY
    ! steps the file is closed and opened again instead, which also makes HDF5 let go of the
    ! memory it keeps for the objects written (the resident set stays flat).
    if (mod(self%nsteps + 1, REOPEN_EVERY) == 0) then
      call self%h5%reopen(stat, errmsg)
    else
      call self%h5%flush(stat, errmsg)
    end if
    if (stat /= STAT_OK) return

    self%nsteps = self%nsteps + 1
    call self%xmf%replace_tail(xdmf_step_grid(self%h5name, self%nnode, self%nelem, self%ntopo, &
      xdmf_step_t(step=step, time=time, has_reaction=present(reaction), has_scalars=present(escalar), &
      has_support=present(support), axisymmetric=self%axisymmetric, has_nodal=present(nodal), solid=self%ndim == 3)) // &
      self%xtail, &
      len(self%xtail), stat, errmsg)
    if (stat == STAT_OK .and. present(pvals) .and. self%npt > 0) call self%pxmf%replace_tail(xdmf_points_grid(self%h5name, &
      self%npt, xdmf_step_t(step=step, time=time, axisymmetric=self%axisymmetric)) // self%xtail, len(self%xtail), stat, errmsg)
  end subroutine fw_write_step

  !> Refuse a step the disk (or the file size limit) cannot hold, before HDF5 tries: HDF5 1.10
  !> does not recover from a write that fails (the file can no longer be closed, and may be
  !> left unreadable). Needed: the step's arrays twice (metadata, chunk growth) plus
  !> ROOM_MARGIN; the file keeps every complete step.
  subroutine check_room(self, step, with_reaction, stat, errmsg)
    type(fields_writer_t), intent(in) :: self
    integer, intent(in) :: step
    logical, intent(in) :: with_reaction
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: need, free
    stat = STAT_OK
    need = 8.0_dp * (4.0_dp * self%nnode * merge(4, 2, with_reaction) + 6.0_dp * self%nelem + 6.0_dp * self%nnode + &
      9.0_dp * self%npt)
    need = 2.0_dp * need + ROOM_MARGIN
    free = room_for(self%h5path)
    if (free >= 0.0_dp .and. free < need) call set_error(stat, errmsg, STAT_RUN, 'field output ' // self%h5path // &
      ': no room left for step ' // str(step) // ' (needs about ' // str(nint(need / 1024)) // &
      ' KiB, ' // str(nint(free / 1024)) // ' KiB left on the device or under the file size limit); ' // &
      'the file holds the steps written before')
  end subroutine check_room

  pure logical function has_shape(a, n1, n2)
    real(dp), intent(in) :: a(:, :)
    integer, intent(in) :: n1, n2
    has_shape = size(a, 1) == n1 .and. size(a, 2) == n2
  end function has_shape

  !> True between a successful open and close.
  pure logical function fw_opened(self)
    class(fields_writer_t), intent(in) :: self
    fw_opened = self%is_open
  end function fw_opened

  !> Close the file. Closing a writer that is not open does nothing.
  subroutine fw_close(self, stat, errmsg)
    class(fields_writer_t), intent(inout) :: self
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer :: st, st2
    character(len=:), allocatable :: msg, msg2
    st = STAT_OK
    if (self%is_open) then
      self%is_open = .false.
      call self%h5%close(st, msg)
    end if
    call self%xmf%close(st2, msg2)
    if (st == STAT_OK .and. st2 /= STAT_OK) then
      st = st2
      msg = msg2
    end if
    if (self%npt > 0) call self%pxmf%close(st2, msg2)
    if (st == STAT_OK .and. st2 /= STAT_OK) then
      st = st2
      msg = msg2
    end if
    self%npt = 0
    if (allocated(self%vec)) deallocate (self%vec)
    if (allocated(self%rz)) deallocate (self%rz)
    self%nsteps = 0
    if (present(stat)) stat = st
    if (present(errmsg) .and. st /= STAT_OK) errmsg = msg
  end subroutine fw_close

  subroutine fw_final(self)
    type(fields_writer_t), intent(inout) :: self
    call self%close()
  end subroutine fw_final
end module fields_hdf5
