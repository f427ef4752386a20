#!/usr/bin/python3
# The kinematics module of `mtcal compensate --format linuxcnc-kins` in LinuxCNC itself (issue 30):
# per example machine, build the module mtcal wrote (its build.sh: halcompile --install), start the
# sim configuration of tests/linuxcnc with it as [KINS]KINEMATICS, command poses spread over the
# travel (G53 G1 in world coordinates: tool point and rotary coordinates) with the machine file's
# tool length and with none, read the joints the controller computed (joint.N.pos-cmd, what
# linuxcnc.stat().joint_position reports) and its forward (stat.actual_position), and check
#   - the actual tool point of the model at those joints (this script's own nominal chain plus
#     `mtcal eval`'s error e = actual - nominal) equals the commanded point within 0.1 um;
#   - actual_position equals the command within 1e-6 mm.
# Prints per machine max |e| and VA of the tool point before (nominal joints) and after (the module).
# G43 (cases with "g43"): the run without a tool length goes on with a tool table of two tools, T1 M6 G43,
# T2 M6 G43 and G49, poses in program coordinates; the module's tool-offset pin on motion.tooloffset.z as
# its linuxcnc-kins.hal nets it: the tool tip (the model with that tool's length) on the commanded point
# within 0.1 um, forward equal to the command plus the offset within 1e-6 mm.
# The direction-dependent COMP_FILE type 1 tables are loaded as the INI snippet says; the tool-point
# check reads pos-cmd, before them, and what LinuxCNC adds to the motor command must equal the
# table's forward or reverse column at pos-cmd within 1e-6 mm, both columns met.
# Usage (through tests/linuxcnc/run-kins): kins_module_test.py --mtcal PATH --root ROOT [--case NAME] [--keep DIR]
import argparse
import csv
import fcntl
import itertools
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
import yaml

import lcnc_test as L
from lcnc_test import Failure

TOL_POINT_MM = 1e-4     # issue 30: the actual tool point on the command within 0.1 um
TOL_FORWARD_MM = 1e-6   # and the forward kinematics equal to the command within 1e-6 mm
MODULE = "mtcal_kins"
# "g43": the run without a tool length goes on with G43 from a tool table (T1 M6 G43, T2 M6 G43, G49).
CASES = {
    "vmc-3axis": {"machine": "examples/machines/vmc-3axis.yaml", "poses": 26, "g43": True},
    "hu40t": {"machine": "examples/machines/hu40t-wCBXfYZt.yaml", "poses": 26},
    "rrttt": {"machine": "examples/machines/rrttt-table-table.yaml", "poses": 26, "g43": True},
    "head-head": {"machine": "examples/machines/head-head-5axis.yaml", "poses": 26, "g43": True},
}
# The G43 check: two tools of different lengths (mm, the machine's units) and poses per segment, drawn
# from the middle of the travel (short moves). The example machines' tools point along -z: G43's Z.
G43_TOOLS = ((1, 60.0), (2, 135.5))
G43_POSES = 5
G43_TOOL_TABLE = "".join("T%d P%d Z%.3f D6 ;mtcal G43 test\n" % (t, t, z) for t, z in G43_TOOLS)


def model_error(machine_path, letters, joints, workdir, tag):
    """e = actual - nominal tool point (mm, workpiece frame) of the model at each joint set, through
    `mtcal eval` (direction of motion 0). Like lcnc_test.mtcal_eval, without its echo check: mtcal eval
    prints the joint columns back with 12 significant digits, and LinuxCNC's joints have more."""
    pin = os.path.join(workdir, "eval-%s-in.csv" % tag)
    pout = os.path.join(workdir, "eval-%s-out.csv" % tag)
    with open(pin, "w") as f:
        f.write(",".join(letters) + "\n")
        for q in joints:
            f.write(",".join(repr(float(q[l])) for l in letters) + "\n")
    L.run([L.MTCAL, "eval", "--machine", machine_path, "--points", pin, "--out", pout], "mtcal eval (%s)" % tag)
    with open(pout) as f:
        rows = list(csv.DictReader(f))
    if len(rows) != len(joints):
        raise Failure("mtcal eval (%s): expected %d rows, found %d" % (tag, len(joints), len(rows)))
    for q, r in zip(joints, rows):
        for l in letters:
            if abs(float(r[l]) - q[l]) > 1e-9 * max(1.0, abs(q[l])):
                raise Failure("mtcal eval (%s): row for %s=%r came back as %r" % (tag, l, q[l], r[l]))
    return np.array([[float(r[k]) for k in ("dx", "dy", "dz")] for r in rows])


