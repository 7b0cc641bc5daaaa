!> The logarithmic (Hencky) strain of a plane-strain point, for `MODEL … KINEMATICS LARGE STRAIN
!> LOG` (docs/large-displacements.md, "Large plastic strains"): ℓ = ½ ln C, C = F'F = I + 2E, with
!> its derivative P = dℓ/dE, so that the stress T conjugate to ℓ (T : dℓ = S : dE) gives the second
!> Piola-Kirchhoff stress S = P' T. In the eigenbasis of E (eigenvalues e1, e2):
!>   ℓ_ii = ½ ln(1 + 2 e_i),   dℓ_ii = dE_ii / (1 + 2 e_i),   dℓ_12 = g dE_12,
!>   g = (ℓ_11 - ℓ_22)/(e1 - e2) (the divided difference; 1/(1 + 2 e) when e1 = e2),
!> every term written without cancellation (a small strain keeps its digits). C is block-diagonal,
!> so the in-plane ℓ does not depend on the thickness's stretch: in plane strain ℓ_zz = 0; in plane
!> stress the law finds ℓ_zz = ln λ_z with T_zz = 0, as it finds ε_zz in small strain. Vectors are Voigt [xx, yy, zz, 2xy] for
!> strains and [xx, yy, zz, xy] for stresses, as the small-strain laws take them.
module log_strain
  use kinds, only: dp
  use law_hyperelastic, only: log1p_
  use lapack_pure, only: dsyev, dpotrf
  implicit none
  private
  public :: hencky_strain, log_tangent, log_curvature, positive_inplane, positive_all

