#!/usr/bin/env python3
"""Identify a 5-axis machine from a simulated probing campaign and print the uncertainty table.

    PYTHONPATH=build/python python3 examples/python/identify_probing.py --out /tmp/ident

The HU40T example machine (with the 14 location and scale errors to identify) plays the real
machine: its SAMBA/TANGO probing plan (21 indexations, balls and a facet) is simulated with 1 um
reading noise and an uncalibrated artefact (50 um), then the 14 errors are identified from those
readings alone, starting from the nominal machine, as from a real measurement. Prints
each estimate with its standard uncertainty and the value imposed, and writes correlation.png
(the estimates' correlation matrix, from the covariance).
"""
import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mtcal  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
ESTIMATE = ["EC0Y", "EB0Z", "EA0Z", "EX0C", "EY0C", "EA0C", "EB0C", "EX0B", "EZ0B", "EA0B", "EC0B",
            "EXX.1", "EYY.1", "EZZ.1"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=".", help="directory for correlation.png")
    ap.add_argument("--noise-um", type=float, default=1.0)
    ap.add_argument("--seed", type=int, default=7)
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    # The imposed machine: the HU40T example with the errors to be identified (the others zero, so
    # that what the readings show is what the model can explain).
    truth = mtcal.Machine.load(str(REPO / "examples" / "machines" / "hu40t-wCBXfYZt.yaml")).with_only(ESTIMATE)
    plan = mtcal.read_probing_plan(truth, str(REPO / "examples" / "plans" / "hu40t-samba-tango.csv"))
    # The virtual machine: what the true machine reads (mm), with noise and artefact error.
    sim = mtcal.simulate(truth, plan, noise=args.noise_um * 1e-3, artefact_error=0.05, seed=args.seed,
                         scale_bars=["1:2:304.8"])
    # Identify starting from the nominal machine: nothing of the truth is known but the readings.
    prior = truth.without_errors()
    run = mtcal.identify(prior, sim.measurements, ESTIMATE, scale_bars=["1:2:304.8"], sigma=args.noise_um * 1e-3)
    print(f"{len(sim.measurements)} probings, rank {run.identifiability.rank}, sigma0 {run.sigma0:.3f}, "
          f"{'converged' if run.converged else 'NOT converged'} in {run.iterations} iterations")
    print(f"{'parameter':<10} {'unit':<7} {'estimate':>12} {'u (1 sigma)':>12} {'imposed':>12} {'|error|/u':>9}")
    for name, unit, value, u in zip(run.names, run.units, run.values, run.uncertainties):
        imposed = truth.parameters[name]
        scale, shown = (1e3, "um") if unit == "mm" else (1e6, "urad") if unit == "rad" else (1e6, "um/m")
        print(f"{name:<10} {shown:<7} {value * scale:>12.3f} {u * scale:>12.3f} {imposed * scale:>12.3f} "
              f"{abs(value - imposed) / u:>9.2f}")
    for name in run.identifiability.unidentifiable:
        print(f"NOT identifiable: {name}")

    corr = run.correlation
    fig, ax = plt.subplots(figsize=(7, 6), constrained_layout=True)
    im = ax.imshow(corr, vmin=-1, vmax=1, cmap="RdBu_r")
    ax.set_xticks(range(len(run.names)), run.names, rotation=90)
    ax.set_yticks(range(len(run.names)), run.names)
    fig.colorbar(im, label="correlation")
    ax.set_title("Correlation of the estimates (covariance sigma0^2 (J^T J)^-1)")
    fig.savefig(out / "correlation.png", dpi=100)
    np.savetxt(out / "covariance.csv", run.covariance, delimiter=",", header=",".join(run.names), comments="")
    print(f"wrote {out / 'correlation.png'} and {out / 'covariance.csv'}")


if __name__ == "__main__":
    main()
