#!/bin/sh
# ldoem-scan drives a scanner (driver::ScannerDevice, libldoem) or a hub's line protocol
# (ldoem_hub_client); it must not link the hub itself: yaml-cpp (the hub's configuration) nor
# the hub's epoll server. Reads the program's dynamic section (NEEDED; ldoem-scan is linked with
# --no-as-needed, so that is its whole link line) and its symbol table (what was pulled out of
# the static libraries).
# Usage: links_only_what_it_uses.sh PATH_TO_LDOEM_SCAN
set -eu
program=$1
needed=$(readelf -d "$program" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p')
[ -n "$needed" ] || { echo "FAIL: no NEEDED entries read from $program" >&2; exit 1; }
status=0
if printf '%s\n' "$needed" | grep -q '^libyaml-cpp'; then
  echo "FAIL: $program needs $(printf '%s\n' "$needed" | grep '^libyaml-cpp')" >&2
  status=1
fi
symbols=$(nm -C "$program")
# A stripped program would pass the checks below without proving anything.
printf '%s\n' "$symbols" | grep -q 'ldoem::driver::ScannerDevice::' ||
  { echo "FAIL: no ldoem symbols in $program (stripped?)" >&2; exit 1; }
for unwanted in 'ldoem::hub::Hub::' 'ldoem::hub::parse_hub_config' 'ldoem::hub::BackEndHandler' 'YAML::'; do
  if printf '%s\n' "$symbols" | grep -q "$unwanted"; then
    echo "FAIL: $program contains $unwanted" >&2
    status=1
  fi
done
[ "$status" -eq 0 ] && echo "ldoem-scan needs: $(printf '%s ' $needed)"
exit "$status"
