#!/usr/bin/env python3
"""Impact-speed sweep of the fragmentation example (doc/fragmentation.md).

Runs examples/scenes/fragmentation.yaml once per impact speed (the driver has no
option for a body's velocity, so each run gets a copy of the scene with the
ball's velocity replaced), reads each run's fragments.csv and balance.csv, and
writes a chart of the fragment count and the largest fragment's mass fraction
against the speed (SVG, no plotting library needed) and a Markdown table.

  python3 examples/fragmentation/sweep.py [--fdem build/apps/fdem/fdem] [--np 2]
      [--speeds 0.5,1,2,4,8] [--out out/fragmentation] [--svg doc/fragmentation.svg]
      [--table out/fragmentation/table.md] [driver options...]

Run it from the repository's root. Unknown arguments go to the driver.
"""
import argparse
import csv
import math
import os
import re
import subprocess
import sys
import time

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.dirname(os.path.dirname(here))
scene_file = os.path.join(root, "examples", "scenes", "fragmentation.yaml")


def scene_at_speed(text, speed, mesh_dir):
    """The scene's text with the ball's velocity set to -speed along z and the
    mesh path made absolute (the copy lives in another folder)."""
    new, n = re.subn(r"velocity: \[0, 0, -?[0-9.eE+-]+\]", f"velocity: [0, 0, {-speed!r}]", text)
    if n != 1:
        sys.exit("sweep.py: the scene does not have exactly one 'velocity: [0, 0, v]'")
    new, n = re.subn(r"mesh: (\S+?\.msh)", lambda m: "mesh: " + os.path.join(mesh_dir, m.group(1)), new)
    if n != 1:
        sys.exit("sweep.py: the scene does not have exactly one mesh file")
    return new


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def run(args, speed, extra):
    out = os.path.join(args.out, f"v{speed:g}")
    os.makedirs(out, exist_ok=True)
    scene = os.path.join(out, "scene.yaml")
    with open(scene_file) as f:
        text = scene_at_speed(f.read(), speed, os.path.dirname(scene_file))
    with open(scene, "w") as f:
        f.write(text)
    cmd = [args.mpiexec, "--oversubscribe", "-n", str(args.np), args.fdem, scene, "-fdem_output", out,
           "-fdem_progress", "0"] + extra
    print("$ " + " ".join(cmd), flush=True)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    t0 = time.time()
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    wall = time.time() - t0
    with open(os.path.join(out, "log.txt"), "w") as f:
        f.write(r.stdout + r.stderr)
    if r.returncode != 0:
        sys.exit(f"sweep.py: the run at {speed} m/s failed ({r.returncode}):\n{r.stdout[-2000:]}{r.stderr[-2000:]}")
    frags = read_csv(os.path.join(out, "fragments.csv"))
    bal = [{k: float(v) for k, v in row.items()} for row in read_csv(os.path.join(out, "balance.csv"))]
    masses = sorted((float(x["mass"]) for x in frags), reverse=True)
    total = sum(masses)
    ke0 = bal[0]["kinetic"]
    last = bal[-1]
    # pieces of one or two tetrahedra: a ball of 1296 cannot resolve smaller ones
    tiny = masses[-1] if masses else 0
    res = {
        "speed": speed, "fragments": len(frags), "mass": total, "largest": masses[0] / total,
        "second": masses[1] / total if len(masses) > 1 else 0.0, "masses": masses,
        "ke0": ke0, "ke_end": last["kinetic"], "strain_end": last["strain"], "fracture": last["fracture"],
        "residual": max(abs(r["dissipated"]) for r in bal), "wall": wall, "tiny": tiny,
        # the largest fragment's speed: how it rebounds (positive: upwards)
        "vz_largest": max(frags, key=lambda x: float(x["mass"]))["vz"],
    }
    print(f"  {len(frags)} fragments, largest {res['largest']:.3f} of the mass, fracture {res['fracture']:.4g} J "
          f"of {ke0:.4g} J, |dissipated| <= {res['residual']:.3g} J, {wall:.0f} s", flush=True)
    return res


