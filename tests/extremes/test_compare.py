#!/usr/bin/python3
"""Tests of tools/compare (issue 5, deliverable 5), run by tests/scenes/extremes/check.py.

1. The one-DOF oscillator (tests/scenes/extremes/oscillator.dat, omega = 2 rad/s, u0 = 0.1 m)
   against its own exact discrete solution u0 cos(Omega t), Omega h = 2 atan(omega h / 2): the
   trapezoidal rule reproduces it to round-off, so the tool must report max and RMS differences
   at round-off; against the continuous solution u0 cos(omega t) it must report exactly the
   phase error computed here independently; at reference times between the samples its linear
   interpolation error is bounded by u0 (Omega h)^2 / 8.
2. The point mass dropped from 1 m (inputs/mass_bounce.dat): the exact impacts are at
   (2k + 1) t_f, t_f = sqrt(2 H / g). The tool's onset shifts must equal those computed here
   from events.csv; the first lies in [0, h] (the impact closes inside a step); the scheme's
   bounce period is constant, so the shifts grow by one constant increment in [0, h) per
   bounce. Between impacts Newmark with a constant force is an exact parabola, so the apexes
   located by the tool's three-point parabola are the exact 1 m heights (to round-off).
3. Usage errors exit 2 with a message; --fail-above exits 1 when exceeded.
"""
import importlib.machinery
import importlib.util
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'scenes'))
from scenecheck import run_limited  # noqa: E402
REBOND = os.environ.get('REBOND', os.path.join(ROOT, 'bin', 'rebond'))
TOOL = os.path.join(ROOT, 'tools', 'compare')
PY = '/usr/bin/python3'

_loader = importlib.machinery.SourceFileLoader('rebond_compare', TOOL)
_spec = importlib.util.spec_from_loader('rebond_compare', _loader)
cmp = importlib.util.module_from_spec(_spec)
_loader.exec_module(cmp)


def report(name, ok, detail=''):
    name = 'compare: ' + name
    print(('PASS ' + name) if ok else ('FAIL %s: %s' % (name, detail)))
    if detail:
        print('#   ' + detail)


def rebond(scene, outdir, *sets):
    cmd = [REBOND, scene, '-o', outdir, '--quiet']
    for s in sets:
        cmd += ['--set', s]
    p = run_limited(cmd, 120, cwd=ROOT, text=True)
    if p.returncode != 0:
        raise RuntimeError('rebond failed: %s' % p.stderr)


def tool(*args):
    p = run_limited([PY, TOOL] + list(args), 60, cwd=ROOT, text=True)
    return p.returncode, p.stdout, p.stderr


def probe(outdir, name):
    with open(os.path.join(outdir, 'probes.csv')) as f:
        names = f.readline().strip().split(',')
    d = np.loadtxt(os.path.join(outdir, 'probes.csv'), delimiter=',', skiprows=1, ndmin=2)
    return d[:, 1], d[:, names.index(name)]


