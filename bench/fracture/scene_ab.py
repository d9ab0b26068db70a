#!/usr/bin/env python3
"""A fracturing scene run by two builds of the fdem driver in interleaved rounds.

Each round runs BASE, then NEW, on one core (`taskset -c CORE` where taskset exists) and reads
the stepping CPU time and the contact searches from the driver's summary. At the end it prints
the median, least and largest CPU time of each build and their ratio, and compares the two
builds' last outputs: balance.csv entry by entry (largest difference), and fracture.csv and
fragments.csv (equal to the byte, or how many rows).

  scene_ab.py --base-fdem BASE --new-fdem NEW [--scene SCENE] [--end T] [--rounds R]
              [--core C] [--out DIR] [driver options...]

Default: examples/scenes/fragmentation.yaml to 1.5 ms, 3 rounds, core 1.
"""
import argparse
import csv
import filecmp
import os
import re
import shutil
import statistics
import subprocess
import sys

root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("--base-fdem", required=True)
ap.add_argument("--new-fdem", required=True)
ap.add_argument("--scene", default=os.path.join(root, "examples", "scenes", "fragmentation.yaml"))
ap.add_argument("--end", default="0.0015", help="-ts_max_time of every run (s)")
ap.add_argument("--rounds", type=int, default=3)
ap.add_argument("--core", default="1")
ap.add_argument("--out", default="/tmp/fdem_scene_ab")
args, more = ap.parse_known_args()

pin = ["taskset", "-c", args.core] if shutil.which("taskset") else []
cpu = {"base": [], "new": []}
last = {}
for r in range(args.rounds):
    for name, fdem in (("base", args.base_fdem), ("new", args.new_fdem)):
        out = os.path.join(args.out, name)
        shutil.rmtree(out, ignore_errors=True)
        cmd = pin + [fdem, args.scene, "-fdem_output", out, "-ts_max_time", args.end, "-fdem_progress", "0"] + more
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode != 0:
            sys.exit(f"{name}: exit status {p.returncode}\n{p.stdout[-2000:]}{p.stderr[-2000:]}")
        m = re.search(r"stepping CPU time ([0-9.eE+-]+) s", p.stdout)
        if not m:
            sys.exit(f"{name}: no stepping CPU time in the driver's summary")
        cpu[name].append(float(m.group(1)))
        searches = re.findall(r"contact \(([a-z-]+)\): (\d+) searches in (\d+) evaluations", p.stdout)
        kept = re.findall(r"contact \(([a-z-]+)\): (\d+) listings where joints broke", p.stdout)
        last[name] = out
        print(f"round {r + 1} {name}: {cpu[name][-1]:.3f} s; searches " +
              ", ".join(f"{w} {s} in {e}" for w, s, e in searches) +
              ("; kept " + ", ".join(f"{w} {k}" for w, k in kept) if kept else ""), flush=True)

for name in ("base", "new"):
    c = cpu[name]
    print(f"{name}: stepping CPU median {statistics.median(c):.3f} s (least {min(c):.3f}, largest {max(c):.3f})")
print(f"base/new (medians): {statistics.median(cpu['base']) / statistics.median(cpu['new']):.3f}")


def rows(path):
    with open(path) as f:
        return list(csv.reader(f))


b, n = rows(os.path.join(last["base"], "balance.csv")), rows(os.path.join(last["new"], "balance.csv"))
worst, where = 0.0, ""
for u, w in zip(b[1:], n[1:]):
    for k, (x, y) in enumerate(zip(u, w)):
        d = abs(float(x) - float(y))
        if d > worst:
            worst, where = d, f"{b[0][k]} at t = {u[0]}"
print(f"balance.csv: {len(b) - 1} and {len(n) - 1} rows; largest difference {worst:.3g}" + (f" ({where})" if where else ""))
for f in ("fracture.csv", "fragments.csv"):
    x, y = os.path.join(last["base"], f), os.path.join(last["new"], f)
    if os.path.exists(x) and os.path.exists(y):
        same = filecmp.cmp(x, y, shallow=False)
        print(f"{f}: " + ("equal to the byte" if same else f"differ ({len(rows(x)) - 1} and {len(rows(y)) - 1} rows)"))
