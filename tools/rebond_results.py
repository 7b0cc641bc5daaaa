"""Reading rebond's OUTDIR (history.csv, probes.csv, events.csv) and the few facts of a scene
the plots need (gravity, the ground plane, the initial position of probed nodes), plus the
measures shared by tools/plot_energy.py, tools/plot_compare.py and tools/validation_report.py.

Energy components (docs/input.md, Output):
  kinetic      1/2 v'Mv
  strain       `stored` (recoverable elastic energy); for elastic laws it equals `internal`
  potential    -external: when gravity is the only external load, its work W satisfies
               V(t) = V(0) - W(t), so the potential energy relative to the initial position is
               -external
  total        kinetic + internal - external = kinetic + strain + potential + dissipated,
               the quantity the method keeps constant (balance = total - total(0)).
"""
import csv
import math
import os
import shlex

import numpy as np


# ----------------------------------------------------------------------------- CSV files
def read_csv(path):
    """Numeric CSV with a header -> dict column name -> float array (keeps dots in names)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise ValueError(f"{path}: empty file")
    names = [n.strip() for n in rows[0]]
    data = np.array([[float(x) for x in r] for r in rows[1:] if r], dtype=float)
    if data.size == 0:
        data = np.zeros((0, len(names)))
    return {n: data[:, i] for i, n in enumerate(names)}


def read_events(path):
    """events.csv -> list of dicts (missing file: no events)."""
    if not os.path.exists(path):
        return []
    out = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            out.append({"step": int(r["step"]), "time": float(r["time"]),
                        "constraint": int(r["constraint"]), "nodes": r["nodes"].strip(),
                        "event": r["event"].strip(), "gap_start": float(r["gap_start"]),
                        "multiplier": float(r["multiplier"]),
                        "energy_restored": float(r["energy_restored"]),
                        "contact": (r.get("contact") or "").strip()})
    return out


class Run:
    """One OUTDIR."""

    def __init__(self, outdir, label=None):
        self.outdir = outdir
        self.label = label or os.path.basename(os.path.normpath(outdir))
        self.hist = read_csv(os.path.join(outdir, "history.csv"))
        ppath = os.path.join(outdir, "probes.csv")
        self.probes = read_csv(ppath) if os.path.exists(ppath) else {"step": self.hist["step"]}
        self.events = read_events(os.path.join(outdir, "events.csv"))
        self.t = self.hist["time"]

    # energies -----------------------------------------------------------------------
    def energies(self):
        h = self.hist
        kin = h["kinetic"]
        internal = h["internal"]
        strain = h["stored"] if "stored" in h else internal
        dissipated = h["dissipated"] if "dissipated" in h else np.zeros_like(kin)
        potential = -h["external"]
        damping = h["damping"] if "damping" in h else np.zeros_like(kin)
        impact = h["impact_dissipated"] if "impact_dissipated" in h else np.zeros_like(kin)
        held = h["contact_held"] if "contact_held" in h else np.zeros_like(kin)
        # internal holds the plastic work already; damping, inelastic impacts and the energy a
        # contact holds until its release (IMPACT SYMMETRIC) are booked apart.
        total = kin + internal + potential + damping + impact + held
        return {"kinetic": kin, "strain": strain, "potential": potential,
                "dissipated": dissipated, "damping": damping, "impact": impact, "held": held,
                "total": total, "balance": h["balance"]}

    def energy_scale(self):
        """The energy swing of the run, max(kinetic + strain): the scale of relative errors."""
        e = self.energies()
        s = float(np.max(e["kinetic"] + e["strain"])) if e["kinetic"].size else 0.0
        return s if s > 0 else 1.0

    def contact_on_probe_rows(self):
        """For each row of probes.csv, whether some contact was active at any step since the
        previous row (from events.csv, so contacts shorter than the output interval count), or
        None when there is no contact data. A condition established at step s and released at
        step r is active at the ends of steps s .. r-1."""
        ps = self.probes["step"].astype(np.int64)
        if ps.size == 0:
            return None
        if not self.events:
            act = self.history_on_probe_rows("active_contacts")
            return None if act is None else act > 0
        last = int(max(ps[-1], max(ev["step"] for ev in self.events)))
        mark = np.zeros(last + 2)
        opened = {}
        for ev in sorted(self.events, key=lambda e: e["step"]):
            if ev["event"] == "establish":
                opened.setdefault(ev["constraint"], ev["step"])
            elif ev["event"] == "release" and ev["constraint"] in opened:
                s0 = opened.pop(ev["constraint"])
                mark[s0] += 1
                mark[ev["step"]] -= 1
        for s0 in opened.values():
            mark[s0] += 1
        active = np.cumsum(mark) > 0               # active[s]: some contact at the end of step s
        csum = np.concatenate(([0], np.cumsum(active)))
        prev = np.concatenate(([ps[0]], ps[:-1]))
        return (csum[ps + 1] - csum[prev + 1] > 0) | active[ps]

    def count_events(self, kind):
        return sum(1 for ev in self.events if ev["event"] == kind)

    def probe_names(self):
        return [n for n in self.probes if n not in ("step", "time")]

    def probe_time(self):
        return self.probes["time"] if "time" in self.probes else self.t

    def history_on_probe_rows(self, column):
        """A history.csv column on the rows of probes.csv (matched by step number), or None."""
        if column not in self.hist:
            return None
        hs = self.hist["step"].astype(np.int64)
        ps = self.probes["step"].astype(np.int64)
        if hs.size == 0:
            return None
        idx = np.minimum(np.searchsorted(hs, ps), hs.size - 1)
        if np.any(hs[idx] != ps):
            return None
        return self.hist[column][idx]


# ----------------------------------------------------------------------------- scene facts
def _statements(path):
    """Scene statements as token lists (comments, '&' continuations and quotes handled)."""
    stmts, buf = [], ""
    with open(path) as f:
        for raw in f:
            line = raw.rstrip("\n")
            # '#' starts a comment unless inside quotes
            out, inq = [], False
            for ch in line:
                if ch == '"':
                    inq = not inq
                if ch == "#" and not inq:
                    break
                out.append(ch)
            line = "".join(out).rstrip()
            if line.endswith("&"):
                buf += line[:-1] + " "
                continue
            line = buf + line
            buf = ""
            if line.strip():
                try:
                    stmts.append(shlex.split(line))
                except ValueError:
                    stmts.append(line.split())
    return stmts


def _after(tokens, key, n):
    up = [t.upper() for t in tokens]
    if key in up:
        i = up.index(key)
        return [float(x) for x in tokens[i + 1:i + 1 + n]]
    return None


class SceneInfo:
    """Gravity, the ground plane and the initial coordinates of one-node groups that the
    generators name (NODE, LINE start/end/mid, RECTANGLE corners/center)."""

    def __init__(self, path=None):
        self.path = path
        self.title = None
        self.gravity = (0.0, 0.0)
        self.coords = {}
        self.obstacles = []
        self.step = None
        self.work_sources = []     # what does external work: gravity, loads, pressure, traction, imposed motion
        if path:
            self._parse(path)

    def _parse(self, path):
        for tk in _statements(path):
            key = tk[0].upper()
            if key == "TITLE" and len(tk) > 1:
                self.title = " ".join(tk[1:])
            elif key == "GRAVITY":
                gx = _after(tk, "GX", 1)
                gy = _after(tk, "GY", 1)
                self.gravity = (gx[0] if gx else 0.0, gy[0] if gy else 0.0)
            elif key == "NODE" and len(tk) > 1:
                at = _after(tk, "AT", 2)
                if at:
                    self.coords[tk[1]] = tuple(at)
            elif key == "LINE" and len(tk) > 1:
                a, b, n = _after(tk, "FROM", 2), _after(tk, "TO", 2), _after(tk, "ELEMENTS", 1)
                if a and b:
                    name = tk[1]
                    self.coords[name + ".start"] = tuple(a)
                    self.coords[name + ".end"] = tuple(b)
                    if n:
                        ne = int(n[0])
                        s = (ne // 2) / ne
                        self.coords[name + ".mid"] = (a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]))
            elif key == "RECTANGLE" and len(tk) > 1:
                o, sz = _after(tk, "ORIGIN", 2), _after(tk, "SIZE", 2)
                ang = _after(tk, "ANGLE", 1)
                if o and sz:
                    c, s = math.cos(math.radians(ang[0] if ang else 0.0)), math.sin(math.radians(ang[0] if ang else 0.0))
                    def at(px, py):
                        return (o[0] + c * px - s * py, o[1] + s * px + c * py)
                    name, lx, ly = tk[1], sz[0], sz[1]
                    for suffix, (px, py) in {"bottom_left": (0, 0), "bottom_right": (lx, 0),
                                             "top_left": (0, ly), "top_right": (lx, ly),
                                             "center": (lx / 2, ly / 2)}.items():
                        self.coords[f"{name}.{suffix}"] = at(px, py)
            elif key == "OBSTACLE":
                p, nrm = _after(tk, "POINT", 2), _after(tk, "NORMAL", 2)
                if p and nrm:
                    self.obstacles.append((tuple(p), tuple(nrm)))
            elif key == "TIME":
                st = _after(tk, "STEP", 1)
                if st:
                    self.step = st[0]
            source = {"LOAD": "loads", "PRESSURE": "pressure", "TRACTION": "traction",
                      "IMPOSE": "imposed motion"}.get(key)
            if source and source not in self.work_sources:
                self.work_sources.append(source)
        if self.gravity != (0.0, 0.0):
            self.work_sources.insert(0, "gravity")

    def up(self):
        """Unit vector opposite to gravity (None without gravity)."""
        g = math.hypot(*self.gravity)
        return None if g == 0 else (-self.gravity[0] / g, -self.gravity[1] / g)

    def ground(self):
        """The obstacle plane facing up (normal along -g, or +y without gravity)."""
        up = self.up() or (0.0, 1.0)
        for p, n in self.obstacles:
            nn = math.hypot(*n)
            if nn > 0 and abs(n[0] / nn - up[0]) < 1e-9 and abs(n[1] / nn - up[1]) < 1e-9:
                return p, (n[0] / nn, n[1] / nn)
        return None


# ----------------------------------------------------------------------------- heights
def probe_signal(run, probes, scene=None):
    """Mean of the chosen probe columns (default: every UY probe, else every probe).

    With a scene whose probed groups have known coordinates and a ground plane normal to y,
    the signal is the height above the ground (coordinate + displacement - ground y);
    otherwise the mean displacement. Returns (time, signal, ylabel, names)."""
    names = list(probes) if probes else [n for n in run.probe_names() if n.upper().endswith(".UY")]
    if not names:
        names = run.probe_names()
    if not names:
        raise ValueError(f"{run.outdir}: probes.csv has no probe column")
    missing = [n for n in names if n not in run.probes]
    if missing:
        raise ValueError(f"{run.outdir}: no probe {', '.join(missing)} (have {', '.join(run.probe_names())})")
    absolute = scene is not None and all(
        n.rsplit(".", 1)[0] in scene.coords and n.rsplit(".", 1)[1].upper() in ("UX", "UY") for n in names)
    cols = []
    for n in names:
        u = run.probes[n].copy()
        if absolute:
            group, dof = n.rsplit(".", 1)
            u += scene.coords[group][0 if dof.upper() == "UX" else 1]
        cols.append(u)
    sig = np.mean(cols, axis=0)
    what = names[0] if len(names) == 1 else "mean of " + ", ".join(names)
    kinds = {probe_kind(n) for n in names}
    ylabel = (f"{kinds.pop()}\n{what}" if len(kinds) == 1 else f"mixed quantities\n{what}")
    if absolute and all(n.upper().endswith(".UY") for n in names):
        gr = scene.ground()
        if gr is not None and abs(gr[1][0]) < 1e-12:
            sig = sig - gr[0][1]
            ylabel = f"height above ground (m)\n{what}"
        else:
            ylabel = f"y (m)\n{what}"
    return run.probe_time(), sig, ylabel, names


PROBE_KINDS = {"UX": "displacement (m)", "UY": "displacement (m)", "RZ": "rotation (rad)",
               "VX": "velocity (m/s)", "VY": "velocity (m/s)", "VRZ": "angular velocity (rad/s)",
               "RX": "reaction (N)", "RY": "reaction (N)", "MZ": "reaction moment (N m)"}


def probe_kind(name):
    """What a probe column (group.DOF) measures, with its unit."""
    return PROBE_KINDS.get(name.rsplit(".", 1)[-1].upper(), "value")


def find_apexes(run, t, sig, min_flight_frac=0.02, min_rise_frac=0.01):
    """Apexes of the body's flights, read on the probe signal.

    A flight is a maximal run of output rows with no contact active since the previous row
    (from events.csv: contacts shorter than the output interval count). It is a bounce when
    it lasts at least min_flight_frac of the longest flight (shorter ones are chatter) and
    when the gravity potential -external, which under gravity alone is m g times the height
    of the centre of mass, reaches its maximum strictly inside it: a flight during which the
    centre of mass only falls (one end lifts off while the other is about to hit) or only
    rises (the run ends) has no apex. The release flight at t = 0 counts, its apex being the
    release position. The apex height is the probe signal at the time of the centre-of-mass
    apex. Without contact data (or no contact at all), the local maxima of the signal.
    Returns a list of (time, height, row)."""
    contact = run.contact_on_probe_rows()
    pot = run.history_on_probe_rows("external")
    if contact is None or pot is None or not np.any(contact):
        i = np.where((sig[1:-1] > sig[:-2]) & (sig[1:-1] >= sig[2:]))[0] + 1
        return [(t[k], sig[k], k) for k in i]
    pot = -pot
    free = ~contact
    flights, k, n = [], 0, free.size
    while k < n:
        if free[k]:
            j = k
            while j + 1 < n and free[j + 1]:
                j += 1
            flights.append((k, j))
            k = j + 1
        else:
            k += 1
    if not flights:
        return []
    longest = max(t[j] - t[i] for i, j in flights)
    span = float(np.max(pot) - np.min(pot))
    out = []
    for i, j in flights:
        if t[j] - t[i] < min_flight_frac * longest:
            continue
        m = i + int(np.argmax(pot[i:j + 1]))
        if (m == i and i > 0) or (m == j and j > i):
            continue
        if out and pot[m] - np.min(pot[out[-1][2]:m + 1]) < min_rise_frac * span:
            continue
        out.append((t[m], sig[m], m))
    return out


def summary(run, probes=None, scene=None, min_flight_frac=0.02, min_rise_frac=0.01):
    """The measures the validation report quotes, for one run."""
    e = run.energies()
    scale = run.energy_scale()
    tot = e["total"]
    t, sig, _, names = probe_signal(run, probes, scene)
    ap = find_apexes(run, t, sig, min_flight_frac, min_rise_frac)
    strain_share = float(np.max(e["strain"]) / scale) if scale else 0.0
    # Rise of the centre of mass at each bounce, relative to its first drop: under gravity
    # alone the potential -external is m g times the centre-of-mass height, so ratios of
    # potential differences are ratios of heights, whatever the probes and the mass.
    cm_rise = []
    pot = run.history_on_probe_rows("external")
    if pot is not None and len(ap) > 1:
        pot = -pot
        rows = [a[2] for a in ap]
        drop = pot[rows[0]] - np.min(pot[rows[0]:rows[1] + 1])
        for k in range(1, len(rows)):
            low = np.min(pot[rows[k - 1]:rows[k] + 1])
            cm_rise.append(float((pot[rows[k]] - low) / drop) if drop > 0 else float("nan"))
    return {
        "label": run.label,
        "steps": int(run.hist["step"][-1]) if run.hist["step"].size else 0,
        "t_end": float(run.t[-1]) if run.t.size else 0.0,
        "energy_scale": scale,
        "max_balance_rel": float(np.max(np.abs(e["balance"])) / scale),
        "total_drift_rel": float((tot[-1] - tot[0]) / scale),
        "total_range_rel": float((np.max(tot) - np.min(tot)) / scale),
        "max_strain_share": strain_share,
        "establish": run.count_events("establish"),
        "release": run.count_events("release"),
        "restored": float(sum(ev["energy_restored"] for ev in run.events if ev["event"] == "establish")),
        "apex_times": [float(a[0]) for a in ap],
        "apex_heights": [float(a[1]) for a in ap],
        "cm_rise": cm_rise,
        "probes": names,
    }


def rebound_ylim(height_lists, release):
    """y limits for a plot of apex heights: the rebounds only (apex 0 off scale) when they all
    stay in a band less than 30 % as tall as the release height above them; None otherwise."""
    reb = [h for hs in height_lists for h in hs[1:]]
    if not reb:
        return None
    lo, hi = min(reb), max(reb)
    if release - lo <= 0 or (hi - lo) >= 0.3 * (release - lo):
        return None
    pad = 0.08 * (hi - lo) if hi > lo else 0.05 * abs(hi) + 1e-6
    return lo - pad, hi + pad
