#!/usr/bin/python3
"""docs/accuracy-speed.md and docs/figures/study_*.png from the sweeps of `make studies`.

usage: accuracy_speed.py [--results results/studies] [--template studies/accuracy-speed.md.in]
                         [--doc docs/accuracy-speed.md] [--figures docs/figures] [--np N]

Reads results/studies/<study>/sweep.csv (rebond sweep) and, for quantities a METRIC cannot give,
each case's history.csv / events.csv / probes.csv:
- energy error against the exact energy: max |kinetic + stored + dissipated - external - E(0)| /
  max(kinetic + stored + dissipated). `max_rel_balance` measures kinetic + W_N (the
  sub-incremented work); for a nonlinear-elastic law with N = 1, W_N is the trapezoid work of
  plain Newmark and that balance is round-off whatever the error, `stored` (psi) is exact;
- centre-of-mass apex heights of the beam drops, y_c = y_c0 - external / (m g) (gravity is the
  only external force, M g consistent with the mass), highest sample of each flight between two
  impacts refined by the parabola through its neighbours (exact in free flight);
- first frequency of the released cantilever from the tip's zero up-crossings;
- dissipated energy at the end of the run.
Tables come from tools/sweep_table.py (messages of failed cases shortened); the reading of
each study is in the template, whose {placeholders} are filled with the measured numbers.
"""
import argparse
import datetime
import math
import os
import platform
import re
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sweep_table  # noqa: E402

G = 9.81
BEAM_MASS = 7800 * 1e-4 * 1.0        # rho A L of the dropped beams (inputs/beam_drop_*.dat)
GAP = 0.01                           # s: contact events closer than this are one impact (sweeps)
F1_EB = 8.382                        # Hz, cantilever_release: Euler-Bernoulli first frequency
T_SPRING = 2 * math.pi * math.sqrt(1 / 100.0)


# ---------------------------------------------------------------- reading
class Study:
    def __init__(self, results, name):
        self.name = name
        self.root = os.path.join(results, name)
        self.header, self.rows = sweep_table.read(os.path.join(self.root, 'sweep.csv'))
        for r in self.rows:
            r['_ok'] = r['status'] == 'ok'
            r['_h'] = num(r['time_step'])
            r['_wall'] = num(r['wall_time'])
            r['_path'] = os.path.join(self.root, r['dir'])

    def names(self):
        out = []
        for r in self.rows:
            if r['name'] not in out:
                out.append(r['name'])
        return out

    def of(self, name, ok=True):
        return [r for r in self.rows if r['name'] == name and (r['_ok'] or not ok)]

    def ref(self):
        return [r for r in self.rows if r['reference'] == '1'][0]


