!> text_format: put_es must give exactly the characters of Fortran's ES24.16E3 edit descriptor
!> without its blanks, put_int those of I0, for every value (history.csv depends on it bit for
!> bit). The reference is the compiler's own formatted WRITE of the same value.
program test_text_format
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf, ieee_negative_inf
  use, intrinsic :: ieee_exceptions, only: ieee_set_halting_mode, ieee_set_flag, ieee_all
  use kinds, only: dp
  use testing, only: check, test_summary
  use text_format, only: put_es, put_int, put_text, ES_MAX_LEN
  implicit none
  integer, parameter :: NRAND = 200000
  real(dp) :: specials(16), x
  integer :: i, nbad, ints(9), pos
  integer(8) :: bits
  character(len=64) :: first_bad
  character(len=80) :: buf

  ! NaN, Inf, huge and subnormals are the data here: libgfortran's formatting of them raises
  ! IEEE flags, which the debug build (make check-debug, -ffpe-trap) would turn into a crash.
  call ieee_set_halting_mode(ieee_all, .false.)
  specials = [0.0_dp, -0.0_dp, 1.0_dp, -1.0_dp, 0.1_dp, 1.0_dp / 3.0_dp, 9.99999999999999999e99_dp, &
    huge(1.0_dp), -huge(1.0_dp), tiny(1.0_dp), 4.9406564584124654e-324_dp, 1.0e-310_dp, 0.5_dp, &
    ieee_value(1.0_dp, ieee_quiet_nan), ieee_value(1.0_dp, ieee_positive_inf), ieee_value(1.0_dp, ieee_negative_inf)]
  nbad = 0
  first_bad = ''
  do i = 1, size(specials)
    call compare(specials(i))
  end do
  call check(nbad == 0, 'put_es = ES24.16E3 without blanks: zeros of both signs, extremes, subnormals, NaN, Inf', &
    trim(first_bad))

  ! Random bit patterns cover every exponent and the rounding of the 17th digit.
  nbad = 0
  call random_seed()
  do i = 1, NRAND
    call random_number(x)
    bits = ishft(int(x * 4294967296.0_dp, 8), 32)
    call random_number(x)
    bits = ior(bits, int(x * 4294967296.0_dp, 8))   ! 64 random bits: sign, exponent, mantissa
    x = transfer(bits, 1.0_dp)
    call compare(x)
    call random_number(x)
    call compare((x - 0.5_dp) * 10.0_dp**(mod(i, 40) - 20))
  end do
  call check(nbad == 0, 'put_es = ES24.16E3 without blanks on 400000 random doubles', trim(first_bad))

  ints = [0, 1, -1, 9, 10, 123456789, -987654321, huge(1), -huge(1) - 1]
  nbad = 0
  do i = 1, size(ints)
    pos = 0
    call put_int(buf, pos, ints(i))
    write (first_bad, '(i0)') ints(i)
    if (buf(1:pos) /= trim(first_bad)) nbad = nbad + 1
  end do
  call check(nbad == 0, 'put_int = I0, including 0 and -huge - 1')

  pos = 0
  call put_int(buf, pos, 42)
  call put_text(buf, pos, ',')
  call put_es(buf, pos, -2.5_dp)
  write (first_bad, '(i0,a,es24.16e3)') 42, ',', -2.5_dp
  call check(buf(1:pos) == squeeze(first_bad), 'pieces append at pos and advance it', buf(1:pos))

contains

  pure function squeeze(s) result(r)
    character(len=*), intent(in) :: s
    character(len=:), allocatable :: r
    integer :: i
    r = ''
    do i = 1, len_trim(s)
      if (s(i:i) /= ' ') r = r // s(i:i)
    end do
  end function squeeze

  subroutine compare(v)
    real(dp), intent(in) :: v
    character(len=32) :: ref
    character(len=ES_MAX_LEN + 8) :: mine
    integer :: p
    call ieee_set_halting_mode(ieee_all, .false.)
    write (ref, '(es24.16e3)') v
    p = 0
    call put_es(mine, p, v)
    call ieee_set_flag(ieee_all, .false.)            ! nothing pending when the modes are restored
    if (mine(1:p) /= trim(adjustl(ref)) .or. p > ES_MAX_LEN) then
      nbad = nbad + 1
      if (len_trim(first_bad) == 0) first_bad = mine(1:p) // ' vs ' // trim(adjustl(ref))
    end if
  end subroutine compare
end program test_text_format
