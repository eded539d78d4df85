#!/usr/bin/env bash
# The main job, from nothing: install the dependencies, build, start the emulated scanner on the
# paper's corridor scene (scenes/corridor.yaml) on vcan0, scan it with ldoem-scan at the paper's
# settings, and write out/corridor.ply, out/corridor.png and the fitted cylinder and wall.
# Where this kernel has no vcan0 (no CAN support), the same job runs inside User-Mode Linux.
set -euo pipefail
cd "$(dirname "$0")/.."
cache=${LDOEM_CACHE:-$HOME/.cache/ldoem}
export CCACHE_DIR=${CCACHE_DIR:-$cache/ccache} CCACHE_BASEDIR=$PWD CCACHE_NOHASHDIR=1

scripts/install-deps.sh
cmake --preset default >/dev/null
cmake --build --preset default

mkdir -p out
if ip link show vcan0 >/dev/null 2>&1; then
  exec scripts/scan-corridor.sh "$@"
fi
echo "demo: no vcan0 on this kernel; running the job inside User-Mode Linux (scripts/uml/run.sh)"
exec scripts/uml/run.sh --timeout 900 -- scripts/scan-corridor.sh "$@"
