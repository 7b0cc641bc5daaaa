!> cholmod_binding: sparse Cholesky solves of a shifted 2D Laplacian (SPD), refactorization
!> with new values, detection of the failing column of an indefinite matrix, determinism.
program test_cholmod_binding
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT
  use testing, only: check, check_close, test_summary
  use sparse_matrix, only: sym_csc_t
  use cholmod_binding, only: cholmod_factor_t, cholmod_version
  implicit none

  write (*, '(a)') '# CHOLMOD ' // cholmod_version()
  call test_laplacian(50)       ! 2500 equations
  call test_laplacian(200)      ! 40000 equations: larger supernodes
  call test_misuse()
  call test_summary('cholmod_binding')

contains

  !> Pattern and values of L + shift*I, L the 5-point Laplacian on an m x m grid (Dirichlet),
  !> assembled from 2-node "edge" elements [1 -1; -1 1] and 1-node shift elements.
  subroutine laplacian(m, shift, pat, v)
    integer, intent(in) :: m
    real(dp), intent(in) :: shift
    type(sym_csc_t), intent(inout) :: pat
    real(dp), allocatable, intent(out) :: v(:)
    integer, allocatable :: eptr(:), edofs(:)
    integer :: ix, iy, i, ne, p, stat
    real(dp), parameter :: kedge(2, 2) = reshape([1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp], [2, 2])
    real(dp) :: kdiag(1, 1)
    character(len=:), allocatable :: errmsg

    allocate (eptr(3 * m * m + 1), edofs(5 * m * m))
    ne = 0
    p = 1
    do iy = 1, m
      do ix = 1, m
        i = ix + (iy - 1) * m
        ne = ne + 1; eptr(ne) = p; edofs(p) = i; p = p + 1
        if (ix < m) then
          ne = ne + 1; eptr(ne) = p; edofs(p:p + 1) = [i, i + 1]; p = p + 2
        end if
        if (iy < m) then
          ne = ne + 1; eptr(ne) = p; edofs(p:p + 1) = [i, i + m]; p = p + 2
        end if
      end do
    end do
    eptr(ne + 1) = p
    if (.not. allocated(pat%colptr)) call pat%build(m * m, eptr(1:ne + 1), edofs(1:p - 1), stat, errmsg)
    allocate (v(pat%nnz))
    v = 0.0_dp
    ! Boundary nodes also tie to the (eliminated) outside: diagonal 4 everywhere.
    do i = 1, ne
      if (eptr(i + 1) - eptr(i) == 2) then
        call pat%add_element(v, edofs(eptr(i):eptr(i) + 1), kedge)
      else
        kdiag(1, 1) = 4.0_dp - real(count_neighbours(edofs(eptr(i)), m), dp) + shift
        call pat%add_element(v, edofs(eptr(i):eptr(i)), kdiag)
      end if
    end do
  end subroutine laplacian

  pure integer function count_neighbours(i, m)
    integer, intent(in) :: i, m
    integer :: ix, iy
    ix = mod(i - 1, m) + 1
    iy = (i - 1) / m + 1
    count_neighbours = merge(1, 0, ix > 1) + merge(1, 0, ix < m) + merge(1, 0, iy > 1) + merge(1, 0, iy < m)
  end function count_neighbours

  real(dp) function rel_residual(pat, v, x, b)
    type(sym_csc_t), intent(in) :: pat
    real(dp), intent(in) :: v(:), x(:), b(:)
    real(dp), allocatable :: r(:)
    allocate (r(size(b)))
    call pat%matvec(v, x, r)
    rel_residual = norm2(b - r) / norm2(b)
  end function rel_residual

  subroutine test_laplacian(m)
    integer, intent(in) :: m
    type(sym_csc_t) :: pat
    type(cholmod_factor_t) :: f
    real(dp), allocatable :: v(:), v2(:), vbad(:), b(:), x(:), x2(:), xx(:), d(:)
    integer :: n, i, stat, minor, jbad
    character(len=:), allocatable :: errmsg, tag
    real(dp) :: lam1

    tag = ' (' // trim(adjustl(itoa(m * m))) // ' eq)'
    call laplacian(m, 0.1_dp, pat, v)
    n = pat%n
    allocate (b(n), x(n), x2(n), xx(n), d(n))
    do i = 1, n
      b(i) = sin(0.37_dp * i) + 0.5_dp
    end do
    call pat%diagonal(v, d)
    call check(all(abs(d - 4.1_dp) < 1.0e-15_dp), 'Laplacian diagonal is 4 + shift' // tag)

    call check(.not. f%is_factored(), 'fresh factor is not factored' // tag)
    call f%factorize(pat, v, stat, errmsg, minor)
    call check(stat == STAT_OK .and. minor == 0, 'SPD Laplacian factorizes' // tag)
    call check(f%is_factored(), 'is_factored after factorize' // tag)
    call f%solve(b, x, stat, errmsg)
    call check(stat == STAT_OK, 'solve succeeds' // tag)
    ! cond(A) <= (8 + 0.1) / 0.1 ~ 81: backward-stable Cholesky gives ~ n_L * eps residual.
    call check(rel_residual(pat, v, x, b) <= 1.0e-12_dp, 'relative residual <= 1e-12' // tag)

    call f%solve(b, x2, stat, errmsg)
    call check(stat == STAT_OK .and. all(x2 == x), 'second solve is bit-identical' // tag)

    ! Exact eigenvector: A u = (4 + shift - 2 cos(pi h) - 2 cos(pi h)) u, u = sin(pi x) sin(pi y).
    lam1 = 4.1_dp - 4.0_dp * cos(acos(-1.0_dp) / (m + 1))
    do i = 1, n
      xx(i) = sin(acos(-1.0_dp) * (mod(i - 1, m) + 1) / (m + 1)) * sin(acos(-1.0_dp) * ((i - 1) / m + 1) / (m + 1))
    end do
    b = lam1 * xx
    call f%solve(b, x, stat, errmsg)
    call check(maxval(abs(x - xx)) <= 1.0e-12_dp, 'solve recovers the exact discrete eigenvector' // tag)

    ! Refactorize: same pattern, new values (shift 2.5 and scaled by 3).
    allocate (v2(size(v)))
    call laplacian(m, 2.5_dp, pat, v2)
    v2 = 3.0_dp * v2
    call f%factorize(pat, v2, stat, errmsg)
    call check(stat == STAT_OK, 'numeric refactorization succeeds' // tag)
    b = lam1 * xx
    call f%solve(b, x, stat, errmsg)
    call check(rel_residual(pat, v2, x, b) <= 1.0e-12_dp, 'residual after refactorization' // tag)
    ! Same eigenvector, eigenvalue 3 (lam1 - 0.1 + 2.5).
    call check(maxval(abs(x - xx * lam1 / (3.0_dp * (lam1 + 2.4_dp)))) <= 1.0e-12_dp, &
               'refactorized solve uses the new values' // tag)

    ! Indefinite: column jbad has diagonal -10. Every principal submatrix without jbad is SPD,
    ! so whatever the ordering, the first failing pivot is jbad's.
    jbad = n / 2 + 7
    vbad = v
    vbad(pat%locate(jbad, jbad)) = -10.0_dp
    call f%factorize(pat, vbad, stat, errmsg, minor)
    call check(stat == STAT_RUN, 'indefinite matrix reports STAT_RUN' // tag)
    call check(minor == jbad, 'failing column is reported (1-based)' // tag, 'minor=' // itoa(minor) // &
               ' expected ' // itoa(jbad))
    if (allocated(errmsg)) then
      call check(index(errmsg, trim(adjustl(itoa(jbad)))) > 0, 'errmsg names the column' // tag, errmsg)
    else
      call check(.false., 'errmsg names the column' // tag, 'no errmsg')
    end if
    call check(.not. f%is_factored(), 'failed factorization is not factored' // tag)
    call f%solve(b, x, stat, errmsg)
    call check(stat /= STAT_OK, 'solve refused after a failed factorization' // tag)

    ! Recovery: refactorize the SPD values after the failure.
    call f%factorize(pat, v, stat, errmsg)
    b = lam1 * xx
    call f%solve(b, x, stat, errmsg)
    call check(stat == STAT_OK .and. maxval(abs(x - xx)) <= 1.0e-12_dp, 'refactorization after failure' // tag)

    call f%destroy()
    call check(.not. f%is_factored(), 'destroyed factor is not factored' // tag)
    call f%destroy()
    call check(.true., 'destroy twice is safe' // tag)
    call check_close(real(n, dp), real(m * m, dp), 0.0_dp, 'order' // tag)
  end subroutine test_laplacian

  subroutine test_misuse()
    type(sym_csc_t) :: pat, pat2
    type(cholmod_factor_t) :: f
    real(dp), allocatable :: v(:), v2(:), b(:), x(:)
    integer :: stat
    character(len=:), allocatable :: errmsg

    allocate (b(4), x(4))
    b = 1.0_dp
    call f%solve(b, x, stat, errmsg)
    call check(stat == STAT_INPUT, 'solve before factorize is an input error')
    call f%factorize(pat, [real(dp) ::], stat, errmsg)
    call check(stat == STAT_INPUT, 'unbuilt pattern is an input error')

    call laplacian(2, 1.0_dp, pat, v)
    call f%factorize(pat, v(1:size(v) - 1), stat, errmsg)
    call check(stat == STAT_INPUT, 'values of the wrong size are an input error')
    call f%factorize(pat, v, stat, errmsg)
    call check(stat == STAT_OK, '4-equation factorization')
    call f%solve(b(1:3), x(1:3), stat, errmsg)
    call check(stat == STAT_INPUT, 'wrong rhs size is an input error')
    call laplacian(3, 1.0_dp, pat2, v2)
    call f%factorize(pat2, v2, stat, errmsg)
    call check(stat == STAT_INPUT, 'changing the pattern on refactorization is an input error')
    call f%destroy()
  end subroutine test_misuse

  function itoa(i) result(s)
    integer, intent(in) :: i
    character(len=12) :: s
    write (s, '(i0)') i
  end function itoa
end program test_cholmod_binding
