#!/usr/bin/env bash
# The D12 demo (docs/dynamic-scenes.md): start ldoem-emud on scenes/warehouse.yaml, where things
# move and the scanner rides a cart, scan it with ldoem-scan and render the cloud (--render).
# TCP by default; `--transport can` needs a vcan0 that is up.
set -euo pipefail

usage() {
  cat <<'EOF'
usage: scripts/scan-warehouse.sh [--out-dir DIR] [--time-scale X | --virtual-time]
                                [--transport can|tcp] [--seed N] [--] [ldoem-scan options]

Starts ldoem-emud on scenes/warehouse.yaml (D12: a walking person, a swinging door, a rolling
ball, a fallen crate, and the scanner on a cart driving past at 0.25 m/s), runs ldoem-scan over
a 180 deg x 40 deg field (0.5 deg x 0.36 deg, 10 Hz) and writes DIR/warehouse.ply, the range
image DIR/warehouse-range.png and the perspective view DIR/warehouse.png (--render).

  --out-dir DIR       where the cloud and preview go (default: out)
  --time-scale X      the daemon's simulated seconds per wall second (default 1: real time)
  --virtual-time      the daemon's virtual clock: as fast as the CPU allows
  --transport can|tcp the scanner link: tcp (127.0.0.1, any port; the default) or can (vcan0)
  --seed N            the noise seed (default: the scene's, 2013)
  other arguments     passed on to ldoem-scan after the demo's settings (later ones win)

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
transport=tcp
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
    echo "scan-warehouse: $binary is missing: build first (cmake --preset default && cmake --build --preset default) or set LDOEM_BUILD" >&2
    exit 1
  fi
done
case "$transport" in
  can) endpoint_args=(--can vcan0) ;;
  tcp) endpoint_args=(--no-can --tcp 127.0.0.1:0) ;;
  *) echo "scan-warehouse: --transport must be can or tcp" >&2; exit 2 ;;
esac

mkdir -p "$out_dir"
work_dir="$(mktemp -d /tmp/ldoem-scan-warehouse.XXXXXX)"
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
"$emud" --scene scenes/warehouse.yaml "${endpoint_args[@]}" --lpt "pty:$lpt_path" --no-flash \
  "${clock_args[@]}" "${seed_args[@]}" --timeout 3600 >"$work_dir/daemon.out" 2>"$work_dir/daemon.err" &
daemon_pid=$!

deadline=$((SECONDS + ready_timeout_s))
until grep -qx ready "$work_dir/daemon.out" 2>/dev/null; do
  if ! kill -0 "$daemon_pid" 2>/dev/null; then
    echo "scan-warehouse: ldoem-emud stopped before it was ready:" >&2
    cat "$work_dir/daemon.err" >&2
    exit 1
  fi
  if ((SECONDS >= deadline)); then
    echo "scan-warehouse: ldoem-emud not ready after ${ready_timeout_s} s" >&2
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

# A wide field so the aisle is seen whole; the cart drives during the whole scan.
scan_command=("$scan" --device "$device" --lpt "lpt:pty:$lpt_path"
  --horizontal-apex 180 --horizontal-resolution 0.5
  --vertical-apex 39.6 --vertical-resolution 0.36 --speed 10
  --out "$out_dir/warehouse.ply" --preview "$out_dir/warehouse-range.png"
  --render "$out_dir/warehouse.png" "${scan_extra[@]}")
echo "scan-warehouse: ${scan_command[*]}" >&2
started_ns=$(date +%s%N)
status=0
"${scan_command[@]}" >"$work_dir/scan.out" || status=$?
finished_ns=$(date +%s%N)
cat "$work_dir/scan.out"
wall_s=$(awk -v ns=$((finished_ns - started_ns)) 'BEGIN {printf "%.1f", ns / 1e9}')
echo "scan-warehouse: ldoem-scan exit status $status after $wall_s s"

[[ $status -eq 0 ]] && echo "scan-warehouse: wrote $out_dir/warehouse.ply, $out_dir/warehouse-range.png and $out_dir/warehouse.png"
exit "$status"
