!> The one number reader of rebond's text inputs (scene files, --set, sweep files, Gmsh meshes,
!> CSV results read back): strict decimal syntax, out-of-range values reported instead of
!> trapping (a build with -ffpe-trap=overflow must survive any input), and the short text
!> of a real for messages.
module number_text
  use, intrinsic :: iso_fortran_env, only: int64
  use, intrinsic :: ieee_exceptions, only: ieee_get_flag, ieee_set_flag, ieee_flag_type, ieee_overflow, ieee_underflow
  use kinds, only: dp
  use errors, only: str
  use, intrinsic :: ieee_exceptions, only: ieee_get_halting_mode, ieee_set_halting_mode, ieee_get_flag, ieee_set_flag, &
    ieee_overflow
  implicit none
  private
  public :: parse_real_text, parse_int_text, parse_int64_text, real_text, shortest_es
  public :: NUM_OK, NUM_MALFORMED, NUM_RANGE

  !> Result codes of the parsers.
  integer, parameter :: NUM_OK = 0, NUM_MALFORMED = 1, NUM_RANGE = 2

contains

  !> Strict decimal real: [+-] (digits[.[digits]] | .digits) [(e|E|d|D)[+-]digits]. No blanks,
  !> NaN, Inf, hex, commas or logicals. ierr: NUM_OK, NUM_MALFORMED, NUM_RANGE (|x| > huge).
  !> The syntax is checked here and the conversion (correct rounding) left to READ. Overflow is
  !> detected before READ, from the decimal digits, so that READ never overflows: a build with
  !> -ffpe-trap=overflow must not die on a bad input. Underflow gives 0 or a subnormal, with
  !> the IEEE flags left as they were.
  pure subroutine parse_real_text(s, x, ierr)
    character(len=*), intent(in) :: s
    real(dp), intent(out) :: x
    integer, intent(out) :: ierr
    !> Decimal digits of (2 - 2**-53) * 2**1023, the smallest magnitude that rounds to +Inf,
    !> as 0.TDIGITS * 10**309.
    character(len=*), parameter :: TDIGITS = '1797693134862315807937289714053034150799341327100378269361737789804449' // &
      '68292764750946649017977587207096330286416692887910946555547851940402630657488671505820681908902000708383676' // &
      '273854845817711531764475730270069855571366959622842914819860834936475292719074168444365510704342711559699508' // &
      '093042880177904174497792'
    type(ieee_flag_type), parameter :: watched(2) = [ieee_overflow, ieee_underflow]
    logical :: flags(2)
    character(len=len(s)) :: buf
    character(len=:), allocatable :: digs
    integer :: n, i, i1, i2, nd1, nd2, ne, ios, e10, expo, k, f, l
    x = 0.0_dp
    ierr = NUM_MALFORMED
    n = len(s)
    i = 1
    if (n == 0) return
    if (n == 1) then                 ! fast path: the "0" z coordinates of plane meshes
      if (s >= '0' .and. s <= '9') then
        x = real(iachar(s) - iachar('0'), dp)
        ierr = NUM_OK
      end if
      return
    end if
    if (s(1:1) == '+' .or. s(1:1) == '-') i = 2
    i1 = i
    nd1 = ndigits(i)
    i = i + nd1
    nd2 = 0
    i2 = i + 1
    if (i <= n) then
      if (s(i:i) == '.') then
        i = i + 1
        nd2 = ndigits(i)
        i = i + nd2
      end if
    end if
    if (nd1 + nd2 == 0) return
    expo = 0
    if (i <= n) then
      if (scan(s(i:i), 'eEdD') == 1) then
        i = i + 1
        k = i
        if (i <= n) then
          if (s(i:i) == '+' .or. s(i:i) == '-') i = i + 1
        end if
        ne = ndigits(i)
        if (ne == 0) return
        expo = exponent_value(s(k:i + ne - 1))
        i = i + ne
      end if
    end if
    if (i /= n + 1) return
    ! significant digits and decimal exponent: |x| = 0.digs * 10**e10
    digs = s(i1:i1 + nd1 - 1) // s(i2:i2 + nd2 - 1)
    f = verify(digs, '0')
    if (f > 0) then
      l = verify(digs, '0', back=.true.)
      e10 = nd1 - f + 1 + expo
      if (e10 > 309 .or. (e10 == 309 .and. lge(digs(f:l), TDIGITS))) then
        ierr = NUM_RANGE
        return
      end if
      if (e10 < -400) then         ! far below the smallest subnormal (~4.9e-324)
        x = sign(0.0_dp, merge(-1.0_dp, 1.0_dp, s(1:1) == '-'))
        ierr = NUM_OK
        return
      end if
    end if
    buf = s
    k = scan(buf, 'dD')
    if (k > 0) buf(k:k) = 'e'
    call ieee_get_flag(watched, flags)
    read (buf, *, iostat=ios) x
    call ieee_set_flag(watched, flags)
    if (ios /= 0 .or. .not. (abs(x) <= huge(x))) then
      ierr = NUM_RANGE
      x = 0.0_dp
    else
      ierr = NUM_OK
    end if
  contains
    pure integer function ndigits(k0)
      integer, intent(in) :: k0
      integer :: m
      m = k0
      do while (m <= n)
        if (s(m:m) < '0' .or. s(m:m) > '9') exit
        m = m + 1
      end do
      ndigits = m - k0
    end function ndigits

    !> Value of a signed exponent, saturated at +-100000 (enough to decide over/underflow).
    pure integer function exponent_value(t)
      character(len=*), intent(in) :: t
      integer :: m, v
      logical :: neg
      neg = t(1:1) == '-'
      v = 0
      do m = 1, len(t)
        if (t(m:m) < '0' .or. t(m:m) > '9') cycle
        v = min(10 * v + (iachar(t(m:m)) - iachar('0')), 100000)
      end do
      exponent_value = merge(-v, v, neg)
    end function exponent_value
  end subroutine parse_real_text

  !> Strict integer: [+-]digits. ierr as parse_real_text (NUM_RANGE outside the default kind).
  pure subroutine parse_int_text(s, n, ierr)
    character(len=*), intent(in) :: s
    integer, intent(out) :: n
    integer, intent(out) :: ierr
    integer(int64) :: v
    n = 0
    call parse_int64_text(s, v, ierr)
    if (ierr /= NUM_OK) return
    if (v > huge(n) .or. v < -int(huge(n), int64) - 1) then
      ierr = NUM_RANGE
      return
    end if
    n = int(v)
  end subroutine parse_int_text

  !> Strict 64-bit integer: [+-]digits (at most 18 significant digits: NUM_RANGE beyond).
  pure subroutine parse_int64_text(s, v, ierr)
    character(len=*), intent(in) :: s
    integer(int64), intent(out) :: v
    integer, intent(out) :: ierr
    integer :: i, k, first
    logical :: neg
    v = 0
    ierr = NUM_MALFORMED
    if (len(s) == 0) return
    i = 1
    neg = s(1:1) == '-'
    if (s(1:1) == '+' .or. s(1:1) == '-') i = 2
    if (i > len(s)) return
    if (verify(s(i:), '0123456789') /= 0) return
    first = verify(s(i:), '0') + i - 1        ! first significant digit (i - 1 if all zeros)
    if (first < i) then
      ierr = NUM_OK
      return
    end if
    if (len(s) - first + 1 > 18) then        ! beyond what int64 holds for every 18-digit value
      ierr = NUM_RANGE
      return
    end if
    do k = first, len(s)
      v = 10 * v + (iachar(s(k:k)) - iachar('0'))
    end do
    if (neg) v = -v
    ierr = NUM_OK
  end subroutine parse_int64_text

  !> The fewest digits after the point of an ES form of x that reads back to x exactly, and
  !> that form (buf). Near huge(x) a short candidate rounds above it (1.8E+308) and reads back
  !> as +Inf, which only rejects it: no trap under -ffpe-trap=overflow, the flag unchanged.
  subroutine shortest_es(x, d, buf)
    real(dp), intent(in) :: x
    integer, intent(out) :: d
    character(len=*), intent(out) :: buf
    character(len=16) :: fmt
    real(dp) :: y
    integer :: ios
    logical :: halt, flag
    call ieee_get_halting_mode(ieee_overflow, halt)
    call ieee_get_flag(ieee_overflow, flag)
    call ieee_set_halting_mode(ieee_overflow, .false.)
    do d = 0, 16
      write (fmt, '(a,i0,a,i0,a)') '(es', d + 10, '.', d, 'e3)'
      write (buf, fmt) x
      read (buf, *, iostat=ios) y
      if (ios == 0 .and. y == x) exit
    end do
    d = min(d, 16)
    call ieee_set_flag(ieee_overflow, flag)
    call ieee_set_halting_mode(ieee_overflow, halt)
  end subroutine shortest_es

  !> The shortest text that reads back to x exactly: "0", "0.5", "-12.25", "1.3E-3", "1E+100"
  !> (plain decimals for exponents -4..14, else E notation without padding).
  function real_text(x) result(s)
    real(dp), intent(in) :: x
    character(len=:), allocatable :: s
    character(len=48) :: buf
    character(len=16) :: fmt
    integer :: d, e, k
    if (x == 0.0_dp) then
      s = '0'
      return
    end if
    call shortest_es(x, d, buf)
    k = scan(buf, 'E')
    read (buf(k + 1:), *) e
    if (e >= -4 .and. e <= 14) then
      write (fmt, '(a,i0,a)') '(f0.', max(d - e, 0), ')'
      write (buf, fmt) x
      s = trim(adjustl(buf))
      if (index(s, '.') > 0) then
        do while (s(len(s):len(s)) == '0')
          s = s(1:len(s) - 1)
        end do
        if (s(len(s):len(s)) == '.') s = s(1:len(s) - 1)
      end if
      if (s(1:1) == '.') s = '0' // s
      if (len(s) > 1) then
        if (s(1:2) == '-.') s = '-0' // s(2:)
      end if
    else
      s = trim(adjustl(buf(1:k - 1)))
      if (s(len(s):len(s)) == '.') s = s(1:len(s) - 1)
      write (buf, '(i0)') abs(e)
      s = s // 'E' // merge('-', '+', e < 0) // trim(buf)
    end if
  end function real_text
end module number_text
