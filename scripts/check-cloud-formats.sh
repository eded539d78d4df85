#!/bin/sh
# Optional external check of ldoem's PLY/PCD writers: writes a synthetic scan in the four
# formats (ply ascii/binary, pcd ascii/binary) and reads each back with Open3D, an independent
# reader (Debian bookworm: apt-get install python3-open3d). Also checks the range-image PNG
# signature and size. Exit 0 = all read back with the right point count and first point;
# 77 = Open3D not installed (skipped); 1 = a mismatch.
# Usage: scripts/check-cloud-formats.sh [BUILD_DIR]   (default build/d; needs the target
#        ldoem_write_sample_clouds built there)
set -eu
build_dir=${1:-build/d}
tool="$build_dir/tests/cloud/ldoem_write_sample_clouds"
python=/usr/bin/python3   # Debian's python, where python3-open3d installs

if ! "$python" -c 'import open3d' 2>/dev/null; then
  echo "check-cloud-formats: python3-open3d not installed, skipped" >&2
  exit 77
fi
if [ ! -x "$tool" ]; then
  echo "check-cloud-formats: $tool not built (cmake --build $build_dir --target ldoem_write_sample_clouds)" >&2
  exit 2
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$tool" "$work" > "$work/manifest.txt"

"$python" - "$work" <<'PY'
import sys, os
import numpy as np
import open3d as o3d

work = sys.argv[1]
failures = 0
for line in open(os.path.join(work, "manifest.txt")):
    name, count, x0, y0, z0 = line.split()
    path = os.path.join(work, name)
    legacy = o3d.io.read_point_cloud(path, remove_nan_points=False, remove_infinite_points=False)
    points = np.asarray(legacy.points)
    expected_first = np.array([float(x0), float(y0), float(z0)])
    ok = points.shape[0] == int(count) and np.allclose(points[0], expected_first, atol=1e-6)
    tensor = o3d.t.io.read_point_cloud(path)
    has_intensity = "intensity" in tensor.point
    print(f"{name}: open3d read {points.shape[0]} points (expected {count}), first point "
          f"{'matches' if ok else 'DIFFERS'}, intensity attribute {'present' if has_intensity else 'absent'}")
    failures += 0 if ok else 1
png = open(os.path.join(work, "scan-range.png"), "rb").read()
png_ok = png[:8] == b"\x89PNG\r\n\x1a\n"
image = o3d.io.read_image(os.path.join(work, "scan-range.png"))
print(f"scan-range.png: signature {'ok' if png_ok else 'BAD'}, open3d size {np.asarray(image).shape}")
failures += 0 if png_ok else 1
sys.exit(1 if failures else 0)
PY