def num(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return float('nan')


def csv_cols(path):
    if not os.path.exists(path):
        return None
    with open(path) as f:
        head = f.readline().strip().split(',')
    data = np.loadtxt(path, delimiter=',', skiprows=1, ndmin=2)
    if data.size == 0:
        return None
    return {k: data[:, i] for i, k in enumerate(head)}


def history(r):
    if '_hist' not in r:
        r['_hist'] = csv_cols(os.path.join(r['_path'], 'history.csv'))
    return r['_hist']


def exact_energy_error(r):
    h = history(r)
    if h is None or not r['_ok']:
        return float('nan')
    tot = h['kinetic'] + h['stored'] + h['dissipated']
    return float(np.max(np.abs(tot - h['external'] - tot[0])) / np.max(tot))


def dissipated_end(r):
    h = history(r)
    return float(h['dissipated'][-1]) if h is not None and r['_ok'] else float('nan')


def iterations_per_step(r):
    return num(r['iterations']) / num(r['steps']) if r['_ok'] else float('nan')


def events(r):
    out = []
    path = os.path.join(r['_path'], 'events.csv')
    if not os.path.exists(path):
        return out
    with open(path) as f:
        f.readline()
        for line in f:
            p = line.strip().split(',')
            if len(p) >= 5:
                out.append((float(p[1]), p[4].strip()))
    return out


def impacts(ev):
    """[(first establish time, last event time, establish count)], events < GAP apart grouped."""
    out, last = [], None
    for t, kind in ev:
        if kind == 'establish' and (last is None or t - last > GAP):
            out.append([t, t, 0])
        if out:
            out[-1][1] = t
            out[-1][2] += kind == 'establish'
        last = t
    return out


def com_apexes(r, yc0):
    """Centre-of-mass height at the apex of each flight after an impact (NaN-free list)."""
    h = history(r)
    if h is None or not r['_ok']:
        return []
    t, yc = h['time'], yc0 - h['external'] / (BEAM_MASS * G)
    imp = impacts(events(r))
    res = []
    for i, (t0, t1, n) in enumerate(imp):
        t_next = imp[i + 1][0] if i + 1 < len(imp) else t[-1] + 1
        idx = np.nonzero((t > t1) & (t < t_next))[0]
        if len(idx) < 3:
            continue
        k = idx[int(np.argmax(yc[idx]))]
        if k == idx[0] or k == idx[-1]:
            continue                       # the flight ends (or the run does) before its apex
        ym, y0, yp = yc[k - 1], yc[k], yc[k + 1]
        a = ym - 2 * y0 + yp
        res.append(y0 - (yp - ym) ** 2 / (8 * a) if a < 0 else y0)
    return res


def frequency(r, probe):
    """Mean frequency of the probe from its zero up-crossings (linear interpolation)."""
    p = csv_cols(os.path.join(r['_path'], 'probes.csv'))
    if p is None or not r['_ok']:
        return float('nan')
    t, u = p['time'], p[probe]
    k = np.nonzero((u[:-1] < 0) & (u[1:] >= 0))[0]
    if len(k) < 2:
        return float('nan')
    tc = t[k] - u[k] * (t[k + 1] - t[k]) / (u[k + 1] - u[k])
    return (len(tc) - 1) / (tc[-1] - tc[0])


# ---------------------------------------------------------------- tables
def short_message(m):
    m = re.sub(r'\s*\(tolerance.*', '', m)
    m = re.sub(r';\s*residual norms:.*', '', m)
    m = re.sub(r'0\.(\d{3})\d*E-(\d)', lambda g: '%.3g' % float('0.%sE-%s' % (g.group(1), g.group(2))), m)
    return m[:110]


def table(st, drop=()):
    """sweep_table.py's Markdown, without the columns in `drop`; a failed case shows its
    shortened message and no steps, iterations or balance (the sweep writes 0 for them)."""
    header = [c for c in st.header if c not in drop]
    rows = []
    for r in st.rows:
        r2 = dict(r)
        if not r['_ok']:
            r2['message'] = short_message(r['message'])
            r2['steps'] = r2['iterations'] = r2['max_rel_balance'] = 'nan'
        rows.append(r2)
    return sweep_table.markdown(header, rows)


def md_table(cols, rows):
    out = ['| ' + ' | '.join(cols) + ' |', '|' + '---|' * len(cols)]
    out += ['| ' + ' | '.join(str(c) for c in row) + ' |' for row in rows]
    return '\n'.join(out) + '\n'


def g(x, d=2):
    return '—' if x is None or (isinstance(x, float) and math.isnan(x)) else '%.*e' % (d, x)


def hlabel(st, r):
    return r.get('TIME.STEP', r['time_step'])


# ---------------------------------------------------------------- plots
def plt_setup():
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    plt.rcParams.update({'font.size': 9, 'axes.titlesize': 10, 'legend.fontsize': 8})
    return plt


STYLE = {}


def style(i):
    colors = ['C0', 'C1', 'C2', 'C3', 'C4', 'C5', 'C6', 'C7']
    marks = ['o', 's', '^', 'v', 'D', 'P', 'X', '*']
    lines = ['-', '-', '-', '--', '--', '--', ':', ':']
    return dict(color=colors[i % 8], marker=marks[i % 8], linestyle=lines[i % 8])


def curve(ax, xs, ys, label, i, logx=True, logy=True, ms=5, lw=1.3, **kw):
    pts = [(x, y) for x, y in zip(xs, ys) if not (math.isnan(x) or math.isnan(y)) and
           (x > 0 or not logx) and (y > 0 or not logy)]
    pts.sort()
    if not pts:
        return
    ax.plot([p[0] for p in pts], [p[1] for p in pts], label=label, ms=ms, lw=lw, **style(i), **kw)
    if logx:
        ax.set_xscale('log')
    if logy:
        ax.set_yscale('log')


def finish(fig, axes, path):
    for ax in axes:
        ax.grid(True, which='both', alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


# ---------------------------------------------------------------- studies
def loglog_interp(xs, ys, y):
    """x where the piecewise log-log line through (xs, ys) (sorted by x, y increasing) first
    reaches y; None outside."""
    pts = sorted((x, v) for x, v in zip(xs, ys) if x > 0 and v > 0)
    for (x0, y0), (x1, y1) in zip(pts, pts[1:]):
        if y0 <= y <= y1 and y1 > y0:
            f = (math.log(y) - math.log(y0)) / (math.log(y1) - math.log(y0))
            return math.exp(math.log(x0) + f * (math.log(x1) - math.log(x0)))
    return None


def correction_study(st, fig_path, plt, probe, energy, scene_label, hunit=None):
    """Three panels: energy error vs h, energy error vs wall time, probe error vs wall time."""
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6))
    perr = 'err_' + probe
    for i, n in enumerate(st.names()):
        rs = st.of(n)
        hs = [r['_h'] / hunit if hunit else r['_h'] for r in rs]
        es = [energy(r) for r in rs]
        curve(axes[0], hs, es, n, i)
        curve(axes[1], [r['_wall'] for r in rs], es, n, i)
        curve(axes[2], [r['_wall'] for r in rs], [num(r[perr]) for r in rs], n, i)
    axes[0].set_xlabel('time step h' + (' / T' if hunit else ' (s)'))
    axes[0].set_ylabel('energy error (max, relative to the total energy)')
    axes[0].set_title('%s: energy error vs step' % scene_label)
    axes[1].set_xlabel('wall time per run (s)')
    axes[1].set_ylabel('energy error')
    axes[1].set_title('energy error vs cost')
    axes[2].set_xlabel('wall time per run (s)')
    axes[2].set_ylabel('error of %s (see table)' % probe)
    axes[2].set_title('probe error vs cost (reference: finest run)')
    axes[0].legend(ncol=2)
    finish(fig, axes, fig_path)
    plt.close(fig)


