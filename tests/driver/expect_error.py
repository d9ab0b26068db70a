#!/usr/bin/env python3
"""Runs `fdem check BAD.yaml` under mpiexec and asserts the error: the exit
status is 1 on every rank (no crash, no MPI abort, no hang: 120 s limit), the
message `fdem: error: <expected>` is printed once, where <expected> is the
text after '# expect: ' at the end of the file (file:line:col and what).
usage: expect_error.py MPIEXEC NP FDEM FILE.yaml"""
import os, subprocess, sys

mpiexec, np, fdem, path = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4]
expect = [l[len("# expect: "):].rstrip("\n") for l in open(path) if l.startswith("# expect: ")]
assert len(expect) == 1, f"{path}: needs exactly one '# expect: ' line"
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
cmd = [mpiexec, "--oversubscribe", "-n", np, fdem, "check", os.path.basename(path), "-fdem_progress", "0"]
try:
    r = subprocess.run(cmd, cwd=os.path.dirname(os.path.abspath(path)), capture_output=True, text=True, timeout=120, env=env)
except subprocess.TimeoutExpired:
    sys.exit(f"FAIL: {path}: fdem hung (no exit within 120 s)")
out = r.stdout + r.stderr
print(out)
ok = True
if r.returncode != 1:
    print(f"FAIL: exit status {r.returncode}, expected 1"); ok = False
for bad in ["MPI_ABORT", "Segmentation", "signal", "Traceback", "PETSC ERROR"]:
    if bad in out:
        print(f"FAIL: the output contains '{bad}'"); ok = False
want = "fdem: error: " + expect[0]
n = out.count(want)
if n != 1:
    print(f"FAIL: expected once (rank 0 only), found {n} times:\n  {want}"); ok = False
sys.exit(0 if ok else 1)
