#!/bin/bash
# What the endpoints' D11 fault hook costs when it is there but no fault acts (docs/faults.md,
# "Cost"): ldoem-emud on TCP with the same 20 Hz, 0.5 deg scene, once without faults (no hook at
# all: the endpoints test a null pointer) and once with faults that never act during the run (the
# hook is asked at every telegram and every write). Both in one run, taking turns, so that the
# load of the machine falls on both alike; prints one Markdown table and the with/without ratios.
#
# Usage: scripts/bench-wire-fault-hook.sh [BUILD_DIR] [--requests N] [--seconds S] [--rounds R]
#   BUILD_DIR   a build with ldoem-emud and ldoem-latency (default build/default)
#   --requests  GET_STATUS round trips per measurement (default 2000)
#   --seconds   length of each GET_PROFILE stream (default 5)
#   --rounds    measurements of each variant, alternating (default 3; medians are reported)
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build/default
requests=2000
seconds=5
rounds=3
while [ $# -gt 0 ]; do
  case $1 in
    --requests) requests=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    -h|--help) sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "bench-wire-fault-hook.sh: unknown option $1" >&2; exit 2 ;;
    *) build=$(cd "$1" && pwd); shift ;;
  esac
done
emud=$build/emulator/daemon/ldoem-emud
client=$build/tests/robustness/ldoem-latency
for program in "$emud" "$client"; do
  [ -x "$program" ] || { echo "bench-wire-fault-hook.sh: $program missing (build ldoem-emud and ldoem-latency)" >&2; exit 2; }
done

tool=bench-wire-fault-hook.sh
# shellcheck source=scripts/lib/latency-daemon.sh
source "$root/scripts/lib/latency-daemon.sh"
write_wall_scene "$work/without.yaml"
# Endpoint faults that are in the scene but never act: triggered by a service nobody asks for.
cp "$work/without.yaml" "$work/with.yaml"
cat >> "$work/with.yaml" <<'YAML'
faults:
  - {kind: garbage, on: {service: GET_SYNC_CLOCK, nth: 1}}
  - {kind: corrupt_checksum, on: {service: GET_SYNC_CLOCK, nth: 1}}
  - {kind: bandwidth, on: {service: GET_SYNC_CLOCK, nth: 1}}
  - {kind: tcp_stall, on: {service: GET_SYNC_CLOCK, nth: 1}}
YAML

results=$work/results.txt
: > "$results"
for round in $(seq 1 "$rounds"); do
  for variant in without with; do
    start_daemon "$work/$variant.yaml" --no-can --tcp 127.0.0.1:0 --virtual-time
    "$client" --tcp "127.0.0.1:$tcp_port" --requests "$requests" | sed "s/^/variant=$variant round=$round /" >> "$results"
    stop_daemon
    start_daemon "$work/$variant.yaml" --no-can --tcp 127.0.0.1:0 --virtual-time
    "$client" --tcp "127.0.0.1:$tcp_port" --profiles "$seconds" | sed "s/^/variant=$variant round=$round /" >> "$results"
    stop_daemon
  done
done

# The median over the rounds of one key for one variant.
median_of() {
  grep "^variant=$1 " "$results" | sed -n "s/.* $2=\([^ ]*\).*/\1/p" | sort -g |
    awk '{ v[NR] = $1 } END { if (NR == 0) print ""; else if (NR % 2) print v[(NR + 1) / 2]; else printf "%.1f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}
echo "| scene | GET_STATUS median (us) | GET_STATUS p99 (us) | profiles/s | bytes/s |"
echo "|---|---|---|---|---|"
for variant in without with; do
  label="no faults (no hook)"; [ $variant = with ] && label="4 endpoint faults, none acting (hook asked)"
  echo "| $label | $(median_of $variant median_us) | $(median_of $variant p99_us) | $(median_of $variant profiles_per_s) | $(median_of $variant bytes_per_s) |"
done
echo
ratios="GET_STATUS median $(ratio "$(median_of with median_us)" "$(median_of without median_us)")"
ratios+=", p99 $(ratio "$(median_of with p99_us)" "$(median_of without p99_us)")"
ratios+=", profiles/s $(ratio "$(median_of with profiles_per_s)" "$(median_of without profiles_per_s)")"
echo "Ratios with/without: $ratios"
echo "(TCP, --virtual-time; $rounds rounds of $requests GET_STATUS and $seconds s of GET_PROFILE 0000 39ff at 20 Hz, 0.5 deg; $(nproc) CPUs, load $(cut -d' ' -f1 /proc/loadavg))"
