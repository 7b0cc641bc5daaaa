!> The closest point of a solid's face to a node (GAP … FACES, node-to-face contact in 3D): the
!> face's shape functions N(ξ, η) (TRI3, QUAD4, TRI6, QUAD8: corners counter-clockwise seen from
!> outside, then the mid-edge nodes 1-2, 2-3, 3-1 [, 3-4, 4-1]), the foot of the normal from the
!> node by Gauss-Newton on (ξ, η), and the outward unit normal there, x_ξ × x_η / |x_ξ × x_η|.
module face_projection
  use kinds, only: dp
  implicit none
  private
  public :: face_shape, project_on_face

  integer, parameter :: MAX_ITER = 30
  real(dp), parameter :: XI_TOL = 1.0e-14_dp

contains

  !> N(1:nfn) and dN/dξ, dN/dη at (xi, eta): triangles on ξ, η >= 0, ξ + η <= 1; quadrilaterals on
  !> [-1, 1]² (QUAD8: serendipity).
  pure subroutine face_shape(nfn, xi, eta, n, dn)
    integer, intent(in) :: nfn
    real(dp), intent(in) :: xi, eta
    real(dp), intent(out) :: n(8), dn(2, 8)
    real(dp), parameter :: sx(4) = [-1.0_dp, 1.0_dp, 1.0_dp, -1.0_dp], sy(4) = [-1.0_dp, -1.0_dp, 1.0_dp, 1.0_dp]
    real(dp) :: l1
    integer :: k
    n = 0.0_dp
    dn = 0.0_dp
    select case (nfn)
    case (3)
      n(1:3) = [1.0_dp - xi - eta, xi, eta]
      dn(:, 1:3) = reshape([-1.0_dp, -1.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 1.0_dp], [2, 3])
    case (6)
      l1 = 1.0_dp - xi - eta
      n(1:6) = [l1 * (2 * l1 - 1), xi * (2 * xi - 1), eta * (2 * eta - 1), 4 * l1 * xi, 4 * xi * eta, 4 * eta * l1]
      dn(1, 1:6) = [1 - 4 * l1, 4 * xi - 1, 0.0_dp, 4 * (l1 - xi), 4 * eta, -4 * eta]
      dn(2, 1:6) = [1 - 4 * l1, 0.0_dp, 4 * eta - 1, -4 * xi, 4 * xi, 4 * (l1 - eta)]
    case (4)
      do k = 1, 4
        n(k) = 0.25_dp * (1 + sx(k) * xi) * (1 + sy(k) * eta)
        dn(1, k) = 0.25_dp * sx(k) * (1 + sy(k) * eta)
        dn(2, k) = 0.25_dp * sy(k) * (1 + sx(k) * xi)
      end do
    case (8)
      do k = 1, 4                                ! corners
        n(k) = 0.25_dp * (1 + sx(k) * xi) * (1 + sy(k) * eta) * (sx(k) * xi + sy(k) * eta - 1)
        dn(1, k) = 0.25_dp * sx(k) * (1 + sy(k) * eta) * (2 * sx(k) * xi + sy(k) * eta)
        dn(2, k) = 0.25_dp * sy(k) * (1 + sx(k) * xi) * (sx(k) * xi + 2 * sy(k) * eta)
      end do
      n(5) = 0.5_dp * (1 - xi * xi) * (1 - eta)          ! mid-edges 1-2, 2-3, 3-4, 4-1
      dn(:, 5) = [-xi * (1 - eta), -0.5_dp * (1 - xi * xi)]
      n(6) = 0.5_dp * (1 + xi) * (1 - eta * eta)
      dn(:, 6) = [0.5_dp * (1 - eta * eta), -eta * (1 + xi)]
      n(7) = 0.5_dp * (1 - xi * xi) * (1 + eta)
      dn(:, 7) = [-xi * (1 + eta), 0.5_dp * (1 - xi * xi)]
      n(8) = 0.5_dp * (1 - xi) * (1 - eta * eta)
      dn(:, 8) = [-0.5_dp * (1 - eta * eta), -eta * (1 - xi)]
    end select
  end subroutine face_shape

  !> The foot of the normal from xb on the face of nodes xf(:, 1:nfn): its parameters, the weights
  !> w = N(ξ, η), the outward unit normal there, the signed distance dist = normal·(xb - x(ξ, η))
  !> and whether the foot is on the face (inside, to tol in the parameters). ok = .false. where
  !> Gauss-Newton does not settle or the face is degenerate.
  pure subroutine project_on_face(nfn, xf, xb, tol, w, normal, dist, inside, ok)
    integer, intent(in) :: nfn
    real(dp), intent(in) :: xf(:, :), xb(3), tol
    real(dp), intent(out) :: w(8), normal(3), dist
    logical, intent(out) :: inside, ok
    real(dp) :: xi, eta, n(8), dn(2, 8), x(3), t1(3), t2(3), a(2, 2), r(2), det, d(2)
    integer :: it
    logical :: tri
    tri = nfn == 3 .or. nfn == 6
    xi = merge(1.0_dp / 3.0_dp, 0.0_dp, tri)
    eta = xi
    ok = .false.
    inside = .false.
    w = 0.0_dp
    normal = 0.0_dp
    dist = 0.0_dp
    do it = 1, MAX_ITER
      call face_shape(nfn, xi, eta, n, dn)
      x = matmul(xf(:, 1:nfn), n(1:nfn))
      t1 = matmul(xf(:, 1:nfn), dn(1, 1:nfn))
      t2 = matmul(xf(:, 1:nfn), dn(2, 1:nfn))
      a = reshape([dot_product(t1, t1), dot_product(t1, t2), dot_product(t1, t2), dot_product(t2, t2)], [2, 2])
      r = [dot_product(t1, xb - x), dot_product(t2, xb - x)]
      det = a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)
      if (.not. det > 0.0_dp) return
      d = [a(2, 2) * r(1) - a(1, 2) * r(2), a(1, 1) * r(2) - a(2, 1) * r(1)] / det
      xi = xi + d(1)
      eta = eta + d(2)
      if (maxval(abs(d)) <= XI_TOL) then
        ok = .true.
        exit
      end if
      if (abs(xi) > 10.0_dp .or. abs(eta) > 10.0_dp) return      ! (far outside: not this face)
    end do
    if (.not. ok) ok = maxval(abs(d)) <= 1.0e-10_dp
    if (.not. ok) return
    call face_shape(nfn, xi, eta, n, dn)
    x = matmul(xf(:, 1:nfn), n(1:nfn))
    t1 = matmul(xf(:, 1:nfn), dn(1, 1:nfn))
    t2 = matmul(xf(:, 1:nfn), dn(2, 1:nfn))
    normal = [t1(2) * t2(3) - t1(3) * t2(2), t1(3) * t2(1) - t1(1) * t2(3), t1(1) * t2(2) - t1(2) * t2(1)]
    normal = normal / norm2(normal)
    w = n
    dist = dot_product(normal, xb - x)
    if (tri) then
      inside = xi >= -tol .and. eta >= -tol .and. xi + eta <= 1.0_dp + tol
    else
      inside = abs(xi) <= 1.0_dp + tol .and. abs(eta) <= 1.0_dp + tol
    end if
  end subroutine project_on_face
end module face_projection
