# Issue 27, item 7: the hostile-input cases of scenes, meshes and files (D5-D8, D11-D13, the mesh
# message, the replay reader). Sourced by scripts/hostile.sh; self-contained (no lib.sh helpers).
# Each hostile_case_* prints one markdown row `| Dn | given | what happened | ok/FAIL |` and
# returns 0 when ok. Every program runs under a wall-time limit (timeout) and an address-space
# limit (ulimit -v in a subshell); temporary files come from mktemp and are removed.
# BUILD_DIR: where the programs are (default build/default, a plain build: a sanitizer build
# cannot start under ulimit -v).

_hf_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
_hf_build() { echo "${BUILD_DIR:-$_hf_root/build/default}"; }
_hf_emud() { echo "$(_hf_build)/emulator/daemon/ldoem-emud"; }
_hf_scene="$_hf_root/scenes/minimal.yaml"

# _hf_run LIMIT_S MEM_MIB PROGRAM ARGS...: runs it bounded; sets _hf_rc, _hf_s (wall seconds),
# _hf_mib (peak RSS) and _hf_msg (last stderr line). rc 124/137: the time limit ended it.
_hf_run() {
  local limit=$1 mem=$2 err times
  shift 2
  err=$(mktemp) times=$(mktemp)
  # `&& ... ||`: a failing program must not end a caller running under set -e.
  (ulimit -v $((mem * 1024)); exec timeout -k 2 "$limit" /usr/bin/time -f '%e %M' -o "$times" "$@") \
    >/dev/null 2>"$err" </dev/null && _hf_rc=0 || _hf_rc=$?
  # time -o writes "Command exited with non-zero status N" first when the status is not 0.
  read -r _hf_s _hf_kib < <(tail -n 1 "$times") || true
  [[ ${_hf_kib:-} =~ ^[0-9]+$ ]] || { _hf_s=$limit _hf_kib=0; }
  _hf_mib=$(( ${_hf_kib:-0} / 1024 ))
  _hf_msg=$(grep -v '^Command exited\|^Command terminated' "$err" | tail -n 1 | tr '|' '/')
  rm -f "$err" "$times"
}

