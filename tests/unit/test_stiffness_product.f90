!> stiffness_product: Bσ = K0 u with each body's kernel modes taken care of. Three QUAD4 plates on
!> one pattern: a free plate far from the origin (translations and rotation are kernel modes), a
!> plate on rollers (only the x translation is), a clamped plate (none), and a free node (no
!> stiffness). Against K0 applied to the deformation alone (exact arithmetic: the rigid part
!> gives nothing): the forces, their net force and moment, the strain energy.
program test_stiffness_product
  use kinds, only: dp
  use testing, only: check, check_close, test_summary
  use errors, only: STAT_OK
  use element_traits, only: ET_QUAD4
  use section, only: section_t
  use elements, only: elem_elastic_d, elem_stiffness
  use sparse_matrix, only: sym_csc_t
  use stiffness_product, only: k0_product_t
  implicit none

  integer, parameter :: NX = 6, NY = 4, NPLATE = 3
  integer, parameter :: NNP = (NX + 1) * (NY + 1)      ! nodes per plate
  integer, parameter :: NNODE = NPLATE * NNP + 1       ! + the free node
  real(dp), parameter :: X0(NPLATE) = [1000.0_dp, 0.0_dp, 5.0_dp], Y0(NPLATE) = [-300.0_dp, 0.0_dp, 3.0_dp]
  type(sym_csc_t) :: pat
  type(k0_product_t) :: k0p
  real(dp), allocatable :: kval(:), x(:, :), u(:), ud(:), rig(:), f(:), fref(:), fbare(:)
  integer, allocatable :: eqn(:, :), body(:), eptr(:), edofs(:)
  integer :: neq
  logical :: held(4, NPLATE + 1)

  call build()
  ! The supports' structural answer (assembly's held_modes): rollers hold UY and the rotation, the
  ! clamp everything.
  held = .false.
  held(2:3, 2) = .true.
  held(1:3, 3) = .true.
  call k0p%setup(pat, kval, eqn, x, body, held)
  call check(k0p%active(), 'set up: active')
  call test_translation()
  call test_rotation()
  call test_clamped_bitwise()
  call test_soft_spring()
  call test_summary('stiffness_product')

