"""MODES n [ABOVE f0] (issue 35, item 1; docs/input.md, "Modes"; docs/modes.md): natural frequencies
and mode shapes of the supported structure, K0 φ = ω² M φ, written to modes.csv and modes.h5/xmf.

- a BEAM2 cantilever (steel, 10 x 10 mm, 1 m): the first four frequencies against Euler-Bernoulli,
  (β_i L)² / 2π sqrt(EI / (ρ A L⁴)), by LAPACK's dense solver (20 elements, 60 equations) and by
  ARPACK's shift-invert Lanczos with CHOLMOD (100 elements, 300 equations); the first mode's
  effective mass 61.3 % of the beam's (Euler-Bernoulli), the shapes scaled to a largest translation
  of 1, every mode's residual |K0 φ - ω² M φ| below 1e-6 of its terms (ARPACK converges the
  eigenvalues of (K0 - σM)⁻¹M to machine precision; measured 1e-11 and 4e-8); ABOVE f0 gives the modes
  above f0 only;
- a QUAD8 cantilever in plane stress (L/h = 20): the first frequency within 0.5 % of Euler-Bernoulli
  (shear and rotary inertia lower it by about 0.1 %); free-free, the frequencies converge with the
  mesh at the element's order, h^4 (the clamp's singular corners slow the cantilever's to about h^1.5);
- a free body: its rigid modes found as zeros (3 in the plane, 1 for an axisymmetric ring), and the
  effective masses of those rigid modes the body's mass in each direction;
- a scene of MODES alone (TIME END = START) writes the modes and no history; the run report takes
  its lowest frequency from the first mode.
"""
import os
import re
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

E, RHO, A, I, L = 2.1e11, 7800.0, 1e-4, 1e-8 / 12, 1.0
BL = np.array([1.875104068711961, 4.694091132974175, 7.854757438237613, 10.995540734875467])
EB = BL ** 2 / (2 * np.pi) * np.sqrt(E * I / (RHO * A * L ** 4))

BEAM = sc.write_scene('beam_modes.dat', """
LINE      beam FROM 0 0 TO 1 0 ELEMENTS 20 TYPE BEAM2
MATERIAL  steel ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800
SECTION   s AREA 1e-4 INERTIA 8.3333333333333333e-10
MODEL     beam MATERIAL steel SECTION s
FIX       beam.start ALL
MODES     4
TIME      STEP 1e-4 END 0
""")


def modes(out):
    return sc.read_csv(os.path.join(out, 'modes.csv'))


for n, path in ((20, 'LAPACK'), (100, 'ARPACK')):
    code, err, out = sc.run(BEAM, ['LINE.ELEMENTS=%d' % n])
    sc.report('BEAM2 cantilever, %d elements: runs' % n, code == 0, err)
    if code != 0:
        continue
    m = modes(out)
    e = np.abs(m['frequency'] / EB - 1)
    sc.report_measured('BEAM2 cantilever, %d elements (%s): f1..f4 within 2e-4 of Euler-Bernoulli' % (n, path),
                       len(m['frequency']) == 4 and np.max(e) <= 2e-4,
                       ', '.join('%.6g Hz (%+.1e)' % (f, x) for f, x in zip(m['frequency'], m['frequency'] / EB - 1)))
    total = RHO * A * L
    sc.report_measured('BEAM2 cantilever, %d elements: mode 1 carries 61.3 %% of the mass along y (0.5 %%)' % n,
                       abs(m['effective_mass_y'][0] / total - 0.6131) <= 0.005, '%.4f' % (m['effective_mass_y'][0] / total))
    sc.close('BEAM2 cantilever, %d elements: period = 1/frequency' % n, m['period'][0], 1 / m['frequency'][0], 1e-15)
    with h5py.File(os.path.join(out, 'modes.h5'), 'r') as f:
        steps = sorted(k for k in f if k.startswith('step_'))
        u = np.array(f[steps[0]]['displacement'])
    sc.report('BEAM2 cantilever, %d elements: modes.h5 holds the 4 shapes, the first scaled to a largest '
              'translation of 1' % n, len(steps) == 4 and abs(np.max(np.abs(u[:, :2])) - 1) <= 1e-15 and
              os.path.exists(os.path.join(out, 'modes.xmf')) and not os.path.exists(os.path.join(out, 'history.csv')),
              '%d steps, max |u| %.17g' % (len(steps), np.max(np.abs(u[:, :2]))))

code, err, out = sc.run(BEAM, ['LINE.ELEMENTS=100', 'MODES.ABOVE=100'])
m = modes(out) if code == 0 else {'frequency': np.zeros(0)}
sc.report_measured('BEAM2 cantilever: MODES 4 ABOVE 100 (ARPACK) gives modes 3 to 6 (f3, f4 of '
                   'Euler-Bernoulli to 2e-4)', code == 0 and len(m['frequency']) == 4 and m['frequency'][0] > 100 and
                   np.max(np.abs(m['frequency'][:2] / EB[2:] - 1)) <= 2e-4, ', '.join('%.6g' % f for f in m['frequency']))

said = sc.run_limited([sc.REBOND, BEAM, '-o', sc.new_dir()], 60, cwd=sc.ROOT, text=True).stdout
sc.report('the run report takes its lowest frequency from the first mode', 'lowest 8.382 Hz' in said and
          'modes: 4 by LAPACK' in said, said[-500:])
