# shellcheck shell=bash disable=SC2034
# Issue 27, the runtime half: faults, the control socket, recording, the event log,
# identification texts, the listen backlog. Sourced by scripts/hostile.sh after lib.sh.

hostile_scene() { echo "$HOSTILE_ROOT/scenes/minimal.yaml"; }

hostile_case_d01_delay_reply() {
  local what="delay_reply delay_s 1e6; then delay_s 60 and 60 000 pipelined GET_STATUS, none read"
  hostile_start --control "$(hostile_scene)" || { hostile_row D1 "$what" "did not start" 1; return; }
  local ok=0 refused before after dropped answered stop_s
  refused=$(hostile_control "$H_CONTROL" \
    '{"execute":"inject-fault","arguments":{"kind":"delay_reply","delay_s":1e6,"duration_s":1e6,"transport":"tcp"}}' |
    hostile_json error.desc)
  [[ "$refused" == *"at most 60"* ]] || ok=1
  hostile_control "$H_CONTROL" \
    '{"execute":"inject-fault","arguments":{"kind":"delay_reply","delay_s":60,"duration_s":1e6,"transport":"tcp"}}' >/dev/null
  before=$(hostile_vmhwm_mib "$H_PID")
  hostile_pipeline "$H_PORT" 0102 60000 0 >/dev/null
  sleep 1
  after=$(hostile_vmhwm_mib "$H_PID")
  dropped=$(hostile_control "$H_CONTROL" '{"execute":"query-status"}' | hostile_json return.counters.delayed_replies_dropped)
  hostile_control "$H_CONTROL" '{"execute":"clear-fault"}' >/dev/null
  answered=no
  hostile_get_status "$H_PORT" && answered=yes
  stop_s=$(hostile_stop "$H_PID")
  awk -v a="$before" -v b="$after" 'BEGIN { exit !(b - a <= 24) }' || ok=1
  [[ "$dropped" =~ ^[0-9]+$ && "$dropped" -ge 59000 ]] || ok=1
  [ "$answered" = yes ] || ok=1
  hostile_row D1 "$what" "1e6 refused (\"${refused:0:40}\"); VmHWM ${before} -> ${after} MiB, delayed_replies_dropped ${dropped} (64 held per connection); GET_STATUS answered: ${answered}; SIGTERM ${stop_s} s" "$ok"
}

