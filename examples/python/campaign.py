#!/usr/bin/env python3
"""A calibration campaign from Python, the steps a metrology engineer scripts:
laser file -> ISO 230-2 acceptance -> fit_motion -> compensation for LinuxCNC -> history -> trend report.

    PYTHONPATH=build/python python3 examples/python/campaign.py --out /tmp/campaign

Reads examples/instruments/x-axis.rtl (a Renishaw laser export of the X axis of a 3-axis mill),
judges it against examples/acceptance/tolerances.yaml and writes its report, fits the X
positioning error EXX into a parameter file, writes LinuxCNC's compensation files from the mill
with that error, and records the ISO 230-2 result in a history store (SQLite) at three dates
(the later two are the same runs with the deviations grown by 20 % and 40 %, to give the trend a
drift; say so in a real campaign's notes), with the compensation loaded as an event between
them. Then the trend of A_X and E_X against the tolerances, as JSON and as an HTML report.
Every step is what the command does (`mtcal iso230-2`, `fit-motion`, `compensate`, `--record`,
`history trend`): the same library calls.
"""
import argparse
import json
from pathlib import Path

import numpy as np

import mtcal

EXAMPLES = Path(__file__).resolve().parents[1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, required=True, help="folder for the outputs (made if missing)")
    ap.add_argument("--examples", type=Path, default=EXAMPLES, help="mtcal's examples folder")
    a = ap.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    laser = str(a.examples / "instruments" / "x-axis.rtl")
    tolerances = str(a.examples / "acceptance" / "tolerances.yaml")

    # 1. The laser test and its acceptance (mtcal iso230-2 x-axis.rtl --tolerance-file ... --report).
    lf = mtcal.read_laser_file(laser)
    meta = lf.report_metadata  # machine, serial, date, axis ... from the file's header
    e = mtcal.iso230_2(lf.runs)
    verdict = mtcal.evaluate_tolerances(e, tolerance_file=tolerances, metadata=meta)
    mtcal.write_report(e, str(a.out / "iso230-2.html"), runs=lf.runs, acceptance=verdict)
    print(f"{lf.error_name} of {meta.get('machine')}: A {e.A:.2f} {e.unit}, verdict "
          f"{'PASS' if verdict.passed else 'FAIL'}; missing on the report: {len(verdict.missing_metadata)} fields")

    # 2. The motion error as a parameter file (mtcal fit-motion x-axis.rtl --out x-axis.yaml).
    fit = mtcal.fit_motion([laser])
    params = a.out / "x-axis.yaml"
    fit.write_parameters(str(params))
    print(f"{fit.errors[0].name}: {fit.fits[0].reason}")

    # 3. Compensation for LinuxCNC from the mill with that error (mtcal compensate --format linuxcnc).
    mill = mtcal.Machine.load(str(a.examples / "instruments" / "mill.yaml"), params=[str(params)])
    comp = mtcal.compensate(mill, "linuxcnc", points=11)
    comp_dir = a.out / "comp-x"
    if not comp_dir.exists():
        comp.write(str(comp_dir))
    print(f"compensation: {', '.join(comp.files)} ({comp.quantity})")

    # 4. The history: the result recorded at three dates, the compensation as an event.
    db = a.out / "history.db"
    if db.exists():
        db.unlink()
    store = mtcal.HistoryStore(str(db))
    targets = lf.runs.targets
    per_mm = {"um": 1e-3, "mm": 1.0}[lf.runs.unit]  # the laser file's deviations, in mm
    for date, growth in (("2026-01-15", 1.0), ("2026-06-15", 1.2), ("2026-11-20", 1.4)):
        up = targets[:, None] + growth * per_mm * lf.runs.up
        down = targets[:, None] + growth * per_mm * lf.runs.down
        result = mtcal.iso230_2(mtcal.PositioningRuns(targets, up, down, unit="mm", source=laser)).to_dict()
        store.record("iso230-2", result, metadata=dict(meta, date=date), inputs=[laser])
    store.add_event(meta["machine"], "2026-03-01", "compensation-loaded", "X pitch table from fit-motion")

    # 5. The trend against the acceptance tolerances (mtcal history trend ... --report trend.html).
    trend = store.trend(meta["machine"], figures=["A_X", "E_X"], tolerance_file=tolerances)
    (a.out / "trend.json").write_text(json.dumps(trend.to_dict(), indent=2))
    mtcal.write_report(trend, str(a.out / "trend.html"))
    for s in trend.to_dict()["series"]:
        t = s["trend"]
        print(f"{s['quantity']}: {t['n']} calibrations, {t['rate_per_year']:.3g} {s['unit']}/year, "
              f"{100 * (t['utilisation'] or 0):.0f} % of the tolerance used, {t['crossing']['status']}")
    assert np.isfinite(e.A) and len(store.list()) == 3
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
