"""VON_MISES with KINEMATICS LARGE: the J2 law on the Green-Lagrange strain E and the second
Piola-Kirchhoff stress S (large rotations, small strains: code_aster's GROT_GDEP), issue 15 item 1's
finite-strain plasticity of the continuum. docs/large-displacements.md.

- The model's definition, at a point: one element in a homogeneous plastic state reached from the
  reference (INITIAL DISPLACEMENT: a stretch diag(1.3, 0.9) turned by 90 degrees) has the stored
  energy, path work, stress and plastic strain of the small-strain law at the strain E (a SMALL run
  with the displacement E X), to 1e-12: QUAD4, QUAD8, TRI3 and TRI6, plane strain and plane stress.
  The rotation leaves no trace (objectivity).
- No yield: VON_MISES with YIELD 1e30 = ELASTIC (St Venant-Kirchhoff) on the ring of
  inputs/ring_impact.dat, to 1e-12 (the same S, the same S̄ of the step, the same iterates).
- Small amplitude: LARGE = SMALL to 1e-6 on the plastic patch of tests/scenes/zone (load and yield
  scaled down to strains of 1e-8), and the difference grows as the amplitude (geometric terms of
  order the strain): x 10 amplitude, x 10 difference (8 to 12).
- The plastic patch LARGE inside the SMALL elastic block: SCHEME ZONE ON (Newton on the patch's equations
  through Woodbury) = ZONE OFF to 1e-8 (the iteration tolerance).
- spinning_plastic.dat: a free square yielding under its centrifugal stress keeps angular momentum
  (1e-10), linear momentum and kinetic + stored + plastic work (|balance| <= 1e-10 of E).
- inputs/ring_plastic.dat: an elastic-plastic ring thrown at a wall at 10 m/s: |balance| <= 1e-10 of E at
  h and 5 h, the wall never crossed, y and angular momentum zero by symmetry, more than half the
  energy dissipated, the ring leaving slower than it came; ENERGY_CORRECTION OFF loses more than 1e-3
  of E there (measured 1.3e-2); a restart from a checkpoint continues bit for bit.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

HERE = os.path.relpath(os.path.dirname(os.path.abspath(__file__)), sc.ROOT)
A, B = 0.3, -0.1                                   # the stretch diag(1 + A, 1 + B)
EA, EB = A + A * A / 2, B + B * B / 2              # its Green-Lagrange strain


def fields0(out):
    import h5py
    with h5py.File(os.path.join(out, 'fields.h5'), 'r') as f:
        return {k: f['step_000000/' + k][()] for k in ('stress', 'plastic_strain')}


def point_state(kind, plane):
    """(LARGE turned, SMALL at E): their histories' first rows and t = 0 fields."""
    turned = sc.one_element('one_%s_LARGE_%s.dat' % (kind, plane), kind, 'KINEMATICS LARGE PLANE ' + plane,
                            lambda x, y: (-(1 + B) * y - x, (1 + A) * x - y))
    small = sc.one_element('one_%s_SMALL_%s.dat' % (kind, plane), kind, 'KINEMATICS SMALL PLANE ' + plane,
                           lambda x, y: (EA * x, EB * y))
    return [(sc.history(o), fields0(o)) for o in (sc.run_ok(turned), sc.run_ok(small))]


# --- the model at a point: LARGE turned = SMALL at E -------------------------------------------------
for kind in sc.ELEMENT_KINDS:
    for plane in ('STRAIN', 'STRESS'):
        (hl, fl), (hs, fs) = point_state(kind, plane)
        err = max(abs(hl[k][0] - hs[k][0]) / abs(hs[k][0]) for k in ('internal', 'stored'))
        err = max(err, np.max(np.abs(fl['stress'] - fs['stress'])) / np.max(np.abs(fs['stress'])))
        err = max(err, np.max(np.abs(fl['plastic_strain'] - fs['plastic_strain'])) / np.max(fs['plastic_strain']))
        plastic = hs['internal'][0] - hs['stored'][0]
        sc.report_measured('%s plane %s, stretched plastically and turned by 90 degrees: work, stored energy, S and plastic '
                  'strain = the small-strain law at E (1e-12)' % (kind, plane.lower()),
                  err <= 1e-12 and plastic > 0.1 * hs['internal'][0],
                  'difference %.2e, plastic work %.3g of %.3g' % (err, plastic, hs['internal'][0]))

