#!/usr/bin/env python3
"""Mesh convergence of the Brazilian disc (doc/fracture_validation.md, "Mesh convergence").
usage: brazilian_convergence.py [--reuse] FDEM NP RESOLUTIONS [DOCDIR]
Runs tests/driver/brazilian_disc.yaml with the disc's `resolution` set to each of RESOLUTIONS
(comma-separated, m) on NP ranks through tests/driver/brazilian.py, which checks each run and
writes its figures (--summary); a check that fails on a mesh is reported in the table, not an
error. Each run's output stays in out_brazilian_<resolution>/ (its scene.yaml is the copy it ran,
check.log what brazilian.py printed); --reuse takes a run from there when it has its figures
(summary.json), e.g. after running the meshes one at a time.
Then prints the table of doc/fracture_validation.md (markdown) and, with DOCDIR, writes
DOCDIR/brazilian_convergence.csv and DOCDIR/brazilian_convergence.png (the load against the
platens' approach on every mesh)."""
import csv, json, math, os, re, subprocess, sys

try:
    import numpy as np
except ImportError:  # a python3 without it (pyenv): the system's has it (scripts/install-deps.sh)
    if sys.executable != "/usr/bin/python3" and os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    raise

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.dirname(here)
sys.path.insert(0, os.path.join(root, "tests", "driver"))
from platens import PlatenLoad  # noqa: E402
args = sys.argv[1:]
reuse = args[:1] == ["--reuse"]
args = args[1:] if reuse else args
fdem, nproc, resolutions = args[0], args[1], args[2].split(",")
docdir = args[3] if len(args) > 3 else None
scene = open(os.path.join(root, "tests/driver/brazilian_disc.yaml")).read()
R, T, V, GAP = 0.05, 0.02, 0.1, 5e-5  # the scene's (brazilian.py)
disc = re.compile(r"(name: disc,.*resolution: )([0-9.e-]+)")
assert disc.search(scene), "brazilian_disc.yaml: no disc resolution"

runs = []
for res in resolutions:
    out = os.path.abspath(f"out_brazilian_{res}")
    os.makedirs(out, exist_ok=True)
    copy = os.path.join(out, "scene.yaml")
    open(copy, "w").write(disc.sub(lambda m: m.group(1) + res, scene))
    summary = os.path.join(out, "summary.json")
    if reuse and os.path.exists(summary):
        log = open(os.path.join(out, "check.log")).read()
    else:
        if os.path.exists(summary):
            os.remove(summary)
        cmd = [sys.executable, os.path.join(root, "tests/driver/brazilian.py"), "mpiexec", nproc, fdem, copy, "--out", out, "--summary", summary]
        print("$ " + " ".join(cmd), flush=True)
        r = subprocess.run(cmd, capture_output=True, text=True)
        log = r.stdout + r.stderr
        open(os.path.join(out, "check.log"), "w").write(log)
    fail = [line[6:] for line in log.splitlines() if line.startswith("FAIL: ")]
    print("\n".join(line for line in log.splitlines() if line.startswith(("peak load", "first broken", "kinetic /", "FAIL", "OK"))))
    if not os.path.exists(summary):
        sys.exit(f"resolution {res}: no figures (see {out}/check.log)")
    s = json.load(open(summary))
    def grab(pattern, cast=float):
        m = re.search(pattern, log)
        return cast(m.group(1)) if m else float("nan")
    s.update(resolution=float(res), tets=grab(r"(\d+) tetrahedra", int), joints=grab(r"fracture: (\d+) joints", int), dt=grab(r"time step ([0-9.e+-]+) s"),
             wall=grab(r"wall time ([0-9.]+) s"), cpu=grab(r"stepping CPU time ([0-9.]+) s"), checks="; ".join(fail) if fail else "met")
    _, t, _, P = PlatenLoad(out)  # the load at each balance row, as brazilian.py reads it
    s["curve"] = (2 * V * t - 2 * GAP, P)
    runs.append(s)

print(f"\n| resolution | tetrahedra | joints | dt | peak load | 2P/(pi D t) / f_t | first break | its \\|z\\| | first 5: \\|z\\| <= | KE / work before it | stepping CPU time, busiest of {nproc} ranks | wall time | checks |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for s in runs:
    print(f"| {s['resolution']:g} m | {s['tets']} | {s['joints']} | {s['dt']:.2g} s | {s['peak_load']:.0f} N | {s['peak_ratio']:.3f} | {s['first_time'] * 1e3:.3f} ms | "
          f"{s['first_z']:.2f} R | {s['first_z_max']:.2f} R | {s['ke_ratio_before_first'] * 100:.2f}% | {s['cpu']:.0f} s | {s['wall']:.0f} s | {s['checks']} |")
if docdir:
    keys = ["resolution", "tets", "joints", "dt", "peak_load", "peak_ratio", "peak_time", "first_time", "first_z", "first_x_max", "first_z_max", "ke_ratio_max", "ke_ratio_before_first", "cpu", "wall", "checks"]
    with open(os.path.join(docdir, "brazilian_convergence.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(keys)
        for s in runs:
            w.writerow([s[k] for k in keys])
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for s in runs:
        x, P = s["curve"]
        ax.plot(x * 1e3, P / 1e3, "-", lw=1, label=f"resolution {s['resolution']:g} m ({s['tets']} tetrahedra): peak {s['peak_ratio']:.3f} f_t")
    ax.axhline(math.pi * 2 * R * T * 1e6 / 2 / 1e3, color="k", ls="--", lw=0.8, label="P for 2P/(pi D t) = f_t")
    ax.set_xlabel("platens' approach after contact (mm)")
    ax.set_ylabel("load P (kN)")
    ax.set_title("Brazilian disc on three meshes")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(docdir, "brazilian_convergence.png"), dpi=90)
    print(f"wrote {docdir}/brazilian_convergence.csv, {docdir}/brazilian_convergence.png")
