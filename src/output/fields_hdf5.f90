!> Field output: OUTDIR/fields.h5 (HDF5) plus OUTDIR/fields.xmf (XDMF 3, for ParaView).
!>
!> fields.h5 layout (HDF5 dimensions are the Fortran ones reversed):
!>   /mesh/coordinates   float64 (3, nnode) in Fortran = (nnode, 3) in HDF5: x, y, z = 0
!>   /mesh/topology      int32 XDMF Mixed array, 0-based node ids:
!>                       MASS -> 1 1 n; SPRING/BAR2/BEAM2 -> 2 2 a b; QUAD4 -> 5 a b c d;
!>                       QUAD8 -> 37 (Quadrilateral_8) with the 4 corners then the 4 mid-sides
!>   /mesh/element_type  int32 (nelem), ET_* codes of module mesh
!>   /times, /steps      float64 / int32 (nsteps), one entry per written step (unlimited, chunked)
!>   /step_NNNNNN        group, attributes time (float64) and step (int32), datasets
!>                       displacement, velocity [, reaction] (3, nnode): (UX, UY, 0) per node,
!>                         z = 0 so that ParaView's "Warp By Vector" moves nodes in the plane only;
!>                       rotation, angular_velocity [, reaction_moment] (nnode): the RZ component
!>                         of u, v [, reaction];
!>                       stress (4, nelem): element mean of Gauss-point values
!>                       (bar/spring: N or sigma,0,0,0; beam: N,M,0,0; quads: sxx,syy,szz,sxy).
!> After each step the file is flushed and fields.xmf rewritten atomically, so a killed run
!> leaves a readable pair holding every completed step. The file is created without HDF5 file
!> locking so that ParaView can open it while the run is going on.
!> Do not copy an open fields_writer_t: both copies would share (and close) the same file.
module fields_hdf5
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, set_error, str
  use mesh, only: mesh_t, ET_MASS, ET_SPRING, ET_BAR2, ET_BEAM2, ET_QUAD4, ET_QUAD8
  use xdmf_writer, only: xdmf_step_t, xdmf_head, xdmf_tail, xdmf_step_grid, step_group_name, write_text_atomic
  use os_utils, only: make_directory
  use hdf5, only: hid_t, hsize_t, h5open_f, h5close_f, &
                  h5fcreate_f, h5fclose_f, h5fflush_f, H5F_ACC_TRUNC_F, H5F_SCOPE_GLOBAL_F, &
                  h5gcreate_f, h5gclose_f, h5lexists_f, &
                  h5screate_simple_f, h5screate_f, h5sclose_f, h5sselect_hyperslab_f, &
                  H5S_SCALAR_F, H5S_UNLIMITED_F, H5S_SELECT_SET_F, &
                  h5dcreate_f, h5dopen_f, h5dclose_f, h5dwrite_f, h5dset_extent_f, h5dget_space_f, &
                  h5acreate_f, h5awrite_f, h5aclose_f, &
                  h5pcreate_f, h5pclose_f, h5pset_chunk_f, h5pset_file_locking_f, &
                  H5P_FILE_ACCESS_F, H5P_DATASET_CREATE_F, H5T_NATIVE_DOUBLE, H5T_NATIVE_INTEGER
  implicit none
  private
  public :: fields_writer_t, mixed_topology
  public :: XDMF_POLYVERTEX, XDMF_POLYLINE, XDMF_QUADRILATERAL, XDMF_QUADRILATERAL_8

  !> XDMF cell codes used in a Mixed topology array.
  integer, parameter :: XDMF_POLYVERTEX = 1, XDMF_POLYLINE = 2, XDMF_QUADRILATERAL = 5
  integer, parameter :: XDMF_QUADRILATERAL_8 = 37

  character(len=*), parameter :: H5_NAME = 'fields.h5', XMF_NAME = 'fields.xmf'
  integer(hsize_t), parameter :: SERIES_CHUNK = 256   ! chunk length of /times and /steps

  !> Number of open writers; the HDF5 Fortran interface is opened by the first, closed by the last.
  integer, save :: h5_users = 0

  type :: fields_writer_t
    private
    logical :: is_open = .false.
    integer(hid_t) :: file_id = -1
    character(len=:), allocatable :: h5path, xmfpath, h5name
    integer :: nnode = 0, nelem = 0, ntopo = 0
    integer :: nsteps = 0
    type(xdmf_step_t), allocatable :: steps(:)
    ! fields.xmf: head, the grids of the written steps (rendered once each, grids(1:ngrids)), tail.
    character(len=:), allocatable :: xhead, xtail, grids
    integer :: ngrids = 0
    ! Work arrays for splitting (UX, UY, RZ) fields, sized in open and reused by every step.
    real(dp), allocatable :: vec(:, :), rz(:)
  contains
    procedure :: open => fw_open
    procedure :: write_step => fw_write_step
    procedure :: close => fw_close
    procedure :: opened => fw_opened
    final :: fw_final
  end type fields_writer_t

