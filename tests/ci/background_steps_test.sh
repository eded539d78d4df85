#!/usr/bin/env bash
# scripts/lib/background-steps.sh, which scripts/test.sh runs its background steps with: a step's
# exit status reaches the foreground, a failed step shows its log, the time printed is the
# step's own (not how long the foreground took to get to it), and bg_stop_all stops a step with
# everything it started (the whole process group), as the EXIT trap of test.sh needs.
# Usage: background_steps_test.sh SOURCE_DIR
set -u
source "$1/scripts/lib/background-steps.sh"
work=$(mktemp -d "${TMPDIR:-/tmp}/ldoem-bg-test.XXXXXX")
trap 'bg_stop_all; rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

bg_start ok "$work/ok.log" true
bg_start broken "$work/broken.log" nice 5 bash -c 'echo the-reason-it-broke; exit 3'
sleep 2
out=$(bg_finish ok 2>&1); status=$?
[ "$status" -eq 0 ] || fail "a step that succeeded returned $status: $out"
seconds=$(sed -n 's/^=== ok (background): \([0-9]*\) s, exit 0, .*/\1/p' <<<"$out")
[ -n "$seconds" ] || fail "no time line for the step that succeeded: $out"
# `true` ends at once; the foreground got to it after 2 s. The step's own time must show.
[ -n "$seconds" ] && [ "$seconds" -gt 1 ] && fail "the step's time is the foreground's ($seconds s)"

out=$(bg_finish broken 2>&1); status=$?
[ "$status" -eq 3 ] || fail "a step that exited 3 returned $status"
grep -q 'the-reason-it-broke' <<<"$out" || fail "a failed step's log was not shown: $out"
grep -q 'exit 3' <<<"$out" || fail "a failed step's exit status was not printed: $out"

bg_finish never-started >/dev/null 2>&1
[ $? -eq 2 ] || fail "finishing an unknown step is not a usage error"

# A niced step is niced as a CPU group too: with autogroup scheduling its new session is a group
# of its own, which the processes' nice alone does not lower against the foreground.
if [ -r /proc/self/autogroup ]; then
  bg_start niced "$work/niced.log" nice 7 cat /proc/self/autogroup
  bg_finish niced >/dev/null 2>&1 || fail "the niced step failed: $(cat "$work/niced.log")"
  # nice -n adds to the caller's niceness (ctest may itself run niced), capped at 19.
  expected=$(( $(nice) + 7 > 19 ? 19 : $(nice) + 7 ))
  grep -q "nice $expected\$" "$work/niced.log" ||
    fail "the niced step's autogroup is not niced to $expected: $(cat "$work/niced.log")"
else
  echo "no /proc/self/autogroup (kernel without autogroup scheduling): group nice not checked"
fi

# A step that started a child of its own: stopping it must stop the child too.
bg_start sleeper "$work/sleeper.log" bash -c 'sleep 300 & echo $! >'"$work"'/child.pid; wait'
for _ in $(seq 50); do [ -s "$work/child.pid" ] && break; sleep 0.1; done
child=$(cat "$work/child.pid" 2>/dev/null)
[ -n "$child" ] || fail "the sleeper step did not start its child"
bg_stop_all
if [ -n "$child" ]; then
  for _ in $(seq 50); do kill -0 "$child" 2>/dev/null || break; sleep 0.1; done
  kill -0 "$child" 2>/dev/null && { fail "bg_stop_all left the step's child $child running"; kill "$child"; }
fi
[ -z "${bg_pid[sleeper]:-}" ] || fail "bg_stop_all left the step in its table"

[ "$failures" -eq 0 ] && echo "background steps: all checks passed"
exit $((failures > 0))
