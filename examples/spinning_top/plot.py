#!/usr/bin/python3
"""Plots the spinning top CSVs (run.sh) like the book's Fig 5.7-5.9:
omega_x and omega_y (body frame) against the exact -sin 100t, cos 100t,
one panel per step h; writes OUT/spinning_top.png."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np


def load(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "doc/rigid"
    hs = ["0.0005", "0.001", "0.005"]
    fig, axes = plt.subplots(len(hs), 1, figsize=(12, 9), sharex=True)
    for ax, h in zip(axes, hs):
        tt = np.linspace(0, 0.25, 2001)
        ax.plot(tt, np.cos(100 * tt), "k-", lw=1.0, label="exact $\\omega_y = \\cos 100t$")
        ax.plot(tt, -np.sin(100 * tt), "k:", lw=1.0, label="exact $\\omega_x = -\\sin 100t$")
        for rot, col in (("munjiza", "tab:red"), ("nosquish", "tab:blue")):
            d = load("%s/spinning_top_%s_h%s.csv" % (out, rot, h))
            err = max(np.abs(d["omega_x"] - d["exact_x"]).max(), np.abs(d["omega_y"] - d["exact_y"]).max())
            ax.plot(d["t"], d["omega_y"], "-", color=col, lw=0.9, label="$\\omega_y$ %s (max err %.3g)" % (rot, err))
            ax.plot(d["t"], d["omega_x"], "--", color=col, lw=0.7, label="$\\omega_x$ %s" % rot)
        d = load("%s/spinning_top_exact_h%s.csv" % (out, h))
        err = max(np.abs(d["omega_x"] - d["exact_x"]).max(), np.abs(d["omega_y"] - d["exact_y"]).max())
        ax.plot(d["t"], d["omega_y"], "o", color="tab:green", ms=3, markevery=max(1, len(d["t"]) // 50), label="$\\omega_y$ exact drift (max err %.1e)" % err)
        ax.set_title("h = %s s (cd)" % h, fontsize=10)
        ax.set_ylabel("$\\omega$ [1/s], body frame")
        ax.set_ylim(-1.2, 1.2)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    axes[-1].set_xlabel("t [s]")
    fig.suptitle("Spinning axisymmetric element (Munjiza Fig 5.6-5.9): I = diag(1,1,2), $\\omega_0$ = (0,1,100)")
    fig.tight_layout()
    fig.savefig("%s/spinning_top.png" % out, dpi=110)
    print("wrote %s/spinning_top.png" % out)


if __name__ == "__main__":
    main()
