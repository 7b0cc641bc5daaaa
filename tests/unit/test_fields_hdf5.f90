!> fields_hdf5: a small mixed mesh (MASS, BEAM2, QUAD4, QUAD8) and 3 steps are written, then read
!> back through the HDF5 Fortran API and compared bit for bit: each (UX, UY, RZ) field must come
!> back as the in-plane vector (UX, UY, 0) plus the scalar RZ; fields.xmf is checked as XML
!> (python3 ElementTree), against fields.h5 (tools/check_xdmf.py, h5py) and for its times.
!> Run from the repository root (tests/run_tests.sh does so) to find tools/check_xdmf.py.
program test_fields_hdf5
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN
  use testing, only: check, test_summary
  use mesh, only: mesh_t
  use element_traits, only: ET_MASS, ET_BEAM2, ET_QUAD4, ET_QUAD8
  use fields_hdf5, only: fields_writer_t, mixed_topology
  use os_utils, only: path_exists, remove_file, remove_directory
  use hdf5, only: hid_t, hsize_t, h5open_f, h5close_f, h5fopen_f, h5fclose_f, H5F_ACC_RDONLY_F, &
                  h5dopen_f, h5dclose_f, h5dread_f, h5dget_space_f, h5sget_simple_extent_ndims_f, &
                  h5sget_simple_extent_dims_f, h5sclose_f, h5aopen_f, h5aread_f, h5aclose_f, &
                  h5gopen_f, h5gclose_f, h5lexists_f, H5T_NATIVE_DOUBLE, H5T_NATIVE_INTEGER
  implicit none

  integer, parameter :: NSTEP = 3
  character(len=*), parameter :: PY = '/usr/bin/python3'
  type(mesh_t) :: msh
  type(fields_writer_t) :: fw
  real(dp), allocatable :: u(:, :, :), v(:, :, :), s(:, :, :), r(:, :)
  real(dp) :: times(NSTEP)
  integer :: steps(NSTEP)
  integer :: stat, k, id, cnt
  character(len=:), allocatable :: errmsg, root, outdir, xmf
  character(len=32) :: buf

  ! A directory of our own: two suites running at once must not share files.
  call system_clock(cnt)
  write (buf, '(i0)') cnt
  root = '/tmp/rebond_test_fields_hdf5_' // trim(buf)
  outdir = root // '/out/case'          ! two levels that do not exist yet
  xmf = outdir // '/fields.xmf'

  call build_mesh(msh)
  call test_topology(msh)

  ! Fields with every bit pattern mattering: random mantissas, signs and exponents.
  allocate (u(3, msh%nnode, NSTEP), v(3, msh%nnode, NSTEP), s(4, msh%nelem, NSTEP), r(3, msh%nnode))
  call random_number(u); call random_number(v); call random_number(s); call random_number(r)
  u = (u - 0.5_dp) * 1.0e-3_dp
  v = (v - 0.5_dp) * 1.0e3_dp
  s = (s - 0.5_dp) * 2.0e8_dp
  r = (r - 0.5_dp) * 1.0e-300_dp      ! tiny values too
  times = [0.0_dp, 1.0_dp / 3.0_dp, 0.2_dp * 7.0_dp]   ! not exact decimals
  steps = [0, 17, 1234567]             ! the last needs more than 6 digits in its group name

  ! Error paths before anything is written.
  call fw%write_step(1, 0.0_dp, u(:, :, 1), v(:, :, 1), s(:, :, 1), stat, errmsg)
  call check(stat == STAT_RUN, 'write_step before open fails')
  call fw%open('/proc/rebond_cannot_be_here', msh, stat, errmsg)
  call check(stat == STAT_RUN, 'open in an impossible directory fails')
  if (stat /= STAT_OK) call check(index(errmsg, '/proc/rebond_cannot_be_here') > 0, 'its message names the path', errmsg)

  call fw%open(outdir, msh, stat, errmsg)
  call check(stat == STAT_OK, 'open', msg(stat, errmsg))
  if (stat /= STAT_OK) call finish()
  call check(fw%opened(), 'opened() after open')
  call check(path_exists(outdir // '/fields.h5') .and. path_exists(xmf), 'fields.h5 and fields.xmf exist after open')
  call check(run(PY // ' tools/check_xdmf.py ' // xmf // ' --grids 0') == 0, 'empty fields.xmf is consistent')
  call fw%open(outdir, msh, stat, errmsg)
  call check(stat == STAT_RUN, 'second open of the same writer fails')

  do k = 1, NSTEP
    if (k == 2) then
      call fw%write_step(steps(k), times(k), u(:, :, k), v(:, :, k), s(:, :, k), stat, errmsg, reaction=r)
    else
      call fw%write_step(steps(k), times(k), u(:, :, k), v(:, :, k), s(:, :, k), stat, errmsg)
    end if
    call check(stat == STAT_OK, 'write_step ' // str_i(k), msg(stat, errmsg))
    if (k == 2) then
      ! Mid-run (file still open for writing, not closed): another process sees 2 complete steps.
      call check(run(PY // ' tools/check_xdmf.py ' // xmf // ' --grids 2') == 0, &
                 'fields.xmf and fields.h5 consistent and readable while the run goes on')
      call check(.not. path_exists(xmf // '.tmp'), 'no fields.xmf.tmp left behind')
    end if
  end do

  ! Misuse is reported, not fatal, and leaves the file usable.
  call fw%write_step(steps(2), times(2), u(:, :, 2), v(:, :, 2), s(:, :, 2), stat, errmsg)
  call check(stat == STAT_RUN, 'writing a step twice fails')
  call fw%write_step(99, 1.0_dp, u(:, 1:2, 1), v(:, :, 1), s(:, :, 1), stat, errmsg)
  call check(stat == STAT_RUN, 'a displacement of the wrong shape is refused')
  call fw%write_step(99, 1.0_dp, u(:, :, 1), v(:, :, 1), s(1:3, :, 1), stat, errmsg)
  call check(stat == STAT_RUN, 'a stress of the wrong shape is refused')
  call fw%write_step(99, 1.0_dp, u(:, :, 1), v(:, :, 1), s(:, :, 1), stat, errmsg, reaction=r(1:2, :))
  call check(stat == STAT_RUN, 'a reaction of the wrong shape is refused')

  call fw%close(stat, errmsg)
  call check(stat == STAT_OK, 'close', msg(stat, errmsg))
  call check(.not. fw%opened(), 'not opened() after close')
  call fw%close(stat, errmsg)
  call check(stat == STAT_OK, 'second close is harmless')

  call test_read_back()
  call test_xmf()

  ! Reopening truncates: the old steps disappear from both files.
  call fw%open(outdir, msh, stat, errmsg)
  call check(stat == STAT_OK, 'reopen', msg(stat, errmsg))
  call fw%write_step(5, 0.5_dp, u(:, :, 1), v(:, :, 1), s(:, :, 1), stat, errmsg, reaction=r)
  call check(stat == STAT_OK, 'write_step after reopen (work arrays sized again)', msg(stat, errmsg))
  call fw%close()
  call check(run(PY // ' tools/check_xdmf.py ' // xmf // ' --grids 1') == 0, 'a reopened case holds only its new step')

  call finish()

contains

  subroutine finish()
    call remove_file(outdir // '/fields.h5', stat, errmsg)
    call remove_file(xmf, stat, errmsg)
    call remove_directory(outdir, stat, errmsg)
    call remove_directory(root // '/out', stat, errmsg)
    call remove_directory(root, stat, errmsg)
    call check(.not. path_exists(root), 'scratch directory removed')
    call test_summary('fields_hdf5')
    stop
  end subroutine finish

  !> Nodes 1-4: unit square (QUAD4); 2,5,6,3 + mid-sides 7-10: next square (QUAD8);
  !> BEAM2 from node 6 to node 11; MASS on node 11.
  subroutine build_mesh(m)
    type(mesh_t), intent(inout) :: m
    real(dp), parameter :: xy(2, 11) = reshape([0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 0.0_dp, 1.0_dp, &
      2.0_dp, 0.0_dp, 2.0_dp, 1.0_dp, 1.5_dp, 0.0_dp, 2.0_dp, 0.5_dp, 1.5_dp, 1.0_dp, 1.0_dp, 0.5_dp, &
      3.0_dp, 1.0_dp], [2, 11])
    integer :: i
    do i = 1, 11
      call m%add_node(xy(:, i), id)
    end do
    call m%add_element(ET_MASS, [11], id)
    call m%add_element(ET_BEAM2, [6, 11], id)
    call m%add_element(ET_QUAD4, [1, 2, 3, 4], id)
    call m%add_element(ET_QUAD8, [2, 5, 6, 3, 7, 8, 9, 10], id)
  end subroutine build_mesh

  !> The Mixed array by the XDMF definition: Polyvertex 1 (count 1), Polyline 2 (count 2),
  !> Quadrilateral 5, Quadrilateral_8 37; node ids 0-based.
  subroutine test_topology(m)
    type(mesh_t), intent(in) :: m
    integer, allocatable :: topo(:)
    type(mesh_t) :: bad
    call mixed_topology(m, topo, stat, errmsg)
    call check(stat == STAT_OK, 'mixed_topology')
    call check(all(topo == expected_topology()), 'mixed topology matches the XDMF layout')
    bad = m
    bad%conn(2, 2) = 12
    call mixed_topology(bad, topo, stat, errmsg)
    call check(stat == STAT_RUN, 'a node number beyond nnode is refused')
    bad = m
    bad%etype(1) = 0
    call mixed_topology(bad, topo, stat, errmsg)
    call check(stat == STAT_RUN, 'an unknown element type is refused')
  end subroutine test_topology

  pure function expected_topology() result(t)
    integer :: t(21)
    t = [1, 1, 10, 2, 2, 5, 10, 5, 0, 1, 2, 3, 37, 1, 4, 5, 2, 6, 7, 8, 9]
  end function expected_topology

  subroutine test_read_back()
    integer(hid_t) :: fid
    integer :: hdferr, k2
    real(dp), allocatable :: a(:, :), t1(:)
    integer, allocatable :: i1(:)
    real(dp) :: xyz(3, 11)
    character(len=:), allocatable :: g
    logical :: ex, ex2
    call h5open_f(hdferr)
    call h5fopen_f(outdir // '/fields.h5', H5F_ACC_RDONLY_F, fid, hdferr)
    call check(hdferr == 0, 'reopen fields.h5 for reading')
    if (hdferr /= 0) return
    xyz(1:2, :) = msh%x(:, 1:11)
    xyz(3, :) = 0.0_dp
    call read_r2(fid, '/mesh/coordinates', 3, 11, a)
    call check(all(a == xyz), '/mesh/coordinates = (x, y, 0) exactly')
    call read_i1(fid, '/mesh/topology', 21, i1)
    call check(all(i1 == expected_topology()), '/mesh/topology')
    call read_i1(fid, '/mesh/element_type', 4, i1)
    call check(all(i1 == [ET_MASS, ET_BEAM2, ET_QUAD4, ET_QUAD8]), '/mesh/element_type')
    call read_r1(fid, '/times', NSTEP, t1)
    call check(all(t1 == times), '/times holds every step time exactly')
    call read_i1(fid, '/steps', NSTEP, i1)
    call check(all(i1 == steps), '/steps holds every step number')
    do k2 = 1, NSTEP
      g = '/step_' // pad6(steps(k2))
      call check_planar(fid, g, 'displacement', 'rotation', u(:, :, k2))
      call check_planar(fid, g, 'velocity', 'angular_velocity', v(:, :, k2))
      call read_r2(fid, g // '/stress', 4, 4, a)
      call check(all(a == s(:, :, k2)), g // '/stress bit for bit')
      call h5lexists_f(fid, g // '/reaction', ex, hdferr)
      call check(ex .eqv. (k2 == 2), g // '/reaction present only where given')
      call h5lexists_f(fid, g // '/reaction_moment', ex2, hdferr)
      call check(ex2 .eqv. (k2 == 2), g // '/reaction_moment present only where given')
      if (ex .and. ex2) call check_planar(fid, g, 'reaction', 'reaction_moment', r)
      call check_attrs(fid, g, times(k2), steps(k2))
    end do
    call h5fclose_f(fid, hdferr)
    call h5close_f(hdferr)
  end subroutine test_read_back

  !> Datasets g/vname (3, nnode) and g/sname (nnode) hold exactly (a(1), a(2), 0) and a(3) of the
  !> (UX, UY, RZ) field a: a copy, so equality is bitwise.
  subroutine check_planar(fid, g, vname, sname, a)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: g, vname, sname
    real(dp), intent(in) :: a(:, :)
    real(dp), allocatable :: b(:, :), c(:)
    call read_r2(fid, g // '/' // vname, 3, 11, b)
    call check(all(b(1:2, :) == a(1:2, :)), g // '/' // vname // '(1:2) = (UX, UY) bit for bit')
    call check(all(b(3, :) == 0.0_dp), g // '/' // vname // '(3) = 0 (in-plane vector)')
    call read_r1(fid, g // '/' // sname, 11, c)
    call check(all(c == a(3, :)), g // '/' // sname // ' = RZ bit for bit')
  end subroutine check_planar

  subroutine check_attrs(fid, g, t, st)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: g
    real(dp), intent(in) :: t
    integer, intent(in) :: st
    integer(hid_t) :: gid, aid
    integer(hsize_t) :: d1(1) = [1_hsize_t]
    integer :: hdferr, ival
    real(dp) :: rval
    call h5gopen_f(fid, g, gid, hdferr)
    call h5aopen_f(gid, 'time', aid, hdferr)
    call h5aread_f(aid, H5T_NATIVE_DOUBLE, rval, d1, hdferr)
    call h5aclose_f(aid, hdferr)
    call check(hdferr == 0 .and. rval == t, g // '@time')
    call h5aopen_f(gid, 'step', aid, hdferr)
    call h5aread_f(aid, H5T_NATIVE_INTEGER, ival, d1, hdferr)
    call h5aclose_f(aid, hdferr)
    call check(hdferr == 0 .and. ival == st, g // '@step')
    call h5gclose_f(gid, hdferr)
  end subroutine check_attrs

  !> Fortran-side dataset shape (n1, n2) and contents.
  subroutine read_r2(fid, path, n1, n2, a)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    integer, intent(in) :: n1, n2
    real(dp), allocatable, intent(out) :: a(:, :)
    integer(hid_t) :: dset, space
    integer(hsize_t) :: dims(2), maxd(2)
    integer :: hdferr, rank
    allocate (a(n1, n2))
    a = -huge(1.0_dp)
    call h5dopen_f(fid, path, dset, hdferr)
    call check(hdferr == 0, 'open ' // path)
    if (hdferr /= 0) return
    call h5dget_space_f(dset, space, hdferr)
    call h5sget_simple_extent_ndims_f(space, rank, hdferr)
    call h5sget_simple_extent_dims_f(space, dims, maxd, hdferr)
    call h5sclose_f(space, hdferr)
    call check(rank == 2 .and. all(dims == [n1, n2]), path // ' dimensions')
    call h5dread_f(dset, H5T_NATIVE_DOUBLE, a, int([n1, n2], hsize_t), hdferr)
    call check(hdferr == 0, 'read ' // path)
    call h5dclose_f(dset, hdferr)
  end subroutine read_r2

  subroutine read_r1(fid, path, n, a)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    integer, intent(in) :: n
    real(dp), allocatable, intent(out) :: a(:)
    integer(hid_t) :: dset, space
    integer(hsize_t) :: dims(1), maxd(1)
    integer :: hdferr, rank
    allocate (a(n))
    a = -huge(1.0_dp)
    call h5dopen_f(fid, path, dset, hdferr)
    call check(hdferr == 0, 'open ' // path)
    if (hdferr /= 0) return
    call h5dget_space_f(dset, space, hdferr)
    call h5sget_simple_extent_ndims_f(space, rank, hdferr)
    call h5sget_simple_extent_dims_f(space, dims, maxd, hdferr)
    call h5sclose_f(space, hdferr)
    call check(rank == 1 .and. dims(1) == n, path // ' rank 1, length')
    call h5dread_f(dset, H5T_NATIVE_DOUBLE, a, int([n], hsize_t), hdferr)
    call h5dclose_f(dset, hdferr)
  end subroutine read_r1

  subroutine read_i1(fid, path, n, a)
    integer(hid_t), intent(in) :: fid
    character(len=*), intent(in) :: path
    integer, intent(in) :: n
    integer, allocatable, intent(out) :: a(:)
    integer(hid_t) :: dset, space
    integer(hsize_t) :: dims(1), maxd(1)
    integer :: hdferr
    allocate (a(n))
    a = -huge(1)
    call h5dopen_f(fid, path, dset, hdferr)
    call check(hdferr == 0, 'open ' // path)
    if (hdferr /= 0) return
    call h5dget_space_f(dset, space, hdferr)
    call h5sget_simple_extent_dims_f(space, dims, maxd, hdferr)
    call h5sclose_f(space, hdferr)
    call check(dims(1) == n, path // ' length')
    call h5dread_f(dset, H5T_NATIVE_INTEGER, a, int([n], hsize_t), hdferr)
    call h5dclose_f(dset, hdferr)
  end subroutine read_i1

  !> fields.xmf: well-formed XML, consistent with fields.h5, 3 grids whose times read back exactly.
  subroutine test_xmf()
    character(len=:), allocatable :: text
    integer :: p, q, ngrid, ntime, ios
    real(dp) :: t
    call check(run(PY // ' -c ''import xml.etree.ElementTree as E; E.parse("' // xmf // '")''') == 0, &
               'fields.xmf is well-formed XML (python3 ElementTree)')
    call check(run(PY // ' tools/check_xdmf.py ' // xmf // ' --grids 3') == 0, &
               'fields.xmf references existing datasets of the declared dimensions (h5py)')
    call slurp(xmf, text)
    call check(index(text, '<Xdmf ') > 0 .and. index(text, 'Version="3.0"') > 0, 'Xdmf Version 3.0')
    call check(index(text, 'CollectionType="Temporal"') > 0, 'temporal collection')
    ngrid = count_of(text, '<Grid Name="step_')
    call check(ngrid == NSTEP, '3 step grids', 'found ' // str_i(ngrid))
    ! Each step grid's name and its Time, in order; the time must read back to the same double.
    p = 1
    ntime = 0
    do k = 1, NSTEP
      q = index(text(p:), '<Grid Name="step_' // pad6(steps(k)) // '"')
      call check(q > 0, 'grid of step ' // str_i(steps(k)) // ' in order')
      if (q == 0) exit
      p = p + q
      q = index(text(p:), '<Time Value="')
      if (q == 0) exit
      p = p + q - 1 + len('<Time Value="')
      read (text(p:p + index(text(p:), '"') - 2), *, iostat=ios) t
      call check(ios == 0 .and. t == times(k), 'Time of step ' // str_i(steps(k)) // ' exact')
      ntime = ntime + 1
    end do
    call check(ntime == NSTEP, 'every grid has a Time')
    call check(count_of(text, 'Name="reaction"') == 1, 'reaction attribute only for the step that has it')
    call check(count_of(text, 'Name="reaction_moment" AttributeType="Scalar"') == 1, &
               'reaction_moment Scalar attribute only for the step that has it')
    call check(count_of(text, 'Name="rotation" AttributeType="Scalar"') == NSTEP .and. &
               count_of(text, 'Name="angular_velocity" AttributeType="Scalar"') == NSTEP, &
               'rotation and angular_velocity Scalar attributes in every step')
    call check(count_of(text, 'Name="displacement" AttributeType="Vector"') == NSTEP .and. &
               count_of(text, 'Name="velocity" AttributeType="Vector"') == NSTEP, &
               'displacement and velocity Vector attributes in every step')
  end subroutine test_xmf

  integer function run(cmd)
    character(len=*), intent(in) :: cmd
    integer :: cstat
    run = -1
    call execute_command_line(cmd, wait=.true., exitstat=run, cmdstat=cstat)
    if (cstat /= 0) run = -1
  end function run

  subroutine slurp(path, text)
    character(len=*), intent(in) :: path
    character(len=:), allocatable, intent(out) :: text
    integer :: un, sz
    open (newunit=un, file=path, access='stream', form='unformatted', action='read')
    inquire (unit=un, size=sz)
    allocate (character(len=sz) :: text)
    read (un) text
    close (un)
  end subroutine slurp

  integer function count_of(text, pat)
    character(len=*), intent(in) :: text, pat
    integer :: p, q
    count_of = 0
    p = 1
    do
      q = index(text(p:), pat)
      if (q == 0) exit
      count_of = count_of + 1
      p = p + q
    end do
  end function count_of

  function pad6(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(len=16) :: b
    write (b, '(i0.6)') i
    s = trim(b)
  end function pad6

  function str_i(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(len=16) :: b
    write (b, '(i0)') i
    s = trim(b)
  end function str_i

  function msg(st, m) result(s)
    integer, intent(in) :: st
    character(len=:), allocatable, intent(in) :: m
    character(len=:), allocatable :: s
    s = ''
    if (st /= STAT_OK .and. allocated(m)) s = m
  end function msg
end program test_fields_hdf5
