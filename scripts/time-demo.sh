#!/usr/bin/env bash
# Times the first command (scripts/demo.sh) as a newcomer meets it (issue 24 item 1):
#   1. a clean Debian 12 root made by mmdebstrap from the mirror of /etc/apt/sources.list* (the
#      apt variant plus git, since the newcomer has cloned the repository), cached as a tarball
#      in ${LDOEM_CACHE:-~/.cache/ldoem}/demo-root like scripts/check-deb-root.sh's;
#   2. a fresh clone of this repository's HEAD inside it (commit first: the worktree's changes
#      are not in it), an empty compiler cache, no ldoem dependency installed;
#   3. `scripts/demo.sh --build-only` run in the root by systemd-nspawn (the host's network, for
#      apt): deps (apt), configure and build, each timed by demo.sh;
#   4. `scripts/demo.sh --scan-only` with the root's programs, run on the host: User-Mode Linux
#      does not boot inside systemd-nspawn (its guest cannot mount /proc over hostfs there), so
#      the scan, with the UML boot's share, is timed outside the root;
#   5. the load average before and after, since the machine may be shared.
#   scripts/time-demo.sh [demo.sh arguments]       (root; mmdebstrap, systemd-nspawn, zstd)
set -euo pipefail
cd "$(dirname "$0")/.."
[ "$(id -u)" -eq 0 ] || { echo "time-demo: needs root (mmdebstrap, systemd-nspawn)" >&2; exit 2; }
for tool in mmdebstrap systemd-nspawn zstd git; do
  command -v "$tool" >/dev/null || { echo "time-demo: $tool is missing (scripts/install-deps.sh)" >&2; exit 2; }
done
cache=${LDOEM_CACHE:-$HOME/.cache/ldoem}/demo-root
mirror=${LDOEM_DEB_MIRROR:-$(sed -n 's/^URIs:[[:space:]]*\(http[^ ]*debian\)\/*$/\1/p' /etc/apt/sources.list.d/*.sources 2>/dev/null | head -n 1)}
[ -n "$mirror" ] || mirror=$(awk '$1 == "deb" && $3 == "bookworm" { print $2; exit }' /etc/apt/sources.list 2>/dev/null)
[ -n "$mirror" ] || { echo "time-demo: no Debian mirror in /etc/apt/sources.list*; set LDOEM_DEB_MIRROR" >&2; exit 2; }
key=$(printf 'bookworm apt git %s\n' "$mirror" | sha256sum | cut -c1-16)
tarball="$cache/bookworm-git-$key.tar.zst"
work=$(mktemp -d "${TMPDIR:-/var/tmp}/ldoem-time-demo.XXXXXX")
trap 'rm -rf "$work"' EXIT
if [ ! -f "$tarball" ]; then
  echo "time-demo: mmdebstrap bookworm (apt variant, git) from $mirror"
  mkdir -p "$cache"
  mmdebstrap --quiet --variant=apt --include=git bookworm "$work/base.tar.zst" "$mirror"
  mv "$work/base.tar.zst" "$tarball"  # only a finished tarball enters the cache
fi
root="$work/root"
mkdir "$root"
tar --zstd -xpf "$tarball" -C "$root"
git clone --quiet --no-local "$PWD" "$root/root/ldoem"
echo "time-demo: a clean bookworm root, a clone of $(git rev-parse --short HEAD), an empty ccache"
echo "time-demo: load average before: $(cut -d' ' -f1-3 /proc/loadavg) ($(nproc) cores)"
started=$SECONDS
status=0
# --keep-unit, --register=no: no host systemd or machined needed. The CPU time (user + system,
# of every process the demo waited for) tells what the build would take on an idle machine.
TIMEFORMAT='time-demo: --build-only used %U s user + %S s system CPU in %R s'
time systemd-nspawn --quiet --register=no --keep-unit --directory="$root" --chdir=/root/ldoem \
  --setenv=HOME=/root --setenv=LANG=C.UTF-8 scripts/demo.sh --build-only || status=$?
built=$((SECONDS - started))
echo "time-demo: scripts/demo.sh --build-only exit $status after $built s in the clean root"
if ((status == 0)); then
  LDOEM_BUILD="$root/root/ldoem/build/demo" "$root/root/ldoem/scripts/demo.sh" --scan-only "$@" || status=$?
  echo "time-demo: scripts/demo.sh --scan-only exit $status after $((SECONDS - started - built)) s on the host"
fi
echo "time-demo: in all $((SECONDS - started)) s"
echo "time-demo: load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
exit "$status"
