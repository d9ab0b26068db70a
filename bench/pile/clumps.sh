#!/bin/bash
# The clump race (doc/performance.md, "Clumps against LAMMPS"): the same bed of 4-sphere clumps
# in fdem (clumps: rigid bodies whose contact shape is spheres, FDEMRigidAddClump) and in LAMMPS
# (fix rigid/small, in.clumps): the clumps on one lattice, turned at random, dropped into a box
# of a floor and four walls, settled for SETTLE steps, then timed over STEPS steps on 1 rank, at
# one time step (1.7e-4 s) and one contact law (Hooke, kn 2e5 N/m, gamma_n 50 /s, friction 0.6).
# fdem's figure is the CPU time of the stepping of a restart from the settled checkpoint (the
# driver's done line); LAMMPS's is the Loop time of its timed run.
# DT runs both at another step (the same in both: the per-body-step ratio is then also the
# per-simulated-second one), e.g. DT=1.7e-3 SETTLE=1200 STEPS=800, fdem's automatic step here.
#   bench/pile/clumps.sh            Environment: SIZES (default "1000 8000"), SETTLE (12000),
#                                   STEPS (2000), DT (1.7e-4), OUT_DIR (/tmp/fdem-clumps)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
HERE=$ROOT/bench/pile
SIZES=${SIZES:-"1000 8000"} SETTLE=${SETTLE:-12000} STEPS=${STEPS:-2000} DT=${DT:-1.7e-4} OUT=${OUT_DIR:-/tmp/fdem-clumps}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
command -v lmp >/dev/null || { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq lammps >/dev/null; }
cmake -S "$ROOT" -B "$ROOT/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$ROOT/build" -j2 --target fdem_driver >/dev/null
FDEM=$ROOT/build/apps/fdem/fdem
mkdir -p "$OUT"
echo "n,fdem_clumps,lammps_clumps,ratio" > "$OUT/clumps.csv"
for N in $SIZES; do
  layers=$(python3 -c "print(max(2, round($N ** (1 / 3))))")
  side=$(python3 -c "import math; print(math.ceil(math.sqrt($N / $layers)) + 1)")
  d=$OUT/$N; mkdir -p "$d"
  end=$(python3 -c "print(repr($SETTLE * $DT))")
  python3 "$HERE/make_clumps.py" "$side" "$layers" "$d/race.yaml" --end "$end" --dt "$DT"
  [ -f "$d/settle/checkpoint.h5" ] || "$FDEM" "$d/race.yaml" -fdem_output "$d/settle" -fdem_progress 0 > "$d/settle.log" 2>&1
  tmax=$(python3 -c "print(repr(($SETTLE + $STEPS) * $DT))")
  "$FDEM" "$d/race.yaml" -restart "$d/settle/checkpoint.h5" -ts_max_time "$tmax" -fdem_output "$d/timed" -fdem_progress 0 > "$d/timed.log" 2>&1
  fdem=$(sed -n 's/.*stepping CPU time .* on the busiest rank: \([0-9.e+]*\) body-steps\/s\/core.*/\1/p' "$d/timed.log")
  grep -E "^contact" "$d/timed.log" | sed "s/^/fdem, $N clumps: /"
  cp "$HERE/clump.mol" "$d/"
  (cd "$d" && lmp -in "$HERE/in.clumps" -var n "$side" -var layers "$layers" -var settle "$SETTLE" -var steps "$STEPS" -var dt "$DT" -log none > lmp.log 2>&1)
  lammps=$(awk -v steps="$STEPS" '/rigid bodies with/ {nb = $1} /^Loop time/ {t = $4} END {printf "%.6g", nb * steps / t}' "$d/lmp.log")
  python3 - "$N" "$fdem" "$lammps" "$OUT/clumps.csv" <<'PY'
import sys
n, f, l, csv = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
print(f"{n} clumps: fdem {f:.3g} body-steps per CPU second, LAMMPS {l:.3g} body-steps per second: LAMMPS / fdem = {l / f:.2f}")
open(csv, "a").write(f"{n},{f:.6g},{l:.6g},{l / f:.4g}\n")
PY
done
