#!/usr/bin/env bash
# The host test suite built with AddressSanitizer + UndefinedBehaviorSanitizer (-O1, assertions on).
# Not part of scripts/test.sh: a second full build doubles CI's time on two cores. Run it before a
# release or after touching decoders, state machines or memory-owning code.
set -euo pipefail
cd "$(dirname "$0")/.."
cache=${LDOEM_CACHE:-$HOME/.cache/ldoem}
export CCACHE_DIR=${CCACHE_DIR:-$cache/ccache} CCACHE_BASEDIR=$PWD CCACHE_NOHASHDIR=1
scripts/install-deps.sh
cmake --preset asan >/dev/null
cmake --build --preset asan
ctest --preset asan -LE 'vcan|gpio|slow|fuzz|bench' -j2
