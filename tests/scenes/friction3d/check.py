"""Coulomb friction in 3D (issue 33): the cone is the circle |Λ_T| <= μ Λ_N, not a pyramid
(src/contact/coulomb_cone.f90, docs/contact.md "Friction in 3D"). Every case checks the energy
balance with history.csv's friction_dissipated (<= 1e-10 of the energy) and that the friction's
account never falls.

- a point mass sliding on a horizontal rough floor with an initial velocity across a tilted gravity
  (g_t = 2 m/s² along x, the mass thrown along y at 3 m/s, μ = 0.3): the friction, always opposite
  to the velocity, bends its path. Against the ODE m v' = m g_t - μ m g_n v/|v| (scipy, 1e-13):
  positions within 1e-8 m at h = 2.5e-4 s, second order in h (a faceted cone would hold the force
  on a facet's normal and miss the path at first order);
- a point mass on a rough incline whose normal is off the grid, (-0.4, 0.3, 0.866): slides down the
  line of steepest descent by ½ g (sin θ - μ cos θ) t² to 1e-12, dissipating μ m g cos θ s; with
  μ > tan θ it sticks (<= 1e-12 m over 1e5 steps);
- a point mass hitting a rough floor with a tangential velocity off the axes, in every impact mode,
  RESTITUTION 1 and 0.5 (SYMMETRIC: 1), v_t large and small: the rigid Coulomb impact, v_t' = v_t (1 - μ (1 + e)
  v_n / |v_t|) or 0, v_n' = e v_n (1e-12), the tangential energy lost booked as friction;
  frictionless, v_t kept;
- two free point masses colliding obliquely through a rough node-to-node GAP … PAIRS: the two-body
  Coulomb impact (1e-12) and the three momenta kept;
- a parcel thrown across a conveyor belt moving diagonally (OBSTACLE … VELOCITY 1.2 0.9 0): its
  velocity relative to the belt falls along its own direction at μ g (positions to 1e-12 m) until it
  rides the belt at V exactly; the friction dissipated ½ m |w0|² (1e-12);
- an elastic HEX8 block sliding on a rough floor: the floor's tangential impulse never leaves the
  circle μ × the normal one; the block's horizontal momenta change by exactly the contact's
  tangential impulses; the friction opposes the sliding direction;
- large zones on the augmented sparse system (MULTIPLIERS AUGMENTED: the directions by a fixed
  point) give the Schur block's Newton answer: the sliding block to 1e-10, the bent path of the
  point mass within 1e-8 m of the ODE;
- a HEX8 block resting on a rough floor (μ 1.5) under a gravity tilted off the grid, from a STATIC
  preload (Coulomb's law on the preload's increments): it stays at its sheared equilibrium (base
  corners <= 1e-15 m over 5000 steps, kinetic energy <= 1e-25 J);
- a restart from a checkpoint while the point mass slides continues bit for bit (the slip's
  direction is part of the checkpoint);
- bad input in 3D: a negative or infinite FRICTION, FRICTION under IMPACT MASSLESS, a 2D velocity
  for a 3D point mass: exit 2 naming file:line and the word.
"""
import os
import sys

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

HERE = 'tests/scenes/friction3d/'
G = 9.81


def energy_checks(tag, out, floor=0.0):
    """The balance and the friction's account (floor: an energy scale where nothing moves)."""
    hist = sc.history(out)
    scale = max(np.abs(hist['kinetic'] + hist['internal']).max(), np.abs(hist['external']).max(), floor)
    bal = np.abs(hist['balance']).max() / scale
    sc.report_measured(tag + ': |balance| <= 1e-10 of the energy, friction booked', bal <= 1e-10, '%.2e' % bal)
    dfr = np.diff(hist['friction_dissipated'])
    sc.report(tag + ': friction_dissipated never falls', dfr.min() >= -1e-14 * scale, 'min step %.2e J' % dfr.min())
    return hist


