#!/usr/bin/env python3
"""Checkpoint and restart (tests/driver/restart.yaml: 150 steps, checkpoints at steps 75 and 150;
restart_move.yaml: the same steps 1-4 for a scene with moved nodes, whose external work is
carried by the checkpoint).
  1. straight run on NP ranks -> A (checkpoint.h5 = step 150, checkpoint.1.h5 = step 75);
  2. restart from A/checkpoint.1.h5 on NP ranks: the last row of balance.csv equals A's bitwise
     (printed with 17 digits: every energy and momentum component identical);
  3. restart from it on the other rank count (1 <-> 2): equal to 1e-9 of the largest value
     (force sums in another order). For a scene that breaks joints (fracture.csv): the same
     joints break in the same steps, every balance row up to the first break after the
     restart is equal to 1e-9, and the last row to 1e-4: a joint point breaks when its damage
     crosses 1, so round-off in the force sums can move a point's break by a step, and the
     fragments' motion amplifies that (doc/fracture.md, "Not built yet"). And for such a
     scene: the checkpoint without its joint_shear_damage and joint_last_energy (as an fdem
     before the shear's secant form wrote it) restarts with a note for each and runs to the
     end; with a shear damage of 1.5, or a last energy of -5, it stops with an error naming
     the joint;
  4. kill -9 during the second checkpoint write (after the temporary file, before the rename;
     -fdem_checkpoint_kill 2): checkpoint.h5 is still the step-75 one, readable, and a restart
     from it ends bitwise equal to A.
  5. kill -9 at random moments: the scene with a checkpoint at every step (and 500 steps) is
     started and all its processes get SIGKILL at a random moment after its first checkpoint
     (within half the duration of a straight run), 6 times; each time the
     checkpoint.h5 left behind (if one was written yet) opens, and a restart from it runs to
     the end and ends bitwise equal to the straight run of that scene. The kill lands at any
     point of a step or of a checkpoint write (HDF5 file open, data, close, link, rename).
usage: restart.py MPIEXEC NP FDEM SCENE"""
import glob, os, random, signal, subprocess, sys, time
from scratch import scratch_dir

mpiexec, np, fdem, scene = sys.argv[1:5]
other = "2" if np == "1" else "1"
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
root = scratch_dir("fdem_restart_")
fail = []

def run(n, out, more, expect_ok=True, scene=scene):
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

def breaks(out): # (time, step, joint) of every joint broken, from fracture.csv
    return [(float(r.split(",")[0]), int(r.split(",")[1]), int(r.split(",")[2])) for r in open(os.path.join(root, out, "fracture.csv")).read().strip().split("\n")[1:] if r]

def rows(out):
    return [[float(x) for x in r.split(",")] for r in open(os.path.join(root, out, "balance.csv")).read().strip().split("\n")[1:]]

if os.path.exists(os.path.join(root, "A", "fracture.csv")):
    rc = rows("C")
    bc = breaks("C")
    ba = [b for b in breaks("A") if b[0] > rc[0][0]] # A's breaks after the restart's time
    check(f"restart on {other} ranks from a {np}-rank checkpoint: the same joints break in the same steps", sorted(b[1:] for b in bc) == sorted(b[1:] for b in ba), f"{len(bc)} breaks")
    t_first = min(b[0] for b in bc) if bc else float("inf")
    ra = {round(r[0], 12): r for r in rows("A")}
    worst_early = max([max(abs(x - y) for x, y in zip(ra[round(r[0], 12)], r)) / scale for r in rc if r[0] < t_first and round(r[0], 12) in ra] or [0.0])
    check(f"restart on {other} ranks from a {np}-rank checkpoint, rows before the first break (t < {t_first:.6g} s): largest difference / largest value", worst_early <= 1e-9, f"{worst_early:.3e} (bound 1e-9)")
    check(f"restart on {other} ranks from a {np}-rank checkpoint, last row: largest difference / largest value", worst <= 1e-4, f"{worst:.3e} (bound 1e-4)")
    # a checkpoint written before the joints' shear damage was kept (the dataset removed), and
    # one with a shear damage out of range; h5py runs under the system python (install-deps.sh)
    import shutil
    old_ckpt, bad_ckpt, bad2_ckpt = (os.path.join(root, f) for f in ("old.h5", "bad.h5", "bad2.h5"))
    for f in (old_ckpt, bad_ckpt, bad2_ckpt):
        shutil.copy(os.path.join(root, "A/checkpoint.1.h5"), f)
    edit = ("import h5py, sys\n"
            "with h5py.File(sys.argv[1], 'r+') as f: del f['joint_shear_damage']; del f['joint_last_energy']\n"
            "with h5py.File(sys.argv[2], 'r+') as f: d = f['joint_shear_damage']; v = d[()]; v[3 * 5 + 1] = 1.5; d[...] = v\n"
            "with h5py.File(sys.argv[3], 'r+') as f: d = f['joint_last_energy']; v = d[()]; v[6 * 5 + 2] = -5; d[...] = v\n")
    subprocess.run(["/usr/bin/python3", "-c", edit, old_ckpt, bad_ckpt, bad2_ckpt], check=True)
    r = run(np, "F", ["-restart", old_ckpt])
    rf = rows("F")[-1]
    check("restart from a checkpoint without joint_shear_damage and joint_last_energy: says so, runs to the end",
          "no joint_shear_damage" in r.stdout and "no joint_last_energy" in r.stdout and abs(rf[0] - a[0]) < 1e-12, f"t = {rf[0]}")
    r = run(np, "G", ["-restart", bad_ckpt], expect_ok=False)
    check("a shear damage of 1.5 in the checkpoint: an error naming joint 5", r.returncode != 0 and "joint 5 has a damage or shear damage outside [0, 1]" in r.stdout + r.stderr, f"exit status {r.returncode}")
    r = run(np, "H", ["-restart", bad2_ckpt], expect_ok=False)
    check("a last energy of -5 in the checkpoint: an error naming joint 5", r.returncode != 0 and "joint 5 has a damage" in r.stdout + r.stderr and "negative dissipated or last energy" in r.stdout + r.stderr, f"exit status {r.returncode}")
