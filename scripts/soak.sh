#!/usr/bin/env bash
# Soak test: ldoem-emud and ldoem-hub under steady load for a bounded time, with their memory,
# descriptors and CPU sampled once a second.
#   scripts/soak.sh [--duration SECONDS] [--build-dir DIR] [--out DIR] [--can auto|on|off]
#                   [--report docs/soak.md]
# Load (scripts/soak.py, scripts/soak_clients.py): TCP clients that connect to ldoem-emud, stream
# profiles and drop the connection (close, CANCEL_PROFILE, reset, mid-telegram); ldoem-hub with 16
# clients asking STATUS, GET2DPROFILE and MOVEMOTOR, whose steps go to a second ldoem-emud over its
# LPT pty; CAN traffic (a third ldoem-emud on vcan0 behind the hub) where vcan0 exists (--can auto).
# Checks: every reply is right (framing, checksum, fields, the static scene's exact profile,
# PROFILESENT counting up, MEASURE mode), the tilt ends where the balanced moves say and the LPT
# steps the daemon counted equal the hub's; after the warm-up (a quarter of the run, at most
# 60 s) no process's RSS grows more than 5 MiB; each process has the same descriptors open when
# idle before and after the load; each stops on SIGTERM.
# Defaults: 600 s, build/default (needs ldoem-emud and ldoem-hub built), --out a new temporary
# folder. --report also plots RSS and descriptors with gnuplot into a PNG next to FILE and writes
# FILE. Exit status 0 passed, 1 a check failed, 2 usage or setup error.
set -euo pipefail
cd "$(dirname "$0")/.."
duration=600 build=build/default out="" can=auto report=""
usage() { echo "usage: scripts/soak.sh [--duration SECONDS] [--build-dir DIR] [--out DIR] [--can auto|on|off] [--report FILE]" >&2; exit 2; }
while [ $# -gt 0 ]; do
  case "$1" in
    --duration) duration=${2:-}; shift 2 || usage ;;
    --build-dir) build=${2:-}; shift 2 || usage ;;
    --out) out=${2:-}; shift 2 || usage ;;
    --can) can=${2:-}; shift 2 || usage ;;
    --report) report=${2:-}; shift 2 || usage ;;
    -h|--help) sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "soak.sh: unknown argument '$1'" >&2; usage ;;
  esac
done
case "$duration" in ''|*[!0-9]*) echo "soak.sh: --duration needs a whole number of seconds" >&2; exit 2 ;; esac
[ -n "$out" ] || out=$(mktemp -d /tmp/ldoem-soak-out.XXXXXX)
status=0
# A hard bound over everything: the run, the final checks and the daemons' stop.
timeout --kill-after=10 $((duration + 180)) \
  python3 scripts/soak.py --duration "$duration" --build-dir "$build" --can "$can" --out "$out" || status=$?
[ -n "$report" ] || exit $status
[ -s "$out/samples.csv" ] || { echo "soak.sh: no samples to report" >&2; exit 2; }
png=${report%.md}.png
python3 scripts/soak_report.py --samples "$out/samples.csv" --summary "$out/summary.txt" \
  --png "$png" --report "$report" --command "scripts/soak.sh --duration $duration --report $report" --status $status
exit $status
