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
tool=scan-warehouse
transport=tcp
source scripts/lib/scene-scan.sh
scene_scan_parse_args "$@"
scene_scan_start_daemon scenes/warehouse.yaml

# A wide field so the aisle is seen whole; the cart drives during the whole scan.
scene_scan_run --horizontal-apex 180 --horizontal-resolution 0.5 \
  --vertical-apex 39.6 --vertical-resolution 0.36 --speed 10 \
  --out "$out_dir/warehouse.ply" --preview "$out_dir/warehouse-range.png" \
  --render "$out_dir/warehouse.png"

[[ $status -eq 0 ]] && echo "scan-warehouse: wrote $out_dir/warehouse.ply, $out_dir/warehouse-range.png and $out_dir/warehouse.png"
exit "$status"