contains

  !> The XDMF Mixed topology array of a mesh (0-based node ids), checking element types and
  !> node numbers.
  pure subroutine mixed_topology(msh, topo, stat, errmsg)
    type(mesh_t), intent(in) :: msh
    integer, allocatable, intent(out) :: topo(:)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    integer :: e, n, k, nen, head(2), nhead
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
      topo(k + nhead + 1:k + nhead + nen) = msh%conn(1:nen, e) - 1
      k = k + nhead + nen
    end do
  end subroutine mixed_topology

  !> Leading entries of an element's record in a Mixed array (cell code, and node count for the
  !> variable-size Polyvertex/Polyline), and its node count; nhead = 0 for an unknown type.
  pure subroutine cell_head(et, head, nhead, nen)
    integer, intent(in) :: et
    integer, intent(out) :: head(2), nhead, nen
    head = 0
    select case (et)
    case (ET_MASS)
      nen = 1; nhead = 2; head = [XDMF_POLYVERTEX, 1]
    case (ET_SPRING, ET_BAR2, ET_BEAM2)
      nen = 2; nhead = 2; head = [XDMF_POLYLINE, 2]
    case (ET_QUAD4)
      nen = 4; nhead = 1; head(1) = XDMF_QUADRILATERAL
    case (ET_QUAD8)
      nen = 8; nhead = 1; head(1) = XDMF_QUADRILATERAL_8
    case default
      nen = 0; nhead = 0
    end select
  end subroutine cell_head

  !> Record the first HDF5 failure (hdferr < 0) as STAT_RUN naming the operation and the file.
  subroutine check_h5(hdferr, op, path, stat, errmsg)
    integer, intent(in) :: hdferr
    character(len=*), intent(in) :: op, path
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    if (hdferr < 0 .and. stat == STAT_OK) then
      stat = STAT_RUN
      errmsg = 'HDF5: cannot ' // op // ' in "' // path // '"'
    end if
  end subroutine check_h5

  !> Write a new float64 dataset holding a(:, :) under loc.
  subroutine write_real2(loc, where, name, a, path, stat, errmsg)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: where, name, path
    real(dp), intent(in) :: a(:, :)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer(hid_t) :: space, dset
    integer(hsize_t) :: dims(2)
    integer :: hdferr
    if (stat /= STAT_OK) return
    dims = shape(a, kind=hsize_t)
    call h5screate_simple_f(2, dims, space, hdferr)
    call check_h5(hdferr, 'create the dataspace of ' // where // '/' // name, path, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5dcreate_f(loc, name, H5T_NATIVE_DOUBLE, space, dset, hdferr)
    call check_h5(hdferr, 'create dataset ' // where // '/' // name, path, stat, errmsg)
    if (stat == STAT_OK) then
      call h5dwrite_f(dset, H5T_NATIVE_DOUBLE, a, dims, hdferr)
      call check_h5(hdferr, 'write dataset ' // where // '/' // name, path, stat, errmsg)
      call h5dclose_f(dset, hdferr)
      call check_h5(hdferr, 'close dataset ' // where // '/' // name, path, stat, errmsg)
    end if
    call h5sclose_f(space, hdferr)
    call check_h5(hdferr, 'close the dataspace of ' // where // '/' // name, path, stat, errmsg)
  end subroutine write_real2

  !> Write a new float64 dataset holding a(:) under loc.
  subroutine write_real1(loc, where, name, a, path, stat, errmsg)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: where, name, path
    real(dp), intent(in) :: a(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer(hid_t) :: space, dset
    integer(hsize_t) :: dims(1)
    integer :: hdferr
    if (stat /= STAT_OK) return
    dims = shape(a, kind=hsize_t)
    call h5screate_simple_f(1, dims, space, hdferr)
    call check_h5(hdferr, 'create the dataspace of ' // where // '/' // name, path, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5dcreate_f(loc, name, H5T_NATIVE_DOUBLE, space, dset, hdferr)
    call check_h5(hdferr, 'create dataset ' // where // '/' // name, path, stat, errmsg)
    if (stat == STAT_OK) then
      call h5dwrite_f(dset, H5T_NATIVE_DOUBLE, a, dims, hdferr)
      call check_h5(hdferr, 'write dataset ' // where // '/' // name, path, stat, errmsg)
      call h5dclose_f(dset, hdferr)
      call check_h5(hdferr, 'close dataset ' // where // '/' // name, path, stat, errmsg)
    end if
    call h5sclose_f(space, hdferr)
    call check_h5(hdferr, 'close the dataspace of ' // where // '/' // name, path, stat, errmsg)
  end subroutine write_real1

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
  !> through the writer's work arrays.
  subroutine write_planar(self, gid, where, a, vname, sname, stat, errmsg)
    class(fields_writer_t), intent(inout) :: self
    integer(hid_t), intent(in) :: gid
    character(len=*), intent(in) :: where, vname, sname
    real(dp), intent(in) :: a(:, :)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    if (stat /= STAT_OK) return
    call split_planar(a, self%vec, self%rz)
    call write_real2(gid, where, vname, self%vec, self%h5path, stat, errmsg)
    call write_real1(gid, where, sname, self%rz, self%h5path, stat, errmsg)
  end subroutine write_planar

  !> Write a new int32 dataset holding a(:) under loc.
  subroutine write_int1(loc, where, name, a, path, stat, errmsg)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: where, name, path
    integer, intent(in) :: a(:)
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer(hid_t) :: space, dset
    integer(hsize_t) :: dims(1)
    integer :: hdferr
    if (stat /= STAT_OK) return
    dims = shape(a, kind=hsize_t)
    call h5screate_simple_f(1, dims, space, hdferr)
    call check_h5(hdferr, 'create the dataspace of ' // where // '/' // name, path, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5dcreate_f(loc, name, H5T_NATIVE_INTEGER, space, dset, hdferr)
    call check_h5(hdferr, 'create dataset ' // where // '/' // name, path, stat, errmsg)
    if (stat == STAT_OK) then
      call h5dwrite_f(dset, H5T_NATIVE_INTEGER, a, dims, hdferr)
      call check_h5(hdferr, 'write dataset ' // where // '/' // name, path, stat, errmsg)
      call h5dclose_f(dset, hdferr)
      call check_h5(hdferr, 'close dataset ' // where // '/' // name, path, stat, errmsg)
    end if
    call h5sclose_f(space, hdferr)
    call check_h5(hdferr, 'close the dataspace of ' // where // '/' // name, path, stat, errmsg)
  end subroutine write_int1

  !> Attach a scalar attribute (float64 if x is given, int32 if i is given) to loc.
  subroutine write_attr(loc, where, name, path, stat, errmsg, x, i)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: where, name, path
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    real(dp), intent(in), optional :: x
    integer, intent(in), optional :: i
    integer(hid_t) :: space, attr, mtype
    integer(hsize_t), parameter :: dims(1) = [1_hsize_t]
    integer :: hdferr
    if (stat /= STAT_OK) return
    mtype = H5T_NATIVE_INTEGER
    if (present(x)) mtype = H5T_NATIVE_DOUBLE
    call h5screate_f(H5S_SCALAR_F, space, hdferr)
    call check_h5(hdferr, 'create the dataspace of attribute ' // where // '@' // name, path, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5acreate_f(loc, name, mtype, space, attr, hdferr)
    call check_h5(hdferr, 'create attribute ' // where // '@' // name, path, stat, errmsg)
    if (stat == STAT_OK) then
      if (present(x)) then
        call h5awrite_f(attr, mtype, x, dims, hdferr)
      else if (present(i)) then
        call h5awrite_f(attr, mtype, i, dims, hdferr)
      end if
      call check_h5(hdferr, 'write attribute ' // where // '@' // name, path, stat, errmsg)
      call h5aclose_f(attr, hdferr)
      call check_h5(hdferr, 'close attribute ' // where // '@' // name, path, stat, errmsg)
    end if
    call h5sclose_f(space, hdferr)
    call check_h5(hdferr, 'close the dataspace of attribute ' // where // '@' // name, path, stat, errmsg)
  end subroutine write_attr

  !> Create an empty, extendable 1-D dataset (float64 or int32) for a per-step series.
  subroutine create_series(loc, name, mtype, path, stat, errmsg)
    integer(hid_t), intent(in) :: loc, mtype
    character(len=*), intent(in) :: name, path
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    integer(hid_t) :: space, dcpl, dset
    integer :: hdferr
    if (stat /= STAT_OK) return
    call h5screate_simple_f(1, [0_hsize_t], space, hdferr, maxdims=[H5S_UNLIMITED_F])
    call check_h5(hdferr, 'create the dataspace of /' // name, path, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5pcreate_f(H5P_DATASET_CREATE_F, dcpl, hdferr)
    call check_h5(hdferr, 'create the creation properties of /' // name, path, stat, errmsg)
    if (stat == STAT_OK) then
      ! An unlimited dimension requires chunked storage.
      call h5pset_chunk_f(dcpl, 1, [SERIES_CHUNK], hdferr)
      call check_h5(hdferr, 'set the chunk size of /' // name, path, stat, errmsg)
      if (stat == STAT_OK) then
        call h5dcreate_f(loc, name, mtype, space, dset, hdferr, dcpl_id=dcpl)
        call check_h5(hdferr, 'create dataset /' // name, path, stat, errmsg)
        if (stat == STAT_OK) then
          call h5dclose_f(dset, hdferr)
          call check_h5(hdferr, 'close dataset /' // name, path, stat, errmsg)
        end if
      end if
      call h5pclose_f(dcpl, hdferr)
      call check_h5(hdferr, 'close the creation properties of /' // name, path, stat, errmsg)
    end if
    call h5sclose_f(space, hdferr)
    call check_h5(hdferr, 'close the dataspace of /' // name, path, stat, errmsg)
  end subroutine create_series

  !> Grow the 1-D series dataset `name` to length n and store x (float64) or i (int32) at n.
  subroutine append_series(loc, name, n, path, stat, errmsg, x, i)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name, path
    integer, intent(in) :: n
    integer, intent(inout) :: stat
    character(len=:), allocatable, intent(inout) :: errmsg
    real(dp), intent(in), optional :: x
    integer, intent(in), optional :: i
    integer(hid_t) :: dset, fspace, mspace
    integer(hsize_t), parameter :: one(1) = [1_hsize_t]
    integer :: hdferr
    if (stat /= STAT_OK) return
    call h5dopen_f(loc, name, dset, hdferr)
    call check_h5(hdferr, 'open dataset /' // name, path, stat, errmsg)
    if (stat /= STAT_OK) return
    call h5dset_extent_f(dset, [int(n, hsize_t)], hdferr)
    call check_h5(hdferr, 'extend dataset /' // name, path, stat, errmsg)
    if (stat == STAT_OK) then
      call h5dget_space_f(dset, fspace, hdferr)
      call check_h5(hdferr, 'get the dataspace of /' // name, path, stat, errmsg)
      if (stat == STAT_OK) then
        call h5sselect_hyperslab_f(fspace, H5S_SELECT_SET_F, [int(n - 1, hsize_t)], one, hdferr)
        call check_h5(hdferr, 'select the last entry of /' // name, path, stat, errmsg)
        call h5screate_simple_f(1, one, mspace, hdferr)
        call check_h5(hdferr, 'create a memory dataspace for /' // name, path, stat, errmsg)
        if (stat == STAT_OK) then
          if (present(x)) then
            call h5dwrite_f(dset, H5T_NATIVE_DOUBLE, [x], one, hdferr, mem_space_id=mspace, file_space_id=fspace)
          else if (present(i)) then
            call h5dwrite_f(dset, H5T_NATIVE_INTEGER, [i], one, hdferr, mem_space_id=mspace, file_space_id=fspace)
          end if
          call check_h5(hdferr, 'append to dataset /' // name, path, stat, errmsg)
          call h5sclose_f(mspace, hdferr)
          call check_h5(hdferr, 'close a memory dataspace for /' // name, path, stat, errmsg)
        end if
        call h5sclose_f(fspace, hdferr)
        call check_h5(hdferr, 'close the dataspace of /' // name, path, stat, errmsg)
      end if
    end if
    call h5dclose_f(dset, hdferr)
    call check_h5(hdferr, 'close dataset /' // name, path, stat, errmsg)
  end subroutine append_series

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
  subroutine fw_open(self, outdir, mesh, stat, errmsg, basename)
    class(fields_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: outdir
    type(mesh_t), intent(in) :: mesh
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    character(len=*), intent(in), optional :: basename
    integer, allocatable :: topo(:)
    real(dp), allocatable :: xyz(:, :)
    integer(hid_t) :: fapl, gid
    integer :: hdferr, st2
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
    if (allocated(self%steps)) deallocate (self%steps)
    allocate (self%steps(16))
    if (allocated(self%vec)) deallocate (self%vec)
    if (allocated(self%rz)) deallocate (self%rz)
    allocate (self%vec(3, self%nnode), self%rz(self%nnode))

    if (h5_users == 0) then
      call h5open_f(hdferr)
      call check_h5(hdferr, 'initialise the HDF5 library', self%h5path, stat, errmsg)
      if (stat /= STAT_OK) return
    end if
    h5_users = h5_users + 1

    call h5pcreate_f(H5P_FILE_ACCESS_F, fapl, hdferr)
    call check_h5(hdferr, 'create file access properties', self%h5path, stat, errmsg)
    if (stat == STAT_OK) then
      ! No lock, so that a viewer can read the completed steps while the run goes on.
      call h5pset_file_locking_f(fapl, .false., .true., hdferr)
      call check_h5(hdferr, 'disable file locking', self%h5path, stat, errmsg)
      if (stat == STAT_OK) then
        call h5fcreate_f(self%h5path, H5F_ACC_TRUNC_F, self%file_id, hdferr, access_prp=fapl)
        call check_h5(hdferr, 'create the file', self%h5path, stat, errmsg)
      end if
      call h5pclose_f(fapl, hdferr)
      call check_h5(hdferr, 'close file access properties', self%h5path, stat, errmsg)
    end if
    if (stat /= STAT_OK) then
      call release_library()
      return
    end if
    self%is_open = .true.

    allocate (xyz(3, mesh%nnode))
    xyz(1:2, :) = mesh%x(1:2, 1:mesh%nnode)
    xyz(3, :) = 0.0_dp
    call h5gcreate_f(self%file_id, 'mesh', gid, hdferr)
    call check_h5(hdferr, 'create group /mesh', self%h5path, stat, errmsg)
    if (stat == STAT_OK) then
      call write_real2(gid, '/mesh', 'coordinates', xyz, self%h5path, stat, errmsg)
      call write_int1(gid, '/mesh', 'topology', topo, self%h5path, stat, errmsg)
      call write_int1(gid, '/mesh', 'element_type', mesh%etype(1:mesh%nelem), self%h5path, stat, errmsg)
      call write_attr(gid, '/mesh', 'nnode', self%h5path, stat, errmsg, i=mesh%nnode)
      call write_attr(gid, '/mesh', 'nelem', self%h5path, stat, errmsg, i=mesh%nelem)
      call h5gclose_f(gid, hdferr)
      call check_h5(hdferr, 'close group /mesh', self%h5path, stat, errmsg)
    end if
    call create_series(self%file_id, 'times', H5T_NATIVE_DOUBLE, self%h5path, stat, errmsg)
    call create_series(self%file_id, 'steps', H5T_NATIVE_INTEGER, self%h5path, stat, errmsg)
    if (stat == STAT_OK) then
      call h5fflush_f(self%file_id, H5F_SCOPE_GLOBAL_F, hdferr)
      call check_h5(hdferr, 'flush the file', self%h5path, stat, errmsg)
    end if
    ! An empty collection replaces any fields.xmf left by an earlier run of the same case.
    self%xhead = xdmf_head()
    self%xtail = xdmf_tail()
    if (allocated(self%grids)) deallocate (self%grids)
    allocate (character(len=16384) :: self%grids)
    self%ngrids = 0
    if (stat == STAT_OK) call write_text_atomic(self%xmfpath, self%xhead // self%xtail, stat, errmsg)
    if (stat /= STAT_OK) call self%close(st2, msg2)   ! keep the first error
  end subroutine fw_open

  !> Append one output step: group /step_NNNNNN in fields.h5, the /times and /steps series, a
  !> flush, then the rewritten fields.xmf. u, v, reaction are (3, nnode) holding UX, UY, RZ (each
  !> stored as an in-plane vector plus a scalar, see the module header); stress is (4, nelem).
  subroutine fw_write_step(self, step, time, u, v, stress, stat, errmsg, reaction)
    class(fields_writer_t), intent(inout) :: self
    integer, intent(in) :: step
    real(dp), intent(in) :: time
    real(dp), intent(in) :: u(:, :), v(:, :), stress(:, :)
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), intent(in), optional :: reaction(:, :)
    character(len=:), allocatable :: grp
    type(xdmf_step_t), allocatable :: tmp(:)
    integer(hid_t) :: gid
    integer :: hdferr
    logical :: exists

    stat = STAT_OK
    if (.not. self%is_open) then
      call set_error(stat, errmsg, STAT_RUN, 'field output: write_step before open')
      return
    end if
    if (.not. (has_shape(u, 3, self%nnode) .and. has_shape(v, 3, self%nnode))) then
      call set_error(stat, errmsg, STAT_RUN, 'field output: displacement and velocity must be (3, ' // &
                     str(self%nnode) // ') arrays')
      return
    end if
    if (.not. has_shape(stress, 4, self%nelem)) then
      call set_error(stat, errmsg, STAT_RUN, 'field output: stress must be a (4, ' // str(self%nelem) // ') array')
      return
    end if
    if (present(reaction)) then
      if (.not. has_shape(reaction, 3, self%nnode)) then
        call set_error(stat, errmsg, STAT_RUN, 'field output: reaction must be a (3, ' // &
                       str(self%nnode) // ') array')
        return
      end if
    end if

    grp = step_group_name(step)
    call h5lexists_f(self%file_id, grp, exists, hdferr)
    call check_h5(hdferr, 'look up group /' // grp, self%h5path, stat, errmsg)
    if (stat /= STAT_OK) return
    if (exists) then
      call set_error(stat, errmsg, STAT_RUN, 'field output: step ' // str(step) // ' is already in "' // &
                     self%h5path // '"')
      return
    end if

    call h5gcreate_f(self%file_id, grp, gid, hdferr)
    call check_h5(hdferr, 'create group /' // grp, self%h5path, stat, errmsg)
    if (stat /= STAT_OK) return
    call write_attr(gid, '/' // grp, 'time', self%h5path, stat, errmsg, x=time)
    call write_attr(gid, '/' // grp, 'step', self%h5path, stat, errmsg, i=step)
    call write_planar(self, gid, '/' // grp, u, 'displacement', 'rotation', stat, errmsg)
    call write_planar(self, gid, '/' // grp, v, 'velocity', 'angular_velocity', stat, errmsg)
    if (present(reaction)) &
      call write_planar(self, gid, '/' // grp, reaction, 'reaction', 'reaction_moment', stat, errmsg)
    call write_real2(gid, '/' // grp, 'stress', stress, self%h5path, stat, errmsg)
    call h5gclose_f(gid, hdferr)
    call check_h5(hdferr, 'close group /' // grp, self%h5path, stat, errmsg)
    call append_series(self%file_id, 'times', self%nsteps + 1, self%h5path, stat, errmsg, x=time)
    call append_series(self%file_id, 'steps', self%nsteps + 1, self%h5path, stat, errmsg, i=step)
    if (stat /= STAT_OK) return
    ! Everything of this step reaches the disk before the .xmf announces it.
    call h5fflush_f(self%file_id, H5F_SCOPE_GLOBAL_F, hdferr)
    call check_h5(hdferr, 'flush the file', self%h5path, stat, errmsg)
    if (stat /= STAT_OK) return

    if (self%nsteps == size(self%steps)) then
      allocate (tmp(2 * self%nsteps))
      tmp(1:self%nsteps) = self%steps(1:self%nsteps)
      call move_alloc(tmp, self%steps)
    end if
    self%nsteps = self%nsteps + 1
    self%steps(self%nsteps) = xdmf_step_t(step=step, time=time, has_reaction=present(reaction))
    ! Only the new step's grid is rendered (re-rendering every step made the output quadratic).
    call append_grid(self, xdmf_step_grid(self%h5name, self%nnode, self%nelem, self%ntopo, self%steps(self%nsteps)))
    call write_text_atomic(self%xmfpath, self%xhead // self%grids(1:self%ngrids) // self%xtail, stat, errmsg)
  end subroutine fw_write_step

  !> grids(1:ngrids) // text, the buffer doubled when full.
  pure subroutine append_grid(self, text)
    class(fields_writer_t), intent(inout) :: self
    character(len=*), intent(in) :: text
    character(len=:), allocatable :: tmp
    if (self%ngrids + len(text) > len(self%grids)) then
      allocate (character(len=max(2 * len(self%grids), self%ngrids + len(text))) :: tmp)
      tmp(1:self%ngrids) = self%grids(1:self%ngrids)
      call move_alloc(tmp, self%grids)
    end if
    self%grids(self%ngrids + 1:self%ngrids + len(text)) = text
    self%ngrids = self%ngrids + len(text)
  end subroutine append_grid

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

  !> Close the file (and the HDF5 interface when no other writer is open). Closing a writer that
  !> is not open does nothing.
  subroutine fw_close(self, stat, errmsg)
    class(fields_writer_t), intent(inout) :: self
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer :: st, hdferr
    character(len=:), allocatable :: msg
    st = STAT_OK
    if (self%is_open) then
      self%is_open = .false.
      call h5fclose_f(self%file_id, hdferr)
      call check_h5(hdferr, 'close the file', self%h5path, st, msg)
      self%file_id = -1
      call release_library(st, msg, self%h5path)
    end if
    if (allocated(self%steps)) deallocate (self%steps)
    if (allocated(self%grids)) deallocate (self%grids)
    self%ngrids = 0
    if (allocated(self%vec)) deallocate (self%vec)
    if (allocated(self%rz)) deallocate (self%rz)
    self%nsteps = 0
    if (present(stat)) stat = st
    if (present(errmsg) .and. st /= STAT_OK) errmsg = msg
  end subroutine fw_close

  !> One writer fewer; the last one closes the HDF5 Fortran interface.
  subroutine release_library(stat, errmsg, path)
    integer, intent(inout), optional :: stat
    character(len=:), allocatable, intent(inout), optional :: errmsg
    character(len=*), intent(in), optional :: path
    integer :: hdferr
    h5_users = max(h5_users - 1, 0)
    if (h5_users > 0) return
    call h5close_f(hdferr)
    if (present(stat) .and. present(errmsg) .and. present(path)) &
      call check_h5(hdferr, 'close the HDF5 library', path, stat, errmsg)
  end subroutine release_library

  subroutine fw_final(self)
    type(fields_writer_t), intent(inout) :: self
    call self%close()
  end subroutine fw_final
end module fields_hdf5
