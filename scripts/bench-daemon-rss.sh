#!/usr/bin/env bash
# Peak resident memory (VmHWM) of ldoem-emud itself while it streams profiles over TCP in virtual
# time, for each scene given (default: the corridor and the 1000-object scene).
# Usage: scripts/bench-daemon-rss.sh [--build-dir DIR] [--seconds N] [SCENE...]
set -euo pipefail
cd "$(dirname "$0")/.."
build=build/default seconds=3
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build=$2; shift 2;;
    --seconds) seconds=$2; shift 2;;
    -h|--help) sed -n 2,4p "$0"; exit 0;;
    *) break;;
  esac
done
[ $# -gt 0 ] || set -- scenes/corridor.yaml scenes/large.yaml
emud=$build/emulator/daemon/ldoem-emud
[ -x "$emud" ] || { echo "bench-daemon-rss: $emud not built (cmake --build --preset default)" >&2; exit 2; }
printf '| scene | profile bytes streamed | peak RSS (MiB) |\n|---|---|---|\n'
for scene in "$@"; do
  out=$(mktemp)
  "$emud" --scene "$scene" --no-can --tcp tcp:127.0.0.1:0 --no-flash --virtual-time --timeout $((seconds + 20)) >"$out" 2>&1 &
  pid=$!
  for _ in $(seq 100); do grep -q '^ready' "$out" && break; sleep 0.1; done
  port=$(sed -n 's/^tcp 127.0.0.1:\([0-9]*\)$/\1/p' "$out")
  # TRANS_ROTATE 0, TRANS_MEASURE, GET_PROFILE stream 0x3DFF, then read for $seconds.
  bytes=$(python3 - "$port" "$seconds" <<'PY'
import functools, socket, sys, time
port, seconds = int(sys.argv[1]), float(sys.argv[2])
def frame(payload):
    xor = functools.reduce(lambda a, b: a ^ b, payload, 0)
    return b"\x02USP" + len(payload).to_bytes(4, "big") + payload + bytes([xor])
s = socket.create_connection(("127.0.0.1", port))
for hexa in ("04030000", "0404", "030100003dff"):
    s.sendall(frame(bytes.fromhex(hexa))); time.sleep(0.2)
start, total = time.time(), 0
while time.time() - start < seconds:
    total += len(s.recv(1 << 16))
print(total)
PY
)
  hwm_kib=$(awk '/^VmHWM/ {print $2}' /proc/$pid/status)
  kill "$pid"; wait "$pid" 2>/dev/null || true; rm -f "$out"
  printf '| %s | %s | %.1f |\n' "$scene" "$bytes" "$(echo "$hwm_kib / 1024" | bc -l)"
done