def study_spring(st, figdir, plt, v):
    correction_study(st, os.path.join(figdir, 'study_spring_correction.png'), plt,
                     'tip.UX@3.141592653589793', exact_energy_error, 'nonlinear spring', hunit=T_SPRING)
    rows = []
    for n in st.names():
        for r in st.of(n, ok=False):
            rows.append([n, 'T/%g' % round(T_SPRING / r['_h'], 3) if r['_h'] < T_SPRING else 'T',
                         g(num(r['max_rel_balance']), 1), g(exact_energy_error(r), 2)])
    v['spring_energy_table'] = md_table(['case', 'h', 'max rel. balance (kinetic + W_N)',
                                         'energy error (kinetic + ψ, exact)'], rows)
    off = st.of('off_N16')
    hs_off, e_off = [r['_h'] for r in off], [exact_energy_error(r) for r in off]
    for n, key in [('on_N16', '16'), ('on_N4', '4')]:
        on = st.of(n)
        hs_on, e_on = [r['_h'] for r in on], [exact_energy_error(r) for r in on]
        for lev, lk in [(1e-4, '1e4'), (1e-3, '1e3')]:
            a, b = loglog_interp(hs_off, e_off, lev), loglog_interp(hs_on, e_on, lev)
            v['spring_hoff_%s' % lk] = 'T/%.0f' % (T_SPRING / a) if a else '—'
            v['spring_hon%s_%s' % (key, lk)] = 'T/%.1f' % (T_SPRING / b) if b else '—'
            v['spring_ratio%s_%s' % (key, lk)] = '%.0f' % (b / a) if a and b else '—'
    pick = {n: {round(T_SPRING / r['_h']): r for r in st.of(n)} for n in st.names()}
    for n in ['on_N16', 'on_N4', 'on_N1', 'off_N16']:
        for div in (200, 10):
            r = pick[n].get(div)
            v['spring_e_%s_%d' % (n, div)] = g(exact_energy_error(r), 1) if r else '—'
            v['spring_p_%s_%d' % (n, div)] = g(num(r['err_tip.UX@3.141592653589793']), 1) if r else '—'
    for div in (200, 10):
        a, b = pick['on_N16'].get(div), pick['off_N16'].get(div)
        v['spring_itratio_%d' % div] = '%.1f' % (num(a['iterations']) / num(b['iterations'])) if a and b else '—'
    v['spring_bal_offN1'] = g(max(num(r['max_rel_balance']) for r in st.of('off_N1')), 0)
    v['table_spring'] = table(st, drop=('SCHEME.ENERGY_CORRECTION', 'MODEL.spring.SUBSTEPS'))


