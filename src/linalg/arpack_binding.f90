!> ARPACK binding (Debian libarpack2-dev): the symmetric generalized eigenproblem A x = λ B x in
!> shift-invert mode (dsaupd/dseupd, mode 3: OP = (A - σB)⁻¹ B, B positive semi-definite), the
!> eigenvalues just above the shift σ. The caller brings the two operations through an extension
!> of shift_invert_t: y = B x, and y = (A - σB)⁻¹ x with its own factorization (CHOLMOD, UMFPACK).
!> Reverse communication: ARPACK never sees the matrices. The start vector is fixed (a run gives
!> the same modes bit for bit).
module arpack_binding
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, set_error, str, check_alloc
  use array_utils, only: stable_order
  implicit none
  private
  public :: shift_invert_t, lanczos_shift_invert

  !> The operations of a shift-invert problem: apply_b (y = B x) and solve_shifted (y = (A - σB)⁻¹ x).
  type, abstract :: shift_invert_t
  contains
    procedure(operation), deferred :: apply_b
    procedure(operation), deferred :: solve_shifted
  end type shift_invert_t

  abstract interface
    subroutine operation(self, x, y, stat, errmsg)
      import :: shift_invert_t, dp
      class(shift_invert_t), intent(inout) :: self
      real(dp), intent(in), contiguous :: x(:)
      real(dp), intent(out), contiguous :: y(:)
      integer, intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine operation
  end interface

  interface
    subroutine dsaupd(ido, bmat, n, which, nev, tol, resid, ncv, v, ldv, iparam, ipntr, workd, workl, lworkl, info)
      import :: dp
      integer, intent(inout) :: ido, info
      character, intent(in) :: bmat
      character(len=2), intent(in) :: which
      integer, intent(in) :: n, nev, ncv, ldv, lworkl
      real(dp), intent(inout) :: tol          !< (0 on entry: ARPACK sets it to the machine precision)
      real(dp), intent(inout) :: resid(n), v(ldv, ncv), workd(3 * n), workl(lworkl)
      integer, intent(inout) :: iparam(11), ipntr(11)
    end subroutine dsaupd
    subroutine dseupd(rvec, howmny, select, d, z, ldz, sigma, bmat, n, which, nev, tol, resid, ncv, v, ldv, iparam, &
                      ipntr, workd, workl, lworkl, info)
      import :: dp
      logical, intent(in) :: rvec
      character, intent(in) :: howmny, bmat
      character(len=2), intent(in) :: which
      integer, intent(in) :: ldz, n, nev, ncv, ldv, lworkl
      logical, intent(inout) :: select(ncv)
      real(dp), intent(out) :: d(nev), z(ldz, nev)
      real(dp), intent(in) :: sigma
      real(dp), intent(inout) :: tol
      real(dp), intent(inout) :: resid(n), v(ldv, ncv), workd(2 * n), workl(lworkl)
      integer, intent(inout) :: iparam(7), ipntr(11)
      integer, intent(out) :: info
    end subroutine dseupd
  end interface

  integer, parameter :: MAX_RESTARTS = 500     !< Lanczos restarts before giving up (iparam(3))

contains

  !> The nev eigenpairs of A x = λ B x with λ just above sigma, ascending: lam(1:nconv), x(:, 1:nconv)
  !> (B-orthonormal). n equations; nev < n. nconv < nev when ARPACK stopped before converging them
  !> all (reported, not an error: the caller says so).
  subroutine lanczos_shift_invert(op, n, nev, sigma, lam, x, nconv, stat, errmsg)
    class(shift_invert_t), intent(inout) :: op
    integer, intent(in) :: n, nev
    real(dp), intent(in) :: sigma
    real(dp), intent(out) :: lam(:), x(:, :)
    integer, intent(out) :: nconv
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp), allocatable :: resid(:), v(:, :), workd(:), workl(:), bx(:), d(:), z(:, :)
    logical, allocatable :: sel(:)
    integer :: ido, info, ncv, lworkl, iparam(11), ipntr(11), i, ast
    real(dp) :: tol
    integer, allocatable :: order(:)
    stat = STAT_OK
    nconv = 0
    if (nev < 1 .or. nev >= n) then
      call set_error(stat, errmsg, STAT_INPUT, 'ARPACK: ' // str(nev) // ' eigenpairs of ' // str(n) // &
        ' equations (1 to n - 1)')
      return
    end if
    ncv = min(n, max(2 * nev + 1, nev + 20))
    lworkl = ncv * (ncv + 8)
    allocate (resid(n), v(n, ncv), workd(3 * n), workl(lworkl), bx(n), sel(ncv), d(nev), stat=ast)
    call check_alloc(ast, 'the Lanczos basis', 8.0_dp * n * (ncv + nev + 5), stat, errmsg)
    if (stat /= STAT_OK) return
    do i = 1, n                                    ! a fixed start vector (info = 1)
      resid(i) = 1.0_dp + 0.5_dp * sin(1.7_dp * i)
    end do
    iparam = 0
    iparam(1) = 1                                  ! exact shifts
    iparam(3) = MAX_RESTARTS
    iparam(7) = 3                                  ! shift-invert
    ipntr = 0
    ido = 0
    info = 1
    tol = 0.0_dp                                   ! machine precision
    do
      call dsaupd(ido, 'G', n, 'LA', nev, tol, resid, ncv, v, n, iparam, ipntr, workd, workl, lworkl, info)
      select case (ido)
      case (-1)                                    ! y = (A - σB)⁻¹ B x
        call op%apply_b(workd(ipntr(1):ipntr(1) + n - 1), bx, stat, errmsg)
        if (stat == STAT_OK) call op%solve_shifted(bx, workd(ipntr(2):ipntr(2) + n - 1), stat, errmsg)
      case (1)                                     ! B x is in workd(ipntr(3))
        call op%solve_shifted(workd(ipntr(3):ipntr(3) + n - 1), workd(ipntr(2):ipntr(2) + n - 1), stat, errmsg)
      case (2)
        call op%apply_b(workd(ipntr(1):ipntr(1) + n - 1), workd(ipntr(2):ipntr(2) + n - 1), stat, errmsg)
      case default
        exit
      end select
      if (stat /= STAT_OK) return
    end do
    if (info < 0) then
      call set_error(stat, errmsg, STAT_RUN, 'ARPACK dsaupd: error ' // str(info) // ' (' // str(n) // ' equations, ' // &
        str(nev) // ' modes, ' // str(ncv) // ' Lanczos vectors)')
      return
    end if
    nconv = iparam(5)
    if (nconv < 1) return
    allocate (z(n, nev), source=0.0_dp)
    call dseupd(.true., 'A', sel, d, z, n, sigma, 'G', n, 'LA', nev, tol, resid, ncv, v, n, iparam, ipntr, workd, &
      workl, lworkl, info)
    if (info /= 0) then
      call set_error(stat, errmsg, STAT_RUN, 'ARPACK dseupd: error ' // str(info))
      nconv = 0
      return
    end if
    nconv = min(nconv, nev)
    order = [(i, i = 1, nconv)]
    call stable_order(d, order)
    do i = 1, nconv
      lam(i) = d(order(i))
      call copy_column(z, order(i), x(:, i))
    end do
  end subroutine lanczos_shift_invert

  pure subroutine copy_column(z, j, y)
    real(dp), intent(in) :: z(:, :)
    integer, intent(in) :: j
    real(dp), intent(out) :: y(:)
    y(1:size(z, 1)) = z(:, j)
  end subroutine copy_column
end module arpack_binding
