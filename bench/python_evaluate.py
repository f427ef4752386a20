#!/usr/bin/env python3
"""mtcal.evaluate through Python against the C++ batch call, measured in the same run.

    PYTHONPATH=build/python python3 bench/python_evaluate.py [--n 1000000] [--repeats 7] [--threads 0]

The 5-axis example (examples/machines/hu40t-wCBXfYZt.yaml), N random configurations inside the
travels with random directions of motion. Times, best and median of the repeats:
  C++    ErrorModel::evaluate_batch on std::vector copies of the inputs, output reused
         (mtcal._mtcal._bench_evaluate_batch: the timing is taken in C++ around the call alone);
  Python mtcal.evaluate(model, configs, directions): argument checks, a new (N, 6) array;
  Python mtcal.evaluate(..., out=buffer): the same into a reused array.
Prints the ratios Python / C++ (target <= 1.2) and checks that both give the same numbers.
"""
import argparse
import statistics
import time
from pathlib import Path

import numpy as np

import mtcal

REPO = Path(__file__).resolve().parents[1]


def timed(f, repeats):
    seconds = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        f()
        seconds.append(time.perf_counter() - t0)
    return seconds


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--machine", default=str(REPO / "examples" / "machines" / "hu40t-wCBXfYZt.yaml"))
    ap.add_argument("--n", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--threads", type=int, default=0, help="0: all cores")
    args = ap.parse_args()

    m = mtcal.Machine.load(args.machine)
    model = mtcal.ErrorModel(m)
    rng = np.random.default_rng(20240601)
    lo = np.array([a.travel[0] for a in m.axes])
    hi = np.array([a.travel[1] for a in m.axes])
    q = lo + (hi - lo) * rng.random((args.n, m.axis_count))
    d = rng.integers(-1, 2, size=q.shape).astype(np.int8)

    cpp = mtcal._mtcal._bench_evaluate_batch(model, q, d, args.repeats, args.threads)
    fresh = timed(lambda: mtcal.evaluate(model, q, d, threads=args.threads), args.repeats)
    buf = np.empty((args.n, 6))
    reused = timed(lambda: mtcal.evaluate(model, q, d, threads=args.threads, out=buf), args.repeats)
    # interleave once more, so that a drift of the machine's speed shows in both
    cpp += mtcal._mtcal._bench_evaluate_batch(model, q, d, args.repeats, args.threads)

    e = mtcal.evaluate(model, q, d, threads=args.threads)
    assert np.array_equal(e, buf), "evaluate with out= differs"
    ref = mtcal.evaluate(m, q[:1000], d[:1000], threads=1)
    assert np.array_equal(e[:1000], ref), "evaluate differs between thread counts"

    print(f"machine {m.name} ({m.topology}), N = {args.n:,} configurations with directions, "
          f"threads {args.threads or 'all'}, {args.repeats} repeats")
    print(f"{'':32} {'best ms':>9} {'median ms':>10} {'Mconfig/s':>10} {'ratio (best)':>13}")
    rows = [("C++ evaluate_batch", cpp), ("Python evaluate (new array)", fresh), ("Python evaluate (out=)", reused)]
    base = min(cpp)
    for name, s in rows:
        print(f"{name:32} {min(s) * 1e3:9.1f} {statistics.median(s) * 1e3:10.1f} {args.n / min(s) / 1e6:10.2f} "
              f"{min(s) / base:13.3f}")
    print(f"ratio Python / C++ (best of each): {min(fresh) / base:.3f} with a new array, "
          f"{min(reused) / base:.3f} with out= (target <= 1.2)")


if __name__ == "__main__":
    main()