def study_cantilever(st, figdir, plt, v):
    correction_study(st, os.path.join(figdir, 'study_cantilever_correction.png'), plt,
                     'beam.end.UY@0.5', lambda r: num(r['max_rel_balance']) if r['_ok'] else float('nan'),
                     'plastic cantilever')
    on = [r for n in st.names() if n.startswith('on_N') and n != 'on_N1' for r in st.of(n)]
    off = [r for n in st.names() if n.startswith('off_N') and n != 'off_N1' for r in st.of(n)]
    v['cant_on_bal_max'] = g(max(num(r['max_rel_balance']) for r in on), 0)
    v['cant_off_bal_min'] = g(min(num(r['max_rel_balance']) for r in off), 1)
    v['cant_off_bal_max'] = g(max(num(r['max_rel_balance']) for r in off), 1)
    v['cant_hmax_on'] = '%g' % max(r['_h'] for r in on)
    v['cant_hmin_off'] = '%g' % min(r['_h'] for r in off)
    v['cant_failed'] = str(sum(not r['_ok'] for r in st.rows))
    by = {(r['name'], r['TIME.STEP']): r for r in st.rows}
    for n in ['on_N16', 'off_N16', 'on_N1']:
        for h in ['5e-5', '2e-4', '2e-3']:
            r = by.get((n, h))
            v['cant_p_%s_%s' % (n, h)] = g(num(r['err_beam.end.UY@0.5']), 1) if r else '—'
    ref = st.ref()
    rows = []
    for n in st.names():
        for r in st.of(n):
            rows.append([n, hlabel(st, r), '%.4f' % dissipated_end(r),
                         g(abs(dissipated_end(r) - dissipated_end(ref)) / dissipated_end(ref), 1)])
    v['cant_diss_table'] = md_table(['case', 'h (s)', 'dissipated at 0.6 s (J)', 'rel. error vs reference'],
                                    rows)
    v['table_cantilever'] = table(st, drop=('SCHEME.ENERGY_CORRECTION', 'MODEL.beam.SUBSTEPS'))


