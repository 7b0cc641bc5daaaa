"""3D solids (issue 32, first part): DIMENSION 3, BOX, HEX8 and TET4, linear elastic, with the method's
exactness and every momentum the physics fixes, on the one code path of 2D.

- code_aster SDNV100A in 3D (inputs/sdnv100_3d.dat: HEX8 1 x 1 x 20, the bar of inputs/sdnv100.dat,
  nu = 0, h = dx/(2c), rebond's defaults): contact from 2e-5 s to 1e-4 s (2L/c) within a step, rebound
  within 0.5 % of 100 m/s, mean contact force within 2 % of rho c v0 A = 1.6e6 N, balance <= 1e-10 E,
  the momenta y, z and the angular momenta about x and z (the bar's axis through the origin sees
  none) at round-off; TET4 (the same block cut in six) likewise.
- Oblique impacts of a HEX8 and a TET4 block on a frictionless plane of normal (0.36, 0.48, 0.8),
  every IMPACT mode, and a VON_MISES block at 10 times the speed (it yields) at the defaults: the momentum along both tangents of the plane kept to 1e-12 of |p0|, the
  impulses along the normal, the normal momentum changed by them (1e-12), the balance <= 1e-10 E.
- A free elastic block with a sheared, spinning initial velocity (INITIAL … FUNCTION ALONG X): the
  three momenta and the three angular momenta (history.csv) constant to 1e-12, kinetic + internal
  constant to 1e-10 (linear: exact).
- INITIAL … ANGULAR_VELOCITY wx wy wz ABOUT x y z with a VELOCITY: kinetic energy, momentum and angular
  momentum equal to those of the box's exact inertia (1e-13), kept.
- PRESSURE and TRACTION on the free faces of a free block: its momentum grows by the total force exactly.
- VON_MISES on HEX8: the J2 block of inputs/block_j2.dat extruded through z equals its plane-strain twin.
- Volumetric locking of HEX8 at nu = 0.499, measured on a cantilever's first frequency, and B-bar.
- MODES in 3D: six rigid modes and a free bar's axial frequency.
- HEX20 and TET10: a cantilever's first bending frequencies against beam theory; their XDMF cells.
- WEDGE6: a free bar's rigid and axial modes, a cantilever converging, PRESSURE on its two kinds of
  faces, its XDMF cells in VTK's order; a Gmsh prism mesh runs as the BOX.
- STATIC and INITIAL … STATIC in 3D: a cantilever under gravity and a tip force against beam theory,
  a block resting on a plane, a block free to slide (input error).
- A moving plane (OBSTACLE … VELOCITY vx vy vz): Galilean invariance against the fixed plane, every
  IMPACT mode.
- GRAVITY GZ: a free block falls with momentum_z = -m g t (1e-12).
- Node-to-node GAP … WITH between two blocks in every IMPACT mode: the six momenta kept (1e-12).
- GMSH in DIMENSION 3: a Gmsh 4.1 volume mesh of the bar (HEX8 and TET4) runs byte for byte as the BOX;
  a volume mesh in a planar scene is an input error naming the file's line.
- A restart of the 3D SDNV100 in the middle of the impact: byte for byte.
- fields.h5 of a 3D run: z coordinates, Hexahedron and Tetrahedron cells, the displacement's z
  component, six stress columns sigma_xx … sigma_xz, and a uniaxial stress sigma_xx = E eps in a
  bar pulled at constant velocity.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402
import contactcheck as cc  # noqa: E402

SDNV = os.path.join(sc.ROOT, 'inputs', 'sdnv100_3d.dat')
MODES = ['AUTO', 'PAPER', 'PERSIST', 'MASSLESS', 'SYMMETRIC']


def sdnv(tag, sets, asserted=True):
    """asserted False: the figures are printed, the physics (momenta, balance) asserted."""
    out = sc.run_ok(SDNV, sets)
    report_measured = sc.report_measured if asserted else (lambda name, ok, detail: print('# %s: %s' % (name, detail)))
    h = sc.history(out)
    c = sc.contacts(out)
    m = 8000 * 0.2 * 0.02 * 0.02
    reb = h['momentum_x'][-1] / (m * 100) - 1
    report_measured(tag + ': rebound within 0.5 % of 100 m/s', abs(reb) <= 5e-3, '%.4f %%' % (100 * reb))
    f = c['force_x']
    on = np.nonzero(f > 0)[0]
    h_step = 1e-6
    t_on, t_off = c['time'][on[0]] - h_step, c['time'][on[-1]]
    report_measured(tag + ': contact from 2e-5 s to 1e-4 s (within a step)',
                       abs(t_on - 2e-5) <= 1.01 * h_step and abs(t_off - 1e-4) <= 1.01 * h_step,
                       'from %.4g s to %.4g s' % (t_on, t_off))
    fm = f[on].mean()
    inner = f[on[2:-2]]
    report_measured(tag + ': mean contact force within 2 % of rho c v0 A = 1.6e6 N', abs(fm / 1.6e6 - 1) <= 0.02,
                       'mean %.5g N, std/mean %.3f over the contact (%.3f without its first and last two steps)'
                       % (fm, f[on].std() / fm, inner.std() / inner.mean()))
    p0 = abs(h['momentum_x'][0])
    side = max(np.abs(h[k]).max() for k in ('momentum_y', 'momentum_z'))
    sc.report_measured(tag + ': momenta y, z stay 0 (1e-12 |p0|)', side <= 1e-12 * p0, '%.2e of |p0|' % (side / p0))
    # The bar's axis is y = z = 0.01: L = (x, 0.01, 0.01) x (p_x, 0, 0) = (0, 0.01 p_x, -0.01 p_x) while the
    # wall pushes through the axis (no tilt, no twist).
    ref = p0 * 0.01
    dl = max(np.abs(h['angular_momentum_x']).max(), np.abs(h['angular_momentum_y'] - 0.01 * h['momentum_x']).max(),
             np.abs(h['angular_momentum'] + 0.01 * h['momentum_x']).max())
    if asserted:                                 # (the TET4 cut is not symmetric about the axis)
        sc.report_measured(tag + ': angular momentum = the axis x the momentum (1e-12)', dl <= 1e-12 * ref,
                           '%.2e of |p0| x 0.01 m' % (dl / ref))
    cc.check_balance(tag, out)


def block(et, normal, v, nel=(3, 2, 2), material='ELASTIC YOUNG 7e10 POISSON 0.33 DENSITY 2700'):
    n = np.array(normal) / np.linalg.norm(normal)
    # The block's lowest corner along n starts 1 mm from the plane through the origin; its three faces
    # there are the contact nodes (MASSLESS: every element keeps a node with mass, and the massless ones
    # are held by the others: a massless surface around two collinear interior nodes would spin freely).
    corners = np.array([[i, j, k] for i in (0, 0.06) for j in (0, 0.04) for k in (0, 0.04)])
    origin = -corners[np.argmin(corners @ n)] + 0.001 * n
    gap_time = 0.001 / max(-(np.array(v) @ n), 1e-9)
    return ('DIMENSION 3\nBOX blk ORIGIN %.17g %.17g %.17g SIZE 0.06 0.04 0.04 ELEMENTS %d %d %d TYPE %s\n'
            'MATERIAL alu %s\nMODEL blk MATERIAL alu\n'
            'INITIAL blk VELOCITY %.17g %.17g %.17g\n'
            'GROUP low NODES blk.xmin blk.ymin blk.zmin\n'
            'OBSTACLE ground NODES low POINT 0 0 0 NORMAL %.17g %.17g %.17g\n'
            'TIME STEP 2e-6 END %.6g\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 0\n'
            % (tuple(origin) + tuple(nel) + (et, material) + tuple(v) + tuple(normal) + (gap_time + 1.5e-3,))), n


def oblique(et, mode, plastic=False):
    normal = (0.36, 0.48, 0.8)
    v = (3.0, -1.0, -2.0)
    if plastic:                                  # J2 aluminium at 10 times the speed: it yields
        text, n = block(et, normal, tuple(10 * x for x in v),
                        material='VON_MISES YOUNG 7e10 POISSON 0.33 DENSITY 2700 YIELD 5e7 H_ISO 5e8')
    else:
        text, n = block(et, normal, v)
    path = sc.write_scene('oblique_%s.dat' % et, text)
    rc, err, out = sc.run(path, ['SCHEME.IMPACT=' + mode])
    tag = 'oblique %s %s%s' % (et, mode, ' VON_MISES' if plastic else '')
    if et == 'TET4' and mode == 'MASSLESS' and rc == 2:
        # TET4 of a 3 x 2 x 2 block with their four nodes on the surface: nowhere to move their mass
        sc.report(tag + ': refused (an element without a node to take the mass)', 'MASSLESS' in err, err.strip()[-200:])
        return
    if not sc.report(tag + ': runs', rc == 0, 'exit %d: %s' % (rc, err.strip()[-300:])):
        return
    h = sc.history(out)
    c = sc.contacts(out)
    p = np.vstack([h['momentum_x'], h['momentum_y'], h['momentum_z']])
    p0 = np.linalg.norm(p[:, 0])
    t1 = np.cross(n, [1.0, 0.0, 0.0])
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(n, t1)
    drift = max(np.abs(t @ p - t @ p[:, 0]).max() for t in (t1, t2)) / p0
    sc.report_measured(tag + ': momentum along both tangents kept (1e-12)', drift <= 1e-12, '%.2e of |p0|' % drift)
    imp = np.vstack([c['impulse_x'], c['impulse_y'], c['impulse_z']])
    tang = max(np.abs(t @ imp).max() for t in (t1, t2))
    norm_total = np.abs(n @ imp).sum()
    sc.report_measured(tag + ': impulses along the normal', tang <= 1e-12 * norm_total,
                       'tangential %.2e, normal total %.3e' % (tang, norm_total))
    pn = n @ p
    dn = np.abs((pn - pn[0]) - np.cumsum(n @ imp)[:len(pn)]).max() / p0
    sc.report_measured(tag + ': the block hits, p.n changes by the normal impulses (1e-12)',
                       pn[-1] > pn[0] + 0.5 * abs(pn[0]) and dn <= 1e-12,
                       'p.n from %.4g to %.4g, off the impulses by %.2e of |p0|' % (pn[0], pn[-1], dn))
    cc.check_balance(tag, out)
    if plastic:
        sc.report_measured(tag + ': the block yields', h['dissipated'][-1] > 1e-3 * h['kinetic'][0],
                           'plastic work %.3g J of %.3g' % (h['dissipated'][-1], h['kinetic'][0]))


def free_block(et):
    text = ('DIMENSION 3\nBOX blk ORIGIN 0.1 -0.02 0.05 SIZE 0.06 0.04 0.04 ELEMENTS 3 2 2 TYPE %s\n'
            'MATERIAL alu ELASTIC YOUNG 7e10 POISSON 0.33 DENSITY 2700\nMODEL blk MATERIAL alu\n'
            'FUNCTION shear POINTS 0.1 -1 0.16 2\n'
            'INITIAL blk VELOCITY 0.5 3 -2 FUNCTION shear ALONG X\n'
            'TIME STEP 1e-6 END 2e-4\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 0\n' % et)
    out = sc.run_ok(sc.write_scene('free_%s.dat' % et, text))
    h = sc.history(out)
    keys = ['momentum_x', 'momentum_y', 'momentum_z', 'angular_momentum_x', 'angular_momentum_y', 'angular_momentum']
    pscale = max(np.abs(h[k]).max() for k in keys[:3])
    lscale = max(np.abs(h[k]).max() for k in keys[3:])
    dp = max(np.abs(h[k] - h[k][0]).max() for k in keys[:3]) / pscale
    dl = max(np.abs(h[k] - h[k][0]).max() for k in keys[3:]) / lscale
    sc.report_measured('free %s: three momenta constant (1e-12)' % et, dp <= 1e-12, '%.2e' % dp)
    sc.report_measured('free %s: three angular momenta constant (1e-12)' % et, dl <= 1e-12 and lscale > 0,
                       '%.2e of %.3e' % (dl, lscale))
    e = h['kinetic'] + h['internal']
    sc.report_measured('free %s: kinetic + internal constant (1e-10)' % et, np.abs(e - e[0]).max() <= 1e-10 * e[0],
                       '%.2e of E' % (np.abs(e - e[0]).max() / e[0]))
    deformed = h['internal'].max() > 1e-3 * e[0]
    sc.report('free %s: the block deforms (internal energy > 1e-3 E)' % et, deformed)


def two_blocks():
    """Two HEX8 blocks, one thrown at the other along x with a sideways drift, node-to-node GAP … WITH:
    the impulses are equal, opposite and collinear, so the three momenta and the three angular momenta
    (about the origin) are kept to 1e-12, with the balance <= 1e-10."""
    text = ('DIMENSION 3\nBOX a ORIGIN 0 0 0 SIZE 0.04 0.02 0.02 ELEMENTS 4 2 2 TYPE HEX8\n'
            'BOX b ORIGIN 0.041 0 0 SIZE 0.04 0.02 0.02 ELEMENTS 4 2 2 TYPE HEX8\n'
            'MATERIAL st ELASTIC YOUNG 2e11 POISSON 0.3 DENSITY 7800\nMODEL a MATERIAL st\nMODEL b MATERIAL st\n'
            'INITIAL a VELOCITY 2 0.3 -0.2\nGAP hit NODES a.xmax WITH b.xmin\n'
            'TIME STEP 1e-6 END 1e-3\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 0\n')
    for mode in MODES:
        rc, err, out = sc.run(sc.write_scene('two_blocks.dat', text), ['SCHEME.IMPACT=' + mode])
        tag = 'GAP WITH 3D %s' % mode
        if not sc.report(tag + ': runs', rc == 0, 'exit %d: %s' % (rc, err.strip()[-300:])):
            continue
        h = sc.history(out)
        keys = ['momentum_x', 'momentum_y', 'momentum_z', 'angular_momentum_x', 'angular_momentum_y', 'angular_momentum']
        p0 = max(np.abs(h[k][0]) for k in keys[:3])
        dp = max(np.abs(h[k] - h[k][0]).max() for k in keys[:3]) / p0
        dl = max(np.abs(h[k] - h[k][0]).max() for k in keys[3:]) / (p0 * 0.08)
        sc.report_measured(tag + ': three momenta and three angular momenta kept (1e-12)', dp <= 1e-12 and dl <= 1e-12,
                           'momenta %.2e, angular momenta %.2e' % (dp, dl))
        hit = h['momentum_x'][0] - 0  # the struck block takes momentum: a's x-momentum falls
        sc.report(tag + ': the blocks collide', np.any(h['active_contacts'] > 0) and hit > 0)
        cc.check_balance(tag, out)


def spinning():
    """INITIAL … ANGULAR_VELOCITY wx wy wz ABOUT x y z with a VELOCITY: a rigid motion, exact against the
    box's inertia (the consistent mass integrates |v|^2 and r x v exactly): kinetic energy
    m v^2/2 + w.I_c w/2, momentum m v, angular momentum about the origin m c x v + I_c w, all to 1e-13; a
    small-strain body keeps them (its infinitesimal rotation strains nothing)."""
    a, b, d = 0.06, 0.04, 0.03
    c = np.array([0.1, -0.02, 0.05]) + 0.5 * np.array([a, b, d])
    w = np.array([3.0, -5.0, 7.0])
    v = np.array([0.5, 1.0, -2.0])
    rho = 2700.0
    m = rho * a * b * d
    ic = m / 12.0 * np.diag([b * b + d * d, a * a + d * d, a * a + b * b])
    for et in ('HEX8', 'TET4'):
        text = ('DIMENSION 3\nBOX blk ORIGIN 0.1 -0.02 0.05 SIZE %g %g %g ELEMENTS 3 2 2 TYPE %s\n'
                'MATERIAL alu ELASTIC YOUNG 7e10 POISSON 0.33 DENSITY %g\nMODEL blk MATERIAL alu\n'
                'INITIAL blk VELOCITY %g %g %g\nINITIAL blk ANGULAR_VELOCITY %g %g %g ABOUT %.17g %.17g %.17g\n'
                'TIME STEP 1e-5 END 1e-3\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 0\n'
                % ((a, b, d, et, rho) + tuple(v) + tuple(w) + tuple(c)))
        out = sc.run_ok(sc.write_scene('spin_%s.dat' % et, text))
        h = sc.history(out)
        ke = 0.5 * m * v @ v + 0.5 * w @ ic @ w
        lo = m * np.cross(c, v) + ic @ w
        p = np.array([h['momentum_x'][0], h['momentum_y'][0], h['momentum_z'][0]])
        l0 = np.array([h['angular_momentum_x'][0], h['angular_momentum_y'][0], h['angular_momentum'][0]])
        errs = (abs(h['kinetic'][0] - ke) / ke, np.linalg.norm(p - m * v) / (m * np.linalg.norm(v)),
                np.linalg.norm(l0 - lo) / np.linalg.norm(lo))
        # TET4's consistent mass integrates quadratics exactly too (rho V (1 + d_ij)/20).
        sc.report_measured('spin %s: kinetic energy, momentum, angular momentum exact (1e-13)' % et, max(errs) <= 1e-13,
                           'errors %.2e, %.2e, %.2e' % errs)
        drift = max(np.abs(h[k] - h[k][0]).max() for k in ('angular_momentum_x', 'angular_momentum_y',
                                                             'angular_momentum')) / np.linalg.norm(lo)
        sc.report_measured('spin %s: angular momentum kept (1e-12)' % et, drift <= 1e-12, '%.2e' % drift)
        sc.report('spin %s: nothing strains (internal <= 1e-14 E)' % et, np.abs(h['internal']).max() <= 1e-14 * ke,
                  '%.2e J' % np.abs(h['internal']).max())


def face_loads():
    """PRESSURE and TRACTION on the faces of a free block (HEX8, TET4): its momentum grows by the total
    force, -p A n and t A, exactly (constant loads: p(t) = F t, 1e-12); a group that is no face is refused."""
    for et in ('HEX8', 'TET4'):
        for kind, stmt, force in (('PRESSURE', 'PRESSURE load NODES blk.xmax VALUE 1e5', [-1e5 * 0.04 * 0.03, 0, 0]),
                                  ('TRACTION', 'TRACTION load NODES blk.zmax VALUE 1e4 -2e4 3e4',
                                   [1e4 * 0.06 * 0.04, -2e4 * 0.06 * 0.04, 3e4 * 0.06 * 0.04])):
            stmt = stmt.replace('load NODES ', '')
            text = ('DIMENSION 3\nBOX blk ORIGIN 0.1 -0.02 0.05 SIZE 0.06 0.04 0.03 ELEMENTS 3 2 2 TYPE %s\n'
                    'MATERIAL alu ELASTIC YOUNG 7e10 POISSON 0.33 DENSITY 2700\nMODEL blk MATERIAL alu\n%s\n'
                    'TIME STEP 1e-6 END 2e-4\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 0\n' % (et, stmt))
            out = sc.run_ok(sc.write_scene('face_%s_%s.dat' % (kind, et), text))
            h = sc.history(out)
            p = np.vstack([h['momentum_x'], h['momentum_y'], h['momentum_z']])
            exact = np.outer(force, h['time'])
            err = np.abs(p - exact).max() / (np.linalg.norm(force) * h['time'][-1])
            sc.report_measured('%s on the faces of a %s block: momentum = total force x t (1e-12)' % (kind, et),
                               err <= 1e-12, '%.2e' % err)
    text = ('DIMENSION 3\nBOX blk ORIGIN 0 0 0 SIZE 0.06 0.04 0.03 ELEMENTS 3 2 2 TYPE HEX8\n'
            'MATERIAL alu ELASTIC YOUNG 7e10 POISSON 0.33 DENSITY 2700\nMODEL blk MATERIAL alu\n'
            'PRESSURE blk.center VALUE 1e5\nTIME STEP 1e-6 END 2e-4\n')
    rc, err, _ = sc.run(sc.write_scene('face_not.dat', text), outdir=os.path.join(sc.new_dir('bad3d'), 'never'))
    msg = ' '.join(sc.message_lines(err))
    sc.report('PRESSURE on a node inside the block: exit 2, line 5, the node named', rc == 2 and 'face_not.dat:5:' in msg
              and 'free element face' in msg, 'exit %d: %s' % (rc, msg[-200:]))


def j2_twin():
    """VON_MISES on HEX8: the plane-strain J2 block of inputs/block_j2.dat (FORMULATION STANDARD) extruded
    one element through z with UZ held is the same problem (u independent of z, the 6-component return
    with no out-of-plane shear is the 4-component one): its kinetic, internal and plastic energies equal
    the QUAD4 run's to 1e-9 of the energy at every step, and its balance is <= 1e-10 E."""
    twod = sc.run_ok(os.path.join(sc.ROOT, 'inputs', 'block_j2.dat'), ['MODEL.block.FORMULATION=STANDARD',
                                                                      'OUTPUT.FIELDS=0'])
    text = ('DIMENSION 3\nBOX block ORIGIN 0 0 0 SIZE 1 0.5 1 ELEMENTS 20 10 1 TYPE HEX8\n'
            'MATERIAL steel VON_MISES YOUNG 2.1e11 POISSON 0.3 DENSITY 7800 YIELD 2.5e8 H_ISO 2e9 H_KIN 0\n'
            'MODEL block MATERIAL steel MASS CONSISTENT SUBSTEPS 8 FORMULATION STANDARD\nFIX block.ymin UX UY UZ\n'
            'FIX block UZ\n'
            'FUNCTION pulse POINTS 0 0  1e-3 1  2e-3 1  3e-3 0\nLOAD press NODES block.ymax FORCE 0 -0.7e7 0 FUNCTION pulse\n'
            'TIME STEP 1e-5 END 5e-3\nSCHEME NEWMARK MAX_ITERATIONS 100\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 0\n')
    out = sc.run_ok(sc.write_scene('j2_3d.dat', text))
    a, b = sc.history(twod), sc.history(out)
    scale = max(a['kinetic'] + a['internal'])
    err = max(np.abs(a[k] - b[k]).max() for k in ('kinetic', 'internal', 'dissipated')) / scale
    sc.report_measured('VON_MISES HEX8 = its plane-strain QUAD4 twin (energies, 1e-9 of E)', err <= 1e-9 and
                       a['dissipated'][-1] > 0.1 * scale, '%.2e; plastic work %.3g J of %.3g' % (err, b['dissipated'][-1],
                                                                                             scale))
    cc.check_balance('VON_MISES HEX8 block', out)


