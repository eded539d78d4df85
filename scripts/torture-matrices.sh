#!/usr/bin/env bash
# The fault matrices of docs/python.md: python3 -m ldoem.torture over every TCP scenario for
#   1. python/tests/naive_client.py (no retry, no reconnect),
#   2. ldoem-scan --retries 0,
#   3. ldoem-scan --retries 3 (its default),
# each a small scan (3 layers) against ldoem-emud on scenes/minimal.yaml in virtual time. Writes
# docs/python-torture-*.png and, with --write-doc, the three tables into docs/python.md.
#   scripts/torture-matrices.sh [--write-doc] [BUILD_DIR]     (default build/default)
set -euo pipefail
cd "$(dirname "$0")/.."
write_doc=false
if [ "${1:-}" = --write-doc ]; then write_doc=true; shift; fi
build=${1:-build/default}
python=$(sed -n 's/^Python3_EXECUTABLE:[A-Z]*=//p' "$build/CMakeCache.txt")
export PYTHONPATH=$PWD/$build/python PYTHONDONTWRITEBYTECODE=1
work=$(mktemp -d "${TMPDIR:-/tmp}/ldoem-torture.XXXXXX")
trap 'rm -rf "$work"' EXIT
scan=$PWD/$build/driver/scan/ldoem-scan
scan_args=(--device '{device}' --lpt '{lpt}' --out "$work/cloud.pcd" --vertical-apex 0.36 --timeout 1)

torture() {  # NAME TITLE -- CMD...
  local name=$1 title=$2; shift 3
  "$python" -m ldoem.torture --out "$work/$name" --title "$title" --jobs 2 -- "$@" | tail -n 1 || true
  cp "$work/$name/matrix.png" "docs/python-torture-$name.png"
}
torture naive "naive_client.py (no retry, no reconnect)" -- "$python" "$PWD/python/tests/naive_client.py" '{device}'
torture scan-retries-0 "ldoem-scan --retries 0" -- "$scan" "${scan_args[@]}" --retries 0
torture scan-retries-3 "ldoem-scan --retries 3" -- "$scan" "${scan_args[@]}" --retries 3

if $write_doc; then
  "$python" - "$work" <<'PY'
import sys
from pathlib import Path
work = Path(sys.argv[1])
parts = ["<!-- written by scripts/torture-matrices.sh --write-doc: do not edit by hand -->"]
for name in ("naive", "scan-retries-0", "scan-retries-3"):
    parts.append((work / name / "matrix.md").read_text().strip())
    parts.append(f"![the {name} matrix](python-torture-{name}.png)")
doc = Path("docs/python.md")
text = doc.read_text()
begin, end = "<!-- torture-matrices: begin -->", "<!-- torture-matrices: end -->"
head, _, rest = text.partition(begin)
_, _, tail = rest.partition(end)
doc.write_text(head + begin + "\n" + "\n\n".join(parts) + "\n" + end + tail)
PY
fi
