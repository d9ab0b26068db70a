#!/usr/bin/env python3
"""The loads on moved rigid bodies (loads.csv): runs the platen scene and checks that
the platen's load at the first row is its weight (nothing touches it yet), to 1e-9,
and that the work of the reaction, the integral of -F . v over the rows (trapezoid),
equals balance.csv's external_work at the end within 3% (the rows sample the force
every 0.2 ms; the work meter integrates it at every evaluation).

  loads_check.py MPIEXEC NP FDEM SCENE
"""
import csv
import os
import subprocess
import sys
from scratch import scratch_dir

mpiexec, np, fdem, scene = sys.argv[1:5]
out = scratch_dir("fdem_loads_")
cmd = [mpiexec, "--oversubscribe", "-n", np, fdem, scene, "-fdem_output", out, "-fdem_progress", "0"]
print("$ " + " ".join(cmd), flush=True)
r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
print(r.stdout[-2000:] + r.stderr[-2000:])
if r.returncode != 0:
    sys.exit("FAIL: exit status %d" % r.returncode)
loads = list(csv.DictReader(open(os.path.join(out, "loads.csv"))))
bal = list(csv.DictReader(open(os.path.join(out, "balance.csv"))))
v = -0.1                                 # the platen's move.velocity (z)
weight = -1000 * 0.2 * 0.2 * 0.02 * 9.81  # density 1000 (no material), box 0.2 x 0.2 x 0.02
f0 = float(loads[0]["platen_Fz"])
t = [0.0] + [float(x["time"]) for x in loads]
F = [f0] + [float(x["platen_Fz"]) for x in loads]
W = sum(0.5 * (-F[i] - F[i - 1]) * v * (t[i] - t[i - 1]) for i in range(1, len(t)))
We = float(bal[-1]["external_work"])
print("first load %.12g N (weight %.12g N); work of the reaction from loads.csv %.6g J, external_work %.6g J" % (f0, weight, W, We))
fails = []
if abs(f0 - weight) > 1e-9 * abs(weight):
    fails.append("the first load is not the platen's weight")
if abs(W - We) > 0.03 * abs(We):
    fails.append("the loads' work differs from external_work by more than 3%")
if abs(float(loads[-1]["time"]) - float(bal[-1]["time"])) > 1e-12:
    fails.append("loads.csv and balance.csv end at different times")
if fails:
    sys.exit("FAIL: " + "; ".join(fails))
print("ok")