def locking():
    """Volumetric locking of HEX8 at nu = 0.499 and its cure, FORMULATION BBAR (AUTO's choice there): the
    first bending frequency of a 1 m x 0.1 m x 0.1 m cantilever (20 x 2 x 2 HEX8, free vibration from a
    linear velocity profile, zero crossings of the tip) against Euler-Bernoulli's 1.875^2/(2 pi L^2)
    sqrt(EI / (rho A)) = 1.6153 Hz: BBAR within 3 %, STANDARD locked (more than 1.5 times it)."""
    fb = 1.875104 ** 2 / (2 * math.pi) * math.sqrt(1e7 * 0.1 ** 4 / 12 / (1000 * 0.01))
    freq = {}
    for form in ('STANDARD', 'BBAR', 'AUTO'):
        text = ('DIMENSION 3\nBOX c ORIGIN 0 0 0 SIZE 1 0.1 0.1 ELEMENTS 20 2 2 TYPE HEX8\n'
                'MATERIAL rub ELASTIC YOUNG 1e7 POISSON 0.499 DENSITY 1000\nMODEL c MATERIAL rub FORMULATION %s\n'
                'FIX c.xmin UX UY UZ\nFUNCTION prof POINTS 0 0 1 1\nINITIAL c VELOCITY 0 0.01 0 FUNCTION prof ALONG X\n'
                'GROUP tip NODES BOX 0.99 0 0 1.01 0 0 OF c\nTIME STEP 0.01 END 3\n'
                'OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE tip UY\n' % form)
        out = sc.run_ok(sc.write_scene('cantilever_%s.dat' % form, text))
        p = sc.probes(out)
        t, y = p['time'], p['tip.UY']
        z = [t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i]) for i in range(len(y) - 1) if y[i] > 0 >= y[i + 1]]
        freq[form] = (len(z) - 1) / (z[-1] - z[0])
    sc.report_measured('HEX8 nu = 0.499, FORMULATION BBAR: first bending frequency within 3 % of beam theory',
                       abs(freq['BBAR'] / fb - 1) <= 0.03, '%.4f Hz against %.4f Hz' % (freq['BBAR'], fb))
    sc.report_measured('HEX8 nu = 0.499, FORMULATION STANDARD: locked (more than 1.5 times beam theory)',
                       freq['STANDARD'] > 1.5 * fb, '%.4f Hz' % freq['STANDARD'])
    sc.report('HEX8 nu = 0.499: FORMULATION AUTO takes BBAR', freq['AUTO'] == freq['BBAR'],
              '%.6f against %.6f Hz' % (freq['AUTO'], freq['BBAR']))


