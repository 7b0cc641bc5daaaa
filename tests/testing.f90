!> Minimal test harness shared by the unit suites: each check prints one line starting with
!> PASS or FAIL; tests/run_tests.sh counts them. A suite ends with test_summary, which
!> exits non-zero when anything failed.
module testing
  use kinds, only: dp
  implicit none
  private
  public :: check, check_close, test_summary

  integer, save :: npass = 0, nfail = 0

contains

  !> Record a logical check.
  subroutine check(cond, name, detail)
    logical, intent(in) :: cond
    character(len=*), intent(in) :: name
    character(len=*), intent(in), optional :: detail
    if (cond) then
      npass = npass + 1
      write (*, '(a)') 'PASS ' // name
    else
      nfail = nfail + 1
      if (present(detail)) then
        write (*, '(a)') 'FAIL ' // name // ': ' // detail
      else
        write (*, '(a)') 'FAIL ' // name
      end if
    end if
  end subroutine check

  !> Record |actual - expected| <= rtol * |expected| + atol (atol defaults to 0).
  subroutine check_close(actual, expected, rtol, name, atol)
    real(dp), intent(in) :: actual, expected, rtol
    character(len=*), intent(in) :: name
    real(dp), intent(in), optional :: atol
    real(dp) :: tol, err
    character(len=160) :: msg
    tol = rtol * abs(expected)
    if (present(atol)) tol = tol + atol
    err = abs(actual - expected)
    write (msg, '(a,es24.16,a,es24.16,a,es10.3,a,es10.3)') 'actual=', actual, ' expected=', expected, &
      ' err=', err, ' tol=', tol
    call check(err <= tol .and. err == err, name, trim(msg))
  end subroutine check_close

  !> Print the suite's count and stop with a non-zero code if anything failed.
  subroutine test_summary(suite)
    character(len=*), intent(in) :: suite
    write (*, '(a,i0,a,i0,a)') '# ' // suite // ': ', npass, ' passed, ', nfail, ' failed'
    if (nfail > 0) error stop 1
  end subroutine test_summary
end module testing
