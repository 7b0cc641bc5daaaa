"""The report of the scene before its first step (issue 37, item 5): the total mass and each
model's, estimates of the highest and lowest natural frequencies, each model's wave speed and
c h/dx, and warnings where the step exceeds the lowest period or a wave speed is implausible.

Asserted against closed forms:
- two masses on two springs (k = 8 N/m, m = 2 kg, fixed at one end): omega^2 = (k/m)(3 -+ sqrt 5)/2,
  the highest and the lowest to 5e-4 (the report prints 4 digits);
- the cantilever of inputs/ (BEAM2, 20 elements): the lowest 8.38 Hz (Euler-Bernoulli
  1.875^2/(2 pi L^2) sqrt(EI/rho A) = 8.3816 Hz) to 0.1 %, its mass rho A L = 0.78 kg;
- the free beam of inputs/beam_flying.dat (no support: its rigid motions taken out): the free-free
  first mode 4.730^2/(2 pi L^2) sqrt(EI/rho A) = 0.79630 Hz to 0.2 %;
- a scene of two models lists both masses, and their sum;
- a step of 1 s on the cantilever (period 0.119 s) warns, naming the step and the period; YOUNG in
  MPa where Pa is meant (c = 5.2 m/s) warns "check the units"; the default step warns of nothing.
"""
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402


def run(scene, sets=()):
    out = sc.new_dir('report')
    cmd = [sc.REBOND, scene, '-o', out]
    for s in sets:
        cmd += ['--set', s]
    p = sc.run_limited(cmd, 120, cwd=sc.ROOT, text=True)
    if p.returncode != 0:
        raise RuntimeError(p.stderr)
    return p.stdout, p.stderr


def freq(out, which):
    m = re.search(which + r' ([0-9.eE+-]+) Hz', out)
    return float(m.group(1)) if m else float('nan')


SPRINGS = sc.write_scene('springs.dat', '''NODE a AT 0 0
NODE b AT 1 0
NODE c AT 2 0
ELEMENT s TYPE SPRING NODES a b b c
ELEMENT m TYPE MASS NODES b c
MATERIAL k ELASTIC YOUNG 8
SECTION pm MASS 2
MODEL s MATERIAL k
MODEL m SECTION pm
FIX a ALL
FIX b UY
FIX c UY
INITIAL c DISPLACEMENT 0.1 0
TIME STEP 0.01 END 0.1
''')
out, err = run(SPRINGS)
lo, hi = [math.sqrt(4.0 * (3 + s * math.sqrt(5)) / 2) / (2 * math.pi) for s in (-1, 1)]
sc.report_measured('two springs and masses: the highest frequency (5e-4)', abs(freq(out, 'highest') / hi - 1) <= 5e-4,
                   '%.7g Hz vs %.7g Hz' % (freq(out, 'highest'), hi))
sc.report_measured('two springs and masses: the lowest frequency (5e-4)', abs(freq(out, 'lowest') / lo - 1) <= 5e-4,
                   '%.7g Hz vs %.7g Hz' % (freq(out, 'lowest'), lo))
sc.report('two models: the total mass (4 kg) and each model\'s',
          'mass 4.000 kg' in out and 'MODEL s: mass 0 kg' in out and 'MODEL m: mass 4.000 kg' in out, out[:600])

CANT = os.path.join('inputs', 'cantilever_release.dat')
out, err = run(CANT, ['TIME.END=1e-3'])
ex = 1.875104 ** 2 / (2 * math.pi) * math.sqrt(2.1e11 * 8.333333333e-10 / (7800 * 1e-4))
sc.report_measured('cantilever: the lowest frequency = Euler-Bernoulli (0.1 %)', abs(freq(out, 'lowest') / ex - 1) <= 1e-3,
                   '%.5g Hz vs %.5g Hz' % (freq(out, 'lowest'), ex))
sc.report('cantilever: mass rho A L = 0.78 kg', 'mass 0.7800 kg' in out, out[:300])
sc.report('cantilever: mass, wave speed and c h/dx per model',
          'MODEL beam: mass 0.7800 kg, wave speed 5189 m/s, c h/dx 10.38 to 10.38' in out,
          out[:600])
sc.report('cantilever at its step: no warning', 'warning' not in err, err)
out, err = run(CANT, ['TIME.STEP=1', 'TIME.END=2'])
sc.report('a 1 s step on a 0.119 s period: a warning naming both',
          'warning' in err and 'TIME STEP 1.000 s' in err and 'period, 0.1193 s' in err, err.strip())
out, err = run(CANT, ['MATERIAL.steel.YOUNG=2.1e5', 'TIME.END=1e-3'])
sc.report('YOUNG in MPa: "check the units"', 'wave speed 5.189 m/s' in err and 'check the units' in err, err.strip())

FLY = os.path.join('inputs', 'beam_flying.dat')
out, err = run(FLY, ['TIME.END=0.01'])
ex = 4.730041 ** 2 / (2 * math.pi * 100.0) * math.sqrt(1e4 * 0.05 / 1.0)
sc.report_measured('free beam: the lowest = the free-free first mode, rigid motions out (0.2 %)',
                   abs(freq(out, 'lowest') / ex - 1) <= 2e-3, '%.5g Hz vs %.5g Hz' % (freq(out, 'lowest'), ex))

# The summary counts the modelled elements: inputs/ring_plastic.dat's Gmsh mesh holds 144 QUAD4 of the
# ring and 48 boundary lines that no MODEL takes (issue 38, item 5).
out, err = run(os.path.join('inputs', 'ring_plastic.dat'), ['TIME.END=4e-4'])
sc.report('ring_plastic: the summary counts the 144 modelled elements, the 48 Gmsh lines apart',
          '192 nodes, 144 elements, 384 equations (and 48 mesh elements in no MODEL, not modelled)' in out, out[:300])

# TRI3 in plane strain with VON_MISES locks (one point; BBAR has nothing to average): a warning naming
# the model and what to mesh with; none in plane stress, none for QUAD4 (which takes BBAR).
TRI = """NODE p1 AT 0 0
NODE p2 AT 1 0
NODE p3 AT 1 1
NODE p4 AT 0 1
ELEMENT t TYPE %s NODES %s
MATERIAL st VON_MISES YOUNG 2e11 POISSON 0.3 DENSITY 7800 YIELD 2e8
SECTION sl THICKNESS 0.1
MODEL t MATERIAL st SECTION sl PLANE %s
FIX p1 ALL
FIX p2 ALL
TIME STEP 1e-5 END 2e-5
"""
_, err = run(sc.write_scene('tri3_strain.dat', TRI % ('TRI3', 'p1 p2 p3', 'STRAIN')))
sc.report('TRI3 VON_MISES in plane strain: a warning that it locks, naming the model, QUAD4 and TRI6',
          'MODEL t: TRI3 in plane strain locks' in err and 'QUAD4' in err and 'TRI6' in err, err.strip())
_, err = run(sc.write_scene('tri3_stress.dat', TRI % ('TRI3', 'p1 p2 p3', 'STRESS')))
sc.report('TRI3 VON_MISES in plane stress: no locking warning', 'locks' not in err, err.strip())
_, err = run(sc.write_scene('quad4_strain.dat', TRI % ('QUAD4', 'p1 p2 p3 p4', 'STRAIN')))
sc.report('QUAD4 VON_MISES in plane strain (BBAR): no locking warning', 'locks' not in err, err.strip())
