#!/usr/bin/env python3
"""Writes hu40t-reached-nominal.csv: 40 commanded world poses of the HU40T spread over its travel and
the joints a controller without compensation reaches for them (the nominal inverse, what LinuxCNC's
trt kinematics commands), in the columns `mtcal pose-check --poses` reads (docs/campaign.md).

Usage: PYTHONPATH=build/python python3 examples/campaign/reached_nominal.py > examples/campaign/hu40t-reached-nominal.csv
"""
import math
import pathlib
import random

import mtcal

HERE = pathlib.Path(__file__).resolve().parent
m = mtcal.Machine.load(str(HERE.parent / "machines" / "hu40t-wCBXfYZt.yaml"))
s = mtcal.CommandedJointSolver(m)
rng = random.Random(33)
print("# 40 poses of the HU40T: commanded world pose (X Y Z mm in the workpiece frame, B C deg) and the")
print("# nominal joints (no compensation), from examples/campaign/reached_nominal.py")
print("pose,X,Y,Z,B,C,qX,qY,qZ,qB,qC")
n = 0
while n < 40:
    b, c = rng.uniform(-60, 60), rng.uniform(-180, 180)
    point = [rng.uniform(-150, 150), rng.uniform(-150, 150), rng.uniform(0, 150)]
    q = s.nominal_inverse(point, [math.radians(c), math.radians(b)], tool_length=m.tool_length)
    # chain order wCBXfYZt: C, B, X, Y, Z
    qc, qb, qx, qy, qz = q
    if not (-300 <= qx <= 300 and -250 <= qy <= 250 and -300 <= qz <= 300):
        continue
    n += 1
    print(f"{n},{point[0]!r},{point[1]!r},{point[2]!r},{b!r},{c!r},{qx!r},{qy!r},{qz!r},"
          f"{math.degrees(qb)!r},{math.degrees(qc)!r}")
