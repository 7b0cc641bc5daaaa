#!/usr/bin/env bash
# Reliability checks (docs/reliability.md); called by `make check-debug` and `make valgrind`.
#
#   tools/check_debug.sh                     debug tree: build, every unit suite, every scene
#   tools/check_debug.sh --valgrind SCENE... memcheck short runs of bin/rebond (normal -O2 -g);
#                                            a .sweep file runs `bin/rebond sweep` (suppressions:
#                                            tools/valgrind.supp, Open MPI only)
#
# Debug mode builds build-debug/ and bin/rebond-debug with -fcheck=all and FPE traps (flags
# from the Makefile: DEBUG_BUILD, DEBUG_BIN, DEBUG_FFLAGS, DEBUG_CFLAGS), so bin/rebond and
# build/ are never touched. A run fails on a non-zero exit, a FAIL line of a suite, a Fortran
# run-time error (bounds, shapes, allocation, pointer, recursion, do-loop) or a trapped
# floating-point exception (SIGFPE: invalid, division by zero, overflow). Run-time warnings
# (array temporaries) are counted and shown, not fatal. Ends with "N passed, M failed".
set -u
cd "$(dirname "$0")/.."
MAKE=${MAKE:-make}
DEBUG_BUILD=${DEBUG_BUILD:-build-debug}
DEBUG_BIN=${DEBUG_BIN:-bin/rebond-debug}
DEBUG_FFLAGS=${DEBUG_FFLAGS:--g -O0 -fcheck=all -ffpe-trap=invalid,zero,overflow -fbacktrace}
DEBUG_CFLAGS=${DEBUG_CFLAGS:--g -O0}
# What makes a run fail besides its exit status (gfortran run-time library and -fbacktrace).
FATAL_RE='Fortran runtime error|Program received signal|Backtrace for this error|Floating-point exception|ERROR STOP'

log=$(mktemp -d /tmp/rebond_check_debug.XXXXXX)
trap 'rm -rf "$log"' EXIT
pass=0; fail=0

# verdict NAME RC OUTFILE [EXPECT_FAIL_LINES]: PASS/FAIL line from the exit status and the output.
verdict() {
  local name=$1 rc=$2 out=$3 why=''
  local nwarn
  nwarn=$(grep -c 'Fortran runtime warning' "$out")
  if grep -Eq "$FATAL_RE" "$out"; then why='run-time check or FPE'
  elif grep -q '^FAIL ' "$out"; then why='assertion FAIL'
  elif [ "$rc" -ne 0 ]; then why="exit code $rc"
  fi
  if [ -z "$why" ]; then
    pass=$((pass + 1))
    printf 'PASS %-58s%s\n' "$name" "$([ "$nwarn" -gt 0 ] && echo " ($nwarn run-time warnings)")"
  else
    fail=$((fail + 1))
    printf 'FAIL %-58s %s; output:\n' "$name" "$why"
    grep -E "$FATAL_RE|^FAIL |^#[0-9]+ |^[[:space:]]+at |At line [0-9]+ of file|rebond: " "$out" | head -40 | sed 's/^/    /'
    grep -Eq "$FATAL_RE|^FAIL " "$out" || tail -8 "$out" | sed 's/^/    /'
  fi
}

