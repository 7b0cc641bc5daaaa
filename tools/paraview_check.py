#!/usr/bin/python3
"""fields.xmf in ParaView's two XDMF readers (issue 37, item 6): runs four scenes (a BEAM2
cantilever, the J2 block of QUAD8, a TRI6 mesh from Gmsh, a contact scene), opens each output's
fields.xmf with Xdmf3ReaderS (ParaView's default) and with the legacy XDMF Reader under pvpython
(xvfb-run), asserts that every array of fields.h5's step groups is present in both with its cells
and nodes, and saves a picture of each to docs/figures/paraview_<case>.png. Prints
"N passed, M failed"; exit 1 on a failure. Installs Debian's paraview when pvpython is missing
(make paraview-check, as root).
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

import h5py

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REBOND = os.path.join(ROOT, 'bin', 'rebond')
CASES = [
    ('beam', 'inputs/cantilever_release.dat', ['TIME.END=5e-3', 'OUTPUT.FIELDS=EVERY 10'], 'displacement'),
    ('quad8_j2', 'inputs/block_j2.dat', ['RECTANGLE.TYPE=QUAD8', 'OUTPUT.FIELDS=EVERY 20'], 'von_mises'),
    ('tri6_gmsh', 'tests/data/tri_msh22.msh', None, 'sigma_xx'),
    ('contact', 'inputs/ring_impact.dat', ['TIME.END=0.01', 'OUTPUT.FIELDS=EVERY 10'], 'reaction'),
]
TRI6_SCENE = '''GMSH m FILE {mesh}
MATERIAL st ELASTIC YOUNG 2e11 POISSON 0.3 DENSITY 7800
SECTION s THICKNESS 0.01
MODEL m.plate MATERIAL st SECTION s
FIX m.{fixed} ALL
INITIAL m VELOCITY 0 -1
TIME STEP 1e-6 END 2e-5
OUTPUT HISTORY EVERY 1 FIELDS EVERY 5
'''

PV_SCRIPT = r'''
import json, sys
from paraview.simple import *
path, png, color = sys.argv[1], sys.argv[2], sys.argv[3]
out = {}
for reader in ('Xdmf3ReaderS', 'XDMFReader'):
    r = Xdmf3ReaderS(FileName=[path]) if reader == 'Xdmf3ReaderS' else XDMFReader(FileNames=[path])
    ts = list(r.TimestepValues) if r.TimestepValues else [0.0]
    r.UpdatePipeline(ts[-1])
    d = servermanager.Fetch(r)
    pd, cd = d.GetPointData(), d.GetCellData()
    out[reader] = {'cells': d.GetNumberOfCells(), 'points': d.GetNumberOfPoints(), 'times': len(ts),
                   'point': [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())],
                   'cell': [cd.GetArrayName(i) for i in range(cd.GetNumberOfArrays())]}
    if reader == 'Xdmf3ReaderS':
        scene = GetAnimationScene()
        scene.UpdateAnimationUsingDataTimeSteps()
        scene.AnimationTime = ts[-1]
        view = GetActiveViewOrCreate('RenderView')
        view.ViewSize = [900, 500]
        disp = Show(r, view)
        assoc = 'CELLS' if color in out[reader]['cell'] else 'POINTS'
        ColorBy(disp, (assoc, color))
        disp.RescaleTransferFunctionToDataRange(True, False)
        disp.SetScalarBarVisibility(view, True)
        view.ViewTime = ts[-1]
        ResetCamera(view)
        SaveScreenshot(png, view, ImageResolution=[900, 500])
        Hide(r, view)
    Delete(r)
print('JSON' + json.dumps(out))
'''


def ensure_paraview():
    if shutil.which('pvpython') and shutil.which('xvfb-run'):
        return True
    print('installing Debian\'s paraview and xvfb (apt-get)...', flush=True)
    env = dict(os.environ, DEBIAN_FRONTEND='noninteractive')
    subprocess.run(['apt-get', 'update'], env=env, capture_output=True)
    p = subprocess.run(['apt-get', 'install', '-y', '--no-install-recommends', 'paraview', 'python3-paraview', 'xvfb',
                        'xauth'], env=env, capture_output=True, text=True)
    return p.returncode == 0 and shutil.which('pvpython') is not None


def h5_arrays(path):
    """The names of the arrays of fields.h5's last step group."""
    with h5py.File(path, 'r') as f:
        steps = sorted(k for k in f.keys() if k.startswith('step_'))
        return sorted(f[steps[-1]].keys()), f['mesh/coordinates'].shape[0]


def main():
    if not ensure_paraview():
        print('0 passed, 1 failed')
        print('paraview could not be installed', file=sys.stderr)
        return 1
    passed = failed = 0

    def report(name, ok, detail=''):
        nonlocal passed, failed
        print(('PASS ' if ok else 'FAIL ') + name + ('' if ok else ': ' + detail), flush=True)
        passed += bool(ok)
        failed += not ok
        return ok

    with tempfile.TemporaryDirectory() as tmp:
        script = os.path.join(tmp, 'pv.py')
        with open(script, 'w') as f:
            f.write(PV_SCRIPT)
        for name, scene, sets, color in CASES:
            if name == 'tri6_gmsh':
                path = os.path.join(tmp, 'tri6.dat')
                with open(path, 'w') as f:
                    f.write(TRI6_SCENE.format(mesh=os.path.join(ROOT, scene), fixed='bottom'))
                scene, sets = path, []
            out = os.path.join(tmp, name)
            cmd = [REBOND, scene, '-o', out, '--quiet'] + sum((['--set', s] for s in sets), [])
            p = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
            if not report('%s: rebond runs' % name, p.returncode == 0, p.stderr.strip()[-300:]):
                continue
            arrays, nnode = h5_arrays(os.path.join(out, 'fields.h5'))
            png = os.path.join(ROOT, 'docs', 'figures', 'paraview_%s.png' % name)
            q = subprocess.run(['xvfb-run', '-a', 'pvpython', script, os.path.join(out, 'fields.xmf'), png, color],
                               capture_output=True, text=True)
            line = [ln for ln in q.stdout.splitlines() if ln.startswith('JSON')]
            if not report('%s: pvpython reads fields.xmf' % name, q.returncode == 0 and line, (q.stderr or q.stdout)[-400:]):
                continue
            got = json.loads(line[0][4:])
            skipped = (q.stdout + q.stderr).count('Skipping unrecognized array type')
            for reader in ('Xdmf3ReaderS', 'XDMFReader'):
                names = set(got[reader]['point']) | set(got[reader]['cell'])
                missing = [a for a in arrays if a not in names]
                report('%s: %s shows every array of fields.h5 (%d)' % (name, reader, len(arrays)), not missing,
                       'missing %s' % ', '.join(missing))
                report('%s: %s reads the %d nodes' % (name, reader, nnode), got[reader]['points'] == nnode,
                       '%d points' % got[reader]['points'])
            report('%s: no array skipped ("unrecognized array type")' % name, skipped == 0, '%d skipped' % skipped)
            report('%s: picture saved (%s)' % (name, os.path.relpath(png, ROOT)), os.path.exists(png))
    print('%d passed, %d failed' % (passed, failed))
    return 0 if failed == 0 else 1


if __name__ == '__main__':
    sys.exit(main())
