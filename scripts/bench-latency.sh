#!/bin/bash
# Request-to-reply latency and sustained profile output of ldoem-emud, as a host sees them:
#   - GET_STATUS round trips (median, p99) on TCP (host) and on vcan0 (inside UML);
#   - profiles/s and bytes/s of a GET_PROFILE stream at 20 Hz, 0.5 deg (a scene whose flash has
#     motor_speed_hz 20 and angle_step_ticks 8), with --virtual-time and at --time-scale 1.
# Prints one Markdown table (docs/latency.md holds the last one measured).
#
# Usage: scripts/bench-latency.sh [BUILD_DIR] [--requests N] [--seconds S] [--no-uml]
#                                 [--compare OLD_EMUD [--rounds N]] [--write-doc FILE]
#   BUILD_DIR   a build with ldoem-emud and ldoem-latency (default build/default)
#   --requests  GET_STATUS round trips per transport (default 2000)
#   --seconds   length of each profile stream (default 10)
#   --no-uml    skip the vcan rows (no UML here)
#   --compare   also measure OLD_EMUD (another build's ldoem-emud) in the same run, old and new
#               taking turns per row, and print the new/old ratios under the table
#   --rounds    with --compare: measure each row N times, old and new interleaved (old new, new
#               old, ...: neither always goes first); the table shows the medians (default 1)
#   --write-doc also write the command, the table and the ratios into FILE, between the lines
#               <!-- bench-latency:begin --> and <!-- bench-latency:end --> (docs/latency.md)
# Inside UML (LDOEM_IN_UML=1) the script measures only the vcan rows and prints them as
# key=value lines; the host run calls itself through scripts/uml/run.sh for that.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build/default
requests=2000
seconds=10
uml=1
old_emud=
rounds=1
doc=
. "$(dirname "$0")/lib/doc-paths.sh"
. "$(dirname "$0")/lib/doc-section.sh"
command_line=$(printf '%s' "scripts/bench-latency.sh $*" | doc_paths)
while [ $# -gt 0 ]; do
  case $1 in
    --requests) requests=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    --no-uml) uml=0; shift ;;
    -h|--help) sed -n '2,21p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    --rounds)
      [[ ${2:-} =~ ^[1-9][0-9]?$ ]] || { echo "bench-latency.sh: --rounds needs a number from 1 to 99" >&2; exit 2; }
      rounds=$2; shift 2 ;;
    --write-doc)
      [ $# -ge 2 ] && grep -q '^<!-- bench-latency:begin -->$' "$2" 2>/dev/null && grep -q '^<!-- bench-latency:end -->$' "$2" ||
        { echo "bench-latency.sh: --write-doc needs a file with the bench-latency:begin/end marker lines" >&2; exit 2; }
      doc=$(cd "$(dirname "$2")" && pwd)/$(basename "$2"); shift 2 ;;
    --compare)
      [ $# -ge 2 ] && [ -x "$2" ] || { echo "bench-latency.sh: --compare needs an ldoem-emud binary" >&2; exit 2; }
      old_emud=$(cd "$(dirname "$2")" && pwd)/$(basename "$2"); shift 2 ;;
    -*) echo "bench-latency.sh: unknown option $1" >&2; exit 2 ;;
    *) build=$(cd "$1" && pwd); shift ;;
  esac
done
new_emud=$build/emulator/daemon/ldoem-emud
client=$build/tools/latency/ldoem-latency
for program in "$new_emud" "$client"; do
  [ -x "$program" ] || { echo "bench-latency.sh: $program missing (build ldoem-latency)" >&2; exit 2; }
done
[ "$rounds" -gt 1 ] && [ -z "$old_emud" ] && { echo "bench-latency.sh: --rounds goes with --compare" >&2; exit 2; }
# The daemons measured: "new" (BUILD_DIR's), and "old" with --compare. Each row runs them in turn,
# `rounds` times, the order swapped from one round to the next.
emud_of() { if [ "$1" = old ]; then echo "$old_emud"; else echo "$new_emud"; fi; }
variants_of_round() {
  if [ -z "$old_emud" ]; then echo new
  elif [ $(($1 % 2)) = 1 ]; then echo "old new"
  else echo "new old"; fi
}
emud=$new_emud

tool=bench-latency.sh
# shellcheck source=scripts/lib/latency-daemon.sh
source "$root/scripts/lib/latency-daemon.sh"
scene=$work/scene-20hz.yaml
write_wall_scene "$scene"

# measure LABEL TRANSPORT_ARGS DAEMON_ARGS: one ldoem-latency run against a fresh daemon.
measure() {
  local label=$1 link=$2; shift 2
  start_daemon "$scene" "$@"
  # shellcheck disable=SC2086
  "$client" $link --requests "$requests" | sed "s/^/label=$label-requests /"
  stop_daemon
  start_daemon "$scene" "$@"
  # shellcheck disable=SC2086
  "$client" $link --profiles "$seconds" | sed "s/^/label=$label-profiles /"
  stop_daemon
}

if [ "${LDOEM_IN_UML:-0}" = 1 ]; then
  for mode in virtual scale1; do
    for round in $(seq 1 "$rounds"); do
      for variant in $(variants_of_round "$round"); do
        emud=$(emud_of $variant)
        if [ $mode = virtual ]; then
          measure $variant-can-virtual "--can vcan0" --can can:vcan0 --virtual-time
        else
          measure $variant-can-scale1 "--can vcan0" --can can:vcan0 --time-scale 1
        fi
      done
    done
  done
  exit 0
fi

