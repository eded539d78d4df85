#!/bin/sh
# Draws ldoem's library graph for docs/architecture.md: CMake's --graphviz on a configure-only
# build folder, reduced to ldoem's own libraries and programs (no tests, benchmarks or external
# libraries), labelled by layer folder, rendered by Debian's graphviz (dot) to docs/architecture-libraries.svg and .png.
# Usage: scripts/architecture-graph.sh [BUILD_DIR]   (default build/graph; nothing is compiled)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build/graph}
command -v dot >/dev/null || { echo "architecture-graph: dot not found (apt-get install graphviz)" >&2; exit 1; }
mkdir -p "$build"
# Read by cmake --graphviz from the build folder: keep ldoem's targets only.
cat >"$build/CMakeGraphVizOptions.cmake" <<'OPTIONS'
set(GRAPHVIZ_GRAPH_NAME "ldoem")
set(GRAPHVIZ_EXTERNAL_LIBS FALSE)
set(GRAPHVIZ_GENERATE_PER_TARGET FALSE)
set(GRAPHVIZ_GENERATE_DEPENDERS FALSE)
set(GRAPHVIZ_IGNORE_TARGETS "_tests$" "_test$" "^ldoem_bench" "support$" "^ldoem_png_reader$"
    "^ldoem-latency$" "^ldoem_write_sample_clouds$" "^ldoem_isotp" "^ldoem_interop" "^ldoem_e2e"
    "^fuzz_" "^ldoem_capture_expectations$" "^ldoem_dissector_fixtures$"
    "^numerics_sweep$" "^ldoem_oracle" "^clock_slip_proxy$" "^ldoem_fuzz_seed_writer$"
    "^ldoem_fault_catalogue_py$" "^ldoem_test_support")
OPTIONS
cmake -S "$root" -B "$build" -G Ninja -DLDOEM_BENCHMARKS=OFF --graphviz="$build/ldoem.dot" >/dev/null
# CMake adds a legend of every target kind; ours has only programs (ovals) and static libraries.
awk '/^subgraph clusterLegend/ { skip = 1 } skip && /^}/ { skip = 0; next } !skip' \
  "$build/ldoem.dot" >"$build/ldoem-targets.dot"
# Each node labelled and coloured by its layer folder (docs/architecture.md "Folders"), from the
# folders the configure step recorded for each target (cmake/LdoemLinkGraph.cmake).
python3 "$root/scripts/architecture_layers.py" "$root" "$build/ldoem-link-graph.txt" \
  "$build/ldoem-targets.dot" "$build/ldoem-graph.dot"
dot -Tsvg "$build/ldoem-graph.dot" -o "$root/docs/architecture-libraries.svg"
dot -Tpng -Gdpi=80 "$build/ldoem-graph.dot" -o "$root/docs/architecture-libraries.png"
echo "architecture-graph: docs/architecture-libraries.svg and .png from $build/ldoem-graph.dot"