def study_drops(sv, si, figdir, plt, v):
    fig, axes = plt.subplots(2, 2, figsize=(12, 8.4))
    for row, (st, yc0, napex, label, key) in enumerate(
            [(sv, 0.52, 3, 'vertical drop', 'vert'), (si, 0.07, 4, 'inclined drop', 'incl')]):
        apex_rows = []
        for i, n in enumerate(st.names()):
            rs = st.of(n)
            ap = [com_apexes(r, yc0) for r in rs]
            for r, a in zip(rs, ap):
                r['_apex'] = a
                imp = impacts(events(r))
                r['_onsets'] = [x[2] for x in imp]
                apex_rows.append([n, hlabel(st, r), len(a)] +
                                 ['%.2f' % (1000 * x) for x in a[:napex]] + ['—'] * (napex - len(a[:napex])) +
                                 ['%.1f' % (sum(r['_onsets']) / len(imp)) if imp else '—'])
            for k in range(napex):
                ys = [1000 * a[k] if len(a) > k else float('nan') for a in ap]
                curve(axes[row, 0], [r['_h'] for r in rs], ys, '%s, apex %d' % (n, k + 1) if True else None,
                      i, logy=False, ms=4 + k, lw=1.0 if k else 1.6)
            mean_on = [sum(r['_onsets']) / len(r['_onsets']) if r['_onsets'] else float('nan') for r in rs]
            curve(axes[row, 1], [r['_h'] for r in rs], mean_on, n + ', mean over impacts', i)
            curve(axes[row, 1], [r['_h'] for r in rs], [num(r['onsets1']) for r in rs], n + ', first impact', i,
                  lw=0.8, ms=3, alpha=0.6)
        axes[row, 0].set_xlabel('time step h (s)')
        axes[row, 0].set_ylabel('centre-of-mass apex height (mm)')
        axes[row, 0].set_title('%s: rebound apexes of the centre of mass' % label)
        axes[row, 0].legend(ncol=3, fontsize=6.5)
        axes[row, 1].set_xlabel('time step h (s)')
        axes[row, 1].set_ylabel('contact onsets (establish events) per impact')
        axes[row, 1].set_title('%s: onsets per impact (events < %g s apart = one impact)' % (label, GAP))
        axes[row, 1].legend(fontsize=7)
        v['apex_table_' + key] = md_table(['case', 'h (s)', 'flights with apex'] +
                                          ['apex %d (mm)' % (k + 1) for k in range(napex)] +
                                          ['mean onsets / impact'], apex_rows)
        v['table_drop_' + key] = table(st, drop=('SCHEME.IMPACT',))
        # headline numbers
        fin = {n: min(st.of(n), key=lambda r: r['_h']) for n in st.names()}
        crs = {n: max(st.of(n), key=lambda r: r['_h']) for n in st.names()}
        for n in st.names():
            a = fin[n]['_apex']
            v['%s_apex1_%s' % (key, n)] = '%.2f' % (1000 * a[0]) if a else '—'
            a1 = [1000 * r['_apex'][0] for r in st.of(n) if r['_apex']]
            v['%s_apex1_range_%s' % (key, n)] = '%.2f–%.2f' % (min(a1), max(a1)) if a1 else '—'
            v['%s_on_fine_%s' % (key, n)] = '%.1f' % (sum(fin[n]['_onsets']) / len(fin[n]['_onsets']))
            v['%s_on_coarse_%s' % (key, n)] = '%.1f' % (sum(crs[n]['_onsets']) / len(crs[n]['_onsets']))
            lo = g(min(num(r['max_rel_balance']) for r in st.of(n)), 0)
            hi = g(max(num(r['max_rel_balance']) for r in st.of(n)), 0)
            v['%s_bal_%s' % (key, n)] = lo if lo == hi else '%s–%s' % (lo, hi)
            v['%s_cd_%s' % (key, n)] = '%s' % ', '.join(
                '%.0f' % (1e6 * num(r['contact_duration'])) for r in sorted(st.of(n), key=lambda r: r['_h'])
                if 'contact_duration' in r) if 'contact_duration' in st.header else '—'
        v['%s_hfine' % key] = '%g' % min(r['_h'] for r in st.rows)
        v['%s_hcoarse' % key] = '%g' % max(r['_h'] for r in st.rows)
    axes[0, 0].axhline(520, color='k', lw=0.8, ls=':')
    axes[0, 0].annotate('rigid rebound (520 mm)', (sv.rows[0]['_h'], 520), fontsize=7, va='bottom')
    finish(fig, axes.ravel(), os.path.join(figdir, 'study_beam_drops.png'))
    plt.close(fig)


