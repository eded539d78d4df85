#!/bin/sh
# External check of ldoem's PLY/PCD writers (run by scripts/test.sh): writes a synthetic scan as
# ldoem-scan lays it out (organised, NaN without an echo, fields x y z intensity t range azimuth
# tilt ring) in the four formats and reads each back with Open3D's tensor reader, an
# independent reader (Debian bookworm: python3-open3d): every field present with its type, the
# point count = width x height, NaN exactly where range is NaN, row 0 the highest tilt and
# column 0 the largest azimuth. PCL itself is not installed (pcl-tools pulls 75 packages: VTK,
# Qt, Open MPI); the PCD headers are checked here against PCL's rules instead (entry order,
# FIELDS/SIZE/TYPE/COUNT of one length, POINTS = WIDTH x HEIGHT, the binary body's length).
# Also checks the range-image PNG. Exit 0 = all good; 77 = Open3D not installed (skipped);
# 1 = a mismatch.
# Usage: scripts/check-cloud-formats.sh [BUILD_DIR]   (default build/default; needs the target
#        ldoem_write_sample_clouds built there)
set -eu
build_dir=${1:-build/default}
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
failures = []
FIELDS = ["x", "y", "z", "intensity", "t", "range", "azimuth", "tilt", "ring"]
ATTRIBUTES = {"intensity": "Float32", "t": "Float32", "range": "Float32", "azimuth": "Float32",
              "tilt": "Float32", "ring": "UInt16"}

def check(name, condition, what):
    if not condition:
        failures.append(f"{name}: {what}")

def check_pcd_rules(name, data):
    """PCL's PCD v0.7 rules for what ldoem writes."""
    end = data.index(b"DATA ")
    end = data.index(b"\n", end) + 1
    lines = [l.split() for l in data[:end].decode("ascii").splitlines() if l and not l.startswith("#")]
    keys = [l[0] for l in lines]
    check(name, keys == ["VERSION", "FIELDS", "SIZE", "TYPE", "COUNT", "WIDTH", "HEIGHT", "VIEWPOINT",
                         "POINTS", "DATA"], f"header entries {keys}")
    entry = {l[0]: l[1:] for l in lines}
    check(name, entry["FIELDS"] == FIELDS, f"FIELDS {entry['FIELDS']}")
    n = len(entry["FIELDS"])
    check(name, len(entry["SIZE"]) == n and len(entry["TYPE"]) == n and len(entry["COUNT"]) == n,
          "FIELDS/SIZE/TYPE/COUNT lengths differ")
    width, height, points = int(entry["WIDTH"][0]), int(entry["HEIGHT"][0]), int(entry["POINTS"][0])
    check(name, width * height == points, "POINTS != WIDTH x HEIGHT")
    if entry["DATA"][0] == "binary":
        record = sum(int(s) * int(c) for s, c in zip(entry["SIZE"], entry["COUNT"]))
        check(name, len(data) - end == record * points, f"binary body {len(data) - end} != {record} x {points}")
    return width, height

for line in open(os.path.join(work, "manifest.txt")):
    name, width, height = line.split()
    width, height = int(width), int(height)
    path = os.path.join(work, name)
    data = open(path, "rb").read()
    if name.endswith(".pcd"):
        check(name, check_pcd_rules(name, data) == (width, height), "WIDTH/HEIGHT differ from the grid")
    else:
        check(name, f"obj_info num_cols {width}\nobj_info num_rows {height}\n".encode() in data,
              "no obj_info num_cols/num_rows (PCL's organised PLY)")
    cloud = o3d.t.io.read_point_cloud(path, remove_nan_points=False, remove_infinite_points=False)
    positions = cloud.point.positions.numpy()
    check(name, positions.shape == (width * height, 3), f"{positions.shape[0]} points, not {width} x {height}")
    for attribute, dtype in ATTRIBUTES.items():
        present = attribute in cloud.point
        check(name, present and str(cloud.point[attribute].dtype) == dtype,
              f"{attribute}: " + (str(cloud.point[attribute].dtype) if present else "dropped by Open3D"))
    if failures:
        continue
    value = {a: cloud.point[a].numpy().reshape(height, width) for a in ATTRIBUTES}
    no_echo = np.isnan(value["range"])
    check(name, np.array_equal(np.isnan(positions[:, 0]).reshape(height, width), no_echo),
          "NaN positions are not exactly the beams without a range")
    check(name, 0 < no_echo.sum() < width * height, "no NaN points or no echo at all")
    check(name, np.all(np.diff(value["tilt"][:, 0]) < 0), "row 0 is not the highest tilt")
    check(name, np.all(np.diff(value["azimuth"][0, :]) < 0), "column 0 is not the largest azimuth")
    check(name, np.all(value["ring"][:, 0] == np.arange(height - 1, -1, -1)), "ring is not the layer")
    echo = ~no_echo
    ranges = np.linalg.norm(positions.reshape(height, width, 3)[echo], axis=1)
    check(name, np.allclose(ranges, value["range"][echo], atol=1e-4), "range differs from |position|")
    print(f"{name}: open3d read {width} x {height} points, {int(no_echo.sum())} NaN (no echo), fields "
          + " ".join(f"{a}:{cloud.point[a].dtype}" for a in ATTRIBUTES))
png = open(os.path.join(work, "scan-range.png"), "rb").read()
check("scan-range.png", png[:8] == b"\x89PNG\r\n\x1a\n", "bad signature")
for failure in failures:
    print("check-cloud-formats: " + failure, file=sys.stderr)
sys.exit(1 if failures else 0)
PY
