"""Shared by brazilian.py and uniaxial.py: run a scene of a specimen between two rigid platens
closing at the same speed, and read the load from its balance.csv.
  RunScene(prefix): parses `MPIEXEC NP FDEM SCENE [--plot DOCDIR] [--out DIR] [-- fdem options]`
    from the command line, runs fdem and returns (options, output folder); exits on failure.
  PlatenLoad(out, v): the rows of out/balance.csv and, per balance interval, the mid time tm and
    the mean load P = (dW/dt) / (2 v) on each platen (W: external_work, v: each platen's speed)."""
import csv, os, subprocess, sys, tempfile

import numpy as np


def RunScene(prefix):
    args = sys.argv[1:]
    mpiexec, nproc, fdem, scene = args[:4]
    rest, extra = args[4:], []
    if "--" in rest:
        i = rest.index("--")
        rest, extra = rest[:i], rest[i + 1:]
    opts = dict(zip(rest[0::2], rest[1::2]))
    out = opts.get("--out") or tempfile.mkdtemp(prefix=prefix)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
    cmd = [mpiexec, "--oversubscribe", "-n", nproc, fdem, scene, "-fdem_output", out, "-fdem_progress", "0"] + extra
    print("$ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=1500, env=env)
    print(r.stdout + r.stderr)
    if r.returncode != 0:
        sys.exit(f"FAIL: fdem exited with {r.returncode}")
    return opts, out


def PlatenLoad(out, v):
    rows = [{k: float(x) for k, x in row.items()} for row in csv.DictReader(open(out + "/balance.csv"))]
    t = np.array([q["time"] for q in rows])
    W = np.array([q["external_work"] for q in rows])
    tm = 0.5 * (t[1:] + t[:-1])
    return rows, t, W, tm, np.diff(W) / np.diff(t) / (2 * v)
