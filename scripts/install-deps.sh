#!/usr/bin/env bash
# Installs every Debian package ldoem needs to build, test, run and benchmark. Idempotent and
# non-interactive; run as root (or with sudo available). Debian 12 (bookworm).
# Usage: scripts/install-deps.sh [--screenshot]
#   --screenshot  also the GUI packages that only scripts/wireshark-screenshot.sh needs (Qt
#                 Wireshark, X tools); CI and the demo do not install them.
set -euo pipefail
screenshot=false
case "${1:-}" in
  --screenshot) screenshot=true ;;
  -h|--help) sed -n '2,6p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  "") ;;
  *) echo "install-deps.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
esac
packages=(
  cmake ninja-build ccache g++ clang libclang-rt-14-dev pkg-config
  libode-dev libyaml-cpp-dev libembree-dev libassimp-dev libeigen3-dev
  libsocketcan-dev libgpiod-dev gpiod libpng-dev libpcap-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  can-utils user-mode-linux kmod iproute2 procps python3 time
  gnuplot-nox
  # the exact oracle of the numerics tests (tests/oracle, docs/numerics.md): CGAL is header-only
  libcgal-dev libgmp-dev libmpfr-dev
  # the Wireshark dissector's tests
  tshark
  # sd_notify for the systemd units, systemd-analyze to check them (scripts/check-units.sh)
  libsystemd-dev systemd
  # cpack -G DEB finds the package's library dependencies with dpkg-shlibdeps; help2man makes
  # the man pages from each program's --help; lintian checks the .deb, mmdebstrap makes the clean
  # Debian 12 root it is installed into and systemd-nspawn boots it (scripts/check-deb-root.sh)
  dpkg-dev help2man lintian mmdebstrap systemd-container zstd
  # load for scripts/test-under-load.sh and scripts/bench-jitter.sh
  stress-ng
  nlohmann-json3-dev libcli11-dev   # control socket (JSON lines), ldoem-ctl
  # the ldoem Python package (python/, docs/python.md): bindings, tests, examples
  pybind11-dev python3-dev python3-pytest python3-numpy python3-matplotlib
  # the fleet's image and its test (scripts/build-image.sh, scripts/check-fleet.sh): runc, as
  # crun fails on hybrid cgroups; catatonit, for the pods' local pause image (none is pulled);
  # mmdebstrap is listed above
  podman runc catatonit
  # for the gpio-sim UML kernel (scripts/uml/build-gpio-kernel.sh)
  linux-source-6.1 build-essential bc flex bison libelf-dev xz-utils
)
if $screenshot; then packages+=(wireshark-qt xvfb xdotool x11-apps netpbm); fi
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
"${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -qq
"${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
