#!/usr/bin/env bash
# scripts/test.sh on a busy machine, the normal case in shared CI runners (issue 23): stress-ng
# loads the machine alongside (`--cpu 2 --io 1`: on 2 cores a load average of about 4 to 5) for
# the whole run and is stopped on exit, whatever happens. Prints the load averages before,
# every 5 minutes, and after, and the conformance runs' inconclusive counts (docs/ci.md).
#   scripts/test-under-load.sh [STRESS-NG ARGS...]     (default: --cpu 2 --io 1)
# Exit status: scripts/test.sh's.
set -uo pipefail
cd "$(dirname "$0")/.."
stress_args=("$@")
((${#stress_args[@]})) || stress_args=(--cpu 2 --io 1)
command -v stress-ng >/dev/null || scripts/install-deps.sh
mkdir -p build
log=build/test-under-load.log
stress_pid="" sampler_pid=""
stop() {
  # Each runs in its own process group (setsid): the group goes, workers included.
  for pid in $stress_pid $sampler_pid; do kill -- -"$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true; done
  stress_pid="" sampler_pid=""
}
trap stop EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

echo "test-under-load: load average before: $(cut -d' ' -f1-3 /proc/loadavg); stress-ng ${stress_args[*]}"
setsid stress-ng "${stress_args[@]}" --timeout 0 >/dev/null 2>&1 &
stress_pid=$!
setsid bash -c 'while sleep 300; do echo "test-under-load: load average $(cut -d" " -f1-3 /proc/loadavg)"; done' &
sampler_pid=$!
# run-against-daemon.sh appends each conformance run's summary here (plain, UML and ASan builds).
summaries=(build/default/tools/conformance/summaries.log build/asan/tools/conformance/summaries.log)
rm -f "${summaries[@]}"
started=$SECONDS
scripts/test.sh 2>&1 | tee "$log"
status=${PIPESTATUS[0]}
load_during=$(cut -d' ' -f1-3 /proc/loadavg)
stop
echo "test-under-load: load average at the end (stress-ng still on): $load_during"
echo "test-under-load: scripts/test.sh exit $status after $((SECONDS - started)) s"
# The conformance runs' summaries: inconclusive cases are the machine's, not the device's.
cat "${summaries[@]}" 2>/dev/null | sed 's/^/test-under-load: conformance /'
total=$(cat "${summaries[@]}" 2>/dev/null | sed -n 's/.* \([0-9]*\) inconclusive$/\1/p' | awk '{ n += $1 } END { print n + 0 }')
echo "test-under-load: $total inconclusive conformance case(s) in all"
exit "$status"
