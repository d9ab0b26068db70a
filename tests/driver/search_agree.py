#!/usr/bin/env python3
"""The contact search's re-search rule loses no contact: runs a scene as it is (a search only
when some body moved more than its margin, from the bound of its move) and again with
`-fdem_contact_buffer 0` (a search at every evaluation), and compares the final state of every
body (DIR/bodies.csv): positions within TOL (m), velocities within 1000 TOL (m/s). A bound that
undercounts a body's move finds a contact late and parts the runs far beyond round-off. At least
MOVING bodies must move faster than 1 cm/s at the end (the collisions happened), and the first
run must have searched less often than it evaluated (else it tests nothing).

  search_agree.py FDEM SCENE TOL MOVING [driver options...]
"""
import csv
import math
import os
import re
import subprocess
import sys

from bodies_agree import compare
from scratch import scratch_dir

fdem, scene, tol, moving = sys.argv[1], sys.argv[2], float(sys.argv[3]), int(sys.argv[4])
more = sys.argv[5:]
root = scratch_dir("fdem_search_")
rows, searches = {}, {}
for name, opts in (("margins", []), ("every evaluation", ["-fdem_contact_buffer", "0"])):
    out = os.path.join(root, name.replace(" ", "_"))
    cmd = [fdem, scene, "-fdem_output", out, "-fdem_progress", "0"] + opts + more
    print("$ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    print(r.stdout[-1200:] + r.stderr[-1200:])
    if r.returncode != 0:
        sys.exit(f"FAIL: exit status {r.returncode} ({name})")
    m = re.search(r"contact \([a-z-]+\): (\d+) searches in (\d+) evaluations", r.stdout)
    if not m:
        sys.exit(f"FAIL: no contact statistics line ({name})")
    searches[name] = (int(m.group(1)), int(m.group(2)))
    with open(os.path.join(out, "bodies.csv")) as f:
        rows[name] = list(csv.reader(f))
fail = []
s, e = searches["margins"]
if not s < e:
    fail.append(f"the first run searched at every evaluation ({s} in {e}): it tests nothing")
if searches["every evaluation"][0] != searches["every evaluation"][1]:
    fail.append(f"-fdem_contact_buffer 0 did not search at every evaluation: {searches['every evaluation']}")
fast = sum(1 for u in rows["margins"][1:] if math.hypot(*[float(x) for x in u[5:8]]) > 0.01)
print(f"searches: {s} in {e} evaluations; {fast} bodies moving faster than 1 cm/s at the end")
if fast < moving:
    fail.append(f"only {fast} bodies move faster than 1 cm/s at the end (want {moving}): too few collisions")
fail += compare(rows["margins"], rows["every evaluation"], tol, "searches by the margins vs at every evaluation")
for f in fail:
    print("FAIL " + f)
sys.exit(1 if fail else 0)
