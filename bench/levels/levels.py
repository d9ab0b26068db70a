#!/usr/bin/env python3
"""Cost against fidelity: one scene at several levels of model (doc/advisor.md).

  levels.py FDEM [OUT_DIR] [--scene slab|column] [--np N] [--count N] [--levels L1,L2,...]

--scene slab (the default): eight stones strike a deformable slab (fixed at
its base) at 1.5 m/s, under gravity. The stones are spheres (the sphere of
each stone's volume, Hertz contact), rigid polyhedra (potential contact) or
deformable meshes; the slab is deformable at every level. Observables:

  strain    the largest strain energy of the scene (the impacts; J)
  rebound   the largest kinetic energy after that peak (the stones' rebound; J)

--scene column: a loose column of pebbles (a jittered lattice, --count of
them, default 1000) is released on a rigid floor and collapses into a heap.
The pebbles are spheres without and with rolling resistance, rigid polyhedra
or deformable meshes. Observables, from the bodies' final centres (bodies.csv,
fragments.csv):

  runout    the horizontal distance from the column's axis within which 95%
            of the pebbles come to rest (m)
  slope     the deposit's mean slope angle (degrees), atan(h / runout), h the
            highest centre within two lattice pitches of the axis (the
            deposit is a low mound, a few pebbles deep, not a cone)

--reuse takes a level's earlier run from OUT_DIR/LEVEL (its run.log and
output) instead of running it again; levels without a run.log are run.

For each level the script runs the fdem driver, reads its CPU time ("stepping
CPU time"; cost = CPU seconds per simulated second) and the observables, and
writes their differences from the last, most faithful level as a table
(levels.csv or column.csv) and a chart (levels.svg or column.svg) of cost
against difference.
"""
import csv
import math
import os
import random
import re
import subprocess
import sys


def arg(name, default):
    return sys.argv[sys.argv.index(name) + 1] if name in sys.argv else default


fdem = sys.argv[1]
out = sys.argv[2] if len(sys.argv) > 2 and not sys.argv[2].startswith("--") else "out_levels"
np_ = arg("--np", "1")
which = arg("--scene", "slab")
if which not in ("slab", "column"):
    sys.exit("levels.py: --scene is slab or column, not %s" % which)
os.makedirs(out, exist_ok=True)
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


# --- eight stones on a slab ------------------------------------------------------------------
class Slab:
    name, title = "levels", "eight stones on a deformable slab, stones at three levels"
    levels = ["spheres", "rigid", "deformable"]
    SIZE, END, V0 = 0.04, 0.06, 1.5
    STONES = [(-0.1, -0.1, 0.035, 1), (0.0, -0.1, 0.04, 2), (0.1, -0.1, 0.045, 3), (-0.1, 0.0, 0.04, 4),
              (0.1, 0.0, 0.035, 5), (-0.1, 0.1, 0.045, 6), (0.0, 0.1, 0.04, 7), (0.1, 0.1, 0.035, 8)]
    observables = [("max_strain_J", "peak strain energy"), ("rebound_J", "rebound kinetic energy")]

    def scene(self, level):
        lines = ["title: stones on a slab, stones as %s" % level,
                 "gravity: [0, 0, -9.81]",
                 "time: {end: %g, scheme: cd}" % self.END,
                 "materials:",
                 "  rubber: {density: 1100, young: 2.0e6, poisson: 0.3, model: neo_hookean, damping: 20}",
                 "  stone: {density: 2600, young: 5.0e7, poisson: 0.25, restitution: 0.6, friction: 0.3, contact_law: hertz}",
                 "contact: {penalty: 5.0e6, friction: 0.3, normal_damping: 200, tangential_viscosity: 1.0e5}",
                 "output: {every: %g, balance: 5.0e-4}" % self.END,
                 "bodies:",
                 "  - {name: slab, model: deformable, material: rubber, shape: {box: [0.4, 0.4, 0.05]}, resolution: 0.025,"
                 " position: [0, 0, -0.025], fix: {below: [z, -0.049]}}"]
        for i, (x, y, z, seed) in enumerate(self.STONES):
            if level == "spheres":
                # the sphere of the stone's volume (a pebble of size s has about the volume of a sphere of radius 0.5 s)
                lines.append("  - {name: s%d, model: sphere, material: stone, shape: {sphere: %g}, position: [%g, %g, %g], velocity: [0, 0, %g]}" % (i, 0.5 * self.SIZE, x, y, z, -self.V0))
            else:
                model = "rigid" if level == "rigid" else "deformable"
                res = "" if level == "rigid" else ", resolution: %g" % (0.5 * self.SIZE)
                lines.append("  - {name: s%d, model: %s, material: stone, shape: {pebble: {size: %g, seed: %d}}%s, position: [%g, %g, %g], velocity: [0, 0, %g]}" % (i, model, self.SIZE, seed, res, x, y, z, -self.V0))
        return "\n".join(lines) + "\n"

    def observe(self, d):
        bal = [{k: float(v) for k, v in row.items()} for row in read_csv(os.path.join(d, "balance.csv"))]
        strain = max(b["strain"] for b in bal)
        t_peak = max(bal, key=lambda b: b["strain"])["time"]
        rebound = max((b["kinetic"] for b in bal if b["time"] > t_peak), default=0.0)
        return {"max_strain_J": strain, "rebound_J": rebound}


