#!/usr/bin/env bash
# Where the augmented multiplier system pays (`make bench`, docs/performance.md).
#
# A steel slab (QUAD4, plane strain) lands flat on a rigid ground: every node of its bottom
# edge (nx + 1 conditions) closes within a few steps and stays closed. The same run with
# SCHEME MULTIPLIERS SCHUR and AUGMENTED, for growing nx (active-set size) at two mesh
# depths (ny) gives the wall time of the run; the run without contact (no OBSTACLE) is the
# baseline. The table goes to BENCH_CONTACT_OUT.
#
# Environment:
#   BENCH_CONTACT_NX    bottom-edge element counts, default "16 32 64 128 256 512 1024"
#   BENCH_CONTACT_NY    element counts through the depth, default "2 16"
#   BENCH_CONTACT_STEPS time steps per run, default 40
#   BENCH_CONTACT_IMPACTS regimes, default "PERSIST OFF": PERSIST (the bottom closes once and
#                       stays closed) and OFF (plain Newmark: the lumped-mass bottom nodes chatter,
#                       the active set changes at almost every step)
#   BENCH_CONTACT_REPEATS runs per case, the fastest kept (default 3)
#   BENCH_CONTACT_MIXED_NX bottom-edge element counts of the mixed-mass table, default "128 512"
#   BENCH_CONTACT_OUT   report file, default: print only
set -euo pipefail
cd "$(dirname "$0")/.."
NXS=${BENCH_CONTACT_NX:-"16 32 64 128 256 512 1024"}
NYS=${BENCH_CONTACT_NY:-"2 16"}
STEPS=${BENCH_CONTACT_STEPS:-40}
IMPACTS=${BENCH_CONTACT_IMPACTS:-"PERSIST OFF"}
REPEATS=${BENCH_CONTACT_REPEATS:-3}
MIXED_NXS=${BENCH_CONTACT_MIXED_NX:-"128 512"}
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
MODEL     slab MATERIAL steel SECTION strip MASS ${MASS:-LUMPED} PLANE STRAIN
INITIAL   slab VELOCITY 0 -1
TIME      STEP 1e-6 END $(awk "BEGIN{print 1e-6*$STEPS}")
SCHEME    IMPACT $IMPACT MULTIPLIERS $solver
OUTPUT    HISTORY EVERY 1 FIELDS EVERY 0
SCN
  [[ $contact == 1 ]] && echo "OBSTACLE  ground NODES slab.bottom POINT 0 0 NORMAL 0 1"
  return 0
}

run() {   # file outdir -> "seconds", the best of BENCH_CONTACT_REPEATS runs
  local f=$1 d=$2 t0 t1 best=1e9 k
  for ((k = 0; k < REPEATS; k++)); do
    rm -rf "$d"
    t0=$(date +%s.%N)
    bin/rebond "$f" -o "$d" > "$d.log" 2>&1 || { echo "bench_contact: $f failed:" >&2; cat "$d.log" >&2; exit 1; }
    t1=$(date +%s.%N)
    best=$(awk "BEGIN{t = $t1 - $t0; print (t < $best) ? t : $best}")
  done
  awk "BEGIN{printf \"%.3f\", $best}"
}

table() {
  echo "### IMPACT $IMPACT"
  echo
  echo "$STEPS steps of 1 us; bin/rebond wall time including start-up, best of $REPEATS runs."
  echo
  echo "| ny | DOFs | max active | no contact (s) | SCHUR (s) | AUGMENTED (s) | faster |"
  echo "|---:|---:|---:|---:|---:|---:|:--|"
  for ny in $NYS; do
    for nx in $NXS; do
      scene "$nx" "$ny" 0 AUTO > "$WORK/free.dat"
      scene "$nx" "$ny" 1 SCHUR > "$WORK/schur.dat"
      scene "$nx" "$ny" 1 AUGMENTED > "$WORK/aug.dat"
      tf=$(run "$WORK/free.dat" "$WORK/o.free")
      ts=$(run "$WORK/schur.dat" "$WORK/o.schur")
      act=$(awk -F, 'NR==1{for(i=1;i<=NF;i++) if($i=="active_contacts") c=i} NR>1 && $c>a{a=$c} END{print a+0}' \
        "$WORK/o.schur/history.csv")
      ta=$(run "$WORK/aug.dat" "$WORK/o.aug")
      dofs=$(( 2 * (nx + 1) * (ny + 1) ))
      best=$(awk "BEGIN{print ($ts <= $ta) ? \"SCHUR\" : \"AUGMENTED\"}")
      echo "| $ny | $dofs | $act | $tf | $ts | $ta | $best |"
    done
  done
}

