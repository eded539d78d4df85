#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test of ldoem:
#   1. host tests (unit, protocol vectors, emulator in virtual time, TCP/serial end to end,
#      conformance over TCP and serial);
#   2. the vcan-labelled tests inside one User-Mode Linux boot with a real vcan0 (daemon on CAN,
#      conformance, can-utils interop, robustness floods, the paper's scan end to end);
#   3. the gpio-labelled tests inside one boot of the project's gpio-sim UML kernel (built once,
#      cached in ${LDOEM_CACHE:-~/.cache/ldoem});
#   4. the installed package: cmake --install, the systemd units (verify, security <= 2.0), the
#      examples/consumer program built against find_package(ldoem) and pkg-config and run
#      against the installed daemon, the .deb (scripts/check-install.sh);
#   5. every libFuzzer target for a short, fixed number of runs under ASan+UBSan;
#   6. the hub, ray caster and sensor model tests under ThreadSanitizer (the tsan preset);
#   7. a 60 s soak test (scripts/soak.sh) inside the vcan UML boot of step 2, so CAN is in it.
# Each step prints its wall time (docs/ci.md).
# The whole suite under ASan+UBSan is scripts/test-asan.sh; slow benchmarks are scripts/bench-*.sh.
# Exit status: 0 only if all passed.
set -euo pipefail
cd "$(dirname "$0")/.."

step_started=$SECONDS
step_name=""
step() {
  [ -n "$step_name" ] && printf '=== %s: %d s\n' "$step_name" $((SECONDS - step_started))
  step_name=$*
  step_started=$SECONDS
  printf '\n=== %s\n' "$*"
}
trap '[ -n "$step_name" ] && printf "=== %s: %d s\n" "$step_name" $((SECONDS - step_started)); printf "=== total: %d s\n" $SECONDS' EXIT
cache=${LDOEM_CACHE:-$HOME/.cache/ldoem}
# The compiler cache lives outside the clone and ignores where the clone is.
export CCACHE_DIR=${CCACHE_DIR:-$cache/ccache} CCACHE_BASEDIR=$PWD CCACHE_NOHASHDIR=1 CCACHE_MAXSIZE=${CCACHE_MAXSIZE:-3G}

step "dependencies"
scripts/install-deps.sh

step "build (default preset)"
cmake --preset default >/dev/null
cmake --build --preset default

step "host tests"
ctest --preset default -LE 'vcan|gpio|slow|fuzz' -j2

step "installed package, systemd units, libldoem consumer"
scripts/check-install.sh build/default

step "vcan tests and a 60 s soak test inside User-Mode Linux"
# One boot for both: the soak's third daemon then serves the hub over vcan0. Both always run.
scripts/uml/run.sh 'status=0
ctest --test-dir build/default -L vcan --output-on-failure || status=$?
scripts/soak.sh --duration 60 --out build/default/soak || status=1
exit $status'

step "gpio tests inside the gpio-sim UML kernel"
gpio_kernel=$(scripts/uml/build-gpio-kernel.sh)
scripts/uml/run.sh --kernel "$gpio_kernel" --gpio -- ctest --test-dir build/default -L gpio --output-on-failure

step "fuzz targets (short runs, ASan+UBSan)"
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz
ctest --test-dir build/fuzz -L fuzz --output-on-failure

step "hub, ray caster and sensor model tests under TSan (tsan preset)"
cmake --preset tsan >/dev/null
cmake --build --preset tsan
ctest --preset tsan -j2
