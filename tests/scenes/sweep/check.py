"""`rebond sweep`: two small sweeps, each run in one process and under mpirun (as root in CI).

1. The one-DOF oscillator of tests/scenes/sdof_period (k = 8 N/m, m = 2 kg, u0 = 0.1 m, v0 = 0):
   the trapezoidal rule gives exactly u_n = u0 cos(Omega t_n), Omega h = 2 atan(omega h / 2)
   (the scheme is a rotation by Omega h in (u, v/omega)). Three steps h = 0.1, 0.05, 0.025 (t = 1 is
   a sample of each) plus a CASE with a negative spring stiffness, which must be recorded as an
   input error without stopping the sweep. Checks: METRIC probe tip.UX AT 1 = u0 cos(Omega 1)
   within 1e-12 relative (round-off of 40 steps), the error column against REFERENCE FINEST equal
   to the closed-form relative difference, the energy balance <= 1e-10 (linear elasticity).
2. inputs/mass_bounce.dat for 3 s (3 bounces), IMPACT PAPER and OFF at two steps: with PAPER each
   apex (parabola through 3 samples; exact for free flight) is at the drop height within 1e-10
   of H, 3 impacts of one onset each lasting one step; OFF loses energy at the impact, so its
   first apex is measurably lower (the metric tells the treatments apart).
Both: the table is the same (except wall_time) in one process and with 2 and 3 MPI ranks, every
case appears once, sweep.h5 holds the same table as sweep.csv, exit status 1 iff a case failed.
"""
import csv
import math
import os
import shutil
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

ROOT = sc.ROOT
REBOND = os.environ.get('REBOND', sc.REBOND)
MPI_ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1',
               OMPI_MCA_rmaps_base_oversubscribe='1')

SDOF = os.path.join(ROOT, 'tests/scenes/sdof_period/sdof.dat')
K, M, U0 = 8.0, 2.0, 0.1
OMEGA = math.sqrt(K / M)
STEPS = [0.1, 0.05, 0.025]

SDOF_SWEEP = """# one-DOF oscillator, three steps, and a case with bad input
SCENE %s
SET TIME.END=1.5
CASE good
CASE bad SET MATERIAL.k.YOUNG=-8
VARY TIME.STEP %s
METRIC balance
METRIC probe tip.UX AT 1
REFERENCE FINEST
""" % (SDOF, ' '.join(repr(h) for h in STEPS))

BOUNCE_SWEEP = """# mass dropped from 1 m, impact treatments
SCENE %s
SET TIME.END=3
CASE paper SET SCHEME.IMPACT=PAPER
CASE off SET SCHEME.IMPACT=OFF
VARY TIME.STEP 2.7e-3 1.3e-3
METRIC apex PROBE ball.UY COUNT 3 SCALE 1
METRIC contact_duration
METRIC onsets COUNT 3
REFERENCE VALUE apex1_ball.UY=0 apex2_ball.UY=0 apex3_ball.UY=0
""" % os.path.join(ROOT, 'inputs/mass_bounce.dat')


def run_sweep(path, outdir, nproc):
    cmd = [REBOND, 'sweep', path, '-o', outdir, '--quiet']
    if nproc > 1:
        mpirun = shutil.which('mpirun')
        if mpirun is None:
            return None, 'mpirun not found (make deps installs openmpi-bin)'
        cmd = [mpirun, '--allow-run-as-root', '--oversubscribe', '-np', str(nproc)] + cmd
    p = sc.run_limited(cmd, 300, cwd=ROOT, capture_output=True, text=True, env=MPI_ENV)
    return p.returncode, p.stderr


def table(outdir):
    with open(os.path.join(outdir, 'sweep.csv'), newline='') as f:
        return list(csv.DictReader(f))


def without_wall(rows):
    return [{k: v for k, v in r.items() if k != 'wall_time'} for r in rows]


def check_h5(tag, outdir, rows):
    import h5py
    with h5py.File(os.path.join(outdir, 'sweep.h5'), 'r') as f:
        cols = [c.decode() for c in f['columns'][:]]
        ok = cols == list(rows[0].keys())
        for c in cols:
            d = f[c][:]
            for i, r in enumerate(rows):
                v = d[i].decode() if isinstance(d[i], bytes) else d[i]
                if isinstance(v, str):
                    ok = ok and v == r[c]
                elif r[c] == 'nan':
                    ok = ok and math.isnan(v)
                else:
                    ok = ok and float(v) == float(r[c])
    sc.report(tag + ': sweep.h5 holds the table of sweep.csv', ok)


