#!/usr/bin/env python3
"""Runs `fdem SCENE [options]` under mpiexec and checks its out/balance.csv.
usage: check_balance.py MPIEXEC NP FDEM SCENE [checks] [-- fdem options]
checks (each fails the test when not met; all bounds are relative):
  --momentum TOL   max_t |P(t) - P(0)| <= TOL * max_t |P|      (linear momentum)
  --angular TOL    max_t |L(t) - L(0)| <= TOL * max_t |L|      (angular momentum about the origin)
  --energy TOL     max_t |dissipated| <= TOL * E_ref, E_ref = max_t (kinetic + strain + contact)
  --dts a,b,...    run once per time step (-ts_dt) and require the --energy error to shrink with dt
  --ke-min T,R     the first local minimum of the kinetic energy lies at T within R*T
  --ke-period T,R  successive deep minima of the kinetic energy are T apart (mean) within R*T
                   (deep: the lowest sample of each run of rows below 20% of the largest kinetic
                   energy, refined by a parabola; ripples of higher modes do not count)
  --at-rest F      kinetic(end) <= F * (gravity(0) - gravity(end))  (potential energy released)
  --final C,V,R    column C of the last row equals V within R * |V|  (e.g. strain,0.02,1e-3)
  --mean-after T,C,LO  the mean of column C over the rows at t >= T is at least LO"""
import csv, math, os, subprocess, sys
from scratch import scratch_dir

args = sys.argv[1:]
mpiexec, np, fdem, scene = args[:4]
rest = args[4:]
extra = []
if "--" in rest:
    i = rest.index("--")
    rest, extra = rest[:i], rest[i + 1:]
finals = [rest[i + 1] for i in range(0, len(rest), 2) if rest[i] == "--final"]
checks = dict(zip(rest[0::2], rest[1::2]))
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
failures = []

def run(more):
    out = scratch_dir("fdem_scene_")
    cmd = [mpiexec, "--oversubscribe", "-n", np, fdem, scene, "-fdem_output", out, "-fdem_progress", "0"] + extra + more
    print("$ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=1200, env=env)
    print(r.stdout + r.stderr)
    if r.returncode != 0:
        sys.exit(f"FAIL: fdem exited with {r.returncode}")
    rows = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(open(out + "/balance.csv"))]
    assert len(rows) >= 2, "balance.csv has fewer than two rows"
    return rows

def vec_drift(rows, keys):
    p0 = [rows[0][k] for k in keys]
    drift = max(math.sqrt(sum((r[k] - p0[i]) ** 2 for i, k in enumerate(keys))) for r in rows)
    scale = max(math.sqrt(sum(r[k] ** 2 for k in keys)) for r in rows)
    return drift / scale if scale > 0 else drift

def energy_error(rows):
    ref = max(r["kinetic"] + r["strain"] + r["contact"] for r in rows)
    return max(abs(r["dissipated"]) for r in rows) / ref

def minima(rows):
    ke = [r["kinetic"] for r in rows]
    out = []
    for i in range(1, len(ke) - 1):
        if ke[i] < ke[i - 1] and ke[i] <= ke[i + 1]:
            # parabola through the three samples
            t0, t1, t2 = rows[i - 1]["time"], rows[i]["time"], rows[i + 1]["time"]
            a, b, c = ke[i - 1], ke[i], ke[i + 1]
            h = t1 - t0
            den = a - 2 * b + c
            out.append(t1 + (0.5 * h * (a - c) / den if den > 0 else 0))
    return out

def deep_minima(rows):
    ke = [r["kinetic"] for r in rows]
    low = 0.2 * max(ke)
    out, i = [], 0
    while i < len(ke):
        if ke[i] >= low:
            i += 1
            continue
        j = i
        while j < len(ke) and ke[j] < low:
            j += 1
        k = min(range(i, j), key=lambda q: ke[q])
        if 0 < k < len(ke) - 1 and j < len(ke) and i > 0:  # a whole dip, not cut by the ends of the run
            a, b, c = ke[k - 1], ke[k], ke[k + 1]
            h, den = rows[k]["time"] - rows[k - 1]["time"], a - 2 * b + c
            out.append(rows[k]["time"] + (0.5 * h * (a - c) / den if den > 0 else 0))
        i = j
    return out

def check(name, value, bound):
    ok = value <= bound
    print(f"{'ok  ' if ok else 'FAIL'} {name}: {value:.3e} (bound {bound:.1e})")
    if not ok:
        failures.append(name)

def check_finals(rows, tag):
    for f in finals:
        col, value, rel = f.split(",")
        value, rel = float(value), float(rel)
        check(f"{tag}{col} at the end {rows[-1][col]:.8g} vs {value:.8g} (relative difference)", abs(rows[-1][col] - value) / abs(value), rel)

if "--dts" in checks:
    errs = []
    for dt in checks["--dts"].split(","):
        rows = run(["-ts_dt", dt])
        errs.append(energy_error(rows))
        if "--momentum" in checks: check(f"dt {dt}: linear momentum drift", vec_drift(rows, ["px", "py", "pz"]), float(checks["--momentum"]))
        if "--energy" in checks: check(f"dt {dt}: energy balance error", errs[-1], float(checks["--energy"]))
        check_finals(rows, f"dt {dt}: ")
    for i in range(1, len(errs)):
        check(f"energy error ratio dt {i} / dt {i - 1} (must shrink)", errs[i] / errs[i - 1], 0.95)
else:
    rows = run([])
    if "--momentum" in checks: check("linear momentum drift", vec_drift(rows, ["px", "py", "pz"]), float(checks["--momentum"]))
    if "--angular" in checks: check("angular momentum drift", vec_drift(rows, ["Lx", "Ly", "Lz"]), float(checks["--angular"]))
    if "--energy" in checks: check("energy balance error", energy_error(rows), float(checks["--energy"]))
    if "--ke-min" in checks:
        T, R = map(float, checks["--ke-min"].split(","))
        m = minima(rows)
        print(f"kinetic energy minima at {m}")
        check(f"first kinetic minimum at {m[0] if m else float('nan'):.6g} s vs {T:.6g} s (relative difference)", abs(m[0] - T) / T if m else 1e9, R)
    if "--ke-period" in checks:
        T, R = map(float, checks["--ke-period"].split(","))
        m = deep_minima(rows)
        print(f"kinetic energy minima at {m}")
        per = (m[-1] - m[0]) / (len(m) - 1) if len(m) >= 2 else float("nan")
        check(f"kinetic energy period {per:.6g} s vs {T:.6g} s (relative difference)", abs(per - T) / T if len(m) >= 2 else 1e9, R)
    check_finals(rows, "")
    if "--mean-after" in checks:
        T, col, lo = checks["--mean-after"].split(",")
        late = [r[col] for r in rows if r["time"] >= float(T)]
        mean = sum(late) / len(late) if late else float("nan")
        print(f"mean {col} over t >= {T}: {mean:.6g} ({len(late)} rows)")
        check(f"{lo} - mean {col} over t >= {T} (must not be positive)", float(lo) - mean if late else 1e9, 0.0)
    if "--at-rest" in checks:
        released = rows[0]["gravity"] - rows[-1]["gravity"]
        check("kinetic energy at the end / potential energy released", rows[-1]["kinetic"] / released if released > 0 else 1e9, float(checks["--at-rest"]))
sys.exit(1 if failures else 0)
