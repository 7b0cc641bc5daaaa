"""Checkpoint/restart and crash-safe outputs (issue 6).

- A run killed with SIGKILL mid-way and restarted from OUTDIR/checkpoint.h5 produces the same
  history.csv and probes.csv as an uninterrupted run, bit for bit; also for a contact scene
  (events.csv too), where the multipliers and the active set are part of the state.
- SIGTERM writes a checkpoint and the summary, exits non-zero, and the restart is bit for bit.
- Every line of the files of a killed run is complete (crash-safe outputs).
- A run that blows up stops with exit 1 and a message naming the step, after the complete
  lines written so far.
"""
import os
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

HERE = 'tests/scenes/restart/'


def launch(scene, outdir, sets=()):
    cmd = [sc.REBOND, scene, '-o', outdir, '--quiet']
    for s in sets:
        cmd += ['--set', s]
    return subprocess.Popen(cmd, cwd=sc.ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def read(path):
    with open(path, 'rb') as f:
        return f.read()


def lines_complete(path, ncol):
    rows = read(path).decode().split('\n')
    return rows[-1] == '' and all(len(r.split(',')) == ncol for r in rows[:-1])


def kill_and_restart(tag, scene, sets, sig, files, wait_rows):
    full = sc.run_ok(scene, sets)
    out = sc.new_dir('killed')
    p = launch(scene, out, sets)
    hist = os.path.join(out, 'history.csv')
    # Kill once the run has passed at least one checkpoint, well before its end (judged by the
    # run's own progress, not by the clock).
    while p.poll() is None:
        if os.path.exists(hist) and read(hist).count(b'\n') > wait_rows and \
                os.path.exists(os.path.join(out, 'checkpoint.h5')):
            break
        time.sleep(0.02)
    p.send_signal(sig)
    _, err = p.communicate()
    nrows = read(hist).count(b'\n')
    total = read(os.path.join(full, 'history.csv')).count(b'\n')
    sc.report(tag + ': killed mid-run', 1 < nrows < total, 'history rows %d of %d' % (nrows, total))
    if sig == signal.SIGKILL:
        sc.report(tag + ': exit by SIGKILL', p.returncode == -signal.SIGKILL, 'exit %s' % p.returncode)
    else:
        sc.report(tag + ': SIGTERM exits non-zero with a restart hint', p.returncode == 1 and '--restart' in err,
                  'exit %s, stderr %r' % (p.returncode, err[-200:]))
    ncol = read(os.path.join(full, 'history.csv')).split(b'\n')[0].count(b',') + 1
    sc.report(tag + ': the killed run left complete lines only', lines_complete(hist, ncol), hist)
    cmd = [sc.REBOND, scene, '-o', out, '--quiet', '--restart', os.path.join(out, 'checkpoint.h5')]
    for s in sets:
        cmd += ['--set', s]
    r = sc.run_limited(cmd, 300, cwd=sc.ROOT, capture_output=True, text=True)
    sc.report(tag + ': restart succeeds', r.returncode == 0, 'exit %d: %s' % (r.returncode, r.stderr[-300:]))
    for name in files:
        same = read(os.path.join(full, name)) == read(os.path.join(out, name))
        sc.report(tag + ': %s bit for bit after restart' % name, same, name)


kill_and_restart('plate SIGKILL', HERE + 'plate.dat', [], signal.SIGKILL, ['history.csv', 'probes.csv'], 600)
kill_and_restart('plate SIGTERM', HERE + 'plate.dat', [], signal.SIGTERM, ['history.csv', 'probes.csv'], 600)
# Contact: the beam drop at a fine step, killed between impacts and during contact phases.
kill_and_restart('beam drop SIGKILL', 'inputs/beam_drop_vertical.dat',
                 ['TIME.STEP=1e-6', 'TIME.END=0.2', 'OUTPUT.FIELDS=0', 'OUTPUT.HISTORY=1', 'OUTPUT.CHECKPOINT=5000'],
                 signal.SIGKILL, ['history.csv', 'probes.csv', 'events.csv'], 60000)

# A run that blows up.
rc, err, out = sc.run(HERE + 'nan.dat')
sc.report('blow-up: exit 1 with a message naming the step', rc == 1 and 'step 1 ' in err and 'diverged' in err,
          'exit %d: %s' % (rc, err.strip()[-300:]))
ncol_hist = read(os.path.join(out, 'history.csv')).split(b'\n')[0].count(b',') + 1
sc.report('blow-up: the history keeps its complete lines (%d columns)' % ncol_hist,
          ncol_hist >= 16 and lines_complete(os.path.join(out, 'history.csv'), ncol_hist), 'history.csv')
sc.report('blow-up: names the first offending DOF', 'node 2' in err and 'DOF UX' in err, err.strip()[-300:])
sc.report('blow-up: a checkpoint of the last good step', os.path.exists(os.path.join(out, 'checkpoint.h5')) and
          'state of step 0' in err, err.strip()[-200:])


def fingerprint():
    """A checkpoint belongs to its scene (issue 12, item 2): a restart under a changed TIME STEP,
    GRAVITY, material or mesh is refused with exit 2 naming the first differing item; TIME END
    and OUTPUT may change; a refused restart creates no output folder."""
    sets = ['OUTPUT.CHECKPOINT=1000', 'TIME.END=2']
    out = sc.run_ok('inputs/mass_bounce.dat', sets)
    ck = os.path.join(out, 'checkpoint.h5')

    def restart(extra, outdir=None):
        cmd = [sc.REBOND, 'inputs/mass_bounce.dat', '-o', outdir or sc.new_dir('fp'), '--quiet', '--restart', ck]
        for s in sets + extra:
            cmd += ['--set', s]
        return subprocess.run(cmd, cwd=sc.ROOT, capture_output=True, text=True)

    for extra, words in ((['TIME.STEP=2.6e-3'], ['TIME', 'STEP']), (['GRAVITY.GY=-9.80'], ['GRAVITY', 'GY']),
                         (['SECTION.m1.MASS=2'], ['SECTION m1', 'MASS']),
                         (['SCHEME.IMPACT=PERSIST'], ['SCHEME', 'IMPACT'])):
        fresh = sc.new_dir('never')
        r = restart(extra, fresh)
        msg = r.stderr.strip()
        sc.report('restart with %s refused: exit 2 naming it' % extra[0],
                  r.returncode == 2 and 'another scene' in msg and all(w in msg for w in words) and msg.count('\n') == 0,
                  'exit %d: %r' % (r.returncode, msg))
        sc.report('refused restart (%s) created no output folder' % extra[0], not os.path.exists(fresh), fresh)
    # Numbers compare by value: 1.3e-3 written as 0.0013 is the same step.
    r = restart(['TIME.STEP=0.0013', 'TIME.END=3', 'OUTPUT.HISTORY=2'])
    sc.report('restart with the same step written otherwise, a later END and other outputs: accepted',
              r.returncode == 0, 'exit %d: %r' % (r.returncode, r.stderr[-300:]))
    fresh = sc.new_dir('never')
    cmd = [sc.REBOND, 'inputs/mass_bounce.dat', '-o', fresh, '--quiet', '--restart', fresh + '/checkpoint.h5']
    r = subprocess.run(cmd, cwd=sc.ROOT, capture_output=True, text=True)
    sc.report('restart from a missing checkpoint: exit 2, no output folder',
              r.returncode == 2 and not os.path.exists(fresh), 'exit %d, exists %s' % (r.returncode, os.path.exists(fresh)))


fingerprint()
