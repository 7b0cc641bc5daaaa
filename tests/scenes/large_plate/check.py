"""Large systems' factor (issue 14, item 3): above 50 000 equations the analysis of S = K0 + 4M/h^2
orders the graph of supervariables (a node's DOFs) by CHOLMOD's nested dissection, one ordering;
below, the best of AMD and METIS on the DOF graph (src/linalg/cholmod_shim.c, docs/performance.md).
A free steel plate, 160 x 160 QUAD4 (51 842 equations), its right edge launched downwards, 20 steps
of 1 us: the run summary names the nested dissection, and the run keeps what any ordering must keep
(an ordering only permutes the factor): linear momentum and angular momentum about the origin (the
linearized kinematics' conserved quantities) constant to 1e-12 relative, |balance| <= 1e-12 of E.
The same plate at 150 x 150 (45 602 equations) names AMD or METIS.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402


def plate(n):
    return sc.write_scene('plate_%d.dat' % n, '''TITLE "free plate, %d x %d QUAD4"
DIMENSION 2
RECTANGLE plate ORIGIN 0 0 SIZE 1 1 ELEMENTS %d %d TYPE QUAD4
MATERIAL steel ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800
SECTION s THICKNESS 0.01
MODEL plate MATERIAL steel SECTION s MASS CONSISTENT PLANE STRAIN
INITIAL plate.right VELOCITY 0 -1
TIME STEP 1e-6 END 2e-5
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0
''' % (n, n, n, n))


def run(n):
    out = sc.new_dir('plate')
    p = sc.run_limited([sc.REBOND, plate(n), '-o', out], 120, cwd=sc.ROOT, text=True)
    line = next((l.strip() for l in p.stdout.splitlines() if 'factor of S' in l), '')
    print('# %d x %d: %s' % (n, n, line))
    return p, out, line


p, out, line = run(160)
sc.report('160 x 160 plate runs (exit 0)', p.returncode == 0, p.stderr[-300:])
sc.report('51 842 equations: the nested dissection of supervariables orders the factor',
          '51842 equations' in p.stdout and 'nested dissection of supervariables ordering' in line, line)
if p.returncode == 0:
    h = sc.history(out)
    for key in ('momentum_y', 'angular_momentum'):
        drift = np.max(np.abs(h[key] - h[key][0])) / abs(h[key][0])
        sc.report_measured('160 x 160: %s constant to 1e-12' % key, drift <= 1e-12, '%.2e' % drift)
    bal = np.max(np.abs(h['balance'])) / np.max(np.abs(h['kinetic'] + h['internal']))
    sc.report_measured('160 x 160: |balance| <= 1e-12 of E', bal <= 1e-12, '%.2e' % bal)
    sc.report('160 x 160: the plate moves (kinetic energy 0.5 m v^2 of the edge at the start)',
              len(h['step']) == 21 and h['kinetic'][0] > 0 and np.max(np.abs(h['internal'])) > 0)

p, out, line = run(150)
sc.report('45 602 equations: the best of AMD and METIS orders the factor',
          p.returncode == 0 and ('AMD ordering' in line or 'METIS ordering' in line), line)
