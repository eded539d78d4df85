#!/usr/bin/env bash
# The paper's experiment end to end (docs/paper-reproduction.md): start ldoem-emud on the corridor
# scene, scan it with ldoem-scan at the paper's settings, and print the fitted cylinder and wall
# beside the true values. Needs a vcan0 that is up (on a kernel without CAN, run it through
# scripts/uml/run.sh -- scripts/scan-corridor.sh), or `--transport tcp` on any machine.
set -euo pipefail

usage() {
  cat <<'EOF'
usage: scripts/scan-corridor.sh [--out-dir DIR] [--time-scale X | --virtual-time]
                                [--transport can|tcp] [--seed N] [--] [ldoem-scan options]

Starts ldoem-emud on scenes/corridor.yaml (CAN vcan0, tilt stepper on a pty), runs ldoem-scan
with the paper's settings (horizontal apex 20 deg at 0.25 deg, vertical apex 21.6 deg at
0.18 deg, 10 Hz; the scene adds range noise sigma 1.5 mm), writes DIR/corridor.ply and
DIR/corridor.png, and prints the fitted cylinder and wall beside the true values.

  --out-dir DIR       where the cloud and preview go (default: out)
  --time-scale X      the daemon's simulated seconds per wall second (default 1: real time)
  --virtual-time      the daemon's virtual clock: as fast as the CPU allows
  --transport can|tcp the scanner link: can (vcan0, the default) or tcp (127.0.0.1, any port)
  --seed N            the noise seed (default: the scene's, 2013)
  other arguments     passed on to ldoem-scan after the paper's settings (later ones win)

Environment: LDOEM_BUILD (build folder, default build/default), LDOEM_EMUD and LDOEM_SCAN
(the binaries themselves), LDOEM_READY_TIMEOUT (seconds to wait for the daemon, default 60).
Exit status: ldoem-scan's (0 scan written), or 1 when the daemon does not start.
EOF
}

cd "$(dirname "$0")/.."
build_dir="${LDOEM_BUILD:-build/default}"
emud="${LDOEM_EMUD:-$build_dir/emulator/daemon/ldoem-emud}"
scan="${LDOEM_SCAN:-$build_dir/driver/scan/ldoem-scan}"
ready_timeout_s="${LDOEM_READY_TIMEOUT:-60}"

out_dir=out
transport=can
clock_args=()
seed_args=()
scan_extra=()
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
    echo "scan-corridor: $binary is missing: build first (cmake --preset default && cmake --build --preset default) or set LDOEM_BUILD" >&2
    exit 1
  fi
done
case "$transport" in
  can) endpoint_args=(--can vcan0) ;;
  tcp) endpoint_args=(--no-can --tcp 127.0.0.1:0) ;;
  *) echo "scan-corridor: --transport must be can or tcp" >&2; exit 2 ;;
esac

mkdir -p "$out_dir"
work_dir="$(mktemp -d /tmp/ldoem-scan-corridor.XXXXXX)"
# The pty link lives inside the private mktemp folder: a predictable /tmp name could be taken
# (or pointed elsewhere) by another user first.
lpt_path="$work_dir/lpt"
daemon_pid=""

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
  rm -rf "$work_dir"
}
trap stop_daemon EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# --timeout: a daemon whose script was killed with SIGKILL still ends by itself.
"$emud" --scene scenes/corridor.yaml "${endpoint_args[@]}" --lpt "pty:$lpt_path" --no-flash \
  "${clock_args[@]}" "${seed_args[@]}" --timeout 3600 >"$work_dir/daemon.out" 2>"$work_dir/daemon.err" &
daemon_pid=$!

deadline=$((SECONDS + ready_timeout_s))
until grep -qx ready "$work_dir/daemon.out" 2>/dev/null; do
  if ! kill -0 "$daemon_pid" 2>/dev/null; then
    echo "scan-corridor: ldoem-emud stopped before it was ready:" >&2
    cat "$work_dir/daemon.err" >&2
    exit 1
  fi
  if ((SECONDS >= deadline)); then
    echo "scan-corridor: ldoem-emud not ready after ${ready_timeout_s} s" >&2
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

# The paper's settings (Koceski & Koceska 2013): 20 deg x 21.6 deg at 0.25 deg x 0.18 deg, 10 Hz.
scan_command=("$scan" --device "$device" --lpt "lpt:pty:$lpt_path"
  --horizontal-apex 20 --horizontal-resolution 0.25
  --vertical-apex 21.6 --vertical-resolution 0.18 --speed 10
  --out "$out_dir/corridor.ply" --preview "$out_dir/corridor.png" --fit "${scan_extra[@]}")
echo "scan-corridor: ${scan_command[*]}" >&2
started_ns=$(date +%s%N)
status=0
"${scan_command[@]}" >"$work_dir/scan.out" || status=$?
finished_ns=$(date +%s%N)
cat "$work_dir/scan.out"
wall_s=$(awk -v ns=$((finished_ns - started_ns)) 'BEGIN {printf "%.1f", ns / 1e9}')
echo "scan-corridor: ldoem-scan exit status $status after $wall_s s"

# "wall distance 4.1801 m (3488 points); cylinder diameter 0.1949 m, length 0.9958 m (1490 points)"
fit_line="$(grep -m1 '^wall distance' "$work_dir/scan.out" || true)"
if [[ $status -eq 0 && -n "$fit_line" ]]; then
  awk -v line="$fit_line" 'BEGIN {
    n = split(line, w, /[ ;,()]+/)
    for (i = 1; i <= n; ++i) {
      if (w[i] == "distance") wall = w[i + 1]
      if (w[i] == "diameter") diameter = w[i + 1]
      if (w[i] == "length") length_m = w[i + 1]
    }
    printf "%-19s %10s %10s %10s\n", "", "fitted", "true", "error"
    printf "%-19s %7.1f mm %7.1f mm %+7.1f mm\n", "cylinder diameter", diameter * 1000, 195.0, diameter * 1000 - 195.0
    printf "%-19s %8.4f m %8.3f m %+7.1f mm\n", "cylinder length", length_m, 0.998, (length_m - 0.998) * 1000
    printf "%-19s %8.4f m %8.3f m %+7.1f mm\n", "wall distance", wall, 4.180, (wall - 4.180) * 1000
  }'
fi
[[ $status -eq 0 ]] && echo "scan-corridor: wrote $out_dir/corridor.ply and $out_dir/corridor.png"
exit "$status"