def study_iteration(ss, sc, figdir, plt, v):
    fig, axes = plt.subplots(2, 3, figsize=(15, 8.4))
    for row, (st, probe, label, hunit) in enumerate([(ss, 'tip.UX@3.141592653589793', 'nonlinear spring', T_SPRING),
                                                     (sc, 'beam.end.UY@0.5', 'plastic cantilever', None)]):
        for i, n in enumerate(st.names()):
            rs = st.of(n)
            hs = [r['_h'] / hunit if hunit else r['_h'] for r in rs]
            curve(axes[row, 0], hs, [iterations_per_step(r) for r in rs], n, i, logy=False)
            curve(axes[row, 1], hs, [r['_wall'] for r in rs], n, i)
            curve(axes[row, 2], [r['_wall'] for r in rs], [num(r['err_' + probe]) for r in rs], n, i)
            bad = [r for r in st.of(n, ok=False) if not r['_ok']]
            if bad:
                axes[row, 0].plot([r['_h'] / hunit if hunit else r['_h'] for r in bad], [0.5] * len(bad), 'x',
                                  color=style(i)['color'], ms=9, mew=2,
                                  label='%s: failed (did not converge)' % n)
        xl = 'time step h' + (' / T' if hunit else ' (s)')
        axes[row, 0].set_xlabel(xl)
        axes[row, 0].set_ylabel('iterations per step (x: run failed)')
        axes[row, 0].set_title('%s: iterations per step' % label)
        axes[row, 0].set_ylim(bottom=0)
        axes[row, 1].set_xlabel(xl)
        axes[row, 1].set_ylabel('wall time per run (s)')
        axes[row, 1].set_title('%s: cost' % label)
        axes[row, 2].set_xlabel('wall time per run (s)')
        axes[row, 2].set_ylabel('error of %s' % probe.split('@')[0])
        axes[row, 2].set_title('%s: probe error vs cost' % label)
        axes[row, 0].legend(fontsize=7)
    finish(fig, axes.ravel(), os.path.join(figdir, 'study_iteration.png'))
    plt.close(fig)
    for st, key in [(ss, 'its'), (sc, 'itc')]:
        rows = []
        for n in st.names():
            for r in st.of(n, ok=False):
                rows.append([n, hlabel(st, r), r['status'], '%.2f' % iterations_per_step(r) if r['_ok'] else '—',
                             '%.3g' % r['_wall']])
        v['%s_summary' % key] = md_table(['case', 'h', 'status', 'iterations / step', 'wall (s)'], rows)
        v['table_' + key] = table(st, drop=('SCHEME.ITERATION', 'SCHEME.ENERGY_CORRECTION'))
    el = {round(T_SPRING / r['_h']): r for r in ss.of('elastic', ok=False)}
    ta = {round(T_SPRING / r['_h']): r for r in ss.of('tangent', ok=False)}
    for d in (200, 10, 5):
        v['its_el_%d' % d] = '%.2f' % iterations_per_step(el[d]) if d in el else '—'
        v['its_ta_%d' % d] = '%.2f' % iterations_per_step(ta[d]) if d in ta else '—'
    fails = [r for r in ss.of('elastic', ok=False) if not r['_ok']]
    v['its_el_fail'] = ', '.join('T/%g' % round(T_SPRING / r['_h'], 2) if r['_h'] < T_SPRING else 'T'
                                 for r in fails) or 'none'
    for n in sc.names():
        f = [r['TIME.STEP'] for r in sc.of(n, ok=False) if not r['_ok']]
        v['itc_fail_%s' % n] = ', '.join(f) if f else 'none'
        by = {r['TIME.STEP']: r for r in sc.of(n, ok=False)}
        for h in ('5e-5', '2e-4', '1e-3'):
            r = by.get(h)
            v['itc_%s_%s' % (n, h)] = '%.2f' % iterations_per_step(r) if r and r['_ok'] else 'failed'
            v['itc_w_%s_%s' % (n, h)] = '%.2f' % r['_wall'] if r and r['_ok'] else '—'