def modes_3d():
    """MODES in 3D: a free steel bar (1 m, 40 x 1 x 1 HEX8, nu = 0) has six rigid modes (zero frequencies,
    their effective masses the bar's mass along x, y and z) and its first axial mode at c/(2L) =
    2500 Hz (0.5 %)."""
    text = ('DIMENSION 3\nBOX bar ORIGIN 0 0 0 SIZE 1 0.05 0.05 ELEMENTS 40 1 1 TYPE HEX8\n'
            'MATERIAL st ELASTIC YOUNG 2e11 POISSON 0 DENSITY 8000\nMODEL bar MATERIAL st\nMODES 16\n'
            'TIME STEP 1e-5 END 0\n')
    out = sc.run_ok(sc.write_scene('modes_3d.dat', text))
    m = sc.read_csv(os.path.join(out, 'modes.csv'))
    f = m['frequency']
    rigid = (f[:6].max() / f[6]) ** 2 <= 1e-10      # (omega^2 of a rigid mode: round-off of the pencil's)
    mass = 8000 * 0.05 * 0.05
    sums = [m['effective_mass_' + d][:6].sum() / mass - 1 for d in 'xyz']
    sc.report_measured('MODES 3D: six rigid modes carrying the mass along x, y, z (1e-9)',
                       rigid and max(abs(x) for x in sums) <= 1e-9, 'highest rigid %.2e Hz; mass sums off by %s'
                       % (f[:6].max(), ', '.join('%.1e' % x for x in sums)))
    axial = f[np.argmin(np.abs(f - 2500.0))]
    sc.report_measured('MODES 3D: first axial mode at c/(2L) = 2500 Hz (0.5 %)', abs(axial / 2500 - 1) <= 5e-3,
                       '%.3f Hz' % axial)


