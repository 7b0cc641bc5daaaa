#!/usr/bin/python3
"""Overlay several rebond runs of one scene (impact modes, time steps, ...), as a PNG.

    tools/plot_compare.py LABEL=OUTDIR [LABEL=OUTDIR ...] [--scene SCENE.dat]
                          [--probe beam.start.UY ...] [--title TEXT] [-o FILE.png]

A run given as a bare OUTDIR is labelled with its folder name. Panels:
  (a) the probe signal against time (one probe, or the mean of several; default every UY
      probe), with each run's apexes;
  (b) the apex (rebound) heights against the bounce number (0 = release);
  (c) |total - total(0)| / max(kinetic + strain) against time, log scale: the energy each
      run created or lost (total = kinetic + strain + potential + dissipated).
Apexes are those of tools/rebond_results.find_apexes (flights of the body, chatter ignored).
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

FLOOR = 1e-17  # below double round-off of a relative energy: drawn at the floor


def parse_run(spec):
    if "=" in spec and not os.path.isdir(spec):
        label, path = spec.rsplit("=", 1)  # labels may hold "=" (h=1e-4)
        return Run(path, label)
    return Run(spec)


def plot_compare(runs, scene, probes, title, out, apex_opts=(0.02, 0.01)):
    fig = plt.figure(figsize=(13, 8.5), constrained_layout=True)
    gs = fig.add_gridspec(2, 2)
    ax_t = fig.add_subplot(gs[0, :])
    ax_b = fig.add_subplot(gs[1, 0])
    ax_e = fig.add_subplot(gs[1, 1])
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    ylabel = None
    result = {}
    for k, run in enumerate(runs):
        c = colors[k % len(colors)]
        t, sig, ylabel, _ = probe_signal(run, probes, scene)
        ap = find_apexes(run, t, sig, *apex_opts)
        result[run.label] = ap
        ax_t.plot(t, sig, color=c, lw=1.0, label=run.label)
        if ap:
            ax_t.plot([a[0] for a in ap], [a[1] for a in ap], "v", color=c, ms=5)
            ax_b.plot(np.arange(len(ap)), [a[1] for a in ap], "o-", color=c, ms=4, lw=1.2,
                      label=f"{run.label} ({len(ap) - 1} bounces)")
        e = run.energies()
        err = np.abs(e["total"] - e["total"][0]) / run.energy_scale()
        ax_e.semilogy(run.t, np.maximum(err, FLOOR), color=c, lw=0.8,
                      label=f"{run.label}: max {np.max(err):.1e}")

    ax_t.set_xlabel("time (s)")
    ax_t.set_ylabel(ylabel, fontsize=9)
    ax_t.set_title("(a) probe height against time (▼ apexes)")
    ax_t.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=min(len(runs), 6), fontsize=8)
    ax_t.grid(alpha=0.3)

    ax_b.set_xlabel("bounce number (0 = release)")
    ax_b.set_ylabel(ylabel, fontsize=9)
    ax_b.set_title("(b) rebound (apex) heights")
    lists = [[a[1] for a in ap] for ap in result.values() if ap]
    zoom = rebound_ylim(lists, max(hs[0] for hs in lists)) if lists else None
    if zoom:
        ax_b.set_ylim(*zoom)
        ax_b.set_title("(b) rebound (apex) heights — release height off scale")
    ax_b.legend(loc="best", fontsize=8)
    ax_b.grid(alpha=0.3)
    nmax = max((len(a) for a in result.values()), default=0)
    if 0 < nmax <= 25:
        ax_b.set_xticks(range(nmax))

    ax_e.set_xlabel("time (s)")
    ax_e.set_ylabel("|total − total(0)| / max(kinetic + strain)")
    ax_e.set_title("(c) energy error (log scale)")
    ax_e.legend(loc="best", fontsize=8)
    ax_e.grid(alpha=0.3)

    fig.suptitle(title or (scene.title if scene and scene.title else "comparison"), fontsize=12)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return result


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("runs", nargs="+", metavar="LABEL=OUTDIR")
    p.add_argument("--scene", help="scene file: probe coordinates, ground plane, title")
    p.add_argument("--probe", action="append", default=[],
                   help="probe column (group.DOF); repeat to average several; default every UY probe")
    p.add_argument("--title")
    p.add_argument("--min-flight", type=float, default=0.02,
                   help="a flight shorter than this fraction of the longest is chatter, not a bounce")
    p.add_argument("--min-rise", type=float, default=0.01,
                   help="a hop raising the centre of mass by less than this fraction of its height "
                        "range is not a bounce")
    p.add_argument("-o", "--output", default="compare.png", help="PNG file (default compare.png)")
    a = p.parse_args(argv)
    try:
        runs = [parse_run(s) for s in a.runs]
        scene = SceneInfo(a.scene) if a.scene else None
        res = plot_compare(runs, scene, a.probe, a.title, a.output, (a.min_flight, a.min_rise))
    except (OSError, ValueError, KeyError) as exc:
        print(f"plot_compare: {exc}", file=sys.stderr)
        return 2
    for label, ap in res.items():
        print(f"{label}: {len(ap)} apexes " + " ".join(f"{h:.4g}" for _, h, _ in ap[:12]))
    print(f"wrote {a.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
