#!/bin/sh
# The Python module under mpirun (mpi_module.py): the command line's run on two processes, then the
# module's. Arguments: MPIEXEC SLUICE WORKDIR.
set -eu
mpiexec=$1 sluice=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
"$mpiexec" --oversubscribe -np 2 "$sluice" run dam_break -q --threads 1 -o "$work/cli" --set domain.dx=0.2 \
  --set time.end=0.2 --set output.interval=0.1
exec "$mpiexec" --oversubscribe -np 2 /usr/bin/python3 "$(dirname "$0")/mpi_module.py" "$work/cli" "$work/py"