def with_tool_length(src, dst, length):
    with open(src) as f:
        doc = yaml.safe_load(f)
    doc.setdefault("tool", {})["length"] = float(length)
    with open(dst, "w") as f:
        yaml.safe_dump(doc, f, sort_keys=False)


def poses_for(m, count, seed, tool_length, margin=0.1):
    """World poses (x y z mm, rotary coordinates deg in the coordinates' order) of nominal joints
    drawn inside the travel less `margin` of it at each end (rotary axes within +-170 deg)."""
    rng = np.random.default_rng(seed)
    letters = "".join(l for l in "XYZABC" if l in m.chain)
    out = []
    for _ in range(count):
        q = {}
        for l in letters:
            lo, hi = m.travel(l)
            if l in "ABC":
                lo, hi = max(lo, -170.0), min(hi, 170.0)
            span = hi - lo
            q[l] = float(rng.uniform(lo + margin * span, hi - margin * span))
        p = m.nominal_tool_point(q)
        out.append((q, [float(v) for v in p] + [q[l] for l in letters if l in "ABC"]))
    return letters, out


def g43_segments(src, workdir, letters):
    """The G43 check's moves, run after the poses without a tool length: per segment (T1 M6 G43,
    T2 M6 G43, G49) the rotary axes to 0 first (a tool change elsewhere moves the joints at once, as
    with trt-kins), the MDI lines, then poses in program coordinates (G90 G1; G54 is 0 here), whose
    tool tip is the commanded point. The truth of a segment: the machine file with that tool length
    (the module's tool-length pin is 0 in this run: the tool table holds the whole length)."""
    base = L.Machine(src)
    axis = str((base.doc.get("tool") or {}).get("axis", "+z")).lower()
    if axis not in ("+z", "z"):
        raise Failure("the G43 check needs a tool along -z (G43's Z offset); %s has tool axis %s" % (src, axis))
    rot = [l for l in letters if l in "ABC"]
    to_zero = ["G53 G1 %s F30000" % " ".join("%s0" % l for l in rot)] if rot else []
    plan = [("G43 T%d" % t, ["T%d M6" % t, "G43"], z) for t, z in G43_TOOLS] + [("G49", ["G49"], 0.0)]
    segments = []
    for k, (label, mdi, length) in enumerate(plan):
        path = os.path.join(workdir, "machine-g43-%d.yaml" % k)
        with_tool_length(src, path, length)
        m = L.Machine(path)
        _, poses = poses_for(m, G43_POSES, 30 + k, length, margin=0.3)
        moves = [{"target": p, "read": True, "label": "%s #%d" % (label, i), "motion": "G90 G1",
                  "before": to_zero + mdi if i == 0 else []} for i, (_, p) in enumerate(poses)]
        segments.append({"label": label, "offset": length, "path": path, "machine": m, "poses": poses, "moves": moves})
    return segments


