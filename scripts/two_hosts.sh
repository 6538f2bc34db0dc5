#!/usr/bin/env bash
# A run on two "hosts" on this machine: two Linux network namespaces joined by a virtual Ethernet
# pair (10.77.0.1 and 10.77.0.2), with Open MPI starting one process in each over TCP, as it does on
# a cluster — its remote-shell launcher replaced by `ip netns exec` — and the result compared with one
# process. Needs root (ip netns) and a release build; removes the namespaces when done.
#
#   bash scripts/two_hosts.sh [sluice run options...]    (default: the dam break at dx = 0.05 m to 0.1 s)
set -euo pipefail
cd "$(dirname "$0")/.."
sluice=$PWD/${SLUICE:-build/release/sluice}
[ -x "$sluice" ] || { echo "two_hosts: $sluice not built; run make build" >&2; exit 1; }
[ "$(id -u)" -eq 0 ] || { echo "two_hosts: needs root (ip netns)" >&2; exit 1; }
options=("$@")
[ ${#options[@]} -gt 0 ] || options=(--set domain.dx=0.05 --set time.end=0.1)
remove_hosts() {
  ip netns del sluice_host_a 2>/dev/null || true
  ip netns del sluice_host_b 2>/dev/null || true
}
remove_hosts  # left over from an interrupted run
work=$(mktemp -d)
trap 'remove_hosts; rm -rf "$work"' EXIT

ip netns add sluice_host_a
ip netns add sluice_host_b
ip link add sluice_veth_a type veth peer name sluice_veth_b
ip link set sluice_veth_a netns sluice_host_a
ip link set sluice_veth_b netns sluice_host_b
ip netns exec sluice_host_a ip addr add 10.77.0.1/24 dev sluice_veth_a
ip netns exec sluice_host_b ip addr add 10.77.0.2/24 dev sluice_veth_b
for h in a b; do
  ip netns exec sluice_host_$h ip link set sluice_veth_$h up
  ip netns exec sluice_host_$h ip link set lo up
done

# Open MPI starts its daemon on a remote host with "<agent> <host> <command>": here the agent enters
# that host's namespace instead of logging in to it.
cat > "$work/netns-rsh" <<'AGENT'
#!/bin/sh
host=$1; shift
case "$host" in
  10.77.0.1) ns=sluice_host_a ;;
  10.77.0.2) ns=sluice_host_b ;;
  *) echo "netns-rsh: unknown host $host" >&2; exit 1 ;;
esac
exec ip netns exec "$ns" /bin/sh -c "$*"
AGENT
chmod +x "$work/netns-rsh"

export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_WAIT_POLICY=PASSIVE
echo "two_hosts: one process per namespace, MPI over TCP between 10.77.0.1 and 10.77.0.2"
ip netns exec sluice_host_a mpirun --host 10.77.0.1,10.77.0.2 -np 2 --oversubscribe \
  --mca plm_rsh_agent "$work/netns-rsh" --mca btl tcp,self \
  --mca btl_tcp_if_include 10.77.0.0/24 --mca oob_tcp_if_include 10.77.0.0/24 \
  -x OMPI_ALLOW_RUN_AS_ROOT -x OMPI_ALLOW_RUN_AS_ROOT_CONFIRM -x OMP_WAIT_POLICY \
  /bin/sh -c 'echo "  process $OMPI_COMM_WORLD_RANK in the namespace of $(ip -4 -o addr show | grep -o "10\.77\.0\.[0-9]*")" >&2;
              exec "$0" "$@"' "$sluice" run -q --threads 1 -o "$work/two" "${options[@]}" | tee "$work/two.txt"
"$sluice" run -q --threads 1 -o "$work/one" "${options[@]}" > "$work/one.txt"

/usr/bin/python3 - "$work/one" "$work/two" <<'PY'
import glob, os, sys
import numpy as np
one, two = sys.argv[1:]
worst = 0.0
frames = sorted(glob.glob(os.path.join(one, "frames", "*.npz")))
for f in frames:
    a, b = np.load(f), np.load(os.path.join(two, "frames", os.path.basename(f)))
    assert (a["id"] == b["id"]).all(), f"{f}: particles differ"
    worst = max(worst, float(np.abs(a["x"] - b["x"]).max()))
print(f"two_hosts: {len(frames)} frames, largest position difference from one process {worst:.3g} m")
sys.exit(0 if worst < 1e-6 else 1)
PY
