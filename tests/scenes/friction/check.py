"""Coulomb friction (issue 33, 2D): OBSTACLE … FRICTION mu, exact multipliers (docs/contact.md,
"Friction"). Every case checks the energy balance with history.csv's friction_dissipated
(<= 1e-10 of the energy) and that the friction never gives energy back (its account never falls).

- a point mass on a rough incline, at 30° and 17° (the plane's normal off the grid): tan θ > μ
  slides with s(t) = ½ g (sin θ − μ cos θ) t² to round-off (the trapezoid rule is exact for a
  constant acceleration) and friction_dissipated = μ m g cos θ s to 1e-12; tan θ < μ sticks:
  displacement 0 (<= 1e-12 m) over 1e5 steps, nothing dissipated;
- a QUAD4 steel block on an incline (gravity tilted 20°, μ = 0.5, ramped in 50 ms): its contact
  nodes stay stuck (<= 1e-12 m) over 1e5 steps;
- the same block sliding (30°, μ = 0.3, 1 m/s): while the five base nodes slide in contact the
  tangential impulse of every step is exactly -μ times the normal one (Coulomb's facet, 1e-12);
- the stick-slip oscillator (a 2 kg mass on a spring of 8 N/m, μ = 0.1, released at 5.5 Δ,
  Δ = μ m g / k): slip phases end at π/ω, 2π/ω, 3π/ω (to one step) at -3.5 Δ, 1.5 Δ, 0.5 Δ (the
  trapezoid rule's phase error (ω h)²/12 = 3e-5: 2e-4), then it sticks for good at rest (v = 0:
  the stick projection, no alternating velocity); the friction dissipated the spring's energy
  ½ k (x0² - x3²) (1e-5);
- a point mass hitting a rough floor at three angles (v_t / v_n = 3, 1, 0.2), RESTITUTION 1 and
  0.5, IMPACT PAPER and PERSIST: the rigid Coulomb impact, v_t' = v_t - μ (1 + e) v_n or 0 when
  that stops it, v_n' = e v_n, to 1e-12, the friction's dissipation its tangential energy loss,
  the tangential impulse at most μ times the normal one; frictionless, v_t is kept;
- two free point masses (1 and 3 kg) colliding obliquely through GAP … PAIRS FRICTION 0.25: the
  two-body Coulomb impact (normal impulse (1 + e) m* v_n, tangential μ times it) to 1e-12, both
  momenta kept;
- a point mass hitting a free steel block obliquely through GAP … SEGMENTS FRICTION 0.3: both
  momentum components kept to 1e-12, the ball's tangential velocity reduced.
"""
import os
import sys

import subprocess

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

HERE = 'tests/scenes/friction/'
G = 9.81


def energy_checks(tag, out, floor=0.0):
    """The balance and the friction's account; floor: an energy scale for a case where nothing
    moves (a stuck body: kinetic, internal and external work all round-off)."""
    hist = sc.history(out)
    scale = max(np.abs(hist['kinetic'] + hist['internal']).max(), np.abs(hist['external']).max(), floor)
    bal = np.abs(hist['balance']).max() / scale
    sc.report(tag + ': |balance| <= 1e-10 of the energy, friction booked', bal <= 1e-10, '%.2e' % bal)
    dfr = np.diff(hist['friction_dissipated'])
    sc.report(tag + ': friction_dissipated never falls', dfr.min() >= -1e-14 * scale, 'min step %.2e J' % dfr.min())
    return hist


