#!/usr/bin/env python3
"""The fragmentation example, short: runs examples/scenes/fragmentation.yaml with
the ball's impact speed set to SPEED (m/s) up to time END (s) on each rank count
of RANKS, and checks each run's fragments.csv and balance.csv:

  * more than one fragment, and the driver's text gives their number;
  * the fragments' masses sum to the ball's mass, computed here from the mesh
    file (tetrahedron volumes times the density), to 1e-9 relative;
  * the last row's fracture column (energy dissipated by the joints) is > 0;
  * the energy balance closes: max |dissipated| <= ETOL * the initial kinetic
    energy (the contact has no friction or damping, so dissipated is the
    numerical error alone);
  * the fragment counts of the rank counts differ by at most CTOL;
  * with --unfractured: the balance closes as well as the unfractured run's. One
    rank runs the scene again with the material's `fracture:` block taken out (the
    same ball, not fracturable, striking the plate), and each run's max
    |dissipated| must be at most 1.5 times that run's. The unfractured ball's is the
    contact's own residual (the potential contact force is the gradient of the overlap
    energy for rigid motions of two tetrahedra, not for deforming ones: its work and the
    energy part by about 1e-3 of the impact energy at the deepest compression, and the
    rebound gives it back). Energy that the joints' bookkeeping
    added at each step (a release of damage taken at the step's end instead of its
    middle: first order in the step) or that the model added at its switches (a
    joint removed with its compression, contact pairs listed already overlapped)
    would show as a balance error several times larger (4.4 times at END = 1.2 ms
    before the release was taken at the middle);
  * with --restart: one rank runs again with checkpoints (every 0.8 END), and a restart
    from the checkpoint at 0.8 END ends with the last row of balance.csv equal to that
    run's, bitwise: the joints' damage, their dissipated energy and the contact energy
    taken over from them (joint_contact_onset) travel with the checkpoint.

  fragmentation_check.py MPIEXEC FDEM SCENE SPEED END ETOL CTOL RANKS [--unfractured] [--restart] [driver options...]
"""
import csv
import os
import re
import subprocess
import sys
from scratch import scratch_dir

mpiexec, fdem, scene = sys.argv[1], sys.argv[2], sys.argv[3]
speed, end, etol, ctol = float(sys.argv[4]), sys.argv[5], float(sys.argv[6]), int(sys.argv[7])
ranks = [int(n) for n in sys.argv[8].split(",")]
more = sys.argv[9:]
unfractured, restart = "--unfractured" in more, "--restart" in more
more = [m for m in more if m not in ("--unfractured", "--restart")]
root = scratch_dir("fdem_fragmentation_")
text = open(scene).read()
text, n1 = re.subn(r"velocity: \[0, 0, -?[0-9.eE+-]+\]", f"velocity: [0, 0, {-speed!r}]", text)
mesh = re.search(r"mesh: (\S+?\.msh)", text).group(1)
mesh_path = os.path.join(os.path.dirname(os.path.abspath(scene)), mesh)
text, n2 = re.subn(r"mesh: \S+?\.msh", "mesh: " + mesh_path, text)
if n1 != 1 or n2 != 1:
    sys.exit("FAIL: the scene must have one 'velocity: [0, 0, v]' and one mesh file")
variant = os.path.join(root, "scene.yaml")
open(variant, "w").write(text)

# the ball's mass from the mesh: Gmsh 2.2 ASCII, 4-node tetrahedra (type 4)
rho = float(re.search(r"rock: \{density: ([0-9.eE+-]+)", text).group(1))
lines = open(mesh_path).read().split("\n")
i = lines.index("$Nodes")
nodes = {}
for ln in lines[i + 2:i + 2 + int(lines[i + 1])]:
    q = ln.split()
    nodes[q[0]] = [float(c) for c in q[1:4]]
i = lines.index("$Elements")
volume = 0.0
for ln in lines[i + 2:i + 2 + int(lines[i + 1])]:
    q = ln.split()
    if q[1] != "4":
        continue
    a, b, c, d = (nodes[t] for t in q[-4:])
    u = [b[k] - a[k] for k in range(3)]
    v = [c[k] - a[k] for k in range(3)]
    w = [d[k] - a[k] for k in range(3)]
    volume += abs(u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                  u[2] * (v[0] * w[1] - v[1] * w[0])) / 6.0
mass = rho * volume
print(f"ball: {mass!r} kg from {mesh_path}")

counts = {}
errs = {}
failures = []
runs = [(n, variant) for n in ranks]
if unfractured:
    text2, n3 = re.subn(r",\s*fracture: \{[^}]*\}", "", text)
    if n3 != 1:
        sys.exit("FAIL: --unfractured needs one ', fracture: {...}' in the scene")
    plain_variant = os.path.join(root, "scene_unfractured.yaml")
    open(plain_variant, "w").write(text2)
    runs.insert(0, (1, plain_variant))
