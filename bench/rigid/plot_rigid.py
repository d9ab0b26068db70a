#!/usr/bin/python3
"""Orientation error against cost for each rotation variant x scheme
(bench_rigid -mode error). usage: plot_rigid.py CSV PNG

Top row: error against force evaluations per body (RHS calls, gradients
included); bottom row: against wall time per body. One panel per rotation
variant (munjiza, nosquish, exact), one line per scheme; slopes 2 and 4 drawn
for reference."""
import csv
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

src = sys.argv[1] if len(sys.argv) > 1 else "doc/rigid/orientation_error_vs_cost.csv"
png = sys.argv[2] if len(sys.argv) > 2 else "doc/rigid/orientation_error_vs_cost.png"
data = OrderedDict()
with open(src) as f:
    for r in csv.DictReader(f):
        data.setdefault(r["rotation"], OrderedDict()).setdefault(r["scheme"], []).append(r)
rots = list(data)
fig, axes = plt.subplots(2, len(rots), figsize=(5 * len(rots), 9), sharey=True)
axes = np.atleast_2d(axes)
colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
for j, rot in enumerate(rots):
    for row, (key, label) in enumerate((("force_evals", "force evaluations per body"), ("wall_per_body_s", "wall time per body [s]"))):
        ax = axes[row, j]
        for k, (scheme, rows) in enumerate(data[rot].items()):
            x = np.array([float(r[key]) for r in rows])
            e = np.array([float(r["orientation_error"]) for r in rows])
            ax.loglog(x, np.maximum(e, 1e-17), "o-", color=colors[k % len(colors)], ms=4, lw=1.2, label=scheme)
        if row == 0:
            x0 = np.array([20.0, 2000.0])
            for p, ls in ((2, ":"), (4, "--")):
                ax.loglog(x0, 1e-1 * (x0 / x0[0]) ** (-p), "k" + ls, lw=0.8, label="slope -%d" % p)
        ax.set_xlabel(label)
        ax.grid(True, which="major", alpha=0.3)
        if j == 0:
            ax.set_ylabel("orientation error max |R - R_ref| at T = 2")
        ax.set_title("drift: %s" % rot)
    axes[0, j].legend(fontsize=8)
fig.suptitle("Rigid bodies under an orientation-dependent torque: orientation error vs cost (100 bodies, one process)")
fig.tight_layout()
fig.savefig(png, dpi=110)
print("wrote " + png)