def sliding_path():
    """The tilted-gravity slide against the ODE, at three steps."""
    mu, gx = 0.3, 2.0

    def rhs(t, y):
        s = np.hypot(y[2], y[3])
        return [y[2], y[3], gx - mu * G * y[2] / s, -mu * G * y[3] / s]
    errs = {}
    for h in [1e-3, 5e-4, 2.5e-4]:
        out = sc.run_ok(HERE + 'slide.dat', ['TIME.STEP=%r' % h])
        if h == 2.5e-4:
            hist = energy_checks('sliding point mass', out)
        pr = sc.probes(out)
        t = pr['time']
        ref = solve_ivp(rhs, [0.0, t[-1]], [0.0, 0.0, 0.0, 3.0], t_eval=t, rtol=1e-13, atol=1e-14, method='DOP853')
        errs[h] = max(np.abs(pr['ball.UX'] - ref.y[0]).max(), np.abs(pr['ball.UY'] - ref.y[1]).max())
        if h == 2.5e-4:
            sc.report('sliding point mass: off the floor never (UZ = 0)', np.abs(pr['ball.UZ']).max() <= 1e-15,
                      '%.2e m' % np.abs(pr['ball.UZ']).max())
            v = np.hypot(pr['ball.VX'], pr['ball.VY'])
            path = np.sum(0.5 * (v[1:] + v[:-1]) * np.diff(t))
            sc.close('sliding point mass: friction_dissipated = mu m g x its path (1e-6)', hist['friction_dissipated'][-1],
                     mu * 2.0 * G * path, 1e-6)
    sc.report_measured('sliding point mass: the bent path within 1e-8 m of the ODE at h = 2.5e-4 s', errs[2.5e-4] <= 1e-8,
              '%.2e m (h = 1e-3: %.2e, 5e-4: %.2e)' % (errs[2.5e-4], errs[1e-3], errs[5e-4]))
    order = np.log2(errs[1e-3] / errs[5e-4]), np.log2(errs[5e-4] / errs[2.5e-4])
    sc.report_measured('sliding point mass: second order in h (1.9 .. 2.1)', all(1.9 <= o <= 2.1 for o in order),
              'orders %.3f, %.3f' % order)


def incline():
    n = np.array([-0.4, 0.3, 0.8660254037844386])
    n = n / np.linalg.norm(n)
    th = np.arccos(n[2])
    out = sc.run_ok(HERE + 'incline.dat')
    hist = energy_checks('incline, mu 0.3', out)
    pr = sc.probes(out)
    u = np.c_[pr['ball.UX'], pr['ball.UY'], pr['ball.UZ']]
    s = np.linalg.norm(u, axis=1)
    s_exact = 0.5 * G * (np.sin(th) - 0.3 * np.cos(th)) * pr['time'] ** 2
    err = np.abs(s - s_exact).max() / s_exact.max()
    sc.report_measured('incline, mu 0.3: slides by 1/2 g (sin - mu cos) t^2 (1e-12)', err <= 1e-12, 'relative error %.2e' % err)
    down = np.array([0.0, 0.0, -1.0]) - np.dot([0.0, 0.0, -1.0], n) * n
    dev = np.linalg.norm(u[-1] / s[-1] - down / np.linalg.norm(down))
    sc.report_measured('incline, mu 0.3: along the line of steepest descent (1e-12)', dev <= 1e-12, '%.2e' % dev)
    sc.close('incline, mu 0.3: friction_dissipated = mu m g cos s (1e-12)', hist['friction_dissipated'][-1],
             0.3 * 2.0 * G * np.cos(th) * s_exact[-1], 1e-12)
    out = sc.run_ok(HERE + 'incline.dat', ['OBSTACLE.FRICTION=0.7', 'TIME.END=100', 'OUTPUT.HISTORY=1000'])
    hist = energy_checks('incline, mu 0.7', out, floor=2.0 * G * 1.0)
    pr = sc.probes(out)
    umax = np.abs(np.c_[pr['ball.UX'], pr['ball.UY'], pr['ball.UZ']]).max()
    sc.report_measured('incline, mu 0.7: sticks over 1e5 steps (<= 1e-12 m)', umax <= 1e-12, '%.2e m' % umax)


