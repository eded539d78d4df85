#!/bin/bash
# What the D11 fault machinery costs a scene that names no fault (docs/faults.md, "Cost"), as
# ratios of runs taking turns in one go, so that the load of the machine falls on all alike:
#
# 1. The paper scan (scripts/scan-corridor.sh's: the corridor, 20 x 21.6 deg at 0.25 x 0.18 deg,
#    10 Hz) by ldoem-scan over TCP with --virtual-time, against three daemons: a BASELINE daemon
#    built from before the fault work ("today's" in issue 10; e.g. commit bda8823), this build on
#    the scene as it is (no faults: no hook), and this build with four endpoint faults that never
#    act (the hook is asked at every telegram and write). Medians of ldoem-scan's wall time and of
#    the daemon's CPU time from ready to the scan's end (all its threads; the scene's loading is
#    left out), their ratios to the baseline, and whether the three clouds are byte-identical
#    (they must be: a scene without faults gives today's profiles).
# 2. GET_STATUS latency and GET_PROFILE throughput (ldoem-latency) on the 20 Hz, 0.5 deg wall
#    scene, this build without and with the dormant faults.
#
# Usage: scripts/bench-wire-fault-hook.sh [BUILD_DIR] [--baseline EMUD] [--scans N] [--requests N]
#                                         [--seconds S] [--rounds R] [--write-doc]
#   BUILD_DIR    a build with ldoem-emud, ldoem-scan and ldoem-latency (default build/default)
#   --baseline   the ldoem-emud to compare against (without it part 1 is left out)
#   --scans      paper scans of each daemon, alternating (default 9; medians are reported)
#   --requests   GET_STATUS round trips per measurement (default 2000)
#   --seconds    length of each GET_PROFILE stream (default 5)
#   --rounds     latency measurements of each variant, alternating (default 3)
#   --write-doc  also put the tables between the "bench-wire-fault-hook" markers of docs/faults.md
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build/default
baseline=
scans=9
requests=2000
seconds=5
rounds=3
write_doc=
while [ $# -gt 0 ]; do
  case $1 in
    --baseline) baseline=$2; shift 2 ;;
    --scans) scans=$2; shift 2 ;;
    --requests) requests=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    --write-doc) write_doc=1; shift ;;
    -h|--help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
    -*) echo "bench-wire-fault-hook.sh: unknown option $1" >&2; exit 2 ;;
    *) build=$(cd "$1" && pwd); shift ;;
  esac
done
this_emud=$build/emulator/daemon/ldoem-emud
client=$build/tools/latency/ldoem-latency
scan=$build/driver/scan/ldoem-scan
for program in "$this_emud" "$client" "$scan" ${baseline:+"$baseline"}; do
  [ -x "$program" ] || { echo "bench-wire-fault-hook.sh: $program missing (build ldoem-emud, ldoem-scan and ldoem-latency)" >&2; exit 2; }
done
emud=$this_emud
# The baseline's commit, when it was built inside a git work tree (its build folder usually is).
baseline_commit=
[ -n "$baseline" ] && baseline_commit=$(git -C "$(dirname "$baseline")" log -1 --format=%h 2>/dev/null || true)

tool=bench-wire-fault-hook.sh
# shellcheck source=scripts/lib/latency-daemon.sh
source "$root/scripts/lib/latency-daemon.sh"

# Endpoint faults that are in the scene but never act: triggered by a service nobody asks for.
dormant_faults() {
  cat <<'YAML'
faults:
  - {kind: garbage, on: {service: GET_SYNC_CLOCK, nth: 1}}
  - {kind: corrupt_checksum, on: {service: GET_SYNC_CLOCK, nth: 1}}
  - {kind: bandwidth, on: {service: GET_SYNC_CLOCK, nth: 1}}
  - {kind: tcp_stall, on: {service: GET_SYNC_CLOCK, nth: 1}}
YAML
}

