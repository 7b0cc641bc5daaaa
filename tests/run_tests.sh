#!/usr/bin/env bash
# Run every unit suite (build/tests/test_*) and every scene test (tests/scenes/*.sh), count the
# PASS/FAIL lines they print, and end with the line `N passed, M failed`.
# A suite that exits non-zero without printing a FAIL line counts as one failure (a crash).
# With an argument (make test T=NAME) only the suites whose name contains NAME run: unit suites
# are named test_<module>, scene tests scene_<case> (tests/scenes/<case>/check.py).
set -u
only=${1:-}
cd "$(dirname "$0")/.."
log=$(mktemp -d)
pass=0; fail=0
run_one() {  # name, command...
  local name=$1; shift
  case "$name" in *"$only"*) ;; *) return 0 ;; esac
  local out="$log/$name.out"
  "$@" >"$out" 2>&1
  local rc=$?
  local p f
  p=$(grep -c '^PASS ' "$out"); f=$(grep -c '^FAIL ' "$out")
  grep -E '^(FAIL|CRASH) ' "$out" | sed "s/^/[$name] /"
  if [ $rc -ne 0 ] && [ "$f" -eq 0 ]; then
    echo "[$name] CRASH exit code $rc; last lines:"; tail -5 "$out" | sed 's/^/    /'
    f=1
  fi
  printf '%-28s %4d passed, %d failed\n' "$name" "$p" "$f"
  pass=$((pass + p)); fail=$((fail + f))
}
for t in build/tests/test_*; do
  [ -x "$t" ] || continue
  run_one "$(basename "$t")" "$t"
done
# Regression scenes: tests/scenes/<case>/check.py (Debian's python3 with numpy), run from the root.
for s in tests/scenes/*/check.py; do
  [ -f "$s" ] || continue
  run_one "scene_$(basename "$(dirname "$s")")" /usr/bin/python3 "$s"
done
rm -rf "$log"
if [ -n "$only" ] && [ $((pass + fail)) -eq 0 ]; then
  echo "no test suite matches T=$only"; fail=1
fi
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