else:
    check(f"restart on {other} ranks from a {np}-rank checkpoint: largest difference / largest value", worst <= 1e-9, f"{worst:.3e} (bound 1e-9)")
r = run(np, "D", ["-fdem_checkpoint_kill", "2"], expect_ok=False)
check("killed during the second checkpoint write", r.returncode != 0, f"exit status {r.returncode}")
check("the temporary file is left, not renamed", len(glob.glob(os.path.join(root, "D/checkpoint.h5.tmp-*"))) == 1)
run(np, "E", ["-restart", os.path.join(root, "D/checkpoint.h5")])
check("restart from the checkpoint that survived the kill ends bitwise equal to the straight run", last("A") == last("E"), f"\n  {last('A')}\n  {last('E')}")

# 5. random kills
def descendants(pid):
    kids = {}
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                ppid = int(open(f"/proc/{d}/stat").read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
            kids.setdefault(ppid, []).append(int(d))
    out, todo = [], [pid]
    while todo:
        p = todo.pop()
        out.append(p)
        todo += kids.get(p, [])
    return out

text = open(scene).read()
if "checkpoint: {every: 0.0075, keep: 2}" not in text or "end: 0.015" not in text:
    sys.exit(1 if fail else 0)  # the random kills run on restart.yaml only
frequent = os.path.join(root, "frequent.yaml")
open(frequent, "w").write(text.replace("checkpoint: {every: 0.0075, keep: 2}", "checkpoint: {every: 1.0e-4, keep: 2}").replace("end: 0.015", "end: 0.05"))
t0 = time.time()
run(np, "F", [], scene=frequent)
straight = time.time() - t0
rng = random.Random()
seed = rng.randrange(1 << 30)
rng.seed(seed)
print(f"random kills: seed {seed}, straight run {straight:.2f} s", flush=True)
survived, tried, scale = 0, 0, 0.5
for k in range(12):  # up to 6 kills that hit a running run; a loaded machine may let some runs finish first
    if survived == 6:
        break
    tried += 1
    out = os.path.join(root, f"K{k}")
    cmd = [mpiexec, "--oversubscribe", "-n", np, fdem, frequent, "-fdem_output", out, "-fdem_progress", "0"]
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    start = time.time()
    while not os.path.exists(os.path.join(out, "checkpoint.h5")) and p.poll() is None and time.time() - start < 300:
        time.sleep(0.01)  # the first checkpoint is written: from here on every moment is a candidate
    time.sleep(rng.uniform(0, scale) * straight)
    delay = time.time() - start
    for q in descendants(p.pid)[::-1]:  # the ranks first, then mpiexec
        try:
            os.kill(q, signal.SIGKILL)
        except ProcessLookupError:
            pass
    p.wait()
    ck = os.path.join(out, "checkpoint.h5")
    if not os.path.exists(ck):
        print(f"kill {k} after {delay:.2f} s: no checkpoint written yet")
        continue
    if p.returncode == 0:
        print(f"kill {k} after {delay:.2f} s: the run had already finished (the next waits at most half as long)")
        scale *= 0.5
        continue
    survived += 1
    print(f"kill {k} after {delay:.2f} s: " + ("in a checkpoint write (its temporary file left)" if glob.glob(ck + ".tmp-*") else "between checkpoint writes"))
    r = run(np, f"R{k}", ["-restart", ck], expect_ok=False, scene=frequent)
    check(f"kill {k} after {delay:.2f} s: the last checkpoint opens and the restart runs to the end", r.returncode == 0, f"exit status {r.returncode}")
    if r.returncode == 0:
        check(f"kill {k}: the restart ends bitwise equal to the straight run", last("F") == last(f"R{k}"), f"\n  {last('F')}\n  {last(f'R{k}')}")
check("at least 3 kills hit a running run that had written a checkpoint", survived >= 3, f"{survived} of {tried} tried")
sys.exit(1 if fail else 0)
