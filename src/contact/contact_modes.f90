!> The settings of contact that the scene chooses (SCHEME IMPACT, SCHEME MULTIPLIERS), defined
!> once: the scene reads the words, contact and contact_multipliers act on the codes.
module contact_modes
  implicit none
  private
  public :: IMPACT_OFF, IMPACT_PAPER, IMPACT_PERSIST, IMPACT_MASSLESS, IMPACT_AUTO, IMPACT_SYMMETRIC, IMPACT_NAMES
  public :: SOLVER_AUTO, SOLVER_SCHUR, SOLVER_AUGMENTED, SWITCH_DEFAULT

  !> SCHEME IMPACT: plain Newmark, the paper's (10)-(16), the persistent-contact variant, or
  !> massless contact nodes (their mass moved to their neighbours, the energy lost at
  !> establishment given back by scaling the body; docs/contact.md).
  integer, parameter :: IMPACT_OFF = 0, IMPACT_PAPER = 1, IMPACT_PERSIST = 2, IMPACT_MASSLESS = 3
  !> SCHEME IMPACT AUTO (default): where every contact node can give its mass away and every impact
  !> is elastic, SYMMETRIC on MIXED or LUMPED masses and MASSLESS on a consistent one; PERSIST
  !> otherwise; resolved when the scene is loaded (scene_contacts), so that the contact code only
  !> ever sees one of the other five.
  integer, parameter :: IMPACT_AUTO = 4
  !> SCHEME IMPACT SYMMETRIC: the contact nodes keep their mass (their element couplings lumped on
  !> them); the kinetic energy an establishment takes (their normal velocity stopped, PERSIST's
  !> projection) and the step's loss (10) are held by the condition and given back at its release
  !> as an impulse on the released nodes, the release being the impact reversed (docs/contact.md).
  integer, parameter :: IMPACT_SYMMETRIC = 5
  !> The words of the codes (IMPACT_NAMES(code)), for messages.
  character(len=*), parameter :: IMPACT_NAMES(0:5) = ['OFF      ', 'PAPER    ', 'PERSIST  ', 'MASSLESS ', 'AUTO     ', &
    'SYMMETRIC']
  !> SCHEME MULTIPLIERS: Schur columns up to AUGMENTED_ABOVE active conditions then the
  !> augmented system (AUTO), or one of them always.
  integer, parameter :: SOLVER_AUTO = 0, SOLVER_SCHUR = 1, SOLVER_AUGMENTED = 2
  !> AUTO: active sets larger than this go to the augmented system (docs/performance-contact.md).
  integer, parameter :: SWITCH_DEFAULT = 128
end module contact_modes
