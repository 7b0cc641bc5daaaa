"""Stresses where users read them (issue 35, item 5; docs/input.md, "Output"): fields.h5 gains the
integration points' stresses as a point set (/points/coordinates, /step_N/points/*,
fields_points.xmf) and smoothed nodal stresses by the L2 projection of the points' values
(src/assembly/stress_recovery.f90), von Mises and the equivalent plastic strain at the nodes too.

- patch: a plate in uniform tension (STATIC) of QUAD4, QUAD8, TRI3 and TRI6: every node's and
  every point's sigma_xx is the applied stress, sigma_yy and sigma_xy zero, von Mises the stress
  (1e-10); one point per integration point, inside the plate;
- plasticity: the same QUAD8 plate pulled to 1.5 σy (VON_MISES, H_ISO h): the nodal and the
  points' equivalent plastic strain (σ - σy)/h at every node and point (1e-10);
- Kirsch: the quarter plate with a hole (tools/plate_hole_mesh.py, QUAD8, 16, 32, 64 elements a
  side), loaded on its outer sides by the consistent nodal forces of Kirsch's exact stresses
  (6-point Gauss on each side): the exact solution is Kirsch's, sigma_xx = 3 σ at the top of the
  hole. The nodal sigma_xx there converges to 3 σ at a rate that reaches at least 1.5 (QUAD8: 2
  asymptotically), within 1e-3 of 3 σ at 64, 50 times closer than the largest element mean.
"""
import os
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

SIG = 1e8
NGAUSS = {'QUAD4': 4, 'QUAD8': 9, 'TRI3': 1, 'TRI6': 3}


def last_step(out):
    f = h5py.File(os.path.join(out, 'fields.h5'), 'r')
    return f, f[sorted(k for k in f if k.startswith('step_'))[-1]]


def patch(kind, law='ELASTIC YOUNG 2e11 POISSON 0.3', load=SIG, extra=''):
    scene = sc.write_scene('patch_%s_%d.dat' % (kind, len(extra)), """RECTANGLE pl ORIGIN 0 0 SIZE 0.3 0.2 ELEMENTS 3 2 TYPE %s
MATERIAL st %s DENSITY 7800
SECTION sl THICKNESS 0.01
MODEL pl MATERIAL st SECTION sl PLANE STRESS
FIX pl.left UX
FIX pl.bottom_left UY
TRACTION pl.right VALUE %r 0
%s
TIME STEP 1e-6 END 1e-6
OUTPUT HISTORY EVERY 1 FIELDS EVERY 1
""" % (kind, law, load, extra or 'STATIC'))
    return sc.run_ok(scene)


def uniform():
    for kind in ['QUAD4', 'QUAD8', 'TRI3', 'TRI6']:
        f, g = last_step(patch(kind))
        nodes = f['mesh/coordinates'].shape[0]
        nx = g['nodal_sigma_xx'][()]
        others = np.concatenate([g['nodal_sigma_yy'][()], g['nodal_sigma_xy'][()], g['points/sigma_yy'][()],
                                 g['points/sigma_xy'][()]])
        px = g['points/sigma_xx'][()]
        err = max(np.max(np.abs(nx - SIG)), np.max(np.abs(px - SIG)), np.max(np.abs(others)),
                  np.max(np.abs(g['nodal_von_mises'][()] - SIG))) / SIG
        sc.report_measured('%s patch in uniform tension: every node and point sigma_xx = σ, the rest 0, von Mises σ' % kind,
                           err <= 1e-10 and len(nx) == nodes, '%.1e' % err)
        xg = f['points/coordinates'][()]
        inside = np.all((xg[:, 0] > 0) & (xg[:, 0] < 0.3) & (xg[:, 1] > 0) & (xg[:, 1] < 0.2))
        npt = (6 if kind.startswith('QUAD') else 12) * NGAUSS[kind]
        sc.report('%s patch: one point per integration point (%d), inside the plate' % (kind, npt),
                  len(px) == npt and len(xg) == len(px) and inside, '%d points' % len(px))


def plastic():
    sy, h = 2e8, 2e10
    out = patch('QUAD8', 'VON_MISES YOUNG 2e11 POISSON 0.3 YIELD %r H_ISO %r' % (sy, h), 1.5 * sy, 'STATIC STEPS 3')
    f, g = last_step(out)
    ep = (1.5 * sy - sy) / h
    err = max(np.max(np.abs(g['nodal_plastic_strain'][()] - ep)), np.max(np.abs(g['points/plastic_strain'][()] - ep))) / ep
    sc.report_measured('VON_MISES patch pulled to 1.5 σy: nodal and points\' plastic strain (σ - σy)/h everywhere',
                       err <= 1e-10, '%.1e' % err)


A, E, NU, T = 0.1, 2e11, 0.3, 0.01


