# shellcheck shell=bash
# Steps of scripts/test.sh that run in the background beside the foreground steps, sourced by
# bash. Each background step runs in its own process group (setsid), so that stopping it stops
# everything it started (mmdebstrap, systemd-nspawn, podman, make), and writes its output to its
# own log, which is shown only when it fails. Its wall time is its own, measured from its start
# to its end, and printed when the foreground waits for it, so a CI log still says where the
# time went.
#
#   bg_start NAME LOG [nice N] CMD ARGS...   start CMD in the background (at nice N if given)
#   bg_finish NAME                            wait for it; print its time and exit status; on
#                                             failure the last 60 lines of its log; returns its
#                                             exit status
#   bg_stop_all                               stop every background step still running (for an
#                                             EXIT trap); quiet when there is none
#
# Bash only (associative arrays). A step's end time is written by the step itself into
# LOG.seconds, so bg_finish reports when the step ended, not when the foreground got to it.

declare -A bg_pid=() bg_log=()

bg_start() {  # NAME LOG [nice N] CMD ARGS...
  local name=$1 log=$2
  shift 2
  local niceness=0
  if [ "${1:-}" = nice ]; then niceness=$2; shift 2; fi
  [ -z "${bg_pid[$name]:-}" ] || { echo "bg_start: '$name' is already running" >&2; return 2; }
  mkdir -p "$(dirname "$log")"
  rm -f "$log.seconds"
  # setsid --wait: the step leads its own process group; bash's $SECONDS counts from that
  # shell's start, so the step measures itself. (Single quotes: the inner bash expands them.)
  # shellcheck disable=SC2016
  # A new session is its own autogroup (CPU group) where the kernel has autogroup scheduling:
  # its nice is set as well as the processes', or a niced step would still take a group's share.
  setsid --wait nice -n "$niceness" bash -c '[ "$(nice)" -gt 0 ] && echo "$(nice)" >/proc/self/autogroup 2>/dev/null
    "$@" >"$0" 2>&1; status=$?
    echo "$SECONDS $status" >"$0.seconds"; exit $status' "$log" "$@" </dev/null &
  bg_pid[$name]=$!
  bg_log[$name]=$log
  printf '=== %s: started in the background (log %s)\n' "$name" "$log"
}

bg_finish() {  # NAME
  local name=$1 pid=${bg_pid[$1]:-} log=${bg_log[$1]:-} status=0 waited=$SECONDS
  [ -n "$pid" ] || { echo "bg_finish: no background step '$name'" >&2; return 2; }
  wait "$pid" || status=$?
  unset "bg_pid[$name]"
  local seconds="?"
  [ -f "$log.seconds" ] && seconds=$(cut -d' ' -f1 "$log.seconds")
  printf '=== %s (background): %s s, exit %d, waited for %d s\n' "$name" "$seconds" "$status" \
    $((SECONDS - waited))
  if [ "$status" -ne 0 ]; then
    echo "=== $name failed; the end of $log:" >&2
    tail -n 60 "$log" >&2
  fi
  return "$status"
}

bg_stop_all() {
  local name
  for name in "${!bg_pid[@]}"; do
    kill -TERM -- "-${bg_pid[$name]}" 2>/dev/null || true
  done
  for name in "${!bg_pid[@]}"; do
    wait "${bg_pid[$name]}" 2>/dev/null || true
    unset "bg_pid[$name]"
  done
}
