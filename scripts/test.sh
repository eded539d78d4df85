#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test of ldoem (docs/ci.md):
#   1. the plain build (default preset) of what must run unsanitized: the programs, the test
#      programs that run inside User-Mode Linux (no sanitizer fits in its address space) and the
#      tests labelled `plain`, which assert wall time (target ldoem_plain_ci);
#   2. the installed package: cmake --install, the systemd units (verify, security <= 2.0), the
#      examples/consumer program built against find_package(ldoem) and pkg-config and run
#      against the installed daemon, the .deb (scripts/check-install.sh);
#   3. the PLY/PCD files read back by Open3D (scripts/check-cloud-formats.sh), the `plain`
#      tests on the plain build, then scripts/hostile.sh (the hostile inputs of issue 27
#      against the plain build's programs, docs/robustness.md);
#   4. the .deb made once with cpack; then, in the background beside the vcan step (they mostly
#      wait on downloads, boots and real-time scans), the .deb through lintian and into a clean
#      Debian 12 root (mmdebstrap, cached), booted with systemd-nspawn, where the installed units
#      take a 3D scan through the hub (scripts/check-deb-root.sh); the fleet
#      (scripts/check-fleet.sh): the OCI image from the same .deb (mmdebstrap, cached in
#      ${LDOEM_CACHE}), 3 scanners and the hub under podman kube play, a scan through the hub
#      from each, one killed and recovered, all removed; and the gpio-sim UML kernel build at
#      the lowest priority (scripts/lib/background-steps.sh runs them: own log, own time);
#   5. the vcan-labelled tests inside one User-Mode Linux boot with a real vcan0 (daemon on CAN,
#      conformance, can-utils interop, robustness floods, the paper's scan end to end), then a
#      60 s soak test (scripts/soak.sh) in the same boot, so CAN is in it; then the wait for
#      step 4's background steps;
#   5b. the gpio-labelled tests inside one boot of the project's gpio-sim UML kernel (built once,
#      cached in ${LDOEM_CACHE:-~/.cache/ldoem});
#   6. the whole host suite and every libFuzzer target (short, fixed runs) under ASan+UBSan (the
#      asan preset: clang, unity build). Its build starts after step 1 at the lowest CPU priority
#      and overlaps steps 2 to 5, which mostly wait on User-Mode Linux and real time;
#   7. the hub, ray caster and sensor model tests under ThreadSanitizer (the tsan preset).
# Each step prints its wall time. Slow benchmarks are scripts/bench-*.sh.
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

step "build: programs and UML test programs (default preset, target ldoem_plain_ci)"
cmake --preset default >/dev/null
cmake --build --preset ci-plain

# Builds in the background, each in its own process group so that the exit trap can stop it, at
# the lowest CPU priority so that the foreground steps' wall-clock tests keep their CPU.
mkdir -p build
background=()
build_in_background() {  # PRESET LOG
  # setsid starts a new session, and with the kernel's autogroup scheduling (on by default) a new
  # session is a CPU group of its own, which `nice` alone does not lower against the foreground's
  # group: the group's own nice is set too, or the "background" build takes half the machine.
  setsid --wait bash -c "echo 19 >/proc/self/autogroup 2>/dev/null; cmake --preset $1 >/dev/null && exec nice -n 19 cmake --build --preset $1" >"$2" 2>&1 &
  background+=("$!")
}
finish_background_build() {  # PID LOG
  wait "$1" && return 0
  echo "test.sh: a background build failed; the end of $2:" >&2
  tail -n 60 "$2" >&2
  exit 1
}
source scripts/lib/background-steps.sh
trap 'for pid in "${background[@]}"; do kill -- -"$pid" 2>/dev/null || true; done; bg_stop_all
[ -n "$step_name" ] && printf "=== %s: %d s\n" "$step_name" $((SECONDS - step_started)); printf "=== total: %d s\n" $SECONDS' EXIT
build_in_background asan build/asan-build.log
asan_build=$!

step "installed package, systemd units, libldoem consumer"
scripts/check-install.sh build/default

step "cloud files read back by Open3D (scripts/check-cloud-formats.sh)"
cmake --build --preset default --target ldoem_write_sample_clouds
scripts/check-cloud-formats.sh build/default

step "tests that assert wall time, on the plain build (label plain)"
ctest --preset default -L plain -j2

step "hostile inputs (issue 27) against the plain build's programs: scripts/hostile.sh"
scripts/hostile.sh --build-dir build/default --budget-s 300

step "the .deb (cpack), once for the clean Debian 12 root and the fleet"
rm -rf build/deb
deb_dir=$PWD/build/deb
(cd build/default && cpack -G DEB -B "$deb_dir" >/dev/null)
deb=$(ls build/deb/*.deb)
echo "$deb"
# The clean root and the fleet mostly wait (downloads, booting, scans in real time), as the vcan
# boot does, so they run beside it instead of after it (docs/ci.md, "Overlap"); the gpio-sim
# kernel, pure CPU, builds beside them at the lowest priority like the ASan build.
bg_start "the .deb in a clean Debian 12 root: lintian, dpkg -i, a 3D scan through its units" \
  build/deb-root.log scripts/check-deb-root.sh --deb "$deb" build/default
bg_start "the fleet: OCI image, 3 emulated scanners and the hub under podman (scripts/check-fleet.sh)" \
  build/fleet.log scripts/check-fleet.sh --build-dir build/default --deb "$deb"
bg_start "the gpio-sim UML kernel (scripts/uml/build-gpio-kernel.sh)" build/gpio-kernel.log nice 19 \
  scripts/uml/build-gpio-kernel.sh

step "vcan tests and a 60 s soak test inside User-Mode Linux"
# One boot for both: the soak's third daemon then serves the hub over vcan0. Both always run.
scripts/uml/run.sh 'status=0
ctest --test-dir build/default -L vcan --output-on-failure || status=$?
scripts/soak.sh --duration 60 --out build/default/soak || status=1
exit $status'

step "the .deb's clean root and the fleet, begun beside the vcan step"
background_status=0
bg_finish "the .deb in a clean Debian 12 root: lintian, dpkg -i, a 3D scan through its units" || background_status=1
bg_finish "the fleet: OCI image, 3 emulated scanners and the hub under podman (scripts/check-fleet.sh)" || background_status=1
((background_status == 0)) || exit 1

step "gpio tests inside the gpio-sim UML kernel"
bg_finish "the gpio-sim UML kernel (scripts/uml/build-gpio-kernel.sh)"
gpio_kernel=$(tail -n 1 build/gpio-kernel.log)
scripts/uml/run.sh --kernel "$gpio_kernel" --gpio -- ctest --test-dir build/default -L gpio --output-on-failure

step "ASan+UBSan: the whole host suite and the fuzz targets (asan preset)"
finish_background_build "$asan_build" build/asan-build.log
build_in_background tsan build/tsan-build.log
tsan_build=$!
ctest --preset asan -j2

step "hub, ray caster and sensor model tests under TSan (tsan preset)"
finish_background_build "$tsan_build" build/tsan-build.log
ctest --preset tsan -j2