cpu() {   # file outdir impact -> "user + system seconds", the best of BENCH_CONTACT_REPEATS runs
  local f=$1 d=$2 best=1e9 k t
  for ((k = 0; k < REPEATS; k++)); do
    rm -rf "$d"
    /usr/bin/time -f '%U %S' -o "$d.time" bin/rebond "$f" -o "$d" --set "SCHEME.IMPACT=$3" > "$d.log" 2>&1 || \
      { echo "bench_contact: $f failed:" >&2; cat "$d.log" >&2; exit 1; }
    t=$(awk '{print $1 + $2}' "$d.time")
    best=$(awk "BEGIN{print ($t < $best) ? $t : $best}")
  done
  awk "BEGIN{printf \"%.2f\", $best}"
}

# The impact correction on a mixed (non-diagonal) mass: PERSIST's projection takes one solve with
# M per active condition; SYMMETRIC lumps the contact rows, so its projection and release impulses
# are read from the rows (no solve). 200 steps: the slab lands, stays down ~2 depth transits, leaves.
mixed_table() {
  echo "### The impact correction on a mixed mass (MASS MIXED)"
  echo
  echo "200 steps of 1 us (landing, contact, release); CPU time (user + system) of the run, best of $REPEATS."
  echo
  echo "| ny | DOFs | conditions | no contact (s) | PERSIST (s) | SYMMETRIC (s) |"
  echo "|---:|---:|---:|---:|---:|---:|"
  local ny=16 nx
  for nx in $MIXED_NXS; do
    STEPS=200 MASS=MIXED scene "$nx" "$ny" 0 AUTO > "$WORK/mfree.dat"
    STEPS=200 MASS=MIXED scene "$nx" "$ny" 1 AUTO > "$WORK/mixed.dat"
    tf=$(cpu "$WORK/mfree.dat" "$WORK/o.mfree" AUTO)
    tp=$(cpu "$WORK/mixed.dat" "$WORK/o.mp" PERSIST)
    ts=$(cpu "$WORK/mixed.dat" "$WORK/o.ms" SYMMETRIC)
    echo "| $ny | $(( 2 * (nx + 1) * (ny + 1) )) | $((nx + 1)) | $tf | $tp | $ts |"
  done
}

report() {
  cat <<HDR
# Contact multipliers: Schur columns or the augmented system

Generated by \`bash tools/bench_contact.sh\` (\`make bench\`) at commit $(git rev-parse --short HEAD 2>/dev/null || echo -),
$(date -u +%Y-%m-%d), on $(nproc) cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')).
A steel slab (QUAD4, plane strain, lumped mass) lands flat on a rigid ground at 1 m/s: its
nx + 1 bottom nodes are the candidates and all close. Each row is the same run with
\`SCHEME MULTIPLIERS SCHUR\` and \`AUGMENTED\` (docs/contact.md), and without the OBSTACLE.
How to read it and the choice of \`AUGMENTED_ABOVE\`: docs/contact.md, "Multipliers".

HDR
  for IMPACT in $IMPACTS; do
    table
    echo
  done
  IMPACT=AUTO mixed_table
  echo
}

if [[ -n $OUT ]]; then
  report | tee "$OUT"
else
  report
fi
