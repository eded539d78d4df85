#!/usr/bin/env bash
# Checks the systemd units as installed: `systemd-analyze verify` must pass on all three, and
# `systemd-analyze security` must rate each at 2.0 or below (lower is better).
#   scripts/check-units.sh [STAGED_ROOT]
# STAGED_ROOT is a `DESTDIR=... cmake --install ... --prefix /usr` tree (scripts/check-install.sh
# makes one); without it the units are checked against stand-in binaries. Prints each unit's
# exposure level; exit status 1 if a check fails.
set -euo pipefail
cd "$(dirname "$0")/.."
limit=2.0
work=$(mktemp -d "${TMPDIR:-/tmp}/ldoem-units.XXXXXX")
trap 'rm -rf "$work"' EXIT
root="$work/root"
mkdir -p "$root/usr/lib/systemd/system" "$root/usr/bin" "$root/etc/ldoem"
if [ $# -ge 1 ]; then
  cp -a "$1/." "$root/"
else
  for program in ldoem-emud ldoem-hub; do printf '#!/bin/sh\n' >"$root/usr/bin/$program"; chmod 755 "$root/usr/bin/$program"; done
  cp packaging/systemd/*.service "$root/usr/lib/systemd/system/"
fi
# The targets and slices the units depend on (sysinit.target, ...) come from the host.
cp -n /usr/lib/systemd/system/*.target /usr/lib/systemd/system/*.slice "$root/usr/lib/systemd/system/" 2>/dev/null || true
units="$root/usr/lib/systemd/system"
ln -sf ldoem-emud@.service "$units/ldoem-emud@corridor.service"
ln -sf ldoem-emud-group@.service "$units/ldoem-emud-group@corridor-two-scanners.service"
status=0
for unit in ldoem-hub.service ldoem-emud@corridor.service ldoem-emud-group@corridor-two-scanners.service; do
  # verify exits 0 on an unknown or misspelt key (it only warns), so any message is a failure.
  if ! messages=$(systemd-analyze verify --root="$root" "$units/$unit" 2>&1) || [ -n "$messages" ]; then
    printf '%s\n' "$messages" >&2
    echo "check-units: systemd-analyze verify failed on $unit" >&2
    status=1
  fi
  level=$(systemd-analyze security --offline=yes --root="$root" "$unit" 2>/dev/null |
          sed -n 's/.*Overall exposure level for [^:]*: \([0-9.]*\).*/\1/p')
  if [ -z "$level" ]; then
    echo "check-units: systemd-analyze security gave no rating for $unit" >&2
    status=1
    continue
  fi
  echo "check-units: $unit exposure $level (limit $limit)"
  if awk -v level="$level" -v limit="$limit" 'BEGIN { exit !(level > limit) }'; then
    echo "check-units: $unit is rated $level, above $limit" >&2
    status=1
  fi
done
exit $status
