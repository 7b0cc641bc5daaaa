!> spd_factor: the scene's SPD factor by CHOLMOD or MUMPS (in this process, MPI started for it).
!> On a shifted 2D Laplacian: MUMPS's solution equals CHOLMOD's to 1e-13 and both solve to a
!> relative residual of 1e-14; the analysis is made once (a refactorization with new values keeps
!> it) and the factor entries and flops are reported; an indefinite matrix is STAT_RUN with the
!> failing column found (minor, as CHOLMOD's); destroy keeps the choice of library; the solver's
!> call counts and times; MUMPS out of core gives the in-core solution.
program test_spd_factor
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, str
  use testing, only: check, test_summary
  use sparse_matrix, only: sym_csc_t
  use cholmod_binding, only: factor_stats_t
  use spd_factor, only: spd_factor_t, LIBRARY_CHOLMOD, LIBRARY_MUMPS, LIBRARY_AUTO
  use parallel, only: parallel_stop
  implicit none

  call test_same_answers(30)      ! 900 equations
  call test_same_answers(120)     ! 14 400 equations
  call test_indefinite()
  call test_out_of_core()
  call test_auto()
  call parallel_stop()
  call test_summary('spd_factor')

contains

  !> L + shift I, L the 5-point Laplacian on an m x m grid (Dirichlet outside): upper triangle.
  subroutine laplacian(m, shift, pat, v)
    integer, intent(in) :: m
    real(dp), intent(in) :: shift
    type(sym_csc_t), intent(out) :: pat
    real(dp), allocatable, intent(out) :: v(:)
    integer :: ix, iy, i, p
    pat%n = m * m
    allocate (pat%colptr(m * m + 1), pat%rowind(3 * m * m), v(3 * m * m))
    p = 1
    do iy = 1, m
      do ix = 1, m
        i = ix + (iy - 1) * m
        pat%colptr(i) = p
        if (iy > 1) then            ! rows sorted within the column: i - m, i - 1, i
          pat%rowind(p) = i - m; v(p) = -1.0_dp; p = p + 1
        end if
        if (ix > 1) then
          pat%rowind(p) = i - 1; v(p) = -1.0_dp; p = p + 1
        end if
        pat%rowind(p) = i; v(p) = 4.0_dp + shift; p = p + 1
      end do
    end do
    pat%colptr(m * m + 1) = p
    pat%nnz = p - 1
    v = v(1:p - 1)
    pat%rowind = pat%rowind(1:p - 1)
  end subroutine laplacian

  subroutine test_same_answers(m)
    integer, intent(in) :: m
    type(sym_csc_t) :: pat
    type(spd_factor_t) :: fc, fm
    real(dp), allocatable :: v(:), b(:), xc(:), xm(:), r(:)
    type(factor_stats_t) :: st, st2
    character(len=:), allocatable :: errmsg, tag
    integer :: stat, i, minor
    real(dp) :: ratio

    tag = ' (' // str(m * m) // ' eq)'
    call laplacian(m, 0.1_dp, pat, v)
    allocate (b(pat%n), xc(pat%n), xm(pat%n), r(pat%n))
    do i = 1, pat%n
      b(i) = sin(0.37_dp * i) + 0.5_dp
    end do
    call fc%choose(LIBRARY_CHOLMOD, .false.)
    call fm%choose(LIBRARY_MUMPS, .false.)
    call check(fc%library() == 'CHOLMOD' .and. fm%library() == 'MUMPS', 'the libraries chosen' // tag)
    call fc%factorize(pat, v, stat, errmsg, minor)
    call fm%factorize(pat, v, stat, errmsg, minor)
    call check(stat == STAT_OK .and. minor == 0 .and. fm%is_factored(), 'MUMPS factorizes the SPD Laplacian' // tag)
    call fc%solve(b, xc, stat, errmsg)
    call fm%solve(b, xm, stat, errmsg)
    call check(stat == STAT_OK, 'MUMPS solves' // tag)
    call pat%matvec(v, xm, r)
    call check(norm2(b - r) < 1.0e-14_dp * norm2(b), 'MUMPS residual < 1e-14' // tag, str(norm2(b - r) / norm2(b)))
    call check(maxval(abs(xm - xc)) <= 1.0e-13_dp * maxval(abs(xc)), 'MUMPS = CHOLMOD to 1e-13' // tag)
    st = fm%stats()
    ratio = fm%cost_ratio()
    call check(st%nnz >= real(pat%nnz, dp) .and. st%flops > 0.0_dp .and. ratio > 0.0_dp .and. &
      fm%solve_flops() == 4.0_dp * st%nnz, 'MUMPS reports its factor entries, flops and cost ratio' // tag)
    call check(all(fm%estimates() >= 0.0_dp) .and. any(fm%estimates() > 0.0_dp), 'MUMPS estimates after analysis' // tag)
    ! New values on the same pattern: refactorized (the analysis kept), the new solution right.
    v = 2.0_dp * v
    call fm%factorize(pat, v, stat, errmsg)
    call fm%solve(b, xm, stat, errmsg)
    call check(stat == STAT_OK .and. maxval(abs(2.0_dp * xm - xc)) <= 1.0e-13_dp * maxval(abs(xc)), &
      'MUMPS refactorized with new values' // tag)
    st2 = fm%stats()
    call check(st2%analysis_cpu == st%analysis_cpu, 'the analysis made once' // tag)
    call check(fm%times%factorizations == 2 .and. fm%times%solves == 2 .and. fm%times%solve_cpu >= 0.0_dp, &
      'call counts kept' // tag)
    ! destroy keeps the library: the next factorize starts MUMPS again.
    call fm%destroy()
    call check(.not. fm%is_factored() .and. fm%library() == 'MUMPS', 'destroy keeps MUMPS chosen' // tag)
    call fm%factorize(pat, v, stat, errmsg)
    call check(stat == STAT_OK .and. fm%ranks() == 1, 'MUMPS again after destroy, on 1 rank' // tag)
    call fm%destroy()
    call fc%destroy()
  end subroutine test_same_answers

  !> A shift that makes the Laplacian indefinite: STAT_RUN, and minor names a column as CHOLMOD does.
  subroutine test_indefinite()
    type(sym_csc_t) :: pat
    type(spd_factor_t) :: fc, fm
    real(dp), allocatable :: v(:)
    character(len=:), allocatable :: errmsg
    integer :: stat, minor_c, minor_m
    call laplacian(20, -1.0_dp, pat, v)
    call fc%choose(LIBRARY_CHOLMOD, .false.)
    call fm%choose(LIBRARY_MUMPS, .false.)
    call fc%factorize(pat, v, stat, errmsg, minor_c)
    call fm%factorize(pat, v, stat, errmsg, minor_m)
    call check(stat == STAT_RUN .and. index(errmsg, 'not positive definite') > 0, 'MUMPS: indefinite is STAT_RUN', errmsg)
    call check(minor_m == minor_c .and. minor_m > 0, 'MUMPS: the failing column found (' // str(minor_m) // ')')
    call fm%destroy()
    call fc%destroy()
  end subroutine test_indefinite

  subroutine test_out_of_core()
    type(sym_csc_t) :: pat
    type(spd_factor_t) :: fi, fo
    real(dp), allocatable :: v(:), b(:), xi(:), xo(:)
    character(len=:), allocatable :: errmsg
    integer :: stat
    call laplacian(60, 0.1_dp, pat, v)
    allocate (b(pat%n), xi(pat%n), xo(pat%n))
    b = 1.0_dp
    call fi%choose(LIBRARY_MUMPS, .false.)
    call fo%choose(LIBRARY_MUMPS, .true.)
    call fi%factorize(pat, v, stat, errmsg)
    call fi%solve(b, xi, stat, errmsg)
    call fo%factorize(pat, v, stat, errmsg)
    call check(stat == STAT_OK, 'MUMPS out of core factorizes', errmsg)
    call fo%solve(b, xo, stat, errmsg)
    call check(stat == STAT_OK .and. maxval(abs(xo - xi)) <= 1.0e-14_dp * maxval(abs(xi)), &
      'MUMPS out of core = in core to 1e-14')
    call fo%destroy()
    call fi%destroy()
  end subroutine test_out_of_core

  !> AUTO in one process (no mpirun) is CHOLMOD.
  subroutine test_auto()
    type(spd_factor_t) :: f
    call f%choose(LIBRARY_AUTO, .false.)
    call check(f%library() == 'CHOLMOD', 'SOLVER AUTO in one process is CHOLMOD')
  end subroutine test_auto
end program test_spd_factor