def g43_check(name, seg, readings, letters, workdir, seconds, g43_seconds):
    """The tool tip (the model with the segment's tool length at the joints LinuxCNC computed) on the
    commanded point within 0.1 um; forward (actual_position) equal to the world LinuxCNC holds, the
    command plus the tool offset along z, within 1e-6 mm; G43 applied (stat and the HAL pin)."""
    m, poses, o = seg["machine"], seg["poses"], seg["offset"]
    if len(readings) != len(poses):
        raise Failure("%s %s: %d readings for %d poses" % (name, seg["label"], len(readings), len(poses)))
    after = [{l: r["joints"][j]["pos_cmd"] for j, l in enumerate(letters)} for r in readings]
    before = [q for q, _ in poses]
    e = model_error(seg["path"], letters, after + before, workdir, "g43-%s" % seg["label"].replace(" ", "-"))
    target = np.array([p[:3] for _, p in poses])
    d_after = np.array([m.nominal_tool_point(q) for q in after]) + e[:len(after)] - target
    d_before = np.array([m.nominal_tool_point(q) for q in before]) + e[len(after):] - target
    world = target + o * np.array([0.0, 0.0, 1.0])
    fwd = max(max(abs(r["actual"][i] - world[k][i]) for i in range(3)) for k, r in enumerate(readings))
    rot_w = max([abs(r["actual"][3 + "ABC".index(l)] - p[3 + k]) for r, (_, p) in zip(readings, poses)
                 for k, l in enumerate(x for x in letters if x in "ABC")] or [0.0])
    offset_seen = max(max(abs(r["tool_offset"][2] - o), abs(r["tooloffset_pin"][2] - o)) for r in readings)

    def va(d):
        return max(float(np.linalg.norm(a - b)) for a, b in itertools.combinations(d, 2))

    c = {"check": "%s %s" % (name, seg["label"]), "poses": len(poses), "tool_length_mm": o,
         "max_e_before_um": float(np.max(np.linalg.norm(d_before, axis=1))) * 1e3,
         "max_e_after_um": float(np.max(np.linalg.norm(d_after, axis=1))) * 1e3,
         "va_before_um": va(d_before) * 1e3, "va_after_um": va(d_after) * 1e3,
         "forward_mm": fwd, "forward_rotary_deg": rot_w, "linuxcnc_seconds": round(seconds, 1),
         "tool_offset_error_mm": offset_seen, "comp_tables": 0, "g43_seconds": round(g43_seconds, 1)}
    c["ok"] = (c["max_e_after_um"] * 1e-3 <= TOL_POINT_MM and fwd <= TOL_FORWARD_MM and rot_w <= 1e-6
               and offset_seen <= 1e-9 and c["max_e_before_um"] > 1.0)
    return c


