#!/bin/bash
# `ldoem-conformance --record` then `--against` on ldoem-emud (docs/conformance.md):
#   1. the suite's vector and conversation cases against a fresh daemon, recorded to a capture;
#   2. --against that capture on another fresh daemon: every exchange must match (times and
#      counters masked: they depend on when the requests came);
#   3. --against a copy in which one GET_STATUS reply says MEASURE instead of IDLE: the run must
#      fail and name the field, status.sensor_mode.
# Usage: against-emulator.sh --daemon EMUD --suite SUITE --scene FILE [--transport tcp|serial|can]
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
daemon="" suite="" scene="" transport=tcp
while (($#)); do
  case "$1" in
    --daemon) daemon=$2; shift 2 ;;
    --suite) suite=$2; shift 2 ;;
    --scene) scene=$2; shift 2 ;;
    --transport) transport=$2; shift 2 ;;
    *) echo "against-emulator.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
done
work=$(mktemp -d /tmp/ldoem-against.XXXXXX)
trap 'rm -rf "$work"' EXIT
run() { "$here/run-against-daemon.sh" --daemon "$daemon" --suite "$suite" --scene "$scene" --transport "$transport" \
          --time-scale 10 --timeout 240 -- "$@"; }

run --filter "$transport/vectors/*" --filter "$transport/conversation/*" --record "$work/recorded.pcapng" \
  >"$work/record.out" 2>&1 || { cat "$work/record.out"; echo "FAIL: recording run"; exit 1; }
[[ -s $work/recorded.pcapng ]] || { echo "FAIL: no capture written"; exit 1; }

run --against "$work/recorded.pcapng" --mask-times --mask-counters >"$work/same.out" 2>&1
status=$?
tail -n 3 "$work/same.out"
if ((status != 0)) || ! grep -qx '0 differences' "$work/same.out"; then
  grep -A12 '^FAIL' "$work/same.out" | head -n 60
  echo "FAIL: --against the emulator's own capture found differences (exit $status)"
  exit 1
fi

# One field edited: the first GET_STATUS reply IDLE (81 02 00 00 00 01, XOR 82) becomes MEASURE
# (... 00 03, XOR 80). Serial and CAN captures carry the payload differently; TCP is enough here.
python3 - "$work/recorded.pcapng" "$work/edited.pcapng" <<'PY' || { echo "FAIL: could not edit the capture"; exit 1; }
import sys
data = open(sys.argv[1], "rb").read()
old = bytes.fromhex("0255535000000006810200000001 82".replace(" ", ""))
new = bytes.fromhex("0255535000000006810200000003 80".replace(" ", ""))
if old not in data:
    sys.exit("no GET_STATUS IDLE reply frame in the capture")
open(sys.argv[2], "wb").write(data.replace(old, new, 1))
PY
run --against "$work/edited.pcapng" --mask-times --mask-counters >"$work/edited.out" 2>&1
status=$?
grep -A3 '^FAIL' "$work/edited.out" | head -n 8
if ((status != 1)) || ! grep -q 'status.sensor_mode: recorded 3, got 1' "$work/edited.out"; then
  echo "FAIL: --against the edited capture did not name status.sensor_mode (exit $status)"
  exit 1
fi
echo "against-emulator: the emulator matches its own capture; the edited field is named"
