# shellcheck shell=bash disable=SC2034
# Helpers for the hostile-input cases (scripts/hostile.sh sources this file first, then every
# other scripts/hostile/*.sh). Each case runs in its own bash process and process group, so a
# case may start daemons freely: hostile_stop ends them, and the EXIT trap below ends what a case
# left running. Set by hostile.sh: HOSTILE_EMUD, HOSTILE_REPLAY, HOSTILE_HUB (programs),
# HOSTILE_WORK (a scratch folder of this case, removed afterwards), HOSTILE_ROOT (the checkout).
#
# The contract of a case (docs/robustness.md): a function hostile_case_<id> (id like
# d01_delay_reply) prints exactly one markdown row `| D1 | what was sent | what happened | ok |`
# (hostile_row does it) and returns 0 when ok, 1 when not.

HOSTILE_PIDS=()
hostile_cleanup() {
  local pid
  for pid in "${HOSTILE_PIDS[@]}"; do
    kill -KILL "$pid" 2>/dev/null || true
  done
}
trap hostile_cleanup EXIT

# hostile_row ID WHAT RESULT OK(0|1): prints the case's row; returns OK.
hostile_row() {
  local verdict=ok
  [ "$4" -eq 0 ] || verdict=FAIL
  printf '| %s | %s | %s | %s |\n' "$1" "$2" "$3" "$verdict"
  return "$4"
}

# hostile_start [--nofile N] [--fsize BYTES] [--as MIB] [--control] [--no-wait] SCENE ARGS...
# Starts ldoem-emud on SCENE (--no-can --tcp tcp:127.0.0.1:0 --no-flash --timeout 300, then ARGS)
# under the limits given, waits up to 30 s for "ready". Sets H_PID, H_PORT (empty when it did
# not start), H_ERR (its stderr file), H_OUT (its stdout file), H_CONTROL (the control socket's
# path, with --control). Returns 1 when it did not start (it may have exited: see H_ERR; with
# --no-wait, 0 and H_PORT is empty until hostile_wait_ready).
hostile_start() {
  local nofile=0 fsize=0 as_mib=0 control=0 wait=1
  while [ $# -gt 0 ]; do
    case "$1" in
      --nofile) nofile=$2; shift 2;;
      --fsize) fsize=$2; shift 2;;
      --as) as_mib=$2; shift 2;;
      --control) control=1; shift;;
      --no-wait) wait=0; shift;;
      *) break;;
    esac
  done
  local scene=$1
  shift
  local n=${#HOSTILE_PIDS[@]}
  H_OUT=$HOSTILE_WORK/daemon$n.out
  H_ERR=$HOSTILE_WORK/daemon$n.err
  H_CONTROL=
  local extra=()
  if [ "$control" -eq 1 ]; then
    H_CONTROL=$HOSTILE_WORK/control$n.sock
    extra=(--control "$H_CONTROL")
  fi
  # The limits are set by a small exec wrapper (RLIMIT_FSIZE with SIGXFSZ ignored: a write past
  # it fails with EFBIG, like a full disk).
  python3 -c '
import os, resource, signal, sys
nofile, fsize, as_mib = (int(v) for v in sys.argv[1:4])
if nofile: resource.setrlimit(resource.RLIMIT_NOFILE, (nofile, nofile))
if fsize:
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, fsize))
if as_mib: resource.setrlimit(resource.RLIMIT_AS, (as_mib << 20, as_mib << 20))
os.execv(sys.argv[4], sys.argv[4:])' "$nofile" "$fsize" "$as_mib" \
    "$HOSTILE_EMUD" --scene "$scene" --no-can --tcp tcp:127.0.0.1:0 --no-flash --timeout 300 "${extra[@]}" "$@" \
    >"$H_OUT" 2>"$H_ERR" &
  H_PID=$!
  HOSTILE_PIDS+=("$H_PID")
  H_PORT=
  [ "$wait" -eq 1 ] || return 0
  hostile_wait_ready
}

# hostile_wait_ready: waits up to 30 s for the last started daemon's "ready"; sets H_PORT.
hostile_wait_ready() {
  local i
  for i in $(seq 300); do
    if grep -q '^ready' "$H_OUT" 2>/dev/null; then
      H_PORT=$(sed -n 's/^tcp 127.0.0.1:\([0-9]*\)$/\1/p' "$H_OUT" | head -n 1)
      return 0
    fi
    kill -0 "$H_PID" 2>/dev/null || return 1
    sleep 0.1
  done
  return 1
}

# hostile_exit_status PID [SECONDS]: waits up to SECONDS (10) for a daemon that should exit by
# itself; sets H_STATUS to its exit status, or "running" (then it is killed). (A variable, not
# output: `wait` works only in the shell that started the daemon, not in a $(...) subshell.)
hostile_exit_status() {
  local pid=$1 limit=${2:-10} i
  H_STATUS=running
  for i in $(seq $((limit * 10))); do
    if ! kill -0 "$pid" 2>/dev/null; then
      H_STATUS=0
      wait "$pid" 2>/dev/null || H_STATUS=$?
      return 0
    fi
    sleep 0.1
  done
  kill -KILL "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
}

