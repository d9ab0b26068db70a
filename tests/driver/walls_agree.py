#!/usr/bin/env python3
"""A flat wall meshed finely or as one cell gives the same grains: runs a scene whose fixed
rigid boxes have no resolution (so the driver meshes each as one cell, doc/spheres.md "Walls
for grains") and the same scene with `resolution: RES` on every fixed box (cubes of RES), and
compares the final state of every body (DIR/bodies.csv): positions within TOL (m), velocities
within 1000 TOL (m/s). The spheres' contacts with a flat face must not depend on how its
triangles cut it: one contact per face, and one spring carried from triangle to triangle.

  walls_agree.py FDEM SCENE RES TOL [driver options...]
"""
import csv
import os
import re
import subprocess
import sys

from bodies_agree import compare
from scratch import scratch_dir

fdem, scene, res, tol = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])
more = sys.argv[5:]
root = scratch_dir("fdem_walls_")
text = open(scene).read()
fine, n = re.subn(r"(fixed: true,[^}\n]*?)(shape: \{box:)", r"\1resolution: " + res + r", \2", text)
if n == 0 or "resolution:" in text:
    sys.exit("FAIL: the scene has no fixed box, or already gives a resolution")
fine_scene = os.path.join(root, "fine.yaml")
open(fine_scene, "w").write(fine)
rows, logs = {}, {}
for name, path in (("one cell", scene), ("cubes", fine_scene)):
    out = os.path.join(root, name.replace(" ", "_"))
    cmd = [fdem, path, "-fdem_output", out, "-fdem_progress", "0"] + more
    print("$ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    print(r.stdout[-1200:] + r.stderr[-1200:])
    if r.returncode != 0:
        sys.exit(f"FAIL: exit status {r.returncode} ({name})")
    logs[name] = r.stdout
    with open(os.path.join(out, "bodies.csv")) as f:
        rows[name] = list(csv.reader(f))
fail = []
if "walls:" not in logs["one cell"] or "walls:" in logs["cubes"]:
    fail.append("the driver did not say (only) for the first run that it meshed the walls as one cell")
fail += compare(rows["one cell"], rows["cubes"], tol, f"walls of one cell vs cubes of {res} m")
for f in fail:
    print("FAIL " + f)
sys.exit(1 if fail else 0)
