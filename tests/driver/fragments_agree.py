#!/usr/bin/env python3
"""Fragments of a fracturing run: runs a scene with the fdem driver on 1 and on 2
ranks and reads DIR/fragments.csv of each. Both must have at least MIN fragments,
whose masses sum to MASS (to 1e-12 relative), and the same fragments in the same
order: the same body, id (first_element) and element count, masses within 1e-12 relative, centres of mass within TOL (m)
and velocities within 1000 TOL (m/s). The driver's text must give the count.
DIR/fracture.csv, the joints in the order they broke, must be the same on 1 and 2
ranks: the same joints (each once) in the same order, at the same steps, their times
within 1e-12 relative and their centroids within TOL (m).

  fragments_agree.py MPIEXEC FDEM SCENE MIN MASS TOL [driver options...]
"""
import csv
import os
import subprocess
import sys
from scratch import scratch_dir

mpiexec, fdem, scene = sys.argv[1], sys.argv[2], sys.argv[3]
nmin, mass, tol = int(sys.argv[4]), float(sys.argv[5]), float(sys.argv[6])
more = sys.argv[7:]
root = scratch_dir("fdem_fragments_")
rows, breaks = {}, {}
for n in (1, 2):
    out = os.path.join(root, f"np{n}")
    cmd = [mpiexec, "--oversubscribe", "-n", str(n), fdem, scene, "-fdem_output", out, "-fdem_progress", "0"] + more
    print("$ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    print(r.stdout[-1500:] + r.stderr[-1500:])
    if r.returncode != 0:
        sys.exit(f"FAIL: exit status {r.returncode} on {n} rank(s)")
    with open(os.path.join(out, "fragments.csv")) as f:
        rows[n] = list(csv.DictReader(f))
    if f"fragments: {len(rows[n])} " not in r.stdout:
        sys.exit(f"FAIL: the driver's text does not give the {len(rows[n])} fragments of fragments.csv ({n} rank(s))")
    with open(os.path.join(out, "fracture.csv")) as f:
        breaks[n] = list(csv.DictReader(f))
    times = [float(x["time"]) for x in breaks[n]]
    if not breaks[n] or times != sorted(times) or len({x["joint"] for x in breaks[n]}) != len(breaks[n]):
        sys.exit(f"FAIL: fracture.csv ({n} rank(s)) is empty, not in time order or has a joint twice")
    total = sum(float(x["mass"]) for x in rows[n])
    print(f"{n} rank(s): {len(rows[n])} fragments, total mass {total!r}")
    if len(rows[n]) < nmin:
        sys.exit(f"FAIL: {len(rows[n])} fragments on {n} rank(s), expected at least {nmin}")
    if abs(total - mass) > 1e-12 * mass:
        sys.exit(f"FAIL: the fragments' masses sum to {total!r}, expected {mass!r} ({n} rank(s))")
a, b = rows[1], rows[2]
if len(a) != len(b):
    sys.exit(f"FAIL: {len(a)} fragments on 1 rank, {len(b)} on 2")
worst = [0.0, 0.0, 0.0]
for ra, rb in zip(a, b):
    if ra["body"] != rb["body"]:
        sys.exit(f"FAIL: fragment {ra['fragment']} is of body {ra['body']} on 1 rank, {rb['body']} on 2")
    if (ra["first_element"], ra["elements"]) != (rb["first_element"], rb["elements"]):
        sys.exit(f"FAIL: fragment {ra['fragment']} has id {ra['first_element']} and {ra['elements']} elements on 1 rank, "
                 f"{rb['first_element']} and {rb['elements']} on 2")
    worst[0] = max(worst[0], abs(float(ra["mass"]) - float(rb["mass"])) / mass)
    worst[1] = max(worst[1], max(abs(float(ra[k]) - float(rb[k])) for k in ("x", "y", "z")))
    worst[2] = max(worst[2], max(abs(float(ra[k]) - float(rb[k])) for k in ("vx", "vy", "vz")))
print(f"1 rank against 2: mass {worst[0]:.3e} relative, centre {worst[1]:.3e} m, velocity {worst[2]:.3e} m/s")
if worst[0] > 1e-12 or worst[1] > tol or worst[2] > 1000 * tol:
    sys.exit("FAIL: 1 and 2 ranks give different fragments")
a, b = breaks[1], breaks[2]
if [(x["joint"], x["step"], x["body"]) for x in a] != [(x["joint"], x["step"], x["body"]) for x in b]:
    sys.exit(f"FAIL: fracture.csv lists other joints or steps on 1 rank ({len(a)} rows) than on 2 ({len(b)})")
dt = max(abs(float(x["time"]) - float(y["time"])) / float(x["time"]) for x, y in zip(a, b))
dx = max(abs(float(x[k]) - float(y[k])) for x, y in zip(a, b) for k in ("x", "y", "z"))
print(f"fracture.csv: {len(a)} joints broken, in the same order on 1 and 2 ranks; time {dt:.3e} relative, centroid {dx:.3e} m")
if dt > 1e-12 or dx > tol:
    sys.exit("FAIL: 1 and 2 ranks give different joint breaks")
print("PASS")
