#!/bin/bash
# Runs an example with bad options and checks that it stops cleanly with the
# expected message: a non-zero exit status, the message (an extended regular
# expression) in its output, no signal or crash (SIGFPE, SIGSEGV, abort), no
# MPI_Abort (every rank ends through PetscFinalize), and no hang (CTest's TIMEOUT).
#   expect_error.sh NP 'REGEX' EXE [OPTIONS...]       (MPIEXEC: the launcher, default mpiexec)
set -uo pipefail
np=$1 regex=$2 exe=$3
shift 3
log=$(mktemp)
trap 'rm -f "$log"' EXIT
${MPIEXEC:-mpiexec} -n "$np" "$exe" "$@" >"$log" 2>&1
status=$?
cat "$log"
fail() { echo "expect_error.sh: FAIL: $*"; exit 1; }
[ "$status" -ne 0 ] || fail "exit status 0 for bad options"
[ "$status" -lt 128 ] || fail "exit status $status (killed by a signal)"
grep -Eq "$regex" "$log" || fail "no message matching: $regex"
! grep -Eq "MPI_ABORT|Caught signal|Floating point exception|Segmentation|SIGSEGV|SIGFPE|Aborted|core dumped" "$log" || fail "a crash or an MPI_Abort, not a clean error exit"
echo "expect_error.sh: ok (exit status $status, message found)"
