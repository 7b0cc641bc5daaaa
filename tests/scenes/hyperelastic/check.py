"""HYPERELASTIC: the compressible neo-Hookean law for KINEMATICS LARGE surface elements (issue 15,
item 1's laws; item 2's exact option for laws with a potential). docs/materials.md,
docs/large-displacements.md.

- Homogeneous states given by INITIAL DISPLACEMENT on one QUAD4 (plane strain, and plane stress
  with C33 from S33 = 0): the strain energy rebond reports
  at t = 0 (the discrete stress's work from the reference) equals the closed form psi(F) x volume
  to 1e-12: a uniaxial squash to half the length (psi = mu (tr E - ln J) + lambda/2 ln² J) and a
  simple shear of 1 (J = 1: psi = mu gamma²/2, where St Venant-Kirchhoff adds (lambda + 2 mu) gamma^4/8).
- spinning_quad.dat: a free neo-Hookean square spinning five turns: angular momentum and energy
  kept to 1e-10, linear momentum zero.
- At small amplitude HYPERELASTIC = ELASTIC (both LARGE) to 1e-6 (the neo-Hookean law's small-strain
  limit is the linear law: the steel cantilever block of tests/scenes/large_bar).
- ring_fast.dat: the ring of inputs/ring_impact.dat at 20 m/s: |balance| <= 1e-10 of E, the wall
  never crossed (1e-9 m), the ring leaving the wall.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

HERE = os.path.relpath(os.path.dirname(os.path.abspath(__file__)), sc.ROOT)
E, NU, T = 1e7, 0.45, 0.1
LAM = E * NU / ((1 + NU) * (1 - 2 * NU))
MU = E / (2 * (1 + NU))

ONE = """NODE a AT 0 0
NODE b AT 1 0
NODE c AT 1 1
NODE d AT 0 1
ELEMENT q TYPE QUAD4 NODES a b c d
GROUP all NODES a b c d
MATERIAL rub %s YOUNG 1e7 POISSON 0.45 DENSITY 1000
SECTION t THICKNESS 0.1
MODEL q MATERIAL rub SECTION t KINEMATICS LARGE PLANE %s
FUNCTION id POINTS 0 0 1 1
INITIAL all DISPLACEMENT %s FUNCTION id ALONG %s
TIME STEP 1e-4 END 1e-4
"""


def energy0(law, disp, along, plane='STRAIN'):
    out = sc.run_ok(sc.write_scene('one_%s_%s_%s.dat' % (law, along, plane), ONE % (law, plane, disp, along)))
    return sc.history(out)['internal'][0]


def psi_plane_stress(c11):
    """Plane-stress neo-Hookean energy of F = diag(sqrt(c11), 1): C33 = c from S33 = 0, by Newton."""
    c = 1.0
    for _ in range(100):
        f = MU * (c - 1) + LAM * 0.5 * math.log(c11 * c)
        c -= f / (MU + 0.5 * LAM / c)
    lj = 0.5 * math.log(c11 * c)
    return MU / 2 * (c11 + 1 + c - 3) - MU * lj + LAM / 2 * lj ** 2


# --- homogeneous states: the closed form ---------------------------------------------------------
lnj = math.log(0.5)
psi = MU * (-0.375 - lnj) + 0.5 * LAM * lnj ** 2
sc.close('uniaxial squash to 0.5 L (J = 0.5): energy = psi(F) x volume (1e-12)', energy0('HYPERELASTIC', '-0.5 0', 'X'),
         psi * T, 1e-12)
sc.close('simple shear gamma = 1 (J = 1): energy = mu gamma²/2 x volume (1e-12)', energy0('HYPERELASTIC', '1 0', 'Y'),
         0.5 * MU * T, 1e-12)
sc.close('uniaxial squash to 0.5 L, PLANE STRESS (C33 from S33 = 0): energy = psi x volume (1e-12)',
         energy0('HYPERELASTIC', '-0.5 0', 'X', 'STRESS'), psi_plane_stress(0.25) * T, 1e-12)
sc.close('simple shear gamma = 1, ELASTIC (St Venant-Kirchhoff): mu/2 + (lambda + 2 mu)/8 (1e-12)',
         energy0('ELASTIC', '1 0', 'Y'), (0.5 * MU + (LAM + 2 * MU) / 8) * T, 1e-12)

# --- the free spinning square ---------------------------------------------------------------------
# (linear momentum: 1e-10 of the corner momenta, 78.5 N s)
sc.free_body('spinning neo-Hookean square', sc.history(sc.run_ok(os.path.join(HERE, 'spinning_quad.dat'))), 1e-8)

# --- small amplitude: HYPERELASTIC = ELASTIC ------------------------------------------------------
text = open(os.path.join(sc.ROOT, 'tests/scenes/large_bar/cantilever_small.dat')).read()
text = text.replace('MODEL     blk MATERIAL st SECTION t', 'MODEL     blk MATERIAL st SECTION t KINEMATICS LARGE')
pe = sc.probes(sc.run_ok(sc.write_scene('small_el.dat', text)))
ph = sc.probes(sc.run_ok(sc.write_scene('small_nh.dat', text.replace('ELASTIC YOUNG', 'HYPERELASTIC YOUNG'))))
diff = max(np.max(np.abs(pe[k] - ph[k])) / np.max(np.abs(pe[k])) for k in pe if k != 'time')
sc.report('cantilever block at small amplitude: HYPERELASTIC = ELASTIC (LARGE) to 1e-6', diff <= 1e-6, '%.2e' % diff)

# --- the ring at 20 m/s -----------------------------------------------------------------------------
out = sc.run_ok(os.path.join(HERE, 'ring_fast.dat'))
h, c = sc.history(out), sc.contacts(out)
bal = np.max(np.abs(h['balance'])) / np.max(h['kinetic'] + h['internal'])
sc.report('ring at 20 m/s, neo-Hookean: |balance| <= 1e-10 of E', bal <= 1e-10, '%.2e' % bal)
gap = np.min(c['min_gap'])
sc.report('ring at 20 m/s: the wall never crossed (1e-9 m)', gap >= -1e-9, '%.2e m' % gap)
sc.report('ring at 20 m/s: released, leaving the wall (momentum_x < 0 at the end)',
          c['active'][-1] == 0 and h['momentum_x'][-1] < 0, 'px %.3f' % h['momentum_x'][-1])
