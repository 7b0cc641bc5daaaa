!> The element mass matrices the impact modes reshape at the contact nodes (assembly's
!> assemble_operators): IMPACT MASSLESS moves the contact nodes' mass to the element's other
!> nodes, IMPACT SYMMETRIC lumps their positive couplings on the diagonals.
module contact_mass
  use kinds, only: dp
  use element_traits, only: NODE_DOFS, DOF_RZ
  implicit none
  private
  public :: move_contact_mass, lump_contact_rows

contains

  !> IMPACT MASSLESS (docs/contact.md): the translational mass of the element's contact nodes
  !> moved to its other nodes (Khenous, Laborde and Renard's mass redistribution): rows and
  !> columns of a contact node's UX, UY zeroed, the mass they held in each direction (2 r - m_cc,
  !> r the row sum) added to the diagonal of the other nodes' same DOF in equal parts, so that
  !> the element's total mass and its gravity load keep their values. An element whose nodes
  !> are all contact nodes keeps its mass.
  pure subroutine move_contact_mass(nodes, mask, massless, me)
    integer, intent(in) :: nodes(:)
    logical, intent(in) :: mask(NODE_DOFS), massless(:)
    real(dp), intent(inout) :: me(:, :)
    integer :: a, b, d, ia, ib, nper, nfree, ntr
    real(dp) :: moved
    nper = count(mask)
    ntr = nper - merge(1, 0, mask(DOF_RZ))     ! the translations lead each node's DOFs
    nfree = count(.not. massless(nodes))
    if (nfree == 0 .or. nfree == size(nodes)) return
    do a = 1, size(nodes)
      if (.not. massless(nodes(a))) cycle
      do d = 1, ntr
        ia = (a - 1) * nper + d
        ! The mass the row holds in a rigid translation along d: its entries on the d DOFs of the
        ! element's nodes (not a beam's rotations, kg m, nor the other direction).
        moved = -me(ia, ia)
        do b = 1, size(nodes)
          moved = moved + 2.0_dp * me(ia, (b - 1) * nper + d)
        end do
        me(ia, :) = 0.0_dp
        me(:, ia) = 0.0_dp
        do b = 1, size(nodes)
          if (massless(nodes(b))) cycle
          ib = (b - 1) * nper + d
          me(ib, ib) = me(ib, ib) + moved / real(nfree, dp)
        end do
      end do
    end do
  end subroutine move_contact_mass

  !> IMPACT SYMMETRIC (docs/contact.md): the positive couplings of the element's contact nodes' UX,
  !> UY with the same DOF of its other nodes lumped on the two diagonals (row sums, the element's
  !> total mass and gravity load kept; M stays positive definite, the change being c [1 -1; -1 1]
  !> with c > 0; the negative couplings of quadratic elements are kept), so that stopping a contact
  !> node's normal velocity (the projection at establishment) and the impulse at its release act on
  !> that node alone (on linear elements).
  pure subroutine lump_contact_rows(nodes, mask, contact, me)
    integer, intent(in) :: nodes(:)
    logical, intent(in) :: mask(NODE_DOFS), contact(:)
    real(dp), intent(inout) :: me(:, :)
    integer :: a, b, d, ia, ib, nper, ntr
    real(dp) :: c
    nper = count(mask)
    ntr = nper - merge(1, 0, mask(DOF_RZ))
    do a = 1, size(nodes)
      if (.not. contact(nodes(a))) cycle
      do d = 1, ntr
        ia = (a - 1) * nper + d
        do b = 1, size(nodes)
          if (b == a) cycle
          ib = (b - 1) * nper + d
          c = me(ia, ib)
          if (c <= 0.0_dp) cycle                 ! (QUAD8, TRI6 corners: kept, M stays definite)
          me(ia, ia) = me(ia, ia) + c
          me(ib, ib) = me(ib, ib) + c
          me(ia, ib) = 0.0_dp
          me(ib, ia) = 0.0_dp
        end do
      end do
    end do
  end subroutine lump_contact_rows
end module contact_mass
