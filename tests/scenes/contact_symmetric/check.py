"""IMPACT SYMMETRIC (docs/contact.md): the contact nodes keep their mass (their element couplings
lumped on them); the kinetic energy an establishment takes (their normal velocity stopped) and
the step's loss (10) are held by the condition and given back at its release as an impulse on the
released nodes: the release is the impact reversed. The default (IMPACT AUTO) on MASS MIXED.

On code_aster SDNV100's bar (../contact_massless/sdnv100_bar.dat with MASS MIXED, h = dx/(10c)):
- AUTO takes SYMMETRIC on a MIXED mass (stdout), MASSLESS on the consistent one;
- at 20 elements the rebound within 0.5 % of 100 m/s (measured -0.354 %), and within 0.1 % of the
  semi-discrete limit of the same mesh (h ten times smaller; measured 0.04 %);
- the rebound error falls at every refinement, 20, 40, 80 elements (it converges with N);
- one contact onset, the wall never pulls, its impulses add up to the momentum change (1e-10),
  the force over the inner 80 % of the contact smooth (std/mean <= 5 %) and its mean within 1 % of
  rho c v0 A, |balance| <= 1e-10 of E;
- while the contact holds, contact_held holds the kinetic energy the establishment took from
  the contact node, 1/2 m_c v0^2 (m_c = rho A dx / 2 once its couplings are lumped, 80 J at 20
  elements; the gap closes at the end of a step, so (10) adds nothing), to 1e-9; after the
  release it is 0 again (1e-12 of E): everything held was given back;
- a restart from a checkpoint taken during the contact continues bit for bit (the held energy is
  in the checkpoint);
- a group the projection leaves without kinetic energy has nothing to give the held energy back
  with, and under gravity would stay down: it takes PAPER's reflection instead (symmetric_fallback).
  The point mass of inputs/mass_bounce.dat (g, dropped from 1 m) bounces 51 times in 46 s back to
  its height within g h^2/8 (the sampled apex), nothing held at the end, the same bits as PERSIST;
  the lumped beam of inputs/beam_land_flat.dat (every node lands in one step) bounces back to its
  height (1e-8 m) at 2 sqrt(2 d/g) within one step, as a rigid rod would.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402
import contactcheck as cc  # noqa: E402

BAR = os.path.join('tests', 'scenes', 'contact_massless', 'sdnv100_bar.dat')
M, V0, F, L, C = 8000 * 4e-4 * 0.2, 100.0, 8000 * 5000 * 100 * 4e-4, 0.2, 5000.0
MIXED = ['MODEL.bar.MASS=MIXED', 'SCHEME.IMPACT=AUTO']


def bar(n, cfl=0.1, extra=()):
    return ['LINE.bar.ELEMENTS=%d' % n, 'TIME.STEP=%r' % (cfl * L / n / C)] + MIXED + list(extra)


errs = {}
for n in (20, 40, 80):
    out = sc.run_ok(BAR, bar(n))
    h, c = sc.history(out), sc.contacts(out)
    tag = 'SYMMETRIC, MIXED, %d elements' % n
    err = h['momentum_x'][-1] / M / V0 - 1
    errs[n] = err
    cc.check_balance(tag, out)
    onsets = sum(1 for e in cc.events(out) if e[3] == 'establish')
    sc.report(tag + ': one contact onset', onsets == 1, '%d onsets' % onsets)
    sc.report(tag + ': the wall never pulls', c['force_x'].min() >= 0.0)
    dp = h['momentum_x'][-1] - h['momentum_x'][0]
    sc.report(tag + ': impulses = momentum change (1e-10)', abs(c['impulse_x'].sum() - dp) <= 1e-10 * abs(dp),
              '%.6e vs %.6e N s' % (c['impulse_x'].sum(), dp))
    on = np.nonzero(c['force_x'] > 0)[0]
    f = c['force_x'][on[0]:on[-1] + 1]
    f = f[len(f) // 10:9 * len(f) // 10]
    sc.report_measured(tag + ': force over the contact smooth (std/mean <= 5 %) and its mean within 1 % of rho c v0 A',
                       f.std() / f.mean() <= 0.05 and abs(f.mean() / F - 1) <= 0.01,
                       'std/mean %.4f, mean %+.3f %%' % (f.std() / f.mean(), 100 * (f.mean() / F - 1)))
    e_scale = np.max(h['kinetic'] + h['internal'])
    held = h['contact_held'][(h['time'] > 3e-5) & (h['time'] < 9e-5)]
    mc = 8000 * 4e-4 * (L / n) / 2
    sc.report_measured(tag + ': held during the contact = 1/2 m_c v0^2 (1e-9), 0 after the release (1e-12 of E)',
                       np.max(np.abs(held / (0.5 * mc * V0**2) - 1)) <= 1e-9 and
                       abs(h['contact_held'][-1]) <= 1e-12 * e_scale,
                       'held %.9e J (1/2 m_c v0^2 = %.9e J), at the end %.1e J' %
                       (held.mean(), 0.5 * mc * V0**2, h['contact_held'][-1]))
    sc.report(tag + ': impact_dissipated never decreases (held energy is in contact_held)',
              np.all(np.diff(h['impact_dissipated']) >= 0.0) and h['impact_dissipated'][-1] == 0.0,
              'min change %.3e J, last %.3e J' % (np.diff(h['impact_dissipated']).min(), h['impact_dissipated'][-1]))
    if n == 20:
        sc.report_measured(tag + ': rebound within 0.5 % of 100 m/s', abs(err) <= 0.005, '%+.3f %%' % (100 * err))
        fine = sc.run_ok(BAR, bar(n, 0.01))
        lim = sc.history(fine)['momentum_x'][-1] / M / V0 - 1
        sc.report_measured(tag + ': within 0.1 % of the semi-discrete limit (h / 10)', abs(err - lim) <= 1e-3,
                           '%+.3f %% vs %+.3f %%' % (100 * err, 100 * lim))
sc.report_measured('SYMMETRIC, MIXED: the rebound error falls at every refinement (20, 40, 80)',
                   errs[20] < errs[40] < errs[80] < 0, ', '.join('%+.3f %%' % (100 * errs[n]) for n in (20, 40, 80)))

# AUTO's choice, said on stdout.
for sets, word in ((bar(20), 'IMPACT SYMMETRIC (AUTO)'), (['SCHEME.IMPACT=AUTO'], 'IMPACT MASSLESS (AUTO)')):
    r = sc.run_limited([sc.REBOND, BAR, '-o', sc.new_dir('auto')] + sum((['--set', s] for s in sets), []), 120,
                       cwd=sc.ROOT, capture_output=True, text=True)
    sc.report('IMPACT AUTO on the bar with %s: %s' % ('MASS MIXED' if 'MODEL.bar.MASS=MIXED' in sets else
                                                      'a consistent mass', word), r.returncode == 0 and word in r.stdout)

# A restart from a checkpoint taken while the contact holds (and holds energy) is bit for bit.
same, detail = sc.restart_same(BAR, bar(20, extra=['OUTPUT.CHECKPOINT=100']), '6e-5',
                               ('history.csv', 'contacts.csv', 'events.csv'))
sc.report('SYMMETRIC: a restart during the contact, history, contacts and events bit for bit', same, detail)

# Groups the projection leaves without kinetic energy: PAPER's reflection (symmetric_fallback).
out = sc.run_ok(os.path.join('inputs', 'mass_bounce.dat'), ['SCHEME.IMPACT=SYMMETRIC'])
y = sc.probes(out)['ball.UY']
apex = [y[i] for i in range(1, len(y) - 1) if y[i] >= y[i - 1] and y[i] > y[i + 1]]
onsets = sum(1 for e in cc.events(out) if e[3] == 'establish')
gh = 9.81 * 1.3e-3 ** 2 / 8
sc.report_measured('SYMMETRIC, point mass under gravity: 51 bounces in 46 s, every apex back to 1 m within g h^2/8',
                   onsets == 51 and len(apex) == 50 and max(abs(a) for a in apex) <= gh,
                   '%d onsets, %d apexes, lowest %.3e m (g h^2/8 = %.3e)' % (onsets, len(apex), min(apex), gh))
sc.report('SYMMETRIC, point mass: nothing held or dissipated at the end',
          sc.history(out)['contact_held'][-1] == 0.0 and sc.history(out)['impact_dissipated'][-1] == 0.0)
ref = sc.run_ok(os.path.join('inputs', 'mass_bounce.dat'), ['SCHEME.IMPACT=PERSIST'])
sc.report('SYMMETRIC, point mass: the same bits as PERSIST',
          np.array_equal(sc.probes(out)['ball.UY'], sc.probes(ref)['ball.UY']))
out = sc.run_ok(os.path.join('inputs', 'beam_land_flat.dat'), ['SCHEME.IMPACT=SYMMETRIC', 'MODEL.beam.MASS=LUMPED',
                                                                'OUTPUT.HISTORY=EVERY 1'])
p = sc.probes(out)
t, y = p['time'], p['beam.mid.UY']
apex = [(t[i], y[i]) for i in range(1, len(y) - 1) if y[i] >= y[i - 1] and y[i] > y[i + 1]]
period = 2 * (2 * 0.02 / 9.81) ** 0.5
sc.report_measured('SYMMETRIC, lumped beam landing flat: back to its height (1e-8 m) at 2 sqrt(2 d/g) within a step',
                   len(apex) >= 1 and abs(apex[0][1]) <= 1e-8 and abs(apex[0][0] - period) <= 1e-5,
                   'apex %s (period %.6f s)' % (['%.5f s: %.2e m' % a for a in apex[:2]], period))