def quadratic():
    """HEX20 and TET10: a cantilever's first three bending frequencies (1 m x 20 mm x 20 mm steel, nu = 0,
    20 x 1 x 1 cells, MODES) against Euler-Bernoulli, beta L = 1.8751, 4.6941, 7.8548 (0.5 %); fields.xmf of
    a HEX20 and a TET10 run checked (tools/check_xdmf.py) and their cells in XDMF's node order: each
    mid-edge node at the middle of XDMF's edge."""
    import subprocess
    import h5py
    ei, ra = 2e11 * 0.02 ** 4 / 12, 8000 * 0.02 ** 2
    fb = [b * b / (2 * math.pi) * math.sqrt(ei / ra) for b in (1.875104069, 4.694091133, 7.854757438)]
    xdmf_edges = {48: [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)],
                  38: [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]}
    for et, code in (('HEX20', 48), ('TET10', 38)):
        text = ('DIMENSION 3\nBOX c ORIGIN 0 0 0 SIZE 1 0.02 0.02 ELEMENTS 20 1 1 TYPE %s\n'
                'MATERIAL st ELASTIC YOUNG 2e11 POISSON 0 DENSITY 8000\nMODEL c MATERIAL st\nFIX c.xmin UX UY UZ\n'
                'MODES 6\nTIME STEP 1e-5 END 0\n' % et)
        out = sc.run_ok(sc.write_scene('cantilever_%s.dat' % et, text))
        f = sc.read_csv(os.path.join(out, 'modes.csv'))['frequency']
        err = max(abs(f[2 * k + j] / fb[k] - 1) for k in range(3) for j in range(2))
        sc.report_measured('%s cantilever: three bending frequencies (both planes) within 0.5 %% of beam theory' % et,
                           err <= 5e-3, ', '.join('%.3f' % x for x in f) + ' Hz against ' +
                           ', '.join('%.3f' % x for x in fb))
        # fields of a dynamic run: the XDMF check, and the node order of the cells
        text2 = text.replace('MODES 6\nTIME STEP 1e-5 END 0\n', 'INITIAL c VELOCITY 0 0 1\nTIME STEP 1e-4 END 1e-3\n'
                             'OUTPUT HISTORY EVERY 1 FIELDS EVERY 5\n')
        out = sc.run_ok(sc.write_scene('fields_%s.dat' % et, text2))
        r = subprocess.run(['/usr/bin/python3', os.path.join(sc.ROOT, 'tools', 'check_xdmf.py'),
                            os.path.join(out, 'fields.xmf')], capture_output=True, text=True)
        sc.report('%s: fields.xmf passes tools/check_xdmf.py' % et, r.returncode == 0, (r.stdout + r.stderr)[-300:])
        with h5py.File(os.path.join(out, 'fields.h5'), 'r') as h:
            xyz = h['mesh/coordinates'][()]
            topo = h['mesh/topology'][()]
        bad, k, cells = 0, 0, 0
        nen = 20 if code == 48 else 10
        while k < len(topo):
            c = topo[k]
            nodes = topo[k + 1:k + 1 + nen]
            k += 1 + nen
            if c != code:
                bad += 1
                continue
            cells += 1
            first = nen - len(xdmf_edges[code])      # the mid-edge nodes follow the corners
            for m, (a, b) in enumerate(xdmf_edges[code]):
                mid = 0.5 * (xyz[nodes[a]] + xyz[nodes[b]])
                if np.abs(xyz[nodes[first + m]] - mid).max() > 1e-12:
                    bad += 1
        sc.report('%s: every cell in XDMF\'s node order (mid-edge nodes at its edges\' middles)' % et,
                  bad == 0 and cells > 0, '%d misplaced of %d cells' % (bad, cells))