# _hf_row ID GIVEN OK: prints the row from the last _hf_run; returns 0 when OK is "ok".
_hf_row() {
  local verdict=FAIL
  [ "$3" = ok ] && verdict=ok
  # Temporary folders shortened to DIR; long messages cut for the table (matching used them whole).
  local shown=${_hf_msg//\/tmp\/tmp.??????????/DIR}
  [ ${#shown} -gt 120 ] && shown="${shown:0:117}..."
  printf '| %s | %s | exit %s in %s s, peak %s MiB: `%s` | %s |\n' "$1" "$2" "$_hf_rc" "$_hf_s" "$_hf_mib" "$shown" "$verdict"
  [ "$verdict" = ok ]
}

# _hf_expect ID GIVEN RC TEXT: ok when the last run exited RC with TEXT in its last line.
_hf_expect() {
  local ok=FAIL
  [ "$_hf_rc" = "$3" ] && [[ $_hf_msg == *"$4"* ]] && ok=ok
  _hf_row "$1" "$2" "$ok"
}

_hf_emud_run() {  # _hf_emud_run MEM_MIB ARGS...: the daemon for 0.3 s at most after start-up
  local mem=$1
  shift
  _hf_run 20 "$mem" "$(_hf_emud)" --no-can --tcp tcp:127.0.0.1:0 --timeout 0.3 "$@"
}

hostile_case_d05_tilt_step_1e9() {
  local dir rc
  dir=$(mktemp -d)
  printf 'effects: [motor_dynamics]\nscanner: {tilt_motor: {world_step_s: 1e-9}}\n' >"$dir/s.yaml"
  _hf_emud_run 1024 --scene "$dir/s.yaml" --no-flash
  _hf_expect D5 '`tilt_motor.world_step_s: 1e-9` with motor_dynamics' 2 'must be in [1e-6, 0.1] s' && rc=0 || rc=1
  rm -rf "$dir"
  return $rc
}

hostile_case_d06_million_sphere_lines() {
  local dir rc
  dir=$(mktemp -d)
  { echo 'objects:'; yes '  - {sphere: {radius_m: 0.5}, pose: {position_m: [5, 0, 0]}}' | head -n 1000000; } >"$dir/s.yaml"
  _hf_emud_run 768 --scene "$dir/s.yaml" --no-flash
  _hf_expect D6 "1 000 000 sphere lines ($(( $(stat -c %s "$dir/s.yaml") >> 20 )) MiB)" 2 'YAML nodes in the scene' && rc=0 || rc=1
  rm -rf "$dir"
  return $rc
}

hostile_case_d07_scene_dev_zero() {
  _hf_emud_run 768 --scene /dev/zero --no-flash
  _hf_expect D7 '`--scene /dev/zero`' 2 'is a character device'
}

hostile_case_d07_scene_fifo() {
  local dir rc
  dir=$(mktemp -d)
  mkfifo "$dir/scene.yaml"
  _hf_emud_run 768 --scene "$dir/scene.yaml" --no-flash
  _hf_expect D7 '`--scene` naming a FIFO' 2 'is a FIFO' && rc=0 || rc=1
  rm -rf "$dir"
  return $rc
}

hostile_case_d07_scene_directory() {
  local dir rc
  dir=$(mktemp -d)
  _hf_emud_run 768 --scene "$dir" --no-flash
  _hf_expect D7 '`--scene` naming a directory' 2 'is a directory' && rc=0 || rc=1
  rm -rf "$dir"
  return $rc
}

hostile_case_d08_stl_header_5e6_triangles() {
  local dir rc
  dir=$(mktemp -d)
  # 80 header bytes, then 5 000 000 as little-endian uint32, then 250 MB of (sparse) zeros.
  { head -c 80 /dev/zero | tr '\0' x; printf '\x40\x4b\x4c\x00'; } >"$dir/huge.stl"
  truncate -s $((84 + 50 * 5000000)) "$dir/huge.stl"
  echo 'objects: [{mesh: {file: huge.stl}}]' >"$dir/s.yaml"
  _hf_emud_run 768 --scene "$dir/s.yaml" --no-flash
  _hf_expect D8 'binary STL header claiming 5 000 000 triangles, 250 MB of zeros' 2 '5000000 triangles' && rc=0 || rc=1
  rm -rf "$dir"
  return $rc
}

hostile_case_d08_mesh_fifo() {
  local dir rc
  dir=$(mktemp -d)
  mkfifo "$dir/rock.obj"
  echo 'objects: [{mesh: {file: rock.obj}}]' >"$dir/s.yaml"
  _hf_emud_run 768 --scene "$dir/s.yaml" --no-flash
  _hf_expect D8 'a mesh file that is a FIFO' 2 'is a FIFO' && rc=0 || rc=1
  rm -rf "$dir"
  return $rc
}

hostile_case_d11_flash_fifo() {
  local dir rc
  dir=$(mktemp -d)
  mkfifo "$dir/x.flash"
  _hf_emud_run 768 --scene "$_hf_scene" --flash "$dir/x.flash"
  _hf_expect D11 '`--flash` naming a FIFO' 2 'is a FIFO' && rc=0 || rc=1
  rm -rf "$dir"
  return $rc
}

hostile_case_d11_event_log_fifo() {
  local dir rc
  dir=$(mktemp -d)
  mkfifo "$dir/events"
  _hf_emud_run 768 --scene "$_hf_scene" --no-flash --event-log "$dir/events"
  _hf_expect D11 '`--event-log` naming a FIFO' 2 'is a FIFO' && rc=0 || rc=1
  rm -rf "$dir"
  return $rc
}

hostile_case_d11_record_fifo() {
  local dir rc
  dir=$(mktemp -d)
  mkfifo "$dir/rec.pcapng"
  _hf_emud_run 768 --scene "$_hf_scene" --no-flash --record "$dir/rec.pcapng"
  _hf_expect D11 '`--record` naming a FIFO' 2 'is a FIFO' && rc=0 || rc=1
  rm -rf "$dir"
  return $rc
}

hostile_case_d12_flash_empty() {
  local dir rc
  dir=$(mktemp -d)
  : >"$dir/x.flash"
  _hf_emud_run 768 --scene "$_hf_scene" --flash "$dir/x.flash"
  local ok=FAIL
  [ "$_hf_rc" = 2 ] && [[ $_hf_msg == *empty* ]] && [ ! -s "$dir/x.flash" ] && ok=ok
  _hf_row D12 'a 0-byte `--flash` file' "$ok" && rc=0 || rc=1
  rm -rf "$dir"
  return $rc
}

hostile_case_d12_flash_symlink() {
  local dir rc ok=FAIL
  dir=$(mktemp -d)
  _hf_emud_run 768 --scene "$_hf_scene" --flash "$dir/real.flash"
  ln -s real.flash "$dir/x.flash"
  _hf_emud_run 768 --scene "$_hf_scene" --flash "$dir/x.flash"
  [ "$_hf_rc" = 0 ] && [ -L "$dir/x.flash" ] && [ -s "$dir/real.flash" ] && ok=ok
  _hf_msg="after the run: x.flash is $( [ -L "$dir/x.flash" ] && echo 'still a symlink' || echo 'a regular file')"
  _hf_row D12 'a `--flash` that is a symlink' "$ok" && rc=0 || rc=1
  rm -rf "$dir"
  return $rc
}

hostile_case_d13_flash_temporaries() {
  local dir rc ok=FAIL
  dir=$(mktemp -d)
  : >"$dir/.x.flash.Ab12Z9"
  : >"$dir/.x.flash.Qw34Er"
  _hf_emud_run 768 --scene "$_hf_scene" --flash "$dir/x.flash" --log-level info
  local left
  left=$(find "$dir" -name '.x.flash.*' | wc -l)
  [ "$_hf_rc" = 0 ] && [ "$left" = 0 ] && ok=ok
  _hf_msg="$left of 2 temporary files left"
  _hf_row D13 'two `.x.flash.XXXXXX` files of killed saves' "$ok" && rc=0 || rc=1
  rm -rf "$dir"
  return $rc
}

hostile_case_replay_bad_block_900mib() {
  local dir rc
  dir=$(mktemp -d)
  # A section header block (28 bytes) and a block whose length (13) is not a multiple of 4, at
  # byte 28, then 900 MiB of sparse zeros.
  printf '\x0a\x0d\x0d\x0a\x1c\x00\x00\x00\x4d\x3c\x2b\x1a\x01\x00\x00\x00\xff\xff\xff\xff\xff\xff\xff\xff\x1c\x00\x00\x00' >"$dir/x.pcapng"
  printf '\x06\x00\x00\x00\x0d\x00\x00\x00' >>"$dir/x.pcapng"
  truncate -s 900M "$dir/x.pcapng"
  _hf_run 60 2048 "$(_hf_build)/emulator/device/replay/ldoem-replay" --tcp tcp:127.0.0.1:0 --timeout 1 "$dir/x.pcapng"
  local ok=FAIL
  [ "$_hf_rc" = 2 ] && [[ $_hf_msg == *'block at byte 28'* ]] && [ "$_hf_mib" -lt 100 ] && ok=ok
  _hf_row replay 'a 900 MiB capture with a bad block at byte 28' "$ok" && rc=0 || rc=1
  rm -rf "$dir"
  return $rc
}

# D8 at run time: add-object of the project's own large mesh while a TCP host polls GET_STATUS
# every 5 ms. The row gives the worst round trip; ok when hosts were answered while the import
# ran (before: the first probe waited for the whole import, so only 1 was answered).
hostile_case_d08_add_object_large_rock() {
  local out rc worst answered seconds
  out=$( (ulimit -v $((2048 * 1024)); exec timeout -k 2 60 python3 - "$(_hf_emud)" "$_hf_scene" \
    "$_hf_root/scenes/meshes/large-rock.obj") <<'PY' 2>&1 || true
import json, os, select, socket, subprocess, sys, tempfile, time
emud, scene, mesh = sys.argv[1:4]
GET_STATUS = bytes.fromhex("0255535000000002010203")
with tempfile.TemporaryDirectory() as folder:
    control = os.path.join(folder, "ctl.sock")
    daemon = subprocess.Popen([emud, "--scene", scene, "--no-can", "--tcp", "tcp:127.0.0.1:0", "--no-flash",
                               "--control", control, "--timeout", "50"], stdout=subprocess.PIPE,
                              stderr=subprocess.DEVNULL, text=True)
    try:
        port = None
        for line in daemon.stdout:
            if line.startswith("tcp "): port = int(line.split(":")[-1])
            if line.strip() == "ready": break
        ctl = socket.socket(socket.AF_UNIX); ctl.connect(control); ctl.settimeout(30); ctl.recv(65536)
        host = socket.create_connection(("127.0.0.1", port), timeout=30)
        def probe():
            start = time.monotonic(); host.sendall(GET_STATUS); got = b""
            while len(got) < 8 or len(got) < 9 + int.from_bytes(got[4:8], "big"):
                chunk = host.recv(65536)
                if not chunk: raise SystemExit("TCP closed")
                got += chunk
            return time.monotonic() - start
        for _ in range(10): probe()
        request = {"execute": "add-object", "id": 1, "arguments": {"object": {"name": "rock",
                   "mesh": {"file": mesh}, "pose": {"position_m": [30, 0, 0]}}}}
        ctl.sendall((json.dumps(request) + "\n").encode())
        began = time.monotonic(); worst = 0.0; answered = 0; seen = b""; done = False
        while not done and time.monotonic() - began < 30:
            worst = max(worst, probe()); answered += 1
            if select.select([ctl], [], [], 0)[0]:
                seen += ctl.recv(65536)
                done = any('"id":1' in l.replace(" ", "") for l in seen.decode(errors="replace").splitlines())
            time.sleep(0.005)
        print(f"{worst * 1000:.0f} {answered} {time.monotonic() - began:.2f} {int(done)}")
    finally:
        daemon.kill(); daemon.wait()
PY
)
  read -r worst answered seconds rc <<<"$(tail -n 1 <<<"$out")" || true
  _hf_rc='-' _hf_s=${seconds:-?} _hf_mib='-'  # the daemon is stopped by the probe, not by itself
  _hf_msg="worst GET_STATUS round trip ${worst:-?} ms, ${answered:-?} answered before the add-object reply"
  local ok=FAIL
  [ "${rc:-0}" = 1 ] && [[ ${answered:-0} =~ ^[0-9]+$ ]] && [ "$answered" -ge 2 ] && ok=ok
  _hf_row D8 '`add-object` of scenes/meshes/large-rock.obj (100 800 triangles), GET_STATUS every 5 ms' "$ok"
}