# The scenes and how long to run them. Default: 20 steps. Longer where the interesting path
# starts later: contact scenes run through the first impact (establishment, the hzero step,
# persistence, release), plastic scenes until the material yields. Columns:
#   scene | TIME.END | further --set, blank-separated | why
SCENE_TABLE=$(cat <<'EOF'
inputs/bar_impact.dat | 6e-4 | | impact at 1e-4 s, contact 3.85e-4 s: through the release
inputs/bar_impact.dat | 6e-4 | SCHEME.IMPACT=PERSIST | the same, PERSIST treatment
inputs/bar_impact.dat | 6e-4 | SCHEME.IMPACT=OFF | the same, plain unilateral contact
inputs/beam_drop_vertical.dat | 0.07 | | impact at 0.0639 s at the scene's h = 1e-5 s
inputs/beam_drop_vertical.dat | 0.2 | TIME.STEP=1e-4 SCHEME.IMPACT=PERSIST | first rebound, PERSIST, coarse h
inputs/beam_drop_vertical_quad.dat | 0.07 | | QUAD8 bottom edge hits at 0.0639 s
inputs/beam_drop_inclined.dat | 0.3 | TIME.STEP=1e-4 | lower end hits at 0.0639 s, then the clatter
inputs/beam_land_flat.dat | 0.1 | TIME.STEP=1e-4 | 21 simultaneous impacts at 0.0639 s
inputs/beams_collide.dat | 1e-3 | | ends meet at 6.15e-4 s, contact 1.93e-4 s (GAP)
inputs/mass_bounce.dat | 2 | | impacts at 0.45 s and 1.35 s, apex in between
inputs/block_j2.dat | 1.5e-3 | | J2 yields under the 1 ms ramp and hold
inputs/cantilever_plastic.dat | 0.1 | | the root yields in the first quarter period (~0.075 s)
inputs/spring_plastic.dat | 0.04 | | yields at 3.3 ms, flows, unloads at ~15 ms
inputs/spring_nonlinear.dat | 0.5 | | one nonlinear period (0.48 s)
inputs/cantilever_release.dat | | | linear beam, 20 steps
inputs/cantilever_release.dat | | SCHEME.PRECISION=EXTENDED | extended-precision path, 20 steps
tests/scenes/contact_nonlinear/bar_drop.dat | 0.02 | | nonlinear bar hits at 5e-3 s, contact and release
tests/scenes/fibre_moment/moment.dat | 4.5 | | fibres yield at ~2.6 s, the whole ramp
EOF
)

# Scenes built to blow up (the run must stop cleanly in production; see run_scene).
BLOWUP_SCENES='tests/scenes/restart/nan.dat'

# STEP of a scene (its TIME statement) or of a TIME.STEP override.
scene_step() {
  local scene=$1 sets=$2 s
  for s in $sets; do
    case $s in TIME.STEP=*) echo "${s#TIME.STEP=}"; return;; esac
  done
  awk 'toupper($1) == "TIME" { for (i = 2; i < NF; i++) if (toupper($i) == "STEP") { print $(i + 1); exit } }' "$scene"
}

# run_scene SCENE END SETS [EXPECT [OUTDIR [ARGS...]]]: one debug run. EXPECT ok (default) or
# blowup (a scene built to diverge: it must stop non-zero, by its "diverged" message or by the
# trapped overflow of the diverging iterate; bounds and other run-time errors still fail).
run_scene() {
  local scene=$1 end=$2 sets=$3 expect=${4:-ok} outdir=${5:-$log/out} step nsteps every name out rc
  shift 5 2>/dev/null || shift $#
  step=$(scene_step "$scene" "$sets")
  if [ -z "$end" ]; then end=$(awk -v h="$step" 'BEGIN { printf "%.6g", 20 * h }'); fi
  nsteps=$(awk -v h="$step" -v t="$end" 'BEGIN { printf "%d", t / h + 0.5 }')
  every=$(( nsteps / 10 )); [ "$every" -lt 1 ] && every=1
  local args=(--set "TIME.END=$end" --set "OUTPUT.FIELDS=$every") s
  for s in $sets; do args+=(--set "$s"); done
  name="$scene${sets:+ [$sets]}${1:+ $1} ${nsteps} steps"
  out="$log/run.out"
  # Not --quiet: the banner and the summary are printed too (and checked).
  "$DEBUG_BIN" "$scene" -o "$outdir" "${args[@]}" "$@" >"$out" 2>&1
  rc=$?
  if [ "$expect" = blowup ]; then
    if [ "$rc" -ne 0 ] && ! grep -q 'Fortran runtime error' "$out" && \
       { grep -q 'diverged' "$out" || grep -q 'SIGFPE' "$out"; }; then
      pass=$((pass + 1)); printf 'PASS %-58s (blows up as designed: %s)\n' "$name" \
        "$(grep -q SIGFPE "$out" && echo 'trapped FPE' || echo 'diverged, exit '$rc)"
    else
      verdict "$name (must blow up)" 1 "$out"
    fi
  else
    verdict "$name" "$rc" "$out"
  fi
  [ "$outdir" = "$log/out" ] && rm -rf "$outdir"
}