def wedges():
    """WEDGE6 (Gmsh's 6-node prism; BOX … TYPE WEDGE6 cuts each cell in two): a free bar (1 m, 40 x 1 x 1
    cells, nu = 0) has six rigid modes and its first axial mode at c/(2L) = 2500 Hz (0.5 %); a
    cantilever's first bending frequency converges to beam theory's (linear prisms lock in bending,
    as TET4: the error falls by more than half from 20 x 1 x 1 to 40 x 2 x 2 cells); PRESSURE on the
    prisms' triangles (z = const) and quadrangles (x = const) of a free block: momentum = p A t along
    each (1e-12); fields.xmf passes tools/check_xdmf.py with every cell in VTK's wedge order (the
    base's right-hand normal pointing away from the top triangle)."""
    import subprocess
    import h5py
    text = ('DIMENSION 3\nBOX bar ORIGIN 0 0 0 SIZE 1 0.05 0.05 ELEMENTS 40 1 1 TYPE WEDGE6\n'
            'MATERIAL st ELASTIC YOUNG 2e11 POISSON 0 DENSITY 8000\nMODEL bar MATERIAL st\nMODES 20\n'
            'TIME STEP 1e-5 END 0\n')
    f = sc.read_csv(os.path.join(sc.run_ok(sc.write_scene('modes_wedge.dat', text)), 'modes.csv'))['frequency']
    axial = f[np.argmin(np.abs(f - 2500.0))]
    sc.report_measured('WEDGE6 free bar: six rigid modes, first axial mode at c/(2L) = 2500 Hz (0.5 %)',
                       (f[:6].max() / f[6]) ** 2 <= 1e-10 and abs(axial / 2500 - 1) <= 5e-3,
                       'highest rigid %.2e Hz, axial %.3f Hz' % (f[:6].max(), axial))
    fb = 1.875104069 ** 2 / (2 * math.pi) * math.sqrt(2e11 * 0.02 ** 4 / 12 / (8000 * 0.02 ** 2))
    errs = []
    for n in ((20, 1, 1), (40, 2, 2)):
        text = ('DIMENSION 3\nBOX c ORIGIN 0 0 0 SIZE 1 0.02 0.02 ELEMENTS %d %d %d TYPE WEDGE6\n'
                'MATERIAL st ELASTIC YOUNG 2e11 POISSON 0 DENSITY 8000\nMODEL c MATERIAL st\nFIX c.xmin UX UY UZ\n'
                'MODES 2\nTIME STEP 1e-5 END 0\n' % n)
        f = sc.read_csv(os.path.join(sc.run_ok(sc.write_scene('cantilever_wedge.dat', text)), 'modes.csv'))['frequency']
        errs.append(f[0] / fb - 1)
    sc.report_measured('WEDGE6 cantilever: first bending frequency converging to beam theory (error halved)',
                       0 < errs[1] < 0.5 * errs[0], '%+.1f %% (20 x 1 x 1), %+.1f %% (40 x 2 x 2) of %.3f Hz'
                       % (100 * errs[0], 100 * errs[1], fb))
    text = ('DIMENSION 3\nBOX b ORIGIN 0 0 0 SIZE 0.3 0.2 0.1 ELEMENTS 3 2 2 TYPE WEDGE6\n'
            'MATERIAL st ELASTIC YOUNG 2e9 POISSON 0.3 DENSITY 1000\nMODEL b MATERIAL st\n'
            'PRESSURE b.zmax VALUE 1e4\nPRESSURE b.xmax VALUE 2e4\nTIME STEP 1e-4 END 2e-3\n'
            'OUTPUT HISTORY EVERY 1 FIELDS EVERY 5\n')
    out = sc.run_ok(sc.write_scene('wedge_pressure.dat', text))
    h = sc.history(out)
    t = h['time']
    err = max(np.abs(h['momentum_z'] + 1e4 * 0.3 * 0.2 * t).max() / (1e4 * 0.06 * t[-1]),
              np.abs(h['momentum_x'] + 2e4 * 0.2 * 0.1 * t).max() / (2e4 * 0.02 * t[-1]), np.abs(h['momentum_y']).max())
    sc.report_measured('WEDGE6 PRESSURE on triangles and quadrangles: momentum = -p A t (1e-12)', err <= 1e-12, '%.1e' % err)
    r = subprocess.run(['/usr/bin/python3', os.path.join(sc.ROOT, 'tools', 'check_xdmf.py'), os.path.join(out, 'fields.xmf')],
                       capture_output=True, text=True)
    sc.report('WEDGE6: fields.xmf passes tools/check_xdmf.py', r.returncode == 0, (r.stdout + r.stderr)[-300:])
    with h5py.File(os.path.join(out, 'fields.h5'), 'r') as f5:
        xyz = f5['mesh/coordinates'][()]
        topo = f5['mesh/topology'][()]
    good = bad = 0
    for k in range(0, len(topo), 7):
        if topo[k] != 8:
            bad += 1
            continue
        c = xyz[topo[k + 1:k + 7]]
        normal = np.cross(c[1] - c[0], c[2] - c[0])
        if normal @ (c[3:].mean(axis=0) - c[:3].mean(axis=0)) < 0:
            good += 1
        else:
            bad += 1
    sc.report('WEDGE6: every XDMF cell a Wedge (code 8) in VTK\'s order', bad == 0 and good == 24,
              '%d good, %d bad' % (good, bad))