def kirsch_stress(x, y):
    r = np.hypot(x, y)
    th = np.arctan2(y, x)
    c2, s2 = np.cos(2 * th), np.sin(2 * th)
    q = (A / r)**2
    srr = SIG / 2 * (1 - q) + SIG / 2 * (1 - 4 * q + 3 * q * q) * c2
    stt = SIG / 2 * (1 + q) - SIG / 2 * (1 + 3 * q * q) * c2
    srt = -SIG / 2 * (1 + 2 * q - 3 * q * q) * s2
    c, s = np.cos(th), np.sin(th)
    return (srr * c * c + stt * s * s - 2 * srt * s * c, srr * s * s + stt * c * c + 2 * srt * s * c,
            (srr - stt) * s * c + srt * (c * c - s * s))


def read_msh(path):
    txt = open(path).read()
    lines = txt.split('$Nodes\n')[1].split('$EndNodes')[0].split('\n')
    n = int(lines[0])
    xy = np.array([[float(v) for v in ln.split()[1:3]] for ln in lines[1:n + 1]])
    elems = txt.split('$Elements\n')[1].split('$EndElements')[0].split('\n')
    sides = []
    for ln in elems[1:int(elems[0]) + 1]:
        v = [int(t) for t in ln.split()]
        if v[1] == 8 and v[3] in (2, 3):              # 3-node lines of "right" and "top"
            sides.append((v[5] - 1, v[6] - 1, v[7] - 1))
    return xy, sides


def kirsch_scene(n):
    msh = os.path.join(sc.TMP, 'hole%d.msh' % n)
    subprocess.run(['/usr/bin/python3', os.path.join(sc.ROOT, 'tools', 'plate_hole_mesh.py'), str(n), str(n), msh, '4'],
                   check=True)
    xy, sides = read_msh(msh)
    f = np.zeros_like(xy)
    gx, gw = np.polynomial.legendre.leggauss(6)
    for a, b, m in sides:
        p3 = xy[[a, b, m]]
        for xi, w in zip(gx, gw):
            nn = np.array([xi * (xi - 1) / 2, xi * (xi + 1) / 2, 1 - xi * xi])
            d = np.array([xi - 0.5, xi + 0.5, -2 * xi]) @ p3
            p = nn @ p3
            ds = np.hypot(*d)
            nrm = np.array([d[1], -d[0]]) / ds
            if nrm @ p < 0:
                nrm = -nrm
            sxx, syy, sxy = kirsch_stress(*p)
            t = np.array([sxx * nrm[0] + sxy * nrm[1], sxy * nrm[0] + syy * nrm[1]])
            for k, node in enumerate((a, b, m)):
                f[node] += w * nn[k] * t * ds * T
    out = ['GMSH p FILE %s' % msh, 'MATERIAL st ELASTIC YOUNG 2e11 POISSON 0.3 DENSITY 7800', 'SECTION sl THICKNESS 0.01',
           'MODEL p.plate MATERIAL st SECTION sl PLANE STRESS', 'FIX p.left UX', 'FIX p.bottom UY']
    for k, i in enumerate(np.nonzero(np.hypot(f[:, 0], f[:, 1]) > 0)[0]):
        x, y = xy[i]
        out.append('GROUP o%d NODES BOX %.17g %.17g %.17g %.17g' % (k, x - 1e-9, y - 1e-9, x + 1e-9, y + 1e-9))
        out.append('LOAD l%d NODES o%d FORCE %.17g %.17g' % (k, k, f[i, 0], f[i, 1]))
    out += ['STATIC', 'TIME STEP 1e-6 END 1e-6', 'OUTPUT HISTORY EVERY 1 FIELDS EVERY 1']
    return sc.write_scene('hole%d.dat' % n, '\n'.join(out) + '\n')


def kirsch():
    errs, emean = [], []
    for n in [16, 32, 64]:
        f, g = last_step(sc.run_ok(kirsch_scene(n)))
        x = f['mesh/coordinates'][()]
        i = np.argmin(np.hypot(x[:, 0], x[:, 1] - A))
        errs.append(abs(g['nodal_sigma_xx'][()][i] / SIG - 3))
        emean.append(abs(g['sigma_xx'][()].max() / SIG - 3))
        print('# Kirsch QUAD8 %d x %d: nodal sigma_xx at the top of the hole 3 σ %+.2e σ, largest element mean %+.2e σ'
              % (n, n, g['nodal_sigma_xx'][()][i] / SIG - 3, g['sigma_xx'][()].max() / SIG - 3))
    rates = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    sc.report_measured('Kirsch (exact tractions, QUAD8): the nodal sigma_xx converges to 3 σ, rate >= 1.5 at the last '
                       'refinement', errs[2] < errs[1] < errs[0] and rates[-1] >= 1.5,
                       'errors %s, rates %s' % (['%.2e' % e for e in errs], ['%.2f' % r for r in rates]))
    sc.report_measured('Kirsch at 64 x 64: within 1e-3 of 3 σ, 50 times closer than the largest element mean',
                       errs[2] <= 3e-3 and errs[2] * 50 <= emean[2], '%.2e σ (element mean %.2e σ)' % (errs[2], emean[2]))


uniform()
plastic()
kirsch()
