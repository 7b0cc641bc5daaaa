#!/usr/bin/python3
"""sweep.csv (written by `rebond sweep`) -> a Markdown table, and optionally a Pareto plot.

usage: sweep_table.py SWEEP.csv [--png PARETO.png] [--metric COLUMN] [-o TABLE.md]

The table has one row per case: case (* marks the reference), name, the varied parameters,
status, steps, iterations, wall time, max relative energy balance, then every metric with its
error against the reference; a message column is added when some case failed.

The Pareto plot shows the error of one metric (--metric, an err_* column or a metric name;
default: the first err_* column with a positive value) against the wall time of each run,
log-log, one curve per method variant: the CASE name, or when the sweep has no CASE
statements, the varied parameters other than TIME.STEP. Points with error 0 (the reference
itself) or no value cannot be drawn on a log scale and are left out (counted in the legend).
"""
import argparse
import csv
import math
import sys

FIXED = ['case', 'name', 'status', 'time_step', 'wall_time', 'steps', 'iterations', 'max_rel_balance',
         'reference', 'dir', 'message']


def read(path):
    with open(path, newline='') as f:
        rows = list(csv.DictReader(f))
        f.seek(0)
        header = next(csv.reader(f))
    return header, rows


def split_columns(header):
    """(parameter columns, metric columns, error columns) in table order."""
    i0 = header.index('status') + 1
    i1 = header.index('time_step')
    params = header[i0:i1]
    errs = [c for c in header if c.startswith('err_')]
    metrics = [c for c in header[header.index('max_rel_balance') + 1:] if not c.startswith('err_')
               and c not in FIXED]
    return params, metrics, errs


def num(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return float('nan')


def fmt(s, digits=3):
    x = num(s)
    if math.isnan(x):
        return '—' if s in ('', 'nan') else s
    if x == int(x) and abs(x) < 1e6:
        return '%d' % x
    return '%.*e' % (digits - 1, x)


def markdown(header, rows):
    params, metrics, errs = split_columns(header)
    failed = any(r['status'] != 'ok' for r in rows)
    named = any(r['name'] for r in rows)
    cols = ['case'] + (['name'] if named else []) + params + ['status', 'steps', 'iterations', 'wall (s)',
                                                               'max rel. balance']
    for m in metrics:
        cols += [m, 'err ' + m]
    if failed:
        cols.append('message')
    out = ['| ' + ' | '.join(cols) + ' |', '|' + '---|' * len(cols)]
    for r in rows:
        cells = [r['case'] + ('*' if r['reference'] == '1' else '')]
        if named:
            cells.append(r['name'])
        cells += [r[p] for p in params]
        cells += [r['status'], r['steps'], r['iterations'], fmt(r['wall_time'], 3),
                  fmt(r['max_rel_balance'], 2)]
        for m in metrics:
            cells += [fmt(r[m], 6), fmt(r['err_' + m], 2)]
        if failed:
            cells.append(r['message'].replace('|', '\\|'))
        out.append('| ' + ' | '.join(cells) + ' |')
    ref = [r['case'] for r in rows if r['reference'] == '1']
    out.append('')
    out.append('* reference case (errors are relative to it)' if ref else
               'Errors are relative to the REFERENCE VALUE of the sweep file.')
    return '\n'.join(out) + '\n'


def variant_of(r, params, named):
    if named:
        return r['name']
    others = [p for p in params if p.upper() != 'TIME.STEP']
    return ', '.join('%s=%s' % (p, r[p]) for p in others) or 'all cases'


def pareto(header, rows, png, metric=None):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    params, metrics, errs = split_columns(header)
    if metric is None:
        for e in errs:
            if any(num(r[e]) > 0 for r in rows):
                metric = e
                break
        if metric is None:
            metric = 'max_rel_balance'
    elif not metric.startswith('err_') and 'err_' + metric in header:
        metric = 'err_' + metric
    if metric not in header:
        raise SystemExit('sweep_table.py: no column %s (columns: %s)' % (metric, ', '.join(header)))
    named = any(r['name'] for r in rows)
    curves = {}
    for r in rows:
        curves.setdefault(variant_of(r, params, named), []).append(r)
    fig, ax = plt.subplots(figsize=(7, 5))
    for label, rs in curves.items():
        pts = sorted((num(r['wall_time']), num(r[metric]), r.get('TIME.STEP', r['time_step'])) for r in rs
                     if r['status'] == 'ok')
        good = [(x, y, h) for x, y, h in pts if x > 0 and y > 0 and not math.isnan(y)]
        skipped = len(rs) - len(good)
        if not good:
            continue
        ax.loglog([p[0] for p in good], [p[1] for p in good], 'o-',
                  label=label + (' (%d not drawn)' % skipped if skipped else ''))
        for x, y, h in good:
            ax.annotate('h=%s' % h, (x, y), textcoords='offset points', xytext=(4, 4), fontsize=7)
    ax.set_xlabel('wall time per run (s)')
    ax.set_ylabel(metric.replace('err_', 'error of ') if metric.startswith('err_') else metric)
    ax.set_title('Pareto: accuracy vs cost')
    ax.grid(True, which='both', alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    plt.close(fig)
    return metric


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('csv')
    ap.add_argument('--png', help='write the Pareto plot (error vs wall time) here')
    ap.add_argument('--metric', help='error column of the Pareto plot (err_* or a metric name)')
    ap.add_argument('-o', '--output', help='write the Markdown table here (default: stdout)')
    a = ap.parse_args(argv)
    header, rows = read(a.csv)
    text = markdown(header, rows)
    if a.output:
        with open(a.output, 'w') as f:
            f.write(text)
    else:
        sys.stdout.write(text)
    if a.png:
        pareto(header, rows, a.png, a.metric)


if __name__ == '__main__':
    main()