def static_3d():
    """STATIC and INITIAL … STATIC in 3D: a HEX20 steel cantilever (1 m, 50 x 50 mm, 20 cells, nu = 0)
    under gravity GZ takes Euler-Bernoulli's tip deflection q L^4 / (8 E I) within 0.5 % and stays at
    rest in the dynamics (the tip moves by less than 1e-9 of it), its support reactions (PROBE RX, RY,
    RZ) the weight along each axis (gravity GX, GY too); a tip force released at t = 0
    (INITIAL … STATIC FORCE) starts the tip at P L^3 / (3 E I) within 0.5 %; a block resting on a
    frictionless plane, held in x and y by FIX, carries its weight on the contact (the contact
    force = m g to 1e-9), and the same block without the FIX is an input error naming its free
    translation along x."""
    base = ('DIMENSION 3\nBOX c ORIGIN 0 0 0 SIZE 1 0.05 0.05 ELEMENTS 20 1 1 TYPE HEX20\n'
            'MATERIAL st ELASTIC YOUNG 2e11 POISSON 0 DENSITY 8000\nMODEL c MATERIAL st\nFIX c.xmin UX UY UZ\n'
            'GROUP tip NODES BOX 0.999 -1e-6 -1e-6 1.001 1e-6 1e-6 OF c\n')
    ei = 2e11 * 0.05 ** 4 / 12
    q = 8000 * 0.05 ** 2 * 9.81
    out = sc.run_ok(sc.write_scene('static_cantilever.dat', base + 'GRAVITY GX -1 GY -2 GZ -9.81\nSTATIC\n'
                                   'TIME STEP 1e-4 END 1e-2\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE tip UZ '
                                   'PROBE c.xmin RX PROBE c.xmin RY PROBE c.xmin RZ\n'))
    p = sc.probes(out)
    uz = p['tip.UZ']
    w = q / (8 * ei)
    sc.report_measured('STATIC 3D: HEX20 cantilever under gravity, tip within 0.5 % of q L^4/(8EI), at rest after',
                       abs(-uz[0] / w - 1) <= 5e-3 and np.abs(uz - uz[0]).max() <= 1e-9 * abs(uz[0]),
                       'tip %.6e m (beam %.6e), moves by %.1e of it' % (-uz[0], w, np.abs(uz - uz[0]).max() / abs(uz[0])))
    mass = 8000 * 0.05 ** 2
    err = max(np.abs(p['c.xmin.R' + d] - mass * g).max() / (mass * 9.81) for d, g in zip('XYZ', (1.0, 2.0, 9.81)))
    sc.report_measured('PROBE RX, RY, RZ in 3D: the support carries the weight m (1, 2, 9.81) N/kg (1e-8)', err <= 1e-8,
                       '%.1e' % err)
    out = sc.run_ok(sc.write_scene('initial_static_3d.dat', base + 'INITIAL tip STATIC FORCE 0 0 -100\n'
                                   'TIME STEP 1e-4 END 1e-3\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE tip UZ\n'))
    uz = sc.probes(out)['tip.UZ']
    w = 100 / (3 * ei)
    sc.report_measured('INITIAL … STATIC FORCE in 3D: the tip starts at P L^3/(3EI) (0.5 %)', abs(-uz[0] / w - 1) <= 5e-3,
                       'tip %.6e m (beam %.6e)' % (-uz[0], w))
    block = ('DIMENSION 3\nBOX b ORIGIN 0 0 0.001 SIZE 0.1 0.1 0.05 ELEMENTS 2 2 1 TYPE HEX8\n'
             'MATERIAL st ELASTIC YOUNG 2e11 POISSON 0.3 DENSITY 8000\nMODEL b MATERIAL st\n'
             'OBSTACLE floor NODES b.zmin POINT 0 0 0.001 NORMAL 0 0 1\nGRAVITY GZ -9.81\nSTATIC\n'
             'TIME STEP 1e-5 END 1e-4\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 0\n')
    out = sc.run_ok(sc.write_scene('static_block.dat', block.replace('STATIC\n', 'STATIC\nFIX b UX UY\n')))
    c = sc.contacts(out)
    m = 8000 * 0.1 * 0.1 * 0.05
    f0 = c['force_z'][c['step'] == 1].sum()
    sc.report_measured('STATIC 3D: a block on a frictionless plane carries m g on its contacts (1e-9)',
                       abs(f0 / (m * 9.81) - 1) <= 1e-9, 'contact force %.10g N, m g %.10g N' % (f0, m * 9.81))
    path = sc.write_scene('static_block_free.dat', block)
    rc, err, _ = sc.run(path, outdir=os.path.join(sc.new_dir('bad3d'), 'never'))
    sc.report('STATIC 3D: a block free to slide on a frictionless plane is an input error naming the mode',
              rc == 2 and 'free translation along x' in err and 'STATIC' in err, err.strip()[:200])


def moving_plane():
    """OBSTACLE … VELOCITY vx vy vz in 3D: an elastic block thrown at a plane of normal (0.36, 0.48, 0.8)
    that moves at (0.2, 0.1, 0.5) m/s (tangential parts included) is, in the plane's frame, the same
    block thrown at the fixed plane with its velocity less the plane's (Galilean invariance): the three
    momenta of the two runs differ by m v_w at every step to round-off, 4 eps a step over the 2 500
    steps (2.2e-12 of |p0|: the two runs' rounding differs, the motion they add does not), in every
    IMPACT mode; the balance, with the plane's work booked as external, <= 1e-10 E."""
    text = ('DIMENSION 3\nBOX b ORIGIN 0.01 0.01 0.02 SIZE 0.04 0.04 0.04 ELEMENTS 2 2 2 TYPE HEX8\n'
            'MATERIAL rub ELASTIC YOUNG 1e7 POISSON 0.3 DENSITY 1000\nMODEL b MATERIAL rub\n'
            'INITIAL b VELOCITY %r %r %r\nGROUP low NODES b.xmin b.ymin b.zmin\n'
            'OBSTACLE floor NODES low POINT 0 0 0 NORMAL 0.36 0.48 0.8%s\n'
            'TIME STEP 1e-5 END 2.5e-2\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 0\n')
    vw = np.array([0.2, 0.1, 0.5])
    v0 = np.array([0.5, -0.3, -2.0])
    m = 1000 * 0.04 ** 3
    moving = sc.write_scene('moving_plane.dat', text % (tuple(v0) + (' VELOCITY 0.2 0.1 0.5',)))
    fixed = sc.write_scene('fixed_plane.dat', text % (tuple(v0 - vw) + ('',)))
    for mode in MODES:
        a = sc.run_ok(moving, ['SCHEME.IMPACT=' + mode])
        ha, hb = sc.history(a), sc.history(sc.run_ok(fixed, ['SCHEME.IMPACT=' + mode]))
        d = max(np.abs(ha['momentum_' + k] - m * vw[i] - hb['momentum_' + k]).max() for i, k in enumerate('xyz'))
        d /= m * np.linalg.norm(v0 - vw)
        hit = np.array([0.36, 0.48, 0.8]) @ np.array([hb['momentum_' + k][-1] for k in 'xyz']) > 0
        bound = 4 * np.finfo(float).eps * (len(ha['step']) - 1)
        sc.report_measured('moving plane 3D, %s: the fixed plane\'s run in its frame (4 eps a step of |p0|), rebounds'
                           % mode, d <= bound and hit, '%.1e (bound %.1e)' % (d, bound))
        cc.check_balance('moving plane 3D, %s' % mode, a)


def falling():
    text = ('DIMENSION 3\nBOX blk ORIGIN 0 0 0 SIZE 0.06 0.04 0.04 ELEMENTS 3 2 2 TYPE HEX8\n'
            'MATERIAL alu ELASTIC YOUNG 7e10 POISSON 0.33 DENSITY 2700\nMODEL blk MATERIAL alu\n'
            'GRAVITY GZ -9.81\nTIME STEP 1e-4 END 0.002\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 0\n')
    out = sc.run_ok(sc.write_scene('falling.dat', text))
    h = sc.history(out)
    m = 2700 * 0.06 * 0.04 * 0.04
    err = np.abs(h['momentum_z'] + m * 9.81 * h['time']).max() / (m * 9.81 * h['time'][-1])
    sc.report_measured('GRAVITY GZ: momentum_z = -m g t (1e-12)', err <= 1e-12, '%.2e' % err)
    side = max(np.abs(h['momentum_x']).max(), np.abs(h['momentum_y']).max())
    sc.report('GRAVITY GZ: momenta x, y stay 0 (1e-12)', side <= 1e-12 * m * 9.81 * h['time'][-1], '%.2e' % side)


