# Sourced by scripts/bench-latency.sh and scripts/bench-wire-fault-hook.sh: a scratch folder, the
# 20 Hz, 0.5 deg wall scene both measure, one ldoem-emud at a time with its ready wait, and the
# ratio of two figures. The caller sets `tool` (its name for messages) and `emud` (the daemon to
# start; it may change between runs) before calling start_daemon.

work=$(mktemp -d "/tmp/ldoem-$tool.XXXXXX")
daemon_pid=
cleanup() {
  if [ -n "$daemon_pid" ]; then kill "$daemon_pid" 2>/dev/null || true; wait "$daemon_pid" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT

# write_wall_scene FILE: a wall 5 m ahead, the flash at 20 Hz and 0.5 deg (D4 defaults otherwise).
write_wall_scene() {
  cat > "$1" <<'YAML'
scanner:
  flash: {motor_speed_hz: 20, angle_step_ticks: 8}
objects:
  - name: wall
    box: {size_m: [0.2, 20, 6]}
    pose: {position_m: [5.1, 0, 0]}
    reflectance: 0.8
YAML
}

# start_daemon SCENE ARGS...: runs $emud on SCENE, waits for "ready", sets daemon_pid and tcp_port.
start_daemon() {
  local scene=$1 out=$work/daemon.out
  shift
  "$emud" --scene "$scene" --no-flash --timeout 600 "$@" > "$out" 2> "$work/daemon.err" &
  daemon_pid=$!
  # Up to 30 s: a loaded machine (or UML) can take a while to build even a small scene.
  for _ in $(seq 1 600); do
    grep -q '^ready$' "$out" 2>/dev/null && break
    kill -0 "$daemon_pid" 2>/dev/null || break
    sleep 0.05
  done
  grep -q '^ready$' "$out" ||
    { echo "$tool: $emud $* not ready; its output: $(cat "$out") $(cat "$work/daemon.err")" >&2; exit 1; }
  tcp_port=$(sed -n 's/^tcp .*:\([0-9]*\)$/\1/p' "$out")
}
stop_daemon() { kill "$daemon_pid" 2>/dev/null || true; wait "$daemon_pid" 2>/dev/null || true; daemon_pid=; }

# ratio A B: A / B to three places, or "-" when either is missing.
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (a == "" || b == "" || b == 0) print "-"; else printf "%.3f", a / b }'; }
