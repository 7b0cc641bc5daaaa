"""Node-to-segment contact (GAP name NODES ga SEGMENTS gs, issue 11): each node of ga paired at
t = 0 with the closest segment of gs it projects onto; one multiplier row couples the node
with the segment's two ends (weights 1, -(1 - xi), -xi) along the segment's normal.

inclined.dat: a point mass thrown at a rigid line inclined at 30 deg (fixed BAR2 elements), hitting
the second element at xi = 0.4. IMPACT PAPER on a point mass is an exact elastic reflection about
the surface: v = (0, -1) -> (-sqrt(3)/2, 1/2), asserted to 1e-12; kinetic energy kept; one
impact; the gap never below -1e-12 m. With RESTITUTION 0.5, Newton's law on the normal velocity:
(-0.6495, 0.125) m/s, 0.5625 J booked as impact_dissipated, the balance at round-off.

blocks.dat: two free steel blocks of equal impedance (nu = 0: bars along y, H = 0.2 m) meet
through non-matching faces (7 against 4 elements). Exact 1D waves: contact 2H/c, the blocks
exchange velocities (momentum transferred m v0 = 156 N s). Asserted, PAPER and PERSIST: balance
<= 1e-10 of the energy, linear and angular momentum kept to 1e-12 of m v0 (both bodies are free),
no penetration (min_gap >= -1e-12 m at every step). Then, PERSIST:
- matching faces (4 against 4): SEGMENTS gives the node-to-node GAP ... WITH result (the same
  rows): contacts.csv equal to 1e-9 relative;
- non-matching, one pass (the 4 nodes of the upper face against the lower segments): the lower
  face's nodes between are free to enter the upper block's sides, the momentum transferred is
  5.5 % low (measured, reported);
- non-matching, two passes (each face's nodes against the other's segments): the momentum
  transferred equals the matching meshes' to 1e-9 (1e-14 measured: the motion is uniform
  across the faces), and is within 1.5 % of m v0 (the spatial error of 20 elements through the
  height, the same with matching meshes).
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402
import contactcheck as cc  # noqa: E402

HERE = os.path.relpath(os.path.dirname(os.path.abspath(__file__)), sc.ROOT)
M_V0 = 7800.0 * 1.0 * 0.2 * 0.1 * 1.0          # upper block: rho * area * thickness * v0


def no_penetration(tag, out):
    c = sc.contacts(out)
    g = c['min_gap'].min()
    return sc.report(tag + ': no penetration (min_gap >= -1e-12 m at every step)', g >= -1e-12, 'min_gap %.3e' % g)


# --- a point mass on an inclined rigid line -----------------------------------------------
out = sc.run_ok(os.path.join(HERE, 'inclined.dat'))
p = sc.probes(out)
ev = cc.events(out)
n_est = sum(1 for e in ev if e[3] == 'establish')
sc.report('inclined: one impact', n_est == 1, '%d establish events' % n_est)
after = p['time'] > 0.6
for col, exact in [('ball.VX', -math.sqrt(3.0) / 2.0), ('ball.VY', 0.5)]:
    err = np.abs(p[col][after] - exact).max()
    sc.report('inclined: %s after the impact = %.6f (1e-12)' % (col, exact), err <= 1e-12, 'error %.3e' % err)
cc.check_balance('inclined', out)
no_penetration('inclined', out)
with open(os.path.join(out, 'events.csv')) as f:
    f.readline()
    nodes = f.readline().split(',')[3]
sc.report('inclined: events.csv names the segment 2-3 and the node 6', nodes == '2 3 6', 'nodes "%s"' % nodes)
# RESTITUTION 0.5: Newton's law on the normal velocity, v' = v_t - e v_n n: (-0.6495, 0.125), the
# kinetic energy (1 - e^2) x 1/2 m v_n^2 = 0.5625 J booked as impact_dissipated.
out = sc.run_ok(os.path.join(HERE, 'inclined.dat'), ['GAP.RESTITUTION=0.5'])
p = sc.probes(out)
h = sc.history(out)
after = p['time'] > 0.6
vn = math.sqrt(3.0) / 2.0                          # |v . n| before the impact
for col, exact in [('ball.VX', -0.25 * math.sqrt(3.0) - 0.5 * vn * 0.5), ('ball.VY', -0.25 + 0.5 * vn * vn)]:
    err = np.abs(p[col][after] - exact).max()
    sc.report('inclined, RESTITUTION 0.5: %s after = %.6f (1e-12)' % (col, exact), err <= 1e-12, 'error %.3e' % err)
sc.close('inclined, RESTITUTION 0.5: impact_dissipated = (1 - e^2) m vn^2 / 2', h['impact_dissipated'][-1],
         0.75 * 0.5 * 2.0 * vn**2, 1e-12)
cc.check_balance('inclined, RESTITUTION 0.5', out)

# --- two free blocks ---------------------------------------------------------------------
with open(os.path.join(sc.ROOT, HERE, 'blocks.dat')) as f:
    BLOCKS = f.read()
TWO = BLOCKS.replace('GAP face NODES up.bottom SEGMENTS lo.top',
                     'GAP face NODES up.bottom SEGMENTS lo.top\nGAP back NODES lo.top SEGMENTS up.bottom')
MATCH = BLOCKS.replace('ELEMENTS 7 20', 'ELEMENTS 4 20')
MATCH_NODES = MATCH.replace('SEGMENTS lo.top', 'WITH lo.top')
assert TWO != BLOCKS and MATCH != BLOCKS and MATCH_NODES != MATCH


def transferred(out):
    """Momentum the upper block received (upwards): the impulses on the NODES group of face
    (its nodes) minus those on the NODES group of back (the lower face's nodes, whose segments
    are the upper block's)."""
    c = sc.contacts(out)
    up = c['impulse_y'][c['contact'] == 'face'].sum()
    lo = c['impulse_y'][c['contact'] == 'back'].sum() if np.any(c['contact'] == 'back') else 0.0
    return up - lo


for mode in ['PAPER', 'PERSIST']:
    out = sc.run_ok(os.path.join(HERE, 'blocks.dat'), ['SCHEME.IMPACT=' + mode])
    h = sc.history(out)
    sc.report('blocks %s: the blocks collide' % mode, np.any(h['active_contacts'] > 0))
    cc.check_balance('blocks ' + mode, out)
    for col in ['momentum_x', 'momentum_y', 'angular_momentum']:
        drift = np.abs(h[col] - h[col][0]).max()
        sc.report('blocks %s: %s kept (1e-12 m v0)' % (mode, col), drift <= 1e-12 * M_V0, 'drift %.3e' % drift)
    no_penetration('blocks ' + mode, out)
one_pass = transferred(out)

match_seg = sc.run_ok(sc.write_scene('match_segments.dat', MATCH))
match_nodes = sc.run_ok(sc.write_scene('match_nodes.dat', MATCH_NODES))
a, b = sc.contacts(match_seg), sc.contacts(match_nodes)
for col in ['force_y', 'impulse_y']:
    # WITH reports the force on its NODES group (the upper face), SEGMENTS too: the same sign.
    d = np.abs(a[col] - b[col]).max() / np.abs(b[col]).max()
    sc.report('matching faces: SEGMENTS %s = node-to-node (1e-9)' % col, d <= 1e-9, 'relative difference %.3e' % d)
m_match = b['impulse_y'].sum()
two = sc.run_ok(sc.write_scene('blocks_two.dat', TWO), ['SCHEME.IMPACT=PERSIST'])
m_two = transferred(two)
print('# momentum transferred: exact %.4f, matching %.4f, non-matching two passes %.4f, one pass %.4f'
      % (M_V0, m_match, m_two, one_pass))
sc.close('non-matching, two passes: momentum transferred = matching meshes', m_two, m_match, 1e-9)
sc.close('non-matching, two passes: momentum transferred = m v0', m_two, M_V0, 0.015)
sc.report('non-matching, one pass: momentum transferred below the two-pass one', one_pass < m_two,
          '%.4f vs %.4f' % (one_pass, m_two))
no_penetration('blocks two passes', two)
cc.check_balance('blocks two passes', two)
