#!/usr/bin/env bash
# The paper's validation (section 3.4): a vertical beam and an inclined beam dropped on the
# ground (`make validation`).
#
# For each scene $INPUTS/<scene>.dat (default inputs/) that exists, runs
#   - the impact treatments at the scene's step:   --set SCHEME.IMPACT=PAPER|PERSIST|AUTO|OFF
#     (AUTO, the default, is MASSLESS on the beams: docs/contact.md)
#   - PAPER at the scene's step times each STEP_FACTOR:  --set TIME.STEP=<h*f>
# into results/validation/<scene>/<run>/, draws the figures into docs/figures/ with
# tools/plot_energy.py and tools/plot_compare.py, and writes docs/validation.md with
# tools/validation_report.py. A missing scene is skipped and reported as such (in the
# output and in docs/validation.md); a run that fails is reported with its exit status
# and whatever it wrote.
#
# Environment:
#   VALIDATION_SCENES        scene names, default "beam_drop_vertical beam_drop_inclined"
#   VALIDATION_STEP_FACTORS  step multipliers of the step study, default "0.1 0.5 1 2 10"
#   VALIDATION_PROBES        probe options for the plots, e.g. "--probe beam.mid.UY"
#                            (default: the mean of every UY probe of the scene)
#   VALIDATION_INPUTS        folder of the scene files, default inputs
#   VALIDATION_OUT           results folder, default results/validation
#   VALIDATION_FIGURES       figures folder, default docs/figures
#   VALIDATION_DOC           report, default docs/validation.md
#   REBOND, PY               the solver (default bin/rebond) and Python (default /usr/bin/python3)
set -uo pipefail
cd "$(dirname "$0")/.." || exit 2

SCENES=${VALIDATION_SCENES:-"beam_drop_vertical beam_drop_inclined"}
FACTORS=${VALIDATION_STEP_FACTORS:-"0.1 0.5 1 2 10"}
PROBES=${VALIDATION_PROBES:-}
INPUTS=${VALIDATION_INPUTS:-inputs}
OUT=${VALIDATION_OUT:-results/validation}
FIG=${VALIDATION_FIGURES:-docs/figures}
DOC=${VALIDATION_DOC:-docs/validation.md}
REBOND=${REBOND:-bin/rebond}
PY=${PY:-/usr/bin/python3}

if [[ ! -x $REBOND ]]; then
    echo "make_validation: $REBOND not found (run make first)" >&2
    exit 2
fi
mkdir -p "$OUT" "$FIG"

# run SCENE LABEL MODE STEP -> appends "label|dir|mode|step|status" to the scene's manifest
run() {
    local scene=$1 label=$2 mode=$3 step=$4
    local dir="$OUT/$scene/$label"
    rm -rf "$dir"
    mkdir -p "$dir"
    local status=0
    "$REBOND" "$INPUTS/$scene.dat" -o "$dir" --set "SCHEME.IMPACT=$mode" --set "TIME.STEP=$step" \
        > "$dir/run.log" 2>&1 || status=$?
    echo "$label|$dir|$mode|$step|$status" >> "$OUT/$scene/runs.txt"
    printf '  %-12s IMPACT %-7s STEP %-10s exit %s\n' "$label" "$mode" "$step" "$status"
}

done_scenes=()
skipped=()
for scene in $SCENES; do
    file="$INPUTS/$scene.dat"
    if [[ ! -f $file ]]; then
        echo "make_validation: $file does not exist, skipped"
        skipped+=("$scene")
        continue
    fi
    h=$("$PY" -B -c "import sys; sys.path.insert(0, 'tools'); from rebond_results import SceneInfo; \
s = SceneInfo('$file'); print(repr(s.step) if s.step else '')")
    if [[ -z $h ]]; then
        echo "make_validation: $file has no TIME STEP, skipped"
        skipped+=("$scene")
        continue
    fi
    echo "$scene (step $h)"
    rm -rf "${OUT:?}/$scene"
    mkdir -p "$OUT/$scene"
    for mode in PAPER PERSIST AUTO OFF; do
        run "$scene" "$mode" "$mode" "$h"
    done
    for f in $FACTORS; do
        [[ $f == 1 || $f == 1.0 ]] && continue      # the PAPER run above
        hf=$(awk -v h="$h" -v f="$f" 'BEGIN { printf "%.10g", h * f }')
        run "$scene" "PAPER_h$f" PAPER "$hf"
    done

    # Figures: one energy figure per impact mode, the modes overlaid, the steps overlaid.
    for mode in PAPER PERSIST AUTO OFF; do
        # shellcheck disable=SC2086
        "$PY" tools/plot_energy.py "$OUT/$scene/$mode" --scene "$file" $PROBES \
            --title "$scene, IMPACT $mode, step $h s" -o "$FIG/${scene}_energy_$mode.png" \
            || echo "  (no energy figure for $mode)"
    done
    # shellcheck disable=SC2086
    "$PY" tools/plot_compare.py "PAPER=$OUT/$scene/PAPER" "PERSIST=$OUT/$scene/PERSIST" \
        "AUTO=$OUT/$scene/AUTO" "OFF=$OUT/$scene/OFF" --scene "$file" $PROBES \
        --title "$scene: impact treatments, step $h s" -o "$FIG/${scene}_modes.png" \
        || echo "  (no mode comparison figure)"
    specs=()
    for f in $FACTORS; do
        hf=$(awk -v h="$h" -v f="$f" 'BEGIN { printf "%.10g", h * f }')
        if [[ $f == 1 || $f == 1.0 ]]; then specs+=("h=$hf=$OUT/$scene/PAPER")
        else specs+=("h=$hf=$OUT/$scene/PAPER_h$f"); fi
    done
    # shellcheck disable=SC2086
    "$PY" tools/plot_compare.py "${specs[@]}" --scene "$file" $PROBES \
        --title "$scene: IMPACT PAPER at several time steps" -o "$FIG/${scene}_steps.png" \
        || echo "  (no step comparison figure)"
    done_scenes+=("$scene")
done

# shellcheck disable=SC2086
"$PY" tools/validation_report.py --results "$OUT" --figures "$FIG" --doc "$DOC" --inputs "$INPUTS" \
    --scenes "${done_scenes[*]:-}" --skipped "${skipped[*]:-}" $PROBES || exit 1
# The section on every scene of inputs/ (exact references, tools/compare) follows.
"$PY" tools/validation_scenes.py --doc "$DOC" || exit 1
echo "wrote $DOC"
if (( ${#skipped[@]} )); then
    echo "skipped (missing scene file): ${skipped[*]}"
fi