def oblique_impacts():
    mu = 0.3
    for mode in ['AUTO', 'PAPER', 'PERSIST', 'SYMMETRIC']:
        for vt in [(1.2, -0.9), (0.12, 0.09)]:
            for e in ([1.0] if mode == 'SYMMETRIC' else [1.0, 0.5]):   # (SYMMETRIC: elastic only)
                tag = 'rough floor %s, v_t (%g, %g), e %g' % (mode, vt[0], vt[1], e)
                sets = ['INITIAL.VELOCITY=%r %r -1' % vt, 'SCHEME.IMPACT=' + mode, 'OBSTACLE.RESTITUTION=%r' % e]
                out = sc.run_ok(HERE + 'hit.dat', sets)
                hist = energy_checks(tag, out)
                pr = sc.probes(out)
                w = np.array(vt)
                after = w * max(1.0 - mu * (1.0 + e) / np.linalg.norm(w), 0.0)
                got = np.array([pr['ball.VX'][-1], pr['ball.VY'][-1]])
                sc.report_measured(tag + ": v_t' of the rigid Coulomb impact (1e-12)", np.abs(got - after).max() <= 1e-12,
                          '%.2e m/s (%s vs %s)' % (np.abs(got - after).max(), got, after))
                sc.report(tag + ": v_n' = e v_n (1e-12)", abs(pr['ball.VZ'][-1] - e) <= 1e-12, '%.15f' % pr['ball.VZ'][-1])
                sc.close(tag + ': dissipated = tangential energy lost (1e-12)', hist['friction_dissipated'][-1],
                         0.5 * 2.0 * (w @ w - after @ after), 1e-12)
                ct = sc.contacts(out)
                over = (np.hypot(ct['impulse_x'], ct['impulse_y']) - mu * ct['impulse_z']).max()
                sc.report(tag + ': tangential impulse inside the circle every step', over <= 1e-15, 'excess %.2e' % over)
        out = sc.run_ok(HERE + 'hit.dat', ['OBSTACLE.FRICTION=0', 'SCHEME.IMPACT=' + mode])
        pr = sc.probes(out)
        err = max(abs(pr['ball.VX'][-1] - 1.2), abs(pr['ball.VY'][-1] + 0.9))
        sc.report('rough floor %s frictionless: v_t kept (1e-12)' % mode, err <= 1e-12, '%.2e' % err)


def pair():
    n = np.array([0.0, 0.6, 0.8])
    va, vb, ma, mb = np.array([2.0, 1.0, 0.5]), np.array([-1.0, -1.0, -0.7]), 1.0, 3.0
    ms = ma * mb / (ma + mb)
    vr = vb - va
    vn = vr @ n
    wt = vr - vn * n
    pn = -2.0 * ms * vn
    pt = min(0.25 * pn, ms * np.linalg.norm(wt))
    p = pn * n - pt * wt / np.linalg.norm(wt)           # the impulse on b
    for mode in ['AUTO', 'PAPER', 'SYMMETRIC']:
        tag = 'GAP PAIRS 3D %s' % mode
        out = sc.run_ok(HERE + 'pair.dat', ['SCHEME.IMPACT=' + mode])
        hist = energy_checks(tag, out)
        pr = sc.probes(out)
        got_a = np.array([pr['a.V' + c][-1] for c in 'XYZ'])
        got_b = np.array([pr['b.V' + c][-1] for c in 'XYZ'])
        err = max(np.abs(got_a - (va - p / ma)).max(), np.abs(got_b - (vb + p / mb)).max())
        sc.report_measured(tag + ': the two-body Coulomb impact (1e-12)', err <= 1e-12, '%.2e' % err)
        for k in ['momentum_x', 'momentum_y', 'momentum_z']:
            drift = np.abs(hist[k] - hist[k][0]).max()
            sc.report(tag + ': %s kept (1e-12)' % k, drift <= 1e-12, '%.2e' % drift)


