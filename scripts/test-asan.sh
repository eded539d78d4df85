#!/usr/bin/env bash
# The host test suite and the libFuzzer targets built with AddressSanitizer +
# UndefinedBehaviorSanitizer (the asan preset: clang, -O1 -g1, assertions on, unity build; no
# vcan/gpio test programs: ASan's shadow memory does not fit in a UML guest's address space, so
# those run only on the plain build). The same step as in scripts/test.sh (docs/ci.md).
#   scripts/test-asan.sh [--no-deps]   (--no-deps: skip scripts/install-deps.sh)
# Tests that assert wall time carry the label `plain` and are left to the plain build.
set -euo pipefail
cd "$(dirname "$0")/.."
cache=${LDOEM_CACHE:-$HOME/.cache/ldoem}
export CCACHE_DIR=${CCACHE_DIR:-$cache/ccache} CCACHE_BASEDIR=$PWD CCACHE_NOHASHDIR=1
case "${1:-}" in
  --no-deps) ;;
  "") scripts/install-deps.sh ;;
  -h|--help) sed -n '2,7p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  *) echo "test-asan.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
esac
cmake --preset asan >/dev/null
cmake --build --preset asan
ctest --preset asan -j2
