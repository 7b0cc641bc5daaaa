"""Stability at the extremes, fast subset (issue 5, deliverable 4; `make test`).

Runs the cases of tests/extremes/matrix.py marked fast (about 40 of its ~70, a few seconds):
steps from 1e-8 s to 10 periods, Young's moduli 1, 1e6 and 1e12 Pa, mass ratios 1e-6 and 1e6,
gaps of 1e-12 m and contacts at t = 0, grazing, 100 simultaneous impacts, 1e6 steps of an
oscillator against its exact discrete solution, and a perfectly plastic member taking ~1000
yield strains in one step. Each must end finite with max |balance| / max(kinetic + internal)
within the case's stated bound and pass its exact checks, or be refused with the expected exit
status and message. Cases that expose a known src/ defect run only in `make extremes`
(the whole matrix; outcomes in docs/extremes.md). Then the tests of tools/compare
(tests/extremes/test_compare.py).
"""
import os
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'extremes'))
import matrix  # noqa: E402
import test_compare  # noqa: E402

rc = matrix.main(['--fast'])
# tools/compare (deliverable 5): a run against its own exact solution (tests/extremes/test_compare.py)
sys.exit(rc or test_compare.main())
