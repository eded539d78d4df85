#!/usr/bin/env bash
# Replays the hostile and unlucky inputs of issue 27 against the built programs and checks that
# each gives a clear error or a bounded result (peak memory from /proc/PID/status VmHWM, time,
# and the daemon still answering GET_STATUS over TCP). Prints one markdown table row per case.
#
# Usage: scripts/hostile.sh [--build-dir DIR] [--budget-s N] [--only REGEX] [--write-doc] [--help]
#   --build-dir DIR  where the programs are built (default build/default)
#   --budget-s N     total time for all cases (default 300); a case gets at most what is left,
#                    and at most 90 s; cases not reached in time are listed as skipped
#   --only REGEX     run only the cases whose id matches (e.g. d01)
#   --write-doc      rewrite the table in docs/robustness.md between its hostile markers
# Exit status: 0 when every case that ran is ok, 1 when one failed, 2 on a usage error.
#
# Cases live in scripts/hostile/*.sh: lib.sh (helpers) is sourced first, then every other file;
# each case is a function hostile_case_<id> that prints exactly one row
# `| D1 | what was sent | what happened | ok |` and returns 0 when ok, 1 when not. Each case runs
# in its own bash process and process group, killed when it overruns.
set -uo pipefail
cd "$(dirname "$0")/.." || exit 2
build=build/default budget=300 only="" write_doc=0
usage() { sed -n 2,17p "$0" | sed 's/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build=${2:?}; shift 2;;
    --budget-s) budget=${2:?}; shift 2;;
    --only) only=${2:?}; shift 2;;
    --write-doc) write_doc=1; shift;;
    -h|--help) usage; exit 0;;
    *) echo "hostile.sh: unknown option $1 (see --help)" >&2; exit 2;;
  esac
done
[[ "$budget" =~ ^[0-9]+$ && "$budget" -gt 0 && "$budget" -le 3600 ]] || {
  echo "hostile.sh: --budget-s must be an integer in [1, 3600]" >&2; exit 2; }
export HOSTILE_EMUD=$PWD/$build/emulator/daemon/ldoem-emud
export HOSTILE_REPLAY=$PWD/$build/emulator/device/replay/ldoem-replay
export HOSTILE_HUB=$PWD/$build/driver/hub/ldoem-hub
export HOSTILE_ROOT=$PWD
[ -x "$HOSTILE_EMUD" ] || { echo "hostile.sh: $HOSTILE_EMUD not built (cmake --build --preset default)" >&2; exit 2; }

case_files=(scripts/hostile/lib.sh)
for file in scripts/hostile/*.sh; do
  [ "$file" = scripts/hostile/lib.sh ] || case_files+=("$file")
done
# shellcheck disable=SC1090
for file in "${case_files[@]}"; do source "$file"; done
mapfile -t cases < <(declare -F | awk '{print $3}' | grep '^hostile_case_' | sort)
[ -z "$only" ] || mapfile -t cases < <(printf '%s\n' "${cases[@]}" | grep -E "$only")
[ ${#cases[@]} -gt 0 ] || { echo "hostile.sh: no case to run" >&2; exit 2; }

work=$(mktemp -d /tmp/ldoem-hostile.XXXXXX)
running=
trap '[ -n "$running" ] && kill -KILL -- -"$running" 2>/dev/null; rm -rf "$work"' EXIT
started=$SECONDS
rows=() passed=0 failed=0 skipped=0
for name in "${cases[@]}"; do
  id=${name#hostile_case_}
  left=$((budget - (SECONDS - started)))
  if [ "$left" -le 2 ]; then
    rows+=("| ${id} | - | not run: the budget of ${budget} s was spent | skipped |")
    skipped=$((skipped + 1))
    continue
  fi
  limit=$((left < 90 ? left : 90))
  mkdir -p "$work/$id"
  export HOSTILE_WORK=$work/$id
  # Its own session and process group: on overrun the case and every daemon it started go.
  # shellcheck disable=SC2016  # $@ is the inner shell's
  setsid bash -c 'for f in "$@"; do source "$f"; done; '"$name" hostile \
    "${case_files[@]/#/$PWD/}" >"$work/$id.row" 2>"$work/$id.log" </dev/null &
  running=$!
  status=
  for _ in $(seq $((limit * 10))); do
    kill -0 "$running" 2>/dev/null || break
    sleep 0.1
  done
  if kill -0 "$running" 2>/dev/null; then
    kill -KILL -- -"$running" 2>/dev/null
    wait "$running" 2>/dev/null
    rows+=("| ${id} | - | did not finish within ${limit} s | FAIL |")
    failed=$((failed + 1))
  else
    wait "$running"
    status=$?
    row=$(grep -m1 '^|' "$work/$id.row")
    if [ -z "$row" ]; then
      row="| ${id} | - | printed no row (exit ${status}): $(tail -n1 "$work/$id.log" | cut -c1-100) | FAIL |"
      status=1
    fi
    rows+=("$row")
    if [ "$status" -eq 0 ]; then passed=$((passed + 1)); else failed=$((failed + 1)); fi
    [ "$status" -eq 0 ] || sed 's/^/  /' "$work/$id.log" | tail -n 20 >&2
  fi
  running=
  printf '%s\n' "${rows[-1]}"
done
elapsed=$((SECONDS - started))

table=$(printf '| defect | what was sent | what happened | verdict |\n|---|---|---|---|\n'; printf '%s\n' "${rows[@]}")
if [ "$write_doc" -eq 1 ]; then
  doc=docs/robustness.md
  if ! grep -q '<!-- hostile:begin -->' "$doc" || ! grep -q '<!-- hostile:end -->' "$doc"; then
    echo "hostile.sh: $doc has no hostile markers" >&2
    exit 2
  fi
  summary="From \`scripts/hostile.sh --write-doc\` ($(date -u +%Y-%m-%d), git $(git rev-parse --short HEAD 2>/dev/null || echo '?'), ${elapsed} s, load $(cut -d' ' -f1 /proc/loadavg)): ${passed} ok, ${failed} failed, ${skipped} skipped."
  awk -v table="$table" -v summary="$summary" '
    /<!-- hostile:begin -->/ { print; print ""; print summary; print ""; print table; print ""; skip = 1; next }
    /<!-- hostile:end -->/ { skip = 0 }
    !skip { print }' "$doc" >"$work/doc" && cat "$work/doc" >"$doc"
  echo "hostile.sh: wrote the table into $doc"
fi
echo "hostile: ${elapsed} s of a budget of ${budget} s"
echo "hostile: ${passed} passed, ${failed} failed, ${skipped} skipped"
[ "$failed" -eq 0 ]
