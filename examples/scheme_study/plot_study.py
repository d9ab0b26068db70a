#!/usr/bin/env python3
"""Plots of the scheme study (Munjiza section 5.3, Figs 5.18-5.21) from the CSV
files written by scheme_study into DIR (default doc/study).

usage: plot_study.py [DIR]
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ORDER = ["cd", "pv", "t112", "t16", "d112", "pc3", "pc4", "pc5", "chin", "omf30", "omf32", "fr", "pefrl"]
LABEL = {"cd": "CD", "pv": "PV", "t112": "T-1/12", "t16": "T-1/6", "d112": "D-1/12", "pc3": "PC-3", "pc4": "PC-4",
         "pc5": "PC-5", "chin": "CHIN", "omf30": "OMF30", "omf32": "OMF32", "fr": "FR", "pefrl": "PEFRL"}
# one colour + marker + line style per scheme (13 need more than the default cycle)
STYLE = {
    "cd": ("black", "o", "-"), "pv": ("grey", "s", "--"),
    "t112": ("tab:blue", "^", "-"), "t16": ("tab:cyan", "v", "-"), "d112": ("navy", "x", ":"),
    "pc3": ("tab:red", "<", "-"), "pc4": ("tab:pink", ">", "-"), "pc5": ("darkred", "D", "-"),
    "chin": ("tab:green", "P", "-"), "omf30": ("olive", "*", "-"), "omf32": ("tab:purple", "h", "-"),
    "fr": ("tab:orange", "d", "-"), "pefrl": ("tab:brown", "X", "-"),
}


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def num(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return math.nan


def by_scheme(rows):
    out = {}
    for r in rows:
        out.setdefault(r["scheme"], []).append(r)
    return [(s, out[s]) for s in ORDER if s in out] + [(s, v) for s, v in out.items() if s not in ORDER]


def style(s):
    c, m, ls = STYLE.get(s, ("k", ".", "-"))
    return dict(color=c, marker=m, linestyle=ls, markersize=4, linewidth=1.2, label=LABEL.get(s, s))


def amplification(d):
    rows = read(os.path.join(d, "amplification.csv"))
    table = {r["scheme"]: r for r in read(os.path.join(d, "table52.csv"))}
    fig, axes = plt.subplots(1, 2, figsize=(15, 6.2), sharey=True)
    for ax, col, title in ((axes[0], "factor", "(5.121), maxima refined to the sampled amplitude"),
                           (axes[1], "factor_raw", "(5.121) literal: raw sample maxima")):
        for s, rs in by_scheme(rows):
            K = [num(r["K"]) for r in rs]
            F = [min(num(r[col]), 1.7) if num(r[col]) == num(r[col]) else math.nan for r in rs]
            st = style(s)
            st["markersize"] = 2.5
            ax.plot(K, F, **st)
        ax.axhline(1.0, color="k", linewidth=0.6)
        ax.set_xlim(0, 6)
        ax.set_ylim(0.8, 1.6)
        ax.set_xlabel(r"$K = \omega h$")
        ax.set_title(title, fontsize=10)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("amplification factor (40 periods; unstable/Inf runs drawn at the top)")
    axes[0].legend(ncol=2, fontsize=8, loc="upper left")
    cells = ["%-7s %.4f %.4f" % (LABEL.get(s, s), num(r["kcrit_5121"]), num(r["kcrit_exact"])) for s, r in table.items()]
    half = (len(cells) + 1) // 2
    lines = ["%-22s   %s" % (cells[i], cells[i + half] if i + half < len(cells) else "") for i in range(half)]
    txt = "K_crit: (5.121) from TS runs, exact (spectral radius)\n" + "\n".join(lines)
    axes[1].text(0.98, 0.02, txt, transform=axes[1].transAxes, va="bottom", ha="right", multialignment="left", family="monospace", fontsize=7.5,
                 bbox=dict(facecolor="white", alpha=0.9, edgecolor="0.7"))
    fig.suptitle("Fig 5.18: amplification factor vs K, oscillator x'' = -x, x(0)=0, v(0)=1 (fdem TS types)")
    fig.tight_layout()
    fig.savefig(os.path.join(d, "amplification.png"), dpi=110)
    plt.close(fig)


def period_error(d):
    rows = read(os.path.join(d, "period_error.csv"))
    fig, axes = plt.subplots(1, 2, figsize=(15, 6.2))
    for s, rs in by_scheme(rows):
        K = [num(r["K"]) for r in rs]
        E = [num(r["period_error_pct"]) for r in rs]
        X = [num(r["period_error_exact_pct"]) for r in rs]
        st = style(s)
        # gaps for unstable runs (inf) and for runs where a parasitic mode has taken over (|error| > 50 %)
        axes[0].plot(K, [e if abs(e) < 50 else math.nan for e in E], **st)
        axes[1].plot(K, [abs(e) if e == e and abs(e) != math.inf else math.nan for e in E], **style(s))
        axes[1].plot(K, [abs(x) for x in X], color=st["color"], linewidth=0.6, linestyle=":")
    axes[0].set_ylim(-3, 3)
    axes[0].set_ylabel("period error after 1000 periods [%]  (5.122-5.123)")
    axes[0].set_title("as in the book (linear axis, -3..3 %)", fontsize=10)
    axes[1].set_yscale("log")
    axes[1].set_ylim(1e-10, 1e2)
    axes[1].set_ylabel("|period error| [%]; dotted: principal eigenvalue of the step map")
    axes[1].set_title("log axis: measured (markers) vs exact (dotted)", fontsize=10)
    for ax in axes:
        ax.axhline(0.0, color="k", linewidth=0.6)
        ax.set_xlim(0, 1.4)
        ax.set_xlabel(r"$K = \omega h$")
        ax.grid(alpha=0.3, which="both")
    axes[0].legend(ncol=2, fontsize=8)
    fig.suptitle("Fig 5.19: period error vs K (zero crossings over 1000 periods)")
    fig.tight_layout()
    fig.savefig(os.path.join(d, "period_error.png"), dpi=110)
    plt.close(fig)


def amplitude_error(d):
    rows = read(os.path.join(d, "amplitude_error.csv"))
    fig, ax = plt.subplots(figsize=(9, 6.5))
    for s, rs in by_scheme(rows):
        K = [num(r["K"]) for r in rs]
        E = [num(r["amplitude_error_pct"]) for r in rs]
        ax.plot(K, [e if e == e and e != math.inf else math.nan for e in E], **style(s))
    ax.set_yscale("log")
    ax.set_ylim(1e-8, 1e1 * 10)
    ax.set_xlim(0, 1.4)
    ax.set_xlabel(r"$K = \omega h$")
    ax.set_ylabel("amplitude error after 1000 periods [%]  (5.124-5.125)")
    ax.set_title("Fig 5.20: phase-corrected RMS amplitude error vs K (unstable runs omitted)", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(ncol=3, fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(os.path.join(d, "amplitude_error.png"), dpi=110)
    plt.close(fig)


def cpu_vs_error(d):
    rows = read(os.path.join(d, "cpu_vs_error.csv"))
    fig, axes = plt.subplots(1, 2, figsize=(15, 6.2))
    for s, rs in by_scheme(rows):
        # in K order (each curve is parametrised by the step); unstable or meaningless (> 100 %) points left out
        pts = [(num(r["amplitude_error_pct"]), num(r["seconds"]) * 1e3, num(r["rhs_evals"])) for r in rs]
        pts = [p for p in pts if p[0] == p[0] and 0 < p[0] <= 100]
        axes[0].plot([p[0] for p in pts], [p[1] for p in pts], **style(s))
        axes[1].plot([p[0] for p in pts], [p[2] for p in pts], **style(s))
    for ax in axes:
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlim(1e-8, 1e2)
        ax.set_xlabel("amplitude error after 1000 periods [%]")
        ax.grid(alpha=0.3, which="both")
    axes[0].set_ylabel("wall time of TSSolve over 1000 periods [ms]")
    axes[0].set_title("Fig 5.21: cost vs accuracy (PetscTime, best of 3, 1 DOF)", fontsize=10)
    axes[1].set_ylabel("momentum-RHS evaluations over 1000 periods")
    axes[1].set_title("RHS evaluations (FDEMTSGetForceEvaluations, incl. FD tangents/gradients)", fontsize=10)
    axes[0].legend(ncol=2, fontsize=8, loc="upper right")
    fig.tight_layout()
    fig.savefig(os.path.join(d, "cpu_vs_error.png"), dpi=110)
    plt.close(fig)


def main():
    d = sys.argv[1] if len(sys.argv) > 1 else "doc/study"
    amplification(d)
    period_error(d)
    amplitude_error(d)
    cpu_vs_error(d)
    print("wrote", ", ".join(os.path.join(d, n + ".png") for n in ("amplification", "period_error", "amplitude_error", "cpu_vs_error")))


if __name__ == "__main__":
    main()
