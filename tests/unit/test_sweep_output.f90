!> The sweep table: numbers written so that they read back exactly, the reference choice
!> (FINEST = smallest successful step, first on a tie; CASE; VALUE) and the errors against it.
program test_sweep_output
  use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
  use kinds, only: dp
  use testing, only: check, check_close, test_summary
  use sweep_spec, only: sweep_t, case_result_t, text_t, REF_FINEST, REF_CASE, REF_VALUE, CS_OK, CS_RUN_ERROR
  use sweep_metrics, only: nan_value
  use sweep_output, only: apply_reference, real_text
  implicit none
  real(dp) :: xs(6), y
  type(sweep_t) :: sw
  type(case_result_t) :: res(4)
  integer :: i, iref
  character(len=40) :: buf

  ! Shortest text that reads back to the same double.
  xs = [0.1_dp, 1.0_dp / 3.0_dp, -2.5e-300_dp, 1.0e10_dp, huge(1.0_dp), 3.0_dp]
  do i = 1, size(xs)
    buf = real_text(xs(i))
    read (buf, *) y
    call check(y == xs(i), 'real_text reads back exactly: ' // real_text(xs(i)))
  end do
  call check(len(real_text(0.1_dp)) < 10, 'real_text: 0.1 is short', real_text(0.1_dp))
  call check(real_text(nan_value()) == 'nan', 'real_text: NaN is "nan"')

  ! Four cases: steps 1e-3 (ok), 5e-4 (ok), 2.5e-4 (failed), 5e-4 (ok); one metric column.
  allocate (sw%columns(1), sw%col_scale(1), sw%cases(4), sw%ref_values(1), sw%ref_given(1))
  sw%columns(1)%s = 'm'
  sw%col_scale = 0.0_dp
  sw%cases(1)%name = 'a'
  sw%cases(2)%name = 'b'
  sw%cases(3)%name = 'c'
  sw%cases(4)%name = 'd'
  res%dt = [1.0e-3_dp, 5.0e-4_dp, 2.5e-4_dp, 5.0e-4_dp]
  res%status = [CS_OK, CS_OK, CS_RUN_ERROR, CS_OK]
  do i = 1, 4
    allocate (res(i)%values(1))
  end do
  res(1)%values = 1.2_dp
  res(2)%values = 1.05_dp
  res(3)%values = nan_value()
  res(4)%values = 0.9_dp
  sw%ref_kind = REF_FINEST
  call apply_reference(sw, res, iref)
  call check(iref == 2, 'FINEST: smallest step among successful cases, the first on a tie')
  call check_close(res(1)%errors(1), 0.15_dp / 1.05_dp, 1.0e-14_dp, 'FINEST: relative error of case 1')
  call check(res(2)%errors(1) == 0.0_dp, 'FINEST: the reference has error 0')
  call check(ieee_is_nan(res(3)%errors(1)), 'a failed case has no error')
  sw%ref_kind = REF_CASE
  sw%ref_case = 'd'
  call apply_reference(sw, res, iref)
  call check(iref == 4, 'CASE: the named case')
  call check_close(res(1)%errors(1), 0.3_dp / 0.9_dp, 1.0e-14_dp, 'CASE: error relative to case d')
  sw%ref_kind = REF_VALUE
  sw%ref_values = 1.0_dp
  sw%ref_given = .true.
  sw%col_scale = 2.0_dp
  call apply_reference(sw, res, iref)
  call check(iref == 0, 'VALUE: no reference case')
  call check_close(res(4)%errors(1), 0.05_dp, 1.0e-14_dp, 'VALUE: |0.9 - 1| / SCALE 2')
  call test_summary('sweep_output')
end program test_sweep_output
