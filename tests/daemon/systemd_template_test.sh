#!/bin/sh
# The installed emulator templates (packaging/systemd/ldoem-emud@.service, one scanner per
# instance, and ldoem-emud-group@.service, a scene with a scanners: list) parse without a warning
# in systemd-analyze verify (ExecStart pointed at /bin/true: the check needs an existing binary),
# and the example env file sets every variable of their ExecStart that systemd does not set
# itself. scripts/check-units.sh checks the installed units further (security rating).
set -eu
source_dir="$1"
example="$source_dir/packaging/systemd/ldoem-emud.env.example"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
for template in ldoem-emud ldoem-emud-group; do
  unit="$source_dir/packaging/systemd/$template@.service"
  sed 's|/usr/bin/ldoem-emud|/bin/true|' "$unit" >"$work/$template@cell1.service"
  report="$(timeout 60 systemd-analyze verify "$work/$template@cell1.service" 2>&1)" || {
    echo "systemd-analyze verify failed on $template@.service: $report"; exit 1; }
  if [ -n "$report" ]; then echo "systemd-analyze verify complained about $template@.service: $report"; exit 1; fi
  for variable in $(grep '^ExecStart=' "$unit" | grep -oE '\$\{?[A-Z_]+' | tr -d '${' | sort -u); do
    [ "$variable" = STATE_DIRECTORY ] && continue  # set by systemd from StateDirectory=
    grep -q "^$variable=" "$example" || { echo "$example does not set $variable"; exit 1; }
  done
done
# The group template must not name one scanner's endpoint or flash: a daemon with several
# scanners refuses those options (exit 2), so the unit would never start.
group="$source_dir/packaging/systemd/ldoem-emud-group@.service"
if grep -E '^(ExecStart|Environment)=.*(--flash |--tcp|--can-ids|--serial|--lpt|--record)' "$group"; then
  echo "ldoem-emud-group@.service names an option a scanner group refuses"; exit 1
fi
# Out of the box a 3D scan works (issue 24): the shipped hub.yaml names ldoem-emud@corridor's
# LPT pty, and the hub runs as the emulator's dynamic user, so that it may open that pty.
unit="$source_dir/packaging/systemd/ldoem-emud@.service"
lpt=$(sed -n 's/^Environment="LDOEM_EMUD_ARGS=.*--lpt lpt:pty:\([^ "]*\).*/\1/p' "$unit" | sed 's/%i/corridor/')
if [ -z "$lpt" ] || ! grep -q "^    lpt: lpt:pty:$lpt\$" "$source_dir/packaging/etc/hub.yaml"; then
  echo "packaging/etc/hub.yaml does not name the LPT pty of ldoem-emud@corridor (${lpt:-none})"; exit 1
fi
for other in ldoem-emud-group@.service ldoem-hub.service; do
  if [ "$(grep '^User=' "$unit")" != "$(grep '^User=' "$source_dir/packaging/systemd/$other")" ]; then
    echo "$other does not run as ldoem-emud@.service's user: the hub could not open its ptys"; exit 1
  fi
done
echo "ok"
