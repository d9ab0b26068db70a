#!/usr/bin/env python3
"""Work-precision charts from the CSV of bench_work_precision.

usage: plot_work_precision.py [CSV] [OUT_PREFIX]
  CSV         default doc/bench/work_precision.csv
  OUT_PREFIX  default doc/bench/work_precision  ->  _time.png, _evals.png

One line per scheme, log-log: error (max |x - x_ref| at T) against wall time
(best of the repeats) and against RHS (force) evaluations. fdem schemes solid,
PETSc's basicsymplectic / rk dashed. Points at the reference's accuracy
(ref_limited = 1) are drawn hollow and are not used for interpolation.
"""
import csv
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

src = sys.argv[1] if len(sys.argv) > 1 else "doc/bench/work_precision.csv"
prefix = sys.argv[2] if len(sys.argv) > 2 else "doc/bench/work_precision"

curves = OrderedDict()
meta = {}
with open(src) as f:
    for row in csv.DictReader(f):
        curves.setdefault(row["scheme"], []).append(row)
        meta = row
if not curves:
    sys.exit("no rows in " + src)

LABELS = {"bs1": "PETSc basicsymplectic 1", "bs2": "PETSc basicsymplectic 2", "bs3": "PETSc basicsymplectic 3",
          "bs4": "PETSc basicsymplectic 4", "rk4": "PETSc rk 4 (combined RHS)"}
markers = "os^vD<>phX*P8"


def plot(xkey, xlabel, out):
    fig, ax = plt.subplots(figsize=(8.5, 6.2))
    for k, (name, rows) in enumerate(curves.items()):
        petsc = rows[0]["family"] == "petsc"
        xs = [float(r[xkey]) for r in rows]
        ys = [float(r["err_max_x"]) for r in rows]
        lim = [r["ref_limited"] == "1" for r in rows]
        label = LABELS.get(name, "fdem " + name) + " (order %s)" % rows[0]["order"]
        line, = ax.loglog(xs, ys, ls="--" if petsc else "-", marker=markers[k % len(markers)], ms=5, label=label)
        hollow = [(x, y) for x, y, l in zip(xs, ys, lim) if l]
        if hollow:
            ax.loglog([p[0] for p in hollow], [p[1] for p in hollow], ls="none", marker=markers[k % len(markers)], ms=8,
                      mfc="white", mec=line.get_color())
    ax.set_xlabel(xlabel)
    ax.set_ylabel("error  max_i |x_i(T) - x_ref,i(T)|")
    ax.set_title("FPU-beta chain, N = %s particles, unequal masses, T = %s: work-precision" % (meta["N"], "%g" % float(meta["T"])))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, ncol=2)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print("wrote", out)


plot("wall_s", "wall time of TSSolve [s] (best of %s)" % meta["repeats"], prefix + "_time.png")
plot("rhs_evals", "RHS (force) evaluations, incl. gradient terms and start-up", prefix + "_evals.png")
