!> The mass the impact corrections work with (method.md sections 3 and 6): M⁻¹ as a lumped
!> diagonal, a CHOLMOD factor of the consistent mass or any operator, checked once on every
!> condition. A submodule of contact: it hands the mass to impact_space.
submodule (contact) contact_mass_ops
  implicit none

contains

  !> Lumped mass: M = diag(mdiag).
  module procedure set_mass_diag
    type(diag_inverse_t) :: op
    allocate (op%d, source=mdiag)
    call set_mass_op(cs, op, stat, errmsg)
  end procedure set_mass_diag

  !> Consistent mass (pattern, values): factorized with CHOLMOD and kept in cs; M must be
  !> positive definite on every free equation.
  module procedure set_mass_chol
    cs%mass_set = .false.
    call cs%sp%set_mass_chol(pat, mval, stat, errmsg)
    if (stat /= STAT_OK) return
    call finish_mass(cs, stat, errmsg)
  end procedure set_mass_chol

  !> Any M⁻¹ operator (tests, special masses); op is copied into cs.
  module procedure set_mass_op
    cs%mass_set = .false.
    call cs%sp%set_mass_op(op)
    call finish_mass(cs, stat, errmsg)
  end procedure set_mass_op

  module procedure contact_destroy_mass
    call cs%sp%destroy_mass()
    cs%mass_set = .false.
  end procedure contact_destroy_mass

  !> Every condition must see a mass: check the diagonal of A M⁻¹A' (n solves with a
  !> consistent mass, once per run).
  subroutine finish_mass(cs, stat, errmsg)
    type(contact_set_t), intent(inout) :: cs
    integer, intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(dp) :: a(1, 1)
    integer :: j
    stat = STAT_OK
    if (.not. cs%finalized) then
      call set_error(stat, errmsg, STAT_INPUT, 'contact_set_mass: call contact_finalize first')
      return
    end if
    if (cs%sp%mass_diagonal()) then
      do j = 1, cs%nc
        if (cs%bilat(j)) cycle                  ! (no impact correction on an IMPOSE row)
        call cs%sp%am_block(cs%c, [j], 1, a, stat, errmsg)
        if (stat /= STAT_OK) return
      end do
    end if
    cs%mass_set = .true.
  end subroutine finish_mass
end submodule contact_mass_ops
