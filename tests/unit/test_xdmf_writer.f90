!> xdmf_writer: names, number formatting, escaping, the document structure and the atomic write.
!> Run from the repository root (tests/run_tests.sh does so).
program test_xdmf_writer
  use kinds, only: dp
  use errors, only: STAT_OK
  use testing, only: check, test_summary
  use xdmf_writer, only: xdmf_step_t, xdmf_document, step_group_name, write_text_atomic, xml_escape, xdmf_real
  use os_utils, only: path_exists, remove_file
  implicit none
  type(xdmf_step_t) :: steps(2)
  character(len=:), allocatable :: doc, errmsg, path, back
  real(dp) :: x, y
  real(dp), parameter :: samples(6) = [0.0_dp, 1.0_dp / 3.0_dp, -2.5e-300_dp, 1.0e300_dp, 0.1_dp, &
                                       huge(1.0_dp)]
  integer :: stat, i, cnt, ios
  character(len=32) :: buf

  call check(step_group_name(42) == 'step_000042', 'step group name is zero-padded to 6 digits')
  call check(step_group_name(1234567) == 'step_1234567', 'step group name grows past 6 digits')

  ! Every double must survive the trip through the XML text (17 significant digits suffice).
  do i = 1, size(samples)
    x = samples(i)
    back = xdmf_real(x)
    read (back, *, iostat=ios) y
    call check(ios == 0 .and. y == x, 'xdmf_real round trip ' // xdmf_real(x))
  end do

  call check(xml_escape('a<b>&"c''') == 'a&lt;b&gt;&amp;&quot;c&apos;', 'xml_escape')

  steps(1) = xdmf_step_t(step=1, time=0.5_dp, has_reaction=.false.)
  steps(2) = xdmf_step_t(step=2, time=1.0_dp, has_reaction=.true., has_scalars=.true.)
  doc = xdmf_document('f&.h5', 11, 4, 21, steps)
  call check(count_of(doc, '<Grid Name="step_') == 2, 'one uniform grid per step')
  call check(count_of(doc, '<Grid') == count_of(doc, '</Grid>'), 'every Grid is closed')
  ! Step 1: displacement, velocity (Vector), rotation, angular_velocity (Scalar), stress and its
  ! four named columns; step 2 adds reaction (Vector), reaction_moment, von_mises and
  ! plastic_strain (Scalar).
  call check(count_of(doc, '<Attribute') == 9 + 13, '9 + 13 attributes (reaction and scalars only in step 2)')
  call check(count_of(doc, 'Name="sigma_xy"') == 2 .and. count_of(doc, 'ItemType="HyperSlab"') == 0 .and. &
    count_of(doc, '/sigma_xx</DataItem>') == 2, 'the stress columns named, each its own dataset, in each step')
  call check(count_of(doc, 'AttributeType="Vector" Center="Node"') == 5, '2 + 3 nodal Vector attributes')
  call check(count_of(doc, 'AttributeType="Scalar" Center="Node"') == 5, '2 + 3 nodal Scalar attributes')
  call check(count_of(doc, '<Attribute Name="rotation" AttributeType="Scalar"') == 2 .and. &
             count_of(doc, '<Attribute Name="angular_velocity" AttributeType="Scalar"') == 2 .and. &
             count_of(doc, '<Attribute Name="reaction_moment" AttributeType="Scalar"') == 1, &
             'rotation, angular_velocity (each step), reaction_moment (step 2) are Scalars')
  call check(count_of(doc, '<Attribute Name="displacement" AttributeType="Vector"') == 2 .and. &
             count_of(doc, '<Attribute Name="velocity" AttributeType="Vector"') == 2 .and. &
             count_of(doc, '<Attribute Name="reaction" AttributeType="Vector"') == 1, &
             'displacement, velocity (each step), reaction (step 2) are Vectors')
  call check(count_of(doc, 'Dimensions="11" NumberType="Float"') == 5, 'Scalar attributes have Dimensions (nnode)')
  call check(count_of(doc, 'f&amp;.h5:/step_000002/reaction_moment<') == 1, 'reaction_moment refers to its dataset')
  call check(count_of(doc, 'f&amp;.h5:/mesh/topology') == 2, 'file name escaped, topology per grid')
  call check(index(doc, 'Dimensions="11 3"') > 0 .and. index(doc, 'Dimensions="4 4"') > 0 &
             .and. index(doc, 'Dimensions="21"') > 0, 'dimensions (nnode 3), (nelem 4), (ntopo)')
  call check(index(doc, 'NumberOfElements="4"') > 0, 'NumberOfElements')

  call system_clock(cnt)
  write (buf, '(i0)') cnt
  path = '/tmp/rebond_test_xdmf_writer_' // trim(buf) // '.xmf'
  call write_text_atomic(path, doc, stat, errmsg)
  call check(stat == STAT_OK, 'write_text_atomic')
  call check(.not. path_exists(path // '.tmp'), 'temporary file renamed away')
  call slurp(path, back)
  call check(back == doc, 'file content is the document, byte for byte')
  call check(run('/usr/bin/python3 -c ''import xml.etree.ElementTree as E; E.parse("' // path // '")''') == 0, &
             'document is well-formed XML (python3 ElementTree)')
  ! Overwrite: the rename replaces the old file.
  call write_text_atomic(path, xdmf_document('fields.h5', 11, 4, 21, steps(1:0)), stat, errmsg)
  call slurp(path, back)
  call check(stat == STAT_OK .and. count_of(back, '<Grid') == 1, 'rewrite replaces the file (empty collection)')
  call write_text_atomic('/proc/no/such/dir/x.xmf', doc, stat, errmsg)
  call check(stat /= STAT_OK, 'writing into a missing directory fails')
  call remove_file(path, stat, errmsg)
  call test_summary('xdmf_writer')

contains

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

  integer function run(cmd)
    character(len=*), intent(in) :: cmd
    integer :: cstat
    run = -1
    call execute_command_line(cmd, wait=.true., exitstat=run, cmdstat=cstat)
    if (cstat /= 0) run = -1
  end function run

  subroutine slurp(p, text)
    character(len=*), intent(in) :: p
    character(len=:), allocatable, intent(out) :: text
    integer :: un, sz
    open (newunit=un, file=p, access='stream', form='unformatted', action='read')
    inquire (unit=un, size=sz)
    allocate (character(len=sz) :: text)
    read (un) text
    close (un)
  end subroutine slurp
end program test_xdmf_writer
