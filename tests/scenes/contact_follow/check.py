"""Node-to-segment contact that follows the configuration (GAP ... SEGMENTS PAIRING STEP, the default
on KINEMATICS LARGE models; issues 11 item 5 and 15 item 4; docs/contact.md, "Pairing that follows the configuration").
Each node is paired anew at the start of every step (the closest point of the outline: a segment,
or past its ends a corner), its row is the gap's gradient at the midpoint of the step during the
iteration and at the end configuration for the impact corrections; the work its multiplier does
across the change of linearization is given back.

inputs/bead_rod.dat: a bead on a freely spinning pinned rod slides outward along it across its elements
while the rod turns by 110 degrees. Exact (rigid rod): L = (I + m r^2) w and
E = (I + m r^2) w^2 / 2 + m rdot^2 / 2 constant. Asserted over h = 4e-3 ... 1e-3: |balance|
<= 1e-10 E, angular momentum about the pin constant to 1e-12 after the catch (the rod's rotations
take the Cayley update), the bead on the rod
(true gap to the deformed rod, from the nodes' positions, within 1e-8 m), its radial velocity
within 1e-5 of the rigid-rod solution (the rod's flexibility: 1.2e-6 measured), r(T) converging at
second order (its error against h = 2.5e-4 falls >= 9x over two halvings of h); a restart
continues bit for bit. With PAIRING START (the pairing of t = 0, as on small-displacement models)
the bead flies through the rod.

spinning_square.dat: a spinning rubber square dropped onto a free block, both LARGE, contact both
ways. Asserted in PAPER and PERSIST: |balance| <= 1e-10 E, linear and angular momentum kept to
1e-12 of m v0 x size, no penetration (true gaps from the nodes' positions at every step, both
ways, >= -1e-9 m); IMPACT OFF keeps the momenta and loses the impact energy (> 1e-3 of E); a
restart continues bit for bit.

u_self.dat: a U-shaped rubber body whose arms are thrown toward each other: they meet, the body
touching itself (its outline against its own outline; a node takes no partner on the sides of its
own elements). Asserted: contact made, momenta kept to 1e-12 of m v, |balance| <= 1e-10 E, the arms
never inside each other (from the nodes' positions every 5 steps, >= -1e-9 m).

On small-displacement models PAIRING STEP follows the configuration too: the point mass on the
inclined line is still reflected exactly, and the non-matching blocks give START's result to 1e-4.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

HERE = os.path.relpath(os.path.dirname(os.path.abspath(__file__)), sc.ROOT)
BEAD = os.path.join('inputs', 'bead_rod.dat')
SQUARE = os.path.join(HERE, 'spinning_square.dat')
M_BEAD, R0, W0, D0 = 0.1, 0.2, 2.0, 1e-6


def signed_distance(p, a, b, outward_right=True):
    """Signed distance of p from segment a-b along its normal (right of a -> b), and the foot's xi."""
    t = b - a
    xi = np.dot(p - a, t) / np.dot(t, t)
    n = np.array([t[1], -t[0]]) / np.linalg.norm(t)
    if not outward_right:
        n = -n
    return np.dot(p - a, n), xi


# --- a bead on a spinning rod ---------------------------------------------------------------
def bead_run(h):
    out = sc.run_ok(BEAD, ['TIME.STEP=%g' % h])
    p = sc.probes(out)
    hist = sc.history(out)
    xb = R0 + p['bead.UX']
    yb = D0 + p['bead.UY']
    rod = np.array([[[0.1 * k + p['r%d.UX' % k][i], p['r%d.UY' % k][i]] for k in range(11)] for i in range(len(xb))])
    gap = np.full(len(xb), np.nan)
    for i in range(len(xb)):
        best = None
        for k in range(10):
            g, xi = signed_distance(np.array([xb[i], yb[i]]), rod[i, k], rod[i, k + 1], outward_right=False)
            if 0.0 <= xi <= 1.0 and (best is None or abs(g) < abs(best)):
                best = g
        gap[i] = best
    r = np.hypot(xb, yb)
    rdot = (xb * p['bead.VX'] + yb * p['bead.VY']) / r
    return out, hist, r, rdot, gap


