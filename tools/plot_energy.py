#!/usr/bin/python3
"""Energy components and rebound heights of one rebond run, as a PNG.

    tools/plot_energy.py OUTDIR [--scene SCENE.dat] [--probe beam.start.UY ...]
                         [--title TEXT] [-o FILE.png]

Panels:
  (a) kinetic, strain (`stored`), the work of the external actions (-external, named by its
      sources from the scene: "gravity potential" when gravity is the only one, else "-work of
      gravity, loads, pressure, traction, imposed motion" as the scene has them; "external work"
      without --scene), and when non-zero the plastic work, the damping (`damping`), the
      inelastic impacts' loss (`impact_dissipated`) and the energy the contacts hold until their
      release (`contact_held`); total = their sum;
  (b) total - total(0) and the balance column, relative to max(kinetic + strain);
  (c) the probe signal (one probe, or the mean of several; default every UY probe) against
      time, labelled by its kind and unit (displacement m, velocity m/s, rotation rad, reaction
      N), with its apexes and the contact-establishment times of events.csv; a run without
      probes shows the contact force of contacts.csv instead (or says there is nothing to show);
  (d) the apex heights against the bounce number (0 = release), only where the body bounces.

--scene gives the initial coordinates of the probed nodes, the ground plane and the sources of
external work, so heights are heights above the ground; without it the signal is the probe's
value. --gravity GX GY is used only when no scene is given, to name the external work.
"""
import argparse
import csv
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.dont_write_bytecode = True  # no __pycache__ in tools/
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rebond_results import Run, SceneInfo, find_apexes, probe_kind, probe_signal, rebound_ylim  # noqa: E402

COLORS = {"kinetic": "tab:blue", "strain": "tab:orange", "potential": "tab:green",
          "dissipated": "tab:purple", "damping": "tab:brown", "impact": "tab:pink", "held": "tab:olive",
          "total": "black"}
NAMES = {"dissipated": "plastic work", "damping": "damping (Rayleigh)", "impact": "inelastic impacts",
         "held": "held by contacts"}


def work_name(scene):
    """The name of -external: what does the external work."""
    src = scene.work_sources if scene is not None else []
    if src == ["gravity"]:
        return "gravity potential"
    if src:
        return "−work of " + ", ".join(src)
    return "−external work"


def plot_run(run, scene, probes, title, out, apex_opts=(0.02, 0.01)):
    e = run.energies()
    t = run.t
    scale = run.energy_scale()
    losses = [k for k in ("dissipated", "damping", "impact", "held") if np.any(np.abs(e[k]) > 1e-12 * scale)]
    pot = np.any(np.abs(e["potential"]) > 1e-12 * scale)
    names = dict(NAMES, potential=work_name(scene))

    fig, axes = plt.subplots(2, 2, figsize=(13, 8.5), constrained_layout=True)
    ax = axes[0, 0]
    for k in ("kinetic", "strain") + (("potential",) if pot else ()) + tuple(losses):
        ax.plot(t, e[k], color=COLORS[k], lw=1.0, label=names.get(k, k))
    tot_label = ("total = kinetic + strain" + (" + " + names["potential"] if pot else "") +
                 "".join(" + " + NAMES[k] for k in losses))
    ax.plot(t, e["total"], color=COLORS["total"], lw=1.6, label=tot_label)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy (J)")
    ax.set_title("(a) energy components" + (" (external work from t = 0)" if pot else ""))
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=3, fontsize=8)
    ax.grid(alpha=0.3)

    ax = axes[0, 1]
    drift = (e["total"] - e["total"][0]) / scale
    ax.plot(t, drift, color="black", lw=1.2, label="(total − total(0)) / E")
    ax.plot(t, e["balance"] / scale, color="tab:red", lw=0.8, ls="--", label="balance / E")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("relative energy error")
    ax.set_title(f"(b) energy error, E = max(kinetic + strain) = {scale:.4g} J", pad=14)
    ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 3), useOffset=False)
    ax.legend(loc="best", fontsize=8)
    ax.grid(alpha=0.3)
    mx = float(np.max(np.abs(drift))) if drift.size else 0.0
    ax.text(0.02, 0.04, f"max |total − total(0)| / E = {mx:.2e}\n"
            f"max |balance| / E = {np.max(np.abs(e['balance'])) / scale:.2e}",
            transform=ax.transAxes, fontsize=8, va="bottom",
            bbox=dict(facecolor="white", alpha=0.8, edgecolor="none"))

    ap = []
    if run.probe_names() or probes:
        tp, sig, ylabel, pnames = probe_signal(run, probes, scene)
        # Apexes are bounce heights: only on displacement probes (UX, UY) of a run with contacts.
        if run.events and all(probe_kind(n).startswith("displacement") for n in pnames):
            ap = find_apexes(run, tp, sig, *apex_opts)
        probe_panel(axes[1, 0], run, tp, sig, ylabel, pnames, ap)
    else:
        contact_panel(axes[1, 0], run)
        ylabel = ""
    bounce_panel(axes[1, 1], run, ap, ylabel)
    fig.suptitle(title or (scene.title if scene and scene.title else run.label), fontsize=12)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return ap


