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
tool=scan-corridor
transport=can
source scripts/lib/scene-scan.sh
scene_scan_parse_args "$@"
scene_scan_start_daemon scenes/corridor.yaml

# The paper's settings (Koceski & Koceska 2013): 20 deg x 21.6 deg at 0.25 deg x 0.18 deg, 10 Hz.
scene_scan_run --horizontal-apex 20 --horizontal-resolution 0.25 \
  --vertical-apex 21.6 --vertical-resolution 0.18 --speed 10 --title "scene corridor.yaml" \
  --out "$out_dir/corridor.ply" --preview "$out_dir/corridor.png" --fit

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
