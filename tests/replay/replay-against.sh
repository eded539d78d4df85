#!/bin/bash
# ldoem-replay served over TCP and over a serial pty, checked by ldoem-conformance --against:
#   1. the suite's vector and conversation cases against ldoem-emud, recorded (--record);
#   2. ldoem-replay of that capture on TCP: --against the capture finds 0 differences;
#   3. a fresh ldoem-replay of it on a serial pty: the same, through the serial framing;
#   4. a request the recording never saw gets SERVICE_FAILURE reason 3 and a diagnostic;
#   5. the capture moved to TCP port 4000 (tests/wireshark/rewrite_port.py, a device configured
#      to another port): ldoem-replay finds the port itself, --against takes it with --port 4000.
# Usage: replay-against.sh --daemon EMUD --replay REPLAY --suite SUITE --scene FILE --run-against SH
set -uo pipefail
daemon="" replay="" suite="" scene="" run_against=""
while (($#)); do
  case "$1" in
    --daemon) daemon=$2; shift 2 ;;
    --replay) replay=$2; shift 2 ;;
    --suite) suite=$2; shift 2 ;;
    --scene) scene=$2; shift 2 ;;
    --run-against) run_against=$2; shift 2 ;;
    *) echo "replay-against.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
done
work=$(mktemp -d /tmp/ldoem-replay.XXXXXX)
replay_pid=""
cleanup() {
  [[ -n $replay_pid ]] && kill "$replay_pid" 2>/dev/null && wait "$replay_pid" 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT

"$run_against" --daemon "$daemon" --suite "$suite" --scene "$scene" --transport tcp --time-scale 10 --timeout 240 \
  -- --filter 'tcp/vectors/*' --filter 'tcp/conversation/*' --record "$work/recorded.pcapng" >"$work/record.out" 2>&1 \
  || { cat "$work/record.out"; echo "FAIL: recording run"; exit 1; }

# Starts ldoem-replay of $capture with the given endpoint options and waits for `ready`.
capture="$work/recorded.pcapng"
start_replay() {
  "$replay" "$capture" "$@" --speed 10 --timeout 200 >"$work/replay.out" 2>"$work/replay.err" &
  replay_pid=$!
  for _ in $(seq 100); do
    grep -qx ready "$work/replay.out" 2>/dev/null && return 0
    kill -0 "$replay_pid" 2>/dev/null || break
    sleep 0.1
  done
  cat "$work/replay.out" "$work/replay.err"
  echo "FAIL: ldoem-replay did not become ready"
  exit 1
}
stop_replay() { kill "$replay_pid" 2>/dev/null; wait "$replay_pid" 2>/dev/null; replay_pid=""; }
check_against() {  # $1: label, then the suite's endpoint options
  local label=$1; shift
  timeout 240 "$suite" "$@" --time-scale 10 --against "$capture" --mask-times --mask-counters \
    >"$work/$label.out" 2>&1
  local status=$?
  tail -n 2 "$work/$label.out"
  if ((status != 0)) || ! grep -qx '0 differences' "$work/$label.out"; then
    grep -A6 '^FAIL' "$work/$label.out" | head -n 40
    echo "--- ldoem-replay stderr"; tail -n 20 "$work/replay.err"
    echo "FAIL: --against ldoem-replay over $label (exit $status)"
    exit 1
  fi
}

start_replay --tcp tcp:127.0.0.1:0
address=$(sed -n 's/^tcp \(.*\)$/\1/p' "$work/replay.out" | head -n 1)
check_against tcp --tcp "tcp:$address"
# A request the recording never saw (the cases send SET_TIME_REL -10 ms, never +7 ms).
python3 - "$address" >"$work/unexpected.out" 2>&1 <<'PY'
import socket, sys
host, port = sys.argv[1].rsplit(":", 1)
payload = bytes([0x02, 0x04, 0x00, 0x07])
frame = b"\x02USP" + len(payload).to_bytes(4, "big") + payload + bytes([0x02 ^ 0x04 ^ 0x00 ^ 0x07])
with socket.create_connection((host, int(port)), timeout=5) as s:
    s.sendall(frame)
    s.settimeout(5)
    reply = b""
    while len(reply) < 15:
        chunk = s.recv(64)
        if not chunk:
            break
        reply += chunk
print(reply.hex())
PY
stop_replay
# FF 00 | 02 04 | 00 03, XOR FA: SERVICE_FAILURE for SET_TIME_REL, reason 3 (docs/replay.md).
if ! grep -qx '0255535000000006ff0002040003fa' "$work/unexpected.out"; then
  cat "$work/unexpected.out"; echo "FAIL: an unrecorded request did not get SERVICE_FAILURE reason 3"; exit 1
fi
grep -q 'SET_TIME_REL 0007 is not in the recording' "$work/replay.err" \
  || { tail -n 5 "$work/replay.err"; echo "FAIL: no diagnostic for the unrecorded request"; exit 1; }

start_replay --serial "serial:pty:$work/serial"
check_against serial --serial "serial:pty:$work/serial"
stop_replay

# A device on TCP port 4000: the same capture with the port changed.
python3 "$(dirname "$0")/../wireshark/rewrite_port.py" "$work/recorded.pcapng" "$work/port4000.pcapng" 4000 \
  || { echo "FAIL: rewrite_port.py"; exit 1; }
capture="$work/port4000.pcapng"
start_replay --tcp tcp:127.0.0.1:0
grep -q 'exchanges (tcp, device port 4000 (detected))' "$work/replay.err" \
  || { head -n 5 "$work/replay.err"; echo "FAIL: ldoem-replay did not find port 4000 in the capture"; exit 1; }
address=$(sed -n 's/^tcp \(.*\)$/\1/p' "$work/replay.out" | head -n 1)
check_against port4000 --tcp "tcp:$address" --port 4000
stop_replay
grep -q '^against .*device port 4000): ' "$work/port4000.out" \
  || { head -n 3 "$work/port4000.out"; echo "FAIL: --against --port 4000 did not take port 4000"; exit 1; }
echo "replay-against: ldoem-replay answers like the recorded emulator over TCP, serial, and from a port-4000 capture; $(grep -c '^PASS' "$work/serial.out") exchanges each"
