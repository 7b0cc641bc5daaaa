!> The step's multipliers (contact_solve_step): the gaps and slips without contact forces, then
!> the LCP of the unilateral conditions (lcp_pivot), or with FRICTION the fixed point of Coulomb's
!> law around it (coulomb), and the constrained update du = du_free + S⁻¹C'Λ.
submodule (contact) contact_step
  implicit none

contains

  !> One iteration of the step: with u_n the displacement at the start of the step and du_free
  !> the update without contact forces, find the step multiplier lambda (LCP) and the constrained
  !> update du = du_free + S⁻¹C'Λ; s is the S⁻¹ of the S given to contact_prepare.
  module procedure solve_step_op
    integer :: j

    stat = STAT_OK
    du = du_free
    if (.not. cs%prepared) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_solve_step: call contact_prepare first')
      return
    end if
    if (size(lambda) /= cs%nc .or. size(u_n) /= cs%neq .or. size(du_free) /= cs%neq .or. size(du) /= cs%neq) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_solve_step: size mismatch (' // str(cs%neq) // &
        ' equations, ' // str(cs%nc) // ' conditions)')
      return
    end if
    lambda = 0.0_dp
    if (cs%nc == 0) return
    call cs%c%gaps(u_n, cs%st%gap_n)
    if (cs%moving) cs%st%gap_n = cs%st%gap_n + cs%wshift   ! (g0 is the step end's: g(n) before the obstacle moved)
    ! A condition that starts the step slightly penetrated (within the input tolerance, or by
    ! the LCP tolerance at an earlier release) is held where it is, not pushed out: its target
    ! is g(n+1) >= g(n). Pushing it out would let the multiplier do the work ½ Λ |g(n)|, which
    ! E_j = ½ Λ max(g(n), 0) of eq (10) cannot take back: energy created. Its tolerance is what
    ! is left of the gap tolerance (tol + g(n), negative beyond it: then it is caught at once),
    ! so that the penetration stays within the tolerance however slowly it creeps in.
    do j = 1, cs%nc
      cs%wq(j) = max(cs%st%gap_n(j), 0.0_dp) + cs%c%dot(j, du_free)
      cs%tolj(j) = cs%settings%gap_rtol * cs%length_scale + min(cs%st%gap_n(j), 0.0_dp)
      if (cs%bilat(j) .or. cs%follow(j)) then  ! an equality, or a gap whose work is given back: it closes
        cs%wq(j) = cs%st%gap_n(j) + cs%c%dot(j, du_free)
        cs%tolj(j) = cs%settings%gap_rtol * cs%length_scale
      end if
      if (cs%tangent(j)) cs%wq(j) = cs%c%dot(j, du_free)   ! (FRICTION: the slip of the step, c_T du)
      if (cs%moving) cs%wq(j) = cs%wq(j) - cs%wshift(j)    ! (a tangent: relative to the obstacle)
    end do
    call cs%ms%bind(cs%c, s)
    if (cs%fr%count() > 0) then
      call cs%fr%solve(cs%ms, cs%wq, cs%settings%gap_rtol * cs%length_scale, cs%tolj, cs%bilat, cs%st%lambda, &
        cs%st%gap, cs%st%active_iter, cs%wdiag, cs%viol, cs%lcp_iter, stat, errmsg)
    else
      call lcp_pivot(cs%ms, cs%wq, cs%settings%gap_rtol * cs%length_scale, cs%st%lambda, cs%st%gap, &
        cs%st%active_iter, cs%wdiag, cs%viol, cs%lcp_iter, stat, errmsg, tol_free=cs%tolj, bilateral=cs%bilat)
    end if
    if (stat /= STAT_OK) then
      call cs%ms%unbind()
      errmsg = errmsg // ' (' // str(count(cs%st%active_iter)) // ' conditions in the last active set)'
      return
    end if
    lambda = cs%st%lambda
    if (any(cs%st%lambda /= 0.0_dp)) then
      call cs%ms%correction(cs%st%lambda, cs%xw, stat, errmsg)
      if (stat == STAT_OK) du = du + cs%xw
    end if
    call cs%ms%unbind()
  end procedure solve_step_op
end submodule contact_step
