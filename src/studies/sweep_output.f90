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
  use, intrinsic :: iso_c_binding, only: c_char, c_loc, c_null_char
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
  use, intrinsic :: ieee_exceptions, only: ieee_overflow, ieee_get_flag, ieee_set_flag, ieee_get_halting_mode, &
    ieee_set_halting_mode
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, set_error, str
  use sweep_spec, only: sweep_t, case_result_t, text_t, status_name, case_dir_name, push, &
                        REF_FINEST, REF_CASE, REF_VALUE, CS_OK
  use sweep_metrics, only: metric_error, nan_value
  use hdf5, only: hid_t, hsize_t, size_t, h5open_f, h5fcreate_f, h5fclose_f, H5F_ACC_TRUNC_F, &
                  h5screate_simple_f, h5sclose_f, h5dcreate_f, h5dclose_f, h5dwrite_f, &
                  h5tcopy_f, h5tset_size_f, h5tset_strpad_f, h5tclose_f, H5T_NATIVE_CHARACTER, H5T_STR_NULLPAD_F, &
                  H5T_NATIVE_DOUBLE, H5T_NATIVE_INTEGER
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
    real(dp) :: y
    integer :: d, ios
    logical :: halt, flag
    if (ieee_is_nan(x)) then
      s = 'nan'
      return
    end if
    ! Near huge(x) a short candidate rounds above it (1.8e308) and reads back as +Inf, which
    ! only rejects that candidate: no trap (-ffpe-trap=overflow), the overflow flag unchanged.
    call ieee_get_halting_mode(ieee_overflow, halt)
    call ieee_get_flag(ieee_overflow, flag)
    call ieee_set_halting_mode(ieee_overflow, .false.)
    do d = 1, 17
      write (buf, '(es30.' // str(d) // 'e3)') x
      read (buf, *, iostat=ios) y
      if (ios == 0 .and. y == x) exit
    end do
    call ieee_set_flag(ieee_overflow, flag)
    call ieee_set_halting_mode(ieee_overflow, halt)
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
    character(len=256) :: iom
    integer :: u, ios, k, j
    stat = STAT_OK
    errmsg = ''
    open (newunit=u, file=path, status='replace', action='write', iostat=ios, iomsg=iom)
    if (ios /= 0) then
      call set_error(stat, errmsg, STAT_RUN, 'cannot write ' // path // ': ' // trim(iom))
      return
    end if
    cols = column_names(sw)
    line = ''
    do j = 1, size(cols)
      if (j > 1) line = line // ','
      line = line // csv_field(cols(j)%s)
    end do
    write (u, '(a)') line
    do k = 1, size(res)
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
      write (u, '(a)') line
    end do
    close (u)
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
    integer(hid_t) :: fid
    integer :: hdferr, k, j, n
    type(text_t), allocatable :: s(:)
    real(dp), allocatable :: x(:)
    stat = STAT_OK
    errmsg = ''
    n = size(res)
    call h5open_f(hdferr)
    if (hdferr /= 0) then
      call set_error(stat, errmsg, STAT_RUN, 'cannot initialize HDF5')
      return
    end if
    call h5fcreate_f(path, H5F_ACC_TRUNC_F, fid, hdferr)
    if (hdferr /= 0) then
      call set_error(stat, errmsg, STAT_RUN, 'cannot create ' // path)
      return
    end if
    allocate (s(n), x(n))
    call put_int('case', [(k, k = 1, n)])
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
    call put_real('time_step', x)
    x = res%wall
    call put_real('wall_time', x)
    call put_int('steps', [(res(k)%steps, k = 1, n)])
    call put_int('iterations', [(res(k)%iterations, k = 1, n)])
    x = res%max_rel_balance
    call put_real('max_rel_balance', x)
    do j = 1, size(sw%columns)
      do k = 1, n
        x(k) = value_or_nan(res(k)%values, j)
      end do
      call put_real(sw%columns(j)%s, x)
    end do
    do j = 1, size(sw%columns)
      do k = 1, n
        x(k) = value_or_nan(res(k)%errors, j)
      end do
      call put_real('err_' // sw%columns(j)%s, x)
    end do
    call put_int('reference', [(merge(1, 0, k == iref), k = 1, n)])
    do k = 1, n
      s(k)%s = case_dir_name(k, n)
    end do
    call put_text('dir', s)
    do k = 1, n
      s(k)%s = message_of(res(k))
    end do
    call put_text('message', s)
    call put_text('columns', column_names(sw))
    call h5fclose_f(fid, hdferr)
    if (hdferr /= 0 .and. stat == STAT_OK) call set_error(stat, errmsg, STAT_RUN, 'cannot close ' // path)

  contains

    subroutine put_real(name, a)
      character(len=*), intent(in) :: name
      real(dp), intent(in) :: a(:)
      integer(hid_t) :: space, dset
      integer(hsize_t) :: dims(1)
      if (stat /= STAT_OK) return
      dims = size(a)
      call h5screate_simple_f(1, dims, space, hdferr)
      call h5dcreate_f(fid, name, H5T_NATIVE_DOUBLE, space, dset, hdferr)
      if (hdferr /= 0) then
        call set_error(stat, errmsg, STAT_RUN, path // ': cannot create dataset ' // name)
      else
        call h5dwrite_f(dset, H5T_NATIVE_DOUBLE, a, dims, hdferr)
        call h5dclose_f(dset, hdferr)
      end if
      call h5sclose_f(space, hdferr)
    end subroutine put_real

    subroutine put_int(name, a)
      character(len=*), intent(in) :: name
      integer, intent(in) :: a(:)
      integer(hid_t) :: space, dset
      integer(hsize_t) :: dims(1)
      if (stat /= STAT_OK) return
      dims = size(a)
      call h5screate_simple_f(1, dims, space, hdferr)
      call h5dcreate_f(fid, name, H5T_NATIVE_INTEGER, space, dset, hdferr)
      if (hdferr /= 0) then
        call set_error(stat, errmsg, STAT_RUN, path // ': cannot create dataset ' // name)
      else
        call h5dwrite_f(dset, H5T_NATIVE_INTEGER, a, dims, hdferr)
        call h5dclose_f(dset, hdferr)
      end if
      call h5sclose_f(space, hdferr)
    end subroutine put_int

    !> Fixed-length strings, NUL-padded to the longest (h5py reads them back without padding).
    subroutine put_text(name, a)
      character(len=*), intent(in) :: name
      type(text_t), intent(in) :: a(:)
      integer(hid_t) :: space, dset, stype
      integer(hsize_t) :: dims(1)
      character(kind=c_char, len=1), allocatable, target :: buf(:)
      integer :: w, i, c
      if (stat /= STAT_OK) return
      w = 1
      do i = 1, size(a)
        w = max(w, len(a(i)%s))
      end do
      allocate (buf(w * size(a)))
      buf = c_null_char
      do i = 1, size(a)
        do c = 1, len(a(i)%s)
          buf((i - 1) * w + c) = a(i)%s(c:c)
        end do
      end do
      dims = size(a)
      call h5tcopy_f(H5T_NATIVE_CHARACTER, stype, hdferr)
      call h5tset_size_f(stype, int(w, size_t), hdferr)
      call h5tset_strpad_f(stype, H5T_STR_NULLPAD_F, hdferr)
      call h5screate_simple_f(1, dims, space, hdferr)
      call h5dcreate_f(fid, name, stype, space, dset, hdferr)
      if (hdferr /= 0) then
        call set_error(stat, errmsg, STAT_RUN, path // ': cannot create dataset ' // name)
      else
        call h5dwrite_f(dset, stype, c_loc(buf), hdferr)
        call h5dclose_f(dset, hdferr)
      end if
      call h5sclose_f(space, hdferr)
      call h5tclose_f(stype, hdferr)
    end subroutine put_text
  end subroutine write_sweep_h5

end module sweep_output
