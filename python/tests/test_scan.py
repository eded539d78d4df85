"""ldoem.scan(): the paper's corridor scan to numpy, the PCD fields, one copy."""

import numpy as np
import pytest

import ldoem


@pytest.fixture(scope="module")
def corridor_scan():
    with ldoem.Emulator("corridor", transports=("tcp", "lpt"), virtual_time=True) as emulator:
        cloud, info = ldoem.scan(emulator.device, emulator.lpt, info=True)
    return cloud, info


def test_the_paper_scan_is_9801_points_with_the_pcd_fields(corridor_scan):
    cloud, info = corridor_scan
    assert ldoem.SCAN_FIELDS == ("x", "y", "z", "intensity", "t", "range", "azimuth", "tilt", "ring")
    assert cloud.shape == (81 * 121, 9) and cloud.dtype == np.float32
    assert info["layers_done"] == 121
    assert (info["width"], info["height"]) == (81, 121)
    assert set(np.unique(cloud[:, 8]).astype(int)) == set(range(121))
    # Organised as seen from the scanner: row 0 the highest tilt, column 0 the leftmost beam.
    grid = cloud.reshape(121, 81, 9)
    assert np.all(np.diff(grid[:, 0, 7]) < 0) and np.all(np.diff(grid[0, :, 6]) < 0)
    echo = np.isfinite(grid[..., 5])
    assert np.allclose(np.linalg.norm(grid[..., :3][echo], axis=1), grid[..., 5][echo], atol=1e-3)
    assert grid[-1, -1, 4] == 0.0 and grid[0, 0, 4] > 20.0  # t: first beam .. last (s)
    assert len(info["identification"]) == 11


def test_the_array_is_numpys_own_memory_filled_once(corridor_scan):
    cloud, _ = corridor_scan
    # Allocated by numpy and written in place by the extension: no view of C++ memory, no
    # intermediate array (the one copy is the cloud's interleaving into rows).
    assert cloud.flags.owndata and cloud.base is None and cloud.flags.c_contiguous


def test_the_cylinder_is_195_mm_by_a_numpy_fit(corridor_scan):
    cloud, _ = corridor_scan
    from fit_cylinder import cylinder_diameter_m
    assert abs(cylinder_diameter_m(cloud) - 0.195) <= 0.003


def test_a_bad_plan_is_a_value_error_with_ldoem_scans_message():
    with pytest.raises(ValueError, match="--lpt"):
        ldoem.scan("tcp:127.0.0.1:1")
