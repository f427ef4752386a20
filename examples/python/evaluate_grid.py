#!/usr/bin/env python3
"""Evaluate a machine model over a grid and plot its error map.

    PYTHONPATH=build/python python3 examples/python/evaluate_grid.py --out /tmp/maps

Loads the 3-axis example, evaluates the volumetric error on an X-Y grid at three heights (one
call, all cores), prints the volumetric accuracy, and writes error_map.png: |e| in um as colour
with the X-Y error vectors as arrows, one panel per height.
"""
import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mtcal  # noqa: E402

REPO = Path(__file__).resolve().parents[2]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--machine", default=str(REPO / "examples" / "machines" / "vmc-3axis.yaml"))
    ap.add_argument("--out", default=".", help="directory for error_map.png")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    m = mtcal.Machine.load(args.machine)
    nx, ny, heights = 41, 26, [-450.0, -250.0, -50.0]
    # Machine.grid orders configurations with the last axis (Z) fastest: (X, Y, Z) -> reshape.
    q = m.grid({"X": np.linspace(-400, 400, nx), "Y": np.linspace(-250, 250, ny), "Z": heights})
    e = mtcal.evaluate(m, q)  # (N, 6): dx dy dz in mm, rx ry rz in rad
    um = e[:, :3] * 1e3
    va = mtcal.volumetric_accuracy(e[:, :3])
    print(f"{m.name}: {len(q)} configurations, largest |e| {np.linalg.norm(um, axis=1).max():.2f} um, "
          f"volumetric accuracy {va.va.value * 1e3:.2f} um")

    X = q[:, 0].reshape(nx, ny, len(heights))
    Y = q[:, 1].reshape(nx, ny, len(heights))
    U = um.reshape(nx, ny, len(heights), 3)
    norm = np.linalg.norm(U, axis=3)
    fig, axes = plt.subplots(1, len(heights), figsize=(5 * len(heights), 4), constrained_layout=True)
    for k, ax in enumerate(axes):
        c = ax.contourf(X[:, :, k], Y[:, :, k], norm[:, :, k], levels=20, vmin=norm.min(), vmax=norm.max())
        s = slice(None, None, 4)
        ax.quiver(X[s, s, k], Y[s, s, k], U[s, s, k, 0], U[s, s, k, 1], color="white")
        ax.set_title(f"Z = {heights[k]:g} mm")
        ax.set_xlabel("X (mm)")
        ax.set_ylabel("Y (mm)")
        ax.set_aspect("equal")
    fig.colorbar(c, ax=axes, label="|e| (um)")
    fig.suptitle(f"{m.name}: translational error (arrows: X-Y components)")
    fig.savefig(out / "error_map.png", dpi=100)
    print(f"wrote {out / 'error_map.png'}")


if __name__ == "__main__":
    main()