def probe_panel(ax, run, tp, sig, ylabel, names, ap):
    """(c) the probe signal with its apexes and the contact establishments."""
    if len(names) > 1 and not all(n.upper().endswith(".UY") for n in names):
        for n in names:                      # different quantities: each on its own line
            ax.plot(tp, run.probes[n], lw=0.9, label=n)
        ylabel = ylabel.split("\n")[0]
    else:
        ax.plot(tp, sig, color="tab:blue", lw=0.9, label=names[0] if len(names) == 1 else "mean of probes")
    if ap:
        ax.plot([a[0] for a in ap], [a[1] for a in ap], "v", color="tab:red", ms=6, label="apexes")
    est = [ev["time"] for ev in run.events if ev["event"] == "establish"]
    if est:
        y0 = ax.get_ylim()[0]
        ax.plot(est, [y0] * len(est), "|", color="tab:gray", ms=10, label=f"contact established ({len(est)})")
    ax.set_xlabel("time (s)")
    ax.set_ylabel(ylabel, fontsize=9)
    ax.set_title("(c) probe and apexes" if ap else "(c) probe")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=3, fontsize=8)
    ax.grid(alpha=0.3)


def contact_panel(ax, run):
    """(c) without probes: the contact forces of contacts.csv, or a note."""
    path = os.path.join(run.outdir, "contacts.csv")
    rows = []
    if os.path.exists(path):
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    if not rows:
        ax.text(0.5, 0.5, "no probe and no contact: nothing to draw here\n(OUTPUT … PROBE group DOF)",
                ha="center", va="center", transform=ax.transAxes)
        ax.set_title("(c) no probe")
        return
    for name in dict.fromkeys(r["contact"] for r in rows):
        sel = [r for r in rows if r["contact"] == name]
        t = np.array([float(r["time"]) for r in sel])
        f = np.array([math.hypot(float(r["force_x"]), float(r["force_y"])) for r in sel])
        ax.plot(t, f, lw=0.9, label=name)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("contact force |F| (N)", fontsize=9)
    ax.set_title("(c) contact forces (contacts.csv; the run has no probe)")
    ax.legend(loc="best", fontsize=8)
    ax.grid(alpha=0.3)


def bounce_panel(ax, run, ap, ylabel):
    """(d) the apex heights against the bounce number, where the body bounces."""
    if len(ap) < 2:
        est = sum(1 for ev in run.events if ev["event"] == "establish")
        ax.text(0.5, 0.5, "no bounce to draw" + (f" ({est} contact establishment{'s' if est > 1 else ''})"
                                                  if est else ""),
                ha="center", va="center", transform=ax.transAxes)
        ax.set_title("(d) rebound heights")
        ax.set_axis_off()
        return
    hts = np.array([a[1] for a in ap])
    nb = np.arange(hts.size)
    ax.plot(nb, hts, "o-", color="tab:red", ms=5)
    ax.axhline(hts[0], color="gray", ls=":", lw=1, label=f"release {hts[0]:.4g}")
    ax.set_xticks(nb if nb.size <= 20 else nb[::max(1, nb.size // 20)])
    ax.legend(loc="best", fontsize=8)
    zoom = rebound_ylim([list(hts)], hts[0])
    if zoom:
        ax.set_ylim(*zoom)
        ax.set_title("(d) rebound (apex) heights — release height off scale")
    else:
        lo, hi = float(hts.min()), float(hts.max())
        pad = 0.1 * (hi - lo) if hi > lo else 0.05 * abs(hi) + 1e-3
        ax.set_ylim(lo - pad, hi + pad)
        ax.set_title("(d) rebound (apex) heights")
    ax.set_xlabel("bounce number (0 = release)")
    ax.set_ylabel(ylabel, fontsize=9)
    ax.grid(alpha=0.3)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("outdir")
    p.add_argument("--scene", help="scene file: probe coordinates, ground plane, gravity, title")
    p.add_argument("--probe", action="append", default=[],
                   help="probe column (group.DOF); repeat to average several; default every UY probe")
    p.add_argument("--gravity", nargs=2, type=float, metavar=("GX", "GY"),
                   help="gravity when no scene is given (for the record only)")
    p.add_argument("--title")
    p.add_argument("--min-flight", type=float, default=0.02,
                   help="a flight shorter than this fraction of the longest is chatter, not a bounce")
    p.add_argument("--min-rise", type=float, default=0.01,
                   help="a hop raising the centre of mass by less than this fraction of its height "
                        "range is not a bounce")
    p.add_argument("-o", "--output", default=None, help="PNG file (default OUTDIR/energy.png)")
    a = p.parse_args(argv)
    try:
        run = Run(a.outdir)
        scene = SceneInfo(a.scene) if a.scene else None
        if scene is None and a.gravity:
            scene = SceneInfo()
            scene.gravity = tuple(a.gravity)
            scene.work_sources = ["gravity"] if any(a.gravity) else []
        out = a.output or os.path.join(a.outdir, "energy.png")
        ap = plot_run(run, scene, a.probe, a.title, out, (a.min_flight, a.min_rise))
    except (OSError, ValueError, KeyError) as exc:
        print(f"plot_energy: {exc}", file=sys.stderr)
        return 2
    print(f"{out}: {len(ap)} apexes" + (", heights " + " ".join(f"{h:.4g}" for _, h, _ in ap[:12]) if ap else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
