#!/bin/sh
# The command-line contract of one tool, checked from outside as a user meets it:
# --help-all prints the recorded full usage text (golden/TOOL.help, first taken from the tool
# before its options moved to CLI11; what help2man reads) and exit 0, -h the same brief screen
# as --help (its size is help_fits.sh's); each bad command line of this tool's table exits 2 with
# one line "TOOL: ..." on stderr; `--completion bash` prints a bash completion; ldoem-hub ends
# with 128+15 on SIGTERM. Every run is bounded by timeout(1).
# Usage: cli_contract.sh TOOL_PATH GOLDEN_DIR [SOURCE_DIR]
set -u
tool=$1
golden_dir=$2
name=$(basename "$tool")
work=$(mktemp -d /tmp/ldoem-cli.XXXXXX)
trap 'rm -rf "$work"' EXIT
failures=0

fail() {
  echo "FAIL $name: $*"
  failures=$((failures + 1))
}

# expect_exit CODE ARGS...: the tool exits CODE; for 2, stderr starts with "NAME: ".
expect_exit() {
  expected=$1
  shift
  timeout 10 "$tool" "$@" >"$work/out" 2>"$work/err" </dev/null
  status=$?
  if [ "$status" -ne "$expected" ]; then
    fail "'$*' exited $status, expected $expected; stderr: $(head -n1 "$work/err")"
    return
  fi
  if [ "$expected" -eq 2 ] && ! head -n1 "$work/err" | grep -q "^$name: ."; then
    fail "'$*' gave no one-line reason on stderr: $(head -n1 "$work/err")"
  fi
}

# expect_old ARGS...: a spelling from before docs/endpoints.md: exit 2 and one line on stderr
# that names the new spelling (issue 24).
expect_old() {
  expect_exit 2 "$@"
  [ "$(wc -l <"$work/err")" -eq 1 ] || fail "'$*' printed $(wc -l <"$work/err") lines on stderr, not one"
  grep -q "is the old spelling; write .* (docs/endpoints.md)$" "$work/err" ||
    fail "'$*' does not name the new spelling: $(head -n1 "$work/err")"
}

expect_exit 0 --help-all
if ! cmp -s "$work/out" "$golden_dir/$name.help"; then
  fail "--help-all differs from $golden_dir/$name.help:"
  diff "$golden_dir/$name.help" "$work/out" | head -n 20
fi
grep -q -- "--completion" "$work/out" || fail "--help-all does not name --completion"
expect_exit 0 --help
mv "$work/out" "$work/brief"
expect_exit 0 -h
cmp -s "$work/out" "$work/brief" || fail "-h and --help differ"
grep -q -- "--help-all" "$work/brief" || fail "--help does not point to --help-all"

expect_exit 0 --completion bash
grep -q "^complete -o filenames -F _" "$work/out" || fail "--completion bash printed no completion"
grep -q -- "--help" "$work/out" || fail "--completion bash does not offer --help"
expect_exit 2 --completion zsh
expect_exit 2 --no-such-option
[ "$(wc -l <"$work/err")" -eq 1 ] || fail "a usage error printed $(wc -l <"$work/err") lines on stderr, not one: $(head -n3 "$work/err")"
grep -q -- "--help" "$work/err" || fail "a usage error gives no hint: $(cat "$work/err")"
expect_exit 0 --version
grep -q "^$name [0-9]" "$work/out" || fail "--version printed: $(head -n1 "$work/out")"
expect_exit 2 stray-argument

