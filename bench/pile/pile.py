#!/usr/bin/env python3
"""The rigid pile benchmark: body-steps per second per core of the `fdem`
driver on a settled pile of irregular pebbles, at two builds (a base revision
and the work tree), and whether their answers agree.

For each size N: the pile is settled once (make_pile.py, the new build, cached
in OUT/N/settle); then each build restarts from that checkpoint and runs S1 and
S2 steps, in interleaved rounds. The cost per step is (CPU(S2) - CPU(S1)) /
(S2 - S1) of the whole process (so set-up cancels; CPU time, not wall time,
because the machine may be shared). Both builds' final states after S2 steps
are compared body by body (bodies.csv; the base's state is read back by
restarting the new build from the base's final checkpoint with no step).

  pile.py --base-fdem BASE --new-fdem NEW [--sizes 1000,8000] [--s1 20] [--s2 120]
          [--rounds 3] [--settle 1.5] [--out /tmp/fdem-pile] [-n RANKS]
"""
import argparse
import csv
import glob
import math
import os
import resource
import subprocess
import sys
import time

here = os.path.dirname(os.path.abspath(__file__))
p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
p.add_argument("--base-fdem", required=True, help="fdem driver of the base revision")
p.add_argument("--new-fdem", required=True, help="fdem driver of the work tree")
p.add_argument("--sizes", default="1000,8000")
p.add_argument("--s1", type=int, default=20)
p.add_argument("--s2", type=int, default=120)
p.add_argument("--rounds", type=int, default=3)
p.add_argument("--settle", type=float, default=1.5, help="simulated seconds of settling (default 1.5)")
p.add_argument("--out", default="/tmp/fdem-pile")
p.add_argument("-n", type=int, default=1, help="MPI ranks (default 1)")
p.add_argument("--skip-base", action="store_true", help="time the new build only")
p.add_argument("--scaling", action="store_true", help="instead: the new build on 1 and 2 ranks, S2 steps, speed-up from the stepping time (wall, and CPU of the busiest rank) of the driver's done line")
a = p.parse_args()
dt = 4.0e-4
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def run(cmd, log):
    """Runs cmd; returns (CPU seconds of the children, stdout)."""
    if a.n > 1:
        cmd = ["mpiexec", "--oversubscribe", "-n", str(a.n)] + cmd
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    with open(log, "w") as f:
        f.write(" ".join(cmd) + "\n" + r.stdout + r.stderr)
    if r.returncode != 0:
        sys.exit(f"pile.py: {' '.join(cmd)} failed (exit {r.returncode}); see {log}")
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), r.stdout


def scene(n, end, path):
    subprocess.run([sys.executable, os.path.join(here, "make_pile.py"), str(n), path, "--end", repr(end)], check=True)


def bodies(path):
    with open(path) as f:
        return [[float(x) for x in row[2:]] for row in list(csv.reader(f))[1:]]


def line(out, key):
    return next((l for l in out.splitlines() if l.startswith(key)), "")


def stepping(out):
    """(wall, busiest-rank CPU) seconds of the stepping, from the driver's done line."""
    import re
    m = re.search(r"stepping ([0-9.]+) s:.*stepping CPU time ([0-9.]+) s", line(out, "done:"))
    return float(m.group(1)), float(m.group(2))


