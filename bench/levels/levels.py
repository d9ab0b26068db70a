#!/usr/bin/env python3
"""Cost against fidelity: one scene at three levels of model (doc/advisor.md).

Eight stones strike a deformable slab (fixed at its base) at 1.5 m/s, under
gravity.
The stones are modelled as spheres (the sphere of each stone's volume, Hertz
contact), as rigid polyhedra (potential contact) or as deformable meshes; the
slab is deformable at every level. For each level the script runs the fdem
driver, reads balance.csv and the driver's CPU time, and reports

  cost      CPU seconds per simulated second (the driver's "stepping CPU time")
  strain    the largest strain energy of the scene (the impacts; J)
  rebound   the largest kinetic energy after that peak (the stones' rebound; J)

and their differences from the deformable level (the reference), as a table
(levels.csv) and a chart (levels.svg) of cost against difference.

  levels.py FDEM [OUT_DIR] [--np N]
"""
import csv
import os
import re
import subprocess
import sys

fdem = sys.argv[1]
out = sys.argv[2] if len(sys.argv) > 2 and not sys.argv[2].startswith("--") else "out_levels"
np_ = sys.argv[sys.argv.index("--np") + 1] if "--np" in sys.argv else "1"
os.makedirs(out, exist_ok=True)
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")

SIZE, END, V0 = 0.04, 0.06, 1.5
STONES = [(-0.1, -0.1, 0.035, 1), (0.0, -0.1, 0.04, 2), (0.1, -0.1, 0.045, 3), (-0.1, 0.0, 0.04, 4),
          (0.1, 0.0, 0.035, 5), (-0.1, 0.1, 0.045, 6), (0.0, 0.1, 0.04, 7), (0.1, 0.1, 0.035, 8)]


def scene(level):
    lines = ["title: stones on a slab, stones as %s" % level,
             "gravity: [0, 0, -9.81]",
             "time: {end: %g, scheme: cd}" % END,
             "materials:",
             "  rubber: {density: 1100, young: 2.0e6, poisson: 0.3, model: neo_hookean, damping: 20}",
             "  stone: {density: 2600, young: 5.0e7, poisson: 0.25, restitution: 0.6, friction: 0.3, contact_law: hertz}",
             "contact: {penalty: 5.0e6, friction: 0.3, normal_damping: 200}",
             "output: {every: %g, balance: 5.0e-4}" % END,
             "bodies:",
             "  - {name: slab, model: deformable, material: rubber, shape: {box: [0.4, 0.4, 0.05]}, resolution: 0.025,"
             " position: [0, 0, -0.025], fix: {below: [z, -0.049]}}"]
    for i, (x, y, z, seed) in enumerate(STONES):
        if level == "spheres":
            # the sphere of the stone's volume (a pebble of size s has about the volume of a sphere of radius 0.5 s)
            lines.append("  - {name: s%d, model: sphere, material: stone, shape: {sphere: %g}, position: [%g, %g, %g], velocity: [0, 0, %g]}" % (i, 0.5 * SIZE, x, y, z, -V0))
        else:
            model = "rigid" if level == "rigid" else "deformable"
            res = "" if level == "rigid" else ", resolution: %g" % (0.5 * SIZE)
            lines.append("  - {name: s%d, model: %s, material: stone, shape: {pebble: {size: %g, seed: %d}}%s, position: [%g, %g, %g], velocity: [0, 0, %g]}" % (i, model, SIZE, seed, res, x, y, z, -V0))
    return "\n".join(lines) + "\n"


rows = []
for level in ["spheres", "rigid", "deformable"]:
    d = os.path.join(out, level)
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, "scene.yaml")
    open(path, "w").write(scene(level))
    cmd = ["mpiexec", "-n", np_, fdem, path, "-fdem_output", d, "-fdem_progress", "0"]
    print("$ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        print(r.stdout[-3000:] + r.stderr[-3000:])
        sys.exit("FAIL: %s level" % level)
    m = re.search(r"stepping CPU time ([0-9.e+-]+) s", r.stdout)
    steps = re.search(r"in (\d+) steps", r.stdout)
    cpu = float(m.group(1))
    bal = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(open(os.path.join(d, "balance.csv")))]
    strain = max(b["strain"] for b in bal)
    t_peak = max(bal, key=lambda b: b["strain"])["time"]
    rebound = max((b["kinetic"] for b in bal if b["time"] > t_peak), default=0.0)
    rows.append({"level": level, "steps": int(steps.group(1)), "cpu_s": cpu, "cost_per_sim_s": cpu / END,
                 "max_strain_J": strain, "rebound_J": rebound})
    print("%s: %d steps, CPU %.3g s (%.3g CPU s per simulated s), max strain energy %.4g J, rebound kinetic energy %.4g J" %
          (level, rows[-1]["steps"], cpu, cpu / END, strain, rebound), flush=True)

ref = rows[-1]
for r in rows:
    r["strain_diff"] = abs(r["max_strain_J"] - ref["max_strain_J"]) / ref["max_strain_J"]
    r["rebound_diff"] = abs(r["rebound_J"] - ref["rebound_J"]) / max(ref["rebound_J"], 1e-300)
with open(os.path.join(out, "levels.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
    w.writeheader()
    w.writerows(rows)
for r in rows:
    print("%-10s cost %.3g CPU s/s, strain energy %+.1f%%, rebound %+.1f%% against the deformable level" %
          (r["level"], r["cost_per_sim_s"], 100 * (r["max_strain_J"] / ref["max_strain_J"] - 1), 100 * (r["rebound_J"] / max(ref["rebound_J"], 1e-300) - 1)))
try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    for key, mk, lab in [("strain_diff", "o", "peak strain energy"), ("rebound_diff", "s", "rebound kinetic energy")]:
        ax.plot([r["cost_per_sim_s"] for r in rows], [100 * max(r[key], 1e-3) for r in rows], mk + "-", label=lab)
    for r in rows:
        ax.annotate(r["level"], (r["cost_per_sim_s"], 100 * max(r["strain_diff"], 1e-3)), textcoords="offset points", xytext=(5, 5))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("cost: CPU seconds per simulated second")
    ax.set_ylabel("difference from the deformable stones (%)")
    ax.set_title("eight stones on a deformable slab, stones at three levels")
    ax.grid(alpha=0.3, which="both")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "levels.svg"))
    print("wrote " + os.path.join(out, "levels.svg"))
except ImportError:
    print("matplotlib not found: no chart (levels.csv has the data)")
