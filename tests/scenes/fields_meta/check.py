"""fields.h5 describes itself (issue 13, item 6): component names and units on every dataset,
the element types by name, the stress columns of each type, the scene's groups.

Read with h5py on the cantilever (BEAM2, groups beam, beam.start, …) and on the bar impact
(contact reactions). On the J2 block (QUAD4, VON_MISES): the von_mises dataset is the von Mises
stress of the element's stress to 1e-12, plastic_strain the element mean of the equivalent
plastic strain (>= 0, > 0 where the block yielded, 0 where von_mises stayed below the yield
stress), both with units; fields.xmf names the stress columns sigma_xx … sigma_xy as hyperslabs
of the stress dataset (column k of it), and the cell scalars von_mises and plastic_strain.
"""
import os
import sys

import h5py

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402


def text(x):
    return x.decode() if isinstance(x, bytes) else str(x)


def cantilever():
    out = sc.run_ok('inputs/cantilever_release.dat', ['TIME.END=2e-3', 'OUTPUT.FIELDS=10'])
    with h5py.File(os.path.join(out, 'fields.h5'), 'r') as f:
        names = [text(x) for x in f['mesh/element_type_names'][()]]
        sc.report('element type codes named', names == ['MASS', 'SPRING', 'BAR2', 'BEAM2', 'QUAD4', 'QUAD8', 'TRI3',
                                                        'TRI6', 'HEX8', 'TET4', 'HEX20', 'TET10', 'WEDGE6'], str(names))
        codes = set(int(c) for c in f['mesh/element_type'][()])
        sc.report('the cantilever is BEAM2 by name', [names[c - 1] for c in codes] == ['BEAM2'], str(codes))
        comps = [text(x) for x in f['mesh/stress_components'][()]]
        sc.report('stress columns of BEAM2: N and M with units', comps[3].startswith('BEAM2: N') and '(bending moment, N m)'
                  in comps[3], comps[3])
        groups = f['groups/nodes']
        sc.report('node groups, 0-based: beam.start = [0], beam.end = [20]',
                  list(groups['beam.start'][()]) == [0] and list(groups['beam.end'][()]) == [20] and
                  len(groups['beam'][()]) == 21, str(list(groups.keys())))
        sc.report('element group beam: 20 elements, 0-based', list(f['groups/elements/beam'][()]) == list(range(20)), '')
        steps = sorted(k for k in f if k.startswith('step_'))
        want = {'displacement': ('ux uy uz', 'm'), 'rotation': ('rz', 'rad'), 'velocity': ('vx vy vz', 'm/s'),
                'angular_velocity': ('wz', 'rad/s')}
        ok = all(tuple(text(f[s][d].attrs[a]) for a in ('components', 'units')) == cu
                 for s in steps for d, cu in want.items())
        ok = ok and all('stress_components' in text(f[s]['stress'].attrs['components']) for s in steps)
        sc.report('every dataset of every step has its components and units (%d steps)' % len(steps), ok and len(steps) > 1,
                  '')


def bar():
    out = sc.run_ok('inputs/bar_impact.dat', ['TIME.END=2e-5', 'OUTPUT.FIELDS=5'])
    with h5py.File(os.path.join(out, 'fields.h5'), 'r') as f:
        s = sorted(k for k in f if k.startswith('step_'))[-1]
        r, m = f[s]['reaction'].attrs, f[s]['reaction_moment'].attrs
        sc.report('contact reactions described: fx fy fz in N, mz in N m',
                  (text(r['components']), text(r['units']), text(m['components']), text(m['units'])) ==
                  ('fx fy fz', 'N', 'mz', 'N m'), str(dict(r)))


