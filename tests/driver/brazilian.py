#!/usr/bin/env python3
"""Brazilian test of a fracturable disc (tests/driver/brazilian_disc.yaml, doc/fracture_validation.md).
usage: brazilian.py MPIEXEC NP FDEM SCENE [--plot DOCDIR] [--out DIR] [-- fdem options]
Runs the scene, then from DIR/balance.csv and DIR/mesh.h5:
  - the load P = (dW/dt) / (2 V) on the platens, W the work of the moved bodies (external_work), V
    each platen's closing speed; the peak gives the tensile strength 2 P / (pi D t), required to be
    f_t within 15%;
  - quasi-static loading: kinetic energy (less the platens' own, constant) below 1% of the work done
    at every row up to the peak or the first frame with a broken joint, whichever comes first (the crack then runs dynamically and
    releases part of the stored energy as kinetic energy: that is reported, not bounded);
  - the first broken joints (cells of damage 1 in the first frame that has any): their centres
    lie within 0.3 R of the loaded diameter (|x|) and 0.7 R of the centre along it (|z|), i.e.
    away from the platens.
--plot DOCDIR writes DOCDIR/brazilian_load.png (load against the platens' closing) and
DOCDIR/brazilian_cracks.png (damaged cells over the disc's outline)."""
import glob, math, os, sys

try:
    import numpy as np, h5py
except ImportError:  # a python3 without them (pyenv): the system's has them (scripts/install-deps.sh)
    if sys.executable != "/usr/bin/python3" and os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    raise
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from platens import PlatenLoad, RunScene  # noqa: E402

# the scene's figures (brazilian_disc.yaml)
R, T, V, FT, GAP = 0.05, 0.02, 0.1, 1.0e6, 5e-5

opts, out = RunScene("fdem_brazilian_")
rows, t, W, tm, P = PlatenLoad(out, V)  # P: the mean load over each balance interval
ke = np.array([q["kinetic"] for q in rows])
closing = 2 * V * tm - 2 * GAP                 # platens' approach beyond first touch
ip = int(np.argmax(P))
sigma = 2 * P[ip] / (math.pi * 2 * R * T)
ratio = sigma / FT
failures = []
print(f"peak load {P[ip]:.1f} N at t = {tm[ip]:.4g} s (closing {closing[ip] * 1e3:.4g} mm): 2P/(pi D t) = {sigma / 1e6:.4g} MPa = {ratio:.3f} f_t")
if abs(ratio - 1) > 0.15: failures.append(f"2P/(pi D t) = {ratio:.3f} f_t, not within 15% of f_t")

# crack pattern from the per-cell damage
frames = []
with h5py.File(out + "/mesh.h5", "r") as f:
    for g in sorted(k for k in f.keys() if k.startswith("step_")):
        G = f[g]
        X = np.array(G["vertices"]).reshape(-1, 3)
        C = np.array(G["cells"]).reshape(-1, 4).astype(int)
        D = np.array(G["damage"]).reshape(-1)
        frames.append((float(G.attrs["time"]), X[C].mean(axis=1), D))
first = next((fr for fr in frames if (fr[2] >= 1).any()), None)
if first is None:
    failures.append("no joint broke")
else:
    tf, cen, D = first
    c = cen[D >= 1]
    print(f"first broken joints in the frame at t = {tf:.4g} s: {len(c)} cells, |x| <= {abs(c[:, 0]).max() / R:.3f} R, |z| <= {abs(c[:, 2]).max() / R:.3f} R")
    if abs(c[:, 0]).max() > 0.3 * R: failures.append("a first broken joint lies farther than 0.3 R from the loaded diameter")
    if abs(c[:, 2]).max() > 0.7 * R: failures.append("a first broken joint lies within 0.3 R of a platen")
    upto = (t <= min(tf, t[ip + 1]) + 1e-12) & (W > 1e-3 * W[ip + 1])
    ke_ratio = max((ke[upto] - ke[0]) / W[upto])  # less the platens' constant kinetic energy
    at_peak = (ke[ip + 1] - ke[0]) / W[ip + 1]
    print(f"kinetic / work: at most {ke_ratio:.2e} up to the first broken joints, {at_peak:.2e} at the end of the peak interval")
    if not ke_ratio < 0.01: failures.append(f"kinetic energy reached {ke_ratio:.3g} of the work before the first joint broke")
    tl, cl, Dl = frames[-1]
    print(f"at the end (t = {tl:.4g} s): {int((Dl >= 1).sum())} of {len(Dl)} cells have a broken joint point, {int((Dl > 0).sum())} are damaged")

if "--plot" in opts:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    d = opts["--plot"]
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(closing * 1e3, P / 1e3, "-", lw=1)
    ax.axhline(math.pi * 2 * R * T * FT / 2 / 1e3, color="k", ls="--", lw=0.8, label="P for 2P/(pi D t) = f_t")
    ax.plot([closing[ip] * 1e3], [P[ip] / 1e3], "o", color="C3", label=f"peak: {ratio:.3f} f_t")
    ax.set_xlabel("platens' approach after contact (mm)")
    ax.set_ylabel("load P (kN)")
    ax.set_title("Brazilian disc: load against displacement")
    ax.legend()
    fig.tight_layout()
    fig.savefig(d + "/brazilian_load.png", dpi=90)
    fig, axs = plt.subplots(1, 2, figsize=(9, 4.2), layout="constrained")
    th = np.linspace(0, 2 * math.pi, 200)
    for ax, fr, name in zip(axs, [first, frames[-1]], ["first broken", "end of run"]):
        tf, cen, D = fr
        ax.plot(R * np.cos(th), R * np.sin(th), "k-", lw=0.6)
        m = D > 0
        sc = ax.scatter(cen[m, 0], cen[m, 2], c=D[m], s=8, cmap="viridis_r", vmin=0, vmax=1)
        b = D >= 1
        ax.scatter(cen[b, 0], cen[b, 2], s=14, facecolors="none", edgecolors="C3", lw=0.8)
        ax.set_aspect("equal")
        ax.set_title(f"{name}, t = {tf * 1e3:.1f} ms")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("z (m, loaded diameter)")
    fig.colorbar(sc, ax=axs, shrink=0.8, label="cell damage (red ring: a broken joint point)")
    fig.savefig(d + "/brazilian_cracks.png", dpi=90)
    print(f"wrote {d}/brazilian_load.png, {d}/brazilian_cracks.png")

if failures:
    sys.exit("FAIL: " + "; ".join(failures))
print("OK")