hostile_case_d02_garbage() {
  local what="garbage bytes 4294967295, then 1e8, then 4096 (the maximum) before one GET_STATUS"
  hostile_start --control "$(hostile_scene)" || { hostile_row D2 "$what" "did not start" 1; return; }
  local ok=0 huge big before after reply bytes
  huge=$(hostile_control "$H_CONTROL" \
    '{"execute":"inject-fault","arguments":{"kind":"garbage","bytes":4294967295,"transport":"tcp"}}')
  big=$(hostile_control "$H_CONTROL" '{"execute":"inject-fault","arguments":{"kind":"garbage","bytes":1e8,"transport":"tcp"}}')
  [[ "$huge" == *'"error"'* && "$big" == *'"error"'* ]] || ok=1
  before=$(hostile_vmhwm_mib "$H_PID")
  hostile_control "$H_CONTROL" '{"execute":"inject-fault","arguments":{"kind":"garbage","bytes":4096,"transport":"tcp"}}' >/dev/null
  reply=$(hostile_send_hex "$H_PORT" 0255535000000002010203 2)
  bytes=$(( ${#reply} / 2 ))
  after=$(hostile_vmhwm_mib "$H_PID")
  [ "$bytes" -eq 4111 ] || ok=1
  hostile_get_status "$H_PORT" || ok=1
  hostile_stop "$H_PID" >/dev/null
  local desc
  desc=$(echo "$huge" | hostile_json error.desc)
  hostile_row D2 "$what" "refused: \"${desc}\" (1e8 too); 4096: ${bytes} bytes back (4096 + the 15-byte reply), VmHWM ${before} -> ${after} MiB" "$ok"
}

hostile_case_d03_control_emfile() {
  local what="ulimit -n 64, 80 UNIX connections to --control held 3 s"
  hostile_start --nofile 64 --control "$(hostile_scene)" || { hostile_row D3 "$what" "did not start" 1; return; }
  local ok=0 cpu0 cpu1 warnings answered=no
  python3 - "$H_CONTROL" <<'PY' &
import socket, sys, time
held = []
for _ in range(80):
    s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    s.setblocking(False)
    try: s.connect(sys.argv[1])
    except OSError: pass
    held.append(s)
time.sleep(3)
PY
  local holder=$!
  sleep 0.5
  cpu0=$(hostile_cpu_s "$H_PID")
  sleep 2
  cpu1=$(hostile_cpu_s "$H_PID")
  wait "$holder"  # the connections close: the daemon's descriptors come back
  for _ in 1 2 3; do hostile_get_status "$H_PORT" && { answered=yes; break; }; done
  hostile_stop "$H_PID" >/dev/null
  warnings=$(grep -c 'control: accept' "$H_ERR")
  awk -v a="$cpu0" -v b="$cpu1" 'BEGIN { exit !(b - a <= 1.0) }' || ok=1
  [ "$warnings" -ge 1 ] && [ "$warnings" -le 3 ] || ok=1
  [ "$answered" = yes ] || ok=1
  hostile_row D3 "$what" "CPU $(awk -v a="$cpu0" -v b="$cpu1" 'BEGIN { printf "%.2f", b - a }') s in 2 s; ${warnings} warning(s) (\"$(grep -m1 'control: accept' "$H_ERR" | sed 's#.*: Too#Too#' | cut -c1-60)\"); GET_STATUS answered once they closed: ${answered}" "$ok"
}

hostile_case_d04_record_rotation() {
  local what="--record-files 10000000; then rotation at 64 KiB keeping 1000 files under 40 000 GET_STATUS"
  local ok=0 status first
  hostile_start --no-wait "$(hostile_scene)" --record "$HOSTILE_WORK/r.pcapng" --record-max-mb 1 --record-files 10000000
  hostile_exit_status "$H_PID" 10
  status=$H_STATUS
  first=$(hostile_first_error "$H_ERR")
  [ "$status" = 2 ] || ok=1
  hostile_start "$(hostile_scene)" --record "$HOSTILE_WORK/r.pcapng" --record-max-mb 0.0625 --record-files 1000 ||
    { hostile_row D4 "$what" "did not start" 1; return; }
  local probe_log=$HOSTILE_WORK/probes
  python3 - "$H_PORT" >"$probe_log" <<'PY' &
import socket, sys, time
port = int(sys.argv[1]); worst = 0.0; missed = 0
frame = bytes.fromhex("0255535000000002010203")
for _ in range(40):
    start = time.monotonic()
    try:
        with socket.create_connection(("127.0.0.1", port), timeout=2) as s:
            s.sendall(frame)
            if not s.recv(64): missed += 1
    except OSError:
        missed += 1
    worst = max(worst, time.monotonic() - start)
    time.sleep(0.1)
print(f"{worst * 1000:.0f} {missed}")
PY
  local prober=$!
  hostile_pipeline "$H_PORT" 0102 40000 1 >/dev/null
  wait "$prober"
  local worst missed stop_s files
  read -r worst missed <"$probe_log"
  stop_s=$(hostile_stop "$H_PID")
  files=$(find "$HOSTILE_WORK" -maxdepth 1 -name 'r.pcapng*' | wc -l)  # FILE and FILE.1 ...
  [ "$missed" = 0 ] || ok=1
  [ "$stop_s" != killed ] || ok=1
  [ -z "$(find "$HOSTILE_WORK" -maxdepth 1 -name 'r.pcapng.rotating*')" ] || ok=1
  [ "$files" -ge 10 ] || ok=1
  hostile_row D4 "$what" "exit ${status} (\"${first:0:70}\"); rotating: ${files} files, 40 GET_STATUS probes: ${missed} missed, slowest ${worst} ms; SIGTERM ${stop_s} s" "$ok"
}

hostile_case_d09_record_full_disk() {
  local what="--record on a disk that fills at 30 001 bytes (RLIMIT_FSIZE), 400 GET_STATUS; ldoem-replay of the file"
  hostile_start --fsize 30001 "$(hostile_scene)" --record "$HOSTILE_WORK/r.pcapng" ||
    { hostile_row D9 "$what" "did not start" 1; return; }
  local ok=0 errors answered=no whole replay_status
  hostile_pipeline "$H_PORT" 0102 400 1 >/dev/null
  hostile_get_status "$H_PORT" && answered=yes
  hostile_stop "$H_PID" >/dev/null
  errors=$(grep -c -- '--record:' "$H_ERR")
  whole=$(python3 - "$HOSTILE_WORK/r.pcapng" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read(); offset = blocks = 0
while offset + 12 <= len(data):
    length = struct.unpack("<I", data[offset + 4:offset + 8])[0]
    if length < 12 or offset + length > len(data): break
    offset += length; blocks += 1
print(f"{len(data)} {blocks} {'yes' if offset == len(data) else 'no'}")
PY
)
  replay_status=0
  timeout 30 "$HOSTILE_REPLAY" "$HOSTILE_WORK/r.pcapng" --tcp tcp:127.0.0.1:0 --timeout 0.3 >/dev/null 2>&1 || replay_status=$?
  [[ "$whole" == *yes ]] || ok=1
  [ "$errors" -eq 1 ] || ok=1
  [ "$answered" = yes ] || ok=1
  [ "$replay_status" -eq 0 ] || ok=1
  local size blocks ends
  read -r size blocks ends <<<"$whole"
  hostile_row D9 "$what" "${size} bytes, ${blocks} whole blocks, ends at a block boundary: ${ends}; ${errors} error line; GET_STATUS answered: ${answered}; ldoem-replay exit ${replay_status}" "$ok"
}

hostile_case_d10_event_log_full() {
  local what="--event-log /dev/full; then a disk that fills at 1500 bytes, 40 faults injected"
  local ok=0 i counted said answered=no refused log=$HOSTILE_WORK/events.jsonl
  # /dev/full is no regular file: refused at start, with what it is (issue 27 item 3).
  hostile_start --no-wait "$(hostile_scene)" --event-log /dev/full
  hostile_exit_status "$H_PID" 20
  refused="exit ${H_STATUS} (\"$(hostile_first_error "$H_ERR" | cut -c1-60)\")"
  [ "$H_STATUS" = 2 ] && grep -q "is a character device" "$H_ERR" || ok=1
  # A full disk at 1500 bytes (RLIMIT_FSIZE, SIGXFSZ ignored: EFBIG): the event log fills after a
  # few records; it is reported once, every lost record is counted, records stay whole, and the
  # daemon goes on.
  hostile_start --fsize 1500 --control "$(hostile_scene)" --event-log "$log" ||
    { hostile_row D10 "$what" "$refused; with RLIMIT_FSIZE: did not start" 1; return; }
  for i in $(seq 40); do
    hostile_control "$H_CONTROL" '{"execute":"inject-fault","arguments":{"kind":"window_dirt","fraction":0.5,"duration_s":1}}' >/dev/null
  done
  counted=$(hostile_control "$H_CONTROL" '{"execute":"query-status"}' | hostile_json return.counters.event_log_write_errors)
  hostile_get_status "$H_PORT" && answered=yes
  hostile_stop "$H_PID" >/dev/null
  said=$(grep -c -- "--event-log $log" "$H_ERR")
  [ "$said" -eq 1 ] || ok=1
  [[ "$counted" =~ ^[0-9]+$ && "$counted" -ge 1 ]] || ok=1
  [ "$answered" = yes ] || ok=1
  python3 -c 'import json,sys; d=open(sys.argv[1],"rb").read(); sys.exit(0 if d.endswith(b"\n") and all(json.loads(l) for l in d.split(b"\n")[:-1]) else 1)' "$log" || ok=1
  hostile_row D10 "$what" "/dev/full: ${refused}; disk full at 1500 bytes: ${said} line on stderr, event_log_write_errors ${counted}, $(stat -c %s "$log") bytes of whole records; GET_STATUS answered: ${answered}" "$ok"
}

hostile_case_d14_identification() {
  local what="sensor_name of 6000 characters (and of 5814)"
  local ok=0 scene=$HOSTILE_WORK/id.yaml status first reply
  { printf 'scanner:\n  identification:\n    sensor_name: "%s"\n' "$(printf 'N%.0s' $(seq 6000))"; cat "$(hostile_scene)"; } >"$scene"
  hostile_start --no-wait "$scene"
  hostile_exit_status "$H_PID" 20
  status=$H_STATUS
  first=$(hostile_first_error "$H_ERR")
  [ "$status" = 2 ] || ok=1
  { printf 'scanner:\n  identification:\n    sensor_name: "%s"\n' "$(printf 'N%.0s' $(seq 5814))"; cat "$(hostile_scene)"; } >"$scene"
  hostile_start "$scene" || { hostile_row D14 "$what" "5814 characters: did not start" 1; return; }
  reply=$(hostile_send_hex "$H_PORT" "$(hostile_frame 01010001)" 2)
  hostile_stop "$H_PID" >/dev/null
  local payload=$(( ${#reply} / 2 - 9 ))
  [ "$payload" -eq 5816 ] || ok=1
  first=$(sed -n 's/.*sensor_name: //p' "$HOSTILE_WORK"/daemon0.err | cut -c1-100)
  hostile_row D14 "$what" "6000: exit ${status} (\"sensor_name: ${first}\"); 5814: a ${payload}-byte reply payload" "$ok"
}

hostile_case_x1_listen_backlog() {
  local what="200 connects to a daemon stopped by SIGSTOP (only the kernel's backlog holds them)"
  hostile_start "$(hostile_scene)" || { hostile_row backlog "$what" "did not start" 1; return; }
  local ok=0 connected
  kill -STOP "$H_PID"
  connected=$(python3 - "$H_PORT" <<'PY'
import select, socket, sys, time
clients = []
for _ in range(200):
    s = socket.socket(); s.setblocking(False); s.connect_ex(("127.0.0.1", int(sys.argv[1]))); clients.append(s)
time.sleep(0.5)  # a SYN dropped for a full backlog is retried after 1 s
_, writable, _ = select.select([], clients, [], 0)
print(sum(1 for s in writable if s.getsockopt(socket.SOL_SOCKET, socket.SO_ERROR) == 0))
PY
)
  kill -CONT "$H_PID"
  hostile_get_status "$H_PORT" || ok=1
  hostile_stop "$H_PID" >/dev/null
  [ "$connected" -eq 200 ] || ok=1
  hostile_row backlog "$what" "${connected} of 200 connected within 0.5 s (backlog SOMAXCONN); GET_STATUS answered after SIGCONT" "$ok"
}