# A point mass on rough inclines (the plane through the origin, normal (-sin θ, cos θ)).
for theta_deg, mu_slide, mu_stick in [(30.0, 0.3, 0.7), (17.0, 0.2, 0.35)]:
    th = np.radians(theta_deg)
    normal = '%r %r' % (float(-np.sin(th)), float(np.cos(th)))
    tag = 'point mass, %g deg, mu %g' % (theta_deg, mu_slide)
    out = sc.run_ok(HERE + 'incline.dat', ['OBSTACLE.NORMAL=' + normal, 'OBSTACLE.FRICTION=%r' % mu_slide])
    hist = energy_checks(tag, out)
    pr = sc.probes(out)
    t = pr['time']
    s = np.hypot(pr['ball.UX'], pr['ball.UY'])
    s_exact = 0.5 * G * (np.sin(th) - mu_slide * np.cos(th)) * t * t
    err = np.abs(s - s_exact).max() / s_exact.max()
    sc.report(tag + ': slides by 1/2 g (sin - mu cos) t^2 (1e-12)', err <= 1e-12, 'relative error %.2e' % err)
    d_exact = mu_slide * 2.0 * G * np.cos(th) * s_exact[-1]
    sc.close(tag + ': friction_dissipated = mu m g cos s (1e-12)', hist['friction_dissipated'][-1], d_exact, 1e-12)
    tag = 'point mass, %g deg, mu %g' % (theta_deg, mu_stick)
    out = sc.run_ok(HERE + 'incline.dat', ['OBSTACLE.NORMAL=' + normal, 'OBSTACLE.FRICTION=%r' % mu_stick,
                                          'TIME.END=100', 'OUTPUT.HISTORY=1000'])
    hist = energy_checks(tag, out, floor=2.0 * G * 1.0)          # (m g x 1 m)
    pr = sc.probes(out)
    umax = np.hypot(pr['ball.UX'], pr['ball.UY']).max()
    sc.report(tag + ': sticks over 1e5 steps (<= 1e-12 m)', umax <= 1e-12, 'largest displacement %.2e m' % umax)
    sc.report(tag + ': nothing dissipated', hist['friction_dissipated'][-1] <= 1e-14, '%.2e J' % hist['friction_dissipated'][-1])

# A QUAD4 block stuck on an incline: the base nodes do not move.
out = sc.run_ok(HERE + 'block_stick.dat')
energy_checks('block on 20 deg, mu 0.5', out, floor=156.0 * G * 0.1)   # (m g x its height)
pr = sc.probes(out)
umax = max(np.abs(pr['block.bottom_left.UX']).max(), np.abs(pr['block.bottom_right.UX']).max())
sc.report('block on 20 deg, mu 0.5: base stuck over 1e5 steps (<= 1e-12 m)', umax <= 1e-12, '%.2e m' % umax)

# The block sliding: Coulomb's facet on every step while the base slides in contact.
out = sc.run_ok(HERE + 'block_slide.dat')
energy_checks('block sliding, 30 deg, mu 0.3', out)
ct = sc.contacts(out)
first_open = int(np.nonzero(ct['active'][1:] < 5)[0][0]) + 1
rows = slice(1, first_open)
ratio = ct['impulse_x'][rows] / ct['impulse_y'][rows]
sc.report('block sliding: %d steps with the base in contact' % (first_open - 1), first_open > 50)
err = np.abs(ratio + 0.3).max()
sc.report('block sliding: tangential impulse = -mu x normal every step (1e-12)', err <= 1e-12, 'max |ratio + mu| %.2e' % err)
sc.report('block sliding: the base slips forward every step', np.all(ct['slip'][rows] < 0.0),
          'slip along t = (-1, 0), summed over the base')

# The stick-slip oscillator.
out = sc.run_ok(HERE + 'oscillator.dat')
hist = energy_checks('stick-slip oscillator', out)
pr = sc.probes(out)
t, x = pr['time'], pr['b.UX']
h, omega, delta, x0 = 0.01, 2.0, 0.1 * 2.0 * G / 8.0, 1.348875
moving = np.nonzero(np.diff(x) != 0.0)[0]
last = t[moving[-1] + 1]
sc.report('oscillator: sticks for good at 3 pi / omega (one step)', abs(last - 3 * np.pi / omega) <= h,
          'last motion at %.4f s, expected %.4f s' % (last, 3 * np.pi / omega))
