#!/usr/bin/env python3
"""The balance rows' interval does not change the answer while no migration is due: runs a scene
with the fdem driver on N ranks as it is and with its balance interval (output.balance) replaced
by the end time, and requires the final rigid bodies (DIR/bodies.csv) identical to the bit, with
something moving faster than 1 cm/s. A run ends its TS at a balance row only where a rigid body has
moved farther than its radius since the last migration (doc/scenes.md); before, it ended it at
every row, and a new TS's fresh force evaluation with damping or friction moved the answer.

  balance_interval.py MPIEXEC N FDEM SCENE [driver options...]
"""
import math
import os
import re
import subprocess
import sys

from scratch import scratch_dir

mpiexec, n, fdem, scene = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4]
more = sys.argv[5:]
root = scratch_dir("fdem_interval_")
text = open(scene).read()
end = re.search(r"end:\s*([0-9.eE+-]+)", text).group(1)
once = re.sub(r"balance:\s*[0-9.eE+-]+", f"balance: {end}", text)
assert once != text, "the scene has no output.balance"
variants = {"rows as in the scene": scene, "one row at the end": os.path.join(root, "once.yaml")}
open(variants["one row at the end"], "w").write(once)
bodies, rows = {}, {}
for k, (name, path) in enumerate(variants.items()):
    out = os.path.join(root, f"run{k}")
    cmd = [mpiexec, "--oversubscribe", "-n", n, fdem, path, "-fdem_output", out, "-fdem_progress", "0"] + more
    print("$ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    print(r.stdout[-1200:] + r.stderr[-1200:])
    if r.returncode != 0:
        sys.exit(f"FAIL: exit status {r.returncode} ({name})")
    bodies[name] = open(os.path.join(out, "bodies.csv")).read()
    rows[name] = sum(1 for _ in open(os.path.join(out, "balance.csv"))) - 1
fail = []
a, b = bodies.values()
speed = max(math.hypot(*map(float, line.split(",")[5:8])) for line in a.splitlines()[1:])
print(f"balance rows: {rows}; largest speed at the end {speed:.3g} m/s; bodies.csv identical: {a == b}")
if a != b:
    fail.append("the final bodies differ between the two balance intervals")
if not speed > 0.01:
    fail.append("nothing moves: the scene tests nothing")
if not rows["rows as in the scene"] > 10 * rows["one row at the end"]:
    fail.append(f"the scene's interval gave too few rows to test: {rows}")
for f in fail:
    print("FAIL " + f)
sys.exit(1 if fail else 0)