for n, scene_file in runs:
    plain = scene_file != variant
    out = os.path.join(root, f"np{n}" + ("_unfractured" if plain else ""))
    cmd = [mpiexec, "--oversubscribe", "-n", str(n), fdem, scene_file, "-fdem_output", out, "-fdem_progress", "0",
           "-ts_max_time", end] + more
    print("$ " + " ".join(cmd), flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    print(r.stdout[-1500:] + r.stderr[-1500:])
    if r.returncode != 0:
        sys.exit(f"FAIL: exit status {r.returncode} on {n} rank(s)")
    frags = list(csv.DictReader(open(os.path.join(out, "fragments.csv"))))
    bal = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(open(os.path.join(out, "balance.csv")))]
    total = sum(float(x["mass"]) for x in frags)
    ke0 = bal[0]["kinetic"]
    err = max(abs(row["dissipated"]) for row in bal) / ke0
    if plain:
        plain_err = err
        print(f"unfractured, 1 rank: {len(frags)} fragment(s), max |dissipated| / kinetic(0) = {err:.3e}", flush=True)
        if len(frags) != 1 or not bal[-1]["fracture"] == 0:
            failures.append(f"the unfractured run has {len(frags)} fragments and fracture {bal[-1]['fracture']!r}")
        continue
    counts[n] = len(frags)
    errs[n] = err
    if unfractured:
        print(f"{n} rank(s): max |dissipated| is {err / plain_err:.2f} times the unfractured run's (at most 1.5)", flush=True)
        if not err <= 1.5 * plain_err:
            failures.append(f"the balance error {err:.3e} on {n} rank(s) is {err / plain_err:.2f} times the unfractured "
                            f"run's {plain_err:.3e} (at most 1.5)")
    fracture = bal[-1]["fracture"]
    print(f"{n} rank(s): {len(frags)} fragments, masses sum {total!r} kg (ball {mass!r}), fracture {fracture:.6g} J, "
          f"max |dissipated| / kinetic(0) = {err:.3e} (kinetic(0) = {ke0:.6g} J)", flush=True)
    if f"fragments: {len(frags)} " not in r.stdout:
        failures.append(f"the driver's text does not give the {len(frags)} fragments ({n} rank(s))")
    if len(frags) < 2:
        failures.append(f"{len(frags)} fragment(s) on {n} rank(s): the ball did not break")
    if abs(total - mass) > 1e-9 * mass:
        failures.append(f"the fragments' masses sum to {total!r}, the ball's is {mass!r} ({n} rank(s))")
    if not fracture > 0:
        failures.append(f"fracture column {fracture!r} is not > 0 ({n} rank(s))")
    if err > etol:
        failures.append(f"energy balance error {err:.3e} above {etol} of the impact energy ({n} rank(s))")
if restart:
    ckpt_variant = os.path.join(root, "scene_checkpoints.yaml")
    open(ckpt_variant, "w").write(text + f"\ncheckpoint: {{every: {0.8 * float(end)!r}, keep: 2}}\n")
    last = {}
    for name, extra in (("straight", []), ("restarted", ["-restart", os.path.join(root, "straight", "checkpoint.1.h5")])):
        out = os.path.join(root, name)
        cmd = [mpiexec, "--oversubscribe", "-n", "1", fdem, ckpt_variant, "-fdem_output", out, "-fdem_progress", "0",
               "-ts_max_time", end] + extra + more
        print("$ " + " ".join(cmd), flush=True)
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
        print(r.stdout[-800:] + r.stderr[-1500:])
        if r.returncode != 0:
            sys.exit(f"FAIL: exit status {r.returncode} ({name})")
        last[name] = open(os.path.join(out, "balance.csv")).read().strip().split("\n")[-1]
    # the handover booked before the checkpoint, as saved in it (h5py runs under the system python)
    q = subprocess.run(["/usr/bin/python3", "-c", "import h5py, sys; print(h5py.File(sys.argv[1], 'r')['joint_contact_onset'][()][0])",
                        os.path.join(root, "straight", "checkpoint.1.h5")], capture_output=True, text=True)
    saved = float(q.stdout) if q.returncode == 0 else float("nan")
    print(f"restart from {0.8 * float(end):g} s: joint_contact_onset in the checkpoint {saved:.6g} J; last rows\n"
          f"  {last['straight']}\n  {last['restarted']}", flush=True)
    if not saved > 0:
        failures.append(f"the checkpoint holds no contact energy taken over from joints ({q.stderr.strip() or saved}): "
                        "the restart check would not test it")
    if last["straight"] != last["restarted"]:
        failures.append("the restart does not end bitwise equal to the run it restarts")
if len(counts) > 1 and max(counts.values()) - min(counts.values()) > ctol:
    failures.append(f"fragment counts {counts} differ by more than {ctol}")
if failures:
    sys.exit("FAIL: " + "; ".join(failures))
print("PASS")
