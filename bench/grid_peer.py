#!/usr/bin/python3
"""`mtcal eval --grid` against a grid-aware numpy peer, single thread, in the same run.

    /usr/bin/python3 bench/grid_peer.py [--build build] [--repeats 3]

The HU40T example (examples/machines/hu40t-wCBXfYZt.yaml) on full grids of about 1e6 and 3e6
configurations. The peer (written for this benchmark) takes each axis' actual and nominal 4x4
transform once per grid value (from bench/grid_factors.cpp: the independent chain of
naive_chain.hpp; not timed, a few dozen matrices) and combines them by broadcasting: prefix
products over the outer axes, then per outer configuration the product with every value of the
last axis, the translation difference and the rotation vector of R_actual R_nominal^T. It is
timed on its combination alone. mtcal is timed as the command (`eval --grid --threads 1
--json`): its `seconds` (the model's evaluation, kernel) and the whole process (wall, including
start-up, the grid's fill, the checks for non-finite values and the largest errors). Both give
the same numbers: checked on a 5^5 grid against `eval --grid --out` (max difference printed).
Prints the ratios peer / mtcal (issue 18 target: >= 5 on the kernel).
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
import numpy as np  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
MACHINE = REPO / "examples" / "machines" / "hu40t-wCBXfYZt.yaml"


def grid_spec(counts):
    c, b, x, y, z = counts
    return f"C=-180:180:{c},B=-90:90:{b},X=-300:300:{x},Y=-250:250:{y},Z=-300:300:{z}"


def factors(build, spec, tmp):
    out = subprocess.run([str(build / "bench" / "mtcal_grid_factors"), str(MACHINE), spec, str(tmp / "f")],
                         check=True, capture_output=True, text=True).stdout.split()
    counts = [int(v) for v in out]
    act = [np.fromfile(tmp / f"f.{k}.actual.f64").reshape(counts[k], 4, 4) for k in range(len(counts))]
    nom = [np.fromfile(tmp / f"f.{k}.nominal.f64").reshape(counts[k], 4, 4) for k in range(len(counts))]
    return act, nom


def peer(act, nom, out, rows=1 << 18):
    """Errors of every grid configuration (last axis fastest) into out (N x 6)."""
    def prefix(tables):
        p = tables[0]
        for t in tables[1:-1]:
            p = (p[:, None] @ t[None]).reshape(-1, 4, 4)
        return p
    pa, pn = prefix(act), prefix(nom)
    la, ln = act[-1], nom[-1]
    last = la.shape[0]
    step = max(1, rows // last)
    for o in range(0, pa.shape[0], step):
        a = pa[o:o + step]
        n = pn[o:o + step]
        # R and t of the products, broadcast over (outer, last).
        ra = np.matmul(a[:, None, :3, :3], la[None, :, :3, :3])
        rn = np.matmul(n[:, None, :3, :3], ln[None, :, :3, :3])
        ta = np.einsum("oij,lj->oli", a[:, :3, :3], la[:, :3, 3]) + a[:, None, :3, 3]
        tn = np.einsum("oij,lj->oli", n[:, :3, :3], ln[:, :3, 3]) + n[:, None, :3, 3]
        d = np.matmul(ra, np.swapaxes(rn, -1, -2))
        v = 0.5 * np.stack([d[..., 2, 1] - d[..., 1, 2], d[..., 0, 2] - d[..., 2, 0], d[..., 1, 0] - d[..., 0, 1]], -1)
        s = np.linalg.norm(v, axis=-1, keepdims=True)
        f = np.where(s > 0, np.arcsin(np.minimum(s, 1.0)) / np.where(s > 0, s, 1.0), 1.0)
        block = out[o * last:(o + a.shape[0]) * last].reshape(a.shape[0], last, 6)
        block[..., :3] = ta - tn
        block[..., 3:] = v * f


def mtcal_eval(build, spec, extra=()):
    t0 = time.perf_counter()
    r = subprocess.run([str(build / "apps" / "mtcal" / "mtcal"), "eval", "-m", str(MACHINE), "--grid", spec,
                        "--threads", "1", "--json", *extra], check=True, capture_output=True, text=True)
    return json.loads(r.stdout), time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(REPO / "build"))
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    build = Path(args.build)
    with tempfile.TemporaryDirectory() as td:
        tmp = Path(td)
        # Same numbers: a 5^5 grid through both.
        spec = grid_spec([5] * 5)
        act, nom = factors(build, spec, tmp)
        mine = np.empty((5 ** 5, 6))
        peer(act, nom, mine)
        mtcal_eval(build, spec, ["--out", str(tmp / "e.csv")])
        with open(tmp / "e.csv") as fh:
            rows = [r for r in csv.reader(line for line in fh if not line.startswith("#"))]
        head = rows[0]
        cols = [head.index(c) for c in ("dx", "dy", "dz", "rx", "ry", "rz")]
        theirs = np.array([[float(r[c]) for c in cols] for r in rows[1:]])
        print(f"5^5 grid: max |mtcal - peer| = {np.abs(theirs[:, :3] - mine[:, :3]).max():.3g} mm, "
              f"{np.abs(theirs[:, 3:] - mine[:, 3:]).max():.3g} rad (CSV rounding included)")
        print(f"{'configurations':>14} {'peer s':>9} {'mtcal kernel s':>15} {'mtcal wall s':>13} "
              f"{'peer/kernel':>12} {'peer/wall':>10}")
        for counts in ([16] * 5, [19, 20, 20, 20, 20]):
            spec = grid_spec(counts)
            act, nom = factors(build, spec, tmp)
            total = int(np.prod(counts))
            out = np.empty((total, 6))
            p, k, w = [], [], []
            for _ in range(args.repeats):  # interleaved, so that a drift of the machine shows in both
                t0 = time.perf_counter()
                peer(act, nom, out)
                p.append(time.perf_counter() - t0)
                j, wall = mtcal_eval(build, spec)
                k.append(j["seconds"])
                w.append(wall)
            print(f"{total:>14} {min(p):>9.3f} {min(k):>15.3f} {min(w):>13.3f} {min(p) / min(k):>12.2f} "
                  f"{min(p) / min(w):>10.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