contains

  !> Three plates of NX x NY unit squares (E = 2e11, nu = 0.3, plane strain) at (X0, Y0): plate 1
  !> free, plate 2 on rollers (UY fixed along its bottom edge), plate 3 clamped along its left
  !> edge; node NNODE alone.
  subroutine build()
    type(section_t) :: sec
    real(dp) :: d(4, 4), ke(16, 16), xe(2, 4)
    integer :: p, i, j, n, e, a, stat, nel, k
    integer, allocatable :: econn(:, :)
    character(len=:), allocatable :: errmsg
    allocate (x(2, NNODE), eqn(3, NNODE))
    eqn = 0
    neq = 0
    do p = 1, NPLATE
      do j = 0, NY
        do i = 0, NX
          n = (p - 1) * NNP + j * (NX + 1) + i + 1
          x(:, n) = [X0(p) + i, Y0(p) + j]
          do a = 1, 2
            if ((p == 2 .and. j == 0 .and. a == 2) .or. (p == 3 .and. i == 0)) then
              eqn(a, n) = -1
            else
              neq = neq + 1
              eqn(a, n) = neq
            end if
          end do
        end do
      end do
    end do
    x(:, NNODE) = [-50.0_dp, 7.0_dp]
    eqn(1:2, NNODE) = [neq + 1, neq + 2]
    neq = neq + 2
    allocate (body(neq))
    do n = 1, NNODE
      do a = 1, 2
        if (eqn(a, n) > 0) body(eqn(a, n)) = min((n - 1) / NNP + 1, NPLATE + 1)
      end do
    end do
    nel = NPLATE * NX * NY
    allocate (eptr(nel + 1), edofs(8 * nel), econn(4, nel))
    e = 0
    do p = 1, NPLATE
      do j = 0, NY - 1
        do i = 0, NX - 1
          e = e + 1
          n = (p - 1) * NNP + j * (NX + 1) + i + 1
          econn(:, e) = [n, n + 1, n + NX + 2, n + NX + 1]
          eptr(e) = 8 * (e - 1) + 1
          do a = 1, 4
            edofs(8 * (e - 1) + 2 * a - 1:8 * (e - 1) + 2 * a) = max(eqn(1:2, econn(a, e)), 0)
          end do
        end do
      end do
    end do
    eptr(nel + 1) = 8 * nel + 1
    call pat%build(neq, eptr, edofs, stat, errmsg)
    call check(stat == STAT_OK, 'pattern built')
    allocate (kval(pat%nnz))
    kval = 0.0_dp
    call elem_elastic_d(ET_QUAD4, 2.0e11_dp, 0.3_dp, sec, d)
    do e = 1, nel
      do k = 1, 4
        xe(:, k) = x(:, econn(k, e))
      end do
      call elem_stiffness(ET_QUAD4, xe, sec, d, ke)
      call pat%add_element(kval, edofs(eptr(e):eptr(e + 1) - 1), ke(1:8, 1:8), stat)
    end do
    allocate (u(neq), ud(neq), rig(neq), f(neq), fref(neq), fbare(neq))
  end subroutine build

  !> A smooth deformation of amplitude 1e-6 m on every equation.
  subroutine deformation()
    integer :: n, a
    do n = 1, NNODE
      do a = 1, 2
        if (eqn(a, n) > 0) ud(eqn(a, n)) = 1.0e-6_dp * sin(0.37_dp * x(1, n) + 0.21_dp * a) * cos(0.23_dp * x(2, n))
      end do
    end do
  end subroutine deformation

  !> Net force x, y and moment about the centroid of plate p's free equations.
  function resultant(p, g) result(r)
    integer, intent(in) :: p
    real(dp), intent(in) :: g(:)
    real(dp) :: r(3), c(2)
    integer :: n, n0
    n0 = (p - 1) * NNP
    c = sum(x(:, n0 + 1:n0 + NNP), dim=2) / NNP
    r = 0.0_dp
    do n = n0 + 1, n0 + NNP
      r(1) = r(1) + g(eqn(1, n))
      r(2) = r(2) + g(eqn(2, n))
      r(3) = r(3) + (x(1, n) - c(1)) * g(eqn(2, n)) - (x(2, n) - c(2)) * g(eqn(1, n))
    end do
  end function resultant

  !> Plate 1 translated by 1e3 m, plate 2 slid by 1e3 m along its rollers: the product on the
  !> shifted u is K0 of the deformation to round-off (the bare product rounds at 1e-6 of it),
  !> and the energy is the deformation's.
  subroutine test_translation()
    real(dp) :: energy, eref, scale
    integer :: n
    call deformation()
    rig = 0.0_dp
    do n = 1, 2 * NNP
      if (n <= NNP) then
        rig(eqn(1, n)) = 1.0e3_dp
        rig(eqn(2, n)) = -2.0e3_dp
      else if (eqn(1, n) > 0) then
        rig(eqn(1, n)) = 1.0e3_dp
      end if
    end do
    u = ud + rig
    ud = u - rig                               ! the deformation u holds (rounded to its ulp)
    call pat%matvec(kval, ud, fref)
    call pat%matvec(kval, u, fbare)
    call k0p%apply(pat, kval, u, f, energy)
    eref = 0.5_dp * dot_product(ud, fref)
    scale = maxval(abs(fref))
    call check(maxval(abs(f - fref)) <= 1.0e-12_dp * scale, 'translated plates: K0 u = K0 u_deformation to 1e-12', &
      'max error / max |f| = ' // r2s(maxval(abs(f - fref)) / scale) // ' (bare product: ' // &
      r2s(maxval(abs(fbare - fref)) / scale) // ')')
    call check_close(energy, eref, 1.0e-12_dp, 'translated plates: strain energy of the deformation')
    call check(all(abs(resultant(1, f)) <= 1.0e-13_dp * scale * [1.0_dp, 1.0_dp, 10.0_dp]), &
      'free plate: net force and moment zero', r2s(maxval(abs(resultant(1, f)))))
    call check(all(pack(f, body == NPLATE + 1) == 0.0_dp), 'free node: no force')
  end subroutine test_translation

  !> Plate 1 also turned by 1e-3 rad about the origin (1000 m away: the rotation is not
  !> shifted out, only the product projected): forces to the rounding of that displacement, net
  !> force and moment zero to round-off of the forces (bare product: its rounding's resultant).
  subroutine test_rotation()
    real(dp) :: energy, scale, th
    integer :: n
    call deformation()
    rig = 0.0_dp
    th = 1.0e-3_dp
    do n = 1, NNP
      rig(eqn(1, n)) = -th * x(2, n) + 1.0_dp
      rig(eqn(2, n)) = th * x(1, n) - 3.0_dp
    end do
    u = ud + rig
    ud = u - rig
    call pat%matvec(kval, ud, fref)
    call pat%matvec(kval, u, fbare)
    call k0p%apply(pat, kval, u, f, energy)
    scale = maxval(abs(fref))
    call check(maxval(abs(f - fref)) <= 1.0e-9_dp * scale, &
      'turned plate: K0 u = K0 u_deformation to 1e-9 (the rounding of the turned u)', &
      'max error / max |f| = ' // r2s(maxval(abs(f - fref)) / scale) // ' (bare product: ' // &
      r2s(maxval(abs(fbare - fref)) / scale) // ')')
    call check(all(abs(resultant(1, f)) <= 1.0e-13_dp * scale * [1.0_dp, 1.0_dp, 10.0_dp]), &
      'turned plate: net force and moment zero', r2s(maxval(abs(resultant(1, f)))) // ' (bare product: ' // &
      r2s(maxval(abs(resultant(1, fbare)))) // ')')
  end subroutine test_rotation

  !> The clamped plate has no kernel mode: its rows are the bare product's, bit for bit.
  subroutine test_clamped_bitwise()
    real(dp) :: energy
    call deformation()
    u = ud + 1.0_dp
    call pat%matvec(kval, u, fbare)
    call k0p%apply(pat, kval, u, f, energy)
    call check(all(pack(f, body == 3) == pack(fbare, body == 3)), 'clamped plate: the bare product bit for bit')
    call check(any(pack(f, body == 1) /= pack(fbare, body == 1)), 'free plate: its rigid part taken out (not the bare product)')
  end subroutine test_clamped_bitwise

  !> Plate 1 on a spring to a support along x (its mode x held, held_modes' answer). At 10 N/m
  !> against a plate of ~1e11 N/m K0's own test sees a kernel (1e-10 relative): a near-mechanism,
  !> on which K0 u would round at eps |K0| |u| of an unbounded drift, so the product stays off. At
  !> 1e9 N/m it is on, and the spring's force is kept: the net force of the plate translated by
  !> 2 m is k_s u (to the rounding of K0 u, 1e-4 N for 2 m).
  subroutine test_soft_spring()
    type(k0_product_t) :: soft, stiff
    real(dp), allocatable :: ks(:)
    logical :: h(4, NPLATE + 1)
    real(dp) :: energy, r(3)
    integer :: i, kd
    kd = pat%colptr(eqn(1, 1) + 1) - 1           ! the diagonal of node 1's UX
    h = held
    h(1, 1) = .true.
    ks = kval
    ks(kd) = ks(kd) + 10.0_dp
    call soft%setup(pat, ks, eqn, x, body, h)
    call check(.not. soft%active(), 'plate on a 10 N/m spring: a near-mechanism, the product is off')
    ks(kd) = kval(kd) + 1.0e9_dp
    call stiff%setup(pat, ks, eqn, x, body, h)
    call check(stiff%active(), 'plate on a 1e9 N/m spring: the product is on')
    u = 0.0_dp
    do i = 1, NNP
      u(eqn(1, i)) = 2.0_dp                    ! plate 1 translated by 2 m along x
    end do
    call stiff%apply(pat, ks, u, f, energy)
    r = resultant(1, f)
    call check_close(r(1), 2.0e9_dp, 1.0e-12_dp, 'plate on a 1e9 N/m spring, translated: net force = k_s u')
    call check_close(energy, 0.5_dp * 1.0e9_dp * 4.0_dp, 1.0e-12_dp, 'plate on a 1e9 N/m spring: energy = k_s u^2 / 2')
  end subroutine test_soft_spring

  function r2s(v) result(s)
    real(dp), intent(in) :: v
    character(len=:), allocatable :: s
    character(len=24) :: buf
    write (buf, '(es10.3)') v
    s = trim(adjustl(buf))
  end function r2s
end program test_stiffness_product