def fields():
    """A bar stretched uniformly, u = (e x, -nu e y, -nu e z) t with e = 1e-3 /s between symmetry planes
    (the exact solution: zero acceleration, which the trapezoidal rule integrates exactly): sigma_xx =
    E e t, the other stresses 0, to round-off, in fields.h5."""
    import h5py
    text = ('DIMENSION 3\nBOX bar ORIGIN 0 0 0 SIZE 0.1 0.01 0.01 ELEMENTS 4 1 1 TYPE %s\n'
            'MATERIAL st ELASTIC YOUNG 2e11 POISSON 0.3 DENSITY 7800\nMODEL bar MATERIAL st\n'
            'FIX bar.xmin UX\nFIX bar.ymin UY\nFIX bar.zmin UZ\nFUNCTION ramp POINTS 0 0 1 1\n'
            'FUNCTION lin POINTS -1 -1 1 1\nINITIAL bar VELOCITY 1e-3 0 0 FUNCTION lin ALONG X\n'
            'INITIAL bar VELOCITY 0 -3e-4 0 FUNCTION lin ALONG Y\nINITIAL bar VELOCITY 0 0 -3e-4 FUNCTION lin ALONG Z\n'
            'IMPOSE bar.xmax UX VALUE 1e-4 FUNCTION ramp\nTIME STEP 1e-2 END 0.1\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 5\n')
    for et, code in (('HEX8', 9), ('TET4', 6)):
        out = sc.run_ok(sc.write_scene('fields_%s.dat' % et, text % et))
        with h5py.File(os.path.join(out, 'fields.h5'), 'r') as f:
            xyz = f['mesh/coordinates'][()]
            topo = f['mesh/topology'][()]
            last = sorted(k for k in f.keys() if k.startswith('step_'))[-1]
            t = f[last].attrs['time']
            u = f[last + '/displacement'][()]
            cols = [k for k in ('sigma_xx', 'sigma_yy', 'sigma_zz', 'sigma_xy', 'sigma_yz', 'sigma_xz') if k in f[last]]
            sxx = f[last + '/sigma_xx'][()]
            has_rot = 'rotation' in f[last]
            stress = f[last + '/stress'][()]
        sc.report('fields %s: z coordinates' % et, np.isclose(xyz[:, 2].max(), 0.01))
        sc.report('fields %s: XDMF cell code %d' % (et, code), topo[0] == code)
        sc.report('fields %s: six stress columns, no rotation field' % et, len(cols) == 6 and stress.shape[1] == 6
                  and not has_rot, 'columns %s, stress %s' % (cols, stress.shape))
        uex = np.column_stack([1e-3 * xyz[:, 0], -3e-4 * xyz[:, 1], -3e-4 * xyz[:, 2]]) * t
        uerr = np.abs(u - uex).max() / 1e-4
        sc.report_measured('fields %s: displacement (e x, -nu e y, -nu e z) t (1e-12)' % et, uerr <= 1e-12,
                           '%.2e of the end displacement at t = %g s' % (uerr, t))
        sxx_exact = 2e11 * 1e-3 * t
        err = np.abs(sxx - sxx_exact).max() / sxx_exact
        lateral = max(np.abs(stress[:, k]).max() for k in (1, 2, 3, 4, 5)) / sxx_exact
        sc.report_measured('fields %s: uniaxial stress sigma_xx = E e t, the others 0 (1e-12)' % et,
                           err <= 1e-12 and lateral <= 1e-12, 'sigma_xx %.2e off, others %.2e of it' % (err, lateral))


def box_msh41(path, n, size, origin, tet=False, wedge=False):
    """A Gmsh 4.1 ASCII volume mesh of the BOX n x n x n cells (the same nodes and elements, in the same
    order, as BOX … TYPE HEX8, TET4 or WEDGE6): physical volume "body", physical surface "xmin" (its face
    x = x0, as 4-node quadrangles)."""
    nx, ny, nz = n
    ids = {}
    nodes = []
    for k in range(nz + 1):
        for j in range(ny + 1):
            for i in range(nx + 1):
                ids[(i, j, k)] = len(nodes) + 1
                nodes.append([origin[a] + size[a] * ([i, j, k][a] / float(n[a])) for a in range(3)])
    corner = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
    perms = [(0, 1, 2), (1, 2, 0), (2, 0, 1), (0, 2, 1), (2, 1, 0), (1, 0, 2)]
    vols = []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                if wedge:                   # two prisms on the diagonal 1-3 of the faces z = const
                    h = [ids[(i + a, j + b, k + c)] for a, b, c in corner]
                    vols += [[h[0], h[1], h[2], h[4], h[5], h[6]], [h[0], h[2], h[3], h[4], h[6], h[7]]]
                    continue
                if not tet:
                    vols.append([ids[(i + a, j + b, k + c)] for a, b, c in corner])
                    continue
                for q, p in enumerate(perms):
                    v = [0, 0, 0]
                    t = [ids[(i, j, k)]]
                    v[p[0]] = 1
                    t.append(ids[(i + v[0], j + v[1], k + v[2])])
                    v[p[1]] = 1
                    t.append(ids[(i + v[0], j + v[1], k + v[2])])
                    t.append(ids[(i + 1, j + 1, k + 1)])
                    if q >= 3:
                        t[2], t[3] = t[3], t[2]
                    vols.append(t)
    faces = [[ids[(0, j, k)], ids[(0, j + 1, k)], ids[(0, j + 1, k + 1)], ids[(0, j, k + 1)]]
             for k in range(nz) for j in range(ny)]
    lo, hi = origin, [origin[a] + size[a] for a in range(3)]
    with open(path, 'w') as f:
        f.write('$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n2 1 "xmin"\n3 2 "body"\n$EndPhysicalNames\n')
        f.write('$Entities\n0 0 1 1\n1 %g %g %g %g %g %g 1 1 0\n' % (lo[0], lo[1], lo[2], lo[0], hi[1], hi[2]))
        f.write('1 %g %g %g %g %g %g 1 2 1 1\n$EndEntities\n' % tuple(lo + hi))
        f.write('$Nodes\n1 %d 1 %d\n3 1 0 %d\n' % (len(nodes), len(nodes), len(nodes)))
        f.write(''.join('%d\n' % (i + 1) for i in range(len(nodes))))
        f.write(''.join('%.17g %.17g %.17g\n' % tuple(x) for x in nodes))
        f.write('$EndNodes\n$Elements\n2 %d 1 %d\n' % (len(vols) + len(faces), len(vols) + len(faces)))
        f.write('2 1 3 %d\n' % len(faces))
        f.write(''.join('%d %s\n' % (e + 1, ' '.join(map(str, q))) for e, q in enumerate(faces)))
        f.write('3 1 %d %d\n' % (6 if wedge else 4 if tet else 5, len(vols)))
        f.write(''.join('%d %s\n' % (len(faces) + e + 1, ' '.join(map(str, q))) for e, q in enumerate(vols)))
        f.write('$EndElements\n')