for k, xk in [(1, -3.5), (2, 1.5), (3, 0.5)]:
    i = int(round(k * np.pi / omega / h))
    win = x[max(i - 2, 0):i + 3]
    xt = win[np.argmax(np.abs(win))] if k < 3 else x[-1]
    sc.close('oscillator: turning point %d at %g delta (2e-4)' % (k, xk), xt / delta, xk, 2e-4)
sc.close('oscillator: friction dissipated the spring energy (1e-5)', hist['friction_dissipated'][-1],
         0.5 * 8.0 * (x0 ** 2 - (0.5 * delta) ** 2), 1e-5)
vrest = np.abs(pr['b.VX'][t > 3 * np.pi / omega + 2 * h]).max()
sc.report('oscillator: at rest once stuck, v = 0 (no alternating velocity)', vrest == 0.0, 'max |v| %.2e m/s' % vrest)

# A point mass hitting a rough floor at three angles.
for mode in ['PAPER', 'PERSIST']:
    for vt in [3.0, 1.0, 0.2]:
        for e in [1.0, 0.5]:
            tag = 'oblique impact %s, vt/vn %g, e %g' % (mode, vt, e)
            sets = ['INITIAL.VELOCITY=%r -1' % vt, 'OBSTACLE.RESTITUTION=%r' % e, 'SCHEME.IMPACT=' + mode]
            out = sc.run_ok(HERE + 'oblique.dat', sets)
            hist = energy_checks(tag, out)
            pr = sc.probes(out)
            after = max(vt - 0.2 * (1 + e), 0.0)
            sc.report(tag + ': rigid Coulomb impact v_t\' (1e-12)', abs(pr['ball.VX'][-1] - after) <= 1e-12,
                      '%.15f vs %.15f' % (pr['ball.VX'][-1], after))
            sc.report(tag + ': v_n\' = e v_n (1e-12)', abs(pr['ball.VY'][-1] - e) <= 1e-12, '%.15f' % pr['ball.VY'][-1])
            sc.close(tag + ': dissipated = tangential energy lost (1e-12)', hist['friction_dissipated'][-1],
                     0.5 * (vt * vt - after * after), 1e-12)
            ct = sc.contacts(out)
            over = (np.abs(ct['impulse_x']) - 0.2 * ct['impulse_y']).max()
            sc.report(tag + ': tangential impulse <= mu x normal every step', over <= 1e-15, 'excess %.2e' % over)
    out = sc.run_ok(HERE + 'oblique.dat', ['INITIAL.VELOCITY=3 -1', 'OBSTACLE.FRICTION=0', 'SCHEME.IMPACT=' + mode])
    pr = sc.probes(out)
    sc.report('oblique impact %s frictionless: v_t kept' % mode, abs(pr['ball.VX'][-1] - 3.0) <= 1e-12,
              '%.15f' % pr['ball.VX'][-1])

# Two free point masses through a rough node-to-node GAP.
out = sc.run_ok(HERE + 'pair.dat')
energy_checks('GAP PAIRS', out)
pr = sc.probes(out)
# relative velocity b - a = (-3, -2): normal impulse 2 m* 2 = 3 N s (m* = 3/4), tangential 0.75 N s
expected = {'a.VX': 2.0 - 0.75, 'a.VY': 1.0 - 3.0, 'b.VX': -1.0 + 0.25, 'b.VY': -1.0 + 1.0}
for k, v in expected.items():
    sc.report('GAP PAIRS: two-body Coulomb impact, %s (1e-12)' % k, abs(pr[k][-1] - v) <= 1e-12,
              '%.15f vs %.15f' % (pr[k][-1], v))
hist = sc.history(out)
sc.close('GAP PAIRS: friction dissipated the tangential energy lost (1e-12)', hist['friction_dissipated'][-1], 1.875, 1e-12)

# A point mass on a free block through rough node-to-segment contact.
out = sc.run_ok(HERE + 'seg.dat')
hist = energy_checks('GAP SEGMENTS', out)
for k in ['momentum_x', 'momentum_y']:
    drift = np.abs(hist[k] - hist[k][0]).max() / np.abs(hist[k][0])
    sc.report('GAP SEGMENTS: %s kept (1e-12)' % k, drift <= 1e-12, 'relative drift %.2e' % drift)
