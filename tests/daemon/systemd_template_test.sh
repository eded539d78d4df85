#!/bin/sh
# The installed emulator template (packaging/systemd/ldoem-emud@.service) parses without a
# warning in systemd-analyze verify (ExecStart pointed at /bin/true: the check needs an existing
# binary), and the example env file sets every variable of ExecStart that systemd does not set
# itself. scripts/check-units.sh checks both installed units further (security rating).
set -eu
source_dir="$1"
unit="$source_dir/packaging/systemd/ldoem-emud@.service"
example="$source_dir/packaging/systemd/ldoem-emud.env.example"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
sed 's|/usr/bin/ldoem-emud|/bin/true|' "$unit" >"$work/ldoem-emud@cell1.service"
report="$(timeout 60 systemd-analyze verify "$work/ldoem-emud@cell1.service" 2>&1)" || {
  echo "systemd-analyze verify failed: $report"; exit 1; }
if [ -n "$report" ]; then echo "systemd-analyze verify complained: $report"; exit 1; fi
for variable in $(grep '^ExecStart=' "$unit" | grep -oE '\$\{?[A-Z_]+' | tr -d '${' | sort -u); do
  [ "$variable" = STATE_DIRECTORY ] && continue  # set by systemd from StateDirectory=
  grep -q "^$variable=" "$example" || { echo "$example does not set $variable"; exit 1; }
done
echo "ok"