def gmsh_volumes():
    """GMSH in DIMENSION 3: the SDNV100 bar read from a Gmsh 4.1 file (HEX8, TET4, WEDGE6 prisms: the BOX's own nodes
    and elements) gives the BOX run's history.csv byte for byte; its surface group is a node group."""
    for et in ('HEX8', 'TET4', 'WEDGE6'):
        d = sc.new_dir('msh')
        os.makedirs(d, exist_ok=True)
        msh = os.path.join(d, 'bar.msh')
        box_msh41(msh, (20, 1, 1), [0.2, 0.02, 0.02], [0.002, 0.0, 0.0], tet=et == 'TET4', wedge=et == 'WEDGE6')
        with open(SDNV) as f:
            base = f.read().replace('FIELDS EVERY 10  PROBE bar.center UX  PROBE bar.center VX', 'FIELDS EVERY 0')
        base = base.replace('TYPE HEX8', 'TYPE ' + et)
        text = base.replace('BOX       bar ORIGIN 0.002 0 0 SIZE 0.2 0.02 0.02 ELEMENTS 20 1 1 TYPE ' + et,
                            'GMSH bar FILE %s' % msh).replace('MODEL     bar MATERIAL', 'MODEL     bar.body MATERIAL')
        ref = sc.run_ok(sc.write_scene('sdnv_box_%s.dat' % et, base))
        out = sc.run_ok(sc.write_scene('sdnv_gmsh_%s.dat' % et, text))
        same = open(os.path.join(ref, 'history.csv'), 'rb').read() == open(os.path.join(out, 'history.csv'), 'rb').read()
        sc.report('GMSH 4.1 volume mesh (%s): the BOX run byte for byte' % et, same)
    path = sc.write_scene('gmsh_volume_in_2d.dat', 'GMSH b FILE %s\nTIME STEP 1e-3 END 1e-2\n' % msh)
    rc, err, _ = sc.run(path, outdir=os.path.join(sc.new_dir('bad3d'), 'never'))
    msg = ' '.join(sc.message_lines(err))
    sc.report('a Gmsh volume mesh read in 2D: exit 2, the file and line of the volume, DIMENSION 3 named',
              rc == 2 and 'bar.msh:' in msg and 'DIMENSION 3' in msg, 'exit %d: %s' % (rc, msg[-300:]))


def bad_inputs():
    cases = [
        ('hex_in_2d', 'NODE a AT 0 0\n', 'RECTANGLE b ORIGIN 0 0 SIZE 1 1 ELEMENTS 1 1 TYPE HEX8\n', 'HEX8'),
        ('quad_in_3d', 'DIMENSION 3\nNODE a AT 0 0 0\nNODE b AT 1 0 0\nNODE c AT 1 1 0\nNODE d AT 0 1 0\n',
         'ELEMENT q TYPE QUAD4 NODES a b c d\nMATERIAL m ELASTIC YOUNG 1 DENSITY 1\nMODEL q MATERIAL m\n', 'q', 3),
        ('box_in_2d', '', 'BOX b ORIGIN 0 0 0 SIZE 1 1 1 ELEMENTS 1 1 1 TYPE HEX8\n', 'b'),
        ('box_zero_size', 'DIMENSION 3\n', 'BOX b ORIGIN 0 0 0 SIZE 1 0 1 ELEMENTS 1 1 1 TYPE HEX8\n', '0'),
        ('box_zero_elements', 'DIMENSION 3\n', 'BOX b ORIGIN 0 0 0 SIZE 1 1 1 ELEMENTS 1 0 1 TYPE HEX8\n', '0'),
        ('dimension_4', '', 'DIMENSION 4\n', '4'),
        ('dimension_late', 'NODE a AT 0 0\n', 'DIMENSION 3\n', '3'),
        ('node_2_coords_in_3d', 'DIMENSION 3\n', 'NODE a AT 0 0\n', 'AT'),
        ('probe_uz_in_2d', 'RECTANGLE b ORIGIN 0 0 SIZE 1 1 ELEMENTS 1 1 TYPE QUAD4\n', 'OUTPUT PROBE b UZ\n', 'UZ'),
        ('fix_uz_in_2d', 'RECTANGLE b ORIGIN 0 0 SIZE 1 1 ELEMENTS 1 1 TYPE QUAD4\n', 'FIX b UZ\n', 'UZ'),
        ('gravity_gz_in_2d', '', 'GRAVITY GZ -9.81\n', 'GZ'),
        ('sphere_in_3d', 'DIMENSION 3\nBOX b ORIGIN 0 0 0 SIZE 1 1 1 ELEMENTS 1 1 1 TYPE HEX8\n',
         'OBSTACLE w NODES b SPHERE 0 0 RADIUS 3 INSIDE\n', 'SPHERE'),
        ('hyperelastic_3d', 'DIMENSION 3\nBOX b ORIGIN 0 0 0 SIZE 1 1 1 ELEMENTS 1 1 1 TYPE HEX8\n'
         'MATERIAL m HYPERELASTIC YOUNG 1e9 POISSON 0.3 DENSITY 1000\n', 'MODEL b MATERIAL m\n', 'm'),
    ]
    inverted = ('inverted_hex', 'DIMENSION 3\n' + ''.join('NODE n%d AT %g %g %g\n' % (i + 1, x, y, z) for i, (x, y, z) in
                enumerate([(0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1), (0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)])),
                'ELEMENT h TYPE HEX8 NODES n1 n2 n3 n4 n5 n6 n7 n8\nMATERIAL m ELASTIC YOUNG 1 DENSITY 1\n'
                'MODEL h MATERIAL m\n', 'h', 3)
    for case in cases + [inverted]:
        name, head, bad, word = case[:4]
        text = head + bad + 'TIME STEP 1e-3 END 1e-2\n'
        line = head.count('\n') + (case[4] if len(case) > 4 else 1)   # the line of the statement at fault
        path = sc.write_scene('bad3d_%s.dat' % name, text)
        outdir = os.path.join(sc.new_dir('bad3d'), 'never')
        rc, err, _ = sc.run(path, outdir=outdir)
        msg = ' '.join(sc.message_lines(err))
        ok = rc == 2 and ('%s:%d:' % (os.path.basename(path), line)) in msg and ("'%s'" % word) in msg \
            and not os.path.exists(outdir)
        sc.report('bad input %s: exit 2, file:line, the word' % name, ok, 'exit %d: %s' % (rc, msg[-300:]))


sdnv('SDNV100 3D HEX8', [])
sdnv('SDNV100 3D TET4', ['BOX.bar.TYPE=TET4'], asserted=False)   # (TET4: a stiff, dispersive bar; printed)
sdnv('SDNV100 3D HEX20', ['BOX.bar.TYPE=HEX20'], asserted=False)  # (quadratic: an optical branch; printed)
sdnv('SDNV100 3D TET10', ['BOX.bar.TYPE=TET10'], asserted=False)
for et in ('HEX8', 'TET4'):
    for mode in MODES:
        oblique(et, mode)
    oblique(et, 'AUTO', plastic=True)
    free_block(et)
same, detail = sc.restart_same(SDNV, ['OUTPUT.CHECKPOINT=10', 'OUTPUT.FIELDS=0'], '6e-5',
                               ('history.csv', 'probes.csv', 'contacts.csv', 'events.csv'))
sc.report('SDNV100 3D: a restart mid-impact gives the same files byte for byte', same, detail)
two_blocks()
gmsh_volumes()
spinning()
face_loads()
j2_twin()
locking()
modes_3d()
quadratic()
wedges()
static_3d()
moving_plane()
falling()
fields()
bad_inputs()
