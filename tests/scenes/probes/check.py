"""Velocity probes (issue 13, item 6): PROBE group VX|VY|VRZ writes the velocity of the DOF.

- the point mass in free fall: VY = -g t exactly (the average-acceleration scheme integrates a
  constant acceleration exactly) until the first impact, and ½ m (VX² + VY²) is the kinetic
  energy of history.csv at every step, impacts included;
- the cantilever beam (no contact): the probed columns satisfy the scheme's eq (3),
  u(n+1) - u(n) = h/2 (v(n) + v(n+1)), for UY/VY and RZ/VRZ of the tip, to round-off;
- a velocity probe of a DOF the node does not carry (VRZ of a point mass) is an input error.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402


def free_fall():
    out = sc.run_ok('inputs/mass_bounce.dat', ['TIME.END=2', 'OUTPUT.PROBE=ball UY ball VX ball VY'])
    p = sc.read_csv(os.path.join(out, 'probes.csv'))
    h = sc.read_csv(os.path.join(out, 'history.csv'))
    t, vy = p['time'], p['ball.VY']
    before = t < 0.4   # the ball lands at 0.4515 s
    err = np.max(np.abs(vy[before] + 9.81 * t[before]))
    sc.report('free fall: VY = -g t before the impact (max error %.1e m/s)' % err, err <= 1e-12 * 9.81 * 0.4, '%.3e' % err)
    ke = 0.5 * (p['ball.VX'] ** 2 + vy ** 2)
    rel = np.max(np.abs(ke - h['kinetic'])) / np.max(h['kinetic'])
    sc.report('½ m v² of the probes is the kinetic energy of history.csv at every step (%.1e)' % rel, rel <= 1e-13,
              '%.3e' % rel)
    sc.report('the probe sees the rebounds (VY > 0 after the impact)', np.max(vy[~before]) > 4.0, '%.3f' % np.max(vy))


def eq3_identity():
    # The cantilever with one OUTPUT line probing the tip's displacements and velocities.
    lines = open(os.path.join(sc.ROOT, 'inputs/cantilever_release.dat')).read().split('\n')
    lines = [ln for ln in lines if not ln.startswith('OUTPUT')]
    lines.append('OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE beam.end UY beam.end VY beam.end RZ beam.end VRZ')
    os.makedirs(sc.TMP, exist_ok=True)
    scene = os.path.join(sc.TMP, 'cantilever_probes.dat')
    with open(scene, 'w') as f:
        f.write('\n'.join(lines) + '\n')
    out = sc.run_ok(scene, ['TIME.END=0.02'])
    p = sc.read_csv(os.path.join(out, 'probes.csv'))
    hstep = np.diff(p['time'])
    for u, v in (('beam.end.UY', 'beam.end.VY'), ('beam.end.RZ', 'beam.end.VRZ')):
        du = np.diff(p[u])
        pred = 0.5 * hstep * (p[v][1:] + p[v][:-1])
        rel = np.max(np.abs(du - pred)) / np.max(np.abs(du))
        sc.report('eq (3) on the probes %s, %s: u(n+1) - u(n) = h/2 (v(n) + v(n+1)) (%.1e)' % (u, v, rel), rel <= 1e-12,
                  '%.3e' % rel)


def refused():
    rc, err, out = sc.run('inputs/mass_bounce.dat', ['OUTPUT.PROBE=ball VRZ'], outdir=sc.new_dir('never'))
    sc.report('PROBE ball VRZ of a point mass refused (exit 2, names VRZ)',
              rc == 2 and "at 'VRZ'" in err and not os.path.exists(out), 'exit %d: %r' % (rc, err))


free_fall()
eq3_identity()
refused()
