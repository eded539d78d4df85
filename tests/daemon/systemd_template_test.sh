#!/bin/sh
# The systemd template (scripts/systemd/ldoem-emud@.service) parses without a warning in
# systemd-analyze verify (ExecStart pointed at /bin/true: the check needs an existing binary),
# and the example env file sets every variable the unit's ExecStart uses.
set -eu
source_dir="$1"
unit="$source_dir/scripts/systemd/ldoem-emud@.service"
example="$source_dir/scripts/systemd/ldoem-emud.env.example"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
sed 's|/usr/local/bin/ldoem-emud|/bin/true|' "$unit" >"$work/ldoem-emud@cell1.service"
report="$(timeout 60 systemd-analyze verify "$work/ldoem-emud@cell1.service" 2>&1)" || {
  echo "systemd-analyze verify failed: $report"; exit 1; }
if [ -n "$report" ]; then echo "systemd-analyze verify complained: $report"; exit 1; fi
for variable in $(grep '^ExecStart=' "$unit" | grep -o '\${[A-Z_]*}' | tr -d '${}' | sort -u); do
  grep -q "^$variable=" "$example" || { echo "$example does not set $variable"; exit 1; }
done
echo "ok"
