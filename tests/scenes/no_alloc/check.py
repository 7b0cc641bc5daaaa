"""No heap allocation in the time loop (docs/performance.md, "Allocations in the time loop").

tools/alloc_per_step.sh runs a scene under valgrind for N and 2N steps with the output of the
loop switched off (OUTPUT HISTORY 0, FIELDS 0) and reports (A(2N) - A(N)) / N, the mallocs per
step once everything allocated before the loop (parsing, assembly, factorization, file
opening) cancels. The standard is exactly zero, on:
- cantilever_release: linear, one solve per step;
- cantilever_plastic: fibre beam, ITERATION ELASTIC, the window N..2N = 60..120 steps holds
  the formation of the plastic hinge (first plastic step 85, ~10 iterations per step);
- spring_plastic: SUBSTEPS 100, ITERATION ELASTIC, plastic flow during the window;
- block_j2: VON_MISES quads (ITERATION ELASTIC; the law's path through subincrement_path), plastic from step 52;
- zone/patch_block: SCHEME ZONE (AUTO takes it), Newton on the zone's equations through Woodbury
  (no refactorization), the patch plastic over the window 100..200; zone/drop_block: the zone
  with contact rows (the contact solve at each iterate), the ground held over 50..100;
- mass_bounce: contact, the window 200..400 holds the first impact (step ~347), in IMPACT
  PAPER and PERSIST;
- bar_impact: a free bar on a wall, PERSIST (projection and body scaling), window 100..200;
- beams_collide: two beams, consistent mass (solves with M), PERSIST about the centre of mass;
- bar_impact with its wall moving at 0.5 m/s (OBSTACLE … VELOCITY), window 50..100 holding the
  impact: the rows' targets, the obstacle's frame (workspaces set at its first motion);
- FRICTION (tests/scenes/friction): the stick-slip oscillator over a slip reversal and its stick,
  the QUAD4 block sliding on its base, the oblique impact's frictional correction.

Contact: the multipliers (Schur columns, LCP pivoting), the impulse (14), the reflection (16)
and the PERSIST projection work in workspaces sized at contact_finalize (the dense blocks grow
only past 64 simultaneous conditions). The augmented system is not exercised here: UMFPACK
allocates its numeric object at each refactorization, i.e. when the active set changes
(docs/performance.md).

ITERATION AUTO (and TANGENT) refactorize the iteration matrix inside the loop, and CHOLMOD's
supernodal numeric factorization allocates its workspace at each call (freed before it returns):
on block_j2, cantilever_plastic and spring_plastic (a system of a few equations, where AUTO is
TANGENT) under AUTO every allocation of the window is CHOLMOD's
(tools/alloc_per_step.sh --where), and their number is a fixed count per factorization (8 with
Debian's SuiteSparse; at most 16 asserted), the factorizations counted from rebond's run summary.
The same for KINEMATICS LARGE (TANGENT): spinning_quad (a LARGE QUAD4), inputs/bead_rod
(node-to-segment contact that follows the configuration, held over the window), inputs/taylor_plane
(STRAIN_MEASURE LOG: the log map's tangent through LAPACK's dsyev on fixed work arrays) and
inputs/taylor_bar (the same, axisymmetric: the hoop stretch, the 4 x 4 positive parts).

Each window is also checked to contain what it is meant to exercise (plastic work growing,
an impact), from a normal run of 2N steps, so that a shorter scene cannot make the test vacuous.
"""
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

TOOL = os.path.join(sc.ROOT, 'tools', 'alloc_per_step.sh')
CASES = [  # scene, N, what the window must contain, --set arguments
    ('inputs/cantilever_release.dat', 20, None, []),
    ('inputs/cantilever_plastic.dat', 60, 'plastic', ['SCHEME.ITERATION=ELASTIC']),
    ('inputs/spring_plastic.dat', 10, 'plastic', ['SCHEME.ITERATION=ELASTIC']),
    ('inputs/block_j2.dat', 60, 'plastic', ['SCHEME.ITERATION=ELASTIC']),
    ('tests/scenes/zone/patch_block.dat', 100, 'plastic', []),
    ('tests/scenes/zone/drop_block.dat', 50, 'impact', []),
    ('inputs/mass_bounce.dat', 200, 'impact', []),
    ('inputs/mass_bounce.dat', 200, 'impact', ['SCHEME.IMPACT=PERSIST']),
    ('inputs/bar_impact.dat', 100, 'impact', ['SCHEME.IMPACT=PERSIST']),
    ('inputs/beams_collide.dat', 400, 'impact', ['SCHEME.IMPACT=PERSIST']),
    ('inputs/hertz_axi.dat', 40, 'impact', ['OUTPUT.FIELDS=EVERY 0']),   # axisymmetric (hoop row, ring weights)
    ('inputs/bar_impact.dat', 50, 'impact', ['OBSTACLE.VELOCITY=0.5 0']),   # a moving wall (its frame, its work)
    # FRICTION: the stick-slip oscillator through a slip reversal and a stick (steps 157-158), the
    # sliding block's base (the active-set passes, dgesv), the oblique impact's friction correction
    ('tests/scenes/friction/oscillator.dat', 100, 'impact', []),
    ('tests/scenes/friction/block_slide.dat', 30, 'impact', []),
    ('tests/scenes/friction/oblique.dat', 20, 'impact', []),
    ('inputs/sdnv100_3d.dat', 30, 'impact', []),                  # 3D: HEX8 through the generic point path
]


