"""Shared helpers of the regression scenes (tests/scenes/<case>/check.py).

Each check runs bin/rebond into a temporary directory, reads the CSV outputs with numpy and
prints one line per assertion, `PASS name` or `FAIL name: measured vs expected`, which
tests/run_tests.sh counts. A check exits non-zero only when it crashes (rebond missing,
unreadable output, a Python error).
"""
import os
import resource
import subprocess
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
REBOND = os.environ.get('REBOND', os.path.join(ROOT, 'bin', 'rebond'))

_tmp = tempfile.TemporaryDirectory(prefix='rebond_check_')
TMP = _tmp.name
_count = [0]


def new_dir(tag='run'):
    """A fresh path inside the temporary directory (not created)."""
    _count[0] += 1
    return os.path.join(TMP, '%s_%d' % (tag, _count[0]))


# Limits are CPU seconds (RLIMIT_CPU: the run gets SIGXCPU past them), never the wall clock, so
# that the checks pass on a loaded machine. HANG_FACTOR x the CPU limit of wall time remains,
# only to end a process that waits forever without using the CPU.
HANG_FACTOR = 50


def run_limited(cmd, cpu, **kw):
    """subprocess.run under a CPU-time limit of `cpu` seconds (set on the child with prlimit, which,
    unlike preexec_fn, is safe from threads), and a hang guard of HANG_FACTOR x cpu wall seconds."""
    kw.pop('capture_output', None)   # always captured
    input_ = kw.pop('input', None)
    with subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, **kw) as p:
        s = int(cpu) + 1
        try:
            resource.prlimit(p.pid, resource.RLIMIT_CPU, (s, s + 5))
        except ProcessLookupError:
            pass
        try:
            out, err = p.communicate(input_, timeout=HANG_FACTOR * cpu)
        except subprocess.TimeoutExpired:
            p.kill()
            p.communicate()
            raise
    return subprocess.CompletedProcess(cmd, p.returncode, out, err)


def run(scene, sets=(), outdir=None, timeout=120):
    """Run rebond quietly; returns (exit code, stderr, output directory). timeout: CPU seconds."""
    if not os.access(REBOND, os.X_OK):
        raise RuntimeError('bin/rebond not built (%s)' % REBOND)
    if outdir is None:
        outdir = new_dir()
    cmd = [REBOND, scene, '-o', outdir, '--quiet']
    for s in sets:
        cmd += ['--set', s]
    p = run_limited(cmd, timeout, cwd=ROOT, capture_output=True, text=True)
    return p.returncode, p.stderr, outdir


def write_scene(name, text):
    """A scene file (text or bytes) named name in the temporary directory; returns its path."""
    os.makedirs(TMP, exist_ok=True)
    path = os.path.join(TMP, name)
    with open(path, 'wb' if isinstance(text, bytes) else 'w') as f:
        f.write(text)
    return path


def message_lines(stderr):
    """The lines of stderr that are rebond's, without the debug build's run-time warnings
    ("At line N of file F" + "Fortran runtime warning: ..."), which make check-debug counts apart."""
    lines = [ln for ln in stderr.strip().split('\n') if ln]
    out = []
    for i, ln in enumerate(lines):
        if ln.startswith('Fortran runtime warning'):
            continue
        if ln.startswith('At line ') and i + 1 < len(lines) and lines[i + 1].startswith('Fortran runtime warning'):
            continue
        out.append(ln)
    return out


def run_ok(scene, sets=()):
    """Run rebond and insist on success (a failure here is a crash of the check)."""
    rc, err, outdir = run(scene, sets)
    if rc != 0:
        raise RuntimeError('rebond %s %s failed (exit %d): %s' % (scene, ' '.join(sets), rc, err.strip()))
    return outdir


def read_csv(path):
    """Columns of a rebond CSV file as a dict name -> float array."""
    with open(path) as f:
        names = f.readline().strip().split(',')
    data = np.loadtxt(path, delimiter=',', skiprows=1, ndmin=2)
    return {n: data[:, i] for i, n in enumerate(names)}


def contacts(outdir):
    """contacts.csv as a dict column -> array (the contact name column as strings)."""
    import csv
    with open(os.path.join(outdir, 'contacts.csv')) as f:
        rows = list(csv.DictReader(f))
    cols = {}
    for k in (rows[0].keys() if rows else []):
        vals = [r[k] for r in rows]
        cols[k] = np.array(vals) if k == 'contact' else np.array([float(x) for x in vals])
    return cols


def history(outdir):
    return read_csv(os.path.join(outdir, 'history.csv'))


def probes(outdir):
    return read_csv(os.path.join(outdir, 'probes.csv'))


def report(name, ok, detail=''):
    if ok:
        print('PASS ' + name)
    else:
        print('FAIL ' + name + (': ' + detail if detail else ''))
    return ok


def report_measured(name, ok, detail):
    """report, with the measured figures printed as a `#` line whatever the outcome (the numbers the
    docs quote)."""
    print('# %s: %s' % (name, detail))
    return report(name, ok, detail)


