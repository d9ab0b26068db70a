#!/usr/bin/env python3
"""Writes the fdem side of the clump race (bench/pile/clumps.sh): the scene of
bench/pile/in.clumps, clump for clump. (SIDE - 1)^2 x LAYERS clumps of four
spheres (radius 0.04 m at the corners of a tetrahedron, centres 0.035 m from
its centre: clump.mol) on a simple cubic lattice of spacing 0.16 m, each
turned at random (fixed seed), dropped into a box of side SIDE x 0.16 m (a
fixed floor at z = 0 and four fixed walls), density 2600 kg/m^3, Hooke
contacts kn = 2e5 N/m, gamma_n = 50 /s, kt = 2/7 kn, gamma_t = gamma_n / 2
(LAMMPS's defaults for NULL), friction 0.6, dt = 1.7e-4 s as in LAMMPS. The
run ends at END (s) with a checkpoint there (a timed restart continues it).

  make_clumps.py SIDE LAYERS OUT.yaml --end END"""
import argparse
import math
import random

p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
p.add_argument("side", type=int)
p.add_argument("layers", type=int)
p.add_argument("out")
p.add_argument("--end", type=float, default=2.04)
p.add_argument("--dt", type=float, default=1.7e-4, help="time step (s); the race's is 1.7e-4, LAMMPS's rule of thumb")
a = p.parse_args()
s = 0.16
L = a.side * s
H = a.layers * s * 1.2 + 0.2
c = 0.0202
rng = random.Random(4912)
lines = [
    f"# {(a.side - 1) ** 2 * a.layers} clumps of 4 spheres in a box (bench/pile/make_clumps.py {a.side} {a.layers})",
    "title: clump race",
    "gravity: [0, 0, -9.81]",
    f"time: {{end: {a.end!r}, dt: {a.dt!r}, scheme: cd}}",
    "materials:",
    "  grain: {density: 2600, contact_law: hooke, kn: 2.0e5, gamma_n: 50, friction: 0.6}",
    "bodies:",
    f"  - {{name: floor, model: rigid, fixed: true, material: grain, shape: {{box: [{L + 0.4!r}, {L + 0.4!r}, 0.1]}}, position: [{L / 2!r}, {L / 2!r}, -0.05]}}",
    f"  - {{name: wall_x0, model: rigid, fixed: true, material: grain, shape: {{box: [0.1, {L!r}, {H!r}]}}, position: [-0.05, {L / 2!r}, {H / 2!r}]}}",
    f"  - {{name: wall_x1, model: rigid, fixed: true, material: grain, shape: {{box: [0.1, {L!r}, {H!r}]}}, position: [{L + 0.05!r}, {L / 2!r}, {H / 2!r}]}}",
    f"  - {{name: wall_y0, model: rigid, fixed: true, material: grain, shape: {{box: [{L + 0.2!r}, 0.1, {H!r}]}}, position: [{L / 2!r}, -0.05, {H / 2!r}]}}",
    f"  - {{name: wall_y1, model: rigid, fixed: true, material: grain, shape: {{box: [{L + 0.2!r}, 0.1, {H!r}]}}, position: [{L / 2!r}, {L + 0.05!r}, {H / 2!r}]}}",
]
balls = f"[[{c}, {c}, {c}, 0.04], [{-c}, {-c}, {c}, 0.04], [{-c}, {c}, {-c}, 0.04], [{c}, {-c}, {-c}, 0.04]]"
n = 0
for k in range(1, a.layers + 1):
    for j in range(1, a.side):
        for i in range(1, a.side):
            ax = [rng.gauss(0, 1) for _ in range(3)]
            deg = 360 * rng.random()
            lines.append(f"  - {{name: c{n}, model: rigid, material: grain, shape: {{spheres: {balls}}}, position: [{i * s!r}, {j * s!r}, {k * s!r}], "
                         f"rotation: {{axis: [{ax[0]:.6f}, {ax[1]:.6f}, {ax[2]:.6f}], degrees: {deg:.4f}}}}}")
            n += 1
lines += [f"output: {{dir: out, every: {a.end!r}, balance: {a.end / 10!r}}}", f"checkpoint: {{every: {a.end!r}, keep: 1}}"]
open(a.out, "w").write("\n".join(lines) + "\n")