def run_all(tag, text, expect_rc):
    path = os.path.join(sc.TMP, tag + '.sweep')
    with open(path, 'w') as f:
        f.write(text)
    tables = {}
    for nproc in (1, 2, 3):
        out = sc.new_dir(tag + '_np%d' % nproc)
        rc, err = run_sweep(path, out, nproc)
        ok = rc == expect_rc and os.path.exists(os.path.join(out, 'sweep.csv'))
        sc.report('%s: %d process%s, exit %s' % (tag, nproc, 'es' if nproc > 1 else '', expect_rc), ok,
                  'exit %s: %s' % (rc, (err or '').strip()[-600:]))
        if ok:
            tables[nproc] = (out, table(out))
    if 1 not in tables:
        raise RuntimeError('%s: the one-process sweep failed' % tag)
    out, rows = tables[1]
    n = len(rows)
    sc.report(tag + ': every case once, in order', [r['case'] for r in rows] == [str(k) for k in range(1, n + 1)])
    for nproc in (2, 3):
        if nproc in tables:
            same = without_wall(tables[nproc][1]) == without_wall(rows)
            sc.report('%s: table with %d MPI ranks = table in one process (but wall_time)' % (tag, nproc), same)
    for r in rows:
        if r['status'] == 'ok':
            d = os.path.join(out, r['dir'])
            sc.report('%s: case %s wrote its own directory %s' % (tag, r['case'], r['dir']),
                      os.path.exists(os.path.join(d, 'history.csv')))
    check_h5(tag, out, rows)
    return rows


# 1. SDOF.
rows = run_all('sdof', SDOF_SWEEP, 1)
good = [r for r in rows if r['name'] == 'good']
bad = [r for r in rows if r['name'] == 'bad']
sc.report('sdof: 3 good + 3 bad cases', len(good) == 3 and len(bad) == 3)
sc.report('sdof: bad input recorded as input_error with its message',
          all(r['status'] == 'input_error' and 'YOUNG' in r['message'] for r in bad),
          '; '.join(r['status'] + ' ' + r['message'] for r in bad))
sc.report('sdof: the good cases ran', all(r['status'] == 'ok' for r in good))


def exact(h, t=1.0):
    om = 2.0 * math.atan(OMEGA * h / 2.0) / h
    return U0 * math.cos(om * t)


for r in good:
    h = float(r['TIME.STEP'])
    sc.report('sdof h=%g: max_rel_balance <= 1e-10' % h, float(r['max_rel_balance']) <= 1e-10, r['max_rel_balance'])
    sc.close('sdof h=%g: u(1) = u0 cos(Omega) of the trapezoidal rule' % h, float(r['tip.UX@1']), exact(h), 1e-12)
    sc.report('sdof h=%g: steps = END/STEP' % h, int(r['steps']) == round(1.5 / h))
ref = [r for r in rows if r['reference'] == '1']
sc.report('sdof: REFERENCE FINEST is the h = 0.025 case', len(ref) == 1 and float(ref[0]['TIME.STEP']) == 0.025)
for r in good:
    h = float(r['TIME.STEP'])
    expected = abs(exact(h) - exact(0.025)) / abs(exact(0.025))
    err = float(r['err_tip.UX@1'])
    print('# sdof h=%g: error %.6e, closed form %.6e' % (h, err, expected))
    sc.report('sdof h=%g: error column = closed-form relative difference to the finest' % h,
              abs(err - expected) <= 1e-10 * max(expected, 1e-3), '%.6e vs %.6e' % (err, expected))

# 2. Mass bounce.
rows = run_all('bounce', BOUNCE_SWEEP, 0)
for r in rows:
    h = float(r['TIME.STEP'])
    apex = np.array([float(r['apex%d_ball.UY' % k]) for k in (1, 2, 3)])
    if r['name'] == 'paper':
        worst = np.max(np.abs(apex))
        print('# bounce PAPER h=%g: apexes - H = %s' % (h, apex))
        sc.report('bounce PAPER h=%g: 3 apexes at H within 1e-10 H' % h, worst <= 1e-10, 'max |apex - H| = %.3e' % worst)
        errs = np.array([float(r['err_apex%d_ball.UY' % k]) for k in (1, 2, 3)])
        sc.report('bounce PAPER h=%g: error columns = |apex - H| / 1' % h, np.all(errs == np.abs(apex)))
        sc.report('bounce PAPER h=%g: 3 impacts, one onset each' % h,
                  float(r['impacts']) == 3 and all(float(r['onsets%d' % k]) == 1 for k in (1, 2, 3)))
        d = float(r['contact_duration'])
        sc.report('bounce PAPER h=%g: the first impact lasts one step' % h, abs(d - h) <= 1e-12, '%.17g' % d)
    else:
        sc.report('bounce OFF h=%g: first apex below H by more than 1e-3 (energy lost)' % h, apex[0] < -1e-3,
                  '%.3e' % apex[0])
