#!/usr/bin/python3
"""Energy components and rebound heights of one rebond run, as a PNG.

    tools/plot_energy.py OUTDIR [--scene SCENE.dat] [--probe beam.start.UY ...]
                         [--title TEXT] [-o FILE.png]

Panels:
  (a) kinetic, strain (`stored`), gravity potential (-external, relative to the initial
      position: exact when gravity is the only external load), and when non-zero the plastic
      work, the damping (`damping`) and the inelastic impacts' loss (`impact_dissipated`);
      total = kinetic + internal + potential + damping + impact losses;
  (b) total - total(0) and the balance column, relative to max(kinetic + strain);
  (c) the probe signal (one probe, or the mean of several; default every UY probe) against
      time, with its apexes and the contact-establishment times of events.csv;
  (d) the apex heights against the bounce number (0 = release).

--scene gives the initial coordinates of the probed nodes and the ground plane, so heights are
heights above the ground; without it the signal is the displacement. --gravity GX GY is used
only when no scene is given, to draw the potential-energy label (it is informative).
"""
import argparse
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.dont_write_bytecode = True  # no __pycache__ in tools/
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rebond_results import Run, SceneInfo, find_apexes, probe_signal, rebound_ylim  # noqa: E402

COLORS = {"kinetic": "tab:blue", "strain": "tab:orange", "potential": "tab:green",
          "dissipated": "tab:purple", "damping": "tab:brown", "impact": "tab:pink", "total": "black"}
NAMES = {"dissipated": "plastic work", "damping": "damping (Rayleigh)", "impact": "inelastic impacts"}


def plot_run(run, scene, probes, title, out, apex_opts=(0.02, 0.01)):
    e = run.energies()
    t = run.t
    scale = run.energy_scale()
    losses = [k for k in ("dissipated", "damping", "impact") if np.any(np.abs(e[k]) > 1e-12 * scale)]

    fig, axes = plt.subplots(2, 2, figsize=(13, 8.5), constrained_layout=True)
    ax = axes[0, 0]
    for k in ("kinetic", "strain", "potential") + tuple(losses):
        ax.plot(t, e[k], color=COLORS[k], lw=1.0, label=NAMES.get(k, k))
    tot_label = "total = kinetic + strain + potential" + "".join(" + " + NAMES[k] for k in losses)
    ax.plot(t, e["total"], color=COLORS["total"], lw=1.6, label=tot_label)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy (J)")
    ax.set_title("(a) energy components (potential relative to t = 0)")
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

    tp, sig, ylabel, names = probe_signal(run, probes, scene)
    ap = find_apexes(run, tp, sig, *apex_opts)
    ax = axes[1, 0]
    ax.plot(tp, sig, color="tab:blue", lw=0.9, label=names[0] if len(names) == 1 else "mean of probes")
    if ap:
        ax.plot([a[0] for a in ap], [a[1] for a in ap], "v", color="tab:red", ms=6, label="apexes")
    est = [ev["time"] for ev in run.events if ev["event"] == "establish"]
    if est:
        y0 = ax.get_ylim()[0]
        ax.plot(est, [y0] * len(est), "|", color="tab:gray", ms=10, label=f"contact established ({len(est)})")
    ax.set_xlabel("time (s)")
    ax.set_ylabel(ylabel, fontsize=9)
    ax.set_title("(c) probe height and apexes")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=3, fontsize=8)
    ax.grid(alpha=0.3)

    ax = axes[1, 1]
    if ap:
        hts = np.array([a[1] for a in ap])
        nb = np.arange(hts.size)
        ax.plot(nb, hts, "o-", color="tab:red", ms=5)
        ax.axhline(hts[0], color="gray", ls=":", lw=1, label=f"release height {hts[0]:.4g} m")
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
    else:
        ax.text(0.5, 0.5, "no apex found", ha="center", va="center", transform=ax.transAxes)
    ax.set_xlabel("bounce number (0 = release)")
    ax.set_ylabel(ylabel, fontsize=9)
    if not ax.get_title():
        ax.set_title("(d) rebound (apex) heights")
    ax.grid(alpha=0.3)

    fig.suptitle(title or (scene.title if scene and scene.title else run.label), fontsize=12)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return ap


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
        out = a.output or os.path.join(a.outdir, "energy.png")
        ap = plot_run(run, scene, a.probe, a.title, out, (a.min_flight, a.min_rise))
    except (OSError, ValueError, KeyError) as exc:
        print(f"plot_energy: {exc}", file=sys.stderr)
        return 2
    print(f"{out}: {len(ap)} apexes" + (", heights " + " ".join(f"{h:.4g}" for _, h, _ in ap[:12]) if ap else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