def study_mass(st, figdir, plt, v):
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6))
    for i, n in enumerate(st.names()):
        rs = st.of(n)
        for r in rs:
            r['_f'] = frequency(r, 'beam.end.UY')
        curve(axes[0], [r['_wall'] for r in rs], [num(r['err_beam.end.UY@0.4']) for r in rs], n, i)
        for r in rs:
            axes[0].annotate('%s' % r['TIME.STEP'], (r['_wall'], num(r['err_beam.end.UY@0.4'])),
                             textcoords='offset points', xytext=(3, 3), fontsize=6, color=style(i)['color'])
        curve(axes[1], [r['_h'] for r in rs], [r['_f'] for r in rs], n, i, logy=False)
    axes[1].axhline(F1_EB, color='k', lw=0.8, ls=':')
    axes[1].annotate('Euler-Bernoulli continuum %.3f Hz' % F1_EB, (st.rows[0]['_h'], F1_EB), fontsize=7,
                     va='bottom')
    axes[0].set_xlabel('wall time per run (s)')
    axes[0].set_ylabel('error of the tip deflection at 0.4 s / static deflection')
    axes[0].set_title('cantilever release: probe error vs cost (labels: h)')
    axes[1].set_xlabel('time step h (s)')
    axes[1].set_ylabel('first frequency from zero crossings (Hz)')
    axes[1].set_title('cantilever release: measured frequency')
    axes[0].legend()
    axes[1].legend()
    finish(fig, axes, os.path.join(figdir, 'study_mass.png'))
    plt.close(fig)
    rows = [[n, r['TIME.STEP'], '%.4f' % r['_f'], g((r['_f'] - F1_EB) / F1_EB, 1)] for n in st.names()
            for r in st.of(n)]
    v['mass_freq_table'] = md_table(['case', 'h (s)', 'f (Hz)', '(f − 8.382) / 8.382'], rows)
    v['table_mass'] = table(st, drop=('MODEL.beam.MASS',))
    for n in st.names():
        rs = sorted(st.of(n), key=lambda r: r['_h'])
        v['mass_f_%s' % n] = '%.3f' % rs[0]['_f']
        v['mass_err_fine_%s' % n] = g(num(rs[0]['err_beam.end.UY@0.4']), 1)
        by = {r['TIME.STEP']: r for r in rs}
        for h in ('1e-4', '1e-3'):
            v['mass_err_%s_%s' % (n, h)] = g(num(by[h]['err_beam.end.UY@0.4']), 1) if h in by else '—'
            v['mass_w_%s_%s' % (n, h)] = '%.2f' % by[h]['_wall'] if h in by else '—'