def belt():
    out = sc.run_ok(HERE + 'belt.dat')
    hist = energy_checks('conveyor belt', out)
    pr = sc.probes(out)
    V = np.array([1.2, 0.9])
    w0 = np.array([0.0, -1.0]) - V
    a = 0.4 * G
    ts = np.linalg.norm(w0) / a
    d = w0 / np.linalg.norm(w0)
    t = pr['time']
    x = np.c_[pr['p.UX'], pr['p.UY']]
    v = np.c_[pr['p.VX'], pr['p.VY']]
    before = t < ts - 1e-3
    x_ex = w0 * t[:, None] - 0.5 * a * t[:, None] ** 2 * d + V * t[:, None]
    err = np.abs(x - x_ex)[before].max()
    sc.report_measured('conveyor belt: the relative velocity falls along itself at mu g (1e-12 m)', err <= 1e-12, '%.2e m' % err)
    err = np.abs(v[t > ts + 1e-3] - V).max()
    sc.report('conveyor belt: rides the belt at V once stuck (exactly)', err == 0.0, '%.2e m/s' % err)
    sc.close('conveyor belt: friction dissipated 1/2 m |w0|^2 (1e-12)', hist['friction_dissipated'][-1],
             0.5 * 2.0 * (w0 @ w0), 1e-12)


def block():
    out = sc.run_ok(HERE + 'block_slide.dat', ['SCHEME.IMPACT=SYMMETRIC'])
    hist = energy_checks('HEX8 block sliding', out)
    ct = sc.contacts(out)
    over = (np.hypot(ct['impulse_x'], ct['impulse_y']) - 0.3 * ct['impulse_z']).max()
    sc.report_measured('HEX8 block sliding: tangential impulse inside the circle every step', over <= 1e-15, 'excess %.2e' % over)
    for k, c in [('momentum_x', 'impulse_x'), ('momentum_y', 'impulse_y')]:
        err = np.abs((hist[k] - hist[k][0]) - np.cumsum(ct[c])).max() / np.hypot(hist['momentum_x'][0], hist['momentum_y'][0])
        sc.report('HEX8 block sliding: %s changes by the contact impulses only (1e-13 of the momentum)' % k, err <= 1e-13,
                  '%.2e' % err)
    m = ct['impulse_z'] > 0.0
    ang = np.arctan2(ct['impulse_y'][m], ct['impulse_x'][m]) - np.arctan2(-0.8, -0.6)
    # (the base nodes' slips turn with the block's vibrations: 6.7e-4 rad measured)
    sc.report_measured('HEX8 block sliding: the friction opposes the sliding direction (1e-3 rad)', np.abs(ang).max() <= 1e-3,
              '%.2e rad' % np.abs(ang).max())
    sc.report('HEX8 block sliding: slows down', hist['momentum_x'][-1] < hist['momentum_x'][0],
              '%.4f -> %.4f N s' % (hist['momentum_x'][0], hist['momentum_x'][-1]))


