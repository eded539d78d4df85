#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test of ldoem:
#   1. host tests (unit, protocol vectors, emulator in virtual time, TCP/serial end to end);
#   2. the vcan-labelled tests inside one User-Mode Linux boot with a real vcan0;
#   3. the gpio-labelled tests inside one boot of the project's gpio-sim UML kernel (built once,
#      cached in ${LDOEM_CACHE:-~/.cache/ldoem});
#   4. the host tests again under ASan+UBSan;
#   5. every libFuzzer target for a short, fixed number of runs under ASan+UBSan.
# Slow benchmarks are not run here (see scripts/bench-*.sh). Exit status: 0 only if all passed.
set -euo pipefail
cd "$(dirname "$0")/.."

step() { printf '\n=== %s\n' "$*"; }

step "dependencies"
scripts/install-deps.sh

step "build (default preset)"
cmake --preset default >/dev/null
cmake --build --preset default

step "host tests"
ctest --preset default -LE 'vcan|gpio|slow|fuzz' -j2

step "vcan tests inside User-Mode Linux"
scripts/uml/run.sh -- ctest --test-dir build/default -L vcan --output-on-failure

step "gpio tests inside the gpio-sim UML kernel"
gpio_kernel=$(scripts/uml/build-gpio-kernel.sh)
scripts/uml/run.sh --kernel "$gpio_kernel" --gpio -- ctest --test-dir build/default -L gpio --output-on-failure

step "host tests under ASan+UBSan"
cmake --preset asan >/dev/null
cmake --build --preset asan
ctest --preset asan -LE 'vcan|gpio|slow|fuzz|bench' -j2

step "fuzz targets (short runs)"
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz
ctest --test-dir build/fuzz -L fuzz --output-on-failure
