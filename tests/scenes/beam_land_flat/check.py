"""inputs/beam_land_flat.dat: a horizontal beam landing flat, 21 simultaneous impacts.

In IMPACT PAPER and PERSIST: all 21 nodes close their contact in the same step (uniform fall);
the coupled impulses (14)-(15) of that step are solved (PAPER: no "no all-negative solution"
warning on stderr for the whole run, which rebond prints when the fixed point fails); and
|balance| <= 1e-10 x total energy over the run.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402
import contactcheck as cc  # noqa: E402

SCENE = 'inputs/beam_land_flat.dat'

for mode in ['PAPER', 'PERSIST']:
    tag = 'beam_land_flat %s' % mode
    rc, err, out = sc.run(SCENE, ['SCHEME.IMPACT=' + mode, 'OUTPUT.FIELDS=0'])
    if rc != 0:
        raise RuntimeError('rebond failed (exit %d): %s' % (rc, err.strip()))
    warn = [line for line in err.splitlines() if 'all-negative' in line]
    print('# %s: %d fixed-point warnings on stderr' % (tag, len(warn)))
    sc.report(tag + ': the n-point fixed point converges (no warning)', not warn, warn[0] if warn else '')
    ev = cc.events(out)
    first = [e for e in ev if e[3] == 'establish' and e[0] == ev[0][0]] if ev else []
    print('# %s: %d contacts established in the first impact step (step %s), %d establish events in all'
          % (tag, len(first), ev[0][0] if ev else '-', sum(e[3] == 'establish' for e in ev)))
    sc.report(tag + ': 21 simultaneous impacts', len(first) == 21, '%d in the first impact step' % len(first))
    cc.check_balance(tag, out)
