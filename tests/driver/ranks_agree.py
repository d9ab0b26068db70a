#!/usr/bin/env python3
"""1 and 2 ranks give the same rigid bodies: runs a scene with the fdem driver
on 1 and on 2 ranks and compares the final state of every rigid body
(DIR/bodies.csv): positions within TOL (m), velocities within 1000 TOL (m/s),
the same bodies in the same order.

  ranks_agree.py MPIEXEC FDEM SCENE TOL [driver options...]
"""
import csv
import os
import subprocess
import sys

from bodies_agree import compare
from scratch import scratch_dir

mpiexec, fdem, scene, tol = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])
more = sys.argv[5:]
root = scratch_dir("fdem_ranks_")
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
fail = compare(rows[1], rows[2], tol, "1 vs 2 ranks")
for f in fail:
    print("FAIL " + f)
sys.exit(1 if fail else 0)