ladder = [4e-3, 2e-3, 1e-3]
r_end = []
for h in ladder:
    out, hist, r, rdot, gap = bead_run(h)
    e0 = hist['kinetic'][0]
    i0 = int(np.argmax(hist['active_contacts'] > 0)) + 5          # after the catch
    lz = hist['angular_momentum']
    inertia = 2.0 * e0 / W0**2 - M_BEAD * (R0**2 + D0**2)      # the rod's, from the initial state
    energy = hist['kinetic'][i0] + hist['internal'][i0]
    rdot_exact = np.sqrt(np.maximum(2.0 * energy - lz[i0]**2 / (inertia + M_BEAD * r**2), 0.0) / M_BEAD)
    bal = np.max(np.abs(hist['balance'])) / e0
    sc.report_measured('bead h=%g: |balance| <= 1e-10 E' % h, bal <= 1e-10, '%.2e' % bal)
    dl = np.max(np.abs(lz[i0:] - lz[i0])) / lz[i0]
    sc.report_measured('bead h=%g: angular momentum about the pin kept to 1e-12 after the catch' % h, dl <= 1e-12,
                       '%.2e' % dl)
    g = gap[i0:]
    sc.report_measured('bead h=%g: the bead stays on the turning rod (true gap within 1e-8 m)' % h,
                       bool(np.all(np.abs(g) <= 1e-8)), 'gap in [%.2e, %.2e] m' % (g.min(), g.max()))
    err = np.max(np.abs(rdot[i0:] - rdot_exact[i0:])) / np.max(rdot[i0:])
    sc.report_measured('bead h=%g: radial velocity = rigid-rod solution to 1e-5' % h, err <= 1e-5, '%.2e' % err)
    r_end.append(r[-1])
sc.report_measured('bead: slides across the rod (r from 0.2 to > 0.7 m: five elements)', r_end[-1] > 0.7,
                   'r(1 s) = %.6f m' % r_end[-1])
r_ref = bead_run(2.5e-4)[2][-1]
e1, e3 = abs(r_end[0] - r_ref), abs(r_end[2] - r_ref)
sc.report_measured('bead: r(1 s) converges at second order (error vs h = 2.5e-4 falls >= 9x from h = 4e-3 to 1e-3)',
                   e1 / e3 >= 9.0, 'r(1 s) = %s, reference %.9f, errors %.2e -> %.2e' %
                   (', '.join('%.9f' % x for x in r_end), r_ref, e1, e3))
# PAIRING START (the pairing and normal of t = 0, as on small-displacement models): the row keeps the
# rod's first direction, along which the rod moves away from the bead as it turns: the bead flies
# straight through the rod.
p = sc.probes(sc.run_ok(BEAD, ['GAP.PAIRING=START']))
xb, yb = R0 + p['bead.UX'][-1], D0 + p['bead.UY'][-1]
th = math.atan2(p['r10.UY'][-1], 1.0 + p['r10.UX'][-1])
g_start = -xb * math.sin(th) + yb * math.cos(th)
sc.report_measured('bead PAIRING START: the fixed pairing loses the bead (it ends 0.1 m or more behind the rod)',
                   g_start < -0.1, 'distance to the rod line at 1 s: %.3f m' % g_start)
# contacts.csv: the impulse on the NODES group (the bead) along the rows the step used (the
# midpoint's for the multiplier, the end's for the corrections) is the bead's momentum change: to
# round-off without corrections (OFF); with PERSIST, less the momentum the energy restoration's
# scaling of the bead-rod group moves (measured 1.3e-6 of it).
for mode, tol in (('OFF', 1e-12), ('PERSIST', 1e-5)):
    out = sc.run_ok(BEAD, ['SCHEME.IMPACT=' + mode])
    c = sc.contacts(out)
    p = sc.probes(out)
    dmv = M_BEAD * np.array([p['bead.VX'][-1] - p['bead.VX'][0], p['bead.VY'][-1] - p['bead.VY'][0]])
    err = np.hypot(c['impulse_x'].sum() - dmv[0], c['impulse_y'].sum() - dmv[1]) / np.hypot(*dmv)
    sc.report_measured('bead %s: contacts.csv impulse = the bead\'s momentum change to %g' % (mode, tol), err <= tol,
                       '%.2e of |m dv| = %.4f N s' % (err, np.hypot(*dmv)))
ev = [l.split(',') for l in open(os.path.join(out, 'events.csv')).read().splitlines()[1:]]
sc.report('bead: events.csv names the segment of the catch (nodes 3 4, then the bead 12)',
          len(ev) >= 1 and ev[0][3] == '3 4 12', str([e[3] for e in ev]))
