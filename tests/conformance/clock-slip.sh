#!/bin/bash
# The device-clock checks fail on a device whose clock slips (docs/conformance.md, "Device clock"):
#   1. control: the suite through clock_slip_proxy with no slip passes the streaming cases, so
#      the proxy itself is transparent;
#   2. the same cases through the proxy slipping 2 ms per profile (TSTART 98 ms apart at 10 Hz)
#      must fail, each naming the device clock, both the timing case and the S1 conversation.
# Usage: clock-slip.sh --daemon EMUD --suite SUITE --proxy PROXY --scene FILE
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
daemon="" suite="" proxy="" scene=""
while (($#)); do
  case "$1" in
    --daemon) daemon=$2; shift 2 ;;
    --suite) suite=$2; shift 2 ;;
    --proxy) proxy=$2; shift 2 ;;
    --scene) scene=$2; shift 2 ;;
    *) echo "clock-slip.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
done
work=$(mktemp -d /tmp/ldoem-clock-slip.XXXXXX)
trap 'rm -rf "$work"' EXIT
cases=(--filter 'tcp/timing/profile_cadence_10_Hz' --filter 'tcp/conversation/S1')
run() {  # SLIP OUT
  "$here/run-against-daemon.sh" --daemon "$daemon" --suite "$suite" --scene "$scene" --transport tcp \
    --time-scale 10 --timeout 240 --proxy "$proxy" "$1" -- "${cases[@]}" >"$2" 2>&1
}

run 0 "$work/control.out"
status=$?
if ((status != 0)) || grep -q 'device clock' "$work/control.out"; then
  cat "$work/control.out"
  echo "FAIL: the suite through the proxy without slip (exit $status)"
  exit 1
fi
tail -n 1 "$work/control.out"

run 2 "$work/slip.out"
status=$?
grep -E '^(PASS|FAIL|INCONCLUSIVE)|passed' "$work/slip.out"
if ((status != 1)); then
  echo "FAIL: a device clock slipping 2 ms per revolution passed (exit $status)"
  exit 1
fi
for name in tcp/timing/profile_cadence_10_Hz tcp/conversation/S1; do
  grep -q "^FAIL $name: device clock: PROFILESENT 1 -> 2: TSTART advanced" "$work/slip.out" || {
    echo "FAIL: $name did not fail on the device clock"
    exit 1
  }
done
echo "PASS: both cases fail on the slipping clock"
