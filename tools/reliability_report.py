#!/usr/bin/python3
"""Measure rebond's reliability and write the results into docs/reliability.md (`make reliability`).

Runs, on bin/rebond (or $REBOND):
- the hostile-input checks (tests/scenes/{bad_input,hostile,full_disk,restart}/check.py): every
  case asserts the exit status, the one message (file:line, statement, word) and the result;
- N fuzzed scenes (tests/fuzz/fuzz.py, its own seed): outcomes by exit status, crashes, hangs;
- K SIGKILLs at random moments of a run writing checkpoints, each followed by --restart, whose
  history.csv and probes.csv must equal an uninterrupted run's bit for bit.
and replaces the block between the markers <!-- report:begin --> and <!-- report:end --> of
docs/reliability.md with the table (counts, the command of each row).

Usage: tools/reliability_report.py [--mutants N] [--kills K] [--seed S] [--no-write]
"""
import argparse
import datetime
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'scenes'))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'fuzz'))
import scenecheck as sc  # noqa: E402
import fuzz  # noqa: E402

DOC = os.path.join(ROOT, 'docs', 'reliability.md')
BEGIN, END = '<!-- report:begin -->', '<!-- report:end -->'
CHECKS = ['bad_input', 'hostile', 'full_disk', 'restart']


def run_check(name):
    p = sc.run_limited([sys.executable, os.path.join(ROOT, 'tests', 'scenes', name, 'check.py')], 1800, cwd=ROOT,
                       text=True)
    npass = len(re.findall(r'^PASS ', p.stdout, re.M))
    fails = re.findall(r'^FAIL .*$', p.stdout, re.M)
    return npass, fails, p.returncode


def kills(k, seed):
    """k SIGKILLs at random moments, each restarted; returns (bit-identical restarts, trials, details)."""
    rng = random.Random(seed)
    scene = 'tests/scenes/restart/plate.dat'
    sets = ['OUTPUT.CHECKPOINT=50']
    full = sc.run_ok(scene, sets)
    want = {n: open(os.path.join(full, n), 'rb').read() for n in ('history.csv', 'probes.csv')}
    same, bad = 0, []
    for t in range(k):
        out = tempfile.mkdtemp(prefix='rebond_kill_')
        cmd = [sc.REBOND, scene, '-o', out, '--quiet'] + sum((['--set', s] for s in sets), [])
        p = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        hist = os.path.join(out, 'history.csv')
        target = rng.randint(60, 1400)   # kill after this many history lines (the run writes ~1500)
        while p.poll() is None:
            if os.path.exists(hist) and open(hist, 'rb').read().count(b'\n') >= target:
                break
            time.sleep(0.001)
        p.send_signal(signal.SIGKILL)
        p.wait()
        ck = os.path.join(out, 'checkpoint.h5')
        if not os.path.exists(ck):   # killed before the first checkpoint: a fresh run is the restart
            r = subprocess.run(cmd, cwd=ROOT, capture_output=True)
        else:
            r = subprocess.run(cmd + ['--restart', ck], cwd=ROOT, capture_output=True)
        ok = r.returncode == 0 and all(open(os.path.join(out, n), 'rb').read() == v for n, v in want.items())
        same += ok
        if not ok:
            bad.append('trial %d (killed at line %d): exit %d' % (t, target, r.returncode))
        shutil.rmtree(out, ignore_errors=True)
    return same, k, bad


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--mutants', type=int, default=2000)
    ap.add_argument('--kills', type=int, default=20)
    ap.add_argument('--seed', default='report')
    ap.add_argument('--no-write', action='store_true')
    a = ap.parse_args()
    t0 = time.time()
    rows = []
    total_pass, total_fail = 0, 0
    for name in CHECKS:
        npass, fails, rc = run_check(name)
        total_pass += npass
        total_fail += len(fails) + (rc != 0 and not fails)
        rows.append('| hostile and failing cases: `tests/scenes/%s/check.py` | %d asserted, %d failed%s |'
                    % (name, npass + len(fails), len(fails), '' if rc == 0 else ' (crashed, exit %d)' % rc))
        for f in fails:
            print(f)
    n, failures, stats = fuzz.fuzz(a.mutants, seed=a.seed, jobs=2, batch=max(a.mutants, 1), verbose=False)
    ex = stats['exit']
    hangs = ex.get('timeout', 0)
    crashes = len(failures) - sum(1 for f in failures if f[2] == 'timeout')
    rows.append('| fuzzed scenes: `tests/fuzz/fuzz.py --mutants %d --seed %s` | %d tried: %d ran (exit 0), %d refused '
                'with a message (exit 2), %d stopped with a message (exit 1); %d crashes, %d hangs |'
                % (a.mutants, a.seed, n, ex.get('0', 0), ex.get('2', 0), ex.get('1', 0), crashes, hangs))
    same, k, bad = kills(a.kills, a.seed)
    rows.append('| SIGKILL at a random step, then `--restart`: `tools/reliability_report.py --kills %d` | %d of %d '
                'restarts bit for bit (history.csv, probes.csv) |' % (k, same, k))
    for b in bad:
        print('FAIL kill ' + b)
    table = '\n'.join([
        BEGIN,
        '## Results (%s, `make reliability`, %.0f s)' % (datetime.date.today().isoformat(), time.time() - t0),
        '',
        'Generated by `tools/reliability_report.py` on `%s`; silent wrong answers are counted by the'
        % os.path.relpath(sc.REBOND, ROOT),
        'checks, each of which asserts the result or the refusal of its case.',
        '',
        '| what was tried (command) | outcome |',
        '|---|---|'] + rows + ['', END])
    print(table)
    if not a.no_write:
        doc = open(DOC).read()
        if BEGIN in doc and END in doc:
            doc = doc[:doc.index(BEGIN)] + table + doc[doc.index(END) + len(END):]
        else:
            doc = doc.rstrip('\n') + '\n\n' + table + '\n'
        with open(DOC, 'w') as f:
            f.write(doc)
    ok = total_fail == 0 and crashes == 0 and hangs == 0 and same == k
    print('%d passed, %d failed' % (total_pass + (n - len(failures)) + same, total_fail + len(failures) + k - same))
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main())
