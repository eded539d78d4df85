#!/usr/bin/env bash
# Runs every libFuzzer target for longer than CI does: scripts/fuzz.sh [SECONDS_PER_TARGET=60].
# Builds the "fuzz" preset (clang, ASan+UBSan); a corpus per target is kept in build/fuzz/corpus/,
# seeded from tests/fuzz/corpus/<target>/ where that exists.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
case "$seconds" in ''|*[!0-9]*) echo "usage: scripts/fuzz.sh [SECONDS_PER_TARGET]" >&2; exit 2;; esac
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz
status=0
for target in build/fuzz/tests/fuzz/fuzz_*; do
  [ -x "$target" ] || continue
  name=$(basename "$target")
  mkdir -p "build/fuzz/corpus/$name"
  echo "=== $name for ${seconds}s"
  log="build/fuzz/corpus/$name.log"
  seeds=()
  [ -d "tests/fuzz/corpus/$name" ] && seeds=("tests/fuzz/corpus/$name")
  if "$target" -max_total_time="$seconds" -max_len=8192 -print_final_stats=1 "build/fuzz/corpus/$name" "${seeds[@]}" >"$log" 2>&1; then
    grep -E '^(#[0-9]+.*DONE|stat::number_of_executed_units)' "$log" || true
  else
    tail -n 40 "$log"; echo "fuzz: $name FAILED (log: $log)" >&2; status=1
  fi
done
exit $status
