"""The L-shaped plate of lplate.geo meshed by Gmsh 4.8.4 (the commands are in lplate.geo): TRI6 in
MSH 2.2 and 4.1, TRI3, QUAD8 (recombined, serendipity), with physical curves "bottom" and "top"
and a physical point "corner"; TRI6 also in binary MSH 4.1 (gmsh -bin). Clamped on "bottom", a pressure ramped to 1 MPa on "top" (1 m,
thickness 0.1 m), heavy Rayleigh damping (ALPHA). Asserted, each mesh:
- the support reaction at rest balances the pressure: RY = p L t = 1e5 N within 1 % (measured
  0.007 %, the rest of the damped motion), |RX| <= 1e-3 p L t;
- |balance| <= 1e-10 of the external work, the damping column booked;
and across meshes: MSH 2.2 and 4.1 of the same mesh give the same probes bit for bit; the corner's
vertical displacement in TRI3 and QUAD8 within 1 % of TRI6's (measured 0.04 % and 0.1 %).
fields.h5's support_reaction field (the supports' nodal reactions, N) sums to the probes' RX,
RY at the last step (1e-9 of p L t).
"""
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

HERE = os.path.relpath(os.path.dirname(os.path.abspath(__file__)), sc.ROOT)
FORCE = 1e6 * 1.0 * 0.1
probes = {}
for mesh in ['tri6_v22', 'tri6_v41', 'tri6_bin', 'tri3', 'quad8']:
    out = sc.run_ok(os.path.join(HERE, 'lplate.dat'), ['GMSH.FILE=lplate_%s.msh' % mesh])
    p = sc.probes(out)
    h = sc.history(out)
    probes[mesh] = p
    sc.close('%s: RY at rest = p L t (1 %%)' % mesh, p['lp.bottom.RY'][-1], FORCE, 0.01)
    sc.report('%s: |RX| at rest <= 1e-3 p L t' % mesh, abs(p['lp.bottom.RX'][-1]) <= 1e-3 * FORCE,
              '%.3e N' % p['lp.bottom.RX'][-1])
    with h5py.File(os.path.join(out, 'fields.h5'), 'r') as f:
        r = f[sorted(k for k in f if k.startswith('step_'))[-1]]['support_reaction'][()]
    d = max(abs(r[:, 0].sum() - p['lp.bottom.RX'][-1]), abs(r[:, 1].sum() - p['lp.bottom.RY'][-1]))
    sc.report('%s: fields.h5 support_reaction sums to the probes RX, RY (1e-9)' % mesh, d <= 1e-9 * FORCE, '%.3e N' % d)
    bal = np.abs(h['balance']).max() / np.abs(h['external']).max()
    sc.report('%s: |balance| <= 1e-10 x external work (damping booked)' % mesh, bal <= 1e-10, '%.3e' % bal)
same = all(np.array_equal(probes['tri6_v22'][k], probes['tri6_v41'][k]) for k in probes['tri6_v22'])
sc.report('MSH 2.2 and 4.1 of the same mesh: the same probes bit for bit', same)
# Binary 4.1 holds Gmsh's coordinates unrounded (its ASCII prints 16 digits: 4e-16 apart): the
# probes agree to 1e-10 of their scale.
d = max(np.abs(probes['tri6_bin'][k] - probes['tri6_v41'][k]).max() / max(np.abs(probes['tri6_v41'][k]).max(), 1e-300)
        for k in probes['tri6_v41'] if k != 'time')
sc.report('binary MSH 4.1 = ASCII 4.1 (probes to 1e-10)', d <= 1e-10, '%.3e' % d)
ref = probes['tri6_v22']['lp.corner.UY'][-1]
for mesh in ['tri3', 'quad8']:
    sc.close('%s: corner UY = TRI6 (1 %%)' % mesh, probes[mesh]['lp.corner.UY'][-1], ref, 0.01)