results=$work/results.txt
load_at_start=$(cut -d' ' -f1-3 /proc/loadavg)
: > "$results"
for mode in virtual scale1; do
  time_arguments=--virtual-time
  [ $mode = scale1 ] && time_arguments="--time-scale 1"
  for round in $(seq 1 "$rounds"); do
    for variant in $(variants_of_round "$round"); do
      emud=$(emud_of $variant)
      start_daemon "$scene" --no-can --tcp tcp:127.0.0.1:0 $time_arguments
      "$client" --tcp "127.0.0.1:$tcp_port" --requests "$requests" | sed "s/^/label=$variant-tcp-$mode-requests /" >> "$results"
      stop_daemon
      start_daemon "$scene" --no-can --tcp tcp:127.0.0.1:0 $time_arguments
      "$client" --tcp "127.0.0.1:$tcp_port" --profiles "$seconds" | sed "s/^/label=$variant-tcp-$mode-profiles /" >> "$results"
      stop_daemon
    done
  done
done
if [ $uml = 1 ]; then
  compare_arguments=()
  [ -n "$old_emud" ] && compare_arguments=(--compare "$old_emud" --rounds "$rounds")
  "$root/scripts/uml/run.sh" --timeout 900 -- "$0" "$build" --requests "$requests" --seconds "$seconds" \
    "${compare_arguments[@]}" | grep '^label=' >> "$results" || echo "bench-latency.sh: the vcan run in UML failed" >&2
fi

# key=value lines -> one table. A row measured in several rounds shows the median of its rounds.
field() {
  sed -n "s/.*[ ^]$1=\([^ ]*\).*/\1/p" <<< "$2" | sort -g |
    awk '{ v[NR] = $1; if ($1 ~ /\./) decimals = 1 }
         END { if (NR == 0) exit; if (NR % 2) print v[(NR + 1) / 2]
               else printf "%.*f\n", decimals, (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}
emud_column=
[ -n "$old_emud" ] && emud_column=" ldoem-emud |"
# The commit a daemon was built from, when its build folder sits in a git checkout.
commit_of() {
  local folder revision
  folder=$(dirname "$1")
  revision=$(git -C "$folder" rev-parse --short HEAD 2>/dev/null) || { echo "unknown commit"; return; }
  git -C "$folder" diff --quiet HEAD -- 2>/dev/null || revision+=" with uncommitted changes"
  echo "commit $revision"
}
report() {
  echo "| transport | time |$emud_column GET_STATUS median (us) | GET_STATUS p99 (us) | profiles/s | bytes/s |"
  echo "|---|---|$([ -n "$old_emud" ] && echo '---|')---|---|---|---|"
  ratios=
  for transport in tcp can; do
    for mode in virtual scale1; do
      where=host; [ $transport = can ] && where="vcan0 in UML"
      time_text="--virtual-time"; [ $mode = scale1 ] && time_text="--time-scale 1"
      for variant in $(variants_of_round 1); do
        req=$(grep "^label=$variant-$transport-$mode-requests " "$results" || true)
        pro=$(grep "^label=$variant-$transport-$mode-profiles " "$results" || true)
        [ -z "$req$pro" ] && continue
        which=; [ -n "$old_emud" ] && which=" $variant |"
        echo "| $transport ($where) | $time_text |$which $(field median_us "$req") | $(field p99_us "$req") | $(field profiles_per_s "$pro") | $(field bytes_per_s "$pro") |"
      done
      if [ -n "$old_emud" ]; then
        old_req=$(grep "^label=old-$transport-$mode-requests " "$results" || true)
        new_req=$(grep "^label=new-$transport-$mode-requests " "$results" || true)
        old_pro=$(grep "^label=old-$transport-$mode-profiles " "$results" || true)
        new_pro=$(grep "^label=new-$transport-$mode-profiles " "$results" || true)
        [ -z "$old_req$new_req" ] && continue
        ratios+="$transport $time_text: GET_STATUS median new/old $(ratio "$(field median_us "$new_req")" "$(field median_us "$old_req")"),"
        ratios+=" p99 new/old $(ratio "$(field p99_us "$new_req")" "$(field p99_us "$old_req")"),"
        ratios+=" profiles/s new/old $(ratio "$(field profiles_per_s "$new_pro")" "$(field profiles_per_s "$old_pro")")"$'\n'
      fi
    done
  done
  if [ -n "$old_emud" ]; then
    echo
    echo "Ratios (new = $new_emud, $(commit_of "$new_emud"); old = $old_emud, $(commit_of "$old_emud")):" | doc_paths
    printf '%s' "$ratios"
  fi
  echo
  echo "($requests GET_STATUS round trips; $seconds s of GET_PROFILE 0000 39ff at 20 Hz, 0.5 deg;$([ -n "$old_emud" ] && echo " $rounds round(s) per row, old and new interleaved;") $(nproc) CPUs, load average $load_at_start at the start, $(cut -d' ' -f1-3 /proc/loadavg) at the end)"
}
report > "$work/report.md"
cat "$work/report.md"
if [ -n "$doc" ]; then
  # The section between the markers becomes this run: the command, the date, the table.
  {
    echo "<!-- bench-latency:begin -->"
    echo "Written by \`$command_line\` on $(date -u '+%Y-%m-%d %H:%M UTC') (this section is the script's output; do not edit it by hand):"
    echo
    cat "$work/report.md"
    echo "<!-- bench-latency:end -->"
  } > "$work/section.md"
  replace_doc_section "$doc" bench-latency "$work/section.md"
  echo "bench-latency.sh: wrote the table into $doc" >&2
fi
