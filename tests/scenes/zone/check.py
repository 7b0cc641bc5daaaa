"""SCHEME ZONE: eq (9) iterated on the nonlinear elements' equations (issue 14, item 1;
src/time/nonlinear_zone.f90, docs/nonlinear-performance.md "The nonlinear zone").

inputs/block_patch.dat (40 x 20, 1640 equations): AUTO takes the zone, ON = OFF, the balance.

patch_block.dat: a 4 x 2 VON_MISES patch (30 equations) in a 20 x 10 ELASTIC block (420), a
400 MPa pulse on the patch. In exact arithmetic the zone's iterates are the whole system's, so:
- AUTO takes the zone here (stdout), and at every ITERATION (ELASTIC, TANGENT, AUTO) ZONE ON and
  OFF give the same kinetic, internal and dissipated energies to the iteration tolerance
  (1e-9 of the energy, TOLERANCE 1e-10), and |balance| <= 1e-10 of E; the patch dissipates (more
  than 5 % of the peak energy), so the iteration is exercised;
- ITERATION ELASTIC: the same iterates, so per step the same number of iterations, or one
  more where the zone's energy budget (the step's work taken on Z: smaller) asks for it;
- with the tangent (Newton on the zone through Woodbury's identity) fewer iterations than the
  whole system's AUTO;
- Rayleigh damping on the elastic block: ON = OFF;
- SCHEME RETRY (MAX_ITERATIONS 3 with ELASTIC makes steps fail): the retried sub-steps take the
  zone of their own step size, the run completes with the balance at 1e-10 (which steps fail
  depends on the last iteration, so ON and OFF sub-step differently: not compared);
- a restart from a checkpoint continues bit for bit;
- drop_block.dat, the zone with contact rows (a plastic patch at the base of a block thrown onto
  the ground, IMPACT AUTO = MASSLESS): the multipliers are solved with S at each iterate, so the
  zone iterates with S: ZONE ON equals the whole system's ITERATION ELASTIC (1e-9 of E, per step
  within one iteration), the balance at 1e-10, the ground never crossed beyond its tolerance;
- a whole LARGE scene forced on the zone (ZONE ON, cantilever_large: every equation in it)
  equals the whole-system iteration.
"""
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

HERE = os.path.relpath(os.path.dirname(os.path.abspath(__file__)), sc.ROOT)
SCENE = os.path.join(HERE, 'patch_block.dat')


def energies_agree(tag, a, b, bound):
    e = np.max(a['kinetic'] + a['internal'])
    d = max(np.max(np.abs(a[k] - b[k])) for k in ('kinetic', 'internal', 'dissipated')) / e
    sc.report('%s: ZONE ON = OFF, energies within %.0e of E' % (tag, bound), d <= bound, '%.2e' % d)


def balance_ok(tag, h):
    bal = np.max(np.abs(h['balance'])) / np.max(h['kinetic'] + h['internal'])
    sc.report('%s: |balance| <= 1e-10 of E' % tag, bal <= 1e-10, '%.2e' % bal)


# --- AUTO takes the zone ---------------------------------------------------------------------------
r = subprocess.run([sc.REBOND, SCENE, '-o', sc.new_dir('say')], cwd=sc.ROOT, capture_output=True, text=True)
sc.report('ZONE AUTO iterates on the patch: "nonlinear zone: 30 of 420 equations"',
          r.returncode == 0 and 'nonlinear zone: 30 of 420 equations' in r.stdout, r.stdout[-300:])

# --- the shipped scene ---------------------------------------------------------------------------------
r = subprocess.run([sc.REBOND, 'inputs/block_patch.dat', '-o', sc.new_dir('bp')], cwd=sc.ROOT, capture_output=True,
                   text=True)
sc.report('inputs/block_patch.dat: "nonlinear zone: 30 of 1640 equations, 18 elements"',
          r.returncode == 0 and 'nonlinear zone: 30 of 1640 equations, 18 elements' in r.stdout, r.stdout[-300:])
a = sc.history(sc.run_ok('inputs/block_patch.dat', ['OUTPUT.FIELDS=0']))
b = sc.history(sc.run_ok('inputs/block_patch.dat', ['OUTPUT.FIELDS=0', 'SCHEME.ZONE=OFF']))
energies_agree('inputs/block_patch.dat', a, b, 1e-9)
balance_ok('inputs/block_patch.dat', a)

# --- ON = OFF at every ITERATION ---------------------------------------------------------------------
runs = {}
for it in ('ELASTIC', 'TANGENT', 'AUTO'):
    for zone in ('ON', 'OFF'):
        runs[it, zone] = sc.history(sc.run_ok(SCENE, ['SCHEME.ITERATION=' + it, 'SCHEME.ZONE=' + zone]))
    energies_agree('ITERATION ' + it, runs[it, 'ON'], runs[it, 'OFF'], 1e-9)
    balance_ok('ITERATION %s, ZONE ON' % it, runs[it, 'ON'])
