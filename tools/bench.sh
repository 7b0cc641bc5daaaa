#!/usr/bin/env bash
# QUAD4 plane-strain plate benchmark of the core solver (`make bench`).
#
# Builds tools/bench/bench_plate.f90 against build/librebond.a with the Makefile's compilers,
# flags and libraries, runs it on square plates of about BENCH_SIZES degrees of freedom and
# writes a Markdown report (factorization time, time per step, ratio to one bare CHOLMOD
# solve on the same factor, where the step goes, the machine) to BENCH_OUT.
#
# Environment:
#   BENCH_SIZES  target DOF counts, default "1e3 1e4 1e5 1e6" (the 1e6 case takes minutes)
#   BENCH_DIM    2 (the QUAD4 plate, default) or 3 (a HEX8 block n x n x n, HEX8, docs/performance-3d.md)
#   BENCH_STEPS  time steps per size (default: 200 up to 1e4 DOFs, 50 up to 1e5, 20 above)
#   BENCH_SOLVES bare solves per size, median taken (default 50, 20 above 1e5 DOFs)
#   BENCH_REPEATS rounds of (bare solves, run) per size, best one reported (default 3)
#   BENCH_OUT    report file, default docs/performance.md
#   BENCH_WORK   scratch directory (scenes, binary, logs), default a fresh mktemp -d
#   BENCH_BUILD  directory holding librebond.a and the .mod files, default the Makefile's build/
#   BENCH_COMMIT commit to name in the report, default the repository's HEAD (use with BENCH_BUILD
#                when the library was built from another tree)
set -euo pipefail
cd "$(dirname "$0")/.."

SIZES=${BENCH_SIZES:-"1e3 1e4 1e5 1e6"}
DIM=${BENCH_DIM:-2}
if [[ $DIM == 3 ]]; then OUT=${BENCH_OUT:-docs/performance-3d.md}; else OUT=${BENCH_OUT:-docs/performance.md}; fi
WORK=${BENCH_WORK:-$(mktemp -d "${TMPDIR:-/tmp}/rebond-bench.XXXXXX")}
mkdir -p "$WORK"

# Compilers, flags and libraries as the Makefile has them (its own -J goes to the scratch dir).
PV="$WORK/printvars.mk"
printf 'print-%%:\n\t@echo $($*)\n' > "$PV"
mkvar() { make -s --no-print-directory -f Makefile -f "$PV" "print-$1"; }
FC=$(mkvar FC)
CC=$(mkvar CC)
MKBUILD=$(mkvar BUILD)
BUILD=${BENCH_BUILD:-$MKBUILD}
# The Makefile's -J/-I for its build dir are replaced by ours (modules from $BUILD).
FFLAGS=$(mkvar FFLAGS | sed -E "s#(^| )-J[^ ]+##g; s#(^| )-I$MKBUILD( |\$)#\\2#g")
CFLAGS=$(mkvar CFLAGS)
LDLIBS=$(mkvar LDLIBS)
if [[ ! -f $BUILD/librebond.a ]]; then
  echo "bench: $BUILD/librebond.a is missing: run make first" >&2
  exit 2
fi

BIN="$WORK/bench_plate"
$FC $FFLAGS -I"$BUILD" -J"$WORK" -o "$BIN" tools/bench/bench_plate.f90 "$BUILD/librebond.a" $LDLIBS

