#!/usr/bin/env python3
"""ISO 230-2 positioning evaluation of real measured runs, with the standard's plot.

    PYTHONPATH=build/python python3 examples/python/iso230_2_real_data.py --out /tmp/iso

Reads the open positioning runs in ../shared/data/iso230-2 (relative to the repository; see its
README.md for their source), evaluates each with ISO 230-2 (A, B, R, E, M per direction) and
writes <file>.png per run file: the mean deviation per target in each direction with the
+-2 s bands, as the standard plots it.
"""
import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mtcal  # noqa: E402

REPO = Path(__file__).resolve().parents[2]


def plot(runs, e, title, path):
    t = e.table
    x = t["target"]
    fig, ax = plt.subplots(figsize=(8, 4.5), constrained_layout=True)
    for key, s, colour, label in (("mean_up", "s_up", "tab:blue", "forward (up)"),
                                  ("mean_down", "s_down", "tab:red", "backward (down)")):
        ax.plot(x, t[key], "o-", color=colour, label=f"{label}: mean deviation")
        ax.fill_between(x, t[key] - 2 * t[s], t[key] + 2 * t[s], color=colour, alpha=0.2, label=f"{label}: +-2 s")
    # every run's deviation, faint: measured - target
    for runs_dir, colour in ((runs.up, "tab:blue"), (runs.down, "tab:red")):
        dev = np.asarray(runs_dir) - x[:, None]
        ax.plot(np.repeat(x, dev.shape[1]), dev.ravel(), ".", color=colour, alpha=0.3)
    ax.axhline(0, color="grey", lw=0.5)
    ax.set_xlabel(f"target ({e.unit})")
    ax.set_ylabel(f"deviation ({e.unit})")
    ax.set_title(f"{title}: A {e.A:.4g}, B {e.B:.4g}, R {e.R:.4g}, E {e.E:.4g}, M {e.M:.4g} {e.unit}")
    ax.legend(fontsize="small")
    fig.savefig(path, dpi=100)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=str(REPO / ".." / "shared" / "data" / "iso230-2"))
    ap.add_argument("--out", default=".", help="directory for the plots")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    files = sorted(Path(args.data).glob("*.dat"))
    if not files:
        raise SystemExit(f"no .dat files in {args.data}")
    print(f"{'file':<22} {'targets':>7} {'runs':>4} {'A':>10} {'B':>10} {'R':>10} {'E':>10} {'M':>10} unit")
    for f in files:
        runs = mtcal.read_positioning(str(f))
        e = mtcal.iso230_2(runs)
        print(f"{f.name:<22} {len(runs.targets):>7} {e.runs:>4} {e.A:>10.5f} {e.B:>10.5f} {e.R:>10.5f} "
              f"{e.E:>10.5f} {e.M:>10.5f} {e.unit}")
        plot(runs, e, f.name, out / f"{f.stem}.png")
    print(f"wrote {len(files)} plots into {out}")


if __name__ == "__main__":
    main()