# hostile_stop PID: SIGTERM, up to 10 s, then SIGKILL. Prints the seconds it took ("killed" when
# it had to be killed).
hostile_stop() {
  local pid=$1 start=$EPOCHREALTIME i
  kill -TERM "$pid" 2>/dev/null || { echo 0; return 0; }
  for i in $(seq 100); do
    if ! kill -0 "$pid" 2>/dev/null; then
      wait "$pid" 2>/dev/null || true
      awk -v a="$start" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.2f\n", b - a }'
      return 0
    fi
    sleep 0.1
  done
  kill -KILL "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
  echo killed
}

# hostile_vmhwm_mib PID: its peak resident memory in MiB (one decimal).
hostile_vmhwm_mib() {
  awk '/^VmHWM/ { printf "%.1f\n", $2 / 1024 }' "/proc/$1/status" 2>/dev/null || echo 0
}

# hostile_cpu_s PID: user + system CPU seconds so far.
hostile_cpu_s() {
  python3 -c '
import os, sys
with open(f"/proc/{sys.argv[1]}/stat") as f:
    fields = f.read().rsplit(")", 1)[1].split()
print(f"{(int(fields[11]) + int(fields[12])) / os.sysconf(\"SC_CLK_TCK\"):.2f}")' "$1" 2>/dev/null || echo 0
}

# hostile_send_hex PORT HEX [SECONDS]: connects, sends the bytes, reads for up to SECONDS (2) or
# until the peer closes; prints what came back in hex (empty line: nothing).
hostile_send_hex() {
  python3 - "$1" "$2" "${3:-2}" <<'PY'
import socket, sys, time
port, data, seconds = int(sys.argv[1]), bytes.fromhex(sys.argv[2]), float(sys.argv[3])
got = b""
try:
    with socket.create_connection(("127.0.0.1", port), timeout=seconds) as s:
        s.sendall(data)
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            s.settimeout(max(0.01, deadline - time.monotonic()))
            chunk = s.recv(65536)
            if not chunk:
                break
            got += chunk
except (OSError, socket.timeout):
    pass
print(got.hex())
PY
}

# hostile_frame HEX_PAYLOAD: the TCP frame of a payload (spec 4.1), in hex.
hostile_frame() {
  python3 -c '
import sys
p = bytes.fromhex(sys.argv[1]); x = 0
for b in p: x ^= b
print((b"\x02USP" + len(p).to_bytes(4, "big") + p + bytes([x])).hex())' "$1"
}

# hostile_get_status PORT: 0 when a GET_STATUS over TCP is answered within 2 s.
hostile_get_status() {
  local reply
  reply=$(hostile_send_hex "$1" 0255535000000002010203 2)
  [[ "$reply" == *02555350????????8102* ]]
}

# hostile_control SOCKET JSON: one control-socket request; prints its reply line.
hostile_control() {
  python3 - "$1" "$2" <<'PY'
import json, socket, sys
s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
s.settimeout(10)
s.connect(sys.argv[1])
f = s.makefile("r")
f.readline()  # greeting
s.sendall((sys.argv[2] + "\n").encode())
while True:
    line = f.readline()
    if not line:
        break
    reply = json.loads(line)
    if "return" in reply or "error" in reply:
        print(line.strip())
        break
PY
}

# hostile_first_error FILE: the first line of a daemon's stderr that says error or warn (else its
# first line), without the program's name, cut to 110 characters, '|' escaped and temporary
# paths replaced, for a table cell.
hostile_first_error() {
  { grep -m1 -E 'error|warn' "$1" || head -n 1 "$1"; } 2>/dev/null | sed 's/^ldoem-[a-z]*: //' | cut -c1-110 |
    sed 's/|/\\|/g; s#/tmp/[^ :]*#FILE#g'
}

# hostile_pipeline PORT HEX_PAYLOAD COUNT [READ(0|1)]: one connection sends COUNT frames of the
# payload as fast as the daemon takes them (at most 20 s), reading the replies when READ is 1
# (else never: a host that pipelines without reading). Prints the frames sent.
hostile_pipeline() {
  python3 - "$1" "$2" "$3" "${4:-0}" <<'PY'
import socket, sys, time
port, payload, count, read = int(sys.argv[1]), bytes.fromhex(sys.argv[2]), int(sys.argv[3]), sys.argv[4] == "1"
x = 0
for b in payload: x ^= b
frame = b"\x02USP" + len(payload).to_bytes(4, "big") + payload + bytes([x])
sent, deadline = 0, time.monotonic() + 20
s = socket.create_connection(("127.0.0.1", port), timeout=5)
try:
    while sent < count and time.monotonic() < deadline:
        n = min(1000, count - sent)
        s.sendall(frame * n)
        sent += n
        if read:
            got = 0
            while got < n:
                chunk = s.recv(1 << 16)
                if not chunk: raise OSError("closed")
                got += chunk.count(b"\x02USP")
except OSError:
    pass
print(sent)
PY
}

# hostile_json FIELD.PATH: reads a control reply on stdin; prints FIELD.PATH of it (or "none").
hostile_json() {
  python3 -c '
import json, sys
value = json.loads(sys.stdin.read() or "{}")
for key in sys.argv[1].split("."):
    value = value.get(key) if isinstance(value, dict) else None
print("none" if value is None else value)' "$1"
}
