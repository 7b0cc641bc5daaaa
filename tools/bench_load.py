#!/usr/bin/python3
"""How long reading a scene takes as it grows (issue 37, item 10): CPU seconds of `rebond SCENE`
stopped after one step, for a FUNCTION of N points and for a scene of N statements (N/2 NODE,
N/2 - 1 ELEMENT BAR2 between them, one MODEL, every node in a named group of its own). Loading
must be linear: targets 200 000 points <= 1 s, 100 000 statements <= 5 s CPU. Writes the table
to docs/performance.md between the markers load:begin and load:end (with --write).

    tools/bench_load.py [--write]
"""
import os
import resource
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REBOND = os.path.join(ROOT, 'bin', 'rebond')
sys.dont_write_bytecode = True
sys.path.insert(0, os.path.join(ROOT, 'tools'))
from docblock import replace_block  # noqa: E402


def cpu_of(path, tmp):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run([REBOND, path, '-o', os.path.join(tmp, 'out'), '--quiet'], capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        raise RuntimeError(p.stderr)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def function_scene(n):
    pts = ' '.join('%d %.6g' % (i, (i % 7) * 0.1) for i in range(n))
    return ('NODE a AT 0 0\nNODE b AT 1 0\nELEMENT s TYPE SPRING NODES a b\nMATERIAL k ELASTIC YOUNG 8\n'
            'ELEMENT m TYPE MASS NODES b\nSECTION pm MASS 2\nMODEL s MATERIAL k\nMODEL m SECTION pm\nFIX a ALL\n'
            'FUNCTION f POINTS %s\nLOAD p NODES b FORCE 1 0 FUNCTION f\nTIME STEP 0.01 END 0.01\n'
            'OUTPUT HISTORY EVERY 1 FIELDS EVERY 0\n' % pts)


def statements_scene(n):
    k = n // 2
    lines = ['NODE n%d AT %d 0' % (i, i) for i in range(k)]
    lines += ['ELEMENT e%d TYPE BAR2 NODES n%d n%d' % (i, i, i + 1) for i in range(k - 1)]
    lines += ['GROUP bars ELEMENTS ' + ' '.join('e%d' % i for i in range(k - 1)),
              'MATERIAL st ELASTIC YOUNG 2e11 DENSITY 7800', 'SECTION a AREA 1e-4', 'MODEL bars MATERIAL st SECTION a',
              'FIX n0 ALL', 'TIME STEP 1e-6 END 1e-6', 'OUTPUT HISTORY EVERY 1 FIELDS EVERY 0']
    return '\n'.join(lines) + '\n'


def main():
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for kind, make, sizes, target in (('FUNCTION points', function_scene, (25000, 50000, 100000, 200000), 1.0),
                                          ('statements', statements_scene, (12500, 25000, 50000, 100000), 5.0)):
            for n in sizes:
                path = os.path.join(tmp, 'scene.dat')
                with open(path, 'w') as f:
                    f.write(make(n))
                t = cpu_of(path, tmp)
                rows.append((kind, n, t, target if n == sizes[-1] else None))
                print('%-16s %7d  %.3f s CPU' % (kind, n, t), flush=True)
    table = ['', '| scene | size | CPU (s) | target |', '|---|---|---|---|']
    for kind, n, t, target in rows:
        table.append('| %s | %d | %.3f | %s |' % (kind, n, t, '≤ %g s' % target if target else ''))
    block = '\n'.join(table) + '\n\n'
    ok = all(t <= target for _, _, t, target in rows if target)
    print('targets met' if ok else 'TARGET MISSED')
    if '--write' in sys.argv:
        replace_block(os.path.join(ROOT, 'docs', 'performance.md'), '<!-- load:begin -->', '<!-- load:end -->', block)
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main())
