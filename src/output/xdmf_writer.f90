!> XDMF 3 light-data (XML) for the field output: a temporal collection of uniform grids whose
!> heavy data live in fields.h5 (layout written by fields_hdf5). Building the document is pure
!> string work; writing it goes through a temporary file and a rename, so a reader (ParaView,
!> a crash) never sees a half-written fields.xmf.
!>
!> Layout referenced (HDF5 dimensions, C order):
!>   /mesh/coordinates (nnode, 3) float64, /mesh/topology (ntopo) int32 (XDMF Mixed array),
!>   /step_NNNNNN/{displacement, velocity, reaction} (nnode, 3) float64: (x, y, 0) Vector,
!>   /step_NNNNNN/{rotation, angular_velocity, reaction_moment} (nnode) float64: Scalar (RZ),
!>   /step_NNNNNN/stress (nelem, 4) float64, and its columns /step_NNNNNN/sigma_xx … sigma_xy (nelem).
!> reaction and reaction_moment are listed only for steps that have them (has_reaction).
!> The 4-component cell stress uses AttributeType="Matrix": XDMF has no 4-vector type, and
!> VTK's Xdmf3 reader then takes the component count from the array size (nelem x 4).
module xdmf_writer
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, set_error, str
  use os_utils, only: os_rename, remove_file
  use text_file, only: text_file_t
  implicit none
  private
  public :: xdmf_step_t, xdmf_document, step_group_name, write_text_atomic, xml_escape, xdmf_real
  public :: xdmf_head, xdmf_tail, xdmf_step_grid, xdmf_points_grid, SIGMA_NAMES, SIGMA_AXI, SIGMA_3D, recovered_name

  !> What the XML needs to know about one written step.
  type :: xdmf_step_t
    integer :: step = 0
    real(dp) :: time = 0.0_dp
    logical :: has_reaction = .false.
    logical :: has_scalars = .false.          !< von_mises and plastic_strain (cell scalars)
    logical :: has_support = .false.          !< support_reaction and support_moment (nodal)
    logical :: axisymmetric = .false.         !< the third stress column is the hoop stress, sigma_tt
    logical :: has_nodal = .false.            !< nodal_sigma_xx … nodal_plastic_strain (stress_recovery)
    logical :: solid = .false.                !< DIMENSION 3: no rotation scalars, six stresses
  end type xdmf_step_t

  !> Growable character buffer: appending is amortised O(1), so a document of many steps is
  !> built in linear time (plain `s = s // t` in a loop would be quadratic).
  type :: text_buffer_t
    character(len=:), allocatable :: buf
    integer :: n = 0
  end type text_buffer_t

  character(len=*), parameter :: NL = new_line('a')
  character(len=*), parameter :: I2 = '      ', I3 = '        ', I4 = '          '   ! indentation
  character(len=8), parameter :: SIGMA_NAMES(4) = [character(len=8) :: 'sigma_xx', 'sigma_yy', 'sigma_zz', 'sigma_xy']
  !> An axisymmetric scene's (x = r, y the axis): the hoop stress sigma_tt in the place of sigma_zz.
  character(len=8), parameter :: SIGMA_AXI(4) = [character(len=8) :: 'sigma_xx', 'sigma_yy', 'sigma_tt', 'sigma_xy']
  !> A DIMENSION 3 scene's six stresses.
  character(len=8), parameter :: SIGMA_3D(6) = [character(len=8) :: 'sigma_xx', 'sigma_yy', 'sigma_zz', 'sigma_xy', &
    'sigma_yz', 'sigma_xz']

