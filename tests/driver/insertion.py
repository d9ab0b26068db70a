#!/usr/bin/env python3
"""Joints inserted during a run (tests/driver/fracture_insertion.yaml, doc/fracture.md).
usage: insertion.py MPIEXEC NP FDEM SCENE PRESPLIT_SCENE
  1. the straight run A on NP ranks inserts joints several times (its summary says how often)
     and breaks the bar; against the same bar split from the start (PRESPLIT_SCENE, run S):
     the peak of the pull (from balance.csv's external work) within 2%, the energy the
     fracture dissipated at the end within 2%, and the balance closed as well (largest
     |dissipated| below 2e-3 of the largest energy);
  2. A's first checkpoint (2.5 ms, between two insertions; the scene keeps them all), restarted
     to the end on NP ranks (B): the same insertions after 2.5 ms as A, the same joints broken
     in the same steps, and the last row of balance.csv equal to A's bitwise (B keeps no room
     in the heap for its rebuilds, -fdem_insert_heap 0, where A has the default: the memory
     the rebuilds land on changes no answer); the scene without insert_at restarted from it
     stops with an error that says why;
  3. the same restart on the other rank count (C): the same insertions, the same joints broken
     (in steps within 2 of A's: the bar is symmetric, and round-off decides between mirror
     joints), the last row within 1e-3 of the largest value.
  A, B and C search without look-ahead (-fdem_insert_ahead 0), so that the bar, whose stress
  is nearly uniform, is split in several insertions with a checkpoint between two of them;
  4. the straight run D with the default look-ahead (the cells near the ratio linked to one
     at it join its insertion) inserts fewer times than A, with the peak pull and
     the energy dissipated by the fracture within 2% of the bar split from the start."""
import csv, os, re, subprocess, sys
from scratch import scratch_dir

mpiexec, np, fdem, scene, presplit = sys.argv[1:6]
other = "2" if np == "1" else "1"
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
root = scratch_dir("fdem_insertion_")
fail = []

def run(n, out, more, sc=scene, expect_ok=True):
    cmd = [mpiexec, "--oversubscribe", "-n", n, fdem, sc, "-fdem_output", os.path.join(root, out), "-fdem_progress", "1"] + more
    print("$ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600, env=env)
    print(r.stdout[-2500:] + r.stderr[-2000:])
    if expect_ok and r.returncode != 0:
        sys.exit(f"FAIL: exit status {r.returncode}")
    return r.stdout if expect_ok else (r.returncode, r.stdout + r.stderr)

def check(name, ok, detail=""):
    print(("ok   " if ok else "FAIL ") + name + (": " + detail if detail else ""))
    if not ok: fail.append(name)

def rows(out):
    with open(os.path.join(root, out, "balance.csv")) as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]

def breaks(out): # (step, joint) of every break
    with open(os.path.join(root, out, "fracture.csv")) as f:
        return [(int(r["step"]), int(r["joint"])) for r in csv.DictReader(f)]

def insertions(text): # (time, tetrahedra) of every insertion the run reports
    return [(float(t), int(n)) for t, n in re.findall(r"t = ([0-9.e+-]+) s: joints inserted at ([0-9]+) tetrahedra", text)]

def peak_pull(out): # the largest power of the moved nodes over their speed (0.1 m/s), N
    r = rows(out)
    return max((b["external_work"] - a["external_work"]) / (b["time"] - a["time"]) / 0.1 for a, b in zip(r, r[1:]))

def worst(out):
    r = rows(out)
    scale = max(max(abs(x["kinetic"]), abs(x["strain"]), abs(x["fracture"]), abs(x["external_work"])) for x in r)
    return max(abs(x["dissipated"]) for x in r) / scale

def last(out):
    return open(os.path.join(root, out, "balance.csv")).read().strip().split("\n")[-1]

