#!/usr/bin/env bash
# The .deb as a user gets it, on a clean Debian 12 (docs/service.md, docs/ci.md):
#   1. the .deb (built here with cpack from BUILD_DIR, or --deb FILE) passes lintian with no error;
#   2. a clean bookworm root made by mmdebstrap from Debian's mirror, with the .deb's dependencies
#      (its Depends field), cached as a tarball in ${LDOEM_CACHE:-~/.cache/ldoem}/deb-root keyed by
#      the package list, so that a rerun only unpacks it;
#   3. `dpkg -i` of the .deb into that root, and `import ldoem` there with the root's python3;
#   4. the root booted with systemd-nspawn (its own network namespace: only its loopback), where a
#      one-shot unit starts ldoem-emud@corridor.service and ldoem-hub.service as shipped (their
#      /etc/ldoem/hub.yaml, their hardening) and runs `ldoem-scan --hub ... --out corridor.ply`
#      at the paper's settings, then powers the root off;
#   5. the cloud has the scan's 81 x 121 = 9801 points.
#   scripts/check-deb-root.sh [--deb FILE] [BUILD_DIR]      (root; default BUILD_DIR build/default)
# Needs root, mmdebstrap, systemd-nspawn (systemd-container), lintian and the Debian mirror of
# /etc/apt/sources.list* (LDOEM_DEB_MIRROR overrides it). Exit status 0 only if all passed.
set -euo pipefail
cd "$(dirname "$0")/.."
deb=""
if [ "${1:-}" = "--deb" ]; then deb=$(realpath "$2"); shift 2; fi
build=${1:-build/default}
[ "$(id -u)" -eq 0 ] || { echo "check-deb-root: needs root (mmdebstrap, dpkg in the root, systemd-nspawn)" >&2; exit 2; }
for tool in mmdebstrap systemd-nspawn lintian zstd; do
  command -v "$tool" >/dev/null || { echo "check-deb-root: $tool is missing (scripts/install-deps.sh)" >&2; exit 2; }
done
cache=${LDOEM_CACHE:-$HOME/.cache/ldoem}/deb-root
work=$(mktemp -d "${TMPDIR:-/tmp}/ldoem-deb-root.XXXXXX")
root="$work/root"
cleanup() {
  if mountpoint -q "$root"; then umount "$root"; fi
  rm -rf "$work"
}
trap cleanup EXIT
started=$SECONDS
step() { printf '\n--- %s (%d s)\n' "$*" $((SECONDS - started)); }

