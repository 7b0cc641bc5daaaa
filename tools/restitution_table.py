#!/usr/bin/python3
"""What RESTITUTION e means on a deformable body (issue 37, item 8): e is Newton's law for the
impacting nodes (their normal velocity after the correction is -e times before), not the
bodies' coefficient of restitution. This measures the body-level coefficient, from the bodies'
momenta after they part, against e:

- two aluminium blocks, TRI6 below (6 x 2) and QUAD8 above (4 x 2), 100 x 50 mm each, 10 mm thick,
  0.1 mm apart, non-matching faces with GAP ... SEGMENTS in both passes; the upper block falls at 1 m/s on the
  lower one at rest, no gravity, no support. Each block's momentum after the impact is its
  momentum before plus the impulses contacts.csv books on it (NODES side of one pass, the
  opposite of the other's); e_body = (v_up - v_lo) / 1 m/s (the separation over the approach speed);
- the rubber ring of inputs/ring.msh (QUAD4) thrown at 5 m/s against a rigid wall;
  e_body = -p_x(end) / p_x(0).
With the fraction of the kinetic energy impact_dissipated holds at the end, against the rigid
bodies' 1 - e^2. Writes the table to docs/contact.md between restitution:begin and :end with
--write.
"""
import csv
import os
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REBOND = os.path.join(ROOT, 'bin', 'rebond')
sys.dont_write_bytecode = True
sys.path.insert(0, os.path.join(ROOT, 'tools'))
from docblock import replace_block  # noqa: E402

BLOCKS = '''RECTANGLE lo ORIGIN 0 0 SIZE 0.1 0.05 ELEMENTS 6 2 TYPE TRI6
RECTANGLE up ORIGIN 0.005 0.0501 SIZE 0.1 0.05 ELEMENTS 4 2 TYPE QUAD8
MATERIAL alu ELASTIC YOUNG 7e10 POISSON 0.33 DENSITY 2700
SECTION t THICKNESS 0.01
MODEL lo MATERIAL alu SECTION t PLANE STRESS
MODEL up MATERIAL alu SECTION t PLANE STRESS
INITIAL up VELOCITY 0 -1
GAP face NODES up.bottom SEGMENTS lo.top RESTITUTION {e}
GAP back NODES lo.top SEGMENTS up.bottom RESTITUTION {e}
TIME STEP 2e-7 END 4e-4
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0
'''
RING = '''GMSH rg FILE {mesh}
MATERIAL rubber ELASTIC YOUNG 1e7 POISSON 0.3 DENSITY 1000
SECTION t THICKNESS 0.01
MODEL rg.ring MATERIAL rubber SECTION t
INITIAL rg.ring VELOCITY 5 0
OBSTACLE wall NODES rg.outer POINT 0.105 0 NORMAL -1 0 RESTITUTION {e}
TIME STEP 2e-4 END 0.04
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0
'''


def run(text, tmp, tag):
    path = os.path.join(tmp, tag + '.dat')
    with open(path, 'w') as f:
        f.write(text)
    out = os.path.join(tmp, tag)
    p = subprocess.run([REBOND, path, '-o', out, '--quiet'], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(p.stderr)
    h = np.genfromtxt(os.path.join(out, 'history.csv'), delimiter=',', names=True)
    with open(os.path.join(out, 'contacts.csv'), newline='') as f:
        c = list(csv.DictReader(f))
    return h, c


def blocks(e, tmp):
    h, c = run(BLOCKS.format(e=e), tmp, 'blocks_%g' % e)
    m = 2700 * 0.1 * 0.05 * 0.01
    iy = {'face': 0.0, 'back': 0.0}
    for r in c:
        iy[r['contact']] += float(r['impulse_y'])
    p_up = -m * 1.0 + iy['face'] - iy['back']       # the upper block: NODES of face, SEGMENTS of back
    p_lo = 0.0 + iy['back'] - iy['face']
    v_up, v_lo = p_up / m, p_lo / m
    e0 = h['kinetic'][0]
    return (v_up - v_lo) / 1.0, h['impact_dissipated'][-1] / e0, (v_up, v_lo), np.abs(h['balance']).max() / e0, \
        abs(h['momentum_y'][-1] - h['momentum_y'][0]) / (m * 1.0), h['active_contacts'][-1]


def ring(e, tmp):
    h, c = run(RING.format(e=e, mesh=os.path.join(ROOT, 'inputs', 'ring.msh')), tmp, 'ring_%g' % e)
    e0 = h['kinetic'][0]
    return -h['momentum_x'][-1] / h['momentum_x'][0], h['impact_dissipated'][-1] / e0, \
        np.abs(h['balance']).max() / e0, h['active_contacts'][-1]


def main():
    rows = ['', '| body | e (nodes) | e_body measured | energy dissipated (impact_dissipated / E) | '
            'rigid bodies: 1 − e² of the normal energy | after |', '|---|---|---|---|---|---|']
    with tempfile.TemporaryDirectory() as tmp:
        for e in (1.0, 0.5, 0.0):
            eb, dis, (vu, vl), bal, dp, act = blocks(e, tmp)
            print('blocks e=%g: e_body %.3f, dissipated %.2f %%, v_up %.3f, v_lo %.3f m/s, balance %.1e, '
                  'momentum %.1e, active at the end %d' % (e, eb, 100 * dis, vu, vl, bal, dp, act), flush=True)
            rows.append('| two blocks (TRI6, QUAD8) | %g | %.3f | %.2f %% | %.1f %% | v_up %.3f, v_lo %.3f m/s%s |'
                        % (e, eb, 100 * dis, 100 * (1 - e * e) / 2, vu, vl, '' if act == 0 else ', still touching'))
        for e in (1.0, 0.5, 0.0):
            eb, dis, bal, act = ring(e, tmp)
            print('ring e=%g: e_body %.3f, dissipated %.2f %%, balance %.1e, active at the end %d'
                  % (e, eb, 100 * dis, bal, act), flush=True)
            rows.append('| ring on a wall (QUAD4) | %g | %.3f | %.2f %% | %.1f %% | %s |'
                        % (e, eb, 100 * dis, 100 * (1 - e * e), 'left the wall' if act == 0 else 'still touching'))
    block = '\n'.join(rows) + '\n\n'
    print(block)
    if '--write' in sys.argv:
        replace_block(os.path.join(ROOT, 'docs', 'contact.md'), '<!-- restitution:begin -->',
                      '<!-- restitution:end -->', block)
    return 0


if __name__ == '__main__':
    sys.exit(main())