for n in (20, 100):
    said = sc.run_limited([sc.REBOND, BEAM, '-o', sc.new_dir(), '--set', 'LINE.ELEMENTS=%d' % n], 60, cwd=sc.ROOT,
                          text=True).stdout
    r = re.search(r'largest relative residual +([0-9.E+-]+)', said)
    sc.report_measured('BEAM2 cantilever, %d elements: every mode\'s residual below 1e-6' % n,
                       r is not None and float(r.group(1)) <= 1e-6, r.group(1) if r else said[-300:])

# --- a QUAD8 cantilever in plane stress: EB and convergence at the element's order ----------------
PLATE = sc.write_scene('plate_modes.dat', """
RECTANGLE beam ORIGIN 0 0 SIZE 1 0.05 ELEMENTS 20 1 TYPE QUAD8
MATERIAL  steel ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800
SECTION   s THICKNESS 0.01
MODEL     beam MATERIAL steel SECTION s PLANE STRESS
FIX       beam.left UX UY
MODES     3
TIME      STEP 1e-4 END 0
""")
FREEBEAM = sc.write_scene('freebeam_modes.dat', """
RECTANGLE beam ORIGIN 0 0 SIZE 1 0.05 ELEMENTS 20 1 TYPE QUAD8
MATERIAL  steel ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800
SECTION   s THICKNESS 0.01
MODEL     beam MATERIAL steel SECTION s PLANE STRESS
MODES     6
TIME      STEP 1e-4 END 0
""")
f1 = modes(sc.run_ok(PLATE, ['RECTANGLE.ELEMENTS=80 4']))['frequency'][0]
eb = BL[0] ** 2 / (2 * np.pi) * np.sqrt(E * (0.01 * 0.05 ** 3 / 12) / (RHO * 0.01 * 0.05))
sc.report_measured('QUAD8 cantilever 80 x 4 (L/h = 20): f1 within 0.5 % of Euler-Bernoulli, below it',
                   abs(f1 / eb - 1) <= 5e-3 and f1 < eb, '%.5g Hz vs %.5g (%+.3f %%)' % (f1, eb, 100 * (f1 / eb - 1)))
# The clamp's corners are singular (the frequencies converge there at about h^1.5); free-free, the QUAD8
# frequencies converge at the element's order, h^4 (measured ratios 15.7, 15.5, 15.3).
fq = {}
for nx, ny in ((20, 1), (40, 2), (80, 4)):
    fq[nx] = modes(sc.run_ok(FREEBEAM, ['RECTANGLE.ELEMENTS=%d %d' % (nx, ny)]))['frequency'][3:6]
d1 = np.abs(fq[20] - fq[40])
d2 = np.abs(fq[40] - fq[80])
sc.report_measured('QUAD8 free-free beam: its first three elastic frequencies converge at the element\'s order, h^4 '
                   '(each change at least 12 times smaller as h halves)', np.all(d2 * 12 <= d1),
                   'ratios ' + ', '.join('%.1f' % r for r in d1 / d2))
ebf = 4.730040744862704 ** 2 / (2 * np.pi) * np.sqrt(E * (0.01 * 0.05 ** 3 / 12) / (RHO * 0.01 * 0.05))
sc.report_measured('QUAD8 free-free beam 80 x 4: f1 within 1.5 % of Euler-Bernoulli, below it (shear, rotary inertia)',
                   abs(fq[80][0] / ebf - 1) <= 0.015 and fq[80][0] < ebf, '%.5g Hz vs %.5g' % (fq[80][0], ebf))

# --- free bodies: the rigid modes as zeros -------------------------------------------------------------
FREE = sc.write_scene('free_modes.dat', """
RECTANGLE blk ORIGIN 0 0 SIZE 0.4 0.1 ELEMENTS 8 2 TYPE QUAD4
MATERIAL  steel ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800
SECTION   s THICKNESS 0.01
MODEL     blk MATERIAL steel SECTION s
MODES     5
TIME      STEP 1e-4 END 0
""")
m = modes(sc.run_ok(FREE))
f = m['frequency']
sc.report_measured('plane free block: 3 rigid modes at 0 Hz (below 1e-6 of the first elastic one), the 4th elastic',
                   np.all(f[:3] <= 1e-6 * f[3]) and f[3] > 0, ', '.join('%.3g' % x for x in f))
mass = 7800 * 0.4 * 0.1 * 0.01
sc.close('plane free block: the rigid modes carry the mass along x', np.sum(m['effective_mass_x'][:3]), mass, 1e-9)
sc.close('plane free block: the rigid modes carry the mass along y', np.sum(m['effective_mass_y'][:3]), mass, 1e-9)
RING = sc.write_scene('ring_modes.dat', """
RECTANGLE blk ORIGIN 0.2 0 SIZE 0.4 0.1 ELEMENTS 8 2 TYPE QUAD8
MATERIAL  steel ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800
MODEL     blk MATERIAL steel AXISYMMETRIC
MODES     3
TIME      STEP 1e-4 END 0
""")
m = modes(sc.run_ok(RING))
f = m['frequency']
sc.report_measured('axisymmetric free ring: 1 rigid mode (the axial translation), then elastic ones',
                   f[0] <= 1e-6 * f[1] and f[1] > 0 and np.all(m['effective_mass_x'] == 0),
                   ', '.join('%.3g' % x for x in f))
sc.close('axisymmetric free ring: the axial mode carries the ring\'s mass', m['effective_mass_y'][0],
         7800 * np.pi * (0.6 ** 2 - 0.2 ** 2) * 0.1, 1e-9)
