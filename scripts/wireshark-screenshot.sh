#!/usr/bin/env bash
# Takes docs/wireshark.png: Wireshark (under Xvfb) with the ldoem dissector, showing a profile
# telegram with its tree expanded. Usage: scripts/wireshark-screenshot.sh CAPTURE FRAME [OUT.png]
# Needs wireshark-qt, xvfb, xdotool, x11-apps (xwd) and netpbm (scripts/install-deps.sh --screenshot).
set -euo pipefail
cd "$(dirname "$0")/.."
capture=${1:?usage: scripts/wireshark-screenshot.sh CAPTURE FRAME [OUT.png]}
frame=${2:?usage: scripts/wireshark-screenshot.sh CAPTURE FRAME [OUT.png]}
out=${3:-docs/wireshark.png}
display=:$((90 + RANDOM % 9))
width=1400 height=1700
# The packet details pane starts about half-way down what the toolbars leave.
details_y=$((110 + (height - 125) / 2))
work=$(mktemp -d)
cleanup() {
  [ -n "${ws_pid:-}" ] && kill "$ws_pid" 2>/dev/null || true
  [ -n "${x_pid:-}" ] && kill "$x_pid" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
Xvfb "$display" -screen 0 ${width}x${height}x24 -nolisten tcp >/dev/null 2>&1 &
x_pid=$!
sleep 1
# A private configuration folder: the user's own profile must not change the picture.
export XDG_CONFIG_HOME=$work HOME=$work DISPLAY=$display
wireshark -r "$capture" -g "$frame" \
  -X lua_script:tools/wireshark/ldoem.lua -X lua_script:tools/wireshark/ldoem_serial.lua \
  -o iso15765.can.ids:1728-1729 -d iso15765.subdissector,ldoem_isotp \
  -o gui.layout_content_3:NONE -o gui.geometry_main_maximized:TRUE >"$work/wireshark.log" 2>&1 &
ws_pid=$!
window=""
for _ in $(seq 1 60); do
  window=$(xdotool search --name "$(basename "$capture")" 2>/dev/null | head -1 || true)
  [ -n "$window" ] && break
  sleep 1
done
[ -n "$window" ] || { cat "$work/wireshark.log"; echo "wireshark-screenshot: no Wireshark window" >&2; exit 1; }
xdotool windowsize "$window" "$width" "$height" windowmove "$window" 0 0
sleep 3
# Focus the packet details (its first row sits just below the middle of the window), select
# the last protocol (ldoem) and open all its subtrees (Shift+Right).
xdotool mousemove --sync 200 "$details_y" click 1
sleep 1
xdotool key End
sleep 1
xdotool key shift+Right
sleep 2
xwd -root -silent -display "$display" | xwdtopnm 2>/dev/null | pnmtopng > "$out"
echo "wrote $out"