def main():
    tmp = tempfile.TemporaryDirectory(prefix='rebond_compare_')
    T = tmp.name
    # ---------------------------------------------------------------- 1. oscillator
    w, u0 = 2.0, 0.1
    h = (2 * math.pi / w) / 20
    n = 200
    osc = os.path.join(T, 'osc')
    rebond('tests/scenes/extremes/oscillator.dat', osc, 'TIME.STEP=%r' % h, 'TIME.END=%r' % (n * h))
    t, u = probe(osc, 'tip.UX')
    W = 2 * math.atan(w * h / 2) / h
    tn = np.arange(n + 1) * h
    ref = os.path.join(T, 'discrete.csv')
    with open(ref, 'w') as f:
        f.write('time,u_exact\n')                   # a header line is accepted
        for x in tn:
            f.write('%.17g,%.17g\n' % (x, u0 * math.cos(W * x)))
    rc, out, err = tool(osc, ref, '--column', 'probes:tip.UX')
    _, r = cmp.read_reference(ref)
    res = cmp.compare_curve(t, u, r[:, 0], r[:, 1])
    report('oscillator vs u0 cos(Omega t): exit 0, Markdown table', rc == 0 and '| probes:tip.UX | 201 |' in out,
           'exit %d, %s' % (rc, (out + err).strip().splitlines()[-1]))
    report('oscillator vs its exact discrete solution: max |diff| <= 1e-13 u0',
           res['max'] <= 1e-13 * u0 and res['rms'] <= res['max'],
           'max %.3e m, RMS %.3e m, %d points' % (res['max'], res['rms'], res['points']))
    # the continuous solution: the tool must report the phase error computed independently
    ref2 = os.path.join(T, 'continuous.csv')
    np.savetxt(ref2, np.c_[tn, u0 * np.cos(w * tn)], delimiter=',')
    _, r2 = cmp.read_reference(ref2)
    res2 = cmp.compare_curve(t, u, r2[:, 0], r2[:, 1])
    d = u - u0 * np.cos(w * tn)
    exp_max, exp_rms = np.max(np.abs(d)), math.sqrt(np.mean(d * d))
    report('oscillator vs u0 cos(omega t): max and RMS = the phase error computed independently',
           abs(res2['max'] - exp_max) <= 1e-12 * exp_max and abs(res2['rms'] - exp_rms) <= 1e-12 * exp_rms,
           'tool max %.15g RMS %.15g, independent %.15g, %.15g' % (res2['max'], res2['rms'], exp_max, exp_rms))
    # phase error after 10 periods: u0 |cos(W t) - cos(w t)| <= u0 |W - w| t, and of that order
    bound = u0 * abs(W - w) * tn[-1]
    report('oscillator: the phase error is the trapezoidal one (<= u0 |Omega - omega| t_end, >= half of it)',
           0.5 * min(bound, 2 * u0) <= res2['max'] <= bound + 1e-15,
           'max %.4e, u0 |Omega - omega| t_end = %.4e' % (res2['max'], bound))
    # reference times between the samples: linear interpolation of the exact discrete cosine
    tm = (np.arange(n) + 0.5) * h
    res3 = cmp.compare_curve(t, u, tm, u0 * np.cos(W * tm))
    ib = u0 * (W * h) ** 2 / 8
    report('oscillator, reference between samples: interpolation error <= u0 (Omega h)^2 / 8',
           0 < res3['max'] <= ib * (1 + 1e-9), 'max %.4e, bound %.4e' % (res3['max'], ib))
    rc, out, err = tool(osc, ref2, '--format', 'text', '--fail-above', '1e-3')
    report('--fail-above below the difference: exit 1; plain text table', rc == 1 and 'max |diff|' in out,
           'exit %d' % rc)
    rc, out, err = tool(osc, ref2, '--fail-above', '1')
    report('--fail-above above the difference: exit 0', rc == 0, 'exit %d' % rc)
    # energies: kinetic + internal is the constant initial strain energy k u0^2 / 2 = 0.04 J
    refe = os.path.join(T, 'energy.csv')
    np.savetxt(refe, np.c_[tn, np.full_like(tn, 0.5 * 8.0 * u0 ** 2)], delimiter=',')
    rc, out, err = tool(osc, refe, '--column', 'history:kinetic+internal', '--fail-above', '1e-14')
    report('history:kinetic+internal = k u0^2 / 2 to 1e-14 J (constant energy)', rc == 0,
           'exit %d: %s' % (rc, out.strip().splitlines()[-1] if out.strip() else err.strip()))

    # ---------------------------------------------------------------- 2. point-mass bounce
    H, g, hb = 1.0, 9.81, 1.3e-3
    tf = math.sqrt(2 * H / g)
    mb = os.path.join(T, 'bounce')
    rebond('inputs/mass_bounce.dat', mb, 'TIME.END=10')
    k = np.arange(11)                                   # impacts at (2k+1) tf < 10 s
    refi = os.path.join(T, 'impacts.csv')
    np.savetxt(refi, (2 * k + 1) * tf)
    rc, out, err = tool(mb, refi, '--events')
    ev = cmp.contact_events(mb, 'establish')
    own = []
    with open(os.path.join(mb, 'events.csv')) as f:
        f.readline()
        for line in f:
            p = line.strip().split(',')
            if p[4] == 'establish':
                own.append(float(p[1]))
    own = np.array(own)
    resb = cmp.compare_events(ev, (2 * k + 1) * tf)
    sh = resb['shifts']
    report('bounce: 11 onsets found and paired', rc == 0 and resb['matched'] == 11 and len(own) == 11,
           'exit %d, run %d, paired %d' % (rc, resb['run_count'], resb['matched']))
    report('bounce: onset shifts = events.csv time - (2k+1) t_f', np.allclose(sh, own - (2 * k + 1) * tf, rtol=0,
                                                                              atol=1e-15),
           'shifts %s' % ', '.join('%.6g' % x for x in sh[:4]))
    report('bounce: first onset in the step that closes the gap (0 <= shift <= h)', 0 <= sh[0] <= hb,
           'shift %.6g s, h = %g s' % (sh[0], hb))
    inc = np.diff(sh)
    report('bounce: constant drift per bounce, in [0, h)', np.ptp(inc) <= 1e-9 and 0 <= inc[0] < hb,
           'increments %.9g ... %.9g s' % (inc.min(), inc.max()))
    refa = os.path.join(T, 'apex.csv')
    ka = np.arange(1, 12)                               # apexes at 2k tf < 10 s, k = 1 ... 11
    np.savetxt(refa, np.c_[2 * ka * tf, np.full(11, H)], delimiter=',')
    rc, out, err = tool(mb, refa, '--events', 'apex', '--column', 'probes:ball.UY', '--offset', '1')
    tt, uy = probe(mb, 'ball.UY')
    at, av = cmp.extrema(tt, uy + 1.0, 'apex')
    report('bounce: 11 apexes found, every one at H = 1 m (exact parabola) to 1e-12 m',
           rc == 0 and len(at) == 11 and np.max(np.abs(av - H)) <= 1e-12,
           '%d apexes, max |height - 1| = %.3e m' % (len(at), np.max(np.abs(av - H)) if len(av) else -1))
    ra = cmp.compare_events(at, 2 * ka * tf, av, np.full(11, H))
    report('bounce: apex shift = onset shift (flight symmetric about the apex)',
           ra['matched'] == 11 and np.allclose(ra['shifts'][:10], sh[:10], rtol=0, atol=1e-9),
           'apex shifts %s' % ', '.join('%.6g' % x for x in ra['shifts'][:4]))

    # ---------------------------------------------------------------- 3. errors
    rc, out, err = tool(osc, ref, '--column', 'probes:nope')
    report('unknown column: exit 2 naming the columns there are', rc == 2 and 'tip.UX' in err, err.strip())
    rc, out, err = tool(os.path.join(T, 'missing'), ref)
    report('missing run folder: exit 2', rc == 2 and 'not a folder' in err, err.strip())
    bad = os.path.join(T, 'bad.csv')
    with open(bad, 'w') as f:
        f.write('0,1\n1,x\n')
    rc, out, err = tool(osc, bad)
    report('unreadable reference: exit 2 with file:line', rc == 2 and 'bad.csv:2' in err, err.strip())
    rc, out, err = tool(osc, refi, '--events', 'apex')
    report('apex events without --column: exit 2', rc == 2 and 'column' in err, err.strip())
    return 0


if __name__ == '__main__':
    sys.exit(main())
