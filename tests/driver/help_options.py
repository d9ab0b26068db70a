#!/usr/bin/env python3
"""Every fdem option the library and the driver read is listed by `fdem --help`.

The options are the strings "-fdem_..." and "-ts_fdem_..." in the sources (src/, apps/); the
help is what `fdem --help` prints (it checks the default scene, so an option read only for some
kinds of scene must be registered whatever the scene). Fails naming each option missing.

  help_options.py FDEM SOURCE_DIR
"""
import os, re, subprocess, sys

fdem, root = sys.argv[1], sys.argv[2]
names = set()
for top in ("src", "apps"):
    for d, _, files in os.walk(os.path.join(root, top)):
        for f in files:
            if f.endswith((".cpp", ".hpp", ".h", ".in")):
                names |= set(re.findall(r'"(-(?:ts_)?fdem_[a-z0-9_]+)', open(os.path.join(d, f), errors="replace").read()))
r = subprocess.run([fdem, "--help"], capture_output=True, text=True, timeout=300)
if r.returncode:
    sys.exit(f"fdem --help failed ({r.returncode}):\n{r.stdout[-2000:]}{r.stderr[-2000:]}")
listed = set(re.findall(r"(-(?:ts_)?fdem_[a-z0-9_]+)", r.stdout))
missing = sorted(names - listed)
print(f"{len(names)} options in the sources, {len(names & listed)} of them listed by fdem --help")
if len(names) < 20:
    sys.exit(f"only {len(names)} options found under {root}: the scan is broken")
if missing:
    sys.exit("not listed by fdem --help: " + " ".join(missing))
