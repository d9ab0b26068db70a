#!/usr/bin/python3
"""Chart of a pebbles_in_a_box run from its energy.csv (in the -fdem_output folder).

usage: plot_pebbles.py HISTORY.csv OUT.png [TITLE]

Left: mean and highest pebble centre height against time. Right: kinetic
energy and the potential energy released (log scale) against time.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    src, out = sys.argv[1], sys.argv[2]
    title = sys.argv[3] if len(sys.argv) > 3 else "pebbles in a box"
    cols = {}
    with open(src) as f:
        for row in csv.DictReader(f):
            for k, v in row.items():
                cols.setdefault(k, []).append(float(v))
    t = cols["t"]
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2))
    a.plot(t, cols["mean_height"], label="mean pebble centre height")
    a.plot(t, cols["max_height"], label="highest pebble centre")
    a.set_xlabel("t (s)")
    a.set_ylabel("height above the floor (m)")
    a.legend()
    a.grid(alpha=0.3)
    ke = [max(x, 1e-12) for x in cols["kinetic_energy"]]
    b.semilogy(t, ke, label="kinetic energy")
    b.semilogy(t, [max(x, 1e-12) for x in cols["potential_energy_released"]], label="potential energy released")
    top = max(max(ke), max(cols["potential_energy_released"]))
    b.set_ylim(1e-7 * top, 3 * top)
    b.set_xlabel("t (s)")
    b.set_ylabel("energy (J)")
    b.legend()
    b.grid(alpha=0.3, which="both")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print("wrote " + out)


if __name__ == "__main__":
    main()