# --- no yield: VON_MISES = ELASTIC (St Venant-Kirchhoff) ------------------------------------------------
ring = open(os.path.join(sc.ROOT, 'inputs/ring_impact.dat')).read().replace('FILE ring.msh', 'FILE ' +
                                                                            os.path.join(sc.ROOT, 'inputs/ring.msh'))
# (VON_MISES takes FORMULATION BBAR by default on a plane-strain QUAD4, ELASTIC not: both given.)
for form in ('STANDARD', 'BBAR'):
    he = sc.history(sc.run_ok(sc.write_scene('ring_el.dat', ring), ['MODEL.FORMULATION=' + form]))
    hv = sc.history(sc.run_ok(sc.write_scene('ring_vm.dat', ring.replace(
        'rubber ELASTIC YOUNG 1e7 POISSON 0.3 DENSITY 1000', 'rubber VON_MISES YOUNG 1e7 POISSON 0.3 DENSITY 1000 YIELD 1e30')),
        ['MODEL.FORMULATION=' + form]))
    diff = max(np.max(np.abs(he[k] - hv[k])) / np.max(np.abs(he[k])) for k in ('kinetic', 'internal', 'momentum_x'))
    sc.report_measured('ring (LARGE, FORMULATION %s): VON_MISES that never yields = ELASTIC (St Venant-Kirchhoff) to 1e-12'
                       % form, diff <= 1e-12, '%.2e' % diff)

# --- small amplitude: LARGE = SMALL ----------------------------------------------------------------------
patch = open(os.path.join(sc.ROOT, 'tests/scenes/zone/patch_block.dat')).read().replace(
    'FILE patch_block.msh', 'FILE ' + os.path.join(sc.ROOT, 'tests/scenes/zone/patch_block.msh')).replace(
    'FIELDS EVERY 0', 'FIELDS EVERY 400')


def small_large(scale):
    """Max relative difference LARGE - SMALL (work, plastic work, displacements at the end) with the
    load and yield scaled by scale (1: strains of 1e-8)."""
    text = patch.replace('YIELD 5e7', 'YIELD %g' % (500 * scale)).replace('FORCE 0 -16000000', 'FORCE 0 %g' % (-160 * scale))
    large = text.replace('PLANE STRAIN', 'PLANE STRAIN KINEMATICS LARGE')
    outs = [sc.run_ok(sc.write_scene('patch_%s_%g.dat' % (k, scale), t)) for k, t in (('s', text), ('l', large))]
    hs, hl = [sc.history(o) for o in outs]
    d = max(np.max(np.abs(hs[k] - hl[k])) / np.max(np.abs(hs[k])) for k in ('internal', 'dissipated', 'kinetic'))
    import h5py
    us = [h5py.File(os.path.join(o, 'fields.h5'), 'r')['step_000400/displacement'][()] for o in outs]
    return max(d, np.max(np.abs(us[0] - us[1])) / np.max(np.abs(us[0]))), hs['dissipated'][-1]


d1, dis = small_large(1.0)
d10, _ = small_large(10.0)
sc.report_measured('plastic patch at strains of 1e-8: LARGE = SMALL to 1e-6 (and it yields)', d1 <= 1e-6 and dis > 0,
          'difference %.2e, dissipated %.3g' % (d1, dis))
sc.report_measured('the difference LARGE - SMALL grows as the amplitude (x 10: 8 to 12)', 8 <= d10 / d1 <= 12,
          '%.2e / %.2e = %.2f' % (d10, d1, d10 / d1))

