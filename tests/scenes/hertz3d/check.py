#!/usr/bin/python3
"""Hertz in 3D (issue 32, item 9): the elastic steel sphere of inputs/hertz_3d.dat (R = 10 mm, E = 210 GPa,
nu = 0.3, rho = 7800, a quarter in TET10 with its symmetry planes held) dropped on a rigid plane at
1 m/s, at the scene's defaults (IMPACT AUTO -> MASSLESS). Hertz's quasi-static contact of elastic
half-spaces: duration 2.87 (m^2 / (R E*^2 v))^(1/5) = 52.27 us, peak force 4/3 E* sqrt(R) d^(3/2) =
2301 N (E* = E / (1 - nu^2) against a rigid plane; m the sphere's mass). Checked on the shipped mesh
(5946 TET10, tools/sphere_quarter_mesh.py 0.01 4e-5 0.2 1.5e-3) and a coarser one made here (2194
TET10: 0.01 8e-5 0.3 2e-3): duration within 3 %, peak force (4 x the quarter's) within 5 %, the
rebound 1 m/s within 0.1 % (of the mesh's own mass: the straight-sided TET10 hold 97-98 % of the
sphere's), |balance| <= 1e-10 of E, and the first contact in the first step (0.1 um at 1 m/s).
"""
import os
import re
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

V_S = 1.0
m_s, t_hertz, f_hertz = sc.hertz_sphere(0.01, 2.1e11, 0.3, 7800.0, V_S)

mesh_dir = sc.new_dir('hertz3d_mesh')
os.makedirs(mesh_dir)
coarse = os.path.join(mesh_dir, 'coarse.msh')
p = subprocess.run(['/usr/bin/python3', os.path.join(sc.ROOT, 'tools', 'sphere_quarter_mesh.py'), '0.01', '8e-5', '0.3',
                    '2e-3', coarse], capture_output=True, text=True)
sc.report('tools/sphere_quarter_mesh.py writes the coarse quarter ball', p.returncode == 0, p.stderr[-300:])

for tag, msh in (('5946 TET10 (inputs/hertz_3d.msh)', None), ('2194 TET10', coarse)):
    sets = ['OUTPUT.FIELDS=EVERY 0'] + (['GMSH.FILE=' + msh] if msh else [])
    out = sc.run_ok(os.path.join('inputs', 'hertz_3d.dat'), sets)
    c = sc.contacts(out)
    steps = np.unique(c['step'])
    fz = 4.0 * np.array([np.sum(c['force_z'][c['step'] == s]) for s in steps])
    times = np.array([c['time'][c['step'] == s][0] for s in steps])
    on = times[fz > 0]
    dur = on.max() - on.min() + 2.5e-7
    h = sc.history(out)
    m_q = h['kinetic'][0] * 2.0 / V_S ** 2                 # the quarter's mass, from its kinetic energy
    bal = np.max(np.abs(h['balance'])) / np.max(h['kinetic'] + h['internal'])
    reb = h['momentum_z'][-1] / m_q
    sc.report_measured('Hertz 3D, %s: contact duration within 3 %% of %.2f us, peak force within 5 %% of %.0f N, '
                       'rebound 1 m/s (0.1 %%), |balance| <= 1e-10 of E' % (tag, 1e6 * t_hertz, f_hertz),
                       abs(dur / t_hertz - 1) <= 0.03 and abs(fz.max() / f_hertz - 1) <= 0.05 and
                       abs(reb - V_S) <= 1e-3 and bal <= 1e-10,
                       'duration %.2f us (%+.2f %%), peak %.0f N (%+.2f %%), rebound %.5f m/s, balance %.1e, mass %.4f of '
                       'the sphere' % (1e6 * dur, 100 * (dur / t_hertz - 1), fz.max(), 100 * (fz.max() / f_hertz - 1),
                                       reb, bal, 4 * m_q / m_s))
    sc.report_measured('Hertz 3D, %s: first contact in the step of 0.1 um / 1 m/s' % tag, on.min() <= 2.5e-7 + 1e-12,
                       'first contact %.3g s' % on.min())