if [ -z "$deb" ]; then
  step "cpack -G DEB in $build"
  (cd "$build" && cpack -G DEB -B "$work/deb" >/dev/null)
  deb=$(ls "$work"/deb/*.deb)
fi

step "lintian $(basename "$deb")"
# Errors fail; the warnings that remain are each explained in docs/service.md.
if ! lintian --fail-on error --tag-display-limit 0 "$deb" 2>&1 | { grep -v "^running with root privileges" || true; } |
     tee "$work/lintian.txt"; then
  echo "check-deb-root: lintian reports $(grep -c '^E:' "$work/lintian.txt" || true) errors" >&2
  exit 1
fi
echo "check-deb-root: lintian: $(grep -c '^E:' "$work/lintian.txt" || true) errors," \
     "$(grep -c '^W:' "$work/lintian.txt" || true) warnings"

step "a clean Debian 12 root with the package's dependencies"
# The package's Depends, each alternative's first choice, without versions: what apt would pull in.
depends=$(dpkg-deb -f "$deb" Depends | tr ',' '\n' | sed 's/|.*//; s/(.*)//; s/[[:space:]]//g' | grep -v '^$' | sort -u)
packages=$(printf '%s\n' systemd $depends | sort -u | paste -sd, -)
mirror=${LDOEM_DEB_MIRROR:-$(sed -n 's/^URIs:[[:space:]]*\(http[^ ]*debian\)\/*$/\1/p' /etc/apt/sources.list.d/*.sources 2>/dev/null | head -n 1)}
[ -n "$mirror" ] || mirror=$(awk '$1 == "deb" && $3 == "bookworm" { print $2; exit }' /etc/apt/sources.list 2>/dev/null)
[ -n "$mirror" ] || { echo "check-deb-root: no Debian mirror in /etc/apt/sources.list*; set LDOEM_DEB_MIRROR" >&2; exit 2; }
key=$(printf 'bookworm apt %s %s\n' "$mirror" "$packages" | sha256sum | cut -c1-16)
tarball="$cache/bookworm-$key.tar.zst"
if [ -f "$tarball" ]; then
  echo "check-deb-root: cached root $tarball"
else
  echo "check-deb-root: mmdebstrap bookworm from $mirror with $packages"
  mkdir -p "$cache"
  mmdebstrap --quiet --variant=apt --include="$packages" bookworm "$work/base.tar.zst" "$mirror"
  mv "$work/base.tar.zst" "$tarball"  # only a finished tarball enters the cache
fi
# The root lives in a tmpfs: unpacking it and removing it at the end take a few seconds instead
# of half a minute on a busy disk (254 MiB, 8477 files).
mkdir "$root"
mount -t tmpfs -o size=2G,mode=0755 ldoem-deb-root "$root"
tar --zstd -xpf "$tarball" -C "$root"

step "dpkg -i $(basename "$deb") in the root"
cp "$deb" "$root/tmp/ldoem.deb"
chroot "$root" dpkg -i /tmp/ldoem.deb >"$work/dpkg.log" 2>&1 || { cat "$work/dpkg.log" >&2; exit 1; }
rm "$root/tmp/ldoem.deb"
for file in /etc/ldoem/hub.yaml /usr/bin/ldoem-replay /usr/share/man/man1/ldoem-emud.1.gz \
            /usr/share/doc/ldoem/copyright /usr/share/bash-completion/completions/ldoem-scan; do
  [ -e "$root$file" ] || { echo "check-deb-root: $file is not installed" >&2; exit 1; }
done
grep -qx /etc/ldoem/hub.yaml "$root/var/lib/dpkg/info/ldoem.conffiles" ||
  { echo "check-deb-root: /etc/ldoem/hub.yaml is not a conffile" >&2; exit 1; }
# The Python package from the .deb, with the root's own python3 and numpy (issue 25).
version=$(chroot "$root" python3 -c "import ldoem; print(ldoem.__version__)" 2>&1) ||
  { echo "check-deb-root: import ldoem from the .deb failed: $version" >&2; exit 1; }
echo "check-deb-root: import ldoem from the .deb: version $version"

step "boot the root (systemd-nspawn), scan through ldoem-hub.service"
# The scan runs inside, as a one-shot unit after boot; it always powers the root off, so the
# boot ends by itself. The paper's settings (scripts/scan-corridor.sh): 81 x 121 beams.
cat >"$root/usr/local/sbin/ldoem-ci-scan" <<'EOF'
#!/bin/sh
out=/var/log/ldoem-ci
mkdir -p "$out"
trap 'journalctl --no-pager -o short-monotonic -u ldoem-emud@corridor -u ldoem-hub >"$out/journal.txt" 2>&1
      systemctl poweroff' EXIT
systemctl start ldoem-emud@corridor.service ldoem-hub.service >"$out/start.txt" 2>&1 || { echo 1 >"$out/scan.rc"; exit 1; }
timeout 300 ldoem-scan --hub 127.0.0.1:49200 --hub-device corridor --out "$out/corridor.ply" \
  --horizontal-apex 20 --horizontal-resolution 0.25 --vertical-apex 21.6 --vertical-resolution 0.18 \
  --speed 10 >"$out/scan.txt" 2>&1
echo $? >"$out/scan.rc"
systemctl is-active ldoem-emud@corridor.service ldoem-hub.service >"$out/active.txt" 2>&1
EOF
chmod 755 "$root/usr/local/sbin/ldoem-ci-scan"
cat >"$root/etc/systemd/system/ldoem-ci-scan.service" <<'EOF'
[Unit]
Description=check-deb-root: a 3D scan through the installed units
After=multi-user.target
[Service]
Type=oneshot
ExecStart=/usr/local/sbin/ldoem-ci-scan
[Install]
WantedBy=multi-user.target
EOF
ln -s /etc/systemd/system/ldoem-ci-scan.service "$root/etc/systemd/system/multi-user.target.wants/"
# --keep-unit, --register=no: no host systemd or machined needed (CI may run in a container).
timeout 600 systemd-nspawn --quiet --register=no --keep-unit --private-network --directory="$root" --boot \
  >"$work/boot.log" 2>&1 || { tail -n 40 "$work/boot.log" >&2; echo "check-deb-root: the boot failed or hung" >&2; exit 1; }

step "the cloud"
out="$root/var/log/ldoem-ci"
report() { for f in start.txt scan.txt active.txt journal.txt; do [ -f "$out/$f" ] && { echo "== $f"; tail -n 30 "$out/$f"; }; done >&2; }
[ "$(cat "$out/scan.rc" 2>/dev/null)" = 0 ] || { report; echo "check-deb-root: the scan through the hub failed" >&2; exit 1; }
points=$(sed -n 's/^element vertex \([0-9]*\)$/\1/p' "$out/corridor.ply" | head -n 1)
[ "$points" = 9801 ] || { report; echo "check-deb-root: corridor.ply has ${points:-no} points, not 81 x 121 = 9801" >&2; exit 1; }
grep -q '^active' "$out/active.txt" && ! grep -qv '^active$' "$out/active.txt" ||
  { report; echo "check-deb-root: a unit did not stay active through the scan" >&2; exit 1; }
sed 's/^/  ldoem-scan: /' "$out/scan.txt" | tr '\r' '\n' | grep -v '^  ldoem-scan: *$' | tail -n 5
grep -E 'Started|ready|lpt|tcp ' "$out/journal.txt" | sed 's/^/  journal: /' | head -n 12
echo "check-deb-root: $(basename "$deb") installed into a clean bookworm root; ldoem-emud@corridor and ldoem-hub" \
     "scanned through systemd: corridor.ply with $points points"
echo "check-deb-root: all passed in $((SECONDS - started)) s"
