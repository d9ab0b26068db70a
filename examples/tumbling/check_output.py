#!/usr/bin/python3
"""Checks the HDF5 + XDMF output of FDEMRigidWriteHDF5 (examples/tumbling).

usage: check_output.py BASE NSTEPS NBODIES

  - BASE.xmf parses as XML: Xdmf/Domain/Grid temporal collection with NSTEPS
    uniform grids, increasing times, Triangle topology, XYZ geometry;
  - every DataItem names a dataset of BASE.h5 whose shape equals its
    Dimensions and whose type matches NumberType/Precision;
  - cells index existing vertices, body_id covers NBODIES bodies;
  - every body is rigid: its pairwise vertex distances are the same in the
    first and the last step (1e-12 relative), and its vertex velocities are
    a rigid field, (v_i - v_j).(x_i - x_j) = 0 (1e-12 relative);
  - the files agree: the group attribute "time" equals the XDMF Time.
Exit status 0 when all hold.
"""
import os
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def main():
    base, nsteps, nbodies = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    tree = ET.parse(base + ".xmf")  # raises on malformed XML
    root = tree.getroot()
    if root.tag != "Xdmf":
        fail("root element is %s, not Xdmf" % root.tag)
    coll = root.find("Domain/Grid")
    if coll is None or coll.get("GridType") != "Collection" or coll.get("CollectionType") != "Temporal":
        fail("no temporal collection under Xdmf/Domain")
    grids = coll.findall("Grid")
    if len(grids) != nsteps:
        fail("%d grids in the XDMF, expected %d" % (len(grids), nsteps))
    h5 = h5py.File(base + ".h5", "r")
    if len(h5.keys()) != nsteps:
        fail("%d groups in the HDF5 file, expected %d" % (len(h5.keys()), nsteps))
    xdir = os.path.dirname(os.path.abspath(base + ".xmf"))
    times, first, last = [], None, None
    for g in grids:
        name = g.get("Name")
        t = float(g.find("Time").get("Value"))
        times.append(t)
        topo, geom = g.find("Topology"), g.find("Geometry")
        if topo.get("TopologyType") != "Triangle" or geom.get("GeometryType") != "XYZ":
            fail("%s: topology %s, geometry %s" % (name, topo.get("TopologyType"), geom.get("GeometryType")))
        data = {}
        for item in g.iter("DataItem"):
            fname, path = item.text.strip().split(":", 1)
            if not os.path.exists(os.path.join(xdir, fname)):
                fail("%s: %s does not exist next to the .xmf" % (name, fname))
            if path not in h5:
                fail("%s: dataset %s missing" % (name, path))
            ds = h5[path]
            dims = tuple(int(d) for d in item.get("Dimensions").split())
            if ds.shape != dims:
                fail("%s: %s has shape %s, XDMF says %s" % (name, path, ds.shape, dims))
            kind = {"Int": "i", "Float": "f"}[item.get("NumberType")]
            if ds.dtype.kind != kind or ds.dtype.itemsize != int(item.get("Precision")):
                fail("%s: %s is %s, XDMF says %s %s" % (name, path, ds.dtype, item.get("NumberType"), item.get("Precision")))
            data[path.rsplit("/", 1)[1]] = ds[...]
        if int(topo.get("NumberOfElements")) != data["cells"].shape[0]:
            fail("%s: NumberOfElements %s != %d cells" % (name, topo.get("NumberOfElements"), data["cells"].shape[0]))
        X, V, C, B = data["vertices"], data["velocity"], data["cells"], data["body_id"][:, 0]
        if not np.all(np.isfinite(X)) or not np.all(np.isfinite(V)):
            fail("%s: non-finite coordinates or velocities" % name)
        if C.min() < 0 or C.max() >= X.shape[0]:
            fail("%s: cells index vertices outside [0, %d)" % (name, X.shape[0]))
        ids = np.unique(B)
        if len(ids) != nbodies or ids.min() != 0 or ids.max() != nbodies - 1:
            fail("%s: body ids %s, expected 0..%d" % (name, ids, nbodies - 1))
        ht = float(h5[name].attrs["time"][()])
        if abs(ht - t) > 1e-14 * max(1.0, abs(t)):
            fail("%s: HDF5 time %r, XDMF time %r" % (name, ht, t))
        # per body: its vertices (contiguous, in skin order)
        bodies = {}
        for b in ids:
            vs = np.unique(C[B == b])
            bodies[b] = (X[vs], V[vs])
            x, v = X[vs], V[vs]
            dx = x[:, None, :] - x[None, :, :]
            dv = v[:, None, :] - v[None, :, :]
            rig = np.abs(np.sum(dx * dv, axis=2)).max()
            scale = np.abs(dx).max() * np.abs(dv).max() + 1e-300
            if rig > 1e-12 * scale:
                fail("%s: body %d velocity is not rigid: |dv.dx| %.3e vs %.3e" % (name, b, rig, scale))
        if first is None:
            first = bodies
        last = bodies
    if any(b <= a for a, b in zip(times, times[1:])):
        fail("times are not increasing: %s" % times)
    worst = 0.0
    for b in first:
        d0 = np.linalg.norm(first[b][0][:, None, :] - first[b][0][None, :, :], axis=2)
        d1 = np.linalg.norm(last[b][0][:, None, :] - last[b][0][None, :, :], axis=2)
        worst = max(worst, np.abs(d1 - d0).max() / d0.max())
    if worst > 1e-12:
        fail("bodies deform between the first and last step: relative distance change %.3e" % worst)
    moved = max(np.abs(last[b][0].mean(axis=0) - first[b][0].mean(axis=0)).max() for b in first)
    if nsteps > 1 and moved == 0:
        fail("no body moved")
    print("ok: %s.xmf well-formed, %d steps (t = %g .. %g), %d bodies, %d vertices / %d triangles in the last step; "
          "rigidity: max relative distance change %.2e" % (base, nsteps, times[0], times[-1], nbodies, X.shape[0], C.shape[0], worst))


if __name__ == "__main__":
    main()
