"""SCHEME MULTIPLIERS: the Schur columns and the augmented sparse system give the same run.

A steel slab (QUAD4, plane strain, lumped mass) lands flat on a rigid ground in IMPACT PERSIST:
its NX + 1 bottom nodes close in one step and stay closed. Asserted:
- SCHUR, AUGMENTED and AUTO (switching at AUGMENTED_ABOVE 10) agree: kinetic, internal and
  correction within 1e-9 x the total energy (both solve the same KKT system to round-off; the
  LCP tolerance is 1e-12 of the model size), and |balance| <= 1e-10 x total energy for each;
- SCHUR computes one column per condition that was ever active (NX + 1, once: the cost follows
  the contact zone), AUGMENTED factorizes once per distinct active set (here: the closed set
  persists, so one LU serves every step after the landing);
- inputs/beam_land_flat.dat in IMPACT PAPER (21 coupled impacts, bounces, consistent mass) and
  inputs/beams_collide.dat in PERSIST (node-to-node GAP conditions between two bodies): the same
  events and energies with AUGMENTED as with SCHUR.
"""
import os
import re
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402
import contactcheck as cc  # noqa: E402

NX = 40
STEPS = 30
SLAB = """TITLE     "slab landing flat"
RECTANGLE slab ORIGIN 0 1e-6 SIZE %g 0.2 ELEMENTS %d 2 TYPE QUAD4
MATERIAL  steel ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800
SECTION   strip THICKNESS 1
MODEL     slab MATERIAL steel SECTION strip MASS LUMPED PLANE STRAIN
INITIAL   slab VELOCITY 0 -1
OBSTACLE  ground NODES slab.bottom POINT 0 0 NORMAL 0 1
TIME      STEP 1e-6 END %g
SCHEME    IMPACT PERSIST
OUTPUT    HISTORY EVERY 1 FIELDS EVERY 0
""" % (0.05 * NX, NX, STEPS * 1e-6)


def run_counted(scene, sets):
    """Run rebond (not quiet) and read the multiplier counters of its summary."""
    out = sc.new_dir('mult')
    cmd = [sc.REBOND, scene, '-o', out]
    for s in sets:
        cmd += ['--set', s]
    p = sc.run_limited(cmd, 120, cwd=sc.ROOT, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError('rebond %s failed (exit %d): %s' % (' '.join(sets), p.returncode, p.stderr.strip()))
    m = re.search(r'contact multipliers: (\d+) Schur solves \((\d+) columns\), (\d+) augmented solves \((\d+) LU\)',
                  p.stdout)
    counts = tuple(int(x) for x in m.groups()) if m else (0, 0, 0, 0)
    return out, counts


def same_energies(tag, a, b):
    ha, hb = sc.history(a), sc.history(b)
    scale = np.max(np.abs(ha['kinetic'] + ha['internal']))
    err = max(np.max(np.abs(ha[k] - hb[k])) for k in ('kinetic', 'internal', 'correction')) / scale
    same_active = np.array_equal(ha['active_contacts'], hb['active_contacts'])
    print('# %s: max energy difference / total = %.3e, active counts equal: %s' % (tag, err, same_active))
    sc.report(tag + ': same energies (1e-9 x total) and active counts', err <= 1e-9 and same_active,
              'difference %.3e, active equal %s' % (err, same_active))


scene = os.path.join(sc.TMP, 'slab.dat')
with open(scene, 'w') as f:
    f.write(SLAB)
runs = {}
for mode, extra in [('SCHUR', []), ('AUGMENTED', []), ('AUTO', ['SCHEME.AUGMENTED_ABOVE=10'])]:
    runs[mode] = run_counted(scene, ['SCHEME.MULTIPLIERS=' + mode] + extra)
    cc.check_balance('slab %s' % mode, runs[mode][0])
h = sc.history(runs['SCHUR'][0])
sc.report('slab: every bottom node closes and stays closed (%d)' % (NX + 1),
          np.all(h['active_contacts'][3:] == NX + 1), 'active counts %s' % h['active_contacts'][:8])
same_energies('slab AUGMENTED vs SCHUR', runs['SCHUR'][0], runs['AUGMENTED'][0])
same_energies('slab AUTO vs SCHUR', runs['SCHUR'][0], runs['AUTO'][0])
s_solves, s_cols, _, _ = runs['SCHUR'][1]
_, _, a_solves, a_lu = runs['AUGMENTED'][1]
print('# slab SCHUR: %d solves, %d columns; AUGMENTED: %d solves, %d LU' % (s_solves, s_cols, a_solves, a_lu))
sc.report('slab SCHUR: one column per condition ever active (%d)' % (NX + 1), s_cols == NX + 1,
          '%d columns' % s_cols)
changes = 1 + int(np.count_nonzero(np.diff(h['active_contacts'][1:]) != 0))
sc.report('slab AUGMENTED: LU only when the active set changes (<= %d), solves every iteration' % (changes + 2),
          0 < a_lu <= changes + 2 and a_solves >= STEPS - 3, '%d LU, %d solves' % (a_lu, a_solves))
a_schur = runs['AUTO'][1]
sc.report('slab AUTO: the large set goes to the augmented system', a_schur[2] > 0 and a_schur[3] > 0,
          'counts %s' % (a_schur,))

for tag, scene, sets in [('beam_land_flat PAPER', 'inputs/beam_land_flat.dat', ['TIME.END=0.12']),
                         ('beams_collide PERSIST', 'inputs/beams_collide.dat', ['SCHEME.IMPACT=PERSIST'])]:
    outs = {}
    for mode in ['SCHUR', 'AUGMENTED']:
        outs[mode] = run_counted(scene, ['SCHEME.MULTIPLIERS=' + mode, 'OUTPUT.FIELDS=0'] + sets)
        cc.check_balance('%s %s' % (tag, mode), outs[mode][0])
    sc.report('%s: AUGMENTED used the augmented system (%d solves)' % (tag, outs['AUGMENTED'][1][2]),
              outs['AUGMENTED'][1][2] > 0, 'counts %s' % (outs['AUGMENTED'][1],))
    same_energies('%s AUGMENTED vs SCHUR' % tag, outs['SCHUR'][0], outs['AUGMENTED'][0])
    ea, eb = cc.events(outs['SCHUR'][0]), cc.events(outs['AUGMENTED'][0])
    sc.report('%s: identical event lists (%d events)' % (tag, len(ea)),
              [(e[0], e[2], e[3]) for e in ea] == [(e[0], e[2], e[3]) for e in eb],
              '%d vs %d events' % (len(ea), len(eb)))
