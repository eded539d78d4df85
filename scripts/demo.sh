#!/usr/bin/env bash
# The first command (README.md), from nothing: install what the demo needs and nothing else
# (scripts/install-deps.sh --demo), build the two programs it runs (the `demo` preset: ldoem-emud
# and ldoem-scan, -O1, unity build), start the emulated scanner on the paper's corridor scene
# (scenes/corridor.yaml) on vcan0, scan it with ldoem-scan at the paper's settings, and end with
# a table (cylinder, wall, points, time) and the files written: out/corridor.ply, the range
# image out/corridor.png and the perspective render out/corridor-render.png.
# Where this kernel has no vcan0 (no CAN support), the scan runs inside User-Mode Linux.
# Arguments are passed on to scripts/scan-corridor.sh (e.g. --transport tcp, --virtual-time).
set -euo pipefail
cd "$(dirname "$0")/.."
cache=${LDOEM_CACHE:-$HOME/.cache/ldoem}
export CCACHE_DIR=${CCACHE_DIR:-$cache/ccache} CCACHE_BASEDIR=$PWD CCACHE_NOHASHDIR=1
export LDOEM_BUILD=build/demo
started=$SECONDS
mark=$SECONDS
timings=()
lap() {  # $1: the step that just ended
  timings+=("$1 $((SECONDS - mark)) s")
  mark=$SECONDS
}

scripts/install-deps.sh --demo
lap deps
cmake --preset demo >/dev/null
lap configure
cmake --build --preset demo
lap build

mkdir -p out
log=$(mktemp "${TMPDIR:-/tmp}/ldoem-demo.XXXXXX")
trap 'rm -f "$log"' EXIT
scan=(scripts/scan-corridor.sh --render out/corridor-render.png "$@")
status=0
if ip link show vcan0 >/dev/null 2>&1; then
  "${scan[@]}" 2>&1 | tee "$log" || status=$?
else
  echo "demo: no vcan0 on this kernel; running the scan inside User-Mode Linux (scripts/uml/run.sh)"
  # The guest prints the host clock (UML reads it) as its first line: the boot's share.
  before_ns=$(date +%s%N)
  scripts/uml/run.sh --timeout 900 -- bash -c 'echo "demo: guest up at $(date +%s%N)"; exec "$@"' demo \
    "${scan[@]}" 2>&1 | tee "$log" || status=$?
  guest_ns=$(sed -n 's/^demo: guest up at \([0-9]*\)$/\1/p' "$log" | head -n 1)
  [[ -n $guest_ns ]] && timings+=("UML boot $(((guest_ns - before_ns) / 1000000000)) s (in the scan)")
fi
lap scan
((status == 0)) || { echo "demo: the scan failed (exit $status)" >&2; exit "$status"; }

# The summary: scan-corridor.sh's fit table, the cloud's point count, and where the time went.
points=$(sed -n 's/^element vertex \([0-9]*\)$/\1/p' out/corridor.ply | head -n 1)
echo
echo "demo: the corridor scan (scenes/corridor.yaml), fitted against the scene's true values"
grep -E '^( +fitted|cylinder diameter|cylinder length|wall distance) ' "$log" || true
printf '%-19s %10s\n' "points" "${points:-?}"
printf '%-19s %8d s  (%s)\n' "time" $((SECONDS - started)) "$(IFS=,; echo "${timings[*]}" | sed 's/,/, /g')"
echo
echo "demo: files written"
for file in out/corridor.ply out/corridor.png out/corridor-render.png; do
  [[ -f $file ]] && printf '  %-24s %8s bytes\n' "$file" "$(stat -c %s "$file")"
done
echo "  programs: build/demo/emulator/daemon/ldoem-emud, build/demo/driver/scan/ldoem-scan (README.md)"
