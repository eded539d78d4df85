#!/bin/bash
# Cadence jitter of ldoem-emud's profile stream, with and without --realtime, on the machine as
# it is and under `stress-ng --cpu 4 --io 2` (docs/latency.md, "Cadence jitter"): a daemon at
# --time-scale 1 streams the 20 Hz, 0.5 deg wall scene over TCP, and ldoem-latency --cadence
# takes each profile's arrival lag behind its own TSTART, less the smallest lag (how much later
# than the best case the host got the revolution). Prints one Markdown table.
#
# Usage: scripts/bench-jitter.sh [BUILD_DIR] [--seconds S] [--write-doc FILE]
#   BUILD_DIR   a build with ldoem-emud and ldoem-latency (default build/default)
#   --seconds   length of each stream (default 20)
#   --write-doc also write the command and the table into FILE, between the lines
#               <!-- bench-jitter:begin --> and <!-- bench-jitter:end --> (docs/latency.md)
# --realtime is granted to root (or with CAP_SYS_NICE / RLIMIT_RTPRIO); the table says whether it
# was. stress-ng runs only for the loaded rows and is stopped on exit.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build/default
seconds=20
doc=
. "$(dirname "$0")/lib/doc-section.sh"
. "$(dirname "$0")/lib/doc-paths.sh"
command_line=$(printf '%s' "scripts/bench-jitter.sh $*" | doc_paths)
while [ $# -gt 0 ]; do
  case $1 in
    --seconds)
      [[ ${2:-} =~ ^[1-9][0-9]{0,2}$ ]] || { echo "bench-jitter.sh: --seconds needs a number from 1 to 999" >&2; exit 2; }
      seconds=$2; shift 2 ;;
    --write-doc)
      [ $# -ge 2 ] && grep -q '^<!-- bench-jitter:begin -->$' "$2" 2>/dev/null && grep -q '^<!-- bench-jitter:end -->$' "$2" ||
        { echo "bench-jitter.sh: --write-doc needs a file with the bench-jitter:begin/end marker lines" >&2; exit 2; }
      doc=$(cd "$(dirname "$2")" && pwd)/$(basename "$2"); shift 2 ;;
    -h|--help) sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "bench-jitter.sh: unknown option $1" >&2; exit 2 ;;
    *) build=$(cd "$1" && pwd); shift ;;
  esac
done
emud=$build/emulator/daemon/ldoem-emud
client=$build/tools/latency/ldoem-latency
for program in "$emud" "$client"; do
  [ -x "$program" ] || { echo "bench-jitter.sh: $program missing (build ldoem-emud ldoem-latency)" >&2; exit 2; }
done
command -v stress-ng >/dev/null || { echo "bench-jitter.sh: stress-ng missing (scripts/install-deps.sh)" >&2; exit 2; }

tool=bench-jitter.sh
# shellcheck source=scripts/lib/latency-daemon.sh
source "$root/scripts/lib/latency-daemon.sh"
stress_pid=
stop_stress() {
  if [ -n "$stress_pid" ]; then kill -- -"$stress_pid" 2>/dev/null || true; wait "$stress_pid" 2>/dev/null || true; fi
  stress_pid=
}
trap 'stop_stress; cleanup' EXIT
scene=$work/scene-20hz.yaml
write_wall_scene "$scene"

# row MACHINE DAEMON: one stream against a fresh daemon; DAEMON is "normal" or "--realtime".
row() {
  local machine=$1 mode=$2 args=() granted=-
  [ "$mode" = --realtime ] && args=(--realtime)
  start_daemon "$scene" --no-can --tcp tcp:127.0.0.1:0 --time-scale 1 "${args[@]}"
  if [ "$mode" = --realtime ]; then
    # The daemon says it right after "ready" (main.cpp asks once the scene is built).
    for _ in $(seq 1 40); do grep -q 'realtime: ' "$work/daemon.err" && break; sleep 0.05; done
    granted=$(grep -o 'realtime: .*' "$work/daemon.err" | head -n 1 | sed 's/|/\\|/g' || true)
  fi
  local line
  line=$("$client" --tcp "127.0.0.1:$tcp_port" --cadence "$seconds")
  stop_daemon
  local load
  load=$(cut -d' ' -f1 /proc/loadavg)
  field() { sed -n "s/.* $1=\([^ ]*\).*/\1/p" <<<"$line"; }
  printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s |\n' "$machine" "$mode" "$load" "$(field profiles)" \
    "$(field skipped)" "$(field lag_p50_ms)" "$(field lag_p99_ms)" "$(field lag_max_ms)" "$granted"
}

{
  echo "| machine | daemon | load (1 min) | profiles | skipped | lag p50 ms | lag p99 ms | lag max ms | --realtime said |"
  echo "|---|---|---|---|---|---|---|---|---|"
  row "as it is" normal
  row "as it is" --realtime
  setsid stress-ng --cpu 4 --io 2 --timeout $((2 * seconds + 60)) >/dev/null 2>&1 &
  stress_pid=$!
  sleep 5  # let the load build up before the first loaded row
  row "stress-ng --cpu 4 --io 2" normal
  row "stress-ng --cpu 4 --io 2" --realtime
  stop_stress
} > "$work/table.md"
cat "$work/table.md"
if [ -n "$doc" ]; then
  {
    echo "<!-- bench-jitter:begin -->"
    echo "Written by \`$command_line\` on $(date -u '+%Y-%m-%d %H:%M UTC'), $(nproc) CPUs, as $(id -un) (this section is the script's output; do not edit it by hand):"
    echo
    cat "$work/table.md"
    echo "<!-- bench-jitter:end -->"
  } > "$work/section.md"
  replace_doc_section "$doc" bench-jitter "$work/section.md"
  echo "bench-jitter.sh: wrote the table into $doc" >&2
fi
