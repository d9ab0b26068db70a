# Sourced by race.sh and chute.sh: the interleaved rounds of one race. Each round runs, on 1 and
# then 2 ranks, fdem, LAMMPS and (when installed) LIGGGHTS on the same start, and prints
# particle-steps per second per core of each (wall clock of the stepping: fdem's "stepping" time,
# LAMMPS's and LIGGGHTS's "Loop time"), the ratios, and one observable of each (OBS_NAME).
# The caller sets: n (spheres), steps, rounds, lig (the LIGGGHTS command, or empty), OBS_NAME,
# and defines
#   fdem_run NP          runs fdem; prints its stepping time, then its observable
#   lmp_run NP           runs LAMMPS; prints its output
#   lig_run NP           runs LIGGGHTS; prints its output
# The codes' observable is the 4th column of the first row of their thermo output.
thermo_col4() { awk '/^ *Step/{getline; getline; print $4}'; }
loop_time() { awk '/^Loop time/{print $4}'; }
run_rounds() {
  r=1
  while [ $r -le "$rounds" ]; do
    for np in 1 2; do
      set -- $(fdem_run $np)
      ft=$1; fobs=$2
      l=$(lmp_run $np 2>&1)
      lt=$(echo "$l" | loop_time); lobs=$(echo "$l" | thermo_col4)
      gt=0; gobs=0
      if [ -n "$lig" ]; then
        g=$(lig_run $np 2>&1)
        gt=$(echo "$g" | loop_time); gobs=$(echo "$g" | thermo_col4)
      fi
      echo "$n $steps $np $ft $lt $gt $fobs $lobs $gobs" | awk -v r=$r -v obs="$OBS_NAME" '{
        n=$1; s=$2; np=$3; fps=n*s/$4/np; lps=n*s/$5/np; gps=($6 > 0) ? n*s/$6/np : 0; rg=(gps > 0) ? fps/gps : 0;
        printf "round %d, %d rank(s), %d spheres: particle-steps/s/core fdem %.3g, LAMMPS %.3g, LIGGGHTS %.3g; fdem/LAMMPS %.2f, fdem/LIGGGHTS %.2f; %s fdem %s, LAMMPS %s, LIGGGHTS %s\n", r, np, n, fps, lps, gps, fps/lps, rg, obs, $7, $8, $9 }'
    done
    r=$((r + 1))
  done
}
