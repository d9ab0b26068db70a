#!/usr/bin/env python3
"""Chart of bench/pile: body-steps per second per core against pile size, fdem
(base revision and work tree), LAMMPS rigid/small and fdem's clumps of the same
spheres (bench/pile/clumps.sh, clumps.csv), log-log, as an SVG
(no plotting library needed).   chart.py OUT_DIR  -> OUT_DIR/pile.svg"""
import csv
import math
import os
import sys

out = sys.argv[1] if len(sys.argv) > 1 else "/tmp/fdem-pile"
series = {}  # name -> [(n, rate)]


def read(path, cols):
    if not os.path.exists(path):
        return
    for row in csv.DictReader(open(path)):
        for col, name in cols:
            if row.get(col):
                series.setdefault(name, []).append((float(row["n"]), float(row[col])))


read(os.path.join(out, "pile.csv"), [("base", "fdem, base revision"), ("new", "fdem, work tree")])
read(os.path.join(out, "lammps.csv"), [("lammps", "LAMMPS rigid/small, 4-sphere clumps")])
read(os.path.join(out, "clumps.csv"), [("fdem_clumps", "fdem, 4-sphere clumps (clumps.sh)")])
if not series:
    sys.exit(f"chart.py: no pile.csv or lammps.csv in {out}")
pts = [p for s in series.values() for p in s]
x0, x1 = math.floor(math.log10(min(p[0] for p in pts))) - 0.3, math.ceil(math.log10(max(p[0] for p in pts))) + 0.3
y0, y1 = math.floor(math.log10(min(p[1] for p in pts))), math.ceil(math.log10(max(p[1] for p in pts)))
W, H, L, B = 640, 420, 80, 60  # size, left and bottom margins
X = lambda v: L + (math.log10(v) - x0) / (x1 - x0) * (W - L - 20)
Y = lambda v: H - B - (math.log10(v) - y0) / (y1 - y0) * (H - B - 20)
colors = ["#888888", "#1f77b4", "#d62728", "#2ca02c"]
s = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
     f'<rect width="{W}" height="{H}" fill="white"/>']
for e in range(math.ceil(x0), math.floor(x1) + 1):
    s.append(f'<line x1="{X(10**e):.1f}" y1="20" x2="{X(10**e):.1f}" y2="{H - B}" stroke="#ddd"/><text x="{X(10**e):.1f}" y="{H - B + 16}" text-anchor="middle">1e{e}</text>')
for e in range(y0, y1 + 1):
    s.append(f'<line x1="{L}" y1="{Y(10**e):.1f}" x2="{W - 20}" y2="{Y(10**e):.1f}" stroke="#ddd"/><text x="{L - 6}" y="{Y(10**e) + 4:.1f}" text-anchor="end">1e{e}</text>')
s.append(f'<text x="{(L + W) / 2}" y="{H - 20}" text-anchor="middle">bodies in the pile</text>')
s.append(f'<text x="16" y="{(H - B) / 2}" text-anchor="middle" transform="rotate(-90 16 {(H - B) / 2})">body-steps per second per core</text>')
for k, (name, p) in enumerate(sorted(series.items())):
    p.sort()
    c = colors[k % len(colors)]
    s.append('<polyline fill="none" stroke="%s" stroke-width="2" points="%s"/>' % (c, " ".join(f"{X(n):.1f},{Y(r):.1f}" for n, r in p)))
    for n, r in p:
        s.append(f'<circle cx="{X(n):.1f}" cy="{Y(r):.1f}" r="4" fill="{c}"/>')
    s.append(f'<rect x="{L + 12}" y="{28 + 18 * k}" width="12" height="12" fill="{c}"/><text x="{L + 30}" y="{38 + 18 * k}">{name}</text>')
s.append("</svg>")
open(os.path.join(out, "pile.svg"), "w").write("\n".join(s) + "\n")
print("chart:", os.path.join(out, "pile.svg"))
