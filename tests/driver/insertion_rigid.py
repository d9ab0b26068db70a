#!/usr/bin/env python3
"""Joints inserted during a run beside rigid bodies (tests/driver/insertion_rigid.yaml): an
insertion builds the deformable model and the scene again and keeps the rigid bodies' model and
their contact as they are.
  1. the straight run A on NP ranks inserts joints at least twice after its first checkpoint
     (0.3 ms), while the two free spheres are in contact (from about 0.2 to 0.6 ms);
  2. a restart B from that checkpoint on NP ranks, whose rigid bodies' model is made from the
     checkpoint: the same insertions after it, the same joints broken in the same steps, and
     the last row of balance.csv and every row of bodies.csv equal to A's bitwise (the kept
     model carries the bodies' state and the spheres' tangential springs through the
     insertions exactly as a checkpoint does).
usage: insertion_rigid.py MPIEXEC NP FDEM SCENE"""
import csv, glob, os, re, subprocess, sys
from scratch import scratch_dir

mpiexec, np, fdem, scene = sys.argv[1:5]
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
root = scratch_dir("fdem_insertion_rigid_")
fail = []

def run(out, more):
    cmd = [mpiexec, "--oversubscribe", "-n", np, fdem, scene, "-fdem_output", os.path.join(root, out), "-fdem_progress", "1"] + more
    print("$ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600, env=env)
    print(r.stdout[-2500:] + r.stderr[-2000:])
    if r.returncode != 0:
        sys.exit(f"FAIL: exit status {r.returncode}")
    return r.stdout

def check(name, ok, detail=""):
    print(("ok   " if ok else "FAIL ") + name + (": " + detail if detail else ""))
    if not ok: fail.append(name)

def insertions(text): # (time, tetrahedra) of every insertion the run reports
    return [(float(t), int(n)) for t, n in re.findall(r"t = ([0-9.e+-]+) s: joints inserted at ([0-9]+) tetrahedra", text)]

def breaks(out):
    with open(os.path.join(root, out, "fracture.csv")) as f:
        return [(int(r["step"]), int(r["joint"])) for r in csv.DictReader(f)]

def last(out):
    return open(os.path.join(root, out, "balance.csv")).read().strip().split("\n")[-1]

def bodies(path):
    return open(path).read()

ta = run("A", [])
first = max(glob.glob(os.path.join(root, "A", "checkpoint.*.h5")), key=lambda f: int(f.split(".")[-2])) # the oldest kept: 0.3 ms
after = [x for x in insertions(ta) if x[0] > 0.0003]
check("the straight run inserts joints at least twice after 0.3 ms", len(after) >= 2, f"{insertions(ta)}")
check("the rigid bodies' contact is in use", re.search(r"contact \(rigid-rigid\): [0-9]+ searches in [1-9][0-9]* evaluations", ta) is not None)
tb = run("B", ["-restart", first])
check("the restart makes the same insertions", insertions(tb) == after, f"{insertions(tb)} against {after}")
check("the restart breaks the same joints in the same steps", breaks("B") == breaks("A") and len(breaks("A")) > 0, f"{len(breaks('B'))} and {len(breaks('A'))} breaks")
check(f"the restart's last balance row equals the straight run's bitwise ({np} ranks)", last("A") == last("B"), f"\n  {last('A')}\n  {last('B')}")
bb = glob.glob(os.path.join(root, "B", "restart_*", "bodies.csv"))
check("the restart's bodies.csv equals the straight run's bitwise", len(bb) == 1 and bodies(bb[0]) == bodies(os.path.join(root, "A", "bodies.csv")))
sys.exit(1 if fail else 0)