def svg_chart(results, path):
    """Two panels: fragment count (log scale) and largest fragment's mass fraction against speed
    (log scale), plus the cumulative mass distribution of the fragments per speed."""
    W, H = 960, 330
    panels = [(60, "fragments"), (380, "largest fragment / ball mass"), (700, "mass fraction in fragments &lt;= m")]
    pw, ph, top = 230, 220, 40
    speeds = [r["speed"] for r in results]
    lo, hi = math.log10(min(speeds)) - 0.1, math.log10(max(speeds)) + 0.1
    colours = ["#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#e6ab02", "#a6761d", "#666666"]
    s = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
         f'<rect width="{W}" height="{H}" fill="white"/>',
         f'<text x="{W / 2}" y="18" text-anchor="middle" font-size="14">Rock ball (R = 5 cm) on a rigid plate: '
         f'fragments against impact speed</text>']

    def xs(v):
        return (math.log10(v) - lo) / (hi - lo) * pw

    cmax = max(r["fragments"] for r in results)
    clog = math.log10(max(10, cmax)) + 0.1
    for k, (x0, title) in enumerate(panels):
        s.append(f'<g transform="translate({x0},{top})">')
        s.append(f'<rect width="{pw}" height="{ph}" fill="none" stroke="black"/>')
        s.append(f'<text x="{pw / 2}" y="-6" text-anchor="middle">{title}</text>')
        if k < 2:
            for v in speeds:
                s.append(f'<line x1="{xs(v):.1f}" y1="{ph}" x2="{xs(v):.1f}" y2="{ph + 4}" stroke="black"/>'
                         f'<text x="{xs(v):.1f}" y="{ph + 16}" text-anchor="middle">{v:g}</text>')
            s.append(f'<text x="{pw / 2}" y="{ph + 32}" text-anchor="middle">impact speed (m/s, log scale)</text>')
        if k == 0:
            def ys(c):
                return ph - math.log10(c) / clog * ph
            for c in (1, 2, 5, 10, 20, 50, 100, 200, 500, 1000):
                if math.log10(c) <= clog:
                    s.append(f'<line x1="-4" y1="{ys(c):.1f}" x2="0" y2="{ys(c):.1f}" stroke="black"/>'
                             f'<text x="-7" y="{ys(c) + 4:.1f}" text-anchor="end">{c}</text>')
            pts = [(xs(r["speed"]), ys(r["fragments"])) for r in results]
        elif k == 1:
            def ys(f):
                return ph - f * ph
            for f in (0, 0.25, 0.5, 0.75, 1):
                s.append(f'<line x1="-4" y1="{ys(f):.1f}" x2="0" y2="{ys(f):.1f}" stroke="black"/>'
                         f'<text x="-7" y="{ys(f) + 4:.1f}" text-anchor="end">{f:g}</text>')
            pts = [(xs(r["speed"]), ys(r["largest"])) for r in results]
        if k < 2:
            s.append('<polyline fill="none" stroke="#333" points="' +
                     " ".join(f"{x:.1f},{y:.1f}" for x, y in pts) + '"/>')
            for x, y in pts:
                s.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="4" fill="#d95f02"/>')
        else:
            # x: fragment mass / ball mass, log scale from 1e-4 to 1; y: cumulative mass fraction
            mlo, mhi = -4.0, 0.0

            def xm(f):
                return (max(math.log10(f), mlo) - mlo) / (mhi - mlo) * pw

            def ym(f):
                return ph - f * ph
            for e in range(-4, 1):
                s.append(f'<line x1="{xm(10 ** e):.1f}" y1="{ph}" x2="{xm(10 ** e):.1f}" y2="{ph + 4}" stroke="black"/>'
                         f'<text x="{xm(10 ** e):.1f}" y="{ph + 16}" text-anchor="middle">1e{e}</text>')
            s.append(f'<text x="{pw / 2}" y="{ph + 32}" text-anchor="middle">fragment mass m / ball mass</text>')
            for f in (0, 0.5, 1):
                s.append(f'<line x1="-4" y1="{ym(f):.1f}" x2="0" y2="{ym(f):.1f}" stroke="black"/>'
                         f'<text x="-7" y="{ym(f) + 4:.1f}" text-anchor="end">{f:g}</text>')
            for i, r in enumerate(results):
                ms = sorted(r["masses"])
                tot = sum(ms)
                acc, pts = 0.0, [(xm(ms[0] / tot), ym(0))]
                for m in ms:
                    pts.append((xm(m / tot), ym(acc / tot)))
                    acc += m
                    pts.append((xm(m / tot), ym(acc / tot)))
                c = colours[i % len(colours)]
                s.append(f'<polyline fill="none" stroke="{c}" stroke-width="1.5" points="' +
                         " ".join(f"{x:.1f},{y:.1f}" for x, y in pts) + '"/>')
                s.append(f'<text x="8" y="{16 + 14 * i}" fill="{c}">{r["speed"]:g} m/s</text>')
        s.append('</g>')
    s.append('</svg>')
    with open(path, "w") as f:
        f.write("\n".join(s) + "\n")


def table(results):
    lines = ["| impact speed (m/s) | kinetic energy (J) | fragments | largest / ball | second / ball | "
             "fracture (J) | fracture / kinetic | max \\|dissipated\\| / kinetic | largest's v_z (m/s) | wall (s) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        lines.append(f"| {r['speed']:g} | {r['ke0']:.4g} | {r['fragments']} | {r['largest']:.3f} | {r['second']:.3f} | "
                     f"{r['fracture']:.3g} | {r['fracture'] / r['ke0']:.3f} | {r['residual'] / r['ke0']:.1e} | "
                     f"{float(r['vz_largest']):+.2f} | {r['wall']:.0f} |")
    return "\n".join(lines)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--fdem", default=os.path.join(root, "build", "apps", "fdem", "fdem"))
    p.add_argument("--mpiexec", default="mpiexec")
    p.add_argument("--np", type=int, default=2)
    p.add_argument("--speeds", default="0.5,1,2,4,8")
    p.add_argument("--out", default=os.path.join("out", "fragmentation"))
    p.add_argument("--svg", default=os.path.join(root, "doc", "fragmentation.svg"))
    p.add_argument("--table", default=None, help="Markdown table file (default OUT/table.md)")
    args, extra = p.parse_known_args()
    speeds = [float(v) for v in args.speeds.split(",")]
    results = [run(args, v, extra) for v in speeds]
    svg_chart(results, args.svg)
    t = table(results)
    with open(args.table or os.path.join(args.out, "table.md"), "w") as f:
        f.write(t + "\n")
    print(t)
    print(f"chart: {args.svg}")


if __name__ == "__main__":
    main()