def close(name, measured, expected, rtol):
    """PASS when |measured - expected| <= rtol |expected|."""
    err = abs(measured - expected) / abs(expected)
    print('# %s: measured %.17g, expected %.17g, relative error %.3e' % (name, measured, expected, err))
    return report(name, err <= rtol, 'measured %.17g vs expected %.17g (relative error %.3e > %.1e)'
                  % (measured, expected, err, rtol))


def relative_balance(outdir):
    """max |balance| / max(kinetic + internal) over the history."""
    h = history(outdir)
    return np.max(np.abs(h['balance'])) / np.max(np.abs(h['kinetic'] + h['internal'])), len(h['step'])


def free_body(tag, h, mom_bound, am_bound=1e-10, bal_bound=1e-10):
    """A free body's conservation laws from its history h, reported: angular momentum constant to
    am_bound (relative), linear momentum within mom_bound (absolute), |balance| <= bal_bound of E."""
    am = h['angular_momentum']
    drift = np.max(np.abs(am - am[0])) / abs(am[0])
    report('%s: angular momentum constant to %g' % (tag, am_bound), drift <= am_bound, '%.2e' % drift)
    mom = max(np.max(np.abs(h['momentum_x'])), np.max(np.abs(h['momentum_y'])))
    report('%s: linear momentum zero (%g)' % (tag, mom_bound), mom <= mom_bound, '%.2e' % mom)
    bal = np.max(np.abs(h['balance'])) / np.max(np.abs(h['kinetic'] + h['internal']))
    report('%s: |balance| <= %g of E' % (tag, bal_bound), bal <= bal_bound, '%.2e' % bal)


def hertz_sphere(radius, young, poisson, density, speed):
    """Hertz's elastic sphere on a rigid plane (quasi-static half-spaces): its mass m, the contact
    duration 2.87 (m^2 / (R E*^2 v))^(1/5) and the peak force 4/3 E* sqrt(R) d^(3/2) at the approach
    d = (15 m v^2 / (16 E* sqrt(R)))^(2/5), E* = E / (1 - nu^2)."""
    import numpy as np
    m = 4.0 / 3.0 * np.pi * radius ** 3 * density
    e_star = young / (1 - poisson ** 2)
    t = 2.87 * (m ** 2 / (radius * e_star ** 2 * speed)) ** 0.2
    d = (15 * m * speed ** 2 / (16 * e_star * np.sqrt(radius))) ** 0.4
    return m, t, 4.0 / 3.0 * e_star * np.sqrt(radius) * d ** 1.5


def restart_same(scene, sets, end_half, files=('history.csv',)):
    """A run stopped at TIME.END = end_half and restarted from its checkpoint (the sets must write one,
    OUTPUT.CHECKPOINT=k) writes the same files as the run in one go, byte for byte. Returns (same,
    detail)."""
    import subprocess
    full = run_ok(scene, sets)
    half = run_ok(scene, list(sets) + ['TIME.END=' + end_half])
    cmd = [REBOND, scene, '-o', half, '--quiet', '--restart', os.path.join(half, 'checkpoint.h5')]
    for x in sets:
        cmd += ['--set', x]
    r = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    same = r.returncode == 0 and all(open(os.path.join(full, f), 'rb').read() == open(os.path.join(half, f), 'rb').read()
                                     for f in files)
    return same, 'exit %d %s' % (r.returncode, r.stderr[-200:])


# One element of each surface kind on the unit square: its nodes, corners then mid-sides.
CORNERS = {'a': (0.0, 0.0), 'b': (1.0, 0.0), 'c': (1.0, 1.0), 'd': (0.0, 1.0)}
ELEMENT_KINDS = {
    'QUAD4': ['a', 'b', 'c', 'd'],
    'QUAD8': ['a', 'b', 'c', 'd', 'ab', 'bc', 'cd', 'da'],
    'TRI3': ['a', 'b', 'c'],
    'TRI6': ['a', 'b', 'c', 'ab', 'bc', 'ca'],
}


def corner_position(name):
    """The reference position of node `name` of ELEMENT_KINDS (a corner, or the middle of two)."""
    if name in CORNERS:
        return CORNERS[name]
    p, q = CORNERS[name[0]], CORNERS[name[1]]
    return (0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]))


def one_element(name, kind, model, disp):
    """A scene of one element of the kind (a von Mises material) with the MODEL parameters `model`, in
    the homogeneous state u = disp(X, Y) at t = 0 (INITIAL DISPLACEMENT), one step, fields written."""
    names = ELEMENT_KINDS[kind]
    s = ''.join('NODE n%s AT %.17g %.17g\n' % ((k,) + corner_position(k)) for k in names)
    s += 'ELEMENT q TYPE %s NODES %s\n' % (kind, ' '.join('n' + k for k in names))
    s += 'MATERIAL m VON_MISES YOUNG 1e6 POISSON 0.3 DENSITY 1000 YIELD 2e4 H_ISO 1e5 H_KIN 5e4\n'
    s += 'SECTION t THICKNESS 0.1\nMODEL q MATERIAL m SECTION t %s\n' % model
    for k in names:
        s += 'INITIAL n%s DISPLACEMENT %.17g %.17g\n' % ((k,) + disp(*corner_position(k)))
    s += 'TIME STEP 1e-4 END 1e-4\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 1\n'
    return write_scene(name, s)