# 1. the straight run against the bar split from the start
no_ahead = ["-fdem_insert_ahead", "0"] # (A, B, C: one insertion a cell reaching the ratio, with its neighbours)
ta = run(np, "A", no_ahead)
run(np, "S", [], presplit)
ia = insertions(ta)
check("the straight run inserts joints several times", len(ia) >= 3, f"{len(ia)} insertions: {ia}")
pa, ps = peak_pull("A"), peak_pull("S")
check("peak pull within 2% of the bar split from the start", abs(pa - ps) <= 0.02 * ps, f"{pa:.5g} N against {ps:.5g} N")
fa, fs = rows("A")[-1]["fracture"], rows("S")[-1]["fracture"]
check("energy dissipated by the fracture within 2% of the bar split from the start", abs(fa - fs) <= 0.02 * fs, f"{fa:.5g} J against {fs:.5g} J")
wa, ws = worst("A"), worst("S")
check("balance closed: largest |dissipated| below 2e-3 of the largest energy", wa <= 2e-3, f"{wa:.3e} (the bar split from the start: {ws:.3e})")
check("the bar breaks", len(breaks("A")) > 0, f"{len(breaks('A'))} joints broken")

# 2. a restart from a checkpoint between two insertions, on the same ranks
import glob
first = max(glob.glob(os.path.join(root, "A", "checkpoint.*.h5")), key=lambda f: int(f.split(".")[-2])) # the oldest kept
tb = run(np, "B", no_ahead + ["-restart", first, "-fdem_insert_heap", "0"])
after = [x for x in ia if x[0] > 0.0025]
check("the restart makes the insertions the straight run made after 2.5 ms", insertions(tb) == after and len(after) >= 2, f"{insertions(tb)} against {after}")
check("the restart breaks the same joints in the same steps", breaks("B") == breaks("A"), f"{len(breaks('B'))} breaks")
check(f"the restart's last balance row equals the straight run's bitwise ({np} ranks)", last("A") == last("B"), f"\n  {last('A')}\n  {last('B')}")

# a scene without insert_at cannot take that checkpoint: an error that says why
code, text = run(np, "X", no_ahead + ["-restart", first], presplit, expect_ok=False)
check("restarting a scene without insert_at from it: an error naming the checkpoint", code != 0 and "inserted joints during the run" in text and "fracture.insert_at" in text, f"exit status {code}")

# 3. the same restart on the other rank count
tc = run(other, "C", no_ahead + ["-restart", first])
check(f"on {other} ranks: the same insertions", [n for _, n in insertions(tc)] == [n for _, n in after], f"{insertions(tc)}")
bc, ba = breaks("C"), breaks("A")
same = sorted(j for _, j in bc) == sorted(j for _, j in ba)
near = same and all(min(abs(s - t) for t, k in ba if k == j) <= 2 for s, j in bc)
check(f"on {other} ranks: the same joints break, in steps within 2 of the straight run's", near, f"{len(bc)} breaks")
a, c = [float(x) for x in last("A").split(",")], [float(x) for x in last("C").split(",")]
d = max(abs(x - y) for x, y in zip(a, c)) / max(abs(x) for x in a)
check(f"on {other} ranks: last balance row within 1e-3 of the largest value", d <= 1e-3, f"{d:.3e}")

# 4. the default look-ahead: fewer rebuilds, the same bar
id_ = insertions(run(np, "D", []))
check("with the look-ahead, fewer insertions", 1 <= len(id_) < len(ia), f"{len(id_)} against {len(ia)}: {id_}")
pd, fd = peak_pull("D"), rows("D")[-1]["fracture"]
check("with the look-ahead, peak pull within 2% of the bar split from the start", abs(pd - ps) <= 0.02 * ps, f"{pd:.5g} N against {ps:.5g} N")
check("with the look-ahead, energy dissipated by the fracture within 2% of the bar split from the start", abs(fd - fs) <= 0.02 * fs, f"{fd:.5g} J against {fs:.5g} J")
sys.exit(1 if fail else 0)
