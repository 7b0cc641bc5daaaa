"""SCHEME RETRY (issue 14, item 5): a step whose iteration of eq (9) fails is taken again as two
half steps, down to h/2^RETRY, and the run goes on.

plastic_bar_wall.dat: a hardening elastic-plastic bar hitting a wall at c h/dx = 1, where the
ELASTIC iteration (K0 + 4M/h2, the scene's) does not converge in 25 iterations at step 11 of the impact
(IMPACT AUTO takes PERSIST: a nonlinear law at the contact node; with MASSLESS it was step 15).
- RETRY 0 (the old behaviour): exit 1 at step 11, 'did not converge'.
- The default (RETRY 4): exit 0; the steps that failed are marked in history.csv (substeps 2) and
  their iterations count the failed attempt (>= 26); the balance stays at the iteration tolerance
  (<= 1e-9 of E); the plastic work equals that of the same run at h/2 without retries to 0.1 %
  (the two runs share the sub-stepped steps, the rest differs by the step); one onset.
- A retried step is exactly two steps of h/2: the extremes plastic bar (one step of ~990 yield
  strains, retried as 2 sub-steps) and the same bar run at h/2 give the same state bit for bit.
- A restart from a checkpoint taken inside the retried phase continues bit for bit.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402
import contactcheck as cc  # noqa: E402

HERE = os.path.relpath(os.path.dirname(os.path.abspath(__file__)), sc.ROOT)
WALL = os.path.join(HERE, 'plastic_bar_wall.dat')


def rel_balance(h):
    e = np.max(h['kinetic'] + h['internal'])
    return np.max(np.abs(h['balance'])) / e


rc, err, _ = sc.run(WALL, ['SCHEME.RETRY=0'])
sc.report('RETRY 0: the step fails as before (exit 1, step 11, did not converge)',
          rc == 1 and 'step 11 ' in err and 'did not converge' in err, 'exit %d: %s' % (rc, err.strip()[:120]))

out = sc.run_ok(WALL)
h = sc.history(out)
retried = h['substeps'] > 1
sc.report('RETRY 4: the run goes on, failed steps taken as sub-steps', retried.sum() >= 1 and h['step'][-1] == 80,
          '%d of 80 steps retried, at most %d sub-steps' % (retried.sum(), h['substeps'].max()))
sc.report('RETRY 4: substeps is 1 on the other steps, 0 at t = 0',
          np.all(h['substeps'][1:][~retried[1:]] == 1) and h['substeps'][0] == 0)
sc.report('RETRY 4: a retried step counts the failed attempt (iterations >= 26)',
          np.all(h['iterations'][retried] >= 26), 'min %d' % h['iterations'][retried].min())
bal = rel_balance(h)
sc.report('RETRY 4: |balance| <= 1e-9 of E over the run', bal <= 1e-9, '%.2e' % bal)
h2 = sc.history(sc.run_ok(WALL, ['TIME.STEP=1e-6', 'SCHEME.RETRY=0']))
sc.close('RETRY 4: plastic work = the run at h/2 (0.1 %)', h['dissipated'][-1], h2['dissipated'][-1], 1e-3)
onsets = sum(1 for e in cc.events(out) if e[3] == 'establish')
sc.report('RETRY 4: one contact onset (the plastic bar stays on the wall)', onsets == 1, '%d onsets' % onsets)

# A retried step is two steps of h/2, bit for bit.
PB = 'tests/scenes/extremes/plastic_bar.dat'
a = sc.run_ok(PB)
b = sc.run_ok(PB, ['TIME.STEP=5e-4', 'SCHEME.RETRY=0'])
ha, hb = sc.history(a), sc.history(b)
pa, pb = sc.probes(a), sc.probes(b)
same = all(ha[k][-1] == hb[k][-1] for k in ('kinetic', 'internal', 'dissipated', 'balance')) and \
    pa['tip.UX'][-1] == pb['tip.UX'][-1]
sc.report('one step retried as 2 sub-steps = 2 steps of h/2 (bit for bit)', same and ha['substeps'][-1] == 2,
          'kinetic %.17g vs %.17g' % (ha['kinetic'][-1], hb['kinetic'][-1]))

# Restart inside the retried phase: checkpoint at step 20, continue to the end.
full = sc.run_ok(WALL, ['OUTPUT.CHECKPOINT=20'])
part = sc.new_dir('retry_part')
rc, err, _ = sc.run(WALL, ['OUTPUT.CHECKPOINT=20', 'TIME.END=4e-5'], outdir=part)
cmd = [sc.REBOND, WALL, '-o', part, '--quiet', '--restart', os.path.join(part, 'checkpoint.h5'),
       '--set', 'OUTPUT.CHECKPOINT=20']
r = sc.run_limited(cmd, 120, cwd=sc.ROOT, capture_output=True, text=True)
with open(os.path.join(full, 'history.csv'), 'rb') as f1, open(os.path.join(part, 'history.csv'), 'rb') as f2:
    same = f1.read() == f2.read()
sc.report('restart inside the retried phase: history.csv bit for bit', rc == 0 and r.returncode == 0 and same,
          'exit %d, %d: %s' % (rc, r.returncode, r.stderr[-200:]))

# --- SCHEME ITERATION AUTO: the tangent where it pays (iteration_matrix) ----------------------
ha = sc.history(sc.run_ok(WALL, ['SCHEME.ITERATION=AUTO']))
ht = sc.history(sc.run_ok(WALL, ['SCHEME.ITERATION=TANGENT']))
ia, ie = ha['iterations'].sum(), h['iterations'].sum()
sc.report('AUTO on the plastic bar: at most 1/4 of the ELASTIC iterations', ia <= ie / 4, '%d vs %d' % (ia, ie))
bal = rel_balance(ha)
sc.report('AUTO on the plastic bar: |balance| <= 1e-10 of E', bal <= 1e-10, '%.2e' % bal)
sc.close('AUTO on the plastic bar: plastic work = TANGENT (1e-4)', ha['dissipated'][-1], ht['dissipated'][-1], 1e-4)
hb_e = sc.history(sc.run_ok('inputs/block_j2.dat', ['TIME.END=1e-3', 'SCHEME.ITERATION=ELASTIC']))
hb_a = sc.history(sc.run_ok('inputs/block_j2.dat', ['TIME.END=1e-3', 'SCHEME.ITERATION=AUTO']))
sc.report('AUTO on the von Mises block: fewer iterations than ELASTIC, balance <= 1e-10',
          hb_a['iterations'].sum() < hb_e['iterations'].sum() and rel_balance(hb_a) <= 1e-10,
          '%d vs %d, balance %.2e' % (hb_a['iterations'].sum(), hb_e['iterations'].sum(), rel_balance(hb_a)))
lin = ['TIME.END=2e-4']
same = open(os.path.join(sc.run_ok('inputs/bar_impact.dat', lin), 'history.csv')).read() == \
    open(os.path.join(sc.run_ok('inputs/bar_impact.dat', lin + ['SCHEME.ITERATION=AUTO']), 'history.csv')).read()
sc.report('AUTO on a linear scene = ELASTIC bit for bit', same)
# A restart carries AUTO's matrix (a tangent factorized in an earlier step) in the checkpoint.
sets = ['SCHEME.ITERATION=AUTO', 'OUTPUT.CHECKPOINT=20']
full = sc.run_ok(WALL, sets)
part = sc.new_dir('auto_part')
rc, err, _ = sc.run(WALL, sets + ['TIME.END=4e-5'], outdir=part)
cmd = [sc.REBOND, WALL, '-o', part, '--quiet', '--restart', os.path.join(part, 'checkpoint.h5')]
for s in sets:
    cmd += ['--set', s]
r = sc.run_limited(cmd, 120, cwd=sc.ROOT, capture_output=True, text=True)
with open(os.path.join(full, 'history.csv'), 'rb') as f1, open(os.path.join(part, 'history.csv'), 'rb') as f2:
    same = f1.read() == f2.read()
sc.report('AUTO: restart from a checkpoint taken on a tangent, history.csv bit for bit',
          rc == 0 and r.returncode == 0 and same, 'exit %d, %d: %s' % (rc, r.returncode, r.stderr[-200:]))
