"""The adaptive step (TIME … ADAPTIVE TOLERANCE tol [MIN hmin] [MAX hmax], src/time/step_control.f90).

1. The point mass of inputs/mass_bounce.dat (5 s, six impacts): the onsets located (EVENTS AUTO
   locates under ADAPTIVE) at the exact instants of a bounce held STEP/32 on the ground (the
   step after an onset), (2k - 1) t_f + (k - 1) STEP/32, to 1e-10 s; the energy height at H at
   every row (1e-10: every step exact in energy, of any length); |balance| <= 1e-10 of E; fewer
   than a tenth of the fixed run's steps.
2. history.csv's h: each row's h is its time less the previous row's; the lengths within
   [MIN, MAX] and STEP x 2^k for the steps the controller chose (a step cut at an event or a kink
   is shorter).
3. The smooth vibration of inputs/cantilever_release.dat (1 s): the error of the tip against a run
   at STEP/16 falls as the tolerance falls (1e-3, 1e-4, 1e-5: each at most half the previous),
   the step count grows about as tol^(-1/2) (the estimate goes as h^2: between 2 and 5 times the
   steps per decade), |balance| <= 1e-10 of E.
4. The plastic block of inputs/block_j2.dat (a FUNCTION POINTS pulse, kinks at 1, 2 and 3 ms):
   each kink is a step end (to 1e-15 s), the plastic work appears, |balance| <= 1e-10 of E.
5. A step that fails is halved by the controller: inputs/spring_nonlinear.dat with ITERATION
   ELASTIC, MAX_ITERATIONS 3 and RETRY 0 stops (exit 1) at its fixed step, and runs to the end
   adaptive (MIN = STEP/4), its balance within 1e-9 of E.
6. Restart: an adaptive run stopped at 2.5 s and restarted from its checkpoint writes the same
   history.csv and probes.csv as the run in one go, byte for byte; a fixed-step run's checkpoint
   is refused by an adaptive run (exit 2: another TIME statement).
7. Bad input (exit 2, file:line, the statement and the word, nothing written): TOLERANCE 0,
   TOLERANCE -1, MIN above STEP, MAX below STEP, TOLERANCE without ADAPTIVE, ADAPTIVE without
   TOLERANCE.
"""
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402
import contactcheck as cc  # noqa: E402

ADAPT = ['TIME.ADAPTIVE=', 'TIME.TOLERANCE=1e-4']

# 1. The bouncing point mass.
BOUNCE = 'inputs/mass_bounce.dat'
STEP = 1.3e-3
TF = np.sqrt(2 * 1.0 / cc.G)
out = sc.run_ok(BOUNCE, ['TIME.END=5', 'OUTPUT.HISTORY=EVERY 1'] + ADAPT)
hist = sc.history(out)
t = hist['time']
est = [e[1] for e in cc.events(out) if e[3] == 'establish']
onsets = np.array([t[np.searchsorted(t, x) - 1] for x in est])
exact = np.array([(2 * k + 1) * TF + k * STEP / 32 for k in range(len(onsets))])
n_exact = sum(1 for k in range(10) if (2 * k + 1) * TF + k * STEP / 32 < 5.0)
err = np.max(np.abs(onsets - exact)) if len(onsets) else np.inf
sc.report_measured('mass_bounce ADAPTIVE: %d onsets at (2k - 1) t_f + (k - 1) STEP/32 (1e-10 s)' % n_exact,
                   len(onsets) == n_exact and err <= 1e-10, '%d onsets, max error %.2e s' % (len(onsets), err))
y = 1.0 + sc.probes(out)['ball.UY']
apex_h = y + hist['kinetic'] / cc.G
dev = np.max(np.abs(apex_h - 1.0))
sc.report_measured('mass_bounce ADAPTIVE: the energy height y + T/(m g) at H at every row (1e-10)', dev <= 1e-10,
                   '%.2e m' % dev)