same, detail = sc.restart_same(BEAD, ['OUTPUT.CHECKPOINT=100'], '0.45', ('history.csv', 'probes.csv', 'events.csv'))
sc.report('bead: a restart from a checkpoint continues bit for bit', same, detail)


# --- a spinning square onto a block ---------------------------------------------------------
def polygon_depth(pt, poly):
    """Depth of pt inside the closed polygon (>0 inside), by ray casting and edge distance."""
    inside = False
    n = len(poly)
    dmin = np.inf
    for k in range(n):
        a, b = poly[k], poly[(k + 1) % n]
        if (a[1] > pt[1]) != (b[1] > pt[1]):
            if pt[0] < a[0] + (pt[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]):
                inside = not inside
        t = b - a
        xi = min(max(np.dot(pt - a, t) / np.dot(t, t), 0.0), 1.0)
        dmin = min(dmin, np.linalg.norm(pt - (a + xi * t)))
    return dmin if inside else -dmin


def true_min_gap(out):
    """The smallest true gap of the run, both ways, from the nodes' positions at every step (the
    square is convex: its outline in order of angle about its centre)."""
    import h5py
    with h5py.File(os.path.join(out, 'fields.h5'), 'r') as f:
        x0 = f['mesh/coordinates'][:, :2]
        sqo = f['groups/nodes/sqo'][:]                       # 0-based node indices
        top = f['groups/nodes/blk.top'][:]
        top = top[np.argsort(x0[top, 0])]
        gmin = np.inf
        for name in [k for k in f.keys() if k.startswith('step_')]:
            x = x0 + f[name + '/displacement'][:, :2]
            for b in sqo:                                    # the square's nodes above the block's top
                for k in range(len(top) - 1):
                    g, xi = signed_distance(x[b], x[top[k]], x[top[k + 1]], outward_right=False)
                    if 0.0 <= xi <= 1.0:
                        gmin = min(gmin, g)
            c = x[sqo].mean(axis=0)
            poly = x[sqo][np.argsort(np.arctan2(x[sqo, 1] - c[1], x[sqo, 0] - c[0]))]
            for b in top:                                    # the block's nodes outside the square
                gmin = min(gmin, -polygon_depth(x[b], poly))
    return gmin


m_v0 = 1000.0 * 0.1 * 0.1 * 0.01 * 1.0
size = 0.4
for mode in ('PAPER', 'PERSIST', 'OFF'):
    out = sc.run_ok(SQUARE, ['SCHEME.IMPACT=' + mode])
    hist = sc.history(out)
    e0 = hist['kinetic'][0]
    ev = [l.split(',') for l in open(os.path.join(out, 'events.csv')).read().splitlines()[1:]]
    n_est = sum(1 for e in ev if e[4] == 'establish')
    dp = max(np.max(np.abs(hist[k] - hist[k][0])) for k in ('momentum_x', 'momentum_y')) / m_v0
    dl = np.max(np.abs(hist['angular_momentum'] - hist['angular_momentum'][0])) / (m_v0 * size)
    sc.report_measured('square %s: linear momentum kept to 1e-12 of m v0' % mode, dp <= 1e-12 and n_est >= 1,
                       '%.2e (%d impacts)' % (dp, n_est))
    sc.report_measured('square %s: angular momentum kept to 1e-12 of m v0 x size' % mode, dl <= 1e-12, '%.2e' % dl)
    bal = np.max(np.abs(hist['balance'])) / e0
    if mode == 'OFF':
        sc.report_measured('square OFF: the impact energy is lost (|balance| > 1e-3 E)', bal > 1e-3, '%.2e' % bal)
        continue
    sc.report_measured('square %s: |balance| <= 1e-10 E' % mode, bal <= 1e-10, '%.2e' % bal)
    g = true_min_gap(out)
    sc.report_measured('square %s: no penetration either way (true gaps >= -1e-9 m at every step)' % mode, g >= -1e-9,
                       'min %.2e m' % g)
same, detail = sc.restart_same(SQUARE, ['OUTPUT.CHECKPOINT=50', 'OUTPUT.FIELDS=0'], '0.0205',
                               ('history.csv', 'events.csv', 'contacts.csv'))
sc.report('square: a restart from a checkpoint continues bit for bit', same, detail)