debug_mode() {
  local tests=() t f
  for f in tests/unit/test_*.f90; do tests+=("$DEBUG_BUILD/tests/$(basename "$f" .f90)"); done
  echo "== build $DEBUG_BIN and ${#tests[@]} unit suites in $DEBUG_BUILD/ ($DEBUG_FFLAGS)"
  if ! FFLAGS="$DEBUG_FFLAGS" CFLAGS="$DEBUG_CFLAGS" $MAKE --no-print-directory BUILD="$DEBUG_BUILD" \
      BIN="$DEBUG_BIN" "$DEBUG_BIN" "${tests[@]}" >"$log/build.out" 2>&1; then
    grep -E 'Error|error:' -A3 "$log/build.out" | head -40
    echo "debug build failed (full log: make output above)"; exit 1
  fi
  echo "== unit suites"
  for t in "${tests[@]}"; do
    "$t" >"$log/unit.out" 2>&1
    verdict "$(basename "$t")" $? "$log/unit.out"
  done
  echo "== scenes (TIME.END shortened, OUTPUT FIELDS ~ every tenth step)"
  local listed=' ' scene end sets why
  while IFS='|' read -r scene end sets why; do
    scene=$(echo $scene); end=$(echo $end); sets=$(echo $sets)
    [ -f "$scene" ] || { echo "FAIL $scene: listed in tools/check_debug.sh but missing"; fail=$((fail + 1)); continue; }
    listed+="$scene "
    run_scene "$scene" "$end" "$sets"
  done <<<"$SCENE_TABLE"
  for scene in $BLOWUP_SCENES; do
    [ -f "$scene" ] || continue
    listed+="$scene "
    run_scene "$scene" '' '' blowup
  done
  # Every other scene file: 20 steps. tests/scenes/extremes/ is run by its matrix below, with
  # the parameters and the expected outcome (some cases must be refused) of each case.
  for scene in inputs/*.dat tests/scenes/*/*.dat; do
    case $scene in tests/scenes/extremes/*) continue;; esac
    case $listed in *" $scene "*) continue;; esac
    run_scene "$scene" '' ''
  done
  # Checkpoint and restart (HDF5 state, history resume): through the bar's contact.
  if "$DEBUG_BIN" --help 2>&1 | grep -q -- '--restart'; then
    echo "== checkpoint and restart"
    run_scene inputs/bar_impact.dat 2e-4 'OUTPUT.CHECKPOINT=50' ok "$log/rs"
    run_scene inputs/bar_impact.dat 6e-4 'OUTPUT.CHECKPOINT=50' ok "$log/rs" --restart "$log/rs/checkpoint.h5"
    rm -rf "$log/rs"
  fi
  # Stability at the extremes (tests/extremes/matrix.py --fast) with the debug binary: each case
  # must end as the matrix expects (finite and within its bound, or refused with its exit status
  # and message); a trapped FPE or a run-time error is a crash there (SIGFPE, exit -8).
  if [ -f tests/extremes/matrix.py ]; then
    echo "== extremes matrix (fast subset)"
    REBOND="$DEBUG_BIN" /usr/bin/python3 tests/extremes/matrix.py --fast >"$log/mx.out" 2>&1
    verdict "tests/extremes/matrix.py --fast ($(grep -c '^PASS' "$log/mx.out") checks)" $? "$log/mx.out"
  fi
  # Hostile input under the traps (issue 12): the bad-input, hostile-input, full-disk and fuzz
  # regression checks on the debug binary; a trapped overflow in the input handling, a bounds
  # error or a crash fails them.
  echo "== hostile input, full disk and fuzz regression (tests/scenes/{bad_input,hostile,full_disk,fuzz})"
  for c in bad_input hostile full_disk fuzz; do
    [ -f "tests/scenes/$c/check.py" ] || continue
    REBOND="$DEBUG_BIN" FUZZ_SKIP="$BLOWUP_SCENES" /usr/bin/python3 "tests/scenes/$c/check.py" >"$log/hi.out" 2>&1
    verdict "tests/scenes/$c/check.py ($(grep -c '^PASS' "$log/hi.out") checks)" $? "$log/hi.out"
  done
  # The sweep driver (docs/sweep.md), in one process and under mpirun: the bouncing-mass study,
  # cut to 1 s. The other studies/*.sweep include cases that diverge by design (e.g. ITERATION
  # ELASTIC at h = T): under -ffpe-trap their overflow stops the whole sweep (see reliability.md).
  local f=studies/mass_bounce.sweep
  if [ -f "$f" ]; then
    echo "== sweep $f (TIME.END=1)"
    "$DEBUG_BIN" sweep "$f" -o "$log/sw" --set TIME.END=1 >"$log/sw.out" 2>&1
    verdict "sweep $f" $? "$log/sw.out"; rm -rf "$log/sw"
    if command -v mpirun >/dev/null; then
      OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -np 3 \
        "$DEBUG_BIN" sweep "$f" -o "$log/sw" --set TIME.END=1 >"$log/sw.out" 2>&1
      verdict "sweep $f (mpirun -np 3)" $? "$log/sw.out"; rm -rf "$log/sw"
    fi
  fi
}

valgrind_mode() {
  command -v valgrind >/dev/null || { echo "valgrind missing: apt-get install valgrind"; exit 1; }
  local vg=(valgrind --tool=memcheck --leak-check=full --errors-for-leak-kinds=definite
            --error-exitcode=3 --num-callers=40 --track-origins=yes)
  [ -f tools/valgrind.supp ] && vg+=(--suppressions=tools/valgrind.supp)
  local scene end cmd
  for scene in "$@"; do
    # Short runs: through the first impact for the bouncing mass, 50 steps otherwise; a sweep
    # file (rebond sweep: MPI_Init, every case, the tables) with every case cut to 0.5 s.
    case $scene in
      *.sweep) end=0.5; cmd=(bin/rebond sweep "$scene") ;;
      *mass_bounce.dat) end=0.5; cmd=(bin/rebond "$scene") ;;
      *) end=$(awk -v h="$(scene_step "$scene" '')" 'BEGIN { printf "%.6g", 50 * h }'); cmd=(bin/rebond "$scene") ;;
    esac
    "${vg[@]}" "${cmd[@]}" -o "$log/out" --quiet --set "TIME.END=$end" --set "OUTPUT.FIELDS=10" >"$log/vg.out" 2>&1
    local rc=$?
    if [ $rc -eq 0 ] && grep -q 'ERROR SUMMARY: 0 errors' "$log/vg.out"; then
      pass=$((pass + 1))
      echo "PASS valgrind ${cmd[*]:1} (TIME.END=$end): $(grep -E 'definitely lost|ERROR SUMMARY' "$log/vg.out" \
        | sed 's/^==[0-9]*== *//' | tr '\n' ' ')"
    else
      fail=$((fail + 1))
      echo "FAIL valgrind ${cmd[*]:1} (TIME.END=$end): exit code $rc"
      grep -E '^==[0-9]+==' "$log/vg.out" | sed 's/^/    /' | head -150
    fi
    rm -rf "$log/out"
  done
}

if [ "${1:-}" = "--valgrind" ]; then
  shift
  valgrind_mode "$@"
else
  debug_mode
fi
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
