#!/bin/bash
# tshark on a capture a test records: ldoem-conformance --record runs its vector and
# conversation cases against ldoem-emud, then check_dissector.py checks that the dissector
# decodes every telegram ldoem's reader finds (ldoem_capture_expectations), profile point counts
# included, with nothing malformed.
# Usage: check_recording.sh --run-against RUN_AGAINST_DAEMON_SH --daemon EMUD --suite SUITE
#          --scene FILE --expectations BIN --tshark TSHARK --lua-dir DIR [--transport tcp|serial|can]
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
run_against="" daemon="" suite="" scene="" expectations="" tshark=tshark lua_dir="" transport=tcp
while (($#)); do
  case "$1" in
    --run-against) run_against=$2; shift 2 ;;
    --daemon) daemon=$2; shift 2 ;;
    --suite) suite=$2; shift 2 ;;
    --scene) scene=$2; shift 2 ;;
    --expectations) expectations=$2; shift 2 ;;
    --tshark) tshark=$2; shift 2 ;;
    --lua-dir) lua_dir=$2; shift 2 ;;
    --transport) transport=$2; shift 2 ;;
    *) echo "check_recording.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
done
work=$(mktemp -d /tmp/ldoem-wireshark.XXXXXX)
trap 'rm -rf "$work"' EXIT
"$run_against" --daemon "$daemon" --suite "$suite" --scene "$scene" --transport "$transport" --time-scale 10 \
  --timeout 240 -- --filter "$transport/vectors/*" --filter "$transport/conversation/*" \
  --record "$work/recorded.pcapng" >"$work/record.out" 2>&1 || { cat "$work/record.out"; exit 1; }
"$expectations" "$work/recorded.pcapng" >"$work/expect.json" || exit 1
python3 "$here/check_dissector.py" --tshark "$tshark" --lua-dir "$lua_dir" \
  --capture "$work/recorded.pcapng" --expect "$work/expect.json"
