#!/usr/bin/env bash
# The first command (README.md), from nothing: install what the demo needs and nothing else
# (scripts/install-deps.sh --demo), build the two programs it runs (the `demo` preset: ldoem-emud
# and ldoem-scan, -O1, unity build), start the emulated scanner on the paper's corridor scene
# (scenes/corridor.yaml) on vcan0, scan it with ldoem-scan at the paper's settings, and end with
# a table (cylinder, wall, points, time) and the files written: out/corridor.ply, the range
# image out/corridor.png and the perspective render out/corridor-render.png.
# Where this kernel has no vcan0 (no CAN support), the scan runs inside User-Mode Linux.
#   scripts/demo.sh [--build-only | --scan-only] [scan-corridor.sh arguments]
#   --build-only  install and build, no scan; --scan-only  scan with the programs in
#   $LDOEM_BUILD (default build/demo); scripts/time-demo.sh times the two halves apart.
# Other arguments go to scripts/scan-corridor.sh (e.g. --transport tcp, --virtual-time).
set -euo pipefail
cd "$(dirname "$0")/.."
cache=${LDOEM_CACHE:-$HOME/.cache/ldoem}
export CCACHE_DIR=${CCACHE_DIR:-$cache/ccache} CCACHE_BASEDIR=$PWD CCACHE_NOHASHDIR=1
export LDOEM_BUILD=${LDOEM_BUILD:-build/demo}
build=true scan=true
case "${1:-}" in
  --build-only) build=true scan=false; shift ;;
  --scan-only) build=false scan=true; shift ;;
esac
started=$SECONDS
mark=$SECONDS
timings=()
lap() {  # $1: the step that just ended
  timings+=("$1 $((SECONDS - mark)) s")
  echo "demo: $1 took $((SECONDS - mark)) s"
  mark=$SECONDS
}

if $build; then
  scripts/install-deps.sh --demo
  lap deps
  cmake --preset demo >/dev/null
  lap configure
  cmake --build --preset demo
  lap build
fi
$scan || exit 0

mkdir -p out
log=$(mktemp "${TMPDIR:-/tmp}/ldoem-demo.XXXXXX")
trap 'rm -f "$log"' EXIT
scan_command=(scripts/scan-corridor.sh --render out/corridor-render.png "$@")
status=0
if ip link show vcan0 >/dev/null 2>&1; then
  "${scan_command[@]}" 2>&1 | tee "$log" || status=$?
else
  echo "demo: no vcan0 on this kernel; running the scan inside User-Mode Linux (scripts/uml/run.sh)"
  # The guest prints the host clock (UML reads it) as its first line: the boot's share. The
  # single quotes are meant: the guest's shell expands them.
  before_ns=$(date +%s%N)
  # shellcheck disable=SC2016
  scripts/uml/run.sh --timeout 900 -- bash -c 'echo "demo: guest up at $(date +%s%N)"; exec "$@"' demo \
    "${scan_command[@]}" 2>&1 | tee "$log" || status=$?
  guest_ns=$(sed -n 's/^demo: guest up at \([0-9]*\)$/\1/p' "$log" | head -n 1)
  [[ -n $guest_ns ]] && boot_s=$(((guest_ns - before_ns) / 1000000000))
fi
lap scan
[[ -n ${boot_s:-} ]] && timings[-1]+=" (UML boot ${boot_s} s of it)"
((status == 0)) || { echo "demo: the scan failed (exit $status)" >&2; exit "$status"; }

# The summary: scan-corridor.sh's fit table, the cloud's point count, and where the time went.
points=$(sed -n 's/^element vertex \([0-9]*\)$/\1/p' out/corridor.ply | head -n 1)
echo
echo "demo: the corridor scan (scenes/corridor.yaml), fitted against the scene's true values"
grep -E '^( +fitted|cylinder diameter|cylinder length|wall distance) {2,}' "$log" || true
printf '%-19s %10s\n' "points" "${points:-?}"
steps=$(printf '%s, ' "${timings[@]}")
printf '%-19s %8d s  (%s)\n' "time" $((SECONDS - started)) "${steps%, }"
echo
echo "demo: files written"
for file in out/corridor.ply out/corridor.png out/corridor-render.png; do
  [[ -f $file ]] && printf '  %-24s %8s bytes\n' "$file" "$(stat -c %s "$file")"
done
echo "  programs: $LDOEM_BUILD/emulator/daemon/ldoem-emud, $LDOEM_BUILD/driver/scan/ldoem-scan (README.md)"
