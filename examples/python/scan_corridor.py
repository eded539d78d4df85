"""Scan the paper's corridor in the emulator and plot it (PNG): the whole example of docs/python.md.

    PYTHONPATH=build/default/python python3 examples/python/scan_corridor.py corridor.png
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import ldoem  # noqa: E402


def main(out="corridor.png"):
    with ldoem.Emulator("corridor", transports=("tcp", "lpt"), virtual_time=True) as emulator:
        cloud = ldoem.scan(emulator.device, emulator.lpt)
    cloud = cloud[np.isfinite(cloud[:, 0])]
    figure, (top, side) = plt.subplots(1, 2, figsize=(13, 5))
    for axes, (a, b), (xlabel, ylabel) in ((top, (0, 1), ("x (m)", "y (m)")), (side, (0, 2), ("x (m)", "z (m)"))):
        shown = axes.scatter(cloud[:, a], cloud[:, b], c=cloud[:, 3], s=1, cmap="viridis")
        axes.set_xlabel(xlabel)
        axes.set_ylabel(ylabel)
        axes.set_aspect("equal")
    top.set_title("from above")
    side.set_title("from the side (floor at z = -0.5 m)")
    figure.colorbar(shown, ax=[top, side], label="echo (intensity)")
    figure.suptitle(f"ldoem.scan of scenes/corridor.yaml: {len(cloud)} points")
    figure.savefig(out, dpi=100)
    print(f"scan_corridor: {len(cloud)} points, plotted to {out}")


if __name__ == "__main__":
    main(*sys.argv[1:2])
