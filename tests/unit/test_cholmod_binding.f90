!> cholmod_binding: sparse Cholesky solves of a shifted 2D Laplacian (SPD), refactorization
!> with new values, detection of the failing column of an indefinite matrix, determinism.
!> umfpack_factor_t: LU solves of the indefinite contact system [S C'; C D] (manufactured
!> solution and the Schur complement by dense LAPACK), refactorization on the same pattern
!> (constraint deactivated then activated), a singular system, bad patterns and misuse.
program test_cholmod_binding
  use kinds, only: dp
  use errors, only: STAT_OK, STAT_RUN, STAT_INPUT, str
  use testing, only: check, check_close, test_summary
  use sparse_matrix, only: sym_csc_t
  use cholmod_binding, only: cholmod_factor_t, cholmod_version, umfpack_factor_t, umfpack_version, factor_stats_t, blas_threads
  use dense_solve, only: spd_solve
  implicit none

  write (*, '(a)') '# CHOLMOD ' // cholmod_version()
  call test_laplacian(50)       ! 2500 equations
  call test_laplacian(200)      ! 40000 equations: larger supernodes
  call test_laplacian(240)      ! 57600 equations: nested dissection of the supervariables
  call test_vector_laplacian(170)
  call test_threads()
  call test_misuse()
  write (*, '(a)') '# UMFPACK ' // umfpack_version()
  call test_kkt()
  call test_umf_singular()
  call test_umf_misuse()
  call test_summary('cholmod_binding')