cc.check_balance('mass_bounce ADAPTIVE', out)
fixed_steps = int(round(5 / STEP))
sc.report_measured('mass_bounce ADAPTIVE: fewer than a tenth of the fixed run\'s steps', len(t) - 1 < fixed_steps / 10,
                   '%d steps against %d' % (len(t) - 1, fixed_steps))

# 2. The h column.
h = hist['h']
ok_diff = np.max(np.abs(h[1:] - np.diff(t))) <= 1e-15 * t[-1]
sc.report('history.csv h: each row\'s time less the previous row\'s', h[0] == 0.0 and ok_diff)
hmin, hmax = STEP / 1024, STEP * 256
k = np.log2(h[1:] / STEP)
cut = set(np.searchsorted(t, est) - 1)                 # the steps cut at an onset end there
chosen = [i for i in range(len(k)) if (i + 1) not in cut]
hc = h[1:][chosen]
sc.report('history.csv h: the controller\'s steps within [MIN, MAX] (a cut at an event may be shorter)',
          np.all(hc >= hmin * (1 - 1e-9)) and np.all(hc <= hmax * (1 + 1e-9)), '%.3e ... %.3e' % (hc.min(), hc.max()))
off = max(abs(k[i] - round(k[i])) for i in chosen)
sc.report('history.csv h: the controller\'s steps are STEP x 2^k (events aside)', off <= 1e-9, 'max |log2 - int| %.1e' % off)

# 3. The smooth vibration.
CANT = 'inputs/cantilever_release.dat'
ref = sc.probes(sc.run_ok(CANT, ['TIME.END=1', 'TIME.STEP=6.25e-6', 'OUTPUT.FIELDS=0']))
scale = np.max(np.abs(ref['beam.end.UY']))
errs, steps = [], []
for tol in ('1e-3', '1e-4', '1e-5'):
    out = sc.run_ok(CANT, ['TIME.END=1', 'OUTPUT.FIELDS=0', 'TIME.ADAPTIVE=', 'TIME.TOLERANCE=' + tol])
    p = sc.probes(out)
    keep = p['time'] <= 1.0
    errs.append(np.max(np.abs(p['beam.end.UY'][keep] - np.interp(p['time'][keep], ref['time'], ref['beam.end.UY'])))
                / scale)
    steps.append(len(p['time']) - 1)
    cc.check_balance('cantilever ADAPTIVE TOLERANCE ' + tol, out)
ratios = [steps[i + 1] / steps[i] for i in range(2)]
sc.report_measured('cantilever ADAPTIVE: the error falls with the tolerance (each at most half the previous)',
                   errs[1] <= 0.5 * errs[0] and errs[2] <= 0.5 * errs[1],
                   'errors %s at tolerances 1e-3, 1e-4, 1e-5' % ', '.join('%.2e' % e for e in errs))
sc.report_measured('cantilever ADAPTIVE: 2 to 5 times the steps per decade of tolerance (h ~ tol^(1/2))',
                   all(2.0 <= r <= 5.0 for r in ratios), 'steps %s' % steps)

# 4. The plastic block and its pulse's kinks.
out = sc.run_ok('inputs/block_j2.dat', ['OUTPUT.FIELDS=0'] + ADAPT)
hist = sc.history(out)
t = hist['time']
miss = max(np.min(np.abs(t - tk)) for tk in (1e-3, 2e-3, 3e-3))
sc.report_measured('block_j2 ADAPTIVE: the pulse\'s kinks at 1, 2, 3 ms are step ends (1e-15 s)', miss <= 1e-15,
                   'max distance %.1e s' % miss)
sc.report('block_j2 ADAPTIVE: plastic work', hist['dissipated'][-1] > 0, '%.3e J' % hist['dissipated'][-1])
cc.check_balance('block_j2 ADAPTIVE', out)

