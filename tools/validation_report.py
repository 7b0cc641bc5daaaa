#!/usr/bin/python3
"""Writes docs/validation.md from the runs of tools/make_validation.sh.

    tools/validation_report.py --results results/validation --figures docs/figures
                               --doc docs/validation.md --scenes "a b" [--skipped "c"]
                               [--probe group.DOF ...]

Each scene folder holds runs.txt (label|dir|mode|step|exit status per line) and one OUTDIR
per run. Every number in the report is measured from those OUTDIRs by rebond_results.summary;
the "reading" paragraphs are generated from the same numbers.
"""
import argparse
import datetime
import os
import subprocess
import sys

sys.dont_write_bytecode = True  # no __pycache__ in tools/
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rebond_results import Run, SceneInfo, probe_signal, summary  # noqa: E402

CLAIMS = {
    "beam_drop_vertical": (
        "« La validation a été faite tout d'abord en étudiant une poutre verticale tombant sur le "
        "sol et rebondissant. Les résultats sont différents en temps mais donnent globalement les "
        "mêmes rebonds quel que soit le pas de temps choisi. »",
        "A vertical beam falls on the ground and bounces. The results differ in time but give "
        "globally the same rebounds whatever the time step. Checked here: the rebound (apex) "
        "heights at several steps, the total energy kinetic + strain + potential, and that the "
        "beam keeps bouncing."),
    "beam_drop_inclined": (
        "« Le second test a consisté à étudier une poutre inclinée qui tombe sur le sol. Sur cet "
        "exemple on a vérifié que l'énergie de déformation plus l'énergie cinétique plus "
        "l'énergie potentielle est bien constante. Numériquement on trouve bien que la poutre "
        "rebondit infiniment. […] lors de certains rebonds beaucoup d'énergie passe en énergie "
        "de déformation […]. Parfois le rebond ne fait intervenir qu'une extrémité, parfois les "
        "deux. Les résultats sont fonction du pas de temps si celui-ci devient trop important. »",
        "An inclined beam falls on the ground. Strain + kinetic + potential energy stays "
        "constant; the beam bounces endlessly; at some bounces much energy goes into strain "
        "energy (the beam's modes are excited); some bounces involve one end, others both; the "
        "results depend on the step when it is too large for the phenomenon."),
}
ROUNDOFF = 1e-8   # relative energy error below which "constant" is claimed (round-off ~1e-11)


def fmt(x, p=3):
    return f"{x:.{p}g}" if isinstance(x, float) else str(x)


def read_manifest(path):
    runs = []
    with open(path) as f:
        for line in f:
            parts = line.rstrip("\n").split("|")
            if len(parts) == 5:
                label, d, mode, step, status = parts
                runs.append({"label": label, "dir": d, "mode": mode, "step": float(step),
                             "status": int(status)})
    return runs


def load(entry, scene, probes):
    """summary() of one run, or an error string."""
    if not os.path.exists(os.path.join(entry["dir"], "history.csv")):
        return None, f"no history.csv (exit status {entry['status']})"
    try:
        run = Run(entry["dir"], entry["label"])
        s = summary(run, probes, scene)
        t, sig, ylabel, _ = probe_signal(run, probes, scene)
        s["rest"] = float(sig.min())
        s["ylabel"] = ylabel.split("\n")[0]
        s["impacts"] = impacts(run, s["apex_times"])
        s["ends"] = end_nodes(entry["dir"], scene)
        return s, None
    except (OSError, ValueError, KeyError) as exc:
        return None, str(exc)


def impacts(run, apex_times):
    """Node sets of the contact establishments between consecutive apexes (one per impact)."""
    out = []
    bounds = list(apex_times) + [float("inf")]
    for a, b in zip(bounds[:-1], bounds[1:]):
        nodes = sorted({ev["nodes"] for ev in run.events
                        if ev["event"] == "establish" and a < ev["time"] <= b},
                       key=lambda x: (len(x), x))
        if nodes:
            out.append(nodes)
    return out


def end_nodes(outdir, scene):
    """Node numbers (1-based, as in events.csv) of the scene's `*.start` and `*.end` groups,
    found by their coordinates in fields.h5; {} when that is not possible."""
    if scene is None:
        return {}
    try:
        import h5py
        import numpy as np
        with h5py.File(os.path.join(outdir, "fields.h5"), "r") as f:
            xyz = np.array(f["mesh/coordinates"])
    except Exception:  # no h5py, no fields.h5, another layout: the report goes without
        return {}
    out = {}
    size = float(np.ptp(xyz[:, :2], axis=0).max()) or 1.0
    for name, (x, y) in scene.coords.items():
        if name.endswith(".start") or name.endswith(".end"):
            d = np.hypot(xyz[:, 0] - x, xyz[:, 1] - y)
            k = int(np.argmin(d))
            if d[k] <= 1e-9 * size:
                out[name] = str(k + 1)
    return out


