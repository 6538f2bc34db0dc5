#!/bin/sh
# MpiCommunicator::abort on one of 3 processes, the others waiting for it in a collective call: the
# whole job must stop (not hang) with the status given (3) and the message as one line on stderr.
# Usage: test_mpi_abort.sh MPIEXEC TEST_PROGRAM
mpiexec=$1
program=$2
out=$("$mpiexec" --oversubscribe -np 3 "$program" --sluice-test-abort 2>&1)
status=$?
printf '%s\n' "$out"
echo "test_mpi_abort: exit status $status (expected 3)"
[ "$status" -eq 3 ] || exit 1
printf '%s\n' "$out" | grep -qx 'sluice: error: stopped on purpose by process 2' || {
  echo "test_mpi_abort: the line 'sluice: error: stopped on purpose by process 2' is missing"
  exit 1
}
