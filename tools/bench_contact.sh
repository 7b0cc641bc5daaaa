#!/usr/bin/env bash
# Where the augmented multiplier system pays (`make bench`, docs/performance.md).
#
# A steel slab (QUAD4, plane strain) lands flat on a rigid ground: every node of its bottom
# edge (nx + 1 conditions) closes within a few steps and stays closed. The same run with
# SCHEME MULTIPLIERS SCHUR and AUGMENTED, for growing nx (active-set size) at two mesh
# depths (ny), in IMPACT PERSIST (the contact holds), gives the wall time of the run and the multiplier counters; the run without
# contact (no OBSTACLE) is the baseline. The table goes to BENCH_CONTACT_OUT.
#
# Environment:
#   BENCH_CONTACT_NX    bottom-edge element counts, default "16 32 64 128 256 512"
#   BENCH_CONTACT_NY    element counts through the depth, default "4 32"
#   BENCH_CONTACT_STEPS time steps per run, default 40
#   BENCH_CONTACT_OUT   report file, default: print only
set -euo pipefail
cd "$(dirname "$0")/.."
NXS=${BENCH_CONTACT_NX:-"16 32 64 128 256 512"}
NYS=${BENCH_CONTACT_NY:-"4 32"}
STEPS=${BENCH_CONTACT_STEPS:-40}
OUT=${BENCH_CONTACT_OUT:-}
WORK=$(mktemp -d "${TMPDIR:-/tmp}/rebond-bench-contact.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
[[ -x bin/rebond ]] || { echo "bench_contact: bin/rebond is missing: run make first" >&2; exit 2; }

scene() {   # nx ny contact(0/1) solver
  local nx=$1 ny=$2 contact=$3 solver=$4
  # Slab 0.05 m per bottom element long, 0.2 m deep, 1 um above the ground, falling at 1 m/s:
  # the bottom closes in the first step and stays closed for the run (contact lasts ~2 depth
  # transits of the wave, 80 us = 80 steps of 1 us).
  cat <<SCN
TITLE     "bench: slab landing flat, nx=$nx ny=$ny"
RECTANGLE slab ORIGIN 0 1e-6 SIZE $(awk "BEGIN{print 0.05*$nx}") 0.2 ELEMENTS $nx $ny TYPE QUAD4
MATERIAL  steel ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800
SECTION   strip THICKNESS 1
MODEL     slab MATERIAL steel SECTION strip MASS LUMPED PLANE STRAIN
INITIAL   slab VELOCITY 0 -1
TIME      STEP 1e-6 END $(awk "BEGIN{print 1e-6*$STEPS}")
SCHEME    IMPACT PERSIST MULTIPLIERS $solver
OUTPUT    HISTORY EVERY 1 FIELDS EVERY 0
SCN
  [[ $contact == 1 ]] && echo "OBSTACLE  ground NODES slab.bottom POINT 0 0 NORMAL 0 1"
  return 0
}

run() {   # file outdir -> "seconds"
  local f=$1 d=$2 t0 t1
  t0=$(date +%s.%N)
  bin/rebond "$f" -o "$d" > "$d.log" 2>&1 || { echo "bench_contact: $f failed:" >&2; cat "$d.log" >&2; exit 1; }
  t1=$(date +%s.%N)
  awk "BEGIN{printf \"%.3f\", $t1 - $t0}"
}

report() {
  echo "| ny | DOFs | active | no contact (s) | SCHUR (s) | AUGMENTED (s) | faster |"
  echo "|---:|---:|---:|---:|---:|---:|:--|"
  for ny in $NYS; do
    for nx in $NXS; do
      scene "$nx" "$ny" 0 AUTO > "$WORK/free.dat"
      scene "$nx" "$ny" 1 SCHUR > "$WORK/schur.dat"
      scene "$nx" "$ny" 1 AUGMENTED > "$WORK/aug.dat"
      tf=$(run "$WORK/free.dat" "$WORK/o.free")
      ts=$(run "$WORK/schur.dat" "$WORK/o.schur")
      act=$(awk -F, 'NR==1{for(i=1;i<=NF;i++) if($i=="active_contacts") c=i} NR>1{a=$c} END{print a}' \
        "$WORK/o.schur/history.csv")
      ta=$(run "$WORK/aug.dat" "$WORK/o.aug")
      dofs=$(( 2 * (nx + 1) * (ny + 1) ))
      best=$(awk "BEGIN{print ($ts <= $ta) ? \"SCHUR\" : \"AUGMENTED\"}")
      echo "| $ny | $dofs | $act | $tf | $ts | $ta | $best |"
    done
  done
}

if [[ -n $OUT ]]; then
  report | tee "$OUT"
else
  report
fi
