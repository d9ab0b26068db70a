#!/usr/bin/env python3
"""Writes the ball mesh of the fragmentation example as a Gmsh 2.2 ASCII file.

A cube of N x N x N cells, each cut into 6 tetrahedra around its main diagonal
(the same cut in every cell, so the mesh is conforming), is mapped onto the
ball of radius R by the smooth cube-to-sphere map

    x' = x sqrt(1 - y^2/2 - z^2/2 + y^2 z^2/3)   (and cyclically),

applied to coordinates scaled to [-1, 1]: the cube's faces land on the sphere,
its centre stays the centre, and no element is turned inside out. Unlike the
driver's `sphere` shape (a star of needles around one centre node), every
element here has a size near 2R/N, so cracks can run in any direction.

  make_ball.py [N] [R] [OUT]     (defaults: 6, 0.05, fragmentation_ball.msh)
"""
import itertools
import math
import sys

n = int(sys.argv[1]) if len(sys.argv) > 1 else 6
R = float(sys.argv[2]) if len(sys.argv) > 2 else 0.05
out = sys.argv[3] if len(sys.argv) > 3 else "fragmentation_ball.msh"


def node(i, j, k):
    return 1 + i + (n + 1) * (j + (n + 1) * k)


nodes = []
for k in range(n + 1):
    for j in range(n + 1):
        for i in range(n + 1):
            x, y, z = (2.0 * i / n - 1, 2.0 * j / n - 1, 2.0 * k / n - 1)
            nodes.append((R * x * math.sqrt(1 - y * y / 2 - z * z / 2 + y * y * z * z / 3),
                          R * y * math.sqrt(1 - z * z / 2 - x * x / 2 + z * z * x * x / 3),
                          R * z * math.sqrt(1 - x * x / 2 - y * y / 2 + x * x * y * y / 3)))
tets = []
unit = [(1, 0, 0), (0, 1, 0), (0, 0, 1)]
for k in range(n):
    for j in range(n):
        for i in range(n):
            for perm in itertools.permutations(range(3)):
                p = [i, j, k]
                t = [node(*p)]
                for a in perm:
                    p = [p[0] + unit[a][0], p[1] + unit[a][1], p[2] + unit[a][2]]
                    t.append(node(*p))
                tets.append(t)
with open(out, "w") as f:
    f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n")
    f.write("$PhysicalNames\n1\n3 1 \"ball\"\n$EndPhysicalNames\n")
    f.write(f"$Nodes\n{len(nodes)}\n")
    for q, (x, y, z) in enumerate(nodes):
        f.write(f"{q + 1} {x:.17g} {y:.17g} {z:.17g}\n")
    f.write(f"$EndNodes\n$Elements\n{len(tets)}\n")
    for e, t in enumerate(tets):
        f.write(f"{e + 1} 4 2 1 1 {t[0]} {t[1]} {t[2]} {t[3]}\n")
    f.write("$EndElements\n")
print(f"{out}: {len(nodes)} nodes, {len(tets)} tetrahedra, radius {R}")
