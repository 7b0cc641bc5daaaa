"""PRESSURE on a KINEMATICS LARGE model follows the deformed sides (issue 37, item 10;
src/assembly/follower_loads.f90), with its load stiffness in the tangent and its work booked by
the scheme's trapezoid rule; the word DEAD keeps the reference sides' forces.

spin.dat: a rubber square spinning at 1000 rad/s under a pressure ramped to 0.5 MPa on its whole
boundary, QUAD4 8 x 8 and QUAD8 4 x 4. A follower pressure on a closed contour has no resultant,
no moment and the potential p t A (A the enclosed area, quadratic in the nodes):
- linear momentum zero to 1e-12 of m omega a; balance <= 1e-10 of the energy;
- angular momentum constant to 1e-10 once the pressure is constant (t >= 1 ms; while it ramps the
  trapezoid's F(n) + F(n+1) at two pressures leaves a second-order moment, measured and printed);
- the work booked from 1 ms to the end equals -p t (A(end) - A(1 ms)) to 1e-12 of p t A0, the area
  of the deformed boundary from fields.h5 (exact for 2- and 3-node sides);
- DEAD: the same run's reference-side forces exert a moment on the turned square: its angular
  momentum changes by more than 10 % (the dead-load drift the issue measured), balance still exact.

block.dat: a soft block turned 30 degrees, clamped at the bottom, pressures on its top and left
sides, damped to rest. The support reaction (RX, RY) balances the pressures on the deformed sides,
-p t times each deformed chord's outward normal, to 1e-9 (the left side's bottom node is held: its
share reaches the reaction through the follower's reaction entries); with DEAD, the reference
sides' totals. The two differ by 0.3 % of the load: the test tells them apart.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402
import h5py  # noqa: E402

HERE = os.path.relpath(os.path.dirname(os.path.abspath(__file__)), sc.ROOT)
P, T = 5e5, 0.01


def dead(name):
    """The scene name with every PRESSURE said DEAD, written to a new file."""
    with open(os.path.join(sc.ROOT, HERE, name)) as f:
        text = f.read()
    lines = [ln + ' DEAD' if ln.startswith('PRESSURE ') else ln for ln in text.splitlines()]
    return sc.write_scene('dead_' + name, '\n'.join(lines) + '\n')


def boundary_area(f, step, quadratic):
    """Area enclosed by the deformed boundary of the square at step (nodes sorted by angle)."""
    x0 = f['mesh/coordinates'][...][:, :2]
    x = x0 + f['step_%06d/displacement' % step][...][:, :2]
    b = set()
    for g in ('top', 'bottom', 'left', 'right'):
        b |= set(f['groups/nodes/sq.' + g][...].tolist())
    b = np.array(sorted(b))
    b = b[np.argsort(np.arctan2(x0[b, 1], x0[b, 0]))]
    p = x[b]
    if not quadratic:
        return 0.5 * np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1])
    # Sides (corner, mid-side, corner): A = sum of the integrals of (x y' - y x') / 2 over s in
    # [-1, 1], 2-point Gauss (the integrand is cubic).
    c = x0[b[0]] / 0.025                               # start at an element corner (4 x 4: a 0.025 m grid)
    if np.max(np.abs(c - np.round(c))) > 1e-9:
        p = np.roll(p, -1, axis=0)
    area = 0.0
    g = 1.0 / math.sqrt(3.0)
    for k in range(0, len(p), 2):
        xa, xm, xb = p[k], p[k + 1], p[(k + 2) % len(p)]
        for s in (-g, g):
            n = np.array([0.5 * s * (s - 1), 1 - s * s, 0.5 * s * (s + 1)])
            dn = np.array([s - 0.5, -2 * s, s + 0.5])
            xs = n[0] * xa + n[1] * xm + n[2] * xb
            ds = dn[0] * xa + dn[1] * xm + dn[2] * xb
            area += 0.5 * (xs[0] * ds[1] - xs[1] * ds[0])
    return area


for tag, sets in [('QUAD4 8 x 8', []), ('QUAD8 4 x 4', ['RECTANGLE.TYPE=QUAD8', 'RECTANGLE.ELEMENTS=4 4'])]:
    out = sc.run_ok(os.path.join(HERE, 'spin.dat'), sets)
    h = sc.history(out)
    e = np.max(h['kinetic'] + h['internal'])
    bal = np.max(np.abs(h['balance'])) / e
    sc.report('spin %s: |balance| <= 1e-10 of the energy' % tag, bal <= 1e-10, '%.2e' % bal)
    mom = max(np.max(np.abs(h['momentum_x'])), np.max(np.abs(h['momentum_y']))) / (0.1 * 1000 * 0.05)
    sc.report('spin %s: linear momentum zero (1e-12 of m omega a)' % tag, mom <= 1e-12, '%.2e' % mom)
    am = h['angular_momentum']
    late = h['time'] >= 1e-3 - 1e-12
    drift = np.max(np.abs(am[late] - am[late][0])) / abs(am[0])
    sc.report('spin %s: angular momentum constant under the constant follower pressure (1e-10)' % tag,
              drift <= 1e-10, '%.2e' % drift)
    ramp = np.max(np.abs(am - am[0])) / abs(am[0])
    sc.report_measured('spin %s: angular momentum change during the ramp (second order, printed)' % tag, True,
                       '%.2e' % ramp)
    with h5py.File(os.path.join(out, 'fields.h5'), 'r') as f:
        quad = 'QUAD8' in tag
        a0, a1, a2 = (boundary_area(f, s, quad) for s in (0, 50, 200))
    w = h['external'][200] - h['external'][50]
    err = abs(w + P * T * (a2 - a1)) / (P * T * a0)
    sc.report('spin %s: work booked = -p t dA after the ramp (1e-12 of p t A0)' % tag, err <= 1e-12,
              'work %.6e, -p t dA %.6e, error %.2e' % (w, -P * T * (a2 - a1), err))
    sc.report('spin %s: the pressure did squeeze the square (A(end) < A0 by > 1 %%)' % tag, a2 < 0.99 * a0,
              'A0 %.6e A %.6e' % (a0, a2))
    hd = sc.history(sc.run_ok(dead('spin.dat'), sets))
    dd = np.max(np.abs(hd['angular_momentum'] - hd['angular_momentum'][0])) / abs(am[0])
    sc.report('spin %s DEAD: the reference sides\' forces turn the spinning square (dL > 10 %%)' % tag, dd > 0.1,
              '%.2e' % dd)
    bd = np.max(np.abs(hd['balance'])) / np.max(hd['kinetic'] + hd['internal'])
    sc.report('spin %s DEAD: |balance| <= 1e-10 of the energy' % tag, bd <= 1e-10, '%.2e' % bd)

S, C = math.sin(math.pi / 6), math.cos(math.pi / 6)
PB, TB = 1e6, 0.1


def chord_force(x0, x, nodes, direction):
    """-p t times the outward chord normal of the side made of nodes, from end to end along
    direction (the body on its left when walked counter-clockwise)."""
    s = x0[nodes] @ direction
    a, b = x[nodes[np.argmin(s)]], x[nodes[np.argmax(s)]]
    ch = b - a
    return -PB * TB * np.array([ch[1], -ch[0]])


for tag, scene in [('follower', os.path.join(HERE, 'block.dat')), ('DEAD', dead('block.dat'))]:
    out = sc.run_ok(scene)
    p = sc.probes(out)
    with h5py.File(os.path.join(out, 'fields.h5'), 'r') as f:
        x0 = f['mesh/coordinates'][...][:, :2]
        x = x0 + (f['step_001500/displacement'][...][:, :2] if tag == 'follower' else 0.0)
        top, left = f['groups/nodes/blk.top'][...], f['groups/nodes/blk.left'][...]
    # The top walked right to left and the left side top to bottom keep the body on their left.
    f_top = chord_force(x0, x, top, -np.array([C, S]))
    f_left = chord_force(x0, x, left, -np.array([-S, C]))
    r = -(f_top + f_left)
    scale = PB * TB
    for k, comp in enumerate(('RX', 'RY')):
        sc.close('block %s: %s at rest balances the pressures on the %s sides' %
                 (tag, comp, 'deformed' if tag == 'follower' else 'reference'), p['blk.bottom.' + comp][-1], r[k],
                 1e-9)
    if tag == 'follower':
        moved = np.max(np.abs(r - (-(chord_force(x0, x0, top, -np.array([C, S])) +
                                     chord_force(x0, x0, left, -np.array([-S, C])))))) / scale
        sc.report('block: the deformed sides\' totals differ from the reference ones (> 1e-3 of p t)', moved > 1e-3,
                  '%.2e' % moved)
    h = sc.history(out)
    bal = abs(h['balance']).max() / abs(h['external']).max()
    sc.report('block %s: |balance| <= 1e-10 x external work (damping booked)' % tag, bal <= 1e-10, '%.3e' % bal)
