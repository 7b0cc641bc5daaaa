!> Fibre (layered) section of a BEAM2: rectangular section of height sec%height and width
!> b = sec%area / sec%height cut into sec%layers equal layers (midpoint rule). Layer f sits at
!> y_f = -h/2 + (f - 1/2) h/n, has area A_f = A/n and strain eps - y_f kappa; the resultants are
!>   N = sum sigma_f A_f,   M = -sum sigma_f y_f A_f.
!> Each layer follows a uniaxial law: elastic, cubic nonlinear elastic (no state) or bilinear
!> elastoplastic (state of law_plastic_1d per layer: q(3(f-1)+1:3f) = [eps_p, alpha, beta]).
!> The fibre stress of the elastoplastic law is recovered from the state as E (eps_f - eps_p).
module beam_fibre
  use kinds, only: dp
  use section, only: section_t
  use law_types, only: law_params_t, law_step_t, NSUB_EXACT, law_step_reset
  use law_plastic_1d, only: P1D_NSTATE, plastic_1d_inside, plastic_1d_path, plastic_auto_nsub
  use law_nonlinear_elastic, only: nle_stress, nle_energy, nle_auto_nsub, nle_path, nle_exact
  implicit none
  private
  public :: FIB_ELASTIC, FIB_NONLINEAR, FIB_PLASTIC
  public :: fibre_layer, fibre_elastic_matrix, fibre_nstate, fibre_update, fibre_stored

  integer, parameter :: FIB_ELASTIC = 1, FIB_NONLINEAR = 2, FIB_PLASTIC = 3

