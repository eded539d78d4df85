#!/usr/bin/env bash
# Runs every libFuzzer target for longer than CI does, one after the other:
#   scripts/fuzz.sh [SECONDS_PER_TARGET=60] [--report docs/fuzzing.md]
# Builds the "fuzz" preset (clang, ASan+UBSan). Each target starts from its committed seeds
# (tests/fuzz/corpus/<target>, read only) and grows a corpus in build/fuzz/corpus/<target>.
# Prints, per target, the executions, the executions per second and new coverage; with
# --report it also writes those figures as a Markdown table. Exit status 1 if any target
# found a crash, a leak, a timeout or a broken invariant (its log is printed).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=60
report=""
while [ $# -gt 0 ]; do
  case "$1" in
    --report) report=${2:?--report needs a file}; shift 2 ;;
    -h|--help) sed -n '2,9p' "$0"; exit 0 ;;
    *[!0-9]*|'') echo "usage: scripts/fuzz.sh [SECONDS_PER_TARGET] [--report FILE]" >&2; exit 2 ;;
    *) seconds=$1; shift ;;
  esac
done
cache=${LDOEM_CACHE:-$HOME/.cache/ldoem}
export CCACHE_DIR=${CCACHE_DIR:-$cache/ccache} CCACHE_BASEDIR=$PWD CCACHE_NOHASHDIR=1
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz
status=0
rows=""
total=0
for target in build/fuzz/tests/fuzz/fuzz_*; do
  [ -x "$target" ] || continue
  name=$(basename "$target")
  corpus="build/fuzz/corpus/$name"
  mkdir -p "$corpus"
  seeds=()
  [ -d "tests/fuzz/corpus/$name" ] && seeds=("tests/fuzz/corpus/$name")
  echo "=== $name for ${seconds}s"
  log="build/fuzz/corpus/$name.log"
  if /usr/bin/time -f '%U %S' -o "$log.cpu" "$target" -max_total_time="$seconds" -max_len=8192 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
      "$corpus" "${seeds[@]}" >"$log" 2>&1; then
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
    cov=$(grep -oE 'cov: [0-9]+' "$log" | tail -n 1 | cut -d' ' -f2)
    units=$(find "$corpus" -type f | wc -l)
    # The last line of /usr/bin/time's output; the parentheses keep awk from reading the ">" of
    # the condition as a redirection to a file.
    cpu=$(awk 'END {printf "%.0f", $1 + $2}' "$log.cpu")
    per_cpu=$(awk -v e="$execs" 'END {c = $1 + $2; printf "%.0f", (c > 0 ? e / c : 0)}' "$log.cpu")
    echo "    $execs executions, $rate per second ($per_cpu per CPU second), coverage $cov, corpus $units files"
    rows+="| \`$name\` | $seconds | $cpu | $execs | $rate | $per_cpu | $cov | $units |"$'\n'
    total=$((total + execs))
  else
    tail -n 40 "$log"; echo "fuzz: $name FAILED (log: $log)" >&2; status=1
    rows+="| \`$name\` | $seconds | | FAILED | | | | |"$'\n'
  fi
done
if [ -n "$report" ]; then
  {
    echo "# Fuzzing"
    echo
    echo "Written by \`scripts/fuzz.sh $seconds --report $report\` on $(date -u +%Y-%m-%d) ($(nproc) cores,"
    echo "$(clang --version | head -n 1); each target built with libFuzzer, ASan and UBSan, run alone"
    echo "for $seconds s from its committed seeds in \`tests/fuzz/corpus/\`, one process, no -jobs). CI runs"
    echo "every target for 20000 executions in the asan build (\`ctest --preset asan -L fuzz\`, docs/ci.md)."
    echo
    echo "Load average at the end: $(cut -d' ' -f1-3 /proc/loadavg). Executions per second are wall-clock"
    echo "figures: on a shared machine they say as much about the other load as about the code;"
    echo "executions per CPU second (user + system time of the fuzzer, from /usr/bin/time) do not."
    echo
    echo "| Target | Seconds | CPU seconds | Executions | Executions/s | Executions per CPU second | Coverage (edges) | Corpus files |"
    echo "|---|---:|---:|---:|---:|---:|---:|---:|"
    printf '%s' "$rows"
    echo
    echo "Total: $total executions. What each target checks is in the comment at the top of its"
    echo "source in \`tests/fuzz/\`: no crash or undefined behaviour, and the invariants stated there"
    echo "(round trips for the codecs and parsers; for the control unit one reply or the documented"
    echo "silence per request and the state table)."
  } >"$report"
  echo "fuzz: wrote $report"
fi
exit $status