def rise(s, k):
    """Apex height above the lowest point of the probe signal."""
    return s["apex_heights"][k] - s["rest"]


def modes_table(rows):
    lines = ["| run | step (s) | exit | steps | max \\|balance\\|/E | total drift/E | total range/E "
             "| max strain/E | establish | release | Σ E_j (J) | bounces | apex heights (first 6) | CM rise / first drop |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for e, s, err in rows:
        if s is None:
            lines.append(f"| {e['label']} | {fmt(e['step'])} | {e['status']} | {err} |" + " |" * 10)
            continue
        ap = ", ".join(f"{h:.4g}" for h in s["apex_heights"][:6])
        cm = ", ".join(f"{100 * r:.0f} %" for r in s["cm_rise"][:5])
        lines.append(
            f"| {e['label']} | {fmt(e['step'])} | {e['status']} | {s['steps']} | {s['max_balance_rel']:.2e} "
            f"| {s['total_drift_rel']:+.2e} | {s['total_range_rel']:.2e} | {s['max_strain_share']:.2f} "
            f"| {s['establish']} | {s['release']} | {s['restored']:.4g} | {len(s['apex_heights']) - 1} | {ap} | {cm} |")
    return "\n".join(lines)


def apex_table(rows, nmax=8, spread=True):
    good = [(e, s) for e, s, _ in rows if s is not None]
    if not good:
        return "", []
    n = min(nmax, max(len(s["apex_heights"]) for _, s in good))
    head = "| run | " + " | ".join(f"apex {k}" for k in range(n)) + " |"
    lines = [head, "|---|" + "---|" * n]
    for e, s in good:
        cells = [f"{s['apex_heights'][k]:.4g}" if k < len(s["apex_heights"]) else "—" for k in range(n)]
        lines.append(f"| {e['label']} | " + " | ".join(cells) + " |")
    # spread across runs of each apex, relative to the release drop
    spreads = []
    for k in (range(1, n) if spread else ()):
        hs = [s["apex_heights"][k] for _, s in good if k < len(s["apex_heights"])]
        if len(hs) == len(good) and len(hs) > 1:
            drop = max(rise(s, 0) for _, s in good)
            spreads.append((k, min(hs), max(hs), (max(hs) - min(hs)) / drop if drop > 0 else 0.0))
    if spreads:
        lines.append("")
        lines.append("| bounce | lowest apex | highest apex | spread / release drop |")
        lines.append("|---|---|---|---|")
        for k, lo, hi, sp in spreads:
            lines.append(f"| {k} | {lo:.4g} | {hi:.4g} | {100 * sp:.1f} % |")
    return "\n".join(lines), spreads


def bounce_sentence(s):
    nb = len(s["apex_heights"]) - 1
    if nb < 1 or not s["cm_rise"]:
        return f"  No bounce after the first impact in {s['t_end']:.3g} s."
    late = sum(1 for t in s["apex_times"][1:] if t > 0.5 * s["t_end"])
    r = s["cm_rise"]
    return (f"  It bounces {nb} times in {s['t_end']:.3g} s ({late} in the second half of the run). "
            f"The centre of mass rises {100 * r[0]:.0f} % of its first drop at the first bounce, "
            f"{100 * r[-1]:.0f} % at the last; at most {100 * max(r):.0f} %.")


def reading(scene_name, modes, steps, spreads):
    """Sentences generated from the measures."""
    out = []
    by = {e["mode"]: s for e, s, _ in modes if s is not None}
    for m in ("PAPER", "PERSIST", "AUTO"):
        s = by.get(m)
        if s is None:
            continue
        ok = s["max_balance_rel"] < ROUNDOFF
        out.append(f"- **{m}**: kinetic + strain + potential "
                   + (f"stays constant to {s['max_balance_rel']:.1e} of E (round-off) over "
                      f"{s['steps']} steps and {s['establish']} contact establishments, "
                      f"which gave back {s['restored']:.4g} J in all"
                      if ok else f"is **not** constant: max |balance|/E = {s['max_balance_rel']:.2e}")
                   + f". Up to {100 * s['max_strain_share']:.0f} % of E is at times strain energy "
                   "(vibration of the beam).")
        out.append(bounce_sentence(s))
    s = by.get("OFF")
    if s is not None:
        out.append(f"- **OFF** (plain Newmark with exact contact) changes the total energy by "
                   f"{100 * s['total_drift_rel']:+.1f} % of E by the end "
                   f"(max |balance|/E = {s['max_balance_rel']:.2e}): the {s['establish']} contact "
                   f"establishments lose Σ E_j = {s['restored']:.4g} J, never given back.")
        out.append(bounce_sentence(s))
    if by:
        out.append("- Contact establishments: " + ", ".join(f"{m} {by[m]['establish']}" for m in
                                                            ("PAPER", "PERSIST", "AUTO", "OFF") if m in by)
                   + "; per bounce: " + ", ".join(
                       f"{m} {by[m]['establish'] / max(1, len(by[m]['apex_heights']) - 1):.1f}"
                       for m in ("PAPER", "PERSIST", "AUTO", "OFF") if m in by) + ".")
    if steps:
        good = [(e, s) for e, s, _ in steps if s is not None]
        worst = max((s["max_balance_rel"] for _, s in good), default=0.0)
        out.append(f"- Steps {', '.join(fmt(e['step']) for e, _ in good)} s: max |balance|/E is at most "
                   f"{worst:.1e}" + (": the energy is exact whatever the step." if worst < ROUNDOFF
                                     else ", above round-off for some step."))
        if spreads:
            first = spreads[0]
            out.append(f"  The first rebound reaches {first[1]:.4g} to {first[2]:.4g} across the steps "
                       f"(spread {100 * first[3]:.1f} % of the release drop); over the bounces that every "
                       f"step has, the largest spread is {100 * max(x[3] for x in spreads):.1f} %.")
        if len(good) >= 2:
            (e1, s1), (e2, s2) = good[0], good[1]
            n = min(len(s1["apex_heights"]), len(s2["apex_heights"]))
            drop = max(rise(s1, 0), rise(s2, 0))
            if n > 1 and drop > 0:
                d = max(abs(s1["apex_heights"][k] - s2["apex_heights"][k]) for k in range(1, n))
                out.append(f"  Between the two smallest steps ({fmt(e1['step'])} and {fmt(e2['step'])} s) "
                           f"the first {n - 1} apex heights differ by at most {100 * d / drop:.1f} % of the "
                           "release drop; the bounce times drift apart from one step to the other "
                           "(« différents en temps »).")
    if scene_name == "beam_drop_inclined" and "PAPER" in by:
        for m in ("PAPER", "PERSIST", "AUTO"):
            if m not in by or not by[m]["impacts"]:
                continue
            imp, ends = by[m]["impacts"], by[m]["ends"]
            if len(ends) == 2:
                (na, ia), (nb, ib) = sorted(ends.items())
                kinds = [(ia in x) + 2 * (ib in x) for x in imp]
                out.append(f"- {m}: of {len(imp)} impacts (contact establishments between two apexes), "
                           f"{kinds.count(1)} touch the ground with `{na}` only, {kinds.count(2)} with `{nb}` "
                           f"only, {kinds.count(3)} with both ends, {kinds.count(0)} with inner nodes only "
                           f"(end nodes {ia} and {ib}; sequence: "
                           + " ".join("·AB+"[k] for k in kinds[:40]) + (" …" if len(kinds) > 40 else "")
                           + f", A = `{na}`, B = `{nb}`, + = both, · = neither).")
            else:
                one = sum(1 for x in imp if len(x) == 1)
                out.append(f"- {m}: of {len(imp)} impacts (contact establishments between two apexes), {one} "
                           f"touch a single node, {len(imp) - one} several nodes.")
    return "\n".join(out)


def git_head():
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                              check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--results", default="results/validation")
    p.add_argument("--figures", default="docs/figures")
    p.add_argument("--doc", default="docs/validation.md")
    p.add_argument("--scenes", default="")
    p.add_argument("--skipped", default="")
    p.add_argument("--probe", action="append", default=[])
    p.add_argument("--inputs", default="inputs", help="folder of the scene files")
    a = p.parse_args(argv)
    scenes = a.scenes.split()
    skipped = a.skipped.split()
    docdir = os.path.dirname(os.path.abspath(a.doc))

    L = ["# Validation: beams dropped on the ground", "",
         f"Generated by `make validation` (`tools/make_validation.sh`) on "
         f"{datetime.date.today().isoformat()}, from commit `{git_head()}` plus the working tree. "
         "Re-run it to refresh every number and figure.", "",
         "The paper validates the method (section 3.4) on two scenes with no closed-form solution: a "
         "vertical beam and an inclined beam dropped on a rigid ground. Each scene is run with the "
         "treatments of contact establishment (`--set SCHEME.IMPACT=PAPER|PERSIST|AUTO|OFF`, "
         "docs/contact.md; AUTO, the default, is MASSLESS on a beam) at its own step, and with PAPER at several steps (`--set TIME.STEP=…`).", "",
         "Measures (tools/rebond_results.py):", "",
         "- **E** = max over the run of kinetic + strain energy: the scale of every relative figure.",
         "- **total** = kinetic + internal − external = kinetic + strain + gravity potential "
         "(+ dissipated): gravity is the only load, so the potential relative to t = 0 is −external. "
         "**balance** is total − total(0), written by rebond; *total drift* is its last value, "
         "*total range* max − min of total, both over E.",
         "- **apex heights**: the probe signal (the mean of the scene's UY probes, as heights above the "
         "ground) at the apex of each flight of the beam. A flight is a run of steps with no active "
         "contact lasting at least 2 % of the longest flight (shorter ones are chatter); its apex is "
         "where the gravity potential, i.e. the height of the centre of mass, is largest, when that is "
         "inside the flight. Apex 0 is the release position; *bounces* counts the others.",
         "- **establish / release**: contact events in events.csv. **Σ E_j**: the energy the scheme loses "
         "at those establishments, eq (10) (the `energy_restored` column): given back as kinetic energy "
         "by PAPER, PERSIST and AUTO, lost with OFF.",
         "- **centre-of-mass rise**: at each bounce, the rise of the centre of mass from its lowest point "
         "since the previous apex, over its first drop, measured on the gravity potential.", ""]

    for name in scenes:
        sdir = os.path.join(a.results, name)
        manifest = os.path.join(sdir, "runs.txt")
        scene_file = os.path.join(a.inputs, name + ".dat")
        scene = SceneInfo(scene_file) if os.path.exists(scene_file) else None
        L += [f"## {name}", ""]
        if scene and scene.title:
            L += [f"`{scene_file}`: {scene.title}. Step {fmt(scene.step)} s. Results in `{sdir}/`.", ""]
        if not os.path.exists(manifest):
            L += ["No runs found.", ""]
            continue
        entries = read_manifest(manifest)
        rows = []
        for e in entries:
            s, err = load(e, scene, a.probe)
            rows.append((e, s, err))
        modes = [r for r in rows if r[0]["label"] in ("PAPER", "PERSIST", "AUTO", "OFF")]
        steps = sorted([r for r in rows if r[0]["mode"] == "PAPER"], key=lambda r: r[0]["step"])
        claim = CLAIMS.get(name)
        L += ["### Reference", ""]
        if claim:
            L += ["> " + claim[0], "", claim[1], ""]
        else:
            L += ["No claim of the paper is attached to this scene: constant total energy for PAPER "
                  "and PERSIST is the reference.", ""]
        L += ["### Measured: impact treatments", "", modes_table(modes), ""]
        ylab = next((s["ylabel"] for _, s, _ in rows if s is not None), "")
        tab, _ = apex_table(modes, spread=False)
        L += [f"Apex heights ({ylab}):", "", tab, ""]
        L += ["### Measured: IMPACT PAPER at several steps", "", modes_table(steps), ""]
        tab, spreads = apex_table(steps)
        L += [f"Apex heights across steps ({ylab}):", "", tab, ""]
        L += ["### Figures", ""]
        for fig, cap in ((f"{name}_modes.png", "PAPER, PERSIST, AUTO and OFF overlaid: probe height, apex heights, "
                          "energy error (log scale)."),
                         (f"{name}_steps.png", "PAPER at several steps overlaid."),
                         (f"{name}_energy_PAPER.png", "PAPER: energy components, energy error, probe height "
                          "and apexes."),
                         (f"{name}_energy_PERSIST.png", "PERSIST: the same."),
                         (f"{name}_energy_AUTO.png", "AUTO (MASSLESS): the same."),
                         (f"{name}_energy_OFF.png", "OFF: the same.")):
            path = os.path.join(a.figures, fig)
            if os.path.exists(path):
                L += [f"![{cap}]({os.path.relpath(os.path.abspath(path), docdir)})", "", f"*{cap}*", ""]
        L += ["### Reading", "", reading(name, modes, steps, spreads), ""]
        failed = [e for e, _, _ in rows if e["status"] != 0]
        if failed:
            L += ["**Runs that did not finish**: " + ", ".join(
                f"{e['label']} (exit {e['status']}, see `{e['dir']}/run.log`)" for e in failed), ""]

    if skipped:
        L += ["## Not run", "", "These scenes were missing when the report was generated (skipped): "
              + ", ".join(f"`{a.inputs}/{s}.dat`" for s in skipped) + ". Run `make validation` again once they exist.",
              ""]
    if not scenes:
        L += ["No validation scene was available: nothing measured yet.", ""]
    os.makedirs(docdir, exist_ok=True)
    with open(a.doc, "w") as f:
        f.write("\n".join(L))
    return 0


if __name__ == "__main__":
    sys.exit(main())
