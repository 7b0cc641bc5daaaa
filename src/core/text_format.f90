!> Numbers appended to a character buffer without the Fortran I/O runtime: a formatted
!> internal WRITE allocates in libgfortran at every statement, and the history rows are built
!> at every step. put_es gives exactly the characters of the ES24.16E3 edit descriptor without
!> its leading blanks (the C library's digits, as libgfortran's), put_int those of I0.
module text_format
  use, intrinsic :: iso_c_binding, only: c_double, c_char, c_int
  use kinds, only: dp
  use c_interfaces, only: rb_format_es
  implicit none
  private
  public :: put_es, put_int, put_text, put_csv, csv_field, ES_MAX_LEN

  !> Longest text put_es writes: sign, 17 digits, the point, E, sign, 3 exponent digits.
  integer, parameter :: ES_MAX_LEN = 24

contains

  !> buf(pos+1:) = x as ES24.16E3 without blanks; pos advances. The caller keeps ES_MAX_LEN
  !> characters free after pos.
  subroutine put_es(buf, pos, x)
    character(len=*), intent(inout) :: buf
    integer, intent(inout) :: pos
    real(dp), intent(in) :: x
    character(kind=c_char) :: tmp(ES_MAX_LEN + 8)
    integer :: n, i
    n = rb_format_es(real(x, c_double), tmp)
    do i = 1, n
      buf(pos + i:pos + i) = tmp(i)
    end do
    pos = pos + n
  end subroutine put_es

  !> buf(pos+1:) = i as I0 (minus sign, digits); pos advances.
  pure subroutine put_int(buf, pos, i)
    character(len=*), intent(inout) :: buf
    integer, intent(inout) :: pos
    integer, intent(in) :: i
    character(len=20) :: d
    integer(8) :: v
    integer :: k
    v = abs(int(i, 8))   ! in 64 bits: -huge(1) - 1 has no 32-bit absolute value
    k = len(d)
    do
      d(k:k) = achar(iachar('0') + int(mod(v, 10_8)))
      v = v / 10_8
      if (v == 0_8) exit
      k = k - 1
    end do
    if (i < 0) then
      k = k - 1
      d(k:k) = '-'
    end if
    buf(pos + 1:pos + len(d) - k + 1) = d(k:)
    pos = pos + len(d) - k + 1
  end subroutine put_int

  !> buf(pos+1:) = s; pos advances.
  pure subroutine put_text(buf, pos, s)
    character(len=*), intent(inout) :: buf
    integer, intent(inout) :: pos
    character(len=*), intent(in) :: s
    buf(pos + 1:pos + len(s)) = s
    pos = pos + len(s)
  end subroutine put_text

  !> buf(pos+1:) = text as one CSV field (RFC 4180): as it is, or between double quotes with its
  !> quotes doubled when it holds a comma, a quote or a line break (a name from the scene or a
  !> Gmsh file can). pos advances; the caller keeps 2 len(text) + 2 characters free.
  pure subroutine put_csv(buf, pos, text)
    character(len=*), intent(inout) :: buf
    integer, intent(inout) :: pos
    character(len=*), intent(in) :: text
    integer :: i
    if (scan(text, ',"' // achar(10) // achar(13)) == 0) then
      buf(pos + 1:pos + len(text)) = text
      pos = pos + len(text)
      return
    end if
    pos = pos + 1
    buf(pos:pos) = '"'
    do i = 1, len(text)
      pos = pos + 1
      buf(pos:pos) = text(i:i)
      if (text(i:i) == '"') then
        pos = pos + 1
        buf(pos:pos) = '"'
      end if
    end do
    pos = pos + 1
    buf(pos:pos) = '"'
  end subroutine put_csv

  !> text as one CSV field (put_csv), for headers built once.
  pure function csv_field(text) result(f)
    character(len=*), intent(in) :: text
    character(len=:), allocatable :: f
    character(len=2 * len(text) + 2) :: buf
    integer :: pos
    pos = 0
    call put_csv(buf, pos, text)
    f = buf(1:pos)
  end function csv_field
end module text_format