contains

  !> HDF5 group name of a step: step_ then the number on at least 6 digits (step_000042, step_1234567).
  pure function step_group_name(step) result(name)
    integer, intent(in) :: step
    character(len=:), allocatable :: name
    character(len=24) :: buf
    write (buf, '(a,i0.6)') 'step_', step
    name = trim(buf)
  end function step_group_name

  !> A real in a form that reads back to the same double (17 significant digits).
  pure function xdmf_real(x) result(s)
    real(dp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: buf
    write (buf, '(es25.16e3)') x
    s = trim(adjustl(buf))
  end function xdmf_real

  !> Escape the five XML special characters for use in attribute values and text.
  pure function xml_escape(s) result(e)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: e
    integer :: i
    e = ''
    do i = 1, len(s)
      select case (s(i:i))
      case ('&')
        e = e // '&amp;'
      case ('<')
        e = e // '&lt;'
      case ('>')
        e = e // '&gt;'
      case ('"')
        e = e // '&quot;'
      case ("'")
        e = e // '&apos;'
      case default
        e = e // s(i:i)
      end select
    end do
  end function xml_escape

  pure subroutine put(tb, s)
    type(text_buffer_t), intent(inout) :: tb
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: tmp
    integer :: cap
    if (.not. allocated(tb%buf)) allocate (character(len=max(4096, 2 * len(s))) :: tb%buf)
    cap = len(tb%buf)
    if (tb%n + len(s) > cap) then
      allocate (character(len=max(2 * cap, tb%n + len(s))) :: tmp)
      tmp(1:tb%n) = tb%buf(1:tb%n)
      call move_alloc(tmp, tb%buf)
    end if
    tb%buf(tb%n + 1:tb%n + len(s)) = s
    tb%n = tb%n + len(s)
  end subroutine put

  !> One HDF DataItem line: <DataItem Dimensions=... >file:/path</DataItem>
  pure function data_item(indent, dims, numtype, prec, h5ref) result(s)
    character(len=*), intent(in) :: indent, dims, numtype, prec, h5ref
    character(len=:), allocatable :: s
    s = indent // '<DataItem Dimensions="' // dims // '" NumberType="' // numtype // '" Precision="' // &
        prec // '" Format="HDF">' // h5ref // '</DataItem>' // NL
  end function data_item

  !> The whole fields.xmf document. h5file is the heavy-data file name as the .xmf should refer to
  !> it (relative to the .xmf's directory, normally 'fields.h5'); ntopo is the length of the Mixed
  !> topology array. With no steps the collection is empty (still a valid document).
  !> It is xdmf_head // xdmf_step_grid of every step // xdmf_tail: a writer that appends steps
  !> keeps the rendered grids and renders only the new one (fields_hdf5).
  pure function xdmf_document(h5file, nnode, nelem, ntopo, steps) result(xml)
    character(len=*), intent(in) :: h5file
    integer, intent(in) :: nnode, nelem, ntopo
    type(xdmf_step_t), intent(in) :: steps(:)
    character(len=:), allocatable :: xml
    type(text_buffer_t) :: tb
    integer :: k

    call put(tb, xdmf_head())
    do k = 1, size(steps)
      call put(tb, xdmf_step_grid(h5file, nnode, nelem, ntopo, steps(k)))
    end do
    call put(tb, xdmf_tail())
    xml = tb%buf(1:tb%n)
  end function xdmf_document

  !> The document up to the first step's grid.
  pure function xdmf_head() result(xml)
    character(len=:), allocatable :: xml
    xml = '<?xml version="1.0" encoding="utf-8"?>' // NL // &
      '<Xdmf xmlns:xi="http://www.w3.org/2001/XInclude" Version="3.0">' // NL // &
      '  <Domain>' // NL // &
      '    <Grid Name="fields" GridType="Collection" CollectionType="Temporal">' // NL
  end function xdmf_head

  !> The document after the last step's grid.
  pure function xdmf_tail() result(xml)
    character(len=:), allocatable :: xml
    xml = '    </Grid>' // NL // '  </Domain>' // NL // '</Xdmf>' // NL
  end function xdmf_tail

  !> The uniform grid of one step (arguments as xdmf_document's).
  pure function xdmf_step_grid(h5file, nnode, nelem, ntopo, st) result(xml)
    character(len=*), intent(in) :: h5file
    integer, intent(in) :: nnode, nelem, ntopo
    type(xdmf_step_t), intent(in) :: st
    character(len=:), allocatable :: xml
    type(text_buffer_t) :: tb
    character(len=:), allocatable :: h5, ndims, cdims, grp
    integer :: k

    h5 = xml_escape(h5file)
    ndims = str(nnode) // ' 3'
    cdims = str(nelem) // ' ' // str(merge(6, 4, st%solid))
    grp = step_group_name(st%step)
    call put(tb, I2 // '<Grid Name="' // grp // '" GridType="Uniform">' // NL)
    call put(tb, I3 // '<Time Value="' // xdmf_real(st%time) // '"/>' // NL)
    call put(tb, I3 // '<Topology TopologyType="Mixed" NumberOfElements="' // str(nelem) // '">' // NL)
    call put(tb, data_item(I4, str(ntopo), 'Int', '4', h5 // ':/mesh/topology'))
    call put(tb, I3 // '</Topology>' // NL)
    call put(tb, I3 // '<Geometry GeometryType="XYZ">' // NL)
    call put(tb, data_item(I4, ndims, 'Float', '8', h5 // ':/mesh/coordinates'))
    call put(tb, I3 // '</Geometry>' // NL)
    call node_attribute(tb, 'displacement', 'Vector', ndims, h5, grp)
    call node_attribute(tb, 'velocity', 'Vector', ndims, h5, grp)
    if (.not. st%solid) call node_attribute(tb, 'rotation', 'Scalar', str(nnode), h5, grp)
    if (.not. st%solid) call node_attribute(tb, 'angular_velocity', 'Scalar', str(nnode), h5, grp)
    if (st%has_reaction) then
      call node_attribute(tb, 'reaction', 'Vector', ndims, h5, grp)
      if (.not. st%solid) call node_attribute(tb, 'reaction_moment', 'Scalar', str(nnode), h5, grp)
    end if
    if (st%has_support) then
      call node_attribute(tb, 'support_reaction', 'Vector', ndims, h5, grp)
      if (.not. st%solid) call node_attribute(tb, 'support_moment', 'Scalar', str(nnode), h5, grp)
    end if
    call put(tb, I3 // '<Attribute Name="stress" AttributeType="Matrix" Center="Cell">' // NL)
    call put(tb, data_item(I4, cdims, 'Float', '8', h5 // ':/' // grp // '/stress'))
    call put(tb, I3 // '</Attribute>' // NL)
    ! Each stress column also as a named scalar, its own dataset: ParaView shows sigma_xx, not
    ! "stress 0" (for BAR2 the first column is the axial stress, for BEAM2 N, M), in both of its
    ! XDMF readers (Xdmf3ReaderS skipped a hyperslab of /stress).
    do k = 1, merge(6, 4, st%solid)
      if (st%solid) then
        call cell_scalar(tb, trim(SIGMA_3D(k)), str(nelem), h5, grp)
      else if (st%axisymmetric) then
        call cell_scalar(tb, trim(SIGMA_AXI(k)), str(nelem), h5, grp)
      else
        call cell_scalar(tb, trim(SIGMA_NAMES(k)), str(nelem), h5, grp)
      end if
    end do
    if (st%has_scalars) then
      call cell_scalar(tb, 'von_mises', str(nelem), h5, grp)
      call cell_scalar(tb, 'plastic_strain', str(nelem), h5, grp)
    end if
    if (st%has_nodal) then
      do k = 1, 6
        call node_attribute(tb, 'nodal_' // recovered_name(k, st%axisymmetric), 'Scalar', str(nnode), h5, grp)
      end do
    end if
    call put(tb, I2 // '</Grid>' // NL)
    xml = tb%buf(1:tb%n)
  end function xdmf_step_grid

  !> The name of recovered field k (stress_recovery): the four stresses, von_mises, plastic_strain.
  pure function recovered_name(k, axisymmetric) result(name)
    integer, intent(in) :: k
    logical, intent(in) :: axisymmetric
    character(len=:), allocatable :: name
    if (k <= 4 .and. axisymmetric) then
      name = trim(SIGMA_AXI(k))
    else if (k <= 4) then
      name = trim(SIGMA_NAMES(k))
    else if (k == 5) then
      name = 'von_mises'
    else
      name = 'plastic_strain'
    end if
  end function recovered_name

  !> The grid of one step's integration points (OUTDIR/fields_points.xmf): a Polyvertex set at
  !> /points/coordinates with the step's /step_NNNNNN/points/{displacement, sigma_xx, …}.
  pure function xdmf_points_grid(h5file, npt, st) result(xml)
    character(len=*), intent(in) :: h5file
    integer, intent(in) :: npt
    type(xdmf_step_t), intent(in) :: st
    character(len=:), allocatable :: xml
    type(text_buffer_t) :: tb
    character(len=:), allocatable :: h5, grp
    integer :: k
    h5 = xml_escape(h5file)
    grp = step_group_name(st%step)
    call put(tb, I2 // '<Grid Name="' // grp // '_points" GridType="Uniform">' // NL)
    call put(tb, I3 // '<Time Value="' // xdmf_real(st%time) // '"/>' // NL)
    call put(tb, I3 // '<Topology TopologyType="Polyvertex" NumberOfElements="' // str(npt) // &
      '" NodesPerElement="1"/>' // NL)
    call put(tb, I3 // '<Geometry GeometryType="XYZ">' // NL)
    call put(tb, data_item(I4, str(npt) // ' 3', 'Float', '8', h5 // ':/points/coordinates'))
    call put(tb, I3 // '</Geometry>' // NL)
    call node_attribute(tb, 'displacement', 'Vector', str(npt) // ' 3', h5, grp // '/points')
    do k = 1, 6
      call node_attribute(tb, recovered_name(k, st%axisymmetric), 'Scalar', str(npt), h5, grp // '/points')
    end do
    call put(tb, I2 // '</Grid>' // NL)
    xml = tb%buf(1:tb%n)
  end function xdmf_points_grid

  !> A cell scalar attribute (dims "nelem") of step group grp.
  pure subroutine cell_scalar(tb, name, dims, h5, grp)
    type(text_buffer_t), intent(inout) :: tb
    character(len=*), intent(in) :: name, dims, h5, grp
    call put(tb, I3 // '<Attribute Name="' // name // '" AttributeType="Scalar" Center="Cell">' // NL)
    call put(tb, data_item(I4, dims, 'Float', '8', h5 // ':/' // grp // '/' // name))
    call put(tb, I3 // '</Attribute>' // NL)
  end subroutine cell_scalar

  !> A nodal attribute (atype Vector: dims "nnode 3"; Scalar: dims "nnode") of step group grp.
  pure subroutine node_attribute(tb, name, atype, dims, h5, grp)
    type(text_buffer_t), intent(inout) :: tb
    character(len=*), intent(in) :: name, atype, dims, h5, grp
    call put(tb, I3 // '<Attribute Name="' // name // '" AttributeType="' // atype // '" Center="Node">' // NL)
    call put(tb, data_item(I4, dims, 'Float', '8', h5 // ':/' // grp // '/' // name))
    call put(tb, I3 // '</Attribute>' // NL)
  end subroutine node_attribute

  !> Write text to path atomically: write path.tmp, close it, rename it over path (every
  !> write checked: a failure leaves the previous path whole and no path.tmp).
  subroutine write_text_atomic(path, text, stat, errmsg)
    character(len=*), intent(in) :: path, text
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(text_file_t) :: f
    character(len=:), allocatable :: msg2
    integer :: st2
    call f%create(path // '.tmp', stat, errmsg)
    if (stat /= STAT_OK) return
    call f%write_text(text, stat, errmsg)
    call f%close_keep(stat, errmsg)
    if (stat /= STAT_OK) then
      call remove_file(path // '.tmp', st2, msg2)
      return
    end if
    call os_rename(path // '.tmp', path, stat, errmsg)
  end subroutine write_text_atomic
end module xdmf_writer