# --- the nonlinear zone with a LARGE plastic patch -------------------------------------------------------
zone = patch.replace('MODEL m.soft MATERIAL jm SECTION plate MASS CONSISTENT PLANE STRAIN',
                     'MODEL m.soft MATERIAL jm SECTION plate MASS CONSISTENT PLANE STRAIN KINEMATICS LARGE')
hz = {z: sc.history(sc.run_ok(sc.write_scene('zone_%s.dat' % z, zone), ['SCHEME.ZONE=' + z, 'SCHEME.ITERATION=TANGENT']))
      for z in ('ON', 'OFF')}
dz = max(np.max(np.abs(hz['ON'][k] - hz['OFF'][k])) / np.max(np.abs(hz['OFF'][k]))
         for k in ('kinetic', 'internal', 'dissipated'))
sc.report_measured('LARGE von Mises patch in a SMALL elastic block: SCHEME ZONE ON (Newton through Woodbury) = OFF to 1e-8, '
       'and it yields', dz <= 1e-8 and hz['ON']['dissipated'][-1] > 0, 'difference %.2e' % dz)

# --- a free spinning square yielding -------------------------------------------------------------------
hsp = sc.history(sc.run_ok(os.path.join(HERE, 'spinning_plastic.dat')))
sc.free_body('spinning von Mises square', hsp, 1e-10)
sc.report_measured('spinning von Mises square: it yields (plastic work > 1 % of the largest stored energy)',
          hsp['dissipated'][-1] > 1e-2 * np.max(hsp['stored']), '%.3g J of %.3g J' % (hsp['dissipated'][-1],
                                                                                    np.max(hsp['stored'])))

# --- the elastic-plastic ring on a wall ----------------------------------------------------------------
scene = 'inputs/ring_plastic.dat'
for step in ('2e-4', '1e-3'):
    out = sc.run_ok(scene, ['TIME.STEP=' + step])
    h, c = sc.history(out), sc.contacts(out)
    e = np.max(h['kinetic'] + h['internal'])
    bal = np.max(np.abs(h['balance'])) / e
    sc.report_measured('plastic ring, h = %s: |balance| <= 1e-10 of E' % step, bal <= 1e-10, '%.2e' % bal)
    sc.report_measured('plastic ring, h = %s: the wall never crossed (1e-12 m)' % step, np.min(c['min_gap']) >= -1e-12,
              '%.2e m' % np.min(c['min_gap']))
    sym = max(np.max(np.abs(h['momentum_y'])), np.max(np.abs(h['angular_momentum']))) / h['momentum_x'][0]
    sc.report_measured('plastic ring, h = %s: y and angular momentum zero by symmetry (1e-9 of m v0)' % step, sym <= 1e-9,
              '%.2e' % sym)
    if step == '2e-4':
        sc.report_measured('plastic ring: more than half the energy dissipated, leaving the wall slower than it came',
                  h['dissipated'][-1] > 0.5 * e and c['active'][-1] == 0 and
                  -0.5 * h['momentum_x'][0] < h['momentum_x'][-1] < 0,
                  'dissipated %.3g of %.3g J, px %.3g -> %.3g' % (h['dissipated'][-1], e, h['momentum_x'][0],
                                                                h['momentum_x'][-1]))
h = sc.history(sc.run_ok(scene, ['SCHEME.ENERGY_CORRECTION=OFF']))
bal = np.max(np.abs(h['balance'])) / np.max(h['kinetic'] + h['internal'])
sc.report_measured('plastic ring, ENERGY_CORRECTION OFF: the balance the correction removes (> 1e-3 of E)', bal > 1e-3,
          '%.2e' % bal)


ok, detail = sc.restart_same(scene, ['OUTPUT.CHECKPOINT=50', 'OUTPUT.FIELDS=0'], '0.012',
                              ('history.csv', 'contacts.csv'))
sc.report_measured('plastic ring: a restart from the checkpoint of step 50 continues bit for bit (history, contacts)', ok, detail)
