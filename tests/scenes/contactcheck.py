"""Helpers shared by the contact scene checks (tests/scenes/<contact case>/check.py).

Energy bound: every contact scene, in IMPACT PAPER and PERSIST, keeps
max |balance| <= 1e-10 x max(kinetic + internal) over the whole run (method.md sections 3, 6:
the impact corrections restore exactly the energy the scheme loses at contact establishment).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scenecheck as sc  # noqa: E402

BALANCE_RTOL = 1e-10
G = 9.81


def events(outdir):
    """events.csv as a list of (step, time, constraint, kind) with kind 'establish' or 'release'."""
    rows = []
    with open(os.path.join(outdir, 'events.csv')) as f:
        f.readline()
        for line in f:
            p = line.strip().split(',')
            if len(p) >= 5:
                rows.append((int(p[0]), float(p[1]), int(p[2]), p[4].strip()))
    return rows


def impacts(ev, separation):
    """Physical impacts: establish events grouped into clusters; a new impact starts when an
    establish comes more than `separation` seconds after the previous contact event.
    Returns a list of (number of establish events, first establish time, last event time)."""
    out = []
    last = None
    for step, t, j, kind in ev:
        if kind == 'establish' and (last is None or t - last > separation):
            out.append([0, t, t])
        if out:
            if kind == 'establish':
                out[-1][0] += 1
            out[-1][2] = t
        last = t
    return [tuple(x) for x in out]


def check_balance(tag, outdir):
    rel, n = sc.relative_balance(outdir)
    print('# %s: max |balance| / max(kinetic + internal) = %.3e over %d rows' % (tag, rel, n))
    return sc.report(tag + ': |balance| <= 1e-10 x total energy', rel <= BALANCE_RTOL,
                     'measured %.3e vs expected <= %.0e' % (rel, BALANCE_RTOL))


def line_com(outdir, axis=0):
    """(times, centre-of-mass displacement, centre-of-mass velocity) along `axis` from
    fields.h5, for a mesh of 2-node elements of one material and section: each element gives
    half its length to each of its nodes (the translational row sums of both the lumped and
    the consistent mass of BAR2 and BEAM2)."""
    import h5py
    with h5py.File(os.path.join(outdir, 'fields.h5'), 'r') as f:
        x = f['mesh/coordinates'][:, :2]
        topo = f['mesh/topology'][:].reshape(-1, 4)    # XDMF mixed: polyline code, 2, n1, n2
        w = np.zeros(x.shape[0])
        for _, _, a, b in topo:
            le = np.hypot(*(x[b] - x[a]))
            w[a] += 0.5 * le
            w[b] += 0.5 * le
        w /= w.sum()
        keys = sorted(k for k in f.keys() if k.startswith('step_'))
        t = np.array([f[k].attrs['time'] for k in keys])
        u = np.array([w @ f[k]['displacement'][:, axis] for k in keys])
        v = np.array([w @ f[k]['velocity'][:, axis] for k in keys])
    return t, u, v