if a.scaling:
    for n in [int(s) for s in a.sizes.split(",")]:
        d = os.path.join(a.out, str(n))
        ck = os.path.join(d, "settle", "checkpoint.h5")
        if not os.path.exists(ck):
            sys.exit(f"pile.py: settle the pile of {n} first (run without --scaling): {ck} is missing")
        scene(n, a.settle + a.s2 * dt, os.path.join(d, f"run{a.s2}.yaml"))
        t = {1: [], 2: []}
        for r in range(a.rounds):
            for ranks in (1, 2):
                a.n = ranks
                _, out = run([a.new_fdem, os.path.join(d, f"run{a.s2}.yaml"), "-restart", ck, "-fdem_output", os.path.join(d, f"np{ranks}"), "-fdem_progress", "0"], os.path.join(d, f"np{ranks}.log"))
                t[ranks].append(stepping(out))
                if r == 0:
                    print(f"N = {n}, {ranks} rank(s): {line(out, 'contact')}", flush=True)
        med = {k: (sorted(x[0] for x in v)[len(v) // 2], sorted(x[1] for x in v)[len(v) // 2]) for k, v in t.items()}
        B1 = bodies(glob.glob(os.path.join(d, "np1", "**", "bodies.csv"), recursive=True)[0])
        B2 = bodies(glob.glob(os.path.join(d, "np2", "**", "bodies.csv"), recursive=True)[0])
        dx = max(math.dist(u[0:3], v[0:3]) for u, v in zip(B1, B2))
        print(f"N = {n}, {a.s2} steps: 1 rank {med[1][0]:.2f} s wall, {med[1][1]:.2f} s CPU; 2 ranks {med[2][0]:.2f} s wall, {med[2][1]:.2f} s CPU on the busiest rank; "
              f"speed-up (CPU, busiest rank) {med[1][1] / med[2][1]:.2f}x, (wall) {med[1][0] / med[2][0]:.2f}x; 1 vs 2 ranks: max |dx| {dx:.3g} m", flush=True)
    sys.exit(0)

results = []
for n in [int(s) for s in a.sizes.split(",")]:
    d = os.path.join(a.out, str(n))
    os.makedirs(d, exist_ok=True)
    ck = os.path.join(d, "settle", "checkpoint.h5")
    if not os.path.exists(ck):
        scene(n, a.settle, os.path.join(d, "settle.yaml"))
        t0 = time.time()
        _, out = run([a.new_fdem, os.path.join(d, "settle.yaml"), "-fdem_output", os.path.join(d, "settle"), "-fdem_progress", "0"], os.path.join(d, "settle.log"))
        print(f"N = {n}: settled in {time.time() - t0:.0f} s: {line(out, 'contact')}", flush=True)
    builds = [("new", a.new_fdem)] + ([] if a.skip_base else [("base", a.base_fdem)])
    cpu = {(b, s): [] for b, _ in builds for s in (a.s1, a.s2)}
    for s in (a.s1, a.s2):
        scene(n, a.settle + s * dt, os.path.join(d, f"run{s}.yaml"))
    for r in range(a.rounds):
        for s in (a.s1, a.s2):
            for b, exe in builds:
                c, out = run([exe, os.path.join(d, f"run{s}.yaml"), "-restart", ck, "-fdem_output", os.path.join(d, f"{b}{s}"), "-fdem_progress", "0"], os.path.join(d, f"{b}{s}.log"))
                cpu[(b, s)].append(c)
                if r == 0 and s == a.s2 and b == "new":
                    print(f"N = {n}, new: {line(out, 'contact')}", flush=True)
    per = {}
    for b, _ in builds:
        per[b] = sorted((c2 - c1) / (a.s2 - a.s1) for c1, c2 in zip(cpu[(b, a.s1)], cpu[(b, a.s2)]))
    nb = n + 5
    row = {"n": n}
    for b in per:
        med = per[b][len(per[b]) // 2]
        row[b] = nb / med  # body-steps per CPU second = per second per busy core
        print(f"N = {n}, {b}: CPU per step {med * 1e3:.3f} ms (rounds {', '.join(f'{x * 1e3:.3f}' for x in per[b])}) -> {row[b]:.4g} body-steps/s/core", flush=True)
    if "base" in per:
        row["speedup"] = row["new"] / row["base"]
        print(f"N = {n}: new/base = {row['speedup']:.2f}x", flush=True)
        # the answers: the base's final state read back by the new build (0 steps from its checkpoint)
        base_ck = os.path.join(d, f"base{a.s2}", "checkpoint.h5")
        run([a.new_fdem, os.path.join(d, f"run{a.s2}.yaml"), "-restart", base_ck, "-fdem_output", os.path.join(d, "base_state"), "-fdem_progress", "0"], os.path.join(d, "base_state.log"))
        found = glob.glob(os.path.join(d, "base_state", "**", "bodies.csv"), recursive=True)
        Nw = glob.glob(os.path.join(d, f"new{a.s2}", "**", "bodies.csv"), recursive=True)
        if found and Nw:
            B, Nn = bodies(found[0]), bodies(Nw[0])
            dx = max(math.dist(u[0:3], v[0:3]) for u, v in zip(B, Nn))
            dv = max(math.dist(u[3:6], v[3:6]) for u, v in zip(B, Nn))
            dw = max(math.dist(u[6:9], v[6:9]) for u, v in zip(B, Nn))
            vmax = max(math.hypot(*u[3:6]) for u in B)
            print(f"N = {n}: after {a.s2} steps, new vs base: max |dx| {dx:.3g} m, max |dv| {dv:.3g} m/s (largest speed {vmax:.3g} m/s), max |domega| {dw:.3g} rad/s", flush=True)
            row.update(dx=dx, dv=dv)
    results.append(row)
with open(os.path.join(a.out, "pile.csv"), "w") as f:
    keys = ["n", "new", "base", "speedup", "dx", "dv"]
    f.write(",".join(keys) + "\n")
    for r in results:
        f.write(",".join(str(r.get(k, "")) for k in keys) + "\n")
print("table:", os.path.join(a.out, "pile.csv"))
