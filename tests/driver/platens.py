"""Shared by brazilian.py and uniaxial.py: run a scene of a specimen between two rigid platens
closing at the same speed, and read the load on the platens from its loads.csv.
  RunScene(prefix): parses `MPIEXEC NP FDEM SCENE [--plot DOCDIR] [--out DIR] [-- fdem options]`
    from the command line, runs fdem and returns (options, output folder); exits on failure.
  PlatenLoad(out): the rows of out/balance.csv, their times t and external_work W, and at each
    row the load P on the platens from out/loads.csv (the driver's force on each moved rigid body,
    one row with each balance row but the first): the mean of what the specimen puts on the top
    platen (+z) and on the bottom one (-z), each less its own weight (its load at the first row,
    when nothing touches it yet); P = 0 at t = 0. The platens are the scene's bodies `top` and
    `bottom`, closing along z."""
import csv, os, subprocess, sys

import numpy as np
from scratch import scratch_dir


def RunScene(prefix):
    args = sys.argv[1:]
    mpiexec, nproc, fdem, scene = args[:4]
    rest, extra = args[4:], []
    if "--" in rest:
        i = rest.index("--")
        rest, extra = rest[:i], rest[i + 1:]
    opts = dict(zip(rest[0::2], rest[1::2]))
    out = opts.get("--out") or scratch_dir(prefix)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
    cmd = [mpiexec, "--oversubscribe", "-n", nproc, fdem, scene, "-fdem_output", out, "-fdem_progress", "0"] + extra
    print("$ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=1500, env=env)
    print(r.stdout + r.stderr)
    if r.returncode != 0:
        sys.exit(f"FAIL: fdem exited with {r.returncode}")
    return opts, out


def PlatenLoad(out):
    rows = [{k: float(x) for k, x in row.items()} for row in csv.DictReader(open(out + "/balance.csv"))]
    t = np.array([q["time"] for q in rows])
    W = np.array([q["external_work"] for q in rows])
    loads = [{k: float(x) for k, x in row.items()} for row in csv.DictReader(open(out + "/loads.csv"))]
    if len(loads) != len(rows) - 1 or abs(loads[-1]["time"] - t[-1]) > 1e-12 * max(1.0, t[-1]):
        sys.exit(f"FAIL: {out}/loads.csv has {len(loads)} rows to {loads[-1]['time'] if loads else 0}, balance.csv {len(rows)} to {t[-1]}")
    top = np.array([q["top_Fz"] for q in loads])
    bottom = np.array([q["bottom_Fz"] for q in loads])
    P = np.concatenate(([0.0], 0.5 * ((top - top[0]) - (bottom - bottom[0]))))
    return rows, t, W, P
