"""Scan the corridor and fit its cylinder with numpy alone: the scene's is 195 mm across.

    PYTHONPATH=build/default/python python3 examples/python/fit_cylinder.py
"""

import sys

import numpy as np

import ldoem


def fit_circle(x, y):
    """Centre and radius of the least-squares algebraic circle x^2 + y^2 + D x + E y + F = 0."""
    design = np.column_stack([x, y, np.ones_like(x)])
    (d, e, f), *_ = np.linalg.lstsq(design, -(x * x + y * y), rcond=None)
    cx, cy = -d / 2, -e / 2
    return cx, cy, float(np.sqrt(cx * cx + cy * cy - f))


def main():
    with ldoem.Emulator("corridor", transports=("tcp", "lpt"), virtual_time=True) as emulator:
        cloud = ldoem.scan(emulator.device, emulator.lpt).astype(np.float64)
    x, y, z = cloud[:, 0], cloud[:, 1], cloud[:, 2]
    # Near the cylinder's axis (x = 2.9 m, y = 0; pivot frame) and above the floor (z = -0.5 m).
    near = np.isfinite(x) & (x > 2.6) & (x < 3.05) & (np.abs(y) < 0.2) & (z > -0.4) & (z < 0.45)
    cx, cy, radius = fit_circle(x[near], y[near])
    diameter_mm = 2000 * radius
    print(f"fit_cylinder: {near.sum()} points, axis at ({cx:.3f}, {cy:.3f}) m, diameter {diameter_mm:.1f} mm "
          f"(scene: 195.0 mm)")
    return 0 if abs(diameter_mm - 195.0) <= 3.0 else 1


if __name__ == "__main__":
    sys.exit(main())