h = runs['AUTO', 'ON']
frac = h['dissipated'][-1] / np.max(h['kinetic'] + h['internal'])
sc.report('the patch yields: dissipated > 5 % of the peak energy', frac > 0.05, '%.3f' % frac)
d = runs['ELASTIC', 'ON']['iterations'] - runs['ELASTIC', 'OFF']['iterations']
same = np.mean(d == 0)
sc.report('ITERATION ELASTIC: per step within one iteration of the whole system\'s, the same in 90 % of the steps',
          np.max(np.abs(d)) <= 1 and same >= 0.9, 'max |difference| %d, same in %.1f %%' % (np.max(np.abs(d)), 100 * same))
ion, ioff = runs['AUTO', 'ON']['iterations'].sum(), runs['AUTO', 'OFF']['iterations'].sum()
sc.report('Newton on the zone: fewer iterations than the whole system\'s AUTO', ion < ioff, '%d against %d' % (ion, ioff))

# --- damping ----------------------------------------------------------------------------------------
text = open(SCENE).read().replace('MODEL m.hard MATERIAL el SECTION plate MASS CONSISTENT PLANE STRAIN',
                                  'MODEL m.hard MATERIAL el SECTION plate MASS CONSISTENT PLANE STRAIN '
                                  'DAMPING ALPHA 2000 BETA 1e-7')
damped = sc.write_scene('damped.dat', text)
for name in ('patch_block.msh',):
    dst = os.path.join(os.path.dirname(damped), name)
    if not os.path.exists(dst):
        os.symlink(os.path.join(sc.ROOT, HERE, name), dst)
a = sc.history(sc.run_ok(damped, ['SCHEME.ZONE=ON']))
b = sc.history(sc.run_ok(damped, ['SCHEME.ZONE=OFF']))
energies_agree('Rayleigh damping', a, b, 1e-9)
balance_ok('Rayleigh damping, ZONE ON', a)

# --- retry --------------------------------------------------------------------------------------------
sets = ['SCHEME.ITERATION=ELASTIC', 'SCHEME.MAX_ITERATIONS=3']
a = sc.history(sc.run_ok(SCENE, sets + ['SCHEME.ZONE=ON']))
sc.report('RETRY under the zone: steps retried as sub-steps', np.sum(a['substeps'] > 1) > 0,
          '%d steps' % np.sum(a['substeps'] > 1))
balance_ok('RETRY, ZONE ON', a)

# --- restart --------------------------------------------------------------------------------------------
same, detail = sc.restart_same(SCENE, ['OUTPUT.CHECKPOINT=50'], '2e-4')
sc.report('restart on the zone: history.csv bit for bit', same, detail)

# --- contact rows ------------------------------------------------------------------------------------
DROP = os.path.join(HERE, 'drop_block.dat')
a_out = sc.run_ok(DROP, ['SCHEME.ZONE=ON'])
a, ca = sc.history(a_out), sc.contacts(a_out)
b = sc.history(sc.run_ok(DROP, ['SCHEME.ZONE=OFF', 'SCHEME.ITERATION=ELASTIC']))
energies_agree('contact (drop_block, against the whole system\'s ITERATION ELASTIC)', a, b, 1e-9)
d = a['iterations'] - b['iterations']
sc.report('contact: per step within one iteration of the whole system\'s ITERATION ELASTIC', np.max(np.abs(d)) <= 1,
          'max |difference| %d' % np.max(np.abs(d)))
balance_ok('contact, ZONE ON', a)
frac = a['dissipated'][-1] / np.max(a['kinetic'] + a['internal'])
sc.report('contact: the patch yields at the impact (dissipated > 1 % of E) and the contact holds',
          frac > 0.01 and np.max(a['active_contacts']) == 5, 'dissipated %.3f of E, max active %d'
          % (frac, np.max(a['active_contacts'])))
gap = np.min(ca['min_gap'])
sc.report('contact: the ground never crossed beyond 1e-9 m', gap >= -1e-9, '%.2e m' % gap)

# --- a LARGE scene forced on the zone --------------------------------------------------------------------
sets = ['TIME.END=0.2']
a = sc.history(sc.run_ok('inputs/cantilever_large.dat', sets + ['SCHEME.ZONE=ON']))
b = sc.history(sc.run_ok('inputs/cantilever_large.dat', sets + ['SCHEME.ZONE=OFF']))
energies_agree('cantilever_large (KINEMATICS LARGE)', a, b, 1e-9)
balance_ok('cantilever_large, ZONE ON', a)
