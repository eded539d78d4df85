"""The corridor's cylinder from a scan, with numpy alone (shared by the tests and
examples/python/fit_cylinder.py): the points near its axis (x = 2.9 m, y = 0 in the scanner's
pivot frame; the pivot stands 0.5 m above the floor), above the floor, then an algebraic circle
fit (Kasa) of x^2 + y^2 + D x + E y + F = 0 in the horizontal plane."""

import numpy as np


def cylinder_points(cloud):
    x, y, z = cloud[:, 0], cloud[:, 1], cloud[:, 2]
    keep = np.isfinite(x) & (x > 2.6) & (x < 3.05) & (np.abs(y) < 0.2) & (z > -0.4) & (z < 0.45)
    return cloud[keep]


def fit_circle(x, y):
    """(centre x, centre y, radius) of the least-squares algebraic circle."""
    design = np.column_stack([x, y, np.ones_like(x)])
    (d, e, f), *_ = np.linalg.lstsq(design, -(x * x + y * y), rcond=None)
    cx, cy = -d / 2, -e / 2
    return cx, cy, float(np.sqrt(cx * cx + cy * cy - f))


def cylinder_diameter_m(cloud):
    points = cylinder_points(cloud).astype(np.float64)
    if len(points) < 20:
        raise ValueError(f"only {len(points)} points near the cylinder")
    _, _, radius = fit_circle(points[:, 0], points[:, 1])
    return 2 * radius