contains

  !> Height y and area a of layer f.
  pure subroutine fibre_layer(sec, f, y, a)
    type(section_t), intent(in) :: sec
    integer, intent(in) :: f
    real(dp), intent(out) :: y, a
    real(dp) :: dh
    dh = sec%height / real(sec%layers, dp)
    y = -0.5_dp * sec%height + (real(f, dp) - 0.5_dp) * dh
    a = sec%area / real(sec%layers, dp)
  end subroutine fibre_layer

  !> Fibre-integrated elastic matrix diag(sum E A_f, sum E y_f^2 A_f) (the coupling sum E y_f A_f
  !> vanishes for the symmetric layout and is dropped).
  pure subroutine fibre_elastic_matrix(e, sec, d)
    real(dp), intent(in) :: e
    type(section_t), intent(in) :: sec
    real(dp), intent(out) :: d(:, :)
    real(dp) :: y, a
    integer :: f
    d = 0.0_dp
    do f = 1, sec%layers
      call fibre_layer(sec, f, y, a)
      d(1, 1) = d(1, 1) + e * a
      d(2, 2) = d(2, 2) + e * y**2 * a
    end do
  end subroutine fibre_elastic_matrix

  pure integer function fibre_nstate(kind, sec)
    integer, intent(in) :: kind
    type(section_t), intent(in) :: sec
    fibre_nstate = 0
    if (kind == FIB_PLASTIC) fibre_nstate = P1D_NSTATE * sec%layers
  end function fibre_nstate

  !> Section update along the straight path (eps, kappa) -> + deps in nsub sub-increments
  !> (nsub = 0: AUTO; elastoplastic: r = E (|deps| + h/2 |dkappa|) / sy of the extreme layer;
  !> nonlinear elastic: the largest layer AUTO count; NSUB_EXACT: the nonlinear elastic layers'
  !> discrete gradients). Elastoplastic: when every layer's elastic
  !> trial stays inside its frozen yield surface the step is elastic: sig = sig_n + D deps with D
  !> the fibre elastic matrix, sigbar the exact chord midpoint, nused = 0. dtan: sum of the layer
  !> tangents (last sub-increment) A_f [1, -y; -y, y^2].
  pure subroutine fibre_update(kind, p, sec, nsub, eps_n, deps, sig_n, q_n, q, r)
    integer, intent(in) :: kind, nsub
    type(law_params_t), intent(in) :: p
    type(section_t), intent(in) :: sec
    real(dp), intent(in) :: eps_n(2), deps(2), sig_n(2), q_n(:)
    real(dp), intent(out) :: q(:)
    type(law_step_t), intent(out) :: r
    real(dp) :: y, a, ef, def, sf_n, sf, sbf, et, df, dmat(2, 2), e
    integer :: f, n, i0, nf
    logical :: inside
    e = p%young
    call law_step_reset(r)
    r%sig(1:2) = 0.0_dp                          ! (the layers add into these)
    r%sigbar(1:2) = 0.0_dp
    r%dtan(1:2, 1:2) = 0.0_dp
    select case (kind)
    case (FIB_PLASTIC)
      inside = .true.
      do f = 1, sec%layers
        call fibre_layer(sec, f, y, a)
        i0 = P1D_NSTATE * (f - 1)
        ef = eps_n(1) - y * eps_n(2)
        def = deps(1) - y * deps(2)
        inside = inside .and. plastic_1d_inside(p, e * (ef - q_n(i0 + 1)), q_n(i0 + 1:i0 + P1D_NSTATE), def)
      end do
      if (inside) then
        call fibre_elastic_matrix(e, sec, dmat)
        call elastic_chord(dmat, sig_n, deps, r)
        q(1:P1D_NSTATE * sec%layers) = q_n(1:P1D_NSTATE * sec%layers)
        return
      end if
      n = nsub
      if (n <= 0) n = plastic_auto_nsub(e * (abs(deps(1)) + 0.5_dp * sec%height * abs(deps(2))) / p%yield)
      r%nused = n
      do f = 1, sec%layers
        call fibre_layer(sec, f, y, a)
        i0 = P1D_NSTATE * (f - 1)
        ef = eps_n(1) - y * eps_n(2)
        def = deps(1) - y * deps(2)
        sf_n = e * (ef - q_n(i0 + 1))
        ! A layer that stays elastic returns the exact chord, equal to the trapezoid of any N.
        call plastic_1d_path(p, n, sf_n, q_n(i0 + 1:i0 + P1D_NSTATE), def, sf, sbf, &
                             q(i0 + 1:i0 + P1D_NSTATE), df, nf, et)
        call accumulate(y, a, sf, sbf, et, r)
        r%dissip = r%dissip + a * df
      end do
    case (FIB_NONLINEAR)
      n = nsub
      if (n == NSUB_EXACT) then
        ! SUBSTEPS EXACT: each layer's discrete gradient, so the section's work is its Δψ.
        r%nused = 1
        do f = 1, sec%layers
          call fibre_layer(sec, f, y, a)
          call nle_exact(e, p%nl_b, eps_n(1) - y * eps_n(2), deps(1) - y * deps(2), sf, sbf, et)
          call accumulate(y, a, sf, sbf, et, r)
        end do
        return
      else if (n <= 0) then
        n = 1
        do f = 1, sec%layers
          call fibre_layer(sec, f, y, a)
          n = max(n, nle_auto_nsub(e, p%nl_b, eps_n(1) - y * eps_n(2), deps(1) - y * deps(2)))
        end do
      end if
      r%nused = n
      do f = 1, sec%layers
        call fibre_layer(sec, f, y, a)
        ef = eps_n(1) - y * eps_n(2)
        def = deps(1) - y * deps(2)
        call nle_path(e, p%nl_b, n, ef, def, nle_stress(e, p%nl_b, ef), sf, sbf, et)
        call accumulate(y, a, sf, sbf, et, r)
      end do
    case default
      call fibre_elastic_matrix(e, sec, dmat)
      call elastic_chord(dmat, sig_n, deps, r)
    end select
  end subroutine fibre_update

  !> The whole step elastic: sig = sig_n + D deps, sigbar the exact chord midpoint.
  pure subroutine elastic_chord(d, sig_n, deps, r)
    real(dp), intent(in) :: d(2, 2), sig_n(2), deps(2)
    type(law_step_t), intent(inout) :: r
    r%sig(1:2) = sig_n + matmul(d, deps)
    r%sigbar(1:2) = 0.5_dp * (sig_n + r%sig(1:2))
    r%dtan(1:2, 1:2) = d
  end subroutine elastic_chord

  !> Add layer (y, a) with stress s, mean stress sb, tangent t to the section resultants.
  pure subroutine accumulate(y, a, s, sb, t, r)
    real(dp), intent(in) :: y, a, s, sb, t
    type(law_step_t), intent(inout) :: r
    r%sig(1:2) = r%sig(1:2) + a * [s, -y * s]
    r%sigbar(1:2) = r%sigbar(1:2) + a * [sb, -y * sb]
    r%dtan(1, 1) = r%dtan(1, 1) + a * t
    r%dtan(1, 2) = r%dtan(1, 2) - a * y * t
    r%dtan(2, 1) = r%dtan(2, 1) - a * y * t
    r%dtan(2, 2) = r%dtan(2, 2) + a * y**2 * t
  end subroutine accumulate

  !> Recoverable energy per unit length: sum A_f psi_f, psi_f = sigma_f^2 / (2E) (elastic,
  !> elastoplastic) or E (eps_f^2/2 + b eps_f^4/4) (nonlinear elastic).
  pure real(dp) function fibre_stored(kind, e, b, sec, eps, q) result(w)
    integer, intent(in) :: kind
    real(dp), intent(in) :: e, b, eps(2), q(:)
    type(section_t), intent(in) :: sec
    real(dp) :: y, a, ef
    integer :: f
    w = 0.0_dp
    do f = 1, sec%layers
      call fibre_layer(sec, f, y, a)
      ef = eps(1) - y * eps(2)
      select case (kind)
      case (FIB_PLASTIC)
        w = w + a * 0.5_dp * e * (ef - q(P1D_NSTATE * (f - 1) + 1))**2
      case (FIB_NONLINEAR)
        w = w + a * nle_energy(e, b, ef)
      case default
        w = w + a * 0.5_dp * e * ef**2
      end select
    end do
  end function fibre_stored
end module beam_fibre