# The median of the numbers on standard input.
median() {
  sort -g | awk '{ v[NR] = $1 } END { if (NR == 0) print ""; else if (NR % 2) print v[(NR + 1) / 2]; else printf "%.4f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}

# The daemon's time on a CPU so far, all its threads, in ns (schedstat: finer than the 10 ms
# ticks of /proc/PID/stat; the daemon's threads live until it stops).
daemon_cpu_ns() { cat /proc/"$daemon_pid"/task/*/schedstat | awk '{ sum += $1 } END { printf "%.0f\n", sum }'; }

report=$work/report.md
: > "$report"
load_before=$(cut -d' ' -f1 /proc/loadavg)

# ------------------------------------------------------------------------------ 1. the paper scan
if [ -n "$baseline" ]; then
  cp "$root/scenes/corridor.yaml" "$work/corridor.yaml"
  { cat "$root/scenes/corridor.yaml"; dormant_faults; } > "$work/corridor-dormant.yaml"
  scan_results=$work/scans.txt
  : > "$scan_results"
  for round in $(seq 1 "$scans"); do
    for variant in baseline plain dormant; do
      scene=$work/corridor.yaml
      emud=$this_emud
      [ $variant = baseline ] && emud=$baseline
      [ $variant = dormant ] && scene=$work/corridor-dormant.yaml
      rm -f "$work/lpt"
      start_daemon "$scene" --no-can --tcp tcp:127.0.0.1:0 --lpt "lpt:pty:$work/lpt" --virtual-time
      ready_cpu_ns=$(daemon_cpu_ns)
      started_ns=$(date +%s%N)
      "$scan" --device "tcp:127.0.0.1:$tcp_port" --lpt "lpt:pty:$work/lpt" --horizontal-apex 20 \
        --horizontal-resolution 0.25 --vertical-apex 21.6 --vertical-resolution 0.18 --speed 10 \
        --out "$work/$variant-$round.ply" > "$work/scan.out" 2>&1 ||
        { echo "$tool: ldoem-scan against the $variant daemon failed: $(cat "$work/scan.out")" >&2; exit 1; }
      finished_ns=$(date +%s%N)
      cpu_ns=$(( $(daemon_cpu_ns) - ready_cpu_ns ))  # the scan's, not the scene's loading
      stop_daemon
      echo "$variant $round $(( (finished_ns - started_ns) / 1000 )) $cpu_ns" >> "$scan_results"
    done
  done
  scan_median() { awk -v v="$1" -v f="$2" '$1 == v { print $f }' "$scan_results" | median; }
  identical=yes
  for ply in "$work"/plain-*.ply "$work"/dormant-*.ply "$work"/baseline-*.ply; do
    cmp -s "$ply" "$work/baseline-1.ply" || identical=no
  done
  {
    echo "Paper scan (ldoem-scan over TCP, --virtual-time; $scans scans of each daemon, taking turns; medians):"
    echo
    echo "| daemon | scan wall time (s) | daemon CPU time during the scan (s) | wall / baseline | CPU / baseline |"
    echo "|---|---|---|---|---|"
    for variant in baseline plain dormant; do
      case $variant in
        baseline) label="baseline: before the fault work (${baseline_commit:-$baseline})" ;;
        plain) label="this build, no faults (no hook)" ;;
        dormant) label="this build, 4 endpoint faults, none acting (hook asked)" ;;
      esac
      wall=$(scan_median $variant 3)
      cpu=$(scan_median $variant 4)
      echo "| $label | $(awk -v us="$wall" 'BEGIN { printf "%.3f", us / 1e6 }') | $(awk -v ns="$cpu" 'BEGIN { printf "%.4f", ns / 1e9 }') | $(ratio "$wall" "$(scan_median baseline 3)") | $(ratio "$cpu" "$(scan_median baseline 4)") |"
    done
    echo
    echo "Clouds byte-identical across the three daemons and all scans: $identical."
    echo
  } >> "$report"
fi
emud=$this_emud

# --------------------------------------------------------------- 2. GET_STATUS latency, throughput
write_wall_scene "$work/without.yaml"
{ cat "$work/without.yaml"; dormant_faults; } > "$work/with.yaml"
results=$work/results.txt
: > "$results"
for round in $(seq 1 "$rounds"); do
  for variant in without with; do
    start_daemon "$work/$variant.yaml" --no-can --tcp tcp:127.0.0.1:0 --virtual-time
    "$client" --tcp "127.0.0.1:$tcp_port" --requests "$requests" | sed "s/^/variant=$variant round=$round /" >> "$results"
    stop_daemon
    start_daemon "$work/$variant.yaml" --no-can --tcp tcp:127.0.0.1:0 --virtual-time
    "$client" --tcp "127.0.0.1:$tcp_port" --profiles "$seconds" | sed "s/^/variant=$variant round=$round /" >> "$results"
    stop_daemon
  done
done

# The median over the rounds of one key for one variant.
median_of() { grep "^variant=$1 " "$results" | sed -n "s/.* $2=\([^ ]*\).*/\1/p" | median; }
{
  echo "GET_STATUS and GET_PROFILE on the 20 Hz, 0.5 deg wall scene (TCP, --virtual-time; $rounds rounds of $requests GET_STATUS and $seconds s of GET_PROFILE 0000 39ff, taking turns; medians):"
  echo
  echo "| scene | GET_STATUS median (us) | GET_STATUS p99 (us) | profiles/s | bytes/s |"
  echo "|---|---|---|---|---|"
  for variant in without with; do
    label="no faults (no hook)"; [ $variant = with ] && label="4 endpoint faults, none acting (hook asked)"
    echo "| $label | $(median_of $variant median_us) | $(median_of $variant p99_us) | $(median_of $variant profiles_per_s) | $(median_of $variant bytes_per_s) |"
  done
  echo
  ratios="GET_STATUS median $(ratio "$(median_of with median_us)" "$(median_of without median_us)")"
  ratios+=", p99 $(ratio "$(median_of with p99_us)" "$(median_of without p99_us)")"
  ratios+=", profiles/s $(ratio "$(median_of with profiles_per_s)" "$(median_of without profiles_per_s)")"
  echo "Ratios with/without: $ratios."
  echo
  echo "Machine: $(nproc) CPUs, load average $load_before before and $(cut -d' ' -f1 /proc/loadavg) after the run ($(date -u +%Y-%m-%d))."
} >> "$report"

cat "$report"
if [ -n "$write_doc" ]; then
  doc=$root/docs/faults.md
  begin='<!-- bench-wire-fault-hook: begin -->'
  end='<!-- bench-wire-fault-hook: end -->'
  if ! grep -qxF "$begin" "$doc" || ! grep -qxF "$end" "$doc"; then
    echo "$tool: $doc: markers $begin / $end missing" >&2
    exit 1
  fi
  awk -v begin="$begin" -v end="$end" -v report="$report" '
    $0 == begin { print; print "<!-- written by scripts/bench-wire-fault-hook.sh --write-doc: do not edit by hand -->"; while ((getline line < report) > 0) print line; skipping = 1; next }
    $0 == end { skipping = 0 }
    !skipping { print }' "$doc" > "$work/doc.md"
  cp "$work/doc.md" "$doc"
  echo "$tool: wrote the tables into $doc"
fi