contains

  !> After the factorizations and solves above: solves run on one BLAS thread, factorizations on
  !> the count OpenBLAS started with (cholmod_shim.c; one per CPU unless OPENBLAS_NUM_THREADS says).
  subroutine test_threads()
    integer :: ts, tf
    call blas_threads(ts, tf)
    call check(ts == 1 .and. tf >= 1, 'BLAS threads: a solve on one thread, a factorization on ' // &
      'OpenBLAS''s count', 'solve ' // str(ts) // ', factorize ' // str(tf))
  end subroutine test_threads

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
    call check_ordering(f, n, tag)

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

  !> The analysis's ordering: the best of AMD and METIS below 50000 equations, the nested
  !> dissection of the supervariables above; a factor with entries.
  subroutine check_ordering(f, n, tag)
    type(cholmod_factor_t), intent(in) :: f
    integer, intent(in) :: n
    character(len=*), intent(in) :: tag
    type(factor_stats_t) :: st
    st = f%stats()
    if (n >= 50000) then
      call check(st%ordering == 3, 'ordering: nested dissection of the supervariables' // tag, 'code ' // itoa(st%ordering))
    else
      call check(st%ordering == 1 .or. st%ordering == 2, 'ordering: best of AMD and METIS' // tag, &
        'code ' // itoa(st%ordering))
    end if
    call check(st%nnz >= real(n, dp) .and. st%flops > 0.0_dp .and. st%analysis_cpu >= 0.0_dp, &
      'analysis figures reported' // tag)
  end subroutine check_ordering

  !> Two DOFs per node (x, y), A = L (x) T + couplings of some x DOFs alone (x of node i to x
  !> of node i + 2 for every 7th node), so that supervariables are pairs and single columns:
  !> the compressed ordering must still solve A x = b (manufactured x) to round-off.
  subroutine test_vector_laplacian(m)
    integer, intent(in) :: m
    type(sym_csc_t) :: pat
    type(cholmod_factor_t) :: f
    real(dp), parameter :: t(2, 2) = reshape([2.0_dp, 1.0_dp, 1.0_dp, 2.0_dp], [2, 2])
    real(dp), parameter :: kedge(2, 2) = reshape([1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp], [2, 2])
    integer, allocatable :: eptr(:), edofs(:)
    real(dp), allocatable :: v(:), xs(:), b(:), x(:)
    real(dp) :: ke(4, 4)
    integer :: ix, iy, i, j, ne, p, n, stat, a, c
    character(len=:), allocatable :: errmsg, tag

    n = 2 * m * m
    tag = ' (' // trim(adjustl(itoa(n))) // ' eq, 2 per node)'
    allocate (eptr(4 * m * m + 1), edofs(12 * m * m))
    ne = 0
    p = 1
    do iy = 1, m
      do ix = 1, m
        i = ix + (iy - 1) * m
        ne = ne + 1; eptr(ne) = p; edofs(p:p + 1) = [2 * i - 1, 2 * i]; p = p + 2
        do j = 1, 2
          if ((j == 1 .and. ix < m) .or. (j == 2 .and. iy < m)) then
            c = merge(i + 1, i + m, j == 1)
            ne = ne + 1; eptr(ne) = p; edofs(p:p + 3) = [2 * i - 1, 2 * i, 2 * c - 1, 2 * c]; p = p + 4
          end if
        end do
        if (mod(i, 7) == 0 .and. i + 2 <= m * m) then
          ne = ne + 1; eptr(ne) = p; edofs(p:p + 1) = [2 * i - 1, 2 * i + 3]; p = p + 2
        end if
      end do
    end do
    eptr(ne + 1) = p
    call pat%build(n, eptr(1:ne + 1), edofs(1:p - 1), stat, errmsg)
    call check(stat == STAT_OK, 'vector Laplacian pattern' // tag)
    allocate (v(pat%nnz), xs(n), b(n), x(n))
    v = 0.0_dp
    do i = 1, ne
      select case (eptr(i + 1) - eptr(i))
      case (2)
        if (edofs(eptr(i) + 1) == edofs(eptr(i)) + 1) then
          call pat%add_element(v, edofs(eptr(i):eptr(i) + 1), 4.1_dp * t)      ! the node's own block
        else
          call pat%add_element(v, edofs(eptr(i):eptr(i) + 1), kedge)           ! x alone to x
        end if
      case (4)
        do a = 1, 2
          do c = 1, 2
            ke(2 * a - 1:2 * a, 2 * c - 1:2 * c) = kedge(a, c) * t
          end do
        end do
        call pat%add_element(v, edofs(eptr(i):eptr(i) + 3), ke)
      end select
    end do
    do i = 1, n
      xs(i) = cos(0.013_dp * i) + 0.25_dp * sin(0.7_dp * i)
    end do
    call pat%matvec(v, xs, b)
    call f%factorize(pat, v, stat, errmsg)
    call check(stat == STAT_OK, 'vector Laplacian factorizes' // tag)
    call f%solve(b, x, stat, errmsg)
    call check(stat == STAT_OK .and. rel_residual(pat, v, x, b) <= 1.0e-12_dp, 'relative residual <= 1e-12' // tag)
    call check(norm2(x - xs) <= 1.0e-10_dp * norm2(xs), 'manufactured solution recovered' // tag)
    call check_ordering(f, n, tag)
  end subroutine test_vector_laplacian

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

  !> S = K + 0.1 M: K = tridiag(-1, 2, -1) (bar fixed at both ends, unit element stiffness),
  !> M = tridiag(1, 4, 1) / 6 (consistent mass). Eigenvalues in (0.1, 4.04): cond(S) < 41.
  pure function stiffness_mass(n) result(s)
    integer, intent(in) :: n
    real(dp) :: s(n, n)
    integer :: i
    s = 0.0_dp
    do i = 1, n
      s(i, i) = 2.0_dp + 0.1_dp * 4.0_dp / 6.0_dp
      if (i > 1) s(i, i - 1) = -1.0_dp + 0.1_dp / 6.0_dp
      if (i < n) s(i, i + 1) = -1.0_dp + 0.1_dp / 6.0_dp
    end do
  end function stiffness_mass

  !> Dense [S C'; C diag(d)].
  pure function kkt(s, c, d) result(a)
    real(dp), intent(in) :: s(:, :), c(:, :), d(:)
    real(dp) :: a(size(s, 1) + size(c, 1), size(s, 1) + size(c, 1))
    integer :: n, i
    n = size(s, 1)
    a = 0.0_dp
    a(1:n, 1:n) = s
    a(n + 1:, 1:n) = c
    a(1:n, n + 1:) = transpose(c)
    do i = 1, size(d)
      a(n + i, n + i) = d(i)
    end do
  end function kkt

  !> 1-based full CSC pattern of the mask (rows ascending in each column).
  subroutine csc_pattern(mask, colptr, rowind)
    logical, intent(in) :: mask(:, :)
    integer, allocatable, intent(out) :: colptr(:), rowind(:)
    integer :: i, j, k
    allocate (colptr(size(mask, 2) + 1), rowind(count(mask)))
    k = 0
    colptr(1) = 1
    do j = 1, size(mask, 2)
      do i = 1, size(mask, 1)
        if (mask(i, j)) then
          k = k + 1
          rowind(k) = i
        end if
      end do
      colptr(j + 1) = k + 1
    end do
  end subroutine csc_pattern

  !> Values of the dense a in the pattern's order (stored zeros included).
  pure function csc_values(a, colptr, rowind) result(v)
    real(dp), intent(in) :: a(:, :)
    integer, intent(in) :: colptr(:), rowind(:)
    real(dp) :: v(size(rowind))
    integer :: j, k
    do j = 1, size(colptr) - 1
      do k = colptr(j), colptr(j + 1) - 1
        v(k) = a(rowind(k), j)
      end do
    end do
  end function csc_values

  !> ||b - A x|| / ||b|| with A in full CSC storage.
  pure real(dp) function csc_residual(colptr, rowind, v, x, b)
    integer, intent(in) :: colptr(:), rowind(:)
    real(dp), intent(in) :: v(:), x(:), b(:)
    real(dp) :: r(size(b))
    integer :: j, k
    r = b
    do j = 1, size(colptr) - 1
      do k = colptr(j), colptr(j + 1) - 1
        r(rowind(k)) = r(rowind(k)) - v(k) * x(j)
      end do
    end do
    csc_residual = norm2(r) / norm2(b)
  end function csc_residual

  !> Sparse LU of the contact system [S C'; C D], S = stiffness_mass(50), three constraints.
  !> Pattern: S's tridiagonal, C's entries and D's diagonal (stored even when zero), so that
  !> one analysis serves active (D_ii = 0) and inactive (C row i = 0, D_ii = 1) constraints.
  !> Tolerances: LU with partial pivoting and UMFPACK's iterative refinement is backward stable,
  !> residual ~ (small growth) * eps ~ 1e-15, so 1e-12 leaves a wide margin; the forward error
  !> is at most cond(A) * residual, cond(A) ~ cond(S) * (C S^-1 C' spread) < 1e3, hence 1e-10.
  subroutine test_kkt()
    integer, parameter :: n = 50, m = 3, nt = n + m
    type(umfpack_factor_t) :: u
    real(dp) :: s(n, n), c(m, n), a(nt, nt), zs(nt), b(nt), z(nt), z2(nt), d(m)
    real(dp) :: y(n, m + 1), sigma(m, m), lam(m), xs(n)
    real(dp), allocatable :: v(:)
    integer, allocatable :: colptr(:), rowind(:)
    logical :: mask(nt, nt), singular
    integer :: i, stat
    character(len=:), allocatable :: errmsg

    s = stiffness_mass(n)
    c = 0.0_dp
    c(1, 10) = 1.0_dp                          ! gap at node 10
    c(2, 25) = 1.0_dp; c(2, 30) = -1.0_dp      ! relative gap between nodes 25 and 30
    c(3, 40) = 0.5_dp; c(3, 41) = 1.0_dp       ! weighted gap over nodes 40, 41
    mask = kkt(s, c, [1.0_dp, 1.0_dp, 1.0_dp]) /= 0.0_dp
    call csc_pattern(mask, colptr, rowind)
    do i = 1, nt
      zs(i) = sin(0.3_dp * i) + 0.2_dp
    end do
    zs(n + 1:) = [1.5_dp, -0.7_dp, 2.0_dp]

    call check(.not. u%is_factored(), 'UMFPACK: fresh factor is not factored')
    call u%analyze(nt, colptr, rowind, stat, errmsg)
    call check(stat == STAT_OK, 'UMFPACK: KKT pattern analyzed', msg_of(errmsg))

    ! (a) all three constraints active, D = 0 (stored zeros): manufactured solution zs.
    d = 0.0_dp
    a = kkt(s, c, d)
    v = csc_values(a, colptr, rowind)
    b = matmul(a, zs)
    call u%factorize(v, stat, errmsg, singular)
    call check(stat == STAT_OK .and. .not. singular, 'UMFPACK: KKT (D = 0) factorizes', msg_of(errmsg))
    call check(u%is_factored(), 'UMFPACK: is_factored after factorize')
    call u%solve(b, z, stat, errmsg)
    call check(stat == STAT_OK, 'UMFPACK: KKT solve succeeds', msg_of(errmsg))
    call check(csc_residual(colptr, rowind, v, z, b) <= 1.0e-12_dp, 'UMFPACK: KKT relative residual <= 1e-12')
    call check(norm2(z - zs) <= 1.0e-10_dp * norm2(zs), 'UMFPACK: KKT recovers the manufactured solution')
    call u%solve(b, z2, stat, errmsg)
    call check(stat == STAT_OK .and. all(z2 == z), 'UMFPACK: second solve is bit-identical')

    ! Independent path: Schur complement by dense Cholesky (LAPACK). S Y = [C' f],
    ! (C S^-1 C') lam = C S^-1 f - g, x = S^-1 f - S^-1 C' lam. C has full row rank: SPD Schur.
    y(:, 1:m) = transpose(c)
    y(:, m + 1) = b(1:n)
    a(1:n, 1:n) = s
    call spd_solve(a(1:n, 1:n), y, stat, errmsg)
    call check(stat == STAT_OK, 'LAPACK: S Y = [C'' f]', msg_of(errmsg))
    sigma = matmul(c, y(:, 1:m))
    lam = matmul(c, y(:, m + 1)) - b(n + 1:)
    call spd_solve(sigma, lam, stat, errmsg)
    call check(stat == STAT_OK, 'LAPACK: Schur complement C S^-1 C'' is SPD', msg_of(errmsg))
    xs = y(:, m + 1) - matmul(y(:, 1:m), lam)
    call check(norm2(z(1:n) - xs) <= 1.0e-10_dp * norm2(xs), 'UMFPACK x matches the Schur complement solution')
    call check(norm2(z(n + 1:) - lam) <= 1.0e-10_dp * norm2(lam), &
               'UMFPACK multipliers match the Schur complement solution')
    call check(maxval(abs(matmul(c, z(1:n)) - b(n + 1:))) <= 1.0e-12_dp * maxval(abs(b)), &
               'UMFPACK: the constraints C x = g hold')

    ! (b) same pattern, new values: constraint 2 inactive (C row/column 2 zeroed, D_22 = 1,
    ! so lam_2 = g_2 exactly decouples), S doubled.
    c(2, :) = 0.0_dp
    d = [0.0_dp, 1.0_dp, 0.0_dp]
    a = kkt(2.0_dp * s, c, d)
    v = csc_values(a, colptr, rowind)
    b = matmul(a, zs)
    call u%factorize(v, stat, errmsg, singular)
    call check(stat == STAT_OK .and. .not. singular, 'UMFPACK: refactorization, constraint 2 inactive', &
               msg_of(errmsg))
    call u%solve(b, z, stat, errmsg)
    call check(stat == STAT_OK .and. csc_residual(colptr, rowind, v, z, b) <= 1.0e-12_dp, &
               'UMFPACK: residual <= 1e-12, constraint 2 inactive')
    call check(norm2(z - zs) <= 1.0e-10_dp * norm2(zs), 'UMFPACK: solution with constraint 2 inactive')
    call check_close(z(n + 2), b(n + 2), 1.0e-12_dp, 'UMFPACK: inactive multiplier lam_2 = g_2')

    ! Constraint 2 active again (D = 0), S doubled: still the first analysis.
    c(2, 25) = 1.0_dp; c(2, 30) = -1.0_dp
    d = 0.0_dp
    a = kkt(2.0_dp * s, c, d)
    v = csc_values(a, colptr, rowind)
    b = matmul(a, zs)
    call u%factorize(v, stat, errmsg, singular)
    call check(stat == STAT_OK .and. .not. singular, 'UMFPACK: refactorization, constraint 2 active', msg_of(errmsg))
    call u%solve(b, z, stat, errmsg)
    call check(stat == STAT_OK .and. csc_residual(colptr, rowind, v, z, b) <= 1.0e-12_dp, &
               'UMFPACK: residual <= 1e-12, constraint 2 reactivated')
    call check(norm2(z - zs) <= 1.0e-10_dp * norm2(zs), 'UMFPACK: solution with constraint 2 reactivated')

    call u%destroy()
    call check(.not. u%is_factored(), 'UMFPACK: destroyed factor is not factored')
    call u%destroy()
    call check(.true., 'UMFPACK: destroy twice is safe')
  end subroutine test_kkt

  !> (c) Two identical active constraint rows (D = 0): the KKT matrix has two equal rows, hence
  !> is singular; elimination makes the second one exactly zero, so UMFPACK must report it.
  subroutine test_umf_singular()
    integer, parameter :: n = 50, m = 2, nt = n + m
    type(umfpack_factor_t) :: u
    real(dp) :: s(n, n), c(m, n), a(nt, nt), b(nt), z(nt), zs(nt)
    real(dp), allocatable :: v(:)
    integer, allocatable :: colptr(:), rowind(:)
    logical :: singular
    integer :: i, stat
    character(len=:), allocatable :: errmsg

    s = stiffness_mass(n)
    c = 0.0_dp
    c(1, 20) = 1.0_dp; c(1, 21) = -1.0_dp
    c(2, :) = c(1, :)
    a = kkt(s, c, [1.0_dp, 1.0_dp])
    call csc_pattern(a /= 0.0_dp, colptr, rowind)
    call u%analyze(nt, colptr, rowind, stat, errmsg)
    call check(stat == STAT_OK, 'UMFPACK: pattern with repeated constraint analyzed', msg_of(errmsg))
    a = kkt(s, c, [0.0_dp, 0.0_dp])
    v = csc_values(a, colptr, rowind)
    call u%factorize(v, stat, errmsg, singular)
    call check(singular, 'UMFPACK: two identical active constraints report singular')
    call check(stat == STAT_RUN, 'UMFPACK: singular KKT gives STAT_RUN')
    call check(index(msg_of(errmsg), 'singular') > 0 .and. index(msg_of(errmsg), 'status 1') > 0, &
               'UMFPACK: errmsg names the status', msg_of(errmsg))
    call check(.not. u%is_factored(), 'UMFPACK: singular factor is not factored')
    b = 1.0_dp
    call u%solve(b, z, stat, errmsg)
    call check(stat == STAT_INPUT, 'UMFPACK: solve refused after a singular factorization')

    ! Fallback as the caller would do it: the second constraint inactive (D_22 = 1).
    a = kkt(s, c, [0.0_dp, 1.0_dp])
    a(n + 2, 1:n) = 0.0_dp
    a(1:n, n + 2) = 0.0_dp
    v = csc_values(a, colptr, rowind)
    do i = 1, nt
      zs(i) = cos(0.2_dp * i)
    end do
    b = matmul(a, zs)
    call u%factorize(v, stat, errmsg, singular)
    call check(stat == STAT_OK .and. .not. singular, 'UMFPACK: refactorization after a singular one', &
               msg_of(errmsg))
    call u%solve(b, z, stat, errmsg)
    call check(stat == STAT_OK .and. norm2(z - zs) <= 1.0e-10_dp * norm2(zs), 'UMFPACK: solve after recovery')
    call u%destroy()
  end subroutine test_umf_singular

  !> (d) Bad patterns and calls out of order give STAT_INPUT and a message, never a crash.
  subroutine test_umf_misuse()
    type(umfpack_factor_t) :: u
    real(dp) :: b(3), x(3)
    logical :: singular
    integer :: stat
    character(len=:), allocatable :: errmsg

    b = 1.0_dp
    call u%solve(b, x, stat, errmsg)
    call check(stat == STAT_INPUT, 'UMFPACK: solve before analyze is an input error')
    call u%factorize([1.0_dp], stat, errmsg, singular)
    call check(stat == STAT_INPUT .and. .not. singular, 'UMFPACK: factorize before analyze is an input error')
    call u%analyze(3, [1, 3, 2, 4], [1, 2, 3], stat, errmsg)
    call check(stat == STAT_INPUT .and. index(msg_of(errmsg), 'monotone') > 0, &
               'UMFPACK: colptr not monotone is an input error', msg_of(errmsg))
    call u%factorize([1.0_dp, 1.0_dp, 1.0_dp], stat, errmsg, singular)
    call check(stat == STAT_INPUT, 'UMFPACK: factorize after a failed analyze is an input error')
    call u%analyze(3, [1, 3, 4, 5], [2, 1, 2, 3], stat, errmsg)
    call check(stat == STAT_INPUT, 'UMFPACK: unsorted rows are an input error', msg_of(errmsg))
    call u%analyze(3, [1, 2, 3, 4], [1, 4, 3], stat, errmsg)
    call check(stat == STAT_INPUT, 'UMFPACK: row out of range is an input error', msg_of(errmsg))
    call u%analyze(3, [1, 2, 3], [1, 2], stat, errmsg)
    call check(stat == STAT_INPUT, 'UMFPACK: size(colptr) /= n + 1 is an input error', msg_of(errmsg))
    call u%analyze(3, [1, 2, 3, 5], [1, 2, 3], stat, errmsg)
    call check(stat == STAT_INPUT, 'UMFPACK: colptr(n+1) /= nnz + 1 is an input error', msg_of(errmsg))

    ! Diagonal 3 x 3 after the failures: the handle is reusable.
    call u%analyze(3, [1, 2, 3, 4], [1, 2, 3], stat, errmsg)
    call check(stat == STAT_OK, 'UMFPACK: analyze after failures', msg_of(errmsg))
    call u%factorize([1.0_dp, 2.0_dp], stat, errmsg, singular)
    call check(stat == STAT_INPUT, 'UMFPACK: values of the wrong size are an input error')
    call u%factorize([2.0_dp, 4.0_dp, 8.0_dp], stat, errmsg, singular)
    call u%solve(b, x, stat, errmsg)
    call check(stat == STAT_OK .and. all(x == [0.5_dp, 0.25_dp, 0.125_dp]), 'UMFPACK: diagonal solve is exact')
    call u%solve(b(1:2), x(1:2), stat, errmsg)
    call check(stat == STAT_INPUT, 'UMFPACK: wrong rhs size is an input error')
    call u%destroy()
  end subroutine test_umf_misuse

  !> errmsg or '' when unallocated (a successful call leaves it unallocated).
  function msg_of(errmsg) result(s)
    character(len=:), allocatable, intent(in) :: errmsg
    character(len=:), allocatable :: s
    s = ''
    if (allocated(errmsg)) s = errmsg
  end function msg_of

  function itoa(i) result(s)
    integer, intent(in) :: i
    character(len=12) :: s
    write (s, '(i0)') i
  end function itoa
end program test_cholmod_binding
