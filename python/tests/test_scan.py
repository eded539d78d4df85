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
    assert ldoem.SCAN_FIELDS == ("x", "y", "z", "intensity", "ring")
    assert cloud.shape == (81 * 121, 5) and cloud.dtype == np.float32
    assert info["layers_done"] == 121
    assert set(np.unique(cloud[:, 4]).astype(int)) == set(range(121))
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
