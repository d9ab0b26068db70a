#!/bin/bash
# Cost of the contact pipeline and of the deformable step at two revisions, as
# ratios of instructions per step (valgrind's callgrind: exact and insensitive
# to the load of a shared machine). Instructions per step are the difference
# between a run of S2 and one of S1 steps, divided by S2 - S1, so that the
# set-up cancels; the set-up is reported separately.
#   bench/compare/compare_revisions.sh BASE_REV [NEW_REV]   (NEW_REV default: the work tree)
# Builds each revision in /tmp/fdem-rev-<sha>/build (git worktree, Release).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BASE=${1:?usage: compare_revisions.sh BASE_REV [NEW_REV]}
NEW=${2:-}
S1=${S1:-5} S2=${S2:-25}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
command -v valgrind >/dev/null || { echo "compare_revisions.sh: valgrind is needed (apt-get install valgrind)" >&2; exit 2; }
tree() { # REV -> a built source tree
  local rev=$1 dir
  if [ -z "$rev" ]; then dir=$ROOT; else
    dir=/tmp/fdem-rev-$(git -C "$ROOT" rev-parse --short "$rev")
    [ -d "$dir" ] || git -C "$ROOT" worktree add -q --detach "$dir" "$rev"
  fi
  cmake -S "$dir" -B "$dir/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$dir/build" -j2 --target bench_contact bench_deformable >/dev/null
  echo "$dir"
}
irefs() { valgrind --tool=callgrind --callgrind-out-file=/dev/null "$@" 2>&1 >/dev/null | awk '/I +refs:/ { gsub(",", "", $NF); print $NF }'; }
measure() { # DIR -> "contact_step contact_setup deformable_step deformable_setup"
  local d=$1 c1 c2 f1 f2
  c1=$(irefs "$d/build/bench/contact/bench_contact" -n_list 1000 -steps $S1 -fdem_rigid_rotation munjiza)
  c2=$(irefs "$d/build/bench/contact/bench_contact" -n_list 1000 -steps $S2 -fdem_rigid_rotation munjiza)
  f1=$(irefs "$d/build/bench/deformable/bench_deformable" -n 16 -steps $S1 -repeats 1)
  f2=$(irefs "$d/build/bench/deformable/bench_deformable" -n 16 -steps $S2 -repeats 1)
  awk -v c1=$c1 -v c2=$c2 -v f1=$f1 -v f2=$f2 -v n=$((S2 - S1)) -v s=$S1 'BEGIN { cs = (c2 - c1) / n; fs = (f2 - f1) / n; print cs, c1 - s * cs, fs, f1 - s * fs }'
}
B=$(tree "$BASE"); N=$(tree "$NEW")
read -r bc bcs bf bfs < <(measure "$B")
read -r nc ncs nf nfs < <(measure "$N")
awk -v b="$BASE" -v n="${NEW:-work tree}" -v bc=$bc -v nc=$nc -v bcs=$bcs -v ncs=$ncs -v bf=$bf -v nf=$nf -v bfs=$bfs -v nfs=$nfs 'BEGIN {
  printf "instructions (callgrind)        %16s %16s %9s\n", "base " b, "new " n, "new/base"
  printf "contact pipeline, per step      %16.4g %16.4g %9.4f\n", bc, nc, nc / bc
  printf "contact pipeline, set-up        %16.4g %16.4g %9.4f\n", bcs, ncs, ncs / bcs
  printf "deformable cd step, per step    %16.4g %16.4g %9.4f\n", bf, nf, nf / bf
  printf "deformable set-up               %16.4g %16.4g %9.4f\n", bfs, nfs, nfs / bfs }'
