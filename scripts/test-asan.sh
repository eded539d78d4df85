#!/usr/bin/env bash
# The host test suite built with AddressSanitizer + UndefinedBehaviorSanitizer (-O1 -g1, assertions
# on, no benchmarks, no vcan/gpio test programs: ASan's shadow memory does not fit in a UML guest's
# address space, so those run only on the plain build). Part of scripts/test.sh (docs/ci.md).
#   scripts/test-asan.sh [--no-deps]   (--no-deps: skip scripts/install-deps.sh)
# Tests that assert wall time are filtered out by the asan test preset (label `plain` too, should
# one be given it); docs/ci.md says which and why.
set -euo pipefail
cd "$(dirname "$0")/.."
cache=${LDOEM_CACHE:-$HOME/.cache/ldoem}
export CCACHE_DIR=${CCACHE_DIR:-$cache/ccache} CCACHE_BASEDIR=$PWD CCACHE_NOHASHDIR=1
case "${1:-}" in
  --no-deps) ;;
  "") scripts/install-deps.sh ;;
  -h|--help) sed -n '2,6p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  *) echo "test-asan.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
esac
cmake --preset asan >/dev/null
cmake --build --preset asan
ctest --preset asan -LE 'vcan|gpio|slow|fuzz|bench|plain' -j2
