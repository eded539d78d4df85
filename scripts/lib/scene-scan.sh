# Sourced by scripts/scan-corridor.sh and scripts/scan-warehouse.sh: start ldoem-emud on a scene
# with its tilt stepper on a private pty, wait until it is ready, run ldoem-scan against it, and
# stop the daemon on any exit. The caller sets `tool` (its name for messages), `transport` (its
# default) and a `usage` function before sourcing, then calls the functions in order.

build_dir="${LDOEM_BUILD:-build/default}"
emud="${LDOEM_EMUD:-$build_dir/emulator/daemon/ldoem-emud}"
scan="${LDOEM_SCAN:-$build_dir/driver/scan/ldoem-scan}"
ready_timeout_s="${LDOEM_READY_TIMEOUT:-60}"
out_dir=out
clock_args=()
seed_args=()
scan_extra=()
daemon_pid=""
work_dir=""

# The options both scripts share; anything else goes to ldoem-scan.
scene_scan_parse_args() {
  while [[ $# -gt 0 ]]; do
    case "$1" in
      --out-dir) out_dir="$2"; shift 2 ;;
      --time-scale) clock_args=(--time-scale "$2"); shift 2 ;;
      --virtual-time) clock_args=(--virtual-time); shift ;;
      --transport) transport="$2"; shift 2 ;;
      --seed) seed_args=(--seed "$2"); shift 2 ;;
      -h|--help) usage; exit 0 ;;
      --) shift; scan_extra+=("$@"); break ;;
      *) scan_extra+=("$1"); shift ;;
    esac
  done
  for binary in "$emud" "$scan"; do
    if [[ ! -x "$binary" ]]; then
      echo "$tool: $binary is missing: build first (cmake --preset default && cmake --build --preset default) or set LDOEM_BUILD" >&2
      exit 1
    fi
  done
  case "$transport" in
    can) endpoint_args=(--can can:vcan0) ;;
    tcp) endpoint_args=(--no-can --tcp tcp:127.0.0.1:0) ;;
    *) echo "$tool: --transport must be can or tcp" >&2; exit 2 ;;
  esac
}

stop_daemon() {
  if [[ -n "$daemon_pid" ]] && kill -0 "$daemon_pid" 2>/dev/null; then
    kill -TERM "$daemon_pid" 2>/dev/null || true
    for _ in $(seq 50); do
      kill -0 "$daemon_pid" 2>/dev/null || break
      sleep 0.1
    done
    kill -KILL "$daemon_pid" 2>/dev/null || true
    wait "$daemon_pid" 2>/dev/null || true
  fi
  [[ -n "$work_dir" ]] && rm -rf "$work_dir"
}

# scene_scan_start_daemon SCENE: sets work_dir, lpt_path and device.
scene_scan_start_daemon() {
  mkdir -p "$out_dir"
  work_dir="$(mktemp -d "/tmp/ldoem-$tool.XXXXXX")"
  # The pty link lives inside the private mktemp folder: a predictable /tmp name could be taken
  # (or pointed elsewhere) by another user first.
  lpt_path="$work_dir/lpt"
  trap stop_daemon EXIT
  trap 'exit 130' INT
  trap 'exit 143' TERM
  # --timeout: a daemon whose script was killed with SIGKILL still ends by itself.
  "$emud" --scene "$1" "${endpoint_args[@]}" --lpt "lpt:pty:$lpt_path" --no-flash \
    "${clock_args[@]}" "${seed_args[@]}" --timeout 3600 >"$work_dir/daemon.out" 2>"$work_dir/daemon.err" &
  daemon_pid=$!
  local deadline=$((SECONDS + ready_timeout_s))
  until grep -qx ready "$work_dir/daemon.out" 2>/dev/null; do
    if ! kill -0 "$daemon_pid" 2>/dev/null; then
      echo "$tool: ldoem-emud stopped before it was ready:" >&2
      cat "$work_dir/daemon.err" >&2
      exit 1
    fi
    if ((SECONDS >= deadline)); then
      echo "$tool: ldoem-emud not ready after ${ready_timeout_s} s" >&2
      cat "$work_dir/daemon.err" >&2
      exit 1
    fi
    sleep 0.05
  done
  sed 's/^/ldoem-emud: /' "$work_dir/daemon.out" >&2
  if [[ "$transport" == can ]]; then
    device=can:vcan0
  else
    device="tcp:$(awk '$1 == "tcp" {print $2}' "$work_dir/daemon.out")"
  fi
}

# scene_scan_run SETTINGS...: ldoem-scan with the caller's settings, then the user's extra
# arguments (later ones win); its output is in $work_dir/scan.out, its exit status in `status`.
scene_scan_run() {
  local scan_command=("$scan" --device "$device" --lpt "lpt:pty:$lpt_path" "$@" "${scan_extra[@]}")
  echo "$tool: ${scan_command[*]}" >&2
  local started_ns finished_ns wall_s
  started_ns=$(date +%s%N)
  status=0
  "${scan_command[@]}" >"$work_dir/scan.out" || status=$?
  finished_ns=$(date +%s%N)
  cat "$work_dir/scan.out"
  wall_s=$(awk -v ns=$((finished_ns - started_ns)) 'BEGIN {printf "%.1f", ns / 1e9}')
  echo "$tool: ldoem-scan exit status $status after $wall_s s"
}
