"""MODEL … SUBSTEPS EXACT: the discrete gradient of a law with a potential (issue 15, item 2's exact
option for the 1D and beam laws; docs/materials.md). NONLINEAR_ELASTIC's step stress becomes
sigbar = (psi(eps1) - psi(eps_n)) / deps, so its work is the energy change itself: the `internal`
work equals the `stored` energy psi to round-off, and the balance of eq (9) is the true energy error
at any step, with one evaluation per point (AUTO's trapezoid over sub-increments is exact only to
its tolerance, 1e-4 of a step's work).

- inputs/spring_nonlinear.dat (a SPRING, small displacements) at h = T/200, T/20 and T/4 (TOLERANCE
  1e-14): kinetic + psi constant to 1e-11 with EXACT; with AUTO the same runs drift by > 1e-5.
- A pendulum on a nonlinear-elastic SPRING (KINEMATICS LARGE, gravity): internal = stored to 1e-12,
  |balance| <= 1e-10 of E (the true energy error; AUTO: internal - stored > 1e-8).
- fibre_beam.dat: a cantilever of NONLINEAR_ELASTIC layers vibrating (b eps^2 ~ 0.1), SMALL and LARGE
  (corotational): internal = stored to 1e-12, kinetic + stored constant to 1e-10; AUTO drifts by > 1e-6.
- A restart of the LARGE cantilever from a checkpoint continues bit for bit.
- Bad input (tests/scenes/bad_input): SUBSTEPS EXACT on a law without a potential.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def measures(h):
    """(max |internal - stored| / max stored, max |kinetic + stored - E0| / max E, max |balance| / E)."""
    e = h['kinetic'] + h['stored']
    return (np.max(np.abs(h['internal'] - h['stored'])) / np.max(h['stored']),
            np.max(np.abs(e - e[0])) / np.max(np.abs(e)),
            np.max(np.abs(h['balance'])) / np.max(h['kinetic'] + h['internal']))


def run_text(name, text, sets=()):
    return sc.history(sc.run_ok(sc.write_scene(name, text), list(sets)))


# --- the nonlinear spring, small displacements, over two decades of h -----------------------------------
spring = open(os.path.join(sc.ROOT, 'inputs/spring_nonlinear.dat')).read()
period = 0.6283185307179586                   # 200 steps of the scene's h
for frac in (200, 20, 4):
    sets = ['TIME.STEP=%.17g' % (period / frac), 'SCHEME.TOLERANCE=1e-14']
    _, drift, _ = measures(run_text('spring_exact.dat', spring.replace('SUBSTEPS AUTO', 'SUBSTEPS EXACT'), sets))
    _, drift_auto, _ = measures(run_text('spring_auto.dat', spring, sets))
    sc.report_measured('nonlinear spring, h = T/%d, SUBSTEPS EXACT: kinetic + psi constant to 1e-11 (AUTO: > 1e-5)' % frac,
           drift <= 1e-11 and drift_auto > 1e-5, 'EXACT %.2e, AUTO %.2e' % (drift, drift_auto))

# --- a pendulum on a nonlinear-elastic spring, KINEMATICS LARGE --------------------------------------
pend = open(os.path.join(sc.ROOT, 'tests/scenes/large_bar/spring_pendulum.dat')).read().replace(
    'MATERIAL  soft   ELASTIC YOUNG 100', 'MATERIAL  soft   NONLINEAR_ELASTIC YOUNG 100 B 10').replace(
    'TIME      STEP 1e-3 END 10', 'TIME      STEP 1e-2 END 10')
gap_e, _, bal_e = measures(run_text('pend_exact.dat', pend.replace('KINEMATICS LARGE', 'KINEMATICS LARGE SUBSTEPS EXACT')))
gap_a, _, _ = measures(run_text('pend_auto.dat', pend))
sc.report_measured('pendulum on a cubic spring (LARGE), SUBSTEPS EXACT: internal = stored to 1e-12 (AUTO: > 1e-8)',
       gap_e <= 1e-12 and gap_a > 1e-8, 'EXACT %.2e, AUTO %.2e' % (gap_e, gap_a))
sc.report_measured('pendulum on a cubic spring (LARGE), SUBSTEPS EXACT: |balance| <= 1e-10 of E, the true energy error',
       bal_e <= 1e-10, '%.2e' % bal_e)

# --- a cantilever of nonlinear-elastic fibres, SMALL and LARGE ----------------------------------------
beam = open(os.path.join(HERE, 'fibre_beam.dat')).read()
for kin in ('SMALL', 'LARGE'):
    gap, drift, _ = measures(run_text('beam_%s.dat' % kin, beam.replace('SUBSTEPS EXACT', 'SUBSTEPS EXACT KINEMATICS ' +
                                                                          kin)))
    _, drift_auto, _ = measures(run_text('beam_%s_auto.dat' % kin, beam.replace('SUBSTEPS EXACT', 'KINEMATICS ' + kin)))
    sc.report_measured('fibre cantilever (%s), SUBSTEPS EXACT: internal = stored to 1e-12' % kin, gap <= 1e-12, '%.2e' % gap)
    sc.report_measured('fibre cantilever (%s), SUBSTEPS EXACT: kinetic + stored constant to 1e-10 (AUTO: > 1e-6)' % kin,
           drift <= 1e-10 and drift_auto > 1e-6, 'EXACT %.2e, AUTO %.2e' % (drift, drift_auto))

# --- a restart continues bit for bit (the LARGE cantilever of cubic layers, EXACT) ------------------------
path = sc.write_scene('beam_restart.dat', beam.replace('SUBSTEPS EXACT', 'SUBSTEPS EXACT KINEMATICS LARGE'))
same, detail = sc.restart_same(path, ['OUTPUT.CHECKPOINT=100'], '0.12')
sc.report_measured('fibre cantilever (LARGE, EXACT): a restart from the checkpoint of step 100 continues bit for bit', same, detail)
