"""`make bench` keeps building and measuring (issue 14): tools/bench.sh on a 1e3-DOF plate, 5 steps,
a few solves, one round, its report in a scratch file. bench_plate is compiled against the
library as it is now (it once stopped compiling unnoticed: the library's API had changed).
Asserted: the run succeeds and prints its RESULT line, and the identity the benchmark relies on
holds: for a linear elastic model from zero stress the internal forces Bσ(u) equal the sparse
product K0 u at the same state (relative difference <= 1e-12; round-off, 3e-15 measured). Speeds
are not asserted (they are the benchmark's to report, not a test's).
"""
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

work = sc.new_dir('bench')
os.makedirs(work, exist_ok=True)
env = dict(os.environ, BENCH_SIZES='1e3', BENCH_STEPS='5', BENCH_SOLVES='3', BENCH_REPEATS='1',
           BENCH_OUT=os.path.join(work, 'performance.md'), BENCH_WORK=work)
p = subprocess.run(['bash', 'tools/bench.sh'], cwd=sc.ROOT, env=env, capture_output=True, text=True, timeout=600)
result = next((l for l in p.stdout.splitlines() if l.startswith('RESULT ')), '')
sc.report('tools/bench.sh builds bench_plate and runs it (exit 0, a RESULT line)', p.returncode == 0 and bool(result),
          'exit %d: %s' % (p.returncode, (p.stderr or p.stdout)[-400:]))
fields = dict(kv.split('=', 1) for kv in result.split()[1:] if '=' in kv)
kdiff = float(fields.get('kdiff', 'nan'))
sc.report('bench: Bσ(u) = K0 u for the linear elastic plate (1e-12)', kdiff <= 1e-12, 'kdiff %s' % fields.get('kdiff'))
sc.report('bench: the report is written', os.path.isfile(os.path.join(work, 'performance.md')))