# 5. A failing step halved.
SPRING = 'inputs/spring_nonlinear.dat'
hard = ['SCHEME.ITERATION=ELASTIC', 'SCHEME.MAX_ITERATIONS=3', 'SCHEME.RETRY=0']
rc, err_text, _ = sc.run(SPRING, hard)
sc.report('spring, MAX_ITERATIONS 3, RETRY 0, fixed step: stops (exit 1)', rc == 1, 'exit %d' % rc)
rc, err_text, out = sc.run(SPRING, hard + ['TIME.ADAPTIVE=', 'TIME.TOLERANCE=1e-2', 'TIME.MIN=7.8539816339744833e-4'])
ok = rc == 0
sc.report('spring, MAX_ITERATIONS 3, RETRY 0, ADAPTIVE: runs to the end, its failing steps halved', ok and
          sc.history(out)['time'][-1] >= 10.0, 'exit %d %s' % (rc, err_text[-300:]))
if ok:
    rel, n = sc.relative_balance(out)
    sc.report_measured('spring ADAPTIVE, halved failing steps: |balance| <= 1e-9 of E', rel <= 1e-9, '%.2e' % rel)

# 6. Restart.
sets = ['TIME.END=5', 'OUTPUT.CHECKPOINT=1', 'OUTPUT.HISTORY=EVERY 1'] + ADAPT
same, detail = sc.restart_same(BOUNCE, sets, '2.5', files=('history.csv', 'probes.csv'))
sc.report('mass_bounce ADAPTIVE restarted at 2.5 s: the same files byte for byte', same, detail)
fixed = sc.run_ok(BOUNCE, ['TIME.END=1', 'OUTPUT.CHECKPOINT=1'])
r = subprocess.run([sc.REBOND, BOUNCE, '-o', fixed, '--quiet', '--restart', os.path.join(fixed, 'checkpoint.h5'),
                    '--set', 'TIME.END=2'] + sum((['--set', x] for x in ADAPT), []),
                   cwd=sc.ROOT, capture_output=True, text=True)
sc.report('a fixed-step checkpoint restarted ADAPTIVE: refused (exit 2, another TIME statement)',
          r.returncode == 2 and 'TIME' in r.stderr and 'checkpoint' in r.stderr, r.stderr[-300:])

# 7. Bad input.
BASE = open(os.path.join(sc.ROOT, BOUNCE)).read()
CASES = [('TIME      STEP 1.3e-3 END 46 ADAPTIVE TOLERANCE 0', "'0'"),
         ('TIME      STEP 1.3e-3 END 46 ADAPTIVE TOLERANCE -1', "'-1'"),
         ('TIME      STEP 1.3e-3 END 46 ADAPTIVE TOLERANCE 1e-3 MIN 2e-3', "'2e-3'"),
         ('TIME      STEP 1.3e-3 END 46 ADAPTIVE TOLERANCE 1e-3 MAX 1e-3', "'1e-3'"),
         ('TIME      STEP 1.3e-3 END 46 TOLERANCE 1e-3', "'TOLERANCE'"),
         ('TIME      STEP 1.3e-3 END 46 ADAPTIVE', "'ADAPTIVE'")]
for i, (line, word) in enumerate(CASES):
    text = BASE.replace('TIME      STEP 1.3e-3 END 46', line)
    path = sc.write_scene('bad_adaptive_%d.dat' % i, text)
    nline = [n + 1 for n, ln in enumerate(text.splitlines()) if ln.startswith('TIME')][0]
    rc, err_text, bad_out = sc.run(path)
    msg = ' '.join(sc.message_lines(err_text))
    sc.report('bad input "%s": exit 2, file:line, TIME, the word %s, nothing written' % (line.split('46 ')[1], word),
              rc == 2 and 'bad_adaptive_%d.dat:%d' % (i, nline) in msg and 'TIME' in msg and word in msg and
              not os.path.exists(bad_out), msg)