# --- a column of pebbles collapsing -------------------------------------------------------------
class Column:
    name, title = "column", "a column of pebbles collapsing, pebbles at four levels"
    levels = ["spheres", "spheres_rolling", "rigid"]   # --levels ...,deformable adds the meshes
    SIZE, END = 0.03, 1.5          # pebble size (its largest semi-axis; m), simulated time (s)
    observables = [("runout_m", "run-out"), ("slope_deg", "slope angle")]

    def __init__(self, count):
        # a square column of n x n pebbles in plan, twice as tall as it is wide; a lattice of pitch
        # 2.3 sizes, each point moved at random by up to 5% of the pitch along each axis (so that no
        # two pebbles touch in any orientation: a pebble lies within one size of its centre), the
        # same for every level
        self.n = max(2, round((count / 2.0) ** (1.0 / 3.0)))
        self.layers = max(1, round(count / self.n ** 2))
        self.pitch = 2.3 * self.SIZE
        rng = random.Random(5)
        self.points = []
        for k in range(self.layers):
            for j in range(self.n):
                for i in range(self.n):
                    jit = [0.05 * self.pitch * (2 * rng.random() - 1) for _ in range(3)]
                    self.points.append(((i - 0.5 * (self.n - 1)) * self.pitch + jit[0], (j - 0.5 * (self.n - 1)) * self.pitch + jit[1],
                                        (k + 0.6) * self.pitch + jit[2], 1 + rng.randrange(1000000)))
        self.floor = 10.0   # the floor's side (m): nothing reaches its edge in the time simulated

    def scene(self, level):
        rolling = ", rolling_friction: 0.1" if level == "spheres_rolling" else ""
        # safety 0.25: at 0.5 the rigid column gained energy when its base compacted (a pebble
        # pressed by several at once vibrates faster than one contact, doc/scenes.md "time")
        lines = ["title: a column of %d pebbles collapsing, pebbles as %s" % (len(self.points), level.replace("_", " with ")),
                 "gravity: [0, 0, -9.81]",
                 "time: {end: %g, safety: 0.25, scheme: cd}" % self.END,
                 "materials:",
                 "  stone: {density: 2600, young: 5.0e9, poisson: 0.25, restitution: 0.3, friction: 0.5, contact_law: hertz%s}" % rolling,
                 "  base: {density: 2600}",
                 "contact: {penalty: 1.0e6, friction: 0.5, normal_damping: 1.0e5, tangential_viscosity: 1.0e6}",
                 "output: {every: %g, balance: 0.01}" % (self.END / 6),
                 "bodies:",
                 # the floor in cells of 0.4 x 0.4 x 0.2 m (the default for a rigid box, cubes of its
                 # smallest side, would make 10 / 0.2 x 10 / 0.2 x 6 = 15 000 skin tetrahedra)
                 "  - {name: floor, model: rigid, material: base, fixed: true, shape: {box: [%g, %g, 0.2]}, resolution: 0.4, position: [0, 0, -0.1]}" % (self.floor, self.floor)]
        for i, (x, y, z, seed) in enumerate(self.points):
            if level.startswith("spheres"):
                shape = "model: sphere, shape: {sphere: %g}" % (0.5 * self.SIZE)
            elif level == "rigid":
                shape = "model: rigid, shape: {pebble: {size: %g, seed: %d}}" % (self.SIZE, seed)
            else:
                shape = "model: deformable, shape: {pebble: {size: %g, seed: %d}}, resolution: %g" % (self.SIZE, seed, self.SIZE)
            lines.append("  - {name: p%d, %s, material: stone, position: [%.6g, %.6g, %.6g]}" % (i, shape, x, y, z))
        return "\n".join(lines) + "\n"

    def observe(self, d):
        pts = [(float(r["x"]), float(r["y"]), float(r["z"])) for r in read_csv(os.path.join(d, "bodies.csv")) if r["name"].startswith("p")]
        frag = os.path.join(d, "fragments.csv")
        if os.path.exists(frag):
            pts += [(float(r["x"]), float(r["y"]), float(r["z"])) for r in read_csv(frag) if r["body"].startswith("p")]
        if len(pts) != len(self.points):
            sys.exit("levels.py: %s has %d pebbles, expected %d" % (d, len(pts), len(self.points)))
        r = sorted(math.hypot(x, y) for x, y, _ in pts)
        runout = r[min(len(r) - 1, int(0.95 * len(r)))]
        h = max(z for x, y, z in pts if math.hypot(x, y) <= 2 * self.pitch)
        slope = h / runout
        return {"runout_m": runout, "slope_deg": math.degrees(math.atan(slope))}