contains

  !> ℓ (Voigt) and P (4 x 4, dℓ = P dE) at the Green-Lagrange strain e (Voigt; e(3) the hoop strain of
  !> an axisymmetric point, 0 in plane strain). ok is
  !> false when C is singular or not positive (an element turned inside out: the caller reports it).
  pure subroutine hencky_strain(e, l, p, ok)
    real(dp), intent(in) :: e(4)
    real(dp), intent(out) :: l(4), p(4, 4)
    logical, intent(out) :: ok
    real(dp) :: m, d, exy, r, ev(2), c, s, lam(2), g, q(3, 3), qi(3, 3), dg(3)
    integer :: i
    exy = 0.5_dp * e(4)
    m = 0.5_dp * (e(1) + e(2))
    d = 0.5_dp * (e(1) - e(2))
    r = hypot(d, exy)
    ev = [m + r, m - r]
    ok = all(1.0_dp + 2.0_dp * ev > 0.0_dp) .and. 1.0_dp + 2.0_dp * e(3) > 0.0_dp
    l = 0.0_dp
    p = 0.0_dp
    p(3, 3) = 1.0_dp
    if (.not. ok) return
    ! The hoop (or thickness) stretch, an eigenvalue of its own: ℓ_zz = ½ ln(1 + 2 E_zz) (0 in plane strain).
    l(3) = 0.5_dp * log1p_(2.0_dp * e(3))
    p(3, 3) = 1.0_dp / (1.0_dp + 2.0_dp * e(3))
    if (r > 0.0_dp) then
      c = cos(0.5_dp * atan2(exy, d))
      s = sin(0.5_dp * atan2(exy, d))
    else
      c = 1.0_dp
      s = 0.0_dp
    end if
    lam = [(0.5_dp * log1p_(2.0_dp * ev(i)), i = 1, 2)]
    ! g = (lam1 - lam2)/(ev1 - ev2) = log1p(2(ev1 - ev2)/(1 + 2 ev2)) / (2 (ev1 - ev2)).
    if (r > 0.0_dp) then
      g = log1p_(4.0_dp * r / (1.0_dp + 2.0_dp * ev(2))) / (4.0_dp * r)
    else
      g = 1.0_dp / (1.0_dp + 2.0_dp * ev(2))
    end if
    ! ℓ = R diag(lam) R' with ℓ_xy = g E_xy (no cancellation of lam1 - lam2).
    l(1) = c * c * lam(1) + s * s * lam(2)
    l(2) = s * s * lam(1) + c * c * lam(2)
    l(4) = 2.0_dp * g * exy
    ! P = Q(-t) diag(1/(1 + 2 e1), 1/(1 + 2 e2), g) Q(t), Q(t) the Voigt strain rotation into the
    ! eigenbasis (engineering shear).
    q = strain_rotation(c, s)
    qi = strain_rotation(c, -s)
    dg = [1.0_dp / (1.0_dp + 2.0_dp * ev(1)), 1.0_dp / (1.0_dp + 2.0_dp * ev(2)), g]
    do i = 1, 3
      q(i, :) = dg(i) * q(i, :)
    end do
    q = matmul(qi, q)
    p([1, 2, 4], [1, 2, 4]) = q
  end subroutine hencky_strain

  !> The material tangent on E of a point on the log strain: dS/dE = P' D P + T : d²ℓ/dE² (D the
  !> law's tangent on ℓ, in dm; P = dℓ/dE, p), the second term by central differences of P at
  !> fixed T (step 1e-5 of the smallest stretch², error ~1e-10 of T). ℓ is concave in E, so under
  !> tension that term softens: without it Newton's iteration converges linearly (the spinning
  !> square of tests/scenes/large_log left 1.2e-10 of E in the balance). The in-plane block is
  !> symmetrized and kept to its positive part: the iteration matrix must stay positive definite
  !> (as the geometric terms leave compression out).
  !> axi (AXISYMMETRIC): the hoop row and column take part (the 4 x 4 is kept to its positive part).
  pure subroutine log_tangent(e, t, p, dm, axi)
    real(dp), intent(in) :: e(4), t(4), p(4, 4)
    real(dp), intent(inout) :: dm(4, 4)
    logical, intent(in) :: axi
    real(dp) :: g(4, 4), a(3, 3), a4(4, 4)
    integer, parameter :: ip(3) = [1, 2, 4]
    dm = matmul(transpose(p), matmul(dm, p))
    call log_curvature(e, t, g)
    if (axi) then
      a4 = dm + 0.5_dp * (g + transpose(g))
      call positive_all(a4, dm)
      return
    end if
    a = dm(ip, ip) + 0.5_dp * (g(ip, ip) + transpose(g(ip, ip)))
    call positive_inplane(a, dm)
  end subroutine log_tangent

  !> The symmetric 4 x 4 a (on E, the hoop row included) kept to its positive part, into dm; a failed
  !> eigensolve leaves dm as it was. A positive definite a (its Cholesky factorization succeeds: the
  !> common case, an elastic or hardening point) is its own positive part, without the eigensolve.
  pure subroutine positive_all(a, dm)
    real(dp), intent(inout) :: a(4, 4)
    real(dp), intent(inout) :: dm(4, 4)
    real(dp) :: w(4), work(24), c(4, 4)
    integer :: info, i
    a = 0.5_dp * (a + transpose(a))
    c = a
    call dpotrf('U', 4, c, 4, info)
    if (info == 0) then
      dm = a
      return
    end if
    call dsyev('V', 'U', 4, a, 4, w, work, size(work), info)
    if (info /= 0) return
    dm = 0.0_dp
    do i = 1, 4
      if (w(i) > 0.0_dp) dm = dm + w(i) * spread(a(:, i), 2, 4) * spread(a(:, i), 1, 4)
    end do
  end subroutine positive_all

  !> g = T : d²ℓ/dE² (4 x 4 on E, not yet symmetric), by central differences of P at fixed T (step
  !> 1e-5 of the smallest stretch²): the part of dS/dE that the log map's curvature gives.
  pure subroutine log_curvature(e, t, g)
    real(dp), intent(in) :: e(4), t(4)
    real(dp), intent(out) :: g(4, 4)
    real(dp) :: dl, l(4), pp(4, 4), pm(4, 4), ep(4), smin
    integer :: k
    logical :: okp, okm
    g = 0.0_dp
    smin = 1.0_dp + (e(1) + e(2)) - hypot(e(1) - e(2), e(4))      ! 1 + 2 (smallest eigenvalue of E)
    dl = 1.0e-5_dp * min(1.0_dp, max(smin, 0.0_dp))
    do k = 1, 4
      if (k == 3 .or. dl <= 0.0_dp) cycle
      ep = e
      ep(k) = e(k) + dl
      call hencky_strain(ep, l, pp, okp)
      ep(k) = e(k) - dl
      call hencky_strain(ep, l, pm, okm)
      if (okp .and. okm) g(:, k) = matmul(t, pp - pm) / (2.0_dp * dl)
    end do
    ! The hoop (thickness) stretch: d²ℓ_zz/dE_zz² = -2/(1 + 2 E_zz)² (only an axisymmetric point's
    ! B has a hoop row to carry it).
    if (1.0_dp + 2.0_dp * e(3) > 0.0_dp) g(3, 3) = -2.0_dp * t(3) / (1.0_dp + 2.0_dp * e(3))**2
  end subroutine log_curvature

  !> The in-plane block a (xx, yy, xy rows of a 4 x 4 on E) symmetrized and kept to its positive
  !> part, into dm(ip, ip) (the rest of dm untouched); a failed eigensolve leaves dm as it was. A
  !> positive definite a is its own positive part (as in positive_all).
  pure subroutine positive_inplane(a, dm)
    real(dp), intent(inout) :: a(3, 3)
    real(dp), intent(inout) :: dm(4, 4)
    real(dp) :: w(3), work(16), c(3, 3)
    integer :: info, i
    integer, parameter :: ip(3) = [1, 2, 4]
    a = 0.5_dp * (a + transpose(a))
    c = a
    call dpotrf('U', 3, c, 3, info)
    if (info == 0) then
      dm(ip, ip) = a
      return
    end if
    call dsyev('V', 'U', 3, a, 3, w, work, size(work), info)
    if (info /= 0) return
    dm(ip, ip) = 0.0_dp
    do i = 1, 3
      if (w(i) > 0.0_dp) dm(ip, ip) = dm(ip, ip) + w(i) * spread(a(:, i), 2, 3) * spread(a(:, i), 1, 3)
    end do
  end subroutine positive_inplane

  !> Voigt (xx, yy, 2xy) strain components in the frame turned by the angle (c, s).
  pure function strain_rotation(c, s) result(q)
    real(dp), intent(in) :: c, s
    real(dp) :: q(3, 3)
    q(1, :) = [c * c, s * s, c * s]
    q(2, :) = [s * s, c * c, -c * s]
    q(3, :) = [-2.0_dp * c * s, 2.0_dp * c * s, c * c - s * s]
  end function strain_rotation

end module log_strain