case $name in
  ldoem-hub)
    printf 'devices:\n  - name: left\n    scanner: tcp:127.0.0.1:1\n' >"$work/hub.yaml"
    expect_exit 2
    expect_exit 2 --config
    expect_exit 2 --config "$work/hub.yaml" --listen nowhere
    expect_exit 2 --config "$work/hub.yaml" --max-age-ms soon
    expect_exit 2 --config "$work/hub.yaml" --max-clients 0
    expect_exit 2 --config "$work/hub.yaml" --queue -1
    expect_exit 2 --config "$work/missing.yaml"
    # The config's endpoints are the grammar of every tool: an old spelling names the new one.
    printf 'devices:\n  - name: left\n    scanner: tcp:127.0.0.1:1\n    lpt: pty:/tmp/x\n' >"$work/old.yaml"
    expect_exit 2 --config "$work/old.yaml"
    grep -q "devices\[0\].lpt: .pty:/tmp/x. is the old spelling; write lpt:pty:/tmp/x (docs/endpoints.md)" "$work/err" ||
      fail "an old lpt spelling in the config does not name the new one: $(head -n1 "$work/err")"
    # Started for real on a free port, then stopped: 128 + SIGTERM.
    timeout 10 "$tool" --config "$work/hub.yaml" --listen 127.0.0.1:0 2>"$work/err" &
    hub=$!
    tries=0
    while ! grep -q "listening" "$work/err" && [ $tries -lt 100 ]; do
      sleep 0.05
      tries=$((tries + 1))
    done
    kill -TERM $hub
    wait $hub
    status=$?
    [ $status -eq 143 ] || fail "SIGTERM: exited $status, expected 143; stderr: $(cat "$work/err")"
    ;;
  ldoem-scan)
    expect_exit 2
    expect_exit 2 --out scan.ply
    expect_exit 2 --device tcp:127.0.0.1:1 --out scan.txt
    expect_exit 2 --device tcp:127.0.0.1:1 --out scan.ply --speed 30
    expect_exit 2 --device tcp:127.0.0.1:1 --out scan.ply --format text
    expect_exit 2 --device tcp:127.0.0.1:1 --out scan.ply --optical-offset 1,2
    expect_exit 2 --device tcp:127.0.0.1:1 --out scan.ply --timeout
    expect_exit 2 --device lpt:pty:/tmp/x --out scan.ply
    expect_exit 2 --hub 127.0.0.1:49200 --out scan.ply
    expect_exit 2 --device tcp:127.0.0.1:1 --hub 127.0.0.1:49200 --hub-device a --out scan.ply
    expect_exit 2 --device tcp:127.0.0.1:1 --out scan.ply --reconnect-attempts 0
    expect_exit 2 --device tcp:127.0.0.1:1 --out scan.ply --reconnect-backoff 0.5
    expect_exit 2 --hub 127.0.0.1:49200 --hub-device a --out scan.ply --reconnect-interval 2
    # Outputs are checked before the first request: the folder's error, not the device's.
    expect_exit 1 --device tcp:127.0.0.1:1 --vertical-apex 0 --out "$work/missing/scan.ply" --timeout 1
    grep -q "missing.*No such file or directory" "$work/err" || fail "a missing output folder is not named: $(cat "$work/err")"
    grep -q "connect" "$work/err" && fail "the device was contacted before the output was checked: $(cat "$work/err")"
    expect_exit 2 --device tcp:127.0.0.1:1 --vertical-apex 0 --out scan.ply --preview scan.jpg
    expect_exit 2 --device tcp:127.0.0.1:1 --vertical-apex 0 --out scan.ply --render scan
    expect_old --device tcp:127.0.0.1:1 --lpt pty:/tmp/x --out scan.ply
    expect_old --device 127.0.0.1:49152 --out scan.ply
    expect_old --device vcan0 --out scan.ply
    expect_exit 2 --device lpt:pty:/tmp/x --out scan.ply
    # A good command line against a port where nothing listens: a runtime failure, exit 1.
    expect_exit 1 --device tcp:127.0.0.1:1 --vertical-apex 0 --out "$work/scan.ply" --timeout 1
    ;;
  ldoem-conformance)
    expect_exit 2
    expect_exit 2 --tcp
    expect_exit 2 --tcp tcp:127.0.0.1:1 --serial serial:/dev/null
    expect_exit 2 --tcp tcp:127.0.0.1:1 --target robot
    expect_exit 2 --tcp tcp:127.0.0.1:1 --time-scale 0
    expect_exit 2 --tcp=tcp:127.0.0.1:1 --timeout=-1
    expect_exit 2 --can can:vcan0:6C0
    expect_old --tcp 127.0.0.1:1
    expect_old --can vcan0
    expect_old --serial /dev/null
    expect_old --ids 6C0,6C1 --tcp tcp:127.0.0.1:1
    expect_exit 2 --tcp tcp:127.0.0.1:1 --filter ''
    expect_exit 2 --tcp tcp:127.0.0.1:1 --filter nomatch
    expect_exit 2 --tcp tcp:127.0.0.1:1 --exclude '*'
    expect_exit 0 --list
    expect_exit 0 --list --tcp tcp:127.0.0.1:1 --filter 'tcp/*' --filter 'x'
    expect_exit 1 --tcp tcp:127.0.0.1:1 --timeout 1 --filter 'tcp/vectors/*'
    ;;
  ldoem-replay)
    expect_exit 2
    expect_exit 2 --tcp
    expect_exit 2 --tcp tcp:127.0.0.1:0
    expect_exit 2 scan.pcapng
    expect_exit 2 a.pcapng b.pcapng --tcp tcp:127.0.0.1:0
    expect_exit 2 scan.pcapng --tcp tcp:127.0.0.1:0 --speed 0
    expect_exit 2 scan.pcapng --tcp=tcp:127.0.0.1:0 --timeout=-1
    expect_exit 2 scan.pcapng --serial serial:/dev/null
    expect_exit 2 scan.pcapng --tcp tcp:127.0.0.1:0 --transport usb
    expect_exit 2 scan.pcapng --tcp tcp:h:70000
    expect_old scan.pcapng --tcp 127.0.0.1:0
    expect_old scan.pcapng --serial pty:/tmp/x
    expect_old scan.pcapng --lpt pty:/tmp/x --tcp tcp:127.0.0.1:0
    expect_old scan.pcapng --can vcan0
    expect_old scan.pcapng --tcp tcp:127.0.0.1:0 --can-ids 6C0:6C1
    # A good command line, but the capture cannot be read: exit 2 with the file named.
    expect_exit 2 "$work/missing.pcapng" --tcp tcp:127.0.0.1:0 --timeout 1
    grep -q "missing.pcapng" "$work/err" || fail "an unreadable capture is not named: $(cat "$work/err")"
    ;;
  ldoem-emud)
    expect_exit 0 --help --time-scale 0  # --help and --version first win over later problems
    expect_exit 2
    expect_exit 2 --scene
    expect_exit 2 --scene s.yaml --no-can
    expect_exit 2 --scene s.yaml --no-flash=1
    expect_exit 2 --scene s.yaml --tcp tcp:h:70000
    expect_exit 2 --scene s.yaml --can can:vcan0:6C0:6C1 --can can:vcan0:6C1:6C2
    expect_old --scene s.yaml --tcp 127.0.0.1:49152
    expect_old --scene s.yaml --serial pty:/tmp/x
    expect_old --scene s.yaml --lpt pty:/tmp/x
    expect_old --scene s.yaml --lpt gpio:ldoem-lpt
    expect_old --scene s.yaml --can vcan0
    expect_old --scene s.yaml --can-ids 6C0:6C1
    expect_exit 2 --scene "$work/missing.yaml" --no-can --tcp tcp:127.0.0.1:0
    ;;
esac

[ $failures -eq 0 ] && echo "PASS $name" && exit 0
exit 1
