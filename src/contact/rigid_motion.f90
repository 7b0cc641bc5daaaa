!> The rigid motion an impact correction must leave alone, and the normal impulses that carry a
!> momentum (docs/contact.md, "What a correction may change").
!>
!> A frictionless contact pushes along the normals of its conditions only: it can change a body's
!> momentum along a rigid mode t only if some active row sees that mode (c_j't /= 0). Against a
!> wall of normal x the momentum along y, and the angular momentum about any point of the normal
!> through the contact, are beyond its reach. PERSIST, MASSLESS and SYMMETRIC restore the energy
!> a step lost by scaling a group's velocity; scaled about the group's motion in the rigid modes
!> its conditions leave invariant, v <- v_r + s (v - v_r), the scaling keeps every momentum the
!> contact cannot change, keeps zero normal velocities (c_j'v_r = 0), and what it changes in the
!> other modes is the momentum of normal impulses at the contact rows (normal_impulses).
!>
!> Dense kernels on the few (<= MAX_RIGID: 3 in 2D, 6 in 3D) rigid modes of a group; no allocation.
module rigid_motion
  use kinds, only: dp
  use lapack_pure, only: dsyev
  implicit none
  private
  public :: invariant_rigid_motion, normal_impulses, MAX_RIGID

  !> The most rigid modes a model has: 3 in 2D (x, y, the rotation about z), 6 in 3D (those, then
  !> z and the rotations about x and y).
  integer, parameter :: MAX_RIGID = 6

  !> A mode whose M-norm is below MODE_RTOL x the largest (relative, after scaling to unit
  !> diagonal) is dependent on the others on this group (a lone node's rotation): dropped.
  real(dp), parameter :: MODE_RTOL = 1.0e-10_dp
  !> A row sees a normalized mode when |c_j'q| / (|c_j| max|q|) exceeds INVARIANT_TOL: the
  !> invariance test (exact invariance gives round-off, 1e-16).
  real(dp), parameter :: INVARIANT_TOL = 1.0e-9_dp

contains

  !> The M-orthogonal projection of a group's velocity on the rigid modes its active conditions
  !> leave invariant. Input over the nm free modes t_k of the group: g = T'M T, p = T'M v,
  !> e(j, k) = c_j't_k for its n active rows, cnorm(j) = |c_j|, rmax(k) = max |t_k| over the
  !> group's equations. Out: the motion v_r = Σ a_k t_k and its kinetic energy tcm = ½ v_r'M v_r.
  !> The modes are made M-orthonormal (eigenvectors of g scaled to unit diagonal; dependent
  !> ones dropped), then the null space of the normalized rows e is taken (eigenvectors of
  !> B'B with eigenvalue below INVARIANT_TOL² x n): v_r is v's component on it. a = 0 when no
  !> mode is invariant (a wall seen by every mode: the scaling is about zero).
  pure subroutine invariant_rigid_motion(g, p, e, cnorm, rmax, a, tcm)
    real(dp), intent(in) :: g(:, :), p(:), e(:, :), cnorm(:), rmax(:)
    real(dp), intent(out) :: a(:), tcm
    real(dp) :: d(MAX_RIGID), gs(MAX_RIGID, MAX_RIGID), lam(MAX_RIGID), t(MAX_RIGID, MAX_RIGID), b(MAX_RIGID), &
      bb(MAX_RIGID, MAX_RIGID), mu(MAX_RIGID), work(64), scale(MAX_RIGID), pi
    integer :: nm, n, k, l, r, j, q, info
    nm = size(p)
    n = size(e, 1)
    a = 0.0_dp
    tcm = 0.0_dp
    if (nm == 0) return
    ! M-orthonormal modes: g scaled to unit diagonal, its eigenvectors, t(:, 1:r) = D V Λ^-½.
    do k = 1, nm
      d(k) = 0.0_dp
      if (g(k, k) > 0.0_dp) d(k) = 1.0_dp / sqrt(g(k, k))
    end do
    do l = 1, nm
      do k = 1, nm
        gs(k, l) = d(k) * g(k, l) * d(l)
      end do
    end do
    call dsyev('V', 'U', nm, gs, MAX_RIGID, lam, work, size(work), info)
    if (info /= 0) return
    r = 0
    do l = 1, nm
      if (.not. (lam(l) > MODE_RTOL * maxval(lam(1:nm)))) cycle
      r = r + 1
      t(1:nm, r) = d(1:nm) * gs(1:nm, l) / sqrt(lam(l))
    end do
    if (r == 0) return
    ! The rows against the orthonormal modes, each normalized: B'B (r x r).
    ! One scale for every column (the largest nodal speed of a unit mode), so that B's null
    ! vectors stay orthonormal in the M-orthonormal basis.
    do l = 1, r
      scale(l) = sum(abs(t(1:nm, l)) * rmax(1:nm))
    end do
    scale(1:r) = maxval(scale(1:r))
    bb = 0.0_dp
    do j = 1, n
      if (.not. (cnorm(j) > 0.0_dp)) cycle
      do l = 1, r
        b(l) = dot_product(e(j, 1:nm), t(1:nm, l)) / (cnorm(j) * max(scale(l), tiny(1.0_dp)))
      end do
      do l = 1, r
        bb(1:r, l) = bb(1:r, l) + b(1:r) * b(l)
      end do
    end do
    if (n > 0) then
      call dsyev('V', 'U', r, bb, MAX_RIGID, mu, work, size(work), info)
      if (info /= 0) return
    else                                         ! (no row: every mode invariant)
      bb = 0.0_dp
      do l = 1, r
        bb(l, l) = 1.0_dp
      end do
      mu = 0.0_dp
    end if
    ! The invariant directions q = t N: v_r = Σ_q (q'M v) q. An eigenvector of B'B is invariant
    ! when every normalized row sees it below INVARIANT_TOL, checked on the rows themselves (the
    ! eigenvalue alone carries eps x |B'B| of round-off).
    do q = 1, r
      if (mu(q) > INVARIANT_TOL * sqrt(real(max(n, 1), dp))) cycle
      if (.not. (row_residual(e, cnorm, t, scale, nm, r, bb(1:r, q)) <= INVARIANT_TOL)) cycle
      pi = 0.0_dp
      do k = 1, nm
        pi = pi + dot_product(t(k, 1:r), bb(1:r, q)) * p(k)
      end do
      do k = 1, nm
        a(k) = a(k) + dot_product(t(k, 1:r), bb(1:r, q)) * pi
      end do
      tcm = tcm + 0.5_dp * pi * pi
    end do
  end subroutine invariant_rigid_motion

  !> max_j |c_j'q| / (|c_j| max|q|) for the direction q = Σ_l w(l) t(:, l) (normalized as in
  !> invariant_rigid_motion): how much the rows see it.
  pure real(dp) function row_residual(e, cnorm, t, scale, nm, r, w) result(res)
    real(dp), intent(in) :: e(:, :), cnorm(:), t(:, :), scale(:), w(:)
    integer, intent(in) :: nm, r
    real(dp) :: b
    integer :: j, l
    res = 0.0_dp
    do j = 1, size(e, 1)
      if (.not. (cnorm(j) > 0.0_dp)) cycle
      b = 0.0_dp
      do l = 1, r
        b = b + w(l) * dot_product(e(j, 1:nm), t(1:nm, l)) / (cnorm(j) * max(scale(l), tiny(1.0_dp)))
      end do
      res = max(res, abs(b))
    end do
  end function row_residual

  !> The impulses z (n) along the rows c_j of least norm whose momenta along the nm rigid modes
  !> are dm: e'z = dm with e(j, k) = c_j't_k. dm lies in the range of e' when it is the momentum
  !> a scaling about invariant_rigid_motion's v_r gave (what the rows cannot see is unchanged);
  !> z = e (e'e)⁺ dm, the pseudo-inverse of the nm x nm e'e by its eigenvectors (cut off relative
  !> to the largest, MODE_RTOL, and to what a row seeing a mode gives, INVARIANT_TOL x escale: the
  !> directions every row leaves invariant carry no impulse). resid = |e'z - dm| / max |dm| (0
  !> when dm = 0; 1 when no row sees any mode).
  pure subroutine normal_impulses(e, dm, escale, z, resid)
    real(dp), intent(in) :: e(:, :), dm(:)
    real(dp), intent(in) :: escale             !< max_j |c_j| x max_k max|t_k|: what a row seeing a mode gives
    real(dp), intent(out) :: z(:), resid
    real(dp) :: ee(MAX_RIGID, MAX_RIGID), lam(MAX_RIGID), y(MAX_RIGID), work(64), c, scale
    integer :: nm, n, k, l, info
    nm = size(dm)
    n = size(e, 1)
    z = 0.0_dp
    resid = 0.0_dp
    if (nm == 0 .or. n == 0) return
    scale = maxval(abs(dm))
    if (.not. (scale > 0.0_dp)) return
    do l = 1, nm
      do k = 1, nm
        ee(k, l) = dot_product(e(1:n, k), e(1:n, l))
      end do
    end do
    call dsyev('V', 'U', nm, ee, MAX_RIGID, lam, work, size(work), info)
    if (info /= 0) then
      resid = huge(1.0_dp)
      return
    end if
    y = 0.0_dp
    do l = 1, nm                                 ! (directions no row sees, to round-off: left out)
      if (.not. (lam(l) > max(MODE_RTOL * maxval(lam(1:nm)), (INVARIANT_TOL * escale)**2))) cycle
      c = dot_product(ee(1:nm, l), dm(1:nm)) / lam(l)
      y(1:nm) = y(1:nm) + c * ee(1:nm, l)
    end do
    do k = 1, n                                  ! (a loop: matmul may take a temporary)
      z(k) = dot_product(e(k, 1:nm), y(1:nm))
    end do
    do k = 1, nm
      resid = max(resid, abs(dot_product(e(1:n, k), z(1:n)) - dm(k)))
    end do
    resid = resid / scale
  end subroutine normal_impulses
end module rigid_motion
