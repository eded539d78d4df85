#!/bin/sh
# What every program promises a user at a terminal (issue 24, "Every program"): --help fits a
# screen (exit 0, at most 40 lines of at most 80 columns, at least three options, a last line
# pointing to --help-all and the man page); --version prints "NAME VERSION"; --help-all names
# --completion; each bad command line below is one line "NAME: reason (try --help)" on stderr
# with exit 2. Every run is bounded by timeout(1).
# Usage: help_fits.sh TOOL_PATH [VERSION]
set -u
tool=$1
version=${2:-}
name=$(basename "$tool")
work=$(mktemp -d /tmp/ldoem-help.XXXXXX)
trap 'rm -rf "$work"' EXIT
failures=0

fail() {
  echo "FAIL $name: $*"
  failures=$((failures + 1))
}

run() {
  timeout 10 "$tool" "$@" >"$work/out" 2>"$work/err" </dev/null
  status=$?
}

run --help
[ "$status" -eq 0 ] || fail "--help exited $status"
lines=$(wc -l <"$work/out")
[ "$lines" -le 40 ] || fail "--help has $lines lines, more than 40"
widest=$(awk '{ if (length($0) > w) w = length($0) } END { print w + 0 }' "$work/out")
[ "$widest" -le 80 ] || fail "--help has a line of $widest columns: $(awk 'length($0) > 80' "$work/out" | head -n1)"
options=$(grep -c '^ *-' "$work/out")
[ "$options" -ge 3 ] || fail "--help names only $options options"
tail -n1 "$work/out" | grep -q -- "--help-all" || fail "--help's last line does not point to --help-all"
tail -n1 "$work/out" | grep -q "man $name" || fail "--help's last line does not point to the man page"

run --help-all
[ "$status" -eq 0 ] || fail "--help-all exited $status"
grep -q -- "--completion" "$work/out" || fail "--help-all does not name --completion"

run --version
[ "$status" -eq 0 ] || fail "--version exited $status"
if [ -n "$version" ]; then
  [ "$(cat "$work/out")" = "$name $version" ] || fail "--version printed '$(cat "$work/out")', not '$name $version'"
else
  grep -q "^$name [0-9]" "$work/out" || fail "--version printed '$(cat "$work/out")'"
fi

# bad ARGS...: one line "NAME: ... (try --help)" on stderr, exit 2 (ldoem-ctl's unknown or
# missing command lists the commands instead).
bad() {
  run "$@"
  [ "$status" -eq 2 ] || fail "'$*' exited $status, expected 2"
  [ "$(wc -l <"$work/err")" -eq 1 ] || fail "'$*' printed $(wc -l <"$work/err") lines on stderr: $(head -n3 "$work/err")"
  grep -q -e "^$name: .*(try --help)$" -e "^$name: .* command.* (commands: .*)$" "$work/err" || fail "'$*' printed: $(head -n1 "$work/err")"
}

bad --no-such-option
case $name in
  ldoem-emud) bad --scene; bad --scene s.yaml --no-can --time-scale soon ;;
  ldoem-hub) bad --config; bad --config h.yaml --max-clients many ;;
  ldoem-scan) bad --out; bad --device tcp:127.0.0.1:1 --out s.ply --speed fast ;;
  ldoem-conformance) bad --tcp; bad --tcp tcp:127.0.0.1:1 --timeout soon ;;
  ldoem-replay) bad --tcp; bad s.pcapng --tcp tcp:127.0.0.1:0 --speed fast ;;
  ldoem-ctl) bad --control; bad --control p inject-fault motor_stall --duration soon; bad --control p bogus; bad --control p ;;
  ldoem-latency) bad --tcp; bad --tcp 127.0.0.1:1 --requests many ;;
esac

[ $failures -eq 0 ] && echo "PASS $name" && exit 0
exit 1