def j2_block():
    import xml.etree.ElementTree as ET
    import numpy as np
    out = sc.run_ok('inputs/block_j2.dat', ['OUTPUT.FIELDS=100'])
    with h5py.File(os.path.join(out, 'fields.h5'), 'r') as f:
        s = sorted(k for k in f if k.startswith('step_'))[-1]
        sig, vm, pe = f[s]['stress'][()], f[s]['von_mises'][()], f[s]['plastic_strain'][()]
        units = (text(f[s]['von_mises'].attrs['units']), text(f[s]['plastic_strain'].attrs['units']))
    x, y, z, t = sig[:, 0], sig[:, 1], sig[:, 2], sig[:, 3]
    ref = np.sqrt(x**2 + y**2 + z**2 - x * y - y * z - z * x + 3 * t**2)
    sc.report('J2 block: von_mises = the von Mises stress of the element stress (1e-12)',
              np.abs(vm - ref).max() <= 1e-12 * ref.max(), '%.3e' % np.abs(vm - ref).max())
    sc.report('J2 block: plastic_strain >= 0, > 0 somewhere (the block yielded)', pe.min() >= 0 and pe.max() > 0,
              '[%.3e, %.3e]' % (pe.min(), pe.max()))
    sc.report('J2 block: units Pa and 1', units[0] == 'Pa' and units[1].startswith('1'), str(units))
    root = ET.parse(os.path.join(out, 'fields.xmf')).getroot()
    grid = root.find('Domain/Grid/Grid')
    names = [a.get('Name') for a in grid.findall('Attribute')]
    ok = all(n in names for n in ['sigma_xx', 'sigma_yy', 'sigma_zz', 'sigma_xy', 'von_mises', 'plastic_strain'])
    cols = []
    with h5py.File(os.path.join(out, 'fields.h5'), 'r') as f:
        s = sorted(k for k in f if k.startswith('step_'))[-1]
        for k, n in enumerate(['sigma_xx', 'sigma_yy', 'sigma_zz', 'sigma_xy']):
            item = [a for a in grid.findall('Attribute') if a.get('Name') == n][0].find('DataItem')
            # Its own dataset (both of ParaView's readers show it), equal to column k of stress.
            cols.append(item.text.strip().endswith('/' + n) and np.array_equal(f[s][n][()], f[s]['stress'][:, k]))
    sc.report('fields.xmf: sigma_xx … sigma_xy are datasets equal to column k of stress, von_mises and '
              'plastic_strain listed', ok and all(cols), str(names))

def resident_set():
    """Field writes at every step do not grow the resident set (issue 37, item 10): HDF5 kept about
    0.65 kB a written step (fields.h5 is now closed and opened again every 1000 writes). The
    maximum resident set of 2000 and 6000 writes of the cantilever, from the kernel (wait4)."""
    import subprocess
    rss = {}
    for n, end in ((2000, 0.2), (6000, 0.6)):
        out = sc.new_dir('rss')
        p = subprocess.Popen([sc.REBOND, 'inputs/cantilever_release.dat', '-o', out, '--quiet', '--set',
                              'TIME.END=%g' % end, '--set', 'OUTPUT.FIELDS=EVERY 1', '--set', 'OUTPUT.HISTORY=EVERY 100'],
                             cwd=sc.ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        _, status, usage = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
        rss[n] = usage.ru_maxrss
        if p.returncode != 0:
            sc.report('resident set: the run of %d writes' % n, False, 'exit %d' % p.returncode)
            return
    grow = (rss[6000] - rss[2000]) / 4000.0
    sc.report_measured('fields every step: the resident set grows <= 0.25 kB a write (was 0.65)', grow <= 0.25,
                       '%d kB at 2000 writes, %d kB at 6000: %.3f kB a write' % (rss[2000], rss[6000], grow))


cantilever()
bar()
j2_block()
resident_set()


def unmodelled():
    """The TRI3 L-plate of tests/scenes/lplate: its Gmsh boundary lines (BAR2) and corner point
    (MASS) belong to no MODEL and are not written; the 126 triangles are, with their groups."""
    out = sc.run_ok('tests/scenes/lplate/lplate.dat', ['GMSH.FILE=lplate_tri3.msh', 'OUTPUT.FIELDS=200',
                                                       'TIME.END=1e-3'])
    with h5py.File(os.path.join(out, 'fields.h5'), 'r') as f:
        codes = set(int(c) for c in f['mesh/element_type'][()])
        names = [text(x) for x in f['mesh/element_type_names'][()]]
        n = len(f['mesh/element_type'][()])
        s = sorted(k for k in f if k.startswith('step_'))[-1]
        ok = f[s]['stress'].shape == (n, 4) and list(f['groups/elements/lp.plate'][()]) == list(range(n))
    sc.report('cells of no MODEL not written: TRI3 only, stresses and group plate match',
              [names[c - 1] for c in codes] == ['TRI3'] and ok, str(codes))


unmodelled()
