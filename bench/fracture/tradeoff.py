#!/usr/bin/python3
"""The joint penalty's trade-off (doc/fracture.md, "Artificial compliance"): a stiffer
penalty keeps more of the body's modulus but shortens the stable time step.

Runs test_fracture_bar (a free-free bar ringing in its first axial mode, whole and split
into joints at p = E, 10 E, 100 E; the largest stable step of cd found by bisection),
reads its figures and writes doc/bench/fracture_tradeoff.csv and .svg: the modulus kept,
E_eff / E_whole, against the stable step relative to the whole bar's.

usage: bench/fracture/tradeoff.py [BUILD_DIR=build]   (Debian python3 with python3-matplotlib)"""
import os, re, subprocess, sys

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.dirname(os.path.dirname(here))
build = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "build")
exe = os.path.join(build, "tests", "deformable", "test_fracture_bar")
out = subprocess.run([exe], capture_output=True, text=True, check=True).stdout
num = r"([0-9.eE+-]+)"
whole_dt = float(re.search(r"whole bar: measured stable step " + num, out).group(1))
m = re.search(r"E_eff/E_whole = " + num + r" at p = 10 E, " + num + r" at p = 100 E", out)
keep = {10.0: float(m.group(1)), 100.0: float(m.group(2))}
keep[1.0] = float(re.search(r"split bar at p = E: E_eff/E_whole = " + num, out).group(1))
step, est = {}, {}
for p, e, meas in re.findall(r"p = " + num + r" E: omega_j = [0-9.eE+-]+ /s, estimated stable step 2/omega_j = " + num + r" s, measured " + num, out):
    step[float(p)], est[float(p)] = float(meas), float(e)
rows = [(p, keep[p], step[p], step[p] / whole_dt, est[p]) for p in sorted(keep)]
csv = os.path.join(root, "doc", "bench", "fracture_tradeoff.csv")
with open(csv, "w") as f:
    f.write("p_over_E,E_eff_over_E_whole,stable_dt_s,stable_dt_over_whole,estimate_2_over_omega_j_s\n")
    f.write(f"whole,1,{whole_dt:.4g},1,\n")
    for r in rows:
        f.write("%g,%.4f,%.4g,%.4f,%.4g\n" % r)
print(open(csv).read())

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
fig, ax = plt.subplots(figsize=(6, 4.2))
ax.plot([r[3] for r in rows], [r[1] for r in rows], "o-", label="split bar (joints on every face)")
for r in rows:
    ax.annotate(f"p = {r[0]:g} E", (r[3], r[1]), textcoords="offset points", xytext=(8, -4))
ax.plot([1], [1], "s", color="k", label="whole bar (no joints)")
ax.set_xscale("log")
ax.set_xlabel("largest stable step of cd / the whole bar's")
ax.set_ylabel("modulus kept, E_eff / E_whole")
ax.set_ylim(0, 1.08)
ax.grid(alpha=.3, which="both")
ax.legend(loc="lower left", fontsize=8)
ax.set_title("Joint penalty: stiffness kept against time step", fontsize=10)
fig.tight_layout()
svg = os.path.join(root, "doc", "bench", "fracture_tradeoff.svg")
fig.savefig(svg)
print("wrote " + csv + " and " + svg)
