#!/usr/bin/env bash
# Heap allocations per time step of bin/rebond ("no allocation in the time loop",
# docs/performance.md).
#
#   tools/alloc_per_step.sh [--mode "MODES"] SCENE [N [--set P=V ...]]
#   tools/alloc_per_step.sh --where[=MODE] SCENE [N [--set P=V ...]]
#
# Runs SCENE under valgrind (memcheck, whose exit summary counts every malloc/new:
# "total heap usage: A allocs") for N and 2N steps (TIME.END = START + k STEP; default N = 20)
# and prints (A(2N) - A(N)) / N, the allocations per step once the set-up costs cancel, in three
# output modes:
#   scene       the scene's own OUTPUT (history.csv/probes.csv lines, fields.h5 every k steps)
#   history     the scene's HISTORY, no fields.h5 (OUTPUT.FIELDS=0)
#   none        no output in the loop (OUTPUT.HISTORY=0, OUTPUT.FIELDS=0): the time loop itself
# (--mode "none" measures only the listed modes). Output lines:  SCENE  MODE  A(N)  A(2N)  per-step
# --where[=MODE]: instead, which call stacks allocate in the extra N steps, in MODE (default
# none): valgrind --xtree-memory=full (massif-format tree, allocated blocks per stack) for both
# runs, the difference per step, largest first, each stack shown as the allocating library
# function (if not ours) <- the rebond frames file:line ("???": a library without symbols,
# e.g. libgfortran's I/O).
# Extra --set arguments go to both runs (e.g. --set SCHEME.ITERATION=TANGENT). Needs valgrind.
set -u
cd "$(dirname "$0")/.."
where=0; wmode=none; modes="scene history none"
while [ $# -gt 0 ]; do
  case $1 in
    --where) where=1; shift;;
    --where=*) where=1; wmode=${1#--where=}; shift;;
    --mode) modes=${2:-}; shift 2;;
    *) break;;
  esac
done
for m in $wmode $modes; do
  case $m in scene|history|none) ;; *) echo "output modes: scene, history, none (got '$m')" >&2; exit 2;; esac
done
[ $# -ge 1 ] || { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 2; }
scene=$1; n=${2:-20}; shift; [ $# -gt 0 ] && shift
extra=("$@")
command -v valgrind >/dev/null || { echo "valgrind missing: apt-get install valgrind" >&2; exit 1; }
[ -x bin/rebond ] || { echo "bin/rebond not built (make)" >&2; exit 1; }
[ -f "$scene" ] || { echo "no scene $scene" >&2; exit 1; }
case $n in ''|*[!0-9]*|0) echo "N must be a positive integer, got '$n'" >&2; exit 2;; esac

# TIME STEP and START: from --set if given, else from the scene's TIME statement.
time_param() {  # PARAM DEFAULT
  local s v=""
  for s in "${extra[@]}"; do case $s in TIME.$1=*) v=${s#TIME.$1=};; esac; done
  [ -z "$v" ] && v=$(awk -v p="$1" 'toupper($1) == "TIME" { for (i = 2; i < NF; i++)
    if (toupper($i) == p) { print $(i + 1); exit } }' "$scene")
  echo "${v:-$2}"
}
step=$(time_param STEP "")
start=$(time_param START 0)
[ -n "$step" ] || { echo "$scene: no TIME STEP" >&2; exit 1; }

tmp=$(mktemp -d /tmp/rebond_alloc.XXXXXX)
trap 'rm -rf "$tmp"' EXIT

# run STEPS TAG VALGRIND-ARGS... -> total allocations on stdout ("" on failure)
run() {
  local k=$1 tag=$2 end; shift 2
  end=$(awk -v t0="$start" -v h="$step" -v k="$k" 'BEGIN { printf "%.17g", t0 + k * h }')
  local args=(--set "TIME.END=$end")
  local s
  for s in "${extra[@]}"; do [ "$s" = --set ] || args+=(--set "$s"); done
  case $tag in
    history) args+=(--set OUTPUT.FIELDS=0) ;;
    none) args+=(--set OUTPUT.HISTORY=0 --set OUTPUT.FIELDS=0) ;;
  esac
  valgrind --undef-value-errors=no --log-file="$tmp/vg_${tag}_$k.log" "$@" \
    bin/rebond "$scene" -o "$tmp/out_${tag}_$k" --quiet "${args[@]}" >"$tmp/rebond_${tag}_$k.log" 2>&1
  local rc=$?
  if [ $rc -ne 0 ]; then
    echo "rebond failed (exit $rc) under valgrind: $scene ${args[*]}" >&2
    tail -5 "$tmp/rebond_${tag}_$k.log" >&2
    return 1
  fi
  sed -n 's/.*total heap usage: \([0-9,]*\) allocs.*/\1/p' "$tmp/vg_${tag}_$k.log" | tr -d ,
}

if [ $where -eq 1 ]; then
  for k in "$n" $((2 * n)); do
    run "$k" "$wmode" --num-callers=60 --xtree-memory=full --xtree-memory-file="$tmp/xt_$k.ms" >/dev/null || exit 1
  done
  echo "allocations per step in $scene, output mode $wmode, by call stack ($n extra steps):"
  python3 - "$tmp/xt_$n.ms" "$tmp/xt_$((2 * n)).ms" "$n" <<'EOF_PY'
import re, sys
NODE = re.compile(r'^( *)n(\d+): (\d+) (.*)$')

def stacks(path):
    """Allocation counts (snapshot 'totBk') per call stack, from valgrind's xtree massif file."""
    out, snap, stack, kids = {}, None, [], []
    for line in open(path):
        if line.startswith('snapshot='):
            snap = None
            continue
        m = NODE.match(line.rstrip('\n'))
        if not m:
            continue
        depth, value, label = len(m.group(1)), int(m.group(3)), m.group(4)
        if depth == 0:
            snap = 'totBk' in label
            stack, kids = [], []
            continue
        if not snap:
            continue
        del stack[depth - 1:], kids[depth - 1:]
        if stack:
            kids[-1] += value          # what the parent passes on to its children
        frame = re.sub(r'^0x[0-9A-F]+: ', '', label)
        stack.append((frame, value))
        kids.append(0)
        if int(m.group(2)) == 0:       # leaf: the whole stack
            key = tuple(f for f, _ in stack)
            out[key] = out.get(key, 0) + value
    return out

a, b, n = stacks(sys.argv[1]), stacks(sys.argv[2]), int(sys.argv[3])
rows = sorted(((b.get(k, 0) - a.get(k, 0), k) for k in set(a) | set(b)), key=lambda r: -r[0])
ours = re.compile(r'\((\w+\.(f90|c)):(\d+)\)')
total = 0
for d, k in rows:
    if d <= 0:
        continue
    total += d
    own = [ours.search(f) for f in k]
    own = ['%s %s:%s' % (f.split(' (')[0].split(': ')[-1], m.group(1), m.group(3)) for f, m in zip(k, own) if m]
    lib = k[0].split(' (')[0] if not ours.search(k[0]) else ''
    print('%9.2f  %s%s' % (d / n, (lib + ' <- ') if lib else '', ' <- '.join(own[:4])))
print('%9.2f  total' % (total / n))
EOF_PY
  exit 0
fi

for tag in $modes; do
  a1=$(run "$n" "$tag") || exit 1
  a2=$(run $((2 * n)) "$tag") || exit 1
  awk -v s="$scene" -v t="$tag" -v a="$a1" -v b="$a2" -v n="$n" \
    'BEGIN { printf "%-40s %-8s %9d %9d %10.2f\n", s, t, a, b, (b - a) / n }'
done