def machine_case(name, spec, workdir):
    src = os.path.join(L.ROOT, spec["machine"])
    out = os.path.join(workdir, "out")
    L.run([L.MTCAL, "compensate", "--machine", src, "--format", "linuxcnc-kins", "--out", out, "--residual-points", "3"],
          "mtcal compensate --format linuxcnc-kins")
    L.run(["sh", os.path.join(out, "build.sh")], "build.sh (halcompile --install)")
    base = L.Machine(src)
    results = []
    for tag, length in (("tool", float((base.doc.get("tool") or {}).get("length", 0.0))), ("no-tool", 0.0)):
        m_path = os.path.join(workdir, "machine-%s.yaml" % tag)
        with_tool_length(src, m_path, length)
        m = L.Machine(m_path)
        letters, poses = poses_for(m, spec["poses"], 7 if tag == "tool" else 8, length)
        limits, axis_limits = {}, {}
        for l in letters:
            lo, hi = m.travel(l)
            limits[l] = (lo - 1000, hi + 1000) if l in "XYZ" else (lo - 10, hi + 10)
            axis_limits[l] = (-5000, 5000) if l in "XYZ" else limits[l]
        cfg = os.path.join(workdir, "cfg-" + tag)
        tool_hal = os.path.join(workdir, "tool-%s.hal" % tag)
        with open(tool_hal, "w") as f:
            f.write("setp %s.tool-length %.9f\n" % (MODULE, length))
        # The direction-dependent terms' COMP_FILE type 1 tables, loaded as the INI snippet says.
        tables = {}
        for j in range(len(letters)):
            path = os.path.join(out, "joint%d-reversal.comp" % j)
            if os.path.exists(path):
                tables[j] = (os.path.basename(path), L.read_comp_file(path))
        snippet = {j: {"COMP_FILE": t[0], "COMP_FILE_TYPE": 1} for j, t in tables.items()}
        L.write_config(cfg, name, letters, MODULE, limits, axis_limits, snippet, ["linuxcnc-kins.hal", os.path.basename(tool_hal)],
                       [os.path.join(out, "linuxcnc-kins.hal"), tool_hal] + [os.path.join(out, t[0]) for t in tables.values()],
                       tool_table=G43_TOOL_TABLE if tag == "no-tool" and spec.get("g43") else "")
        moves = [{"target": p, "read": True, "label": "pose%d" % i} for i, (_, p) in enumerate(poses)]
        segments = g43_segments(src, workdir, letters) if tag == "no-tool" and spec.get("g43") else []
        for seg in segments:
            moves += seg["moves"]
        res = L.run_linuxcnc(cfg, {"joints": len(letters), "coordinates": letters, "moves": moves, "feed": 30000})
        g43_readings = res["readings"][len(poses):]
        g43_seconds = g43_readings[-1]["seconds"] - res["readings"][len(poses) - 1]["seconds"] if g43_readings else 0.0
        res["readings"] = res["readings"][:len(poses)]
        if len(res["readings"]) != len(poses) or len(g43_readings) != sum(len(seg["poses"]) for seg in segments):
            raise Failure("%s: %d readings for %d poses" % (name, len(res["readings"]) + len(g43_readings), len(moves)))
        # After: the joints LinuxCNC computed; before: the nominal joints of the same poses.
        after = [{l: r["joints"][j]["pos_cmd"] for j, l in enumerate(letters)} for r in res["readings"]]
        before = [q for q, _ in poses]
        e = model_error(m_path, letters, after + before, workdir, tag)
        target = np.array([p[:3] for _, p in poses])
        actual_after = np.array([m.nominal_tool_point(q) for q in after]) + e[:len(after)]
        actual_before = np.array([m.nominal_tool_point(q) for q in before]) + e[len(after):]
        # What LinuxCNC adds to the motor command (motor-pos-cmd - pos-cmd - motor-offset) against the table,
        # interpolated at pos-cmd (control.c compute_screw_comp()): the forward or the reverse column, by the
        # joint's last direction of motion. A G1 in world coordinates moves a joint non-monotonically (the
        # rotary axes turn along the line), so that direction is not the sign of the pose-to-pose change:
        # the check takes the column that matches and counts both, each must occur.
        comp_worst, comp_max, comp_cols = 0.0, 0.0, [0, 0]
        for r in res["readings"]:
            for j, (_, (nom, fwd, rev)) in tables.items():
                jr = r["joints"][j]
                ef, er = (L.interpolate_held(nom, col, jr["pos_cmd"]) for col in (fwd, rev))
                applied = jr["motor_pos_cmd"] - jr["pos_cmd"] - jr["motor_offset"]
                dev = min(abs(applied - ef), abs(applied - er))
                comp_worst = max(comp_worst, dev)
                comp_max = max(comp_max, abs(ef), abs(er))
                if abs(ef - er) > 1e-5:
                    comp_cols[0 if abs(applied - ef) < abs(applied - er) else 1] += 1
        d_after = actual_after - target
        d_before = actual_before - target
        fwd = max(max(abs(r["actual"][i] - p[i]) for i in range(3)) for r, (_, p) in zip(res["readings"], poses))
        rot_w = max([abs(r["actual"][3 + "ABC".index(l)] - p[3 + k]) for r, (_, p) in zip(res["readings"], poses)
                     for k, l in enumerate(x for x in letters if x in "ABC")] or [0.0])

        def va(d):
            return max(float(np.linalg.norm(a - b)) for a, b in itertools.combinations(d, 2))

        c = {"check": "%s %s" % (name, tag), "poses": len(poses), "tool_length_mm": length,
             "max_e_before_um": float(np.max(np.linalg.norm(d_before, axis=1))) * 1e3,
             "max_e_after_um": float(np.max(np.linalg.norm(d_after, axis=1))) * 1e3,
             "va_before_um": va(d_before) * 1e3, "va_after_um": va(d_after) * 1e3,
             "forward_mm": fwd, "forward_rotary_deg": rot_w, "linuxcnc_seconds": round(res["seconds"], 1),
             "comp_tables": len(tables), "comp_worst_mm": comp_worst, "comp_max_mm": comp_max, "comp_columns": comp_cols}
        c["ok"] = (c["max_e_after_um"] * 1e-3 <= TOL_POINT_MM and fwd <= TOL_FORWARD_MM and rot_w <= 1e-6 and c["max_e_before_um"] > 1.0
                   and comp_worst <= L.TOLERANCE_MM and (not tables or (comp_max > 1e-5 and min(comp_cols) > 0)))
        results.append(c)
        for seg in segments:
            n = len(seg["poses"])
            results.append(g43_check(name, seg, g43_readings[:n], letters, workdir, res["seconds"], g43_seconds))
            g43_readings = g43_readings[n:]
    return results


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--mtcal", required=True)
    ap.add_argument("--root", required=True)
    ap.add_argument("--case", action="append")
    ap.add_argument("--keep")
    ap.add_argument("--results")
    a = ap.parse_args()
    L.MTCAL, L.ROOT = os.path.abspath(a.mtcal), os.path.abspath(a.root)
    # The reversal tables step by up to 25.2 um when a joint turns (HU40T's Y: +-12.58 um). LinuxCNC
    # never applies a step between a*T^2/4 and a*T^2/2 of the joint's acceleration a (see
    # lcnc_test.write_config); 20x the axis acceleration puts that window at 25-50 um, where the HU40T
    # step fell (its correction never settled), 40x at 50-100 um.
    if "MTCAL_LCNC_JOINT_ACCEL_FACTOR" not in os.environ:
        L.JOINT_ACCELERATION_FACTOR = 40
    if shutil.which("halcompile") is None or not os.path.exists("/usr/include/linuxcnc/kinematics.h"):
        print("FAIL linuxcnc-kins: halcompile or /usr/include/linuxcnc/kinematics.h missing: install Debian's linuxcnc-uspace-dev "
              "(scripts/install-deps --linuxcnc)")
        return 1
    base = os.path.abspath(a.keep) if a.keep else tempfile.mkdtemp(prefix="mtcal-lcnc-kins-", dir="/tmp")
    os.makedirs(base, exist_ok=True)
    passed = failed = 0
    checks = []
    with open(L.LOCK_FILE, "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        for name in a.case or list(CASES):
            workdir = os.path.join(base, name)
            shutil.rmtree(workdir, ignore_errors=True)
            os.makedirs(workdir)
            print("-- %s: %s, kinematics module %s" % (name, CASES[name]["machine"], MODULE), flush=True)
            try:
                cs = machine_case(name, CASES[name], workdir)
            except Failure as e:
                cs = [{"check": name, "ok": False, "why": str(e)}]
            for c in cs:
                checks.append(c)
                if c["ok"]:
                    passed += 1
                    print("PASS %s: %d poses, tool length %g mm: max |e| %.3f -> %.6f um, VA %.3f -> %.6f um; forward %.2g mm, "
                          "rotary %.2g deg; LinuxCNC run %.1f s" % (c["check"], c["poses"], c["tool_length_mm"], c["max_e_before_um"],
                                                                  c["max_e_after_um"], c["va_before_um"], c["va_after_um"],
                                                                  c["forward_mm"], c["forward_rotary_deg"], c["linuxcnc_seconds"]) +
                          ("" if "tool_offset_error_mm" not in c else " (G43: its moves and tool changes %.1f s)" % c["g43_seconds"]), flush=True)
                    if c["comp_tables"]:
                        print("     COMP_FILE type 1 reversal tables on %d joint(s): applied - table %.2g mm (corrections up to %.4f mm; "
                              "forward column %d times, reverse %d)" % (c["comp_tables"], c["comp_worst_mm"], c["comp_max_mm"],
                                                                      c["comp_columns"][0], c["comp_columns"][1]), flush=True)
                else:
                    failed += 1
                    print("FAIL %s: %s" % (c["check"], c.get("why") or json.dumps(c)), flush=True)
    if a.results:
        with open(a.results, "w") as f:
            json.dump({"checks": checks}, f, indent=1)
    if not a.keep and not failed:
        shutil.rmtree(base, ignore_errors=True)
    elif failed:
        print("files of this run kept in %s" % base)
    print("linuxcnc-kins: %d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