def step_of(scene):
    with open(os.path.join(sc.ROOT, scene)) as f:
        for line in f:
            w = line.split('#')[0].split()
            if w and w[0].upper() == 'TIME':
                up = [x.upper() for x in w]
                return float(w[up.index('STEP') + 1])
    raise RuntimeError('%s: no TIME STEP' % scene)


def window_ok(scene, n, what, sets):
    """True when steps n+1..2n of a normal run contain `what`."""
    if what is None:
        return True, ''
    out = sc.run_ok(scene, ['TIME.END=%r' % (2 * n * step_of(scene)), 'OUTPUT.HISTORY=1'] + sets)
    h = sc.history(out)
    steps = h['step']
    if what == 'plastic':
        d = h['dissipated']
        grow = d[steps == 2 * n][0] - d[steps == n][0]
        return grow > 0.0, 'plastic work over the window %.3e J' % grow
    hits = int(np.count_nonzero((h['active_contacts'] > 0) & (steps > n)))
    return hits > 0, '%d steps with an active contact in the window' % hits


if subprocess.run(['bash', '-c', 'command -v valgrind'], capture_output=True).returncode != 0:
    sc.report('valgrind installed (tools/install_deps.sh)', False, 'valgrind not found')
    sys.exit(0)

for scene, n, what, sets in CASES:
    name = os.path.basename(scene) + ''.join(' ' + x for x in sets)
    ok, detail = window_ok(scene, n, what, sets)
    if what is not None:
        print('# %s: %s' % (name, detail))
        sc.report('%s: steps %d..%d exercise the %s path' % (name, n, 2 * n, what), ok, detail)
    args = ['bash', TOOL, '--mode', 'none', scene, str(n)]
    for x in sets:
        args += ['--set', x]
    p = sc.run_limited(args, 300, cwd=sc.ROOT, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError('%s failed on %s: %s' % (TOOL, scene, p.stderr.strip()))
    fields = p.stdout.split()
    a1, a2, per_step = int(fields[2]), int(fields[3]), float(fields[4])
    print('# %s: %d allocations for %d steps, %d for %d steps: %.2f per step (output off)'
          % (name, a1, n, a2, 2 * n, per_step))
    sc.report('%s: zero heap allocations per time step, output off' % name, a2 == a1,
              '%.2f allocations per step (%d extra over steps %d..%d)' % (per_step, a2 - a1, n + 1, 2 * n))


# --- ITERATION AUTO: the allocations are CHOLMOD's, a fixed number per refactorization ----------
def factorizations(scene, steps, sets):
    """The iteration matrix's factorizations in a run of `steps` steps (rebond's summary)."""
    cmd = [sc.REBOND, scene, '-o', sc.new_dir(), '--set', 'TIME.END=%r' % (steps * step_of(scene)),
           '--set', 'OUTPUT.HISTORY=0', '--set', 'OUTPUT.FIELDS=0']
    for x in sets:
        cmd += ['--set', x]
    p = sc.run_limited(cmd, 300, cwd=sc.ROOT, capture_output=True, text=True)
    for line in p.stdout.splitlines():
        if 'iteration matrix factorized' in line:
            return int(line.split('factorized')[1].split()[0])
    return 1


# KINEMATICS LARGE takes TANGENT: a LARGE QUAD4 (large_plane_element), and node-to-segment contact that
# follows the configuration (rows rewritten at each iterate and at the end of each step, the held contact's
# work given back by scaling), the bead held on its rod over the window.
for scene, n, sets in (('inputs/block_j2.dat', 60, ['SCHEME.ITERATION=AUTO']),
                       ('inputs/cantilever_plastic.dat', 60, ['SCHEME.ITERATION=AUTO']),
                       ('inputs/spring_plastic.dat', 10, ['SCHEME.ITERATION=AUTO']),
                       ('tests/scenes/large_bar/spinning_quad.dat', 20, []),
                       ('inputs/bead_rod.dat', 40, []),
                       ('inputs/taylor_plane.dat', 15, []),
                       ('inputs/taylor_bar.dat', 15, [])):
    name = os.path.basename(scene) + (' AUTO' if sets else ' (LARGE: TANGENT)')
    if not sets:
        ok, detail = window_ok(scene, n, 'impact', sets) if 'bead' in scene else (True, '')
        if 'bead' in scene:
            sc.report('%s: steps %d..%d hold the contact' % (name, n, 2 * n), ok, detail)
    df = factorizations(scene, 2 * n, sets) - factorizations(scene, n, sets)
    args = ['bash', TOOL, '--mode', 'none', scene, str(n)] + [a for x in sets for a in ('--set', x)]
    fields = sc.run_limited(args, 300, cwd=sc.ROOT, capture_output=True, text=True).stdout.split()
    da = int(fields[3]) - int(fields[2])
    sc.report('%s: the extra allocations are a fixed number (<= 16) per refactorization' % name,
              df > 0 and da % df == 0 and da // df <= 16, '%d allocations, %d factorizations over steps %d..%d'
              % (da, df, n + 1, 2 * n))
    where = sc.run_limited(['bash', TOOL, '--where', scene, str(n)] + [a for x in sets for a in ('--set', x)], 300,
                           cwd=sc.ROOT, capture_output=True, text=True).stdout.splitlines()
    stacks = [ln for ln in where[1:] if ln.strip() and not ln.strip().endswith('total')]
    sc.report('%s: every allocation in the window is CHOLMOD\'s factorization' % name,
              len(stacks) > 0 and all('cholmod_malloc <- rb_chol_factorize' in ln for ln in stacks),
              '; '.join(ln.strip()[:60] for ln in stacks))

