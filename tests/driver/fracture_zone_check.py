#!/usr/bin/env python3
"""A bar fracturable only in a fracture zone: runs SCENE (with fracture_zone:) with the fdem
driver on 1 and on 2 ranks, and checks on each: the driver reports fewer joints than for
WHOLE, the same bar fracturable everywhere (read from `fdem check WHOLE`); the bar breaks
(at least MIN fragments in fragments.csv, their masses summing to MASS to 1e-12 relative);
every joint in fracture.csv broke inside the zone [LO, HI] (x,y,z each), the joints' centroids
there within TOL (m: they are where the bar is at the break, stretched a little). 1 and 2
ranks must give the same joint count, fragments (body, id, elements) and broken joints in the
same order.

  fracture_zone_check.py MPIEXEC FDEM SCENE WHOLE MIN MASS LO HI TOL
"""
import csv
import os
import re
import subprocess
import sys
from scratch import scratch_dir

mpiexec, fdem, scene, whole = sys.argv[1:5]
nmin, mass = int(sys.argv[5]), float(sys.argv[6])
lo, hi = [float(v) for v in sys.argv[7].split(",")], [float(v) for v in sys.argv[8].split(",")]
tol = float(sys.argv[9])
root = scratch_dir("fdem_fracture_zone_")


def joints(text, what):
    m = re.search(r"^fracture: (\d+) joints", text, re.M)
    if not m:
        sys.exit(f"FAIL: {what}: the driver does not report its joints ('fracture: N joints')")
    return int(m.group(1))


cmd = [mpiexec, "--oversubscribe", "-n", "1", fdem, "check", whole, "-fdem_progress", "0"]
print("$ " + " ".join(cmd), flush=True)
r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
if r.returncode != 0:
    sys.exit(f"FAIL: fdem check {whole}: exit status {r.returncode}\n{r.stdout[-1500:]}{r.stderr[-1500:]}")
n_whole = joints(r.stdout, whole)
# the model advisor counts the split: everywhere for WHOLE, the zone's share of the tetrahedra
# for SCENE (checked against the share of the bar's length the zone covers)
if "split everywhere" not in r.stdout:
    sys.exit(f"FAIL: fdem check {whole}: the advisor does not say the body is split everywhere")
cmd = [mpiexec, "--oversubscribe", "-n", "1", fdem, "check", scene, "-fdem_progress", "0"]
print("$ " + " ".join(cmd), flush=True)
rz = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
m = re.search(r"in its fracture_zone: (\d+)% of its tetrahedra split", rz.stdout)
share = round(100 * (hi[2] - lo[2]) / 0.1)  # the bar is 0.1 m long along z, the zone across it
print(f"advisor: {m.group(0) if m else 'no share of the tetrahedra split'} (the zone covers {share}% of the bar)")
if rz.returncode != 0 or not m or int(m.group(1)) != share:
    sys.exit(f"FAIL: fdem check {scene}: the advisor should give the share of tetrahedra split, {share}%")
runs = {}
for n in (1, 2):
    out = os.path.join(root, f"np{n}")
    cmd = [mpiexec, "--oversubscribe", "-n", str(n), fdem, scene, "-fdem_output", out, "-fdem_progress", "0"]
    print("$ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    print(r.stdout[-2000:] + r.stderr[-1500:])
    if r.returncode != 0:
        sys.exit(f"FAIL: exit status {r.returncode} on {n} rank(s)")
    nj = joints(r.stdout, scene)
    print(f"{n} rank(s): {nj} joints with the zone, {n_whole} in the whole bar")
    if not nj < n_whole:
        sys.exit(f"FAIL: {nj} joints with the fracture zone, not fewer than the whole bar's {n_whole}")
    if "only those in its fracture_zone" not in r.stdout:
        sys.exit("FAIL: the driver's joint count does not mention the fracture zone")
    with open(os.path.join(out, "fragments.csv")) as f:
        frags = list(csv.DictReader(f))
    if f"fragments: {len(frags)} " not in r.stdout:
        sys.exit(f"FAIL: the driver's text does not give the {len(frags)} fragments of fragments.csv")
    total = sum(float(x["mass"]) for x in frags)
    print(f"{n} rank(s): {len(frags)} fragments, total mass {total!r}")
    if len(frags) < nmin:
        sys.exit(f"FAIL: {len(frags)} fragments, expected at least {nmin}: the bar did not break")
    if abs(total - mass) > 1e-12 * mass:
        sys.exit(f"FAIL: the fragments' masses sum to {total!r}, expected {mass!r}")
    with open(os.path.join(out, "fracture.csv")) as f:
        breaks = list(csv.DictReader(f))
    if not breaks:
        sys.exit("FAIL: fracture.csv lists no broken joint")
    worst = 0.0
    for b in breaks:
        for k, c in enumerate("xyz"):
            x = float(b[c])
            worst = max(worst, lo[k] - x, x - hi[k])
    print(f"{n} rank(s): {len(breaks)} joints broken, z from {min(float(b['z']) for b in breaks):.6g} to "
          f"{max(float(b['z']) for b in breaks):.6g} m; furthest outside the zone by {worst:.3g} m")
    if worst > tol:
        sys.exit(f"FAIL: a joint broke outside the fracture zone, {worst:.3g} m beyond it (tolerance {tol} m)")
    runs[n] = (nj, [(x["body"], x["first_element"], x["elements"]) for x in frags], [(x["joint"], x["step"], x["body"]) for x in breaks])
if runs[1] != runs[2]:
    sys.exit("FAIL: 1 and 2 ranks give other joint counts, fragments or broken joints")
print("PASS")
