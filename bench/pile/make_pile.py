#!/usr/bin/env python3
"""Writes the scene of the rigid pile benchmark (bench/pile/run.sh): N irregular
pebbles (size 0.08 m, ~20 skin tetrahedra each) packed above the floor of a
fixed box whose footprint grows with N (about N^(1/3) pebbles per side), as
examples/scenes/pebbles_in_a_box.yaml.

  make_pile.py N OUT.yaml [--end SECONDS] [--resolution R]
"""
import argparse
import math

p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
p.add_argument("n", type=int, help="number of pebbles (>= 1)")
p.add_argument("out", help="scene file to write")
p.add_argument("--end", type=float, default=1.0, help="simulated seconds (default 1.0)")
p.add_argument("--resolution", type=float, default=0.2, help="cell size of the walls' meshes (m, default 0.2)")
a = p.parse_args()
if a.n < 1:
    p.error("N must be >= 1")
s = 0.18                                  # lattice spacing of the packed pebbles (m; size 0.08 is a semi-axis)
side = max(2, math.ceil(a.n ** (1 / 3) * 1.15))
L = side * s                              # inner footprint L x L
layers = math.ceil(a.n / (side * side))
H = 0.2 + 3.0 * layers * s               # packing region height: room for the random packing
wall_h = H + 0.1
t = 0.1                                   # wall thickness
res = a.resolution
with open(a.out, "w") as f:
    f.write(f"""# Rigid pile benchmark (bench/pile): {a.n} pebbles in a {L:.2f} x {L:.2f} m box.
title: rigid pile of {a.n} pebbles
gravity: [0, 0, -9.81]
time: {{end: {a.end}, dt: 4.0e-4, scheme: cd}}
materials:
  rock: {{density: 2600}}
contact: {{penalty: 3.0e6, friction: 0.6, normal_damping: 1.0e5, tangential_viscosity: 1.0e5, buffer: 0.012}}
bodies:
  - {{name: floor, model: rigid, fixed: true, shape: {{box: [{L + 2 * t:.4f}, {L + 2 * t:.4f}, {t}]}}, resolution: {res}, position: [{L / 2:.4f}, {L / 2:.4f}, {-t / 2}]}}
  - {{name: wall_x0, model: rigid, fixed: true, shape: {{box: [{t}, {L:.4f}, {wall_h:.4f}]}}, resolution: {res}, position: [{-t / 2}, {L / 2:.4f}, {wall_h / 2:.4f}]}}
  - {{name: wall_x1, model: rigid, fixed: true, shape: {{box: [{t}, {L:.4f}, {wall_h:.4f}]}}, resolution: {res}, position: [{L + t / 2:.4f}, {L / 2:.4f}, {wall_h / 2:.4f}]}}
  - {{name: wall_y0, model: rigid, fixed: true, shape: {{box: [{L + 2 * t:.4f}, {t}, {wall_h:.4f}]}}, resolution: {res}, position: [{L / 2:.4f}, {-t / 2}, {wall_h / 2:.4f}]}}
  - {{name: wall_y1, model: rigid, fixed: true, shape: {{box: [{L + 2 * t:.4f}, {t}, {wall_h:.4f}]}}, resolution: {res}, position: [{L / 2:.4f}, {L + t / 2:.4f}, {wall_h / 2:.4f}]}}
  - {{name: pebble, model: rigid, material: rock, shape: {{pebble: {{size: 0.08, seed: 5}}}}, position: [{L / 2:.4f}, {L / 2:.4f}, 0.06]}}
generate:
  - {{pack: {{count: {a.n - 1}, like: pebble, region: {{lo: [0.05, 0.05, 0.15], hi: [{L - 0.05:.4f}, {L - 0.05:.4f}, {H:.4f}]}}, scale: [0.85, 1.15], seed: 5}}}}
output: {{dir: out_pile, every: {a.end}, balance: {a.end / 10}}}
checkpoint: {{every: {a.end}, keep: 1}}
""")
