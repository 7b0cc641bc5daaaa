"""KINEMATICS LARGE on 3D solids (issue 32, item 4; src/assembly/large_solid.f90): total Lagrangian,
St Venant-Kirchhoff (ELASTIC) and J2 on (E, S) (VON_MISES), eq (9)'s discrete gradient on the
Green-Lagrange strain.

- A free elastic block tumbling about a skew axis (INITIAL VELOCITY + ANGULAR_VELOCITY wx wy wz ABOUT
  its centre), HEX8 and TET10, at h = T/10, T/100 and T/1000 of its lowest elastic period T (MODES):
  at the defaults, kinetic + internal constant and the balance <= 1e-10 of E, the three momenta to
  1e-12 of |p|, the three angular momenta (about the origin, in the current configuration) to 1e-10
  of |L| (the iteration's TOLERANCE bounds them); with SCHEME TOLERANCE 1e-12, E, p and L to 1e-12.
  Over 2 rad LARGE keeps the block's diagonal (within its centrifugal stretch) where KINEMATICS SMALL,
  not frame-indifferent, stretches it by more than 50 % (the test can fail).
- The 3D kernel against the 2D one: a QUAD4 plane-strain cantilever whipped to a tip deflection of
  60 % of its length (KINEMATICS LARGE, ELASTIC, HYPERELASTIC and VON_MISES) and its HEX8 extrusion, one element
  through z with UZ held, give the same energies and tip motion at every step (1e-10).
- A neo-Hookean cube crushed to half its height against a wall rebounds, balance <= 1e-10 E.
- A VON_MISES block thrown obliquely at a frictionless wall fast enough to flatten its corner
  (KINEMATICS LARGE, the defaults): the balance <= 1e-10 of E, the momentum along both tangents of
  the wall kept to 1e-12 of |p0|, plastic work > 0.
- Input errors: STRAIN_MEASURE LOG and FORMULATION BBAR with KINEMATICS LARGE on HEX8, and a
  PRESSURE that would follow the faces of a 3D LARGE model (say DEAD).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402
import contactcheck as cc  # noqa: E402

BLOCK = ('DIMENSION 3\nBOX b ORIGIN 0 0 0 SIZE 0.4 0.2 0.1 ELEMENTS 4 2 1 TYPE {etype}\n'
         'MATERIAL st ELASTIC YOUNG 2e7 POISSON 0.3 DENSITY 1000\n')


def lowest_period(etype):
    out = sc.run_ok(sc.write_scene('modes_%s.dat' % etype, BLOCK.format(etype=etype) +
                                   'MODEL b MATERIAL st\nMODES 8\nTIME STEP 1e-4 END 0\n'))
    f = sc.read_csv(os.path.join(out, 'modes.csv'))['frequency']
    return 1.0 / f[6]                                   # (the six rigid modes first)


def drifts(out):
    h = sc.history(out)
    e = h['kinetic'] + h['internal']
    p = [h['momentum_' + d] for d in 'xyz']
    ang = [h['angular_momentum_x'], h['angular_momentum_y'], h['angular_momentum']]
    pn = np.sqrt(sum(x[0] ** 2 for x in p))
    ln = np.sqrt(sum(x[0] ** 2 for x in ang))
    return (np.abs(e - e[0]).max() / e[0], max(np.abs(x - x[0]).max() for x in p) / pn,
            max(np.abs(x - x[0]).max() for x in ang) / ln, sc.relative_balance(out)[0], h)


def tumbling():
    for etype in ('HEX8', 'TET10'):
        period = lowest_period(etype)
        for div in (10, 100, 1000):
            h = period / div
            text = (BLOCK.format(etype=etype) + 'MODEL b MATERIAL st KINEMATICS LARGE\nINITIAL b VELOCITY 1 -2 0.5\n'
                    'INITIAL b ANGULAR_VELOCITY 30 -50 80 ABOUT 0.2 0.1 0.05\n'
                    'TIME STEP %r END %r\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 0\n' % (h, period * (2 if etype == 'HEX8'
                                                                                            else 1)))
            scene = sc.write_scene('tumble_%s_%d.dat' % (etype, div), text)
            de, dp, dl, bal, hist = drifts(sc.run_ok(scene))
            tag = '%s tumbling, h = T/%d' % (etype, div)
            sc.report_measured(tag + ', defaults: E and balance <= 1e-10 E, momenta 1e-12, angular momenta 1e-10',
                               de <= 1e-10 and bal <= 1e-10 and dp <= 1e-12 and dl <= 1e-10 and
                               hist['internal'].max() > 1e-3 * hist['kinetic'][0],
                               'E %.1e, balance %.1e, p %.1e, L %.1e (internal up to %.2g of E)'
                               % (de, bal, dp, dl, hist['internal'].max() / hist['kinetic'][0]))
            de, dp, dl, bal, _ = drifts(sc.run_ok(scene, ['SCHEME.TOLERANCE=1e-12']))
            sc.report_measured(tag + ', TOLERANCE 1e-12: E, p and L to 1e-12',
                               max(de, bal, dp, dl) <= 1e-12, 'E %.1e, balance %.1e, p %.1e, L %.1e' % (de, bal, dp, dl))
    corners = ('GROUP c0 NODES BOX -1e-6 -1e-6 -1e-6 1e-6 1e-6 1e-6 OF b\n'
               'GROUP c1 NODES BOX 0.399999 0.199999 0.099999 0.400001 0.200001 0.100001 OF b\n'
               'OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 ' + ' '.join('PROBE c%d U%s' % (k, d) for k in (0, 1) for d in 'XYZ')
               + '\n')
    text = (BLOCK.format(etype='HEX8').replace('ELASTIC', 'HYPERELASTIC') + 'MODEL b MATERIAL st KINEMATICS LARGE\n'
            'INITIAL b VELOCITY 1 -2 0.5\nINITIAL b ANGULAR_VELOCITY 30 -50 80 ABOUT 0.2 0.1 0.05\n'
            'TIME STEP 1e-4 END 2e-2\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 0\n')
    de, dp, dl, bal, _ = drifts(sc.run_ok(sc.write_scene('tumble_hyper.dat', text)))
    sc.report_measured('HYPERELASTIC HEX8 tumbling, defaults: E and balance <= 1e-10 E, momenta 1e-12, angular '
                       'momenta 1e-10', max(de, bal, dl) <= 1e-10 and dp <= 1e-12,
                       'E %.1e, balance %.1e, p %.1e, L %.1e' % (de, bal, dp, dl))
    diag = {}
    for kin in ('SMALL', 'LARGE'):
        text = (BLOCK.format(etype='HEX8') + 'MODEL b MATERIAL st KINEMATICS %s\nINITIAL b VELOCITY 1 -2 0.5\n'
                'INITIAL b ANGULAR_VELOCITY 30 -50 80 ABOUT 0.2 0.1 0.05\nTIME STEP 1e-4 END 2e-2\n' % kin + corners)
        p = sc.probes(sc.run_ok(sc.write_scene('tumble_%s.dat' % kin, text)))
        d = np.array([0.4, 0.2, 0.1]) + np.array([p['c1.U' + a][-1] - p['c0.U' + a][-1] for a in 'XYZ'])
        diag[kin] = np.linalg.norm(d) / np.linalg.norm([0.4, 0.2, 0.1]) - 1
    sc.report_measured('tumbling 2 rad: LARGE keeps the block\'s diagonal (2 %), SMALL (not frame-indifferent) '
                       'stretches it by more than 50 %', abs(diag['LARGE']) <= 0.02 and diag['SMALL'] > 0.5,
                       'LARGE %+.2f %%, SMALL %+.0f %%' % (100 * diag['LARGE'], 100 * diag['SMALL']))


def twins():
    for law, mat in (('ELASTIC', 'rub ELASTIC YOUNG 1e7 POISSON 0.3 DENSITY 1000'),
                     ('HYPERELASTIC', 'rub HYPERELASTIC YOUNG 1e7 POISSON 0.3 DENSITY 1000'),
                     ('VON_MISES', 'rub VON_MISES YOUNG 1e7 POISSON 0.3 DENSITY 1000 YIELD 4e4 H_ISO 1e5 H_KIN 0')):
        common = ('MATERIAL %s\nFUNCTION prof POINTS 0 0 1 1\nTIME STEP 1e-3 END 0.4\n'
                  'OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE tip UX PROBE tip UY\n' % mat)
        two = ('RECTANGLE c ORIGIN 0 0 SIZE 1 0.1 ELEMENTS 10 2 TYPE QUAD4\nSECTION s THICKNESS 0.1\n'
               'MODEL c MATERIAL rub SECTION s KINEMATICS LARGE FORMULATION STANDARD SUBSTEPS 4\nFIX c.left UX UY\n'
               'INITIAL c VELOCITY 0 8 FUNCTION prof ALONG X\nGROUP tip NODES BOX 0.99 0 1.01 0 OF c\n' + common)
        three = ('DIMENSION 3\nBOX c ORIGIN 0 0 0 SIZE 1 0.1 0.1 ELEMENTS 10 2 1 TYPE HEX8\n'
                 'MODEL c MATERIAL rub KINEMATICS LARGE FORMULATION STANDARD SUBSTEPS 4\nFIX c.xmin UX UY UZ\n'
                 'FIX c UZ\nINITIAL c VELOCITY 0 8 0 FUNCTION prof ALONG X\nGROUP tip NODES BOX 0.99 0 0 1.01 0 0 OF c\n'
                 + common)
        a = sc.run_ok(sc.write_scene('twin2d_%s.dat' % law, two))
        b = sc.run_ok(sc.write_scene('twin3d_%s.dat' % law, three))
        ha, hb = sc.history(a), sc.history(b)
        pa, pb = sc.probes(a), sc.probes(b)
        scale = (ha['kinetic'] + ha['internal']).max()
        err = max(np.abs(ha[k] - hb[k]).max() for k in ('kinetic', 'internal', 'dissipated')) / scale
        tip = max(np.abs(pa['tip.' + d] - pb['tip.' + d]).max() for d in ('UX', 'UY'))
        sc.report_measured('LARGE %s: HEX8 extrusion = QUAD4 plane strain (energies and tip, 1e-10)' % law,
                           err <= 1e-10 and tip <= 1e-10 and abs(pa['tip.UY']).max() > 0.3,
                           'energies %.1e of E, tip %.1e m; tip deflection up to %.2f m, plastic work %.3g of %.3g J'
                           % (err, tip, abs(pa['tip.UY']).max(), ha['dissipated'][-1], scale))
        cc.check_balance('LARGE %s HEX8 cantilever' % law, b)


def crushed():
    """HYPERELASTIC (neo-Hookean) and ELASTIC (St Venant-Kirchhoff) cubes thrown at a wall fast enough
    to halve their height: the balance <= 1e-10 of E at the defaults; the neo-Hookean cube rebounds
    with its energy, where St Venant-Kirchhoff, which softens in compression, collapses (an element
    turned inside out stops the run or leaves it crushed)."""
    rebound = {}
    for law in ('HYPERELASTIC', 'ELASTIC'):
        text = ('DIMENSION 3\nBOX b ORIGIN 0 0 0.001 SIZE 0.1 0.1 0.1 ELEMENTS 2 2 2 TYPE HEX8\n'
                'MATERIAL rub %s YOUNG 1e6 POISSON 0.3 DENSITY 1000\nMODEL b MATERIAL rub KINEMATICS LARGE\n'
                'INITIAL b VELOCITY 0 0 -30\nOBSTACLE wall NODES b.zmin POINT 0 0 0 NORMAL 0 0 1\n'
                'GROUP top NODES BOX 0.049 0.049 0.1009 0.051 0.051 0.1011 OF b\n'
                'TIME STEP 2e-5 END 1e-2\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE top UZ\n' % law)
        path = sc.write_scene('crushed_%s.dat' % law, text)
        rc, err, out = sc.run(path)
        if law == 'HYPERELASTIC':
            h = sc.history(out)
            squeeze = 1 + sc.probes(out)['top.UZ'].min() / 0.1
            rebound[law] = h['momentum_z'][-1] / (1000 * 0.001 * 30)
            sc.report_measured('HYPERELASTIC HEX8 cube at 30 m/s: crushed to half its height, rebounds, balance <= 1e-10 '
                               'E at the defaults', rc == 0 and squeeze < 0.6 and rebound[law] > 0.5 and
                               sc.relative_balance(out)[0] <= 1e-10, 'height down to %.2f, rebound %.3f of v0, '
                               'balance %.1e' % (squeeze, rebound[law], sc.relative_balance(out)[0]))
        else:
            print('# ELASTIC (St Venant-Kirchhoff) cube at 30 m/s: exit %d %s' % (rc, err.strip()[:160]))


def plastic_wall():
    n = np.array([0.36, 0.48, 0.8])
    t1 = np.array([0.8, 0.0, -0.36])
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(n, t1)
    v0 = -60 * n + 25 * t1 - 10 * t2
    text = ('DIMENSION 3\nBOX b ORIGIN 0 0 0 SIZE 0.02 0.02 0.02 ELEMENTS 3 3 3 TYPE HEX8\n'
            'MATERIAL st VON_MISES YOUNG 2e11 POISSON 0.3 DENSITY 7800 YIELD 2.5e8 H_ISO 1e9 H_KIN 0\n'
            'MODEL b MATERIAL st KINEMATICS LARGE\nINITIAL b VELOCITY %r %r %r\n'
            'OBSTACLE wall NODES b POINT -1e-5 -1e-5 -1e-5 NORMAL 0.36 0.48 0.8\n'
            'TIME STEP 2e-7 END 2e-5\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 0\n' % tuple(v0))
    out = sc.run_ok(sc.write_scene('plastic_wall.dat', text))
    h = sc.history(out)
    p = np.array([h['momentum_' + d] for d in 'xyz'])
    m = 7800 * 0.02 ** 3
    tang = max(np.abs(t @ p - m * (t @ v0)).max() for t in (t1, t2)) / (m * np.linalg.norm(v0))
    sc.report_measured('LARGE VON_MISES oblique wall impact, defaults: tangential momenta kept (1e-12 of |p0|), '
                       'plastic work > 0', tang <= 1e-12 and h['dissipated'][-1] > 0 and (n @ p)[-1] > (n @ p)[0],
                       'tangential %.1e; plastic work %.3g J of %.3g J; normal momentum %.3g -> %.3g'
                       % (tang, h['dissipated'][-1], h['kinetic'][0], (n @ p)[0], (n @ p)[-1]))
    cc.check_balance('LARGE VON_MISES oblique wall impact', out)


def bad_input():
    base = (BLOCK.format(etype='HEX8') + '{model}\nTIME STEP 1e-4 END 1e-3\n')
    cases = [('STRAIN_MEASURE LOG on HEX8', 'MODEL b MATERIAL st KINEMATICS LARGE STRAIN_MEASURE LOG', 4, 'LOG'),
             ('FORMULATION BBAR with KINEMATICS LARGE on HEX8', 'MODEL b MATERIAL st KINEMATICS LARGE FORMULATION BBAR',
              4, 'BBAR'),
             ('a following PRESSURE on a 3D LARGE model', 'MODEL b MATERIAL st KINEMATICS LARGE\n'
              'PRESSURE b.zmax VALUE 1e5', 5, 'b.zmax')]
    for k, (tag, model, line, word) in enumerate(cases):
        path = sc.write_scene('bad_%d.dat' % k, base.format(model=model))
        out = sc.new_dir('bad')
        rc, err, _ = sc.run(path, outdir=out)
        ok = rc == 2 and ('%s:%d:' % (os.path.basename(path), line)) in err and "'%s'" % word in err and \
            not (os.path.isdir(out) and os.listdir(out))
        sc.report('input error: %s (exit 2, file:line, the word, nothing written)' % tag, ok, err.strip()[:200])
    path = sc.write_scene('dead.dat', base.format(model='MODEL b MATERIAL st KINEMATICS LARGE\n'
                                                  'PRESSURE b.zmax VALUE 1e5 DEAD'))
    sc.run_ok(path)
    sc.report('a DEAD PRESSURE on a 3D LARGE model runs', True)


tumbling()
twins()
crushed()
plastic_wall()
bad_input()