pr = sc.probes(out)
sc.report('GAP SEGMENTS: the friction slowed the ball along the surface', pr['ball.VX'][-1] < 1.9,
          'v_t %.6f m/s (2 before)' % pr['ball.VX'][-1])
sc.report('GAP SEGMENTS: friction dissipated energy', hist['friction_dissipated'][-1] > 0.0,
          '%.4e J' % hist['friction_dissipated'][-1])

# A spinning ring set on a rough floor (meshes made by tools/ring_mesh.py in the temporary folder).
with open(HERE + 'spin.dat') as f:
    spin = f.read()
m = np.pi * (0.1 ** 2 - 0.08 ** 2) * 0.01 * 1000.0
inertia = m * (0.1 ** 2 + 0.08 ** 2) / 2.0
r, w0 = 0.1, 10.0
vf = w0 * r * inertia / (inertia + m * r * r)
loss = 0.5 * inertia * w0 ** 2 * m * r * r / (inertia + m * r * r)
errors = []
for n in [12, 24]:
    mesh = os.path.join(sc.TMP, 'ring%d.msh' % n)
    subprocess.run(['/usr/bin/python3', os.path.join(sc.ROOT, 'tools', 'ring_mesh.py'), str(n), '3', mesh], check=True)
    scene = sc.write_scene('spin%d.dat' % n, spin.replace('FILE ring.msh', 'FILE ring%d.msh' % n))
    tag = 'spinning ring, %d nodes around' % (4 * n)
    out = sc.run_ok(scene)
    hist = energy_checks(tag, out)
    t = hist['time']
    v_end = (hist['momentum_x'][t > 0.2] / m).mean()
    errors.append((v_end / vf - 1.0, hist['friction_dissipated'][-1] / loss - 1.0))
    print('# %s: rolling speed %.5f m/s (rigid %.5f, %+.2f %%), friction loss %.6f J (rigid %.6f, %+.2f %%)' %
          (tag, v_end, vf, 100 * errors[-1][0], hist['friction_dissipated'][-1], loss, 100 * errors[-1][1]))
sc.report('spinning ring: rolling speed converging with the mesh', abs(errors[1][0]) < abs(errors[0][0]),
          '%.2e then %.2e' % (errors[0][0], errors[1][0]))
sc.report('spinning ring: friction loss converging with the mesh', abs(errors[1][1]) < abs(errors[0][1]),
          '%.2e then %.2e' % (errors[0][1], errors[1][1]))
sc.report('spinning ring, 96 nodes: rolling speed within 1 % of the rigid body', abs(errors[1][0]) <= 0.01,
          '%+.2f %%' % (100 * errors[1][0]))
sc.report('spinning ring, 96 nodes: friction loss within 1.5 % of the rigid body', abs(errors[1][1]) <= 0.015,
          '%+.2f %%' % (100 * errors[1][1]))

# A restart continues bit for bit: the friction states and their dissipation are checkpointed.
for scene, half, sets in [('oscillator.dat', '1.6', ['OUTPUT.CHECKPOINT=20']),
                          ('block_slide.dat', '0.0004', ['TIME.END=0.0008', 'OUTPUT.CHECKPOINT=7'])]:
    same, detail = sc.restart_same(HERE + scene, sets, half, files=('history.csv', 'contacts.csv', 'probes.csv'))
    sc.report('%s: a restart from the checkpoint continues bit for bit' % scene, same, detail)

# A parcel on a conveyor belt: friction relative to a moving obstacle.
out = sc.run_ok(HERE + 'belt.dat')
hist = energy_checks('conveyor belt', out)
pr = sc.probes(out)
t, x, v = pr['time'], pr['p.UX'], pr['p.VX']
acc, belt, h = 0.4 * G, 1.5, 1e-3
ts = belt / acc
slide = t < ts - h
err = np.abs(x[slide] - 0.5 * acc * t[slide] ** 2).max()
sc.report('conveyor belt: slides by 1/2 mu g t^2 (1e-12 m)', err <= 1e-12, 'max error %.2e m' % err)
sc.report('conveyor belt: rides the belt at V once stuck (1e-12)', np.abs(v[t > ts + h] - belt).max() <= 1e-12,
          'max |v - V| %.2e' % np.abs(v[t > ts + h] - belt).max())
