"""Node-to-face contact in 3D (issue 33): GAP … NODES ga FACES gf, each node of ga paired at t = 0
with the foot of its normal on a free face of gf (src/input/scene_gap_faces.f90,
src/mesh/face_projection.f90; docs/input.md "GAP … FACES in detail").

- a steel cube (2 × 2 × 2 HEX8) thrown at a free slab (3 × 3 × 1 HEX8: the meshes do not match),
  resting on it at t = 0, in every impact mode but MASSLESS, with FRICTION 0.2 and without: the six
  momenta (linear and angular) of the free pair kept to 1e-12, |balance| <= 1e-10 of E, no gap
  below -1e-12 m, the floor's tangential impulse inside the circle μ × the normal one;
- the same from a 1 mm gap, frictionless: the six momenta kept (with friction the tangential force
  at the node and its reaction at the foot are the gap apart: small-displacement kinematics, the
  angular momenta about x and y then change by that moment, measured and printed);
- quadratic faces (HEX20 and TET10 slabs) and cubes of every type: the six momenta kept;
- a point mass hitting a free block between its nodes: the three linear momenta kept, the impulse
  inside the cone;
- matching meshes: GAP … FACES gives GAP … WITH's history (1e-10): a node on a face's corner has
  the weights (1, 0, 0, 0);
- two passes (cube on slab and slab on cube, for two deformable faces): non-matching, the six
  momenta kept; matching, the momentum transferred is one pass's (1e-12) and the history the same;
- the augmented sparse system (MULTIPLIERS AUGMENTED: the cone's fixed point, the Schur Newton where
  a contact would slip against its force) gives the Schur block's answer (1e-12), PAPER and from a gap;
- a restart mid-impact continues bit for bit;
- bad input: FACES in 2D, with WITH, PAIRING STEP, a LARGE model without PAIRING START, no node
  facing a face, a node inside the face it faces.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

HERE = 'tests/scenes/contact_faces/'
MOMENTA = ['momentum_x', 'momentum_y', 'momentum_z', 'angular_momentum_x', 'angular_momentum_y', 'angular_momentum']


def drifts(hist, keys):
    """Largest change of each quantity over the run, relative to the largest initial momentum."""
    scale = max(abs(hist[k][0]) for k in keys)
    return max(np.abs(hist[k] - hist[k][0]).max() for k in keys) / scale


def balance(tag, out, mu):
    hist = sc.history(out)
    bal = np.abs(hist['balance']).max() / np.abs(hist['kinetic'] + hist['internal']).max()
    sc.report_measured(tag + ': |balance| <= 1e-10 of E', bal <= 1e-10, '%.2e' % bal)
    dfr = np.diff(hist['friction_dissipated'])
    sc.report(tag + ': friction_dissipated never falls', dfr.min() >= -1e-14, '%.2e' % dfr.min())
    ct = sc.contacts(out)
    sc.report_measured(tag + ': no gap below -1e-12 m', ct['min_gap'].min() >= -1e-12, '%.2e m' % ct['min_gap'].min())
    if mu > 0.0:
        over = (np.hypot(ct['impulse_x'], ct['impulse_y']) - mu * ct['impulse_z']).max()
        sc.report(tag + ': tangential impulse inside the circle every step', over <= 1e-15, 'excess %.2e' % over)
        sc.report(tag + ': the contact was made and slipped', ct['active'].max() > 0 and
                  hist['friction_dissipated'][-1] > 0.0, 'dissipated %.3e J' % hist['friction_dissipated'][-1])
    return hist


def cube_slab():
    for mode in ['AUTO', 'PAPER', 'PERSIST', 'SYMMETRIC']:
        for mu in [0.2, 0.0]:
            tag = 'cube on slab %s, mu %g' % (mode, mu)
            out = sc.run_ok(HERE + 'cube_slab.dat', ['SCHEME.IMPACT=' + mode, 'GAP.FRICTION=%r' % mu])
            hist = balance(tag, out, mu)
            d = drifts(hist, MOMENTA)
            sc.report_measured(tag + ': the six momenta kept (1e-12)', d <= 1e-12, '%.2e' % d)
    out = sc.run_ok(HERE + 'cube_slab.dat', ['BOX.cube.ORIGIN=0.08 0.11 0.051', 'GAP.FRICTION=0', 'TIME.END=1.2e-3'])
    hist = balance('cube from a 1 mm gap, frictionless', out, 0.0)
    d = drifts(hist, MOMENTA)
    sc.report_measured('cube from a 1 mm gap, frictionless: the six momenta kept (1e-12)', d <= 1e-12, '%.2e' % d)
    out = sc.run_ok(HERE + 'cube_slab.dat', ['BOX.cube.ORIGIN=0.08 0.11 0.051', 'TIME.END=1.2e-3'])
    hist = balance('cube from a 1 mm gap, mu 0.2', out, 0.2)
    d = drifts(hist, MOMENTA[:3] + MOMENTA[5:])
    sc.report_measured('cube from a 1 mm gap, mu 0.2: linear momenta and the one about z kept (1e-12)', d <= 1e-12,
                       '%.2e (about x and y, the friction at the gap\'s lever: %.2e)' % (d, drifts(hist, MOMENTA[3:5])))


def quadratic():
    for slab, cube in [('HEX20', 'HEX20'), ('TET10', 'HEX8'), ('HEX20', 'TET10'), ('HEX8', 'TET4'), ('WEDGE6', 'HEX8')]:
        tag = '%s cube on a %s slab' % (cube, slab)
        out = sc.run_ok(HERE + 'cube_slab.dat', ['BOX.slab.TYPE=' + slab, 'BOX.cube.TYPE=' + cube, 'GAP.FRICTION=0',
                                                 'SCHEME.IMPACT=PERSIST'])
        hist = balance(tag, out, 0.0)
        d = drifts(hist, MOMENTA)
        sc.report_measured(tag + ': the six momenta kept (1e-12)', d <= 1e-12, '%.2e' % d)


def ball():
    for mode in ['AUTO', 'PAPER', 'SYMMETRIC']:
        tag = 'point mass on a block %s' % mode
        out = sc.run_ok(HERE + 'ball_block.dat', ['SCHEME.IMPACT=' + mode])
        hist = balance(tag, out, 0.3)
        d = drifts(hist, MOMENTA[:3])
        sc.report_measured(tag + ': the three linear momenta kept (1e-12)', d <= 1e-12, '%.2e' % d)


def matching():
    sets = ['BOX.cube.SIZE=0.2 0.2 0.1', 'BOX.cube.ORIGIN=0 0.1 0.05', 'BOX.cube.ELEMENTS=2 2 1',
            'BOX.slab.ELEMENTS=3 3 1', 'GAP.FRICTION=0', 'SCHEME.IMPACT=PERSIST']
    faces = sc.run_ok(HERE + 'cube_slab.dat', sets)
    text = open(HERE + 'cube_slab.dat').read().replace('FACES slab.zmax FRICTION 0.2', 'WITH slab.zmax NORMAL 0 0 -1')
    with_ = sc.run_ok(sc.write_scene('cube_slab_with.dat', text), sets[:-2] + ['SCHEME.IMPACT=PERSIST'])
    a, b = sc.history(faces), sc.history(with_)
    err = max(np.abs(a[k] - b[k]).max() / max(np.abs(b[k]).max(), 1e-300)
              for k in ['kinetic', 'internal', 'momentum_z', 'angular_momentum_x'])
    sc.report_measured('matching meshes: GAP … FACES = GAP … WITH (1e-10)', err <= 1e-10, '%.2e' % err)


def two_passes():
    text = open(HERE + 'cube_slab.dat').read().replace(
        'GAP       hit NODES cube.zmin FACES slab.zmax FRICTION 0.2\n',
        'GAP       hit NODES cube.zmin FACES slab.zmax FRICTION 0.2\nGAP       hit2 NODES slab.zmax FACES cube.zmin FRICTION 0.2\n')
    two = sc.write_scene('cube_slab_two.dat', text)
    hist = balance('two passes', sc.run_ok(two), 0.0)
    d = drifts(hist, MOMENTA)
    sc.report_measured('two passes, non-matching: the six momenta kept (1e-12)', d <= 1e-12, '%.2e' % d)
    sets = ['BOX.cube.SIZE=0.2 0.2 0.1', 'BOX.cube.ORIGIN=0 0.1 0.05', 'BOX.cube.ELEMENTS=2 2 1', 'SCHEME.IMPACT=PERSIST']
    one = sc.run_ok(HERE + 'cube_slab.dat', sets + ['GAP.FRICTION=0'])
    both = sc.run_ok(two, sets + ['GAP.hit.FRICTION=0', 'GAP.hit2.FRICTION=0'])
    c1, c2 = sc.contacts(one), sc.contacts(both)
    p1 = c1['impulse_z'].sum()
    hit = np.array([c == 'hit' for c in c2['contact']])
    p2 = c2['impulse_z'][hit].sum() - c2['impulse_z'][~hit].sum()     # (hit2's impulses are on the slab)
    sc.report_measured('two passes, matching: the momentum transferred is one pass\'s (1e-12)',
                       abs(p2 - p1) <= 1e-12 * abs(p1), '%.17g vs %.17g N s' % (p2, p1))
    a, b = sc.history(one), sc.history(both)
    err = max(np.abs(a[k] - b[k]).max() / np.abs(a[k]).max() for k in ['kinetic', 'internal', 'momentum_z'])
    sc.report_measured('two passes, matching: the history of one pass (1e-10)', err <= 1e-10, '%.2e' % err)


def augmented():
    for sets in [['SCHEME.IMPACT=PAPER'], ['BOX.cube.ORIGIN=0.08 0.11 0.051', 'TIME.END=1.2e-3'], []]:
        a = sc.history(sc.run_ok(HERE + 'cube_slab.dat', sets + ['SCHEME.MULTIPLIERS=SCHUR']))
        b = sc.history(sc.run_ok(HERE + 'cube_slab.dat', sets + ['SCHEME.MULTIPLIERS=AUGMENTED']))
        err = max(np.abs(a[k] - b[k]).max() / np.abs(a[k]).max() for k in ['kinetic', 'internal', 'friction_dissipated',
                                                                              'momentum_z'])
        sc.report_measured('cube on slab %s: MULTIPLIERS AUGMENTED = SCHUR (1e-12)' % ' '.join(sets), err <= 1e-12,
                           '%.2e' % err)


def restart():
    same, detail = sc.restart_same(HERE + 'cube_slab.dat', ['OUTPUT.CHECKPOINT=50', 'TIME.END=4e-4'], '2e-4',
                                   files=('history.csv', 'contacts.csv'))
    sc.report('cube on slab: a restart mid-impact continues bit for bit', same, detail)


def bad_inputs():
    base = open(HERE + 'cube_slab.dat').read()
    gap = 'GAP       hit NODES cube.zmin FACES slab.zmax FRICTION 0.2\n'
    cases = [
        ('FACES in 2D', 'RECTANGLE a ORIGIN 0 0 SIZE 1 1 ELEMENTS 1 1 TYPE QUAD4\nRECTANGLE b ORIGIN 0 1 SIZE 1 1 '
         'ELEMENTS 1 1 TYPE QUAD4\nMATERIAL m ELASTIC YOUNG 1e9 DENSITY 1000\nMODEL a MATERIAL m\nMODEL b MATERIAL m\n'
         'GAP g NODES b.bottom FACES a.top\nTIME STEP 1e-5 END 1e-4\n', 6, 'FACES'),
        ('FACES with WITH', base.replace(gap, 'GAP hit NODES cube.zmin FACES slab.zmax WITH slab.zmax\n'), 8, 'FACES'),
        ('PAIRING STEP', base.replace(gap, 'GAP hit NODES cube.zmin FACES slab.zmax PAIRING STEP\n'), 8, 'STEP'),
        ('a LARGE model without PAIRING START',
         base.replace('MODEL     cube MATERIAL steel', 'MODEL     cube MATERIAL steel KINEMATICS LARGE'), 8, 'FACES'),
        ('no node facing a face', base.replace(gap, 'GAP hit NODES cube.zmax FACES slab.zmin\n'), 8, 'slab.zmin'),
        ('a node inside the face', base.replace('ORIGIN 0.08 0.11 0.05 ', 'ORIGIN 0.08 0.11 0.049 '), 8, 'hit'),
    ]
    for name, text, line, word in cases:
        path = sc.write_scene('faces_bad.dat', text)
        outdir = os.path.join(sc.new_dir('faces_bad'), 'never')
        rc, err, _ = sc.run(path, outdir=outdir)
        msg = ' '.join(sc.message_lines(err))
        ok = rc == 2 and ('faces_bad.dat:%d:' % line) in msg and ("'%s'" % word) in msg and not os.path.exists(outdir)
        sc.report('bad input, %s: exit 2, file:line, the word' % name, ok, 'exit %d: %s' % (rc, msg[-300:]))


if __name__ == '__main__':
    cube_slab()
    quadratic()
    ball()
    matching()
    two_passes()
    augmented()
    restart()
    bad_inputs()
