!> Setting up a contact set once its rows are added (contact_finalize): the rows checked against
!> the free equations, the state, FRICTION's rows, the impact modes' scratch and the multiplier
!> system sized. A submodule of contact.
submodule (contact) contact_setup
  implicit none

contains

  !> Check the conditions against neq free equations, set the model size (length_scale > 0,
  !> e.g. the bounding-box diagonal; tolerances are relative to it) and allocate the state and
  !> the workspaces: nothing active, no reaction. The initial gaps are the driver's (scene)
  !> business. cs%settings%solver and %switch_size are read here.
  module procedure contact_finalize
    integer :: nc, g0j, j
    real(dp), allocatable :: g0(:)
    type(paper_t) :: fresh_paper
    type(persist_t) :: fresh_persist
    type(massless_t) :: fresh_massless
    type(symmetric_t) :: fresh_symmetric
    type(scaling_t) :: fresh_following
    call cs%c%finalize(neq, stat, errmsg)
    if (stat /= STAT_OK) return
    if (.not. (length_scale > 0.0_dp)) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact: the model size must be positive, got ' // str(length_scale))
      return
    end if
    nc = cs%c%n()
    cs%nc = nc
    cs%neq = neq
    cs%length_scale = length_scale
    allocate (g0(nc))
    do g0j = 1, nc
      g0(g0j) = cs%c%gap0(g0j)
    end do
    call cs%st%init(g0)
    if (allocated(cs%bilat)) deallocate (cs%bilat)
    allocate (cs%bilat(nc))
    call cs%fr%init(nc)
    if (allocated(cs%tangent)) deallocate (cs%tangent)
    allocate (cs%tangent(nc))
    call cs%fr%tangent_mask(cs%tangent)
    cs%bilat = [(j >= cs%first_bilateral, j = 1, nc)] .or. cs%tangent
    if (allocated(cs%follow)) deallocate (cs%follow, cs%xg, cs%geo_now, cs%geo_step)
    allocate (cs%follow(nc), cs%xg(nc), cs%geo_now(nc), cs%geo_step(nc))
    cs%follow = .false.
    cs%st%active_iter = cs%bilat                  ! (st%active: the contacts only, none yet)
    if (allocated(cs%wq)) deallocate (cs%wq, cs%wdiag, cs%gn, cs%gend, cs%e, cs%y, cs%r, cs%nu, cs%viol, cs%now, &
      cs%est, cs%rel, cs%fallback, cs%xw, cs%ev, cs%tolj, cs%cimp, cs%bimp, cs%lam_step, cs%changing)
    allocate (cs%lam_step(nc), cs%changing(nc), cs%cimp(nc), cs%bimp(3, nc), cs%tolj(nc), cs%wq(nc), cs%wdiag(nc), &
      cs%gn(nc), cs%gend(nc), cs%e(nc), cs%y(nc), cs%r(nc), cs%nu(nc), cs%viol(nc), &
      cs%now(nc), cs%est(nc), cs%rel(nc), cs%fallback(nc), cs%ev(nc), cs%xw(neq))
    cs%fallback = .false.
    cs%inelastic = any([(cs%c%restitution(j) < 1.0_dp, j = 1, nc)])
    call cs%sp%init(neq, nc)                       ! (the rigid modes go; M⁻¹ stays)
    cs%paper = fresh_paper                         ! (the modes size their scratch at first use)
    cs%persist = fresh_persist
    cs%massless = fresh_massless
    cs%symmetric = fresh_symmetric
    cs%following = fresh_following
    call cs%paper%init(nc)                         ! (PAPER, and the fallback of PERSIST and SYMMETRIC)
    if (present(mode)) then
      select case (mode)
      case (IMPACT_PERSIST)
        call cs%persist%init(neq, nc)
      case (IMPACT_MASSLESS)
        call cs%massless%init(neq, nc)
      case (IMPACT_SYMMETRIC)
        call cs%symmetric%init(neq, nc)
      end select
      if (mode /= IMPACT_OFF) call cs%following%init(neq, nc)
    end if
    cs%wdiag = 1.0_dp
    cs%cimp = 0.0_dp
    cs%bimp = 0.0_dp
    cs%lam_step = 0.0_dp
    cs%n_ev = 0
    cs%ms%mode = cs%settings%solver
    cs%ms%switch_size = cs%settings%switch_size
    call cs%ms%bind(cs%c)
    call cs%ms%init(int(min(int(max(nc, 1), 8), max(8_8, min(int(cs%settings%switch_size, 8), &
      cs%settings%z_max_entries / max(neq, 1))))))
    call cs%ms%set_pairs([(cs%fr%tangent_of(j), j = 1, nc)], [(cs%fr%tangent2_of(j), j = 1, nc)])   ! (FRICTION)
    call cs%ms%unbind()
    cs%finalized = .true.
    cs%prepared = .false.
  end procedure contact_finalize
end submodule contact_setup
