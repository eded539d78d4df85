#!/usr/bin/env bash
# What a user of the installed package gets, checked from a built tree (default: build/default):
#   1. `cmake --install` into a staging folder (DESTDIR, prefix /usr);
#   2. the systemd units as installed (scripts/check-units.sh: verify, security <= 2.0);
#   3. examples/consumer built against the installed CMake package (find_package(ldoem),
#      ldoem::driver) and once more with pkg-config (ldoem.pc) from a `cmake --install --prefix
#      DIR`, as docs/service.md shows it (no --define-prefix: ldoem.pc finds its own prefix);
#   4. the consumer run against the installed ldoem-emud with an installed scene (TCP);
#   5. the Python package (when built): `import ldoem` from the installed prefix, on the
#      interpreter's sys.path, and ldoem.Scanner against the installed daemon;
#   6. `cpack -G DEB`, and the package holds the programs, units, scenes, the library and the
#      Python package, with /etc/ldoem/hub.yaml as a conffile (scripts/check-deb-root.sh installs
#      and runs it).
#   scripts/check-install.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/default}
work=$(mktemp -d "${TMPDIR:-/tmp}/ldoem-install.XXXXXX")
daemon_pid=""
cleanup() {
  if [ -n "$daemon_pid" ]; then kill "$daemon_pid" 2>/dev/null || true; wait "$daemon_pid" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT
step() { printf '\n--- %s\n' "$*"; }

step "cmake --install $build (DESTDIR, prefix /usr)"
DESTDIR="$work/root" cmake --install "$build" --prefix /usr >/dev/null
root="$work/root"
multiarch=$(dpkg-architecture -qDEB_HOST_MULTIARCH)  # Wireshark's plugin folder is under it
for file in usr/share/ldoem/scenes/corridor.yaml etc/ldoem/hub.yaml \
            usr/lib/systemd/system/ldoem-emud@.service usr/lib/systemd/system/ldoem-emud-group@.service \
            usr/lib/systemd/system/ldoem-hub.service usr/share/doc/ldoem/copyright \
            usr/share/doc/ldoem/changelog.Debian.gz "usr/lib/$multiarch/wireshark/plugins/ldoem.lua" \
            "usr/lib/$multiarch/wireshark/plugins/ldoem_serial.lua" \
            usr/include/ldoem/driver/scanner.hpp usr/include/ldoem/protocol/messages.hpp; do
  [ -e "$root/$file" ] || { echo "check-install: /$file is not installed" >&2; exit 1; }
done
# Every program with its man page and its bash completion.
for program in ldoem-emud ldoem-hub ldoem-scan ldoem-conformance ldoem-ctl ldoem-replay; do
  for file in "usr/bin/$program" "usr/share/man/man1/$program.1.gz" "usr/share/bash-completion/completions/$program"; do
    [ -s "$root/$file" ] || { echo "check-install: /$file is not installed" >&2; exit 1; }
  done
done
libdir=$(cd "$root/usr" && dirname "$(find . -name libldoem.a | head -n 1)")
[ -n "$libdir" ] && [ -f "$root/usr/$libdir/cmake/ldoem/ldoemConfig.cmake" ] && [ -f "$root/usr/$libdir/pkgconfig/ldoem.pc" ] ||
  { echo "check-install: libldoem, its CMake package or ldoem.pc is missing" >&2; exit 1; }

step "systemd units"
scripts/check-units.sh "$root"

step "examples/consumer against find_package(ldoem)"
cmake -S examples/consumer -B "$work/consumer" -G Ninja -DCMAKE_PREFIX_PATH="$root/usr" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/consumer" >/dev/null

step "examples/consumer against pkg-config ldoem (cmake --install --prefix DIR)"
cmake --install "$build" --prefix "$work/prefix" >/dev/null
[ -f "$work/prefix/etc/ldoem/hub.yaml" ] || { echo "check-install: --prefix DIR has no DIR/etc/ldoem/hub.yaml" >&2; exit 1; }
flags=$(PKG_CONFIG_PATH="$work/prefix/$libdir/pkgconfig" pkg-config --cflags --libs ldoem)
# shellcheck disable=SC2086
c++ -o "$work/consumer-pc" examples/consumer/main.cpp $flags

step "consumer against the installed ldoem-emud"
"$root/usr/bin/ldoem-emud" --scene "$root/usr/share/ldoem/scenes/minimal.yaml" --no-can --tcp tcp:127.0.0.1:0 \
  --no-flash --timeout 120 >"$work/emud.out" 2>"$work/emud.err" &
daemon_pid=$!
for _ in $(seq 200); do grep -qx ready "$work/emud.out" && break; sleep 0.05; done
grep -qx ready "$work/emud.out" || { cat "$work/emud.err" >&2; echo "check-install: ldoem-emud not ready" >&2; exit 1; }
address=$(sed -n 's/^tcp //p' "$work/emud.out" | head -n 1)
for consumer in "$work/consumer/ldoem-consumer" "$work/consumer-pc"; do
  timeout 60 "$consumer" "tcp:$address" | tee "$work/consumer.out"
  grep -q '^profile .*: [1-9][0-9]* points$' "$work/consumer.out" ||
    { echo "check-install: $consumer took no profile" >&2; exit 1; }
done

if grep -q '^LDOEM_PYTHON:BOOL=ON' "$build/CMakeCache.txt"; then
  step "the Python package from the installed prefix"
  python=$(sed -n 's/^Python3_EXECUTABLE:[A-Z]*=//p' "$build/CMakeCache.txt")
  init=$(cd "$root" && find usr -path '*-packages/ldoem/__init__.py' | head -n 1)
  [ -n "$init" ] || { echo "check-install: the ldoem Python package is not installed" >&2; exit 1; }
  site=/$(dirname "$(dirname "$init")")
  "$python" -c "import sys; sys.exit(0 if '$site' in sys.path else 1)" ||
    { echo "check-install: $site is not on $python's sys.path" >&2; exit 1; }
  ls "$root$site"/ldoem-*.dist-info/entry_points.txt >/dev/null
  (cd "$work" && PYTHONPATH="$root$site" "$python" -c "import ldoem; print('ldoem', ldoem.__version__)")
  (cd "$work" && PYTHONPATH="$root$site" LDOEM_EMUD="$root/usr/bin/ldoem-emud" LDOEM_SCENES="$root/usr/share/ldoem/scenes" \
    timeout 60 "$python" -c "import ldoem
with ldoem.Emulator('minimal', virtual_time=True) as emulator, ldoem.Scanner(emulator.device) as scanner:
    print('ldoem.Scanner against the installed ldoem-emud:', scanner.status())")
fi

step "cpack -G DEB"
(cd "$build" && cpack -G DEB -B "$work/deb" >/dev/null)
deb=$(ls "$work"/deb/*.deb)
contents=$(dpkg-deb -c "$deb")
for file in ./usr/bin/ldoem-emud ./usr/bin/ldoem-replay ./usr/lib/systemd/system/ldoem-hub.service \
            ./usr/share/ldoem/scenes/corridor.yaml ./etc/ldoem/hub.yaml; do
  grep -q " $file\$" <<<"$contents" || { echo "check-install: $file missing from $(basename "$deb")" >&2; exit 1; }
done
if grep -q '^LDOEM_PYTHON:BOOL=ON' "$build/CMakeCache.txt"; then
  grep -q 'dist-packages/ldoem/__init__.py$\|site-packages/ldoem/__init__.py$' <<<"$contents" ||
    { echo "check-install: the ldoem Python package is missing from the package" >&2; exit 1; }
fi
grep -q 'libldoem.a$' <<<"$contents" || { echo "check-install: libldoem.a missing from the package" >&2; exit 1; }
grep -q ' ./usr/etc' <<<"$contents" && { echo "check-install: the package installs into /usr/etc" >&2; exit 1; }
[ "$(dpkg-deb --ctrl-tarfile "$deb" | tar -xOf - ./conffiles)" = /etc/ldoem/hub.yaml ] ||
  { echo "check-install: /etc/ldoem/hub.yaml is not the package's conffile" >&2; exit 1; }
echo "check-install: $(basename "$deb") ($(du -k "$deb" | cut -f1) KiB), depends: $(dpkg-deb -f "$deb" Depends)"
echo "check-install: all passed"
