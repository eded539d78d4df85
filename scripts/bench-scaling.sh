#!/usr/bin/env bash
# Build and run ldoem_bench_daemon_scaling (tests/bench/daemon_scaling_main.cpp: N scanners in one
# ldoem-emud daemon, all on its one loop thread, in virtual time), then write docs/scaling.md
# (scripts/scaling_report.py): scanners per core in real time on one daemon thread and memory
# per added scanner, for scenes/corridor.yaml and scenes/large.yaml, with the paper's effects and
# with every effect on, what TRANS_MEASURE answers to a whole-turn 14 400 beams/s configuration,
# plus the machine, its load and this exact command. A missed target is reported, never turned
# into a failing exit status; a run that fails (a refused TRANS_MEASURE, missing profiles) is.
#
# Usage: scripts/bench-scaling.sh [--build-dir DIR] [--no-build] [--scanners N] [--all-scanners M]
#   --scanners N      scanners in the paper-effects runs [201]
#   --all-scanners M  scanners in the every-effect runs [41]
# Run it niced on a shared machine: nice -n 10 scripts/bench-scaling.sh (CPU time is measured,
# so the load matters less, but it is written into the report).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build/bench"
do_build=1
scanners=201
all_scanners=41
. "$(dirname "$0")/lib/doc-paths.sh"
command_line=$(printf '%s' "scripts/bench-scaling.sh $*" | doc_paths)
while [[ $# -gt 0 ]]; do
  case "$1" in
    --build-dir) build="$2"; shift 2 ;;
    --no-build) do_build=0; shift ;;
    --scanners) scanners="$2"; shift 2 ;;
    --all-scanners) all_scanners="$2"; shift 2 ;;
    --help|-h) sed -n '2,14p' "$0"; exit 0 ;;
    *) echo "unknown argument: $1" >&2; exit 2 ;;
  esac
done
for count in "$scanners" "$all_scanners"; do
  [[ "$count" =~ ^[0-9]+$ && "$count" -ge 2 && "$count" -le 441 ]] ||
    { echo "bench-scaling: scanner counts are 2..441 (a 21 x 21 grid), got $count" >&2; exit 2; }
done

if [[ $do_build -eq 1 ]]; then
  cmake -S "$root" -B "$build" -G Ninja -DLDOEM_ONLY="protocol;emulator;tests/bench" \
        -DLDOEM_BENCHMARKS=ON >/dev/null
  cmake --build "$build" -j2 --target ldoem_bench_daemon_scaling >/dev/null
fi
bench="$build/tests/bench/ldoem_bench_daemon_scaling"
[[ -x "$bench" ]] || { echo "bench-scaling: $bench not built" >&2; exit 2; }

load_at_start="$(cut -d' ' -f1-3 /proc/loadavg)"
cpu_model="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
cores="$(nproc)"
niceness="$(nice)"
started="$(date -u '+%Y-%m-%d %H:%M UTC')"
results="$build/daemon-scaling.json"
cd "$root"
run() { timeout 900 "$bench" "$@" >>"$results"; }
# The last run's estimate of scanners per core (at most 441), unless that count has been run.
next_count() {
  python3 - "$results" "$1" "$2" <<'PYTHON'
import json, sys
runs = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]
runs = [r for r in runs if r.get("scene") == sys.argv[2] and r.get("effects") == sys.argv[3]]
estimate = min(441, int(runs[-1]["scanners_per_core"]))
if estimate >= 2 and estimate not in {r["scanners"] for r in runs}:
    print(estimate)
PYTHON
}
: >"$results"
# The whole turn at the device's peak pulse rate, two ways, then the largest the device keeps up.
run scenes/corridor.yaml probe-full-turn 20 8
run scenes/corridor.yaml probe-full-turn 10 4
run scenes/corridor.yaml probe-full-turn 15 8
for scene in scenes/corridor.yaml scenes/large.yaml; do
  for effects in paper all; do
    count=$scanners
    [[ $effects == all ]] && count=$all_scanners
    run "$scene" "$effects" 1  # the baseline memory per added scanner is measured from
    run "$scene" "$effects" "$count"
    # Check the estimate N / (CPU s per simulated s) with that many scanners, and again from
    # that run's estimate (the cost per scanner grows with N), at most 4 times and 441 scanners.
    for _ in 1 2 3 4; do
      next="$(next_count "$scene" "$effects")"
      [[ -n "$next" ]] || break
      run "$scene" "$effects" "$next"
    done
  done
done
load_at_end="$(cut -d' ' -f1-3 /proc/loadavg)"

python3 "$root/scripts/scaling_report.py" "$results" "$root/docs/scaling.md" \
  --command "$command_line" --date "$started" --cpu "$cpu_model" --cores "$cores" \
  --load-start "$load_at_start" --load-end "$load_at_end" --nice "$niceness" \
  --scanners "$scanners" --all-scanners "$all_scanners"
echo "wrote docs/scaling.md" >&2