sc = Slab() if which == "slab" else Column(int(arg("--count", "1000")))
levels = arg("--levels", ",".join(sc.levels)).split(",")
rows = []
for level in levels:
    d = os.path.join(out, level)
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, "scene.yaml")
    with open(path, "w") as f:
        f.write(sc.scene(level))
    log = os.path.join(d, "run.log")
    if "--reuse" in sys.argv and os.path.exists(log):
        print("reusing " + log, flush=True)
        stdout = open(log).read()
    else:
        cmd = ["mpiexec", "-n", np_, fdem, path, "-fdem_output", d, "-fdem_progress", "0"]
        print("$ " + " ".join(cmd), flush=True)
        r = subprocess.run(cmd, capture_output=True, text=True, env=env)
        if r.returncode != 0:
            print(r.stdout[-3000:] + r.stderr[-3000:])
            sys.exit("FAIL: %s level" % level)
        stdout = r.stdout
        with open(log, "w") as f:
            f.write(stdout)
    cpu = float(re.search(r"stepping CPU time ([0-9.e+-]+) s", stdout).group(1))
    steps = int(re.search(r"in (\d+) steps", stdout).group(1))
    row = {"level": level, "steps": steps, "cpu_s": cpu, "cost_per_sim_s": cpu / sc.END}
    row.update(sc.observe(d))
    rows.append(row)
    print("%s: %d steps, CPU %.3g s (%.3g CPU s per simulated s), %s" % (level, steps, cpu, cpu / sc.END,
          ", ".join("%s %.4g" % (lab, row[key]) for key, lab in sc.observables)), flush=True)

ref = rows[-1]
for r in rows:
    for key, _ in sc.observables:
        r[key + "_diff"] = abs(r[key] - ref[key]) / max(abs(ref[key]), 1e-300)
with open(os.path.join(out, sc.name + ".csv"), "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
    w.writeheader()
    w.writerows(rows)
for r in rows:
    print("%-16s cost %.3g CPU s/s, %s against the %s level" % (r["level"], r["cost_per_sim_s"],
          ", ".join("%s %+.1f%%" % (lab, 100 * (r[key] / max(abs(ref[key]), 1e-300) - 1)) for key, lab in sc.observables), ref["level"]))
try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    for (key, lab), mk in zip(sc.observables, "os"):
        ax.plot([r["cost_per_sim_s"] for r in rows], [100 * max(r[key + "_diff"], 1e-3) for r in rows], mk + "-", label=lab)
    first = sc.observables[0][0] + "_diff"
    for r in rows:
        ax.annotate(r["level"].replace("_", " + "), (r["cost_per_sim_s"], 100 * max(r[first], 1e-3)), textcoords="offset points", xytext=(5, 5))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("cost: CPU seconds per simulated second")
    ax.set_ylabel("difference from the %s level (%%)" % ref["level"])
    ax.set_title(sc.title)
    ax.grid(alpha=0.3, which="both")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, sc.name + ".svg"))
    print("wrote " + os.path.join(out, sc.name + ".svg"))
except ImportError:
    print("matplotlib not found: no chart (%s.csv has the data)" % sc.name)