sc.close('conveyor belt: the belt did m V^2 (1e-12)', hist['external'][-1], 2.0 * belt ** 2, 1e-12)
sc.close('conveyor belt: half of it dissipated, 1/2 m V^2 (1e-12)', hist['friction_dissipated'][-1], belt ** 2, 1e-12)

# An elastic ring hitting a rough wall obliquely, at three angles.
ring_m = np.pi * (0.1 ** 2 - 0.08 ** 2) * 0.01 * 1000.0
ring_i = ring_m * (0.1 ** 2 + 0.08 ** 2) / 2.0


def rebound(hist):
    """Centre velocity and spin after the impact (L about the origin less m x_cm x v_cm)."""
    t = hist['time']
    vx, vy = hist['momentum_x'] / ring_m, hist['momentum_y'] / ring_m
    x = np.concatenate([[0.0], np.cumsum(0.5 * (vx[1:] + vx[:-1]) * np.diff(t))])
    y = np.concatenate([[0.0], np.cumsum(0.5 * (vy[1:] + vy[:-1]) * np.diff(t))])
    w = (hist['angular_momentum'][-1] - ring_m * (x[-1] * vy[-1] - y[-1] * vx[-1])) / ring_i
    return vx[-1], vy[-1], w


# The momenta are asserted to 1e-12 with the iteration converged to 1e-12 (SCHEME TOLERANCE): what
# moves them then is the contact's impulses alone. At the default 1e-10 the converged residual's
# moment moves the angular momentum by up to 9e-12 of it (Newton on eq (9)'s step tangent stops
# nearer the tolerance than the linear iteration did: 5e-14 before).
for vt in [1.0, 2.0, 7.0]:
    vel = 'INITIAL.VELOCITY=%r -2' % vt
    angle = np.degrees(np.arctan(vt / 2.0))
    for mode in ['AUTO', 'PAPER', 'SYMMETRIC', 'frictionless']:
        sets = [vel, 'SCHEME.TOLERANCE=1e-12'] + (['OBSTACLE.FRICTION=0'] if mode == 'frictionless' else
                                                    ['SCHEME.IMPACT=' + mode])
        tag = 'ring at %.0f deg, %s' % (angle, mode)
        out = sc.run_ok('inputs/ring_rough_wall.dat', sets)
        hist = energy_checks(tag, out)
        ct = sc.contacts(out)
        dl = hist['angular_momentum'] - hist['angular_momentum'][0] - np.cumsum(ct['impulse_moment'])
        dp = hist['momentum_x'] - hist['momentum_x'][0] - np.cumsum(ct['impulse_x'])
        err = max(np.abs(dl).max() / np.abs(hist['angular_momentum']).max(),
                  np.abs(dp).max() / np.abs(hist['momentum_x']).max())
        sc.report(tag + ': momenta change by the impulses and their moments (1e-12)', err <= 1e-12, '%.2e' % err)
        vx, vy, w = rebound(hist)
        print('# %s: rebound v = (%.4f, %.4f) m/s, %.2f deg from the normal, spin %.3f rad/s, friction %.4e J' %
              (tag, vx, vy, np.degrees(np.arctan2(vx, vy)), w, hist['friction_dissipated'][-1]))
        if mode in ['PAPER', 'SYMMETRIC']:
            over = ((np.abs(ct['impulse_x']) - 0.3 * ct['impulse_y']) / np.maximum(ct['impulse_y'], 1e-300)).max()
            sc.report(tag + ': tangential impulse <= mu x normal every step', over <= 1e-12, 'excess %.2e' % over)
            w_rough = w
        if mode in ['PAPER', 'SYMMETRIC'] and vt == 7.0:      # it slides throughout: Coulomb's facet
            ratio = (hist['momentum_x'][-1] - hist['momentum_x'][0]) / (hist['momentum_y'][-1] - hist['momentum_y'][0])
            sc.report(tag + ': sliding throughout, momentum change x = -mu y (1e-12)', abs(ratio + 0.3) <= 1e-12,
                      'ratio %.15f' % ratio)
        if mode == 'frictionless':
            drift = np.abs(hist['momentum_x'] - hist['momentum_x'][0]).max() / abs(hist['momentum_x'][0])
            sc.report(tag + ': tangential momentum kept (1e-12)', drift <= 1e-12, '%.2e' % drift)
            sc.report(tag + ': spin below 1 % of the rough wall\'s (its deformation only)', abs(w) <= 0.01 * abs(w_rough),
                      'w %.3f rad/s against %.3f' % (w, w_rough))

