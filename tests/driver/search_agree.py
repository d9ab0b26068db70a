#!/usr/bin/env python3
"""The contact search's re-search rule loses no contact: runs a scene as it is (a search only
when some body moved more than its margin, from the bound of its move) and again with
`-fdem_contact_buffer 0 -fdem_contact_keep_search 0` (a search at every evaluation, and every
listing that fracture causes made whole), and compares the final state of every
body (DIR/bodies.csv): positions within TOL (m), velocities within 1000 TOL (m/s). A bound that
undercounts a body's move finds a contact late and parts the runs far beyond round-off. At least
MOVING bodies must move faster than 1 cm/s at the end (the collisions happened), and the first
run must have searched less often than it evaluated (else it tests nothing). Where the scene
fractures, both runs must break the same joints in the same steps (DIR/fracture.csv) and give the
same fragments (DIR/fragments.csv: ids and element counts, centres within TOL, velocities within
1000 TOL), and with
--kept the first run must have kept its search at some listing where joints broke or softened
(Engine::KeepSearch) and made some of those listings in place (Engine::RefreshListing: only the
changed records written), some of these asking again only the candidates of the records that
changed (the others' answers kept), so that the kept candidates, the records written in place and
the pairs kept from the listing before are what is compared; the second run keeps none.

  search_agree.py FDEM SCENE TOL MOVING [--kept] [--ranks MPIEXEC N] [driver options...]
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
want_kept, launch = False, []
while more and more[0] in ("--kept", "--ranks"):
    if more[0] == "--kept":
        want_kept, more = True, more[1:]
    else:
        launch, more = [more[1], "-n", more[2]], more[3:]
root = scratch_dir("fdem_search_")
rows, searches, breaks, kept, in_place, few, pieces = {}, {}, {}, {}, {}, {}, {}
for name, opts in (("margins", []), ("every evaluation", ["-fdem_contact_buffer", "0", "-fdem_contact_keep_search", "0"])):
    out = os.path.join(root, name.replace(" ", "_"))
    cmd = launch + [fdem, scene, "-fdem_output", out, "-fdem_progress", "0"] + opts + more
    print("$ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    print(r.stdout[-1200:] + r.stderr[-1200:])
    if r.returncode != 0:
        sys.exit(f"FAIL: exit status {r.returncode} ({name})")
    m = re.search(r"contact \([a-z-]+\): (\d+) searches in (\d+) evaluations", r.stdout)
    if not m:
        sys.exit(f"FAIL: no contact statistics line ({name})")
    searches[name] = (int(m.group(1)), int(m.group(2)))
    lines = re.findall(r"contact \([a-z-]+\): (\d+) listings where joints broke.*, (\d+) of them made in place, (\d+) of these asking again only", r.stdout)
    kept[name] = sum(int(k) for k, _, _ in lines)
    in_place[name] = sum(int(m) for _, m, _ in lines)
    few[name] = sum(int(q) for _, _, q in lines)
    with open(os.path.join(out, "bodies.csv")) as f:
        rows[name] = list(csv.reader(f))
    if os.path.exists(os.path.join(out, "fracture.csv")):
        with open(os.path.join(out, "fracture.csv")) as f:
            breaks[name] = [(u["step"], u["joint"]) for u in csv.DictReader(f)]
    if os.path.exists(os.path.join(out, "fragments.csv")):
        with open(os.path.join(out, "fragments.csv")) as f:
            pieces[name] = list(csv.DictReader(f))
fail = []
s, e = searches["margins"]
if not s < e:
    fail.append(f"the first run searched at every evaluation ({s} in {e}): it tests nothing")
if searches["every evaluation"][0] < searches["every evaluation"][1]:  # (more where fracture lists again)
    fail.append(f"-fdem_contact_buffer 0 did not search at every evaluation: {searches['every evaluation']}")
fast = sum(1 for u in rows["margins"][1:] if math.hypot(*[float(x) for x in u[5:8]]) > 0.01)
print(f"searches: {s} in {e} evaluations; {fast} bodies moving faster than 1 cm/s at the end")
if fast < moving:
    fail.append(f"only {fast} bodies move faster than 1 cm/s at the end (want {moving}): too few collisions")
if len(rows["margins"]) > 2 or not pieces:  # (a scene of one rigid body and deformable ones: their fragments below)
    fail += compare(rows["margins"], rows["every evaluation"], tol, "searches by the margins vs at every evaluation")
if breaks:
    b, c = breaks.get("margins", []), breaks.get("every evaluation", [])
    print(f"joint breaks: {len(b)} and {len(c)}")
    if b != c:
        fail.append(f"the runs broke different joints or in different steps ({len(b)} and {len(c)} breaks)")
if pieces:
    a, b = pieces.get("margins", []), pieces.get("every evaluation", [])
    if [(u["first_element"], u["elements"]) for u in a] != [(u["first_element"], u["elements"]) for u in b]:
        fail.append(f"the runs give different fragments ({len(a)} and {len(b)})")
    else:
        dx = max((abs(float(u[k]) - float(w[k])) for u, w in zip(a, b) for k in ("x", "y", "z")), default=0.0)
        dv = max((abs(float(u[k]) - float(w[k])) for u, w in zip(a, b) for k in ("vx", "vy", "vz")), default=0.0)
        print(f"fragments: {len(a)}; centres {dx:.3e} m and velocities {dv:.3e} m/s apart")
        if dx > tol or dv > 1000 * tol:
            fail.append(f"the fragments part: centres {dx:.3e} m, velocities {dv:.3e} m/s")
if want_kept:
    print(f"listings that kept the search: {kept['margins']}, {in_place['margins']} of them made in place, {few['margins']} of these asking again only the candidates of the records that changed")
    if kept["margins"] == 0:
        fail.append("no listing kept the search: the kept candidates are not tested")
    if in_place["margins"] == 0:
        fail.append("no listing was made in place: the records written in place are not tested")
    if few["margins"] == 0:
        fail.append("no listing in place asked again only the candidates of the records that changed: that way is not tested")
    if kept["every evaluation"] != 0:
        fail.append(f"-fdem_contact_keep_search 0 kept the search at {kept['every evaluation']} listings")
for f in fail:
    print("FAIL " + f)
sys.exit(1 if fail else 0)
