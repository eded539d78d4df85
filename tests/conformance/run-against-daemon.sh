#!/bin/bash
# Start ldoem-emud on one transport, run ldoem-conformance against it, always stop the daemon.
#
# Usage:
#   run-against-daemon.sh --daemon EMUD --suite SUITE --scene FILE --transport tcp|serial|can
#                         [--time-scale X | --virtual-time] [--timeout SECONDS] [--can-if IF]
#                         [--proxy PROXY SLIP_MS] [-- SUITE-ARGS...]
#   tcp:    the daemon listens on 127.0.0.1, port 0 (a free port it prints), --no-can
#   serial: the daemon's serial pty is symlinked in a temporary folder, --no-can
#   can:    the daemon and the suite use IF (default vcan0): run inside scripts/uml/run.sh
# The daemon always runs with --no-flash, so every run starts from the D4 power-up defaults.
# --virtual-time runs the daemon's clock virtually (ldoem-emud --virtual-time) and tells the suite
# so: device-clock values are then exact, and nothing is judged on the wall clock.
# --proxy (tcp only) puts tests/conformance/test/clock_slip_proxy between suite and daemon: a
# device double whose profile times slip SLIP_MS per profile (0: passed through unchanged).
# --timeout bounds the whole suite run (default 480 s); the daemon gets 10 s to say "ready".
# Exit status: the suite's (0 all passed, 1 a case failed, 2 usage); 3 when the daemon did not
# start; 124 when the suite timed out.
set -uo pipefail

daemon="" suite="" scene="" transport="" time_scale=10 timeout_s=480 can_if=vcan0 clock=() proxy="" slip_ms=0
while (($#)); do
  case "$1" in
    --daemon) daemon=$2; shift 2 ;;
    --suite) suite=$2; shift 2 ;;
    --scene) scene=$2; shift 2 ;;
    --transport) transport=$2; shift 2 ;;
    --time-scale) time_scale=$2; shift 2 ;;
    --virtual-time) clock=(--virtual-time); shift ;;
    --timeout) timeout_s=$2; shift 2 ;;
    --can-if) can_if=$2; shift 2 ;;
    --proxy) proxy=$2; slip_ms=$3; shift 3 ;;
    --) shift; break ;;
    *) echo "run-against-daemon.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
done
[[ -x $daemon && -x $suite && -r $scene ]] || { echo "run-against-daemon.sh: need --daemon, --suite, --scene" >&2; exit 2; }

work=$(mktemp -d /tmp/ldoem-conformance.XXXXXX)
daemon_pid="" proxy_pid=""
stop_daemon() {
  [[ -n $proxy_pid ]] && { kill -KILL "$proxy_pid" 2>/dev/null; wait "$proxy_pid" 2>/dev/null; }
  if [[ -n $daemon_pid ]] && kill -0 "$daemon_pid" 2>/dev/null; then
    kill -TERM "$daemon_pid" 2>/dev/null
    for _ in $(seq 30); do kill -0 "$daemon_pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$daemon_pid" 2>/dev/null
    wait "$daemon_pid" 2>/dev/null
  fi
  rm -rf "$work"
}
trap stop_daemon EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

daemon_args=(--scene "$scene" --no-flash --time-scale "$time_scale" "${clock[@]}")
case "$transport" in
  tcp) daemon_args+=(--no-can --tcp tcp:127.0.0.1:0) ;;
  serial) daemon_args+=(--no-can --serial "serial:pty:$work/serial") ;;
  can) daemon_args+=(--can "can:$can_if") ;;
  *) echo "run-against-daemon.sh: --transport must be tcp, serial or can" >&2; exit 2 ;;
esac

"$daemon" "${daemon_args[@]}" >"$work/daemon.out" 2>"$work/daemon.err" &
daemon_pid=$!
for _ in $(seq 100); do
  grep -qx ready "$work/daemon.out" 2>/dev/null && break
  kill -0 "$daemon_pid" 2>/dev/null || break
  sleep 0.1
done
if ! grep -qx ready "$work/daemon.out" 2>/dev/null; then
  echo "run-against-daemon.sh: ldoem-emud did not become ready: ${daemon_args[*]}" >&2
  cat "$work/daemon.out" "$work/daemon.err" >&2
  exit 3
fi

case "$transport" in
  tcp)
    address=$(sed -n 's/^tcp \(.*\)$/\1/p' "$work/daemon.out" | head -n 1)
    if [[ -n $proxy ]]; then
      "$proxy" "${address##*:}" "$slip_ms" >"$work/proxy.out" 2>&1 &
      proxy_pid=$!
      for _ in $(seq 100); do grep -qx ready "$work/proxy.out" 2>/dev/null && break; sleep 0.1; done
      grep -qx ready "$work/proxy.out" || { echo "run-against-daemon.sh: the proxy did not start" >&2; cat "$work/proxy.out" >&2; exit 3; }
      echo "clock_slip_proxy ${address##*:} $slip_ms"
      address=$(sed -n 's/^tcp \(.*\)$/\1/p' "$work/proxy.out" | head -n 1)
    fi
    suite_args=(--tcp "tcp:$address") ;;
  serial) suite_args=(--serial "serial:pty:$work/serial") ;;
  can) suite_args=(--can "can:$can_if") ;;
esac

echo "ldoem-emud ${daemon_args[*]}"
echo "ldoem-conformance ${suite_args[*]} --target emulator --time-scale $time_scale ${clock[*]} $*"
timeout --kill-after=5 "$timeout_s" "$suite" "${suite_args[@]}" --target emulator --time-scale "$time_scale" \
  "${clock[@]}" "$@" | tee "$work/suite.out"
status=${PIPESTATUS[0]}
# The summary and any INCONCLUSIVE case, kept next to the suite for scripts/test-under-load.sh
# (ctest shows a passing test's output nowhere else).
{ grep -E '^(INCONCLUSIVE |[0-9]+ passed, )' "$work/suite.out" | sed "s|^|$transport $*: |"; } \
  >>"$(dirname "$suite")/summaries.log" 2>/dev/null || true
if ((status != 0)) && [[ -s $work/daemon.err ]]; then
  echo "--- ldoem-emud stderr (last 20 lines) ---"
  tail -n 20 "$work/daemon.err"
fi
exit "$status"