# The augmented sparse system (MULTIPLIERS AUGMENTED, AUTO on large zones) gives the Schur columns'
# steps: the sliding block before it rocks, the oblique ring, the stick-slip oscillator.
for scene, sets in [(HERE + 'block_slide.dat', ['TIME.END=6e-4']), ('inputs/ring_rough_wall.dat', ['INITIAL.VELOCITY=2.0 -2']),
                    (HERE + 'oscillator.dat', [])]:
    runs = [sc.history(sc.run_ok(scene, sets + ['SCHEME.MULTIPLIERS=' + m])) for m in ['SCHUR', 'AUGMENTED']]
    err = max(np.abs(runs[0][k] - runs[1][k]).max() / max(np.abs(runs[0][k]).max(), 1e-300)
              for k in ['momentum_x', 'momentum_y', 'kinetic', 'friction_dissipated'])
    sc.report('%s: MULTIPLIERS AUGMENTED = SCHUR (1e-12)' % os.path.basename(scene), err <= 1e-12,
              'largest relative difference %.2e' % err)

# STATIC with friction: the dynamics starts from the static equilibrium the friction holds.
with open(HERE + 'block_stick.dat') as f:
    text = f.read()
text = text.replace('FUNCTION ramp', '').replace('END 1', 'END 0.01') + 'STATIC\n'
out = sc.run_ok(sc.write_scene('block_static.dat', text))
hist = sc.history(out)
pr = sc.probes(out)
move = max(np.abs(pr[k] - pr[k][0]).max() for k in ['block.bottom_left.UX', 'block.bottom_right.UX', 'block.top_left.UX'])
sc.report('STATIC block on 20 deg, mu 0.5: stays at its equilibrium (1e-15 m)', move <= 1e-15, 'moved %.2e m' % move)
sc.report('STATIC block on 20 deg, mu 0.5: no kinetic energy (1e-20 J)', hist['kinetic'].max() <= 1e-20,
          '%.2e J' % hist['kinetic'].max())
sc.report('STATIC block on 20 deg, mu 0.5: the top moved by the static shear', np.abs(pr['block.top_left.UX'][0]) > 1e-10,
          'u_x %.3e m' % pr['block.top_left.UX'][0])
rc, err, _ = sc.run(sc.write_scene('block_static_slides.dat', text.replace('FRICTION 0.5', 'FRICTION 0.3')))
sc.report('STATIC block on 20 deg, mu 0.3 < tan 20 deg: no equilibrium, exit 1 naming STATIC',
          rc == 1 and 'STATIC' in err and 'did not converge' in err, 'exit %d: %s' % (rc, err.strip()[:200]))
with open(HERE + 'incline.dat') as f:
    text = f.read()
out = sc.run_ok(sc.write_scene('incline_static.dat', text + 'STATIC\n'), ['OBSTACLE.FRICTION=0.7'])
pr = sc.probes(out)
umax = np.hypot(pr['ball.UX'], pr['ball.UY']).max()
sc.report('STATIC point mass at the origin on 30 deg, mu 0.7: rests (1e-12 m)', umax <= 1e-12, '%.2e m' % umax)
