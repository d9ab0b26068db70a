#!/bin/bash
# The rigid pile benchmark (doc/performance.md): fdem's `fdem` driver on a
# settled pile of irregular pebbles against a base revision (body-steps per
# CPU second, same answer body by body), on 1 and 2 ranks, and LAMMPS
# rigid/small clumps of 4 spheres settled in a box, side by side; a chart of
# body-steps/s/core against pile size.
#   bench/pile/run.sh [BASE_REV]        (default 5613d90, before the box search)
# Environment: SIZES (fdem piles, default 1000), LAMMPS_SIZES (default
# "1000 8000"), ROUNDS (default 3), OUT_DIR (default /tmp/fdem-pile).
# The first run settles each fdem pile (1.5 s simulated; ~12 min for 1000
# pebbles on one core) and keeps it in OUT_DIR/N/settle.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
HERE=$ROOT/bench/pile
BASE=${1:-5613d90}
SIZES=${SIZES:-1000} LAMMPS_SIZES=${LAMMPS_SIZES:-"1000 8000"} ROUNDS=${ROUNDS:-3} OUT=${OUT_DIR:-/tmp/fdem-pile}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mkdir -p "$OUT"
cmake -S "$ROOT" -B "$ROOT/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$ROOT/build" -j2 --target fdem_driver >/dev/null
BDIR=/tmp/fdem-rev-$(git -C "$ROOT" rev-parse --short "$BASE")
[ -d "$BDIR" ] || git -C "$ROOT" worktree add -q --detach "$BDIR" "$BASE"
cmake -S "$BDIR" -B "$BDIR/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BDIR/build" -j2 --target fdem_driver >/dev/null
NEW=$ROOT/build/apps/fdem/fdem OLD=$BDIR/build/apps/fdem/fdem
sizes=$(echo $SIZES | tr ' ' ',')
echo "== fdem: work tree against $BASE, 1 rank"
python3 "$HERE/pile.py" --base-fdem "$OLD" --new-fdem "$NEW" --sizes "$sizes" --s1 10 --s2 60 --rounds "$ROUNDS" --out "$OUT"
echo "== fdem: 1 and 2 ranks"
python3 "$HERE/pile.py" --base-fdem "$OLD" --new-fdem "$NEW" --sizes "$sizes" --s2 60 --rounds "$ROUNDS" --out "$OUT" --scaling
echo "== LAMMPS rigid/small, 4-sphere clumps, 1 rank"
if command -v lmp >/dev/null; then
  echo "n,lammps" > "$OUT/lammps.csv"
  for N in $LAMMPS_SIZES; do
    layers=$(python3 -c "import math; print(max(2, round($N ** (1 / 3))))")
    side=$(python3 -c "import math; print(math.ceil(math.sqrt($N / $layers)) + 1)")
    d=$OUT/lammps_$N; mkdir -p "$d"; cp "$HERE/clump.mol" "$d/"
    (cd "$d" && lmp -in "$HERE/in.clumps" -var n "$side" -var layers "$layers" -var settle 12000 -var steps 2000 -log none > lmp.log 2>&1)
    awk -v steps=2000 '/rigid bodies with/ {nb = $1} /^Loop time/ {t = $4} END {printf "LAMMPS: %d clumps, %d steps in %.3f s: %.4g body-steps/s/core\n", nb, steps, t, nb * steps / t}' "$d/lmp.log"
    awk -v steps=2000 '/rigid bodies with/ {nb = $1} /^Loop time/ {t = $4} END {printf "%d,%.6g\n", nb, nb * steps / t}' "$d/lmp.log" >> "$OUT/lammps.csv"
  done
else
  echo "lmp not found (apt-get install lammps): LAMMPS side skipped"
fi
python3 "$HERE/chart.py" "$OUT"
