"""Fuzzed scenes never crash (issue 6): a short run of the harness tests/fuzz/fuzz.py.

Runs MUTANTS mutants of the shipped scenes with the fixed seed SEED (the same mutants at every run;
`make fuzz` runs 10 000 with another seed) and prints the harness's `PASS fuzz: ...` per batch or
`FAIL fuzz <mutant>: <reason>` per crash (saved in tests/fuzz/crashes/). Then the crashes that the
fuzzer found and that were fixed are replayed as regression cases: each must exit 2 with
`rebond: error: FILE:LINE: KEYWORD name: ...` naming the line and the word at fault.
"""
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(HERE)), 'fuzz'))
import scenecheck as sc  # noqa: E402
import fuzz  # noqa: E402

SEED = 'check'
MUTANTS = 400

# (name, scene lines, line at fault, word at fault): absurd counts that crashed or hung rebond
# (allocation failure in the generators, integer overflow of nx*ny, loops of 1e9 sub-increments).
BASE = [
    'MATERIAL st ELASTIC YOUNG 2e11 DENSITY 7800',
    'SECTION sc AREA 1e-4 INERTIA 1e-9 HEIGHT 0.01',
    'TIME STEP 1e-5 END 3e-5',
]
CASES = [
    ('line_2e31', ['LINE b FROM 0 0 TO 1 0 ELEMENTS 2147483647 TYPE BAR2'], 4, '2147483647'),
    ('line_1e9', ['LINE b FROM 0 0 TO 1 0 ELEMENTS 1000000000 TYPE BEAM2'], 4, '1000000000'),
    ('rect_65536sq', ['RECTANGLE r ORIGIN 0 0 SIZE 1 1 ELEMENTS 65536 65536 TYPE QUAD4'], 4, '65536'),
    ('rect_46341sq', ['RECTANGLE r ORIGIN 0 0 SIZE 1 1 ELEMENTS 46341 46341 TYPE QUAD8'], 4, '46341'),
    ('rect_2e31x1', ['RECTANGLE r ORIGIN 0 0 SIZE 1 1 ELEMENTS 2147483647 1 TYPE QUAD4'], 4, '2147483647'),
    ('substeps_1e9', ['LINE b FROM 0 0 TO 1 0 ELEMENTS 2 TYPE BAR2',
                      'MODEL b MATERIAL st SECTION sc SUBSTEPS 1000000000'], 5, '1000000000'),
    ('layers_1e9', ['SECTION fib AREA 1e-4 HEIGHT 0.01 LAYERS 1000000000'], 4, '1000000000'),
    # A mesh file that never ends (read until memory ran out): refused at its first line.
    ('gmsh_dev_zero', ['GMSH m FILE /dev/zero'], 4, '/dev/zero'),
    # An initial velocity of 1e308 overflowed the kinetic energy (SIGFPE under make check-debug).
    ('initial_v_1e308', ['LINE b FROM 0 0 TO 1 0 ELEMENTS 2 TYPE BAR2', 'MODEL b MATERIAL st SECTION sc',
                         'INITIAL b VELOCITY 1e308 0'], 6, '1e308'),
    # A beam section of INERTIA 1e300 overflowed E I (SIGFPE under make check-debug, seed check 209).
    ('inertia_1e300', ['SECTION big AREA 1e-4 INERTIA 1e300 HEIGHT 0.01'], 4, '1e300'),
    # A FUNCTION value of -1e300 scaling a pressure overflowed it (SIGFPE under the debug build,
    # seed s9dbg2 5635).
    ('function_1e300', ['FUNCTION ramp POINTS 0 0 2e-3 -1e300'], 4, '-1e300'),
    # A NONLINEAR_ELASTIC B of 1e300 (1e30 already) overflowed E b eps^3 on the first iterates (SIGFPE
    # under make check-debug, seed check 209 once inputs/sdnv100.dat joined the corpus).
    ('nl_b_1e300', ['MATERIAL nl NONLINEAR_ELASTIC YOUNG 2.1e11 B 1e300 DENSITY 7800'], 4, '1e300'),
    ('nl_b_minus_1e30', ['MATERIAL nl NONLINEAR_ELASTIC YOUNG 2.1e11 B -1e30 DENSITY 7800'], 4, '-1e30'),
]


def regression():
    d = os.path.join(sc.TMP, 'fuzz_regression')
    os.makedirs(d, exist_ok=True)
    for name, extra, line, word in CASES:
        path = os.path.join(d, name + '.dat')
        with open(path, 'w') as f:
            f.write('\n'.join(BASE + extra) + '\n')
        t0 = time.time()
        try:
            rc, err, outdir = sc.run(path, timeout=30)
        except Exception as e:   # a hang is a failure of the case, not of the check
            print('FAIL fuzz regression %s: %s' % (name, e))
            continue
        want = '%s:%d: ' % (path, line)
        ok = rc == 2 and want in err and ("at '%s'" % word) in err and not os.path.exists(outdir)
        msg = next((l for l in err.splitlines() if l.startswith('rebond: error:')), err.strip())
        if ok:
            print('PASS fuzz regression %s: exit 2 in %.2f s, %s' % (name, time.time() - t0, msg[:160]))
        else:
            print('FAIL fuzz regression %s: exit %d, expected 2 with "%s" and word %r: %s'
                  % (name, rc, want, word, msg[:300]))


def main():
    t0 = time.time()
    fuzz.fuzz(MUTANTS, seed=SEED, jobs=2, batch=100, timeout=20.0)
    regression()
    print('fuzz check: %.1f s' % (time.time() - t0))


if __name__ == '__main__':
    main()