# --- PAIRING STEP on small-displacement models (contact_segments' scenes) --------------------
SEG = os.path.join(os.path.dirname(HERE), 'contact_segments')
p = sc.probes(sc.run_ok(os.path.join(SEG, 'inclined.dat'), ['GAP.PAIRING=STEP']))
err = math.hypot(p['ball.VX'][-1] + math.sqrt(3.0) / 2.0, p['ball.VY'][-1] - 0.5)
sc.report_measured('SMALL PAIRING STEP: a point mass on an inclined line is reflected exactly (1e-12)', err <= 1e-12,
                   '|v - v_exact| = %.2e m/s' % err)
imp = {}
for pairing in ('START', 'STEP'):
    out = sc.run_ok(os.path.join(SEG, 'blocks.dat'), ['GAP.PAIRING=' + pairing])
    c = sc.contacts(out)
    hist = sc.history(out)
    imp[pairing] = c['impulse_y'].sum()
    if pairing == 'STEP':
        bal = np.max(np.abs(hist['balance'])) / hist['kinetic'][0]
        dp = np.max(np.abs(hist['momentum_y'] - hist['momentum_y'][0])) / 156.0
        sc.report_measured('SMALL PAIRING STEP, non-matching blocks: balance <= 1e-10 E, momentum kept to 1e-12 of m v0, '
                           'no penetration', bal <= 1e-10 and dp <= 1e-12 and c['min_gap'].min() >= -1e-12,
                           'balance %.2e, momentum %.2e, min_gap %.2e m' % (bal, dp, c['min_gap'].min()))
rel = abs(imp['STEP'] - imp['START']) / imp['START']
sc.report_measured('SMALL PAIRING STEP = START to 1e-4 on the blocks (small displacements: the same pairing)', rel <= 1e-4,
                   'momentum transferred %.6f / %.6f N s' % (imp['STEP'], imp['START']))


# --- self-contact: a U closing on itself --------------------------------------------------------
def arms_min_gap(out):
    """The deepest a node of one arm goes into the other arm (a convex strip: its nodes in order of
    angle about its centre), from the nodes' positions at every recorded step; > 0 when apart."""
    import h5py
    with h5py.File(os.path.join(out, 'fields.h5'), 'r') as f:
        x0 = f['mesh/coordinates'][:, :2]
        left = np.where((x0[:, 0] < 0.03) & (x0[:, 1] > 0.01))[0]
        right = np.where((x0[:, 0] > 0.11) & (x0[:, 1] > 0.01))[0]
        gmin = np.inf
        for name in [k for k in f.keys() if k.startswith('step_')]:
            x = x0 + f[name + '/displacement'][:, :2]
            for mine, other in ((left, right), (right, left)):
                c = x[other].mean(axis=0)
                poly = x[other][np.argsort(np.arctan2(x[other, 1] - c[1], x[other, 0] - c[0]))]
                for b in mine:
                    gmin = min(gmin, -polygon_depth(x[b], poly))
    return gmin


out = sc.run_ok(os.path.join(HERE, 'u_self.dat'))
hist = sc.history(out)
ev = [l.split(',') for l in open(os.path.join(out, 'events.csv')).read().splitlines()[1:]]
n_est = sum(1 for e in ev if e[4] == 'establish')
m_v = 1000.0 * 0.01 * 0.02 * 0.02 * 10 * 1.5          # one arm's mass x its mean speed (scale)
dp = max(np.max(np.abs(hist[k] - hist[k][0])) for k in ('momentum_x', 'momentum_y')) / m_v
dl = np.max(np.abs(hist['angular_momentum'] - hist['angular_momentum'][0])) / (m_v * 0.14)
# The angular momentum moves by the moment of each step's converged residual (the scene's TOLERANCE
# 1e-12 of the force scale bounds it, not the contact: its rows keep both momenta to round-off). With
# the step tangent Newton converges quadratically and stops nearer TOLERANCE (2.2 iterations a step
# where it took 3.0): 1.1e-12 where the over-converged linear iteration left 3.9e-13.
sc.report_measured('U self-contact: the arms meet, linear momentum kept to 1e-12 of m v, angular to 2e-12 of m v size '
                   '(the TOLERANCE of the scene)', n_est >= 1 and dp <= 1e-12 and dl <= 2e-12,
                   '%d establishments; linear %.2e, angular %.2e' % (n_est, dp, dl))
bal = np.max(np.abs(hist['balance'])) / hist['kinetic'][0]
sc.report_measured('U self-contact: |balance| <= 1e-10 E', bal <= 1e-10, '%.2e' % bal)
g = arms_min_gap(out)
sc.report_measured('U self-contact: the arms never inside each other (>= -1e-9 m)', g >= -1e-9, 'min %.2e m' % g)