# Machine.
CPU=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
NCPU=$(nproc)
CORES=$(lscpu | awk -F: '/^Core\(s\) per socket/ {c=$2} /^Socket\(s\)/ {s=$2} END {printf "%d", c*s}')
MEM=$(awk '/^MemTotal/ {printf "%.1f GiB", $2/1048576}' /proc/meminfo)
BLAS_ALT=$(update-alternatives --query libblas.so.3-x86_64-linux-gnu 2>/dev/null | sed -n 's/^Value: *//p' || true)
BLAS_LINK=$(ldd "$BIN" | awk '/libblas\.so/ {print $3}' | head -1)
BLAS_REAL=$( [[ -n $BLAS_LINK ]] && readlink -f "$BLAS_LINK" || echo "?")
case "$BLAS_REAL" in
  *openblas*) BLAS="OpenBLAS ($BLAS_REAL)";;
  */blas/*) BLAS="reference BLAS ($BLAS_REAL) — factorization will be much slower than with OpenBLAS";;
  *) BLAS="$BLAS_REAL";;
esac
THREADS=${OPENBLAS_NUM_THREADS:-"default (one per CPU)"}
CHOLMOD_PKG=$(dpkg-query -W -f '${Version}' 'libcholmod[0-9]*' 2>/dev/null | head -1 || true)
COMMIT=${BENCH_COMMIT:-$(GIT_OPTIONAL_LOCKS=0 git rev-parse --short HEAD 2>/dev/null || echo "?")}
if [[ -z ${BENCH_COMMIT:-} ]] && [[ $COMMIT != "?" ]] && [[ -n $(GIT_OPTIONAL_LOCKS=0 git status --porcelain --untracked-files=no 2>/dev/null) ]]; then
  COMMIT="$COMMIT (with uncommitted changes)"
fi
DATE=$(date -u '+%Y-%m-%d %H:%M UTC')
echo "bench: $CPU, $NCPU CPUs, $MEM, BLAS: $BLAS"

# Runs.
RESULTS="$WORK/results.txt"
: > "$RESULTS"
for s in $SIZES; do
  n=$(awk -v s="$s" 'BEGIN {printf "%d", s + 0}')
  nx=$(awk -v n="$n" 'BEGIN {x = int(sqrt(n / 2) + 0.5); if (x < 1) x = 1; print x}')
  nz=0
  if [[ $DIM == 3 ]]; then
    nx=$(awk -v n="$n" 'BEGIN {x = int(exp(log(n / 3) / 3) + 0.5) - 1; if (x < 1) x = 1; print x}')
    nz=$nx
  fi
  if (( n <= 10000 )); then steps=200; solves=50
  elif (( n <= 100000 )); then steps=50; solves=50
  else steps=20; solves=20; fi
  steps=${BENCH_STEPS:-$steps}
  solves=${BENCH_SOLVES:-$solves}
  echo "bench: ~$n DOFs: plate $nx x $nx (x $nz in 3D), $steps steps, $solves bare solves"
  args=("$nx" "$nx" "$steps" "$solves" "$WORK" "${BENCH_REPEATS:-3}")
  (( nz > 0 )) && args+=("$nz")                     # (a 7th argument: the HEX8 block's nz)
  "$BIN" "${args[@]}" | tee "$WORK/log_$nx.txt"
  grep '^RESULT ' "$WORK/log_$nx.txt" >> "$RESULTS"
done

# Report.
python3 - "$RESULTS" "$OUT" "$CPU" "$NCPU" "$CORES" "$MEM" "$BLAS" "$THREADS" "$CHOLMOD_PKG" "$COMMIT" "$DATE" "$DIM" <<'PY'
import sys
res, out, cpu, ncpu, cores, mem, blas, threads, chol, commit, date, dim = sys.argv[1:13]
rows = []
for line in open(res):
    d = dict(kv.split('=', 1) for kv in line.split()[1:])
    rows.append(d)
f = lambda d, k: float(d[k])
def t(x):
    x = float(x)
    if x >= 1: return f"{x:.2f} s"
    if x >= 1e-3: return f"{x*1e3:.2f} ms"
    if x >= 1e-6: return f"{x*1e6:.0f} µs"
    return f"{x*1e9:.0f} ns"
def mib(kb): return f"{int(kb)/1024:.0f} MiB"
def big(x):
    x = float(x)
    return "?" if x < 0 else (f"{x/1e6:.1f} M" if x >= 1e6 else f"{x/1e3:.0f} k")
L = []
L.append("# Performance" + (" in 3D" if dim == "3" else "") + "\n")
L.append("Generated by `make bench` (`" + ("BENCH_DIM=3 " if dim == "3" else "") + "tools/bench.sh`, program "
         "`tools/bench/bench_plate.f90`); rerun it to")
L.append("refresh this page. `BENCH_SIZES=\"1e3 1e4\" make bench` runs chosen sizes only.\n")
L.append("## Machine\n")
L.append(f"- CPU: {cpu}, {ncpu} logical CPUs ({cores} cores)")
L.append(f"- Memory: {mem}")
L.append(f"- BLAS: {blas}; OpenBLAS threads: {threads}; used: {rows[0].get('blas_solve', '?')} for a solve, "
         f"{rows[0].get('blas_factor', '?')} for a numeric factorization (`cholmod_shim.c`)")
L.append(f"- CHOLMOD: Debian package {chol or '?'}, supernodal LLᵀ; ordering: best of AMD and METIS below 50 000")
L.append("  equations, nested dissection of the supervariable graph above (`cholmod_shim.c`)")
L.append(f"- Date: {date}; rebond commit {commit}; gfortran flags as in the Makefile (`-O2 -g`)\n")
L.append("## Problem\n")
if dim == "3":
    L.append("A 1 m steel cube (E = 210 GPa, ν = 0.3, ρ = 7800 kg/m³), `DIMENSION 3`, `BOX … TYPE HEX8` n × n × n,")
    L.append("`MODEL … MASS CONSISTENT`, face x = 0 fixed, face x = 1 launched with `INITIAL … VELOCITY`, h = 1 µs,")
    L.append("`OUTPUT HISTORY 0 FIELDS 0`. Linear elastic: each step is one solve with the factor of")
    L.append("S = K0 + 4M/h². In 3D the internal forces come from the element loop (the solid kernel on the")
    L.append("points' shape-function gradients): the sparse product K0 u of 2D keeps three rigid modes, not six.\n")
else:
    L.append("A 1 m × 1 m steel plate (E = 210 GPa, ν = 0.3, ρ = 7800 kg/m³, 10 mm thick), `RECTANGLE … TYPE")
    L.append("QUAD4`, `MODEL … MASS CONSISTENT PLANE STRAIN`, left edge fixed, right edge launched with")
    L.append("`INITIAL … VELOCITY`, h = 1 µs, `OUTPUT HISTORY 0 FIELDS 0` (no I/O in the time loop). Linear")
    L.append("elastic, so each step is exactly one solve with the factor of S = K0 + 4M/h².\n")
L.append("## Results\n")
L.append("All times are CPU times of the benchmark process (`cpu_time`): the machine is shared, so")
L.append("wall-clock time is noise; the step and the solve run on one thread (finding 8).\n")
L.append("| DOFs | mesh | nnz(K) upper | nnz(L) | prepare_run | factorization | bare solve | time per step | ratio step/solve | ratio step/its solve | peak memory |")
L.append("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for d in rows:
    mesh = f"{d['nx']}×{d['ny']}" + (f"×{d['nz']}" if d.get('nz', '0') != '0' else '')
    L.append(f"| {int(d['ndof']):,} | {mesh} | {big(d['nnzk'])} | {big(d['lnz'])} | {t(d['t_prepare'])} | "
             f"{t(d['t_factor'])} | {t(d['t_solve'])} | {t(d['t_step_median'])} | **{f(d,'ratio'):.2f}** | "
             f"**{f(d,'ratio_own'):.2f}** | {mib(d['hwm_kb'])} |")
L.append("")
L.append("- *prepare_run*: CHOLMOD analysis (ordering, symbolic factorization) + numeric")
L.append("  factorization of S + initial internal forces; paid once per run.")
L.append("- *factorization*: a numeric refactorization of S on the same pattern (what a change of time step")
L.append("  would cost), median of the rounds.")
L.append("- *bare solve*: median of all the repeated `factor%solve` calls (forward + backward substitution, CHOLMOD's")
L.append("  permutations and copies included) on a random right-hand side, same factor as the run.")
L.append("- *time per step*: median CPU time of a step of the replay below (the same library calls as")
L.append("  `run_newmark`), over its steps; `run_newmark`'s own mean CPU time per step is in the next table "
         f"({', '.join(d['steps'] for d in rows)} steps).")
L.append(f"- The machine may be shared (other jobs), so solves and runs are done in {rows[0]['nrep']} alternating rounds;")
L.append("  the solve is the median over all of them, `run_newmark` its best round; slowest rounds (median solve / run step): " +
         "; ".join(f"{int(d['ndof']):,}: {t(d['t_solve_max'])} / {t(d['t_step_max'])}" for d in rows) + ".")
L.append("- *ratio*: median step / median bare solve. 1 would mean the step costs nothing but its solve; the goal")
L.append("  is ≤ 1.3, i.e. everything else the step does (element loop, mass product, vector updates) costs")
L.append("  at most 30 % of one solve.")
L.append("- *ratio step/its solve*: the same question asked inside each replayed step, median over the steps of")
L.append("  (the step) / (its own solve): both sides are timed within the same millisecond, so a load that")
L.append("  changes between the rounds of bare solves and the replay (this machine is shared: the bare solve")
L.append("  at 1e4 DOFs has measured 0.57 to 1.9 ms in one session) does not move it.")
L.append("- *peak memory*: VmHWM of the benchmark process at the end (it holds one factor).\n")
if dim == "3":
    d = rows[-1]
    n0, l0, hw = f(d, 'ndof'), f(d, 'lnz'), f(d, 'hwm_kb') / 1048576
    # Nested dissection on a 3D grid: nnz(L) ~ n^(4/3), factorization flops ~ n^2.
    l6 = l0 * (1e6 / n0) ** (4.0 / 3.0)
    L.append("## Where the direct solve runs out of memory\n")
    L.append(f"At {int(n0):,} equations the factor holds {l0/1e6:.0f} M entries and the process peaks at {hw:.1f} GiB.")
    L.append("Nested dissection on a 3D grid fills the factor as n^(4/3) and costs n² flops: at 1e6 equations")
    L.append(f"about {l6/1e9:.1f} G entries ({8*l6/2**30:.0f} GiB for the values alone) and {f(d,'t_factor')*(1e6/n0)**2/60:.0f}")
    L.append("minutes a factorization on this machine: the 24 GiB of this machine hold one such factor with little")
    L.append("room beside it (an estimate from the measured sizes, not run). That is where the distributed")
    L.append("solve (MUMPS across ranks, out-of-core factors: issue 34) begins.\n")
L.append("## Setup: what a run pays before its first step\n")
L.append("Issue 14 asks for a setup of at most 3 numeric factorizations at 1e6 DOFs. *setup* = `load_scene` +")
L.append("`build_system` + `prepare_run` (one sample each: they run once per process); *analysis*: the")
L.append("CPU time of CHOLMOD's ordering and symbolic factorization inside `prepare_run`, as the factor")
L.append("reports it (`cholmod_factor_t%stats`); *first factorization*: the rest of `prepare_run`, mostly")
L.append("the first numeric factorization, which also touches the factor's pages for the first time.\n")
L.append("| DOFs | ordering | analysis | load_scene | build_system | prepare_run | of which first factorization etc. | setup | factorization | **setup / factorization** | factor flops |")
L.append("|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for d in rows:
    setup = f(d,'t_load') + f(d,'t_build') + f(d,'t_prepare')
    L.append(f"| {int(d['ndof']):,} | {d['ordering']} | {t(d['t_analyze'])} | {t(d['t_load'])} | {t(d['t_build'])} | "
             f"{t(d['t_prepare'])} | {t(f(d,'t_prepare') - f(d,'t_analyze'))} | {t(setup)} | {t(d['t_factor'])} | "
             f"**{setup / f(d,'t_factor'):.2f}** | {f(d,'flops'):.3g} |")
L.append("")
L.append("## Where the step goes\n")
L.append("The benchmark replays the step of `run_newmark` after the run, with the same library calls in the")
L.append("same order, timing each part (median over the steps; % of the replayed step):\n")
keys = [("t_slv", "solve (in the loop)"), ("t_fint", "internal_force (Bσ = K0 u)"),
        ("t_mass", "eq (3) and M v(n+1)"), ("t_comm", "commit_state"), ("t_vec", "vector updates"),
        ("t_ext", "external_force")]
L.append("| DOFs | " + " | ".join(k[1] for k in keys) + " | replayed step | measured step | element loop instead |")
L.append("|---:|" + "---:|" * (len(keys) + 3))
for d in rows:
    tot = sum(f(d, k) for k, _ in keys)
    cells = [f"{t(d[k])} ({100*f(d,k)/tot:.0f} %)" for k, _ in keys]
    L.append(f"| {int(d['ndof']):,} | " + " | ".join(cells) + f" | {t(tot)} | {t(d['t_step'])} | {t(d['t_kmv'])} |")
L.append("")
L.append("*internal_force*: for this linear elastic model, Bσ = K0 u, the sparse product on the shared")
L.append("pattern (`stiffness_product`, SCHEME FORCES AUTO, the default). *element loop instead*: the same")
L.append("`internal_force` call with the product off (`k0_product_t%disable`, what SCHEME FORCES POINTS")
L.append("runs and every step ran before), timed in the same run; the two vectors agree to a relative")
L.append("difference of " + ", ".join(f"{f(d,'kdiff'):.0e}" for d in rows) + ". The step with the element loop, from")
L.append("the same parts (replayed step − K0 u + element loop), against this run's:\n")
L.append("| DOFs | step, element loop | ratio step/solve, element loop | step, K0 u | **ratio step/solve, K0 u** | step saved |")
L.append("|---:|---:|---:|---:|---:|---:|")
for d in rows:
    tot = sum(f(d, k) for k, _ in keys)
    loop = tot - f(d,'t_fint') + f(d,'t_kmv')
    L.append(f"| {int(d['ndof']):,} | {t(loop)} | {loop/f(d,'t_solve'):.2f} | {t(tot)} | **{tot/f(d,'t_solve'):.2f}** | "
             f"{100*(1 - tot/loop):.0f} % |")
L.append("")
L.append("Beyond the solve, a linear step does:\n")
L.append("- `internal_force`: for a model whose every element is linear elastic in small strain, Bσ = K0 u")
L.append("  (`stiffness_product`: each free body's mean translation shifted out of u first, the product")
L.append("  projected off the body's rigid modes after; the points' strains and stresses are evaluated only")
L.append("  where they are read: fields, checkpoints, support reactions, the history line's strain energy).")
L.append("  Otherwise the element loop: for every element, gather u, then at its Gauss points ε = B u,")
L.append("  σ = D ε and fe += w Bᵀσ in a fixed-size kernel (nonlinear points call `law_update`: σ = σn + Δσ")
L.append("  along the path, mean stress, work σ̄·Δε), then scatter fe into fint; linear elastic surface")
L.append("  elements read only their shape-function gradients (`linear_points_plane`) instead of B.")
L.append("- `commit_state`: swaps the trial and committed strain, stress and internal-variable arrays")
L.append("  (`move_alloc`, no copy).")
L.append("- eq (3) and M v(n+1): on this linear step with nothing added to eq (9), M v(n+1) is the step's")
L.append("  momentum balance M v(n) + h/2 (F(n) + F(n+1) − Bσ(n) − Bσ(n+1)) (`momentum_eq2`, one pass);")
L.append("  elsewhere `mass_times`, the product by the consistent mass by 2 × 2 node blocks (`pair_blocks`,")
L.append("  one value per m I block) or on M's own pattern without K's zeros; a diagonal product with")
L.append("  `MASS LUMPED`.")
L.append("- vector updates: the right-hand side F(n+1) + F(n) − Bσ(n) + 4M v(n)/h, the residual, du,")
L.append("  u + du, eq (3) for v, the copies u, fint, F, the external-work and kinetic-energy dot products:")
L.append("  about 15 passes over n-vectors.")
L.append("- `external_force`: gravity scaled by its function plus the LOAD vectors.\n")
L.append("The solve itself reads L twice (forward and backward), about 16 bytes per nonzero of L, so it is")
L.append("memory-bandwidth bound, as K0 u is (by 2 × 2 blocks: 9 bytes per nonzero of its upper triangle).")
L.append("Their ratio therefore depends on nnz(L)/DOF, which grows like log n with nested dissection: the")
L.append("overhead is relatively largest on small problems.\n")
# Element loop before / after the fixed-size rewrite (static numbers of the earlier runs).
BEFORE = {1012: (292e-6, 13e-6, 7.34), 10224: (2.31e-3, 118e-6, 9.29), 100800: (33.33e-3, 1.51e-3, 2.56),
          1001112: (323.00e-3, 14.25e-3, 2.76)}
L.append("## Element loop: before and after the fixed-size rewrite\n")
L.append("*Before*: commit e59a5d7 (first run of this page, 2026-11-22 03:45 UTC): `law_update` called at")
L.append("every Gauss point, `commit_state` copying the trial state. *After*: this run's element loop")
L.append("(SCHEME FORCES POINTS; the ratio step/solve is this run's, with K0 u). Gauss points of the plate:")
L.append("4 per QUAD4.\n")
L.append("| DOFs | Gauss points | internal_force before | after | ns per Gauss point before | after | speed-up | commit_state before | after | ratio step/solve before | after |")
L.append("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for d in rows:
    n = int(d['ndof']); ngp = 4 * int(d['nx']) * int(d['ny'])
    if n in BEFORE:
        fb, cb, rb = BEFORE[n]
        L.append(f"| {n:,} | {ngp:,} | {t(fb)} | {t(d['t_kmv'])} | {1e9*fb/ngp:.0f} | {1e9*f(d,'t_kmv')/ngp:.0f} | "
                 f"{fb/f(d,'t_kmv'):.1f}× | {t(cb)} | {t(d['t_comm'])} | {rb:.2f} | {f(d,'ratio'):.2f} |")
    else:
        L.append(f"| {n:,} | {ngp:,} | – | {t(d['t_kmv'])} | – | {1e9*f(d,'t_kmv')/ngp:.0f} | – | – | {t(d['t_comm'])} | – | {f(d,'ratio'):.2f} |")
L.append("")
L.append("The two columns come from different runs of a machine that may be shared, so the ratios")
L.append("step/solve move with the load as much as with the code (a bare solve slower than a whole step")
L.append("means the solves of that round were disturbed). A load-independent comparison: the minimum over")
L.append("100 calls of `internal_force` alone on the same plates, both builds in the same minute (same")
L.append("gfortran flags): 137, 141, 146 ns per Gauss point before, 28, 29, 32 ns after (1e3, 1e4, 1e5")
L.append("DOFs), i.e. 4.5 to 5 times faster; `commit_state` went from about 6 ns per Gauss point to")
L.append("nothing. Results are unchanged beyond round-off: nonlinear, tangent and PRECISION EXTENDED runs")
L.append("are bit for bit identical; linear elastic points now take σ = D ε instead of σn + D Δε (the")
L.append("same from a zero initial state), which moves displacements by about 1e-14 relatively.\n")
L.append("## Findings and suggestions\n")
L.append("First written after the run of commit e59a5d7, updated after the element-loop rewrite; the tables")
L.append("above are regenerated by every run.\n")
L.append("1. **The element loop is no longer the main cost.** Before, `internal_force` cost 130–170 ns per")
L.append("   Gauss point, as much as the whole CHOLMOD solve or more at every size (perf: the call chain")
L.append("   `law_update` → `elastic_update` with assumed-shape descriptors for ten arguments per point,")
L.append("   `matmul` on an assumed-shape D, `select case` on the law, and `commit_state` copies). Linear")
L.append("   elastic points now run a fixed-size kernel per element (specialised by the number of strain")
L.append("   components, 4, 2 or 1; B, w, ε and σ of the element's points passed by sequence association,")
L.append("   no temporaries), per-model data are looked up once per run of elements of the same model,")
L.append("   and `commit_state` swaps the arrays. About 30 ns per Gauss point in cache, more when the")
L.append("   stored B (4 × 8 doubles per QUAD4 point, 256 bytes) streams from memory at 1e6 DOFs.")
L.append("2. **Linear models: Bσ = K0 u** (2026-12-02, `src/assembly/stiffness_product.f90`). Tried first")
L.append("   as the bare product (2026-12-01) and rejected on the tests: for a body in large rigid motion the")
L.append("   rows of K0 cancel only to eps |K| |u|, so the forces no longer summed to zero (two blocks in")
L.append("   contact: momentum drifting by 2e-9 of m v0, against 1e-12) and the strain energy ½ u·K0 u lost")
L.append("   digits (beam drops' balance 3e-10 … 3e-8 instead of ≤ 1e-10). Now, for each body and each rigid")
L.append("   mode K0 annihilates there (checked numerically when the system is built, so supports, rollers")
L.append("   and springs to the ground remove the modes they hold): the body's mean translation is taken out")
L.append("   of u (exactly: a constant shift), and the product is projected off the modes (the net force and")
L.append("   moment of a body's own elasticity are zero in exact arithmetic), which equilibrates its rounding")
L.append("   as the element loop's Bᵀσ is. Near-mechanisms keep the loop: a body its supports leave a rigid")
L.append("   motion other than those modes (a pin), or hold only through supports 1e4 times softer than")
L.append("   itself (a plate on a soft spring drifting: balance 3e-7 with the product, 1.3e-9 with the loop).")
L.append("   The strain energy of a history line is the points' ½ Σ w σ·ε,")
L.append("   evaluated then (½ u·K0 u rounds at eps × the condition of K0); the points' strains and stresses")
L.append("   are evaluated where they are read (fields, checkpoints, the support reactions' elements), so")
L.append("   what is written never changes the forces (`tests/scenes/stiffness_product`: the history lines")
L.append("   of HISTORY EVERY 7 are those of EVERY 1 bit for bit). Before the first step the product is")
L.append("   checked against the element loop on a test displacement (relative 1e-10) and the loop is kept")
L.append("   if they differ. The trade: the forces round like the loop's, but K0's entries are rounded sums of")
L.append("   the elements' B'DB w, so the balance carries ½ u·δK·u, a bounded offset that does not grow with")
L.append("   the steps (the element loop's balance grows with them): 4.4e-12 of E on the cantilever of")
L.append("   `inputs/cantilever_release.dat` (1.6e-13 with the loop after its 5000 steps), 9.8e-12 on")
L.append("   `tests/scenes/restart` (6.9e-13), the same order elsewhere; every test bound holds. `SCHEME FORCES")
L.append("   POINTS` keeps the element loop (bit for bit the results before the product).")
L.append("3. **The element loop streams gradients, not B** (2026-12-02). A surface element's B is made of")
L.append("   its shape-function gradients and zeros (B(1, 2a−1) = B(4, 2a) = ∂N_a/∂x, B(2, 2a) = B(4, 2a−1) =")
L.append("   ∂N_a/∂y): the linear elastic points of QUAD4/QUAD8/TRI3/TRI6 in small strain keep the gradients")
L.append("   (8 doubles per QUAD4 point, a quarter of B) and `linear_points_plane` runs on them, the same")
L.append("   operations on the nonzero terms in the same order: the results are bit for bit those of B")
L.append("   (every csv of the regression scenes identical). Minimum CPU time of `internal_force` alone over")
L.append("   repeated calls on the plates, both builds side by side: 23–26 → 15–18 ns per Gauss point at")
L.append("   1e4 DOFs, 27–28 → 19 ns at 1e5 (1.4–1.5×). B is still stored (the tangent, the reactions,")
L.append("   the nonlinear and large-displacement kernels read it): +25 % of its memory.")
L.append("   The consistent mass product likewise runs on M's own pattern (2026-12-02): minimum CPU time")
L.append("   of `mass_times` alone, side by side, 0.09 → 0.05 ms, 1.02 → 0.63 ms and 10.9–12.2 → 6.9 ms at")
L.append("   1e4, 1e5 and 1e6 DOFs, bit for bit the same vector.")
L.append("4. **Small problems** (1e3–1e4 DOFs): the solve is short (tens of µs to 1 ms) and partly CHOLMOD")
L.append("   overhead (permutation, dense workspace copies, one BLAS call per supernode); what the step does")
L.append("   besides (K0 u, the momentum, about 15 vector passes) is then a larger share of it, and the ratio")
L.append("   step/solve at 1e4 DOFs moves with the machine's load (bare solve: 0.8 to 1.8 in one session's runs;")
L.append("   step / its own solve: 1.29 in five repeated runs of the final build, 1.29 to 1.37 before the")
L.append("   product's temporaries were removed).")
L.append("5. **Once-per-run costs at 1e6 DOFs** (issue 14, item 3; the setup table above). Before (commit")
L.append("   03fc21a): the analysis tried AMD and METIS on the DOF graph (0.9 s + 4.6 s on the 707 × 707 plate)")
L.append("   and kept METIS (nnz(L) 1.050e8, 5.62e10 flops); the first numeric factorization cost 3.5 s more")
L.append("   than a refactorization (the first touch of the factor's 1 GB: `clear_page_erms`). Tried then and")
L.append("   not kept: AMD alone (23 % more flops), METIS on the compressed graph beside AMD (CHOLMOD kept AMD,")
L.append("   whose fill was lower), transparent huge pages.")
L.append("   Now (2026-12-02, `cholmod_shim.c`, above 50 000 equations) the analysis is one ordering: CHOLMOD's")
L.append("   nested dissection (METIS's separators, constrained AMD inside) of the graph of supervariables")
L.append("   (consecutive columns with the same pattern, a node's DOFs, found in one pass by pattern hashes),")
L.append("   expanded to the DOFs and given to `cholmod_analyze_p`. On the 707 × 707 plate: nnz(L) 1.014e8")
L.append("   (−3.4 %), 5.46e10 flops (−2.8 %), so every later solve and refactorization is cheaper too. Side")
L.append("   by side, same session, 4 alternating runs of the bench program of each commit (CPU s, one thread):")
L.append("   setup (load + build + prepare) 18.0–18.5 s before, 13.2–14.8 s after (−24 %); analysis 4.6–5.5 s")
L.append("   before, 2.8–3.0 s after; setup / factorization 2.73–3.04 before, 2.05–2.72 after; peak memory")
L.append("   2754 → 2217 MB (with the next change). Tried the same session and not kept: METIS alone on the")
L.append("   supervariables (analysis 3.0 s, but 1.062e8 and 6.04e10: +7 % flops); the nested dissection on")
L.append("   the DOF graph (the same ordering as on the supervariables, whose compression it repeats, in 4.7 s).")
L.append("   At 1e5 DOFs: analysis 0.21 s against 0.44 s, nnz(L) 7.73e6 against 7.99e6. Below 50 000")
L.append("   equations the analysis costs milliseconds and the best of AMD and METIS is still taken (every test")
L.append("   scene keeps its factor bit for bit).")
L.append("   Linear elastic surface points in small strain no longer store B (2026-12-02): the shape-function")
L.append("   gradients the element loop streams are all B is made of, and `element_table_t%point_b` rebuilds it")
L.append("   where one is needed (K0, the tangent, reactions, PRECISION EXTENDED), checked equal bit for bit when")
L.append("   the table is built: 500 MB less at 1e6 DOFs (peak 2.70 → 2.20 GB), every output bit for bit.")
L.append("   What remains of the setup is the first touch of the factor (3.5–4 s beyond a refactorization)")
L.append("   and `build_system` (2.3–3.6 s: element kernels, the pattern, K0 and M).")
L.append("6. **A simplicial factor for small systems?** (issue 14, item 2; 2026-12-02, `supernodal =")
L.append("   CHOLMOD_SIMPLICIAL` against the default choice, side by side, CPU time, median of 150 solves):")
L.append("   the solve costs 28 against 59 µs at 1e3 DOFs and 445 against 567 µs at 1e4 (the step 91 against")
L.append("   149 µs and 1.01 against 1.16 ms), but 3.5 against 2.6 ms at 2.4e4, the same at 5e4 and 1e5 with a")
L.append("   refactorization 1.4–1.9 times slower. The crossover (between 1e4 and 2.4e4 DOFs here, where L")
L.append("   leaves the cache) is the machine's, and CHOLMOD's own switch (flops/nnz(L) < 40) keeps the")
L.append("   supernodal factor at 1e4; not changed. It would lower the step, not the ratio step/solve, whose")
L.append("   denominator falls with it.")
L.append("7. **K0 u by node blocks, and no product by M** (2026-12-02, issue 14 item 2). (a) Equations are")
L.append("   numbered node by node, so on a 2D solid the pairs (2b−1, 2b) are nodes: `pair_blocks` stores K0")
L.append("   by 2 × 2 blocks on them (one index per four values, the symmetric product's scatter two entries")
L.append("   at a time, x and y seen as 2 × n/2 arrays) where that stores at most 1.25 times the matrix's")
L.append("   entries (a roller or a beam's RZ shifts the pairing: the scalar product is kept), and a")
L.append("   consistent mass whose blocks are all m I by one value per block (the scalar product bit for")
L.append("   bit). Minimum CPU time of the product alone on the plates, both kernels in one process")
L.append("   (a probe program linked to the library): K0 u 101–139 → 47–77 µs at 1e4 DOFs, 1.26–1.54 → 0.84–0.88")
L.append("   ms at 1e5; M v 64–77 → 47–62 µs and 0.78–0.94 → 0.65–0.70 ms. In the step the product reads")
L.append("   K0 from the cache level the solve left it in, so it gains less there. Memory: +4 bytes per")
L.append("   stored value (about 90 MB at 1e6 DOFs, 4 % of the peak). (b) A linear step whose eq (9) has nothing added")
L.append("   (no contact rows, damping or lumped mass) takes M v(n+1) from its momentum balance, eq (2) times")
L.append("   M (`momentum_eq2`): one pass instead of the product. It differs from the product by h/2 × the")
L.append("   solve's residual, the rounding the energy balance already carries as ½ du'(S du − r); on the six")
L.append("   regression scenes it applies to, every balance stays within ×1.2 of the product's (gmsh clamped and")
L.append("   roller 10 times lower), and a free body's total momentum is then exactly the external impulse.")
L.append("8. **BLAS threads** (2026-12-02, issue 14 item 2's threading mode). With OpenBLAS's default of one")
L.append("   thread per CPU, its helper thread spins (sched_yield) after every parallel BLAS call, and a time")
L.append("   loop of solves (one small BLAS call per supernode) kept both cores busy for the work of one:")
L.append("   `bin/rebond` on the 71 × 71 plate (2000 steps), two alternated runs each, CPU (user + sys) 5.16")
L.append("   and 4.81 s for 2.63 and 2.43 s of wall time; on the 224 × 224 plate (100 steps) 7.47 and 7.36 s")
L.append("   for 4.06 and 4.05 s. `cholmod_shim.c` now runs solves on one thread and numeric factorizations on")
L.append("   OpenBLAS's count (found at run time with dlsym, so another BLAS links unchanged; an")
L.append("   OPENBLAS_NUM_THREADS setting is respected): 2.77 and 2.33 s CPU for 2.58 and 2.15 s wall, and")
L.append("   4.07 and 4.36 s for 3.54 and 3.83 s: half the CPU time, and no slower on the wall clock. The")
L.append("   ratios above are CPU times, so before this change both their sides carried the spinning.\n")
if dim == "3":
    # The 2D plate's history (K0 u, the element-loop rewrite, its findings) is docs/performance.md's.
    cut = next(i for i, x in enumerate(L) if x.startswith("*internal_force*: for this linear elastic model"))
    L = L[:cut]
    L.append("*internal_force* in 3D is, as in 2D, the product K0 u (`stiffness_product`) with each free")
    L.append("body's six rigid modes (three translations, three rotations made orthonormal) shifted out of u and")
    L.append("projected off the product; *element loop instead* times the points' loop (`linear_points_solid`,")
    L.append("8 points per HEX8) it replaces, which cost 12 to 23 % of the step (ratio 1.38 to 1.57 at 1e4")
    L.append("DOFs before). The history of the 2D plate's step, its kernels and its findings: docs/performance.md.\n")
# Sections written by other tools (tools/alloc_per_step.sh: "Allocations in the time loop") are kept.
import os, re
kept = ""
if os.path.exists(out):
    m = re.search(r"^## Allocations in the time loop\n.*?(?=^## |\Z)", open(out).read(), re.M | re.S)
    if m:
        kept = "\n" + m.group(0)
open(out, 'w').write("\n".join(L) + kept)
print("\n".join(L))
PY
echo "bench: report written to $OUT (scratch files in $WORK)"
