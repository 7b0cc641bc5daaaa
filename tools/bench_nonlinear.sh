#!/usr/bin/env bash
# Nonlinear-material benchmark (issue 3), run by `make bench` after tools/bench.sh.
#
# Cost per step versus SUBSTEPS with and without the energy correction, versus the size of the
# plastic zone, and the energy error versus the time step (Markdown table + PNG plot).
# Takes 1 to 3 minutes.
#
# Environment:
#   BENCH_NL_OUT     report file, default docs/nonlinear-performance.md
#   BENCH_NL_PNG     plot, default docs/energy-vs-step.png
#   BENCH_NL_REPEATS runs per timed case, best taken (default 2)
#   BENCH_WORK       scratch directory, default a fresh mktemp -d
#   REBOND           the binary, default bin/rebond
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${BENCH_NL_OUT:-docs/nonlinear-performance.md}
PNG=${BENCH_NL_PNG:-docs/energy-vs-step.png}
WORK=${BENCH_WORK:-$(mktemp -d "${TMPDIR:-/tmp}/rebond-bench-nl.XXXXXX")}
BIN=${REBOND:-bin/rebond}
if [[ ! -x $BIN ]]; then
  echo "bench_nonlinear: $BIN is missing: run make first" >&2
  exit 2
fi
/usr/bin/python3 tools/bench/bench_nonlinear.py "$BIN" "$OUT" "$PNG" "$WORK/nl"
echo "bench_nonlinear: report written to $OUT, plot $PNG (scratch files in $WORK)"
