#!/usr/bin/env python3
"""Checkpoint and restart (tests/driver/restart.yaml: 150 steps, checkpoints at steps 75 and 150).
  1. straight run on NP ranks -> A (checkpoint.h5 = step 150, checkpoint.1.h5 = step 75);
  2. restart from A/checkpoint.1.h5 on NP ranks: the last row of balance.csv equals A's bitwise
     (printed with 17 digits: every energy and momentum component identical);
  3. restart from it on the other rank count (1 <-> 2): equal to 1e-9 of the largest value
     (force sums in another order);
  4. kill -9 during the second checkpoint write (after the temporary file, before the rename;
     -fdem_checkpoint_kill 2): checkpoint.h5 is still the step-75 one, readable, and a restart
     from it ends bitwise equal to A.
usage: restart.py MPIEXEC NP FDEM SCENE"""
import os, subprocess, sys, tempfile

mpiexec, np, fdem, scene = sys.argv[1:5]
other = "2" if np == "1" else "1"
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
root = tempfile.mkdtemp(prefix="fdem_restart_")
fail = []

def run(n, out, more, expect_ok=True):
    cmd = [mpiexec, "--oversubscribe", "-n", n, fdem, scene, "-fdem_output", os.path.join(root, out), "-fdem_progress", "0"] + more
    print("$ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600, env=env)
    print(r.stdout[-3000:] + r.stderr[-2000:])
    if expect_ok and r.returncode != 0:
        sys.exit(f"FAIL: exit status {r.returncode}")
    return r

def last(out):
    return open(os.path.join(root, out, "balance.csv")).read().strip().split("\n")[-1]

def check(name, ok, detail=""):
    print(("ok   " if ok else "FAIL ") + name + (": " + detail if detail else ""))
    if not ok: fail.append(name)

run(np, "A", [])
check("checkpoints kept", os.path.exists(os.path.join(root, "A/checkpoint.h5")) and os.path.exists(os.path.join(root, "A/checkpoint.1.h5")))
run(np, "B", ["-restart", os.path.join(root, "A/checkpoint.1.h5")])
check(f"75 steps + restart + 75 steps == 150 steps, bitwise ({np} ranks)", last("A") == last("B"), f"\n  {last('A')}\n  {last('B')}")
run(other, "C", ["-restart", os.path.join(root, "A/checkpoint.1.h5")])
a, c = [float(x) for x in last("A").split(",")], [float(x) for x in last("C").split(",")]
scale = max(abs(x) for x in a)
worst = max(abs(x - y) for x, y in zip(a, c)) / scale
check(f"restart on {other} ranks from a {np}-rank checkpoint: largest difference / largest value", worst <= 1e-9, f"{worst:.3e} (bound 1e-9)")
r = run(np, "D", ["-fdem_checkpoint_kill", "2"], expect_ok=False)
check("killed during the second checkpoint write", r.returncode != 0, f"exit status {r.returncode}")
check("the temporary file is left, not renamed", os.path.exists(os.path.join(root, "D/checkpoint.h5.tmp")))
run(np, "E", ["-restart", os.path.join(root, "D/checkpoint.h5")])
check("restart from the checkpoint that survived the kill ends bitwise equal to the straight run", last("A") == last("E"), f"\n  {last('A')}\n  {last('E')}")
sys.exit(1 if fail else 0)
