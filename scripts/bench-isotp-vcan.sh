#!/bin/bash
# ISO-TP frames per second through vcan0 inside User-Mode Linux: builds tests/interop's
# isotp_vcan_bench, boots UML once through scripts/uml/run.sh, runs it in each configuration
# below and prints one Markdown table (docs/isotp-vcan.md holds the last one measured).
#
#   1. BS 0, STmin 0, the kernel's default receive buffer
#   2. BS 0, STmin 0, a 4 MB receive buffer (what libldoem's CAN transport asks for)
#   3. BS 8, STmin 0, the kernel's default receive buffer
#
# Usage: scripts/bench-isotp-vcan.sh [--build-dir DIR] [--messages N] [--bytes B] [--no-build]
#   --build-dir  build folder (default build/isotp-vcan-bench; configured with
#                LDOEM_ONLY="protocol;tests/interop", RelWithDebInfo)
#   --messages   messages per configuration (default 200)
#   --bytes      bytes per message (default 5800, a 0.125 deg profile, D1)
#   --no-build   use the build folder as it is
# Exit status: 0 all ran; 1 a run failed (socket error); 2 usage; 125 the UML harness failed.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build/isotp-vcan-bench
messages=200
bytes=5800
do_build=1
while [ $# -gt 0 ]; do
  case $1 in
    --build-dir) build=$2; shift 2 ;;
    --messages) messages=$2; shift 2 ;;
    --bytes) bytes=$2; shift 2 ;;
    --no-build) do_build=0; shift ;;
    *) echo "bench-isotp-vcan.sh: unknown option $1" >&2; exit 2 ;;
  esac
done

if [ "$do_build" = 1 ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DLDOEM_ONLY="protocol;tests/interop" -DLDOEM_BENCHMARKS=ON > /dev/null
  cmake --build "$build" -j2 --target isotp_vcan_bench > /dev/null
fi
bench=$build/tests/interop/isotp_vcan_bench
[ -x "$bench" ] || { echo "bench-isotp-vcan.sh: $bench missing" >&2; exit 2; }

load=$(cut -d' ' -f1-3 /proc/loadavg)
log=$(mktemp /tmp/ldoem-isotp-vcan.XXXXXX)
trap 'rm -f "$log"' EXIT

# One guest for all three runs; each run's RESULT line is collected from the merged output.
guest="set -e
\"$bench\" --messages $messages --bytes $bytes --block-size 0
\"$bench\" --messages $messages --bytes $bytes --block-size 0 --receive-buffer 4194304
\"$bench\" --messages $messages --bytes $bytes --block-size 8"
set +e
"$root/scripts/uml/run.sh" --timeout 1200 "$guest" > "$log" 2>&1
status=$?
set -e
if [ "$status" -ne 0 ]; then
  cat "$log" >&2
  echo "bench-isotp-vcan.sh: the guest ended with status $status" >&2
  exit $(( status == 125 ? 125 : 1 ))
fi

field() { sed -n "s/.* $1=\([^ ]*\).*/\1/p" <<< "$2"; }
echo "Command: scripts/bench-isotp-vcan.sh --messages $messages --bytes $bytes (load average at start: $load)"
echo
echo "| BS | STmin | receive buffer (granted) | messages | frames/s | messages/s | payload MB/s | frames sent | frames lost | kernel drops | messages intact | failed |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
grep '^RESULT ' "$log" | while read -r line; do
  line=" ${line#RESULT }"
  printf '| %s | %s us | %s B | %s x %s B | %s | %s | %s | %s | %s | %s | %s | %s |\n' \
    "$(field bs "$line")" "$(field stmin_us "$line")" "$(field rcvbuf "$line")" \
    "$(field messages "$line")" "$(field bytes "$line")" "$(field frames_per_s "$line")" \
    "$(field messages_per_s "$line")" "$(field payload_mb_per_s "$line")" "$(field sent_frames "$line")" \
    "$(field lost_frames "$line")" "$(field kernel_drops "$line")" "$(field intact "$line")" "$(field failed "$line")"
done