def augmented():
    out = sc.run_ok(HERE + 'block_slide.dat', ['SCHEME.IMPACT=SYMMETRIC'])
    aug = sc.run_ok(HERE + 'block_slide.dat', ['SCHEME.IMPACT=SYMMETRIC', 'SCHEME.MULTIPLIERS=AUGMENTED'])
    a, b = sc.history(out), sc.history(aug)
    err = max(np.abs(a[k] - b[k]).max() / np.abs(a[k]).max() for k in ['kinetic', 'friction_dissipated', 'momentum_x',
                                                                          'momentum_y'])
    sc.report_measured('HEX8 block sliding: the augmented fixed point = the Schur Newton (1e-10)', err <= 1e-10, '%.2e' % err)
    mu, gx = 0.3, 2.0

    def rhs(t, y):
        s = np.hypot(y[2], y[3])
        return [y[2], y[3], gx - mu * G * y[2] / s, -mu * G * y[3] / s]
    pr = sc.probes(sc.run_ok(HERE + 'slide.dat', ['SCHEME.MULTIPLIERS=AUGMENTED']))
    t = pr['time']
    ref = solve_ivp(rhs, [0.0, t[-1]], [0.0, 0.0, 0.0, 3.0], t_eval=t, rtol=1e-13, atol=1e-14, method='DOP853')
    err = max(np.abs(pr['ball.UX'] - ref.y[0]).max(), np.abs(pr['ball.UY'] - ref.y[1]).max())
    sc.report_measured('sliding point mass, MULTIPLIERS AUGMENTED: within 1e-8 m of the ODE', err <= 1e-8, '%.2e m' % err)


def block_static():
    out = sc.run_ok(HERE + 'block_static.dat')
    hist = sc.history(out)
    pr = sc.probes(out)
    umax = max(np.ptp(pr[k]) for k in ['c1.UX', 'c1.UY', 'c2.UX', 'c2.UY'])
    sc.report_measured('HEX8 block from STATIC on a rough floor, mu 1.5: rests (corners <= 1e-15 m)', umax <= 1e-15,
                       '%.2e m' % umax)
    sc.report_measured('HEX8 block from STATIC on a rough floor, mu 1.5: kinetic energy <= 1e-25 J',
                       hist['kinetic'].max() <= 1e-25, '%.2e J' % hist['kinetic'].max())


def restart():
    same, detail = sc.restart_same(HERE + 'slide.dat', ['TIME.END=0.5', 'OUTPUT.CHECKPOINT=100'], '0.25',
                                   files=('history.csv', 'contacts.csv', 'probes.csv'))
    sc.report('sliding point mass: a restart from the checkpoint continues bit for bit', same, detail)


def bad_inputs():
    head = ('DIMENSION 3\nNODE ball AT 0 0 0\nELEMENT pm TYPE MASS NODES ball\nSECTION m1 MASS 2\n'
            'MODEL pm SECTION m1\nTIME STEP 1e-3 END 1e-2\n')
    floor = 'OBSTACLE floor NODES ball POINT 0 0 0 NORMAL 0 0 1'
    cases = [('negative FRICTION', floor + ' FRICTION -0.1\n', 'OBSTACLE floor', '-0.1'),
             ('FRICTION not finite', floor + ' FRICTION inf\n', 'OBSTACLE floor', 'inf'),
             ('FRICTION with IMPACT MASSLESS', floor + ' FRICTION 0.3\nSCHEME IMPACT MASSLESS\n', 'OBSTACLE floor',
              'FRICTION'),
             ('a 2D velocity on a 3D point mass', 'INITIAL ball VELOCITY 0 3\n', 'INITIAL', 'VELOCITY')]
    for name, bad, stmt, word in cases:
        path = sc.write_scene('friction3d_bad.dat', head + bad)
        outdir = os.path.join(sc.new_dir('friction3d_bad'), 'never')
        rc, err, _ = sc.run(path, outdir=outdir)
        msg = ' '.join(sc.message_lines(err))
        ok = rc == 2 and 'friction3d_bad.dat:7:' in msg and stmt in msg and ("'%s'" % word) in msg
        sc.report('bad input 3D, %s: exit 2, file:line, the statement and the word' % name, ok,
                  'exit %d: %s' % (rc, msg[-300:]))


if __name__ == '__main__':
    sliding_path()
    incline()
    oblique_impacts()
    pair()
    belt()
    block()
    augmented()
    block_static()
    restart()
    bad_inputs()