def study_substeps(sc, sb, figdir, plt, v):
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6))
    for ax, st, col, probe, label, key in [(axes[0], sc, 'MODEL.beam.SUBSTEPS', 'beam.end.UY@0.5',
                                            'plastic cantilever (h = 2e-4 s)', 'subc'),
                                           (axes[1], sb, 'MODEL.block.SUBSTEPS', 'block.top_left.UY@5e-3',
                                            'J2 block (h = 1e-5 s)', 'subb')]:
        ref = st.ref()
        dref = dissipated_end(ref)
        fixed = [r for r in st.rows if r['_ok'] and r[col] != 'AUTO' and r['reference'] != '1']
        auto = [r for r in st.rows if r['_ok'] and r[col] == 'AUTO']
        for i, (lab, f) in enumerate([('probe error', lambda r: num(r['err_' + probe])),
                                      ('dissipated energy error', lambda r: abs(dissipated_end(r) - dref) / dref)]):
            curve(ax, [r['_wall'] for r in fixed], [f(r) for r in fixed], 'fixed N: ' + lab, i)
            ax.plot([r['_wall'] for r in auto], [f(r) for r in auto], '*', ms=15, color=style(i)['color'],
                    mec='k', label='AUTO: ' + lab)
            for r in fixed:
                ax.annotate('N=%s' % r[col], (r['_wall'], f(r)), textcoords='offset points', xytext=(4, 3),
                            fontsize=7)
        ax.set_xscale('log')
        ax.set_yscale('log')
        ax.set_xlabel('wall time per run (s)')
        ax.set_ylabel('error against N = %s (same step)' % ref[col])
        ax.set_title('%s: fixed N vs AUTO' % label)
        ax.legend(fontsize=7)
        rows = [[r[col], r['status'], r['iterations'], '%.3g' % r['_wall'], '%.5f' % dissipated_end(r),
                 g(abs(dissipated_end(r) - dref) / dref, 1), g(num(r['err_' + probe]), 1)] for r in st.rows]
        v['%s_table' % key] = md_table(['N', 'status', 'iterations', 'wall (s)', 'dissipated (J)',
                                        'err dissipated', 'err probe'], rows)
        v['table_' + key] = table(st)
        by = {r[col]: r for r in st.rows}
        for n in ('1', '2', '4', '8', '16', 'AUTO'):
            r = by.get(n)
            v['%s_pe_%s' % (key, n)] = g(num(r['err_' + probe]), 1) if r else '—'
            v['%s_de_%s' % (key, n)] = g(abs(dissipated_end(r) - dref) / dref, 1) if r else '—'
            v['%s_w_%s' % (key, n)] = '%.2f' % r['_wall'] if r else '—'
        v['%s_w_ref' % key] = '%.2f' % ref['_wall']
        ra, r4 = by.get('AUTO'), by.get('4')
        v['%s_auto_vs_4' % key] = ('%.0f' % ((abs(dissipated_end(ra) - dref)) / abs(dissipated_end(r4) - dref))
                                   if ra and r4 else '—')
    finish(fig, axes, os.path.join(figdir, 'study_substeps.png'))
    plt.close(fig)


# ---------------------------------------------------------------- main
def machine():
    cpu = 'unknown CPU'
    try:
        with open('/proc/cpuinfo') as f:
            for line in f:
                if line.startswith('model name'):
                    cpu = line.split(':', 1)[1].strip()
                    break
    except OSError:
        pass
    try:
        fc = subprocess.run(['gfortran', '--version'], capture_output=True, text=True).stdout.splitlines()[0]
    except (OSError, IndexError):
        fc = 'gfortran'
    return '%s, %d cores (nproc), %s %s, %s' % (cpu, os.cpu_count() or 0, platform.system(), platform.release(),
                                               fc)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--results', default='results/studies')
    ap.add_argument('--template', default='studies/accuracy-speed.md.in')
    ap.add_argument('--doc', default='docs/accuracy-speed.md')
    ap.add_argument('--figures', default='docs/figures')
    ap.add_argument('--np', default='?', help='the mpirun -np of the sweeps (for the text)')
    a = ap.parse_args(argv)
    plt = plt_setup()
    os.makedirs(a.figures, exist_ok=True)
    S = lambda n: Study(a.results, n)  # noqa: E731
    v = {'machine': machine(), 'np': a.np, 'date': datetime.date.today().isoformat()}
    study_spring(S('spring_correction'), a.figures, plt, v)
    study_cantilever(S('cantilever_correction'), a.figures, plt, v)
    study_drops(S('drop_vertical'), S('drop_inclined'), a.figures, plt, v)
    study_iteration(S('iteration_spring'), S('iteration_cantilever'), a.figures, plt, v)
    study_mass(S('mass_matrix'), a.figures, plt, v)
    study_substeps(S('substeps_cantilever'), S('substeps_block'), a.figures, plt, v)
    with open(a.template) as f:
        text = f.read()
    missing = sorted(set(re.findall(r'\{(\w+)\}', text)) - set(v))
    if missing:
        raise SystemExit('accuracy_speed.py: template placeholders without a value: ' + ', '.join(missing))
    with open(a.doc, 'w') as f:
        f.write(text.format(**v))
    print('accuracy_speed.py: wrote %s and %s/study_*.png' % (a.doc, a.figures))


if __name__ == '__main__':
    main()
