#!/usr/bin/env python3
"""1 and 2 ranks give the same rigid bodies: runs a scene with the fdem driver
on 1 and on 2 ranks and compares the final state of every rigid body
(DIR/bodies.csv): positions within TOL (m), velocities within 1000 TOL (m/s),
the same bodies in the same order.

  ranks_agree.py MPIEXEC FDEM SCENE TOL [driver options...]
"""
import csv
import math
import os
import subprocess
import sys
import tempfile

mpiexec, fdem, scene, tol = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])
more = sys.argv[5:]
root = tempfile.mkdtemp(prefix="fdem_ranks_")
rows = {}
for n in (1, 2):
    out = os.path.join(root, f"np{n}")
    cmd = [mpiexec, "--oversubscribe", "-n", str(n), fdem, scene, "-fdem_output", out, "-fdem_progress", "0"] + more
    print("$ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    print(r.stdout[-1500:] + r.stderr[-1500:])
    if r.returncode != 0:
        sys.exit(f"FAIL: exit status {r.returncode} on {n} rank(s)")
    with open(os.path.join(out, "bodies.csv")) as f:
        rows[n] = list(csv.reader(f))
a, b = rows[1], rows[2]
fail = []
if a[0] != b[0] or a[0][:5] != ["id", "name", "x", "y", "z"]:
    fail.append(f"bodies.csv headers: {a[0]} / {b[0]}")
if [r[:2] for r in a[1:]] != [r[:2] for r in b[1:]] or len(a) < 3:
    fail.append("the bodies (ids and names) differ between 1 and 2 ranks, or there are fewer than 2")
dx = max(math.dist([float(x) for x in u[2:5]], [float(x) for x in v[2:5]]) for u, v in zip(a[1:], b[1:]))
dv = max(math.dist([float(x) for x in u[5:8]], [float(x) for x in v[5:8]]) for u, v in zip(a[1:], b[1:]))
moved = max(math.hypot(*[float(x) for x in u[5:8]]) for u in a[1:])
print(f"{len(a) - 1} bodies: 1 vs 2 ranks, max |dx| {dx:.3g} m (bound {tol:g}), max |dv| {dv:.3g} m/s (bound {tol * 1e3:g}); largest speed {moved:.3g} m/s")
if not dx <= tol:
    fail.append(f"positions differ by {dx:.3g} m > {tol:g}")
if not dv <= tol * 1e3:
    fail.append(f"velocities differ by {dv:.3g} m/s > {tol * 1e3:g}")
if not moved > 0.01:
    fail.append("nothing moves: the scene tests nothing")
for f in fail:
    print("FAIL " + f)
sys.exit(1 if fail else 0)
