#!/usr/bin/env python3
"""The cost of a fracturable body with joints inserted during the run, against the same body
split from the start and the same body not fracturable (bench/fracture/crater.yaml: a ball
cracks a block under it only).

Each round runs the three variants in turn, pinned to one core (`taskset -c CORE` where it
exists), all at the time step of the split block (the joints' limit, `-ts_dt`), without output
files. From each run's summary: the time in the TS's steps per step (TSStep: the body's cost
per step), the stepping CPU time per step (with the insertions' searches and rebuilds), the
joints at the end and the fragments. Prints the medians and the ratios to the block that is not
fracturable: the ratio of the medians, and the median and range of each round's ratio (the variants of a
round run one after the other, so a machine whose speed drifts moves both alike).

  insertion.py --fdem FDEM [--scene SCENE] [--rounds R] [--core C] [driver options...]
"""
import argparse, os, re, shutil, statistics, subprocess, sys, tempfile

root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("--fdem", required=True)
ap.add_argument("--scene", default=os.path.join(root, "bench", "fracture", "crater.yaml"))
ap.add_argument("--rounds", type=int, default=3)
ap.add_argument("--core", default="1")
args, more = ap.parse_known_args()

text = open(args.scene).read()
work = tempfile.mkdtemp(prefix="fdem_insertion_")
variants = {"not fracturable": re.sub(r",\s*fracture: \{[^}]*\}", "", text),
            "split from the start": re.sub(r",\s*insert_at: [0-9.e+-]+", "", text),
            "joints inserted": text}
files = {}
for k, (name, t) in enumerate(variants.items()):
    files[name] = os.path.join(work, f"v{k}.yaml")
    open(files[name], "w").write(t)
pin = ["taskset", "-c", args.core] if shutil.which("taskset") else []

def run(name, dt=None):
    cmd = pin + [args.fdem, files[name], "-fdem_output", "none", "-fdem_progress", "0"] + (["-ts_dt", repr(dt)] if dt else []) + more
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode:
        sys.exit(f"{' '.join(cmd)} failed:\n{r.stdout[-2000:]}{r.stderr[-2000:]}")
    o = r.stdout
    steps = int(re.search(r"in ([0-9]+) steps", o).group(1))
    res = {"steps": steps,
           "dt": float(re.search(r"time step ([0-9.e+-]+) s", o).group(1)),
           "tsstep": float(re.search(r"TSStep ([0-9.]+) s", o).group(1)) / steps,
           "cpu": float(re.search(r"stepping CPU time ([0-9.]+) s", o).group(1)) / steps,
           "joints": int(m.group(1)) if (m := re.search(r"([0-9]+) joints at the end", o)) else int(m2.group(1)) if (m2 := re.search(r"fracture: ([0-9]+) joints", o)) else 0,
           "fragments": int(m.group(1)) if (m := re.search(r"fragments: ([0-9]+)", o)) else 1,
           "insertions": int(m.group(1)) if (m := re.search(r"joints inserted ([0-9]+) times", o)) else 0,
           "rebuild": float(m.group(1)) if (m := re.search(r"the rebuilds took ([0-9.e+-]+) s", o)) else 0.0}
    return res

dt = run("split from the start")["dt"] # the joints' limit, for all three
print(f"time step {dt:.4g} s (the split block's); {args.rounds} rounds on core {args.core}", flush=True)
res = {n: [] for n in variants}
for r in range(args.rounds):
    for n in variants:
        x = run(n, dt)
        res[n].append(x)
        print(f"round {r + 1} {n:22s} {x['steps']} steps: TSStep {1e3 * x['tsstep']:.3f} ms/step, stepping CPU {1e3 * x['cpu']:.3f} ms/step, {x['joints']} joints at the end, {x['fragments']} fragments, {x['insertions']} insertions ({x['rebuild']:.2f} s of wall time in the searches and rebuilds)", flush=True)
base = statistics.median(x["tsstep"] for x in res["not fracturable"])
basec = statistics.median(x["cpu"] for x in res["not fracturable"])
print("\n| block | TSStep per step (median) | ratio | stepping CPU per step, with the rebuilds | ratio | the rounds' ratios: median (range) | joints at the end | fragments |")
print("|---|---|---|---|---|---|---|---|")
for n in variants:
    t = statistics.median(x["tsstep"] for x in res[n])
    c = statistics.median(x["cpu"] for x in res[n])
    ratios = [x["cpu"] / y["cpu"] for x, y in zip(res[n], res["not fracturable"])]
    print(f"| {n} | {1e3 * t:.3f} ms | {t / base:.2f} | {1e3 * c:.3f} ms | {c / basec:.2f} | {statistics.median(ratios):.2f} ({min(ratios):.2f}-{max(ratios):.2f}) | {res[n][-1]['joints']} | {res[n][-1]['fragments']} |")
shutil.rmtree(work)
