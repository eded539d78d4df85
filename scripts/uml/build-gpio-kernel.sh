#!/bin/sh
# Build (once) the small User-Mode Linux kernel that has gpio-sim AND vcan/CAN_RAW/CAN_ISOTP built
# in, and print its path on stdout. Debian's stock linux.uml has no GPIOLIB and no can-isotp, so the
# gpio back end of the pseudo-LPT (D8) and the kernel ISO-TP transport can only be tested in this
# kernel. The recipe (which options and why) is gpio-kernel.config.sh next to this script.
#
# The kernel is cached OUTSIDE the clone, keyed by a hash of this script and the config fragment:
#   ${LDOEM_CACHE:-$HOME/.cache/ldoem}/uml-gpio-<hash>/linux
# A warm cache prints the path and returns at once; a cold one takes ~4-5 min on 2 cores.
#
# Usage: scripts/uml/build-gpio-kernel.sh [--help]
#   Environment: LDOEM_CACHE (cache root), LDOEM_LINUX_SOURCE (tarball, default
#   /usr/src/linux-source-6.1.tar.xz from Debian's linux-source-6.1), LDOEM_KERNEL_JOBS (default 2).
# Exit status: 0 and the kernel path on stdout; 1 if the build failed (log tail on stderr);
#   2 on a usage error.
set -eu

here=$(cd "$(dirname "$0")" && pwd)
fragment="$here/gpio-kernel.config.sh"

case "${1:-}" in
  -h|--help) sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  "") ;;
  *) echo "build-gpio-kernel.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
esac

cache_root=${LDOEM_CACHE:-$HOME/.cache/ldoem}
key=$(cat "$0" "$fragment" | sha256sum | cut -c1-16)
cache_dir="$cache_root/uml-gpio-$key"
kernel="$cache_dir/linux"

# Fast path: nothing to do, no lock, no tools (must stay well under a second).
if [ -x "$kernel" ]; then
  echo "$kernel"
  exit 0
fi

say() { echo "build-gpio-kernel.sh: $*" >&2; }

source_tarball=${LDOEM_LINUX_SOURCE:-/usr/src/linux-source-6.1.tar.xz}
jobs=${LDOEM_KERNEL_JOBS:-2}
if [ ! -r "$source_tarball" ]; then
  say "$source_tarball not found; install it with: apt-get install -y linux-source-6.1"
  exit 1
fi
for tool in make gcc flex bison bc tar xz flock; do
  command -v "$tool" >/dev/null 2>&1 || { say "missing build tool '$tool'"; exit 1; }
done

mkdir -p "$cache_root"
# One builder per key at a time: a second caller waits and then finds the finished kernel.
exec 9>"$cache_root/uml-gpio-$key.lock"
flock 9
if [ -x "$kernel" ]; then
  echo "$kernel"
  exit 0
fi

work=$(mktemp -d "$cache_root/uml-gpio-$key.build.XXXXXX")
cleanup() { rm -rf "$work"; }
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM
log="$work/build.log"
started=$(date +%s)

fail() {
  say "$1; last lines of the build log:"
  tail -n 40 "$log" >&2 || true
  exit 1
}

say "building the gpio-sim UML kernel in $work (about 5 min with -j$jobs)"
tar -xf "$source_tarball" -C "$work" >>"$log" 2>&1 || fail "unpacking $source_tarball failed"
src=$(find "$work" -mindepth 1 -maxdepth 1 -type d -name 'linux-source-*' | head -n 1)
[ -n "$src" ] || fail "no linux-source-* folder in $source_tarball"
out="$work/build"
mkdir -p "$out"

# shellcheck source=gpio-kernel.config.sh
. "$fragment"
(
  cd "$src"
  make ARCH=um O="$out" tinyconfig
  ldoem_gpio_kernel_options "scripts/config --file $out/.config"
  make ARCH=um O="$out" olddefconfig
) >>"$log" 2>&1 || fail "configuring the kernel failed"

for option in $LDOEM_GPIO_KERNEL_REQUIRED; do
  grep -q "^CONFIG_$option=y" "$out/.config" || fail "CONFIG_$option did not end up =y"
done

(cd "$src" && make ARCH=um O="$out" -j"$jobs") >>"$log" 2>&1 || fail "make failed"
[ -x "$out/linux" ] || fail "the build produced no $out/linux"

mkdir -p "$cache_dir"
cp "$out/.config" "$cache_dir/config"
cp "$out/linux" "$cache_dir/linux.tmp"
mv "$cache_dir/linux.tmp" "$kernel"   # atomic: the fast path never sees a half-written kernel
say "done in $(( $(date +%s) - started )) s: $kernel"
echo "$kernel"
