!> The table of a sweep: errors against the reference, OUTPUT/sweep.csv and OUTPUT/sweep.h5.
!>
!> Columns, in this order (docs/sweep.md): case, name, status, the parameter columns (text as
!> given), time_step, wall_time, steps, iterations, max_rel_balance, the metric columns, err_<metric>
!> for each, reference (1 on the reference case's row), dir (relative to OUTPUT), message.
!> One row per case in definition order, whatever order the runs finished in, so two sweeps
!> of the same file differ only in wall_time.
!> sweep.h5 holds one dataset per column at the root (float64, int32, or fixed-length NUL-padded
!> strings) and /columns, the column names in table order.
module sweep_output
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, set_error, str
  use sweep_spec, only: sweep_t, case_result_t, text_t, status_name, case_dir_name, push, &
                        REF_FINEST, REF_CASE, REF_VALUE, CS_OK
  use sweep_metrics, only: metric_error, nan_value
  use hdf5_file, only: h5_file_t
  use text_file, only: text_file_t
  use number_text, only: shortest_es
  implicit none
  private
  public :: apply_reference, write_sweep_csv, write_sweep_h5, real_text, seconds_text

contains

  !> Errors of every case against the reference of sw; iref is the reference case (0 for
  !> REFERENCE VALUE, or when the reference case did not succeed: errors are then NaN).
  !> FINEST: the successful case with the smallest TIME.STEP, the first of them on a tie.
  subroutine apply_reference(sw, res, iref)
    type(sweep_t), intent(in) :: sw
    type(case_result_t), intent(inout) :: res(:)
    integer, intent(out) :: iref
    real(dp), allocatable :: ref(:)
    integer :: k
    iref = 0
    select case (sw%ref_kind)
    case (REF_FINEST)
      do k = 1, size(res)
        if (res(k)%status /= CS_OK) cycle
        if (iref == 0) then
          iref = k
        else if (res(k)%dt < res(iref)%dt) then
          iref = k
        end if
      end do
    case (REF_CASE)
      do k = 1, size(res)
        if (sw%cases(k)%name == sw%ref_case) then
          if (res(k)%status == CS_OK) iref = k
          exit
        end if
      end do
    end select
    allocate (ref(size(sw%columns)))
    ref = nan_value()
    if (sw%ref_kind == REF_VALUE) then
      where (sw%ref_given) ref = sw%ref_values
    else if (iref > 0) then
      ref = res(iref)%values
    end if
    do k = 1, size(res)
      if (allocated(res(k)%errors)) deallocate (res(k)%errors)
      allocate (res(k)%errors(size(sw%columns)))
      res(k)%errors = nan_value()
      if (res(k)%status == CS_OK .and. allocated(res(k)%values)) res(k)%errors = metric_error(res(k)%values, ref, sw%col_scale)
    end do
  end subroutine apply_reference

  !> Shortest text that reads back to the same double ("nan" for NaN).
  function real_text(x) result(s)
    real(dp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: buf
    integer :: d
    if (ieee_is_nan(x)) then
      s = 'nan'
      return
    end if
    ! At least one digit after the point: the table's format ("5.0E-001") is a contract.
    call shortest_es(x, d, buf)
    if (d == 0) write (buf, '(es30.1e3)') x
    s = trim(adjustl(buf))
  end function real_text

  !> A duration for messages: "12.345".
  function seconds_text(x) result(s)
    real(dp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=32) :: buf
    if (ieee_is_nan(x)) then
      s = 'nan'
      return
    end if
    write (buf, '(f0.3)') x
    s = trim(buf)
    if (s(1:1) == '.') s = '0' // s
  end function seconds_text

  !> A CSV field: quoted (with doubled quotes) when it holds a comma, a quote or a line break.
  pure function csv_field(s) result(f)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: f
    integer :: i
    if (scan(s, ',"' // achar(10) // achar(13)) == 0) then
      f = s
      return
    end if
    f = '"'
    do i = 1, len(s)
      if (s(i:i) == '"') then
        f = f // '""'
      else if (s(i:i) == achar(10) .or. s(i:i) == achar(13)) then
        f = f // ' '
      else
        f = f // s(i:i)
      end if
    end do
    f = f // '"'
  end function csv_field

  function column_names(sw) result(cols)
    type(sweep_t), intent(in) :: sw
    type(text_t), allocatable :: cols(:)
    integer :: j
    allocate (cols(0))
    call push(cols, 'case')
    call push(cols, 'name')
    call push(cols, 'status')
    do j = 1, size(sw%params)
      call push(cols, sw%params(j)%s)
    end do
    call push(cols, 'time_step')
    call push(cols, 'wall_time')
    call push(cols, 'steps')
    call push(cols, 'iterations')
    call push(cols, 'max_rel_balance')
    do j = 1, size(sw%columns)
      call push(cols, sw%columns(j)%s)
    end do
    do j = 1, size(sw%columns)
      call push(cols, 'err_' // sw%columns(j)%s)
    end do
    call push(cols, 'reference')
    call push(cols, 'dir')
    call push(cols, 'message')
  end function column_names

  subroutine write_sweep_csv(path, sw, res, iref, stat, errmsg)
    character(len=*), intent(in) :: path
    type(sweep_t), intent(in) :: sw
    type(case_result_t), intent(in) :: res(:)
    integer, intent(in) :: iref
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(text_t), allocatable :: cols(:)
    character(len=:), allocatable :: line
    type(text_file_t) :: f
    integer :: k, j
    stat = STAT_OK
    errmsg = ''
    call f%create(path, stat, errmsg)
    if (stat /= STAT_OK) return
    cols = column_names(sw)
    line = ''
    do j = 1, size(cols)
      if (j > 1) line = line // ','
      line = line // csv_field(cols(j)%s)
    end do
    call f%write_line(line, stat, errmsg)
    do k = 1, size(res)
      if (stat /= STAT_OK) exit
      line = str(k) // ',' // csv_field(sw%cases(k)%name) // ',' // status_name(res(k)%status)
      do j = 1, size(sw%params)
        line = line // ',' // csv_field(sw%cases(k)%values(j)%s)
      end do
      line = line // ',' // real_text(res(k)%dt) // ',' // real_text(res(k)%wall) // ',' // str(res(k)%steps) // &
        ',' // str(res(k)%iterations) // ',' // real_text(res(k)%max_rel_balance)
      do j = 1, size(sw%columns)
        line = line // ',' // real_text(value_or_nan(res(k)%values, j))
      end do
      do j = 1, size(sw%columns)
        line = line // ',' // real_text(value_or_nan(res(k)%errors, j))
      end do
      line = line // ',' // str(merge(1, 0, k == iref)) // ',' // case_dir_name(k, size(res)) // ',' // &
        csv_field(message_of(res(k)))
      call f%write_line(line, stat, errmsg)
    end do
    call f%close_keep(stat, errmsg)
  end subroutine write_sweep_csv

  pure real(dp) function value_or_nan(a, j)
    real(dp), allocatable, intent(in) :: a(:)
    integer, intent(in) :: j
    value_or_nan = nan_value()
    if (allocated(a)) then
      if (j <= size(a)) value_or_nan = a(j)
    end if
  end function value_or_nan

  pure function message_of(r) result(s)
    type(case_result_t), intent(in) :: r
    character(len=:), allocatable :: s
    s = ''
    if (allocated(r%message)) s = r%message
  end function message_of

  subroutine write_sweep_h5(path, sw, res, iref, stat, errmsg)
    character(len=*), intent(in) :: path
    type(sweep_t), intent(in) :: sw
    type(case_result_t), intent(in) :: res(:)
    integer, intent(in) :: iref
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(h5_file_t) :: h5
    integer :: k, j, n
    type(text_t), allocatable :: s(:)
    real(dp), allocatable :: x(:)
    n = size(res)
    call h5%create(path, 'sweep table', stat, errmsg)
    if (stat /= STAT_OK) return
    allocate (s(n), x(n))
    call h5%write('case', [(k, k = 1, n)], stat, errmsg)
    do k = 1, n
      s(k)%s = sw%cases(k)%name
    end do
    call put_text('name', s)
    do k = 1, n
      s(k)%s = status_name(res(k)%status)
    end do
    call put_text('status', s)
    do j = 1, size(sw%params)
      do k = 1, n
        s(k)%s = sw%cases(k)%values(j)%s
      end do
      call put_text(sw%params(j)%s, s)
    end do
    ! copies: res%dt etc. are not contiguous
    x = res%dt
    call h5%write('time_step', x, stat, errmsg)
    x = res%wall
    call h5%write('wall_time', x, stat, errmsg)
    call h5%write('steps', [(res(k)%steps, k = 1, n)], stat, errmsg)
    call h5%write('iterations', [(res(k)%iterations, k = 1, n)], stat, errmsg)
    x = res%max_rel_balance
    call h5%write('max_rel_balance', x, stat, errmsg)
    do j = 1, size(sw%columns)
      do k = 1, n
        x(k) = value_or_nan(res(k)%values, j)
      end do
      call h5%write(sw%columns(j)%s, x, stat, errmsg)
    end do
    do j = 1, size(sw%columns)
      do k = 1, n
        x(k) = value_or_nan(res(k)%errors, j)
      end do
      call h5%write('err_' // sw%columns(j)%s, x, stat, errmsg)
    end do
    call h5%write('reference', [(merge(1, 0, k == iref), k = 1, n)], stat, errmsg)
    do k = 1, n
      s(k)%s = case_dir_name(k, n)
    end do
    call put_text('dir', s)
    do k = 1, n
      s(k)%s = message_of(res(k))
    end do
    call put_text('message', s)
    call put_text('columns', column_names(sw))
    call h5%close(stat, errmsg)

  contains

    !> Fixed-length strings, NUL-padded to the longest (h5py reads them back without padding).
    subroutine put_text(name, a)
      character(len=*), intent(in) :: name
      type(text_t), intent(in) :: a(:)
      integer :: w, i
      w = 1
      do i = 1, size(a)
        w = max(w, len(a(i)%s))
      end do
      block
        character(len=w) :: t(size(a))
        do i = 1, size(a)
          t(i) = a(i)%s
        end do
        call h5%write_text(name, t, stat, errmsg)
      end block
    end subroutine put_text
  end subroutine write_sweep_h5

end module sweep_output
