#!/usr/bin/env bash
# Fails when two C++ types of the project share a name (issue 22, item 10): a reader who meets
# `TcpEndpoint` or `Transport` must not have to work out which of two it is, and the asan
# preset's unity build must not meet two file-local types of one name in one batch.
#   scripts/check-type-names.sh [SOURCE_ROOT]
# Looks at every class, struct and enum defined at namespace scope (written at column 0, as the
# whole tree is) in the .hpp/.cpp/.h files of the tree, tests included. Types nested in a class
# or local to a function are indented and named through their scope, so they may repeat.
# Forward declarations (`class X;`) and out-of-line members (`struct X::Impl {`) are not
# definitions of a new name. Prints each clash with its places; exit status 1 if there is one.
set -euo pipefail
root=${1:-"$(dirname "$0")/.."}
cd "$root"
definitions=$(find . \( -name build -o -name .git -o -name 'build-*' \) -prune -o \
                   -type f \( -name '*.hpp' -o -name '*.cpp' -o -name '*.h' \) -print0 |
  xargs -0 grep -HnE '^(class|struct|enum class|enum struct|enum)[[:space:]]+(\[\[[^]]*\]\][[:space:]]+)?[A-Za-z_][A-Za-z0-9_]*[[:space:]]*(final[[:space:]]*)?(\{|:[^:]|$)' |
  sed -E 's/^\.\/([^:]+:[0-9]+):(class|struct|enum class|enum struct|enum)[[:space:]]+(\[\[[^]]*\]\][[:space:]]+)?([A-Za-z0-9_]+).*/\4 \1/' |
  sort || true)
clashes=$(printf '%s\n' "$definitions" | cut -d' ' -f1 | sort | uniq -d)
if [ -z "$clashes" ]; then
  exit 0
fi
echo "check-type-names: these names are defined more than once; give each its own name:" >&2
for name in $clashes; do
  printf '%s\n' "$definitions" | awk -v n="$name" '$1 == n { print "  " $1 "  " $2 }' >&2
done
exit 1
