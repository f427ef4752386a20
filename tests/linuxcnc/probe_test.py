#!/usr/bin/python3
# Planning proved in LinuxCNC (issue 31 item 4; docs/planning.md, "The LinuxCNC run"):
#   mtcal plan (nominal RRTTT, one sphere) -> the probing program (G38.2, PROBEOPEN log)
#   -> LinuxCNC 2.9 headless, nominal kinematics (trivkins), the simulated probe of
#      `mtcal linuxcnc-probe` built with halcompile from a TRUTH machine (the nominal one plus
#      tests/linuxcnc/probe/rrttt-truth.yaml, and a sphere 35-50 um from where the plan puts it)
#   -> mtcal probe-log reads the log LinuxCNC wrote -> mtcal identify
#   -> every identified parameter within 3 predicted standard uncertainties of the truth.
# Also: the trip overshoot measured at every logged contact (the truth's tip at the logged joints),
# and a probe that never trips (the plan's sphere 20 mm above the real one): LinuxCNC's "G38.2 move
# finished without making contact", and probe-log's message naming the missing contact.
# Usage (through tests/linuxcnc/run-probe): probe_test.py --mtcal PATH --root ROOT [--keep DIR] [--only CASE]
import argparse
import csv
import fcntl
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import yaml

import lcnc_test as L
from lcnc_test import Failure

MACHINE = "examples/machines/rrttt-table-table.yaml"
ARTEFACT = "examples/plans/rrttt-viprey-sphere.csv"  # its sphere (120, -80, 60) mm; its rows are not used
TRUTH = "tests/linuxcnc/probe/rrttt-truth.yaml"
ESTIMATE = ["EX0C", "EY0C", "EA0C", "EB0C", "EY0A", "EZ0A", "EB0A", "EC0A"]
SPHERE_PLAN = np.array([120.0, -80.0, 60.0])
SPHERE_TRUE = SPHERE_PLAN + np.array([0.035, -0.042, 0.021])  # where the sphere really is (unknown to mtcal)
BALL, TIP = 25.4, 3.0          # mm, plan's defaults
POSES = 12
MOVE_FEED = 12000.0            # mm/min between touches (the sim moves at up to 500 mm/s)
SERVO_PERIOD_S = 0.001         # tests/linuxcnc/sim.ini.in SERVO_PERIOD
FEED = 120.0                   # mm/min: the probing feed (below)
APPROACH = 0.5                 # mm before the expected contact: the truth is within 0.1 mm of the nominal
# The trip is seen once per servo period: the tip is logged up to one period's travel s = F T past the
# contact, uniform, so the touch noise is s / sqrt(12) (docs/planning.md). A ball centre from the
# five touches (pole, four on the equator, radius free): across the tool s/sqrt(12)/sqrt(2), along it
# s/sqrt(12)*sqrt(5/4). The plan's reading sigma is the larger one.
STEP_MM = FEED / 60.0 * SERVO_PERIOD_S
SIGMA_TOUCH_MM = STEP_MM / math.sqrt(12.0)
SIGMA_CENTRE_MM = SIGMA_TOUCH_MM * math.sqrt(1.25)
LETTERS = "XYZAC"  # LinuxCNC joint order (trivkins coordinates=XYZAC)


def mtcal(*args, what=None):
    return L.run([L.MTCAL, *args], what or "mtcal " + args[0])


def nominal_machine(workdir):
    with open(os.path.join(L.ROOT, MACHINE)) as f:
        doc = yaml.safe_load(f)
    doc["errors"] = {}
    doc["name"] = "RRTTT nominal (mtcal LinuxCNC probe test)"
    path = os.path.join(workdir, "nominal.yaml")
    with open(path, "w") as f:
        yaml.safe_dump(doc, f, sort_keys=False)
    # The truth as one machine file, for the overshoot check through `mtcal eval` (the component got it as
    # nominal.yaml + --params TRUTH).
    with open(os.path.join(L.ROOT, TRUTH)) as f:
        truth = yaml.safe_load(f)["errors"]
    doc["errors"] = truth
    doc["name"] = "RRTTT truth (mtcal LinuxCNC probe test)"
    tpath = os.path.join(workdir, "truth.yaml")
    with open(tpath, "w") as f:
        yaml.safe_dump(doc, f, sort_keys=False)
    return path, tpath, {k: to_internal(v) for k, v in truth.items()}


def to_internal(text):
    m = re.fullmatch(r"\s*(-?[\d.]+)\s*(um|urad)\s*", str(text))
    if not m:
        raise Failure("%s: expected 'VALUE um' or 'VALUE urad', found %r" % (TRUTH, text))
    return float(m.group(1)) * 1e-3 if m.group(2) == "um" else float(m.group(1)) * 1e-6


def plan(workdir, nominal, artefact, tag, poses):
    out = os.path.join(workdir, "plan-%s.csv" % tag)
    prog = os.path.join(workdir, "probe-%s.ngc" % tag)
    text = mtcal("plan", "-m", nominal, "--artefact", artefact, "--estimate", ",".join(ESTIMATE), "--poses", str(poses),
                 "--sigma-um", repr(SIGMA_CENTRE_MM * 1e3), "--probe-feed", repr(FEED), "--approach", repr(APPROACH), "--move-feed", repr(MOVE_FEED),
                 "--out", out, "--gcode", prog, "--json")
    return out, prog, json.loads(text)


def build_probe(workdir, nominal):
    out = os.path.join(workdir, "probe")
    mtcal("linuxcnc-probe", "-m", nominal, "--params", os.path.join(L.ROOT, TRUTH), "--sphere",
          ",".join(repr(float(v)) for v in SPHERE_TRUE), "--sphere-diameter", repr(BALL), "--stylus-diameter", repr(TIP),
          "--out", out)
    L.run(["sh", os.path.join(out, "build.sh")], "build.sh (halcompile --install mtcal_probe.c)")
    return out


def run_program(workdir, tag, nominal, probe_dir, program):
    m = L.Machine(nominal)
    limits = {}
    for l in LETTERS:
        lo, hi = m.travel(l)
        limits[l] = (lo - 1.0, hi + 1.0)  # the program retracts to the travel's end
    joints_hal = os.path.join(workdir, "probe-joints-%s.hal" % tag)
    with open(joints_hal, "w") as f:
        f.write("# The simulated probe reads the joints' feedback: the loop-back signals of sim.hal.\n")
        for j in range(len(LETTERS)):
            f.write("net j%d-loop => mtcal_probe.joint-%d\n" % (j, j))
    cfg = os.path.join(workdir, "cfg-" + tag)
    shutil.copy(program, os.path.join(workdir, "probe.ngc"))
    L.write_config(cfg, "probe-" + tag, LETTERS, "trivkins coordinates=%s" % LETTERS, limits, limits, {},
                   ["linuxcnc-probe.hal", os.path.basename(joints_hal)],
                   [os.path.join(probe_dir, "linuxcnc-probe.hal"), joints_hal, os.path.join(workdir, "probe.ngc")])
    res = L.run_linuxcnc(cfg, {"joints": len(LETTERS), "coordinates": LETTERS, "program": "probe.ngc", "timeout": 240})
    return cfg, res


def overshoot(workdir, truth_path, log):
    """The truth's tip at each logged contact: how far past the contact (mm) LinuxCNC logged it."""
    rows = []
    with open(log) as f:
        for line in f:
            v = [float(x) for x in line.split()]
            rows.append({"X": v[0], "Y": v[1], "Z": v[2], "A": v[3], "C": v[5]})
    from kins_module_test import model_error
    e = model_error(truth_path, LETTERS, rows, workdir, "truth")
    m = L.Machine(truth_path)
    tips = np.array([m.nominal_tool_point(q) for q in rows]) + e
    return (BALL + TIP) / 2 - np.linalg.norm(tips - SPHERE_TRUE, axis=1)


def identify_case(workdir):
    nominal, truth_path, truth = nominal_machine(workdir)
    plan_csv, prog, pj = plan(workdir, nominal, os.path.join(L.ROOT, ARTEFACT), "main", POSES)
    predicted = {k: v["u"] for k, v in pj["predicted"]["parameters"].items()}
    probe_dir = build_probe(workdir, nominal)
    cfg, res = run_program(workdir, "main", nominal, probe_dir, prog)
    if not res["completed"]:
        raise Failure("LinuxCNC stopped the probing program: %s" % "; ".join(m["text"] for m in res["messages"]))
    log = os.path.join(cfg, "mtcal-contacts.txt")
    meas = os.path.join(workdir, "measured.csv")
    mtcal("probe-log", "-m", nominal, "--plan", plan_csv, "--log", log, "--approach", repr(APPROACH), "--out", meas)
    ij = json.loads(mtcal("identify", "-m", nominal, "--measurements", meas, "--estimate", ",".join(ESTIMATE), "--json"))
    over = overshoot(workdir, truth_path, log)
    print("  probing program: %d poses, %d contacts logged; LinuxCNC run %.1f s (program %.1f s)"
          % (POSES, len(over), res["seconds"], res["program_seconds"]))
    print("  trip overshoot at the %d contacts (truth tip past the sphere): mean %.3f um, std %.3f um, range %.3f .. "
          "%.3f um; one servo period's travel F T = %.3f um, predicted std F T / sqrt(12) = %.3f um"
          % (len(over), over.mean() * 1e3, over.std(ddof=1) * 1e3, over.min() * 1e3, over.max() * 1e3, STEP_MM * 1e3,
             SIGMA_TOUCH_MM * 1e3))
    print("  %-5s %12s %12s %12s %12s %12s %7s" % ("param", "truth", "identified", "difference", "u predicted",
                                                    "u identify", "|d|/u"))
    ok = True
    worst = 0.0
    for name in ESTIMATE:
        p = ij["parameters"][name]
        f, unit = (1e3, "um") if name[2] in "XYZ" and name[1] in "XYZ" and name[3] in "ABC" else (1e6, "urad")
        f, unit = (1e3, "um") if name[1] in "XYZ" else (1e6, "urad")
        d = p["value"] - truth[name]
        ratio = abs(d) / predicted[name]
        worst = max(worst, ratio)
        ok = ok and ratio <= 3.0
        print("  %-5s %9.3f %-4s %9.3f %-4s %9.3f %-4s %9.3f %-4s %9.3f %-4s %7.2f" % (
            name, truth[name] * f, unit, p["value"] * f, unit, d * f, unit, predicted[name] * f, unit, p["u"] * f, unit, ratio))
    # The overshoot must be what the servo period explains: within [0, 2 steps] (the trip is seen in the
    # cycle it happens or the next) and spread like a uniform distribution over one step.
    spread_ok = over.min() > -1e-6 and over.max() < 2 * STEP_MM + 1e-6 and 0.5 * SIGMA_TOUCH_MM < over.std(ddof=1) < 1.5 * SIGMA_TOUCH_MM
    return {"check": "identify from LinuxCNC's log", "ok": ok and spread_ok, "worst_ratio": worst, "overshoot_ok": spread_ok,
            "linuxcnc_seconds": res["seconds"]}


def no_contact_case(workdir):
    """The plan's sphere 20 mm above the real one: the first G38.2 ends without contact."""
    nominal, _, _ = nominal_machine(workdir)
    art = os.path.join(workdir, "artefact-high.csv")
    with open(os.path.join(L.ROOT, ARTEFACT)) as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    head = rows[0]
    with open(art, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(head)
        for r in rows[1:2]:
            r[head.index("z")] = repr(SPHERE_PLAN[2] + 20.0)
            w.writerow(r)
    plan_csv, prog, _ = plan(workdir, nominal, art, "high", 12)
    probe_dir = os.path.join(workdir, "probe")
    if not os.path.exists(os.path.join(probe_dir, "mtcal_probe.c")):
        probe_dir = build_probe(workdir, nominal)
    cfg, res = run_program(workdir, "high", nominal, probe_dir, prog)
    texts = [m["text"] for m in res["messages"]]
    lcnc_ok = any("G38.2 move finished without making contact" in t for t in texts) and not res["completed"]
    log = os.path.join(cfg, "mtcal-contacts.txt")
    meas = os.path.join(workdir, "measured-high.csv")
    p = subprocess.run([L.MTCAL, "probe-log", "-m", nominal, "--plan", plan_csv, "--log", log, "--approach", repr(APPROACH),
                        "--out", meas], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    msg = p.stderr.strip()
    mtcal_ok = (p.returncode != 0 and not os.path.exists(meas) and msg.startswith("mtcal: error: " + log) and
                "contact 1 is missing (touch 1 of the plan's record 1" in msg and "G38.2 move finished without making contact" in msg)
    print("  LinuxCNC: %s" % ("; ".join(texts) or "(no message)"))
    print("  mtcal probe-log: exit %d: %s" % (p.returncode, msg))
    return {"check": "a probe that never trips", "ok": lcnc_ok and mtcal_ok, "linuxcnc_seconds": res["seconds"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--mtcal", required=True)
    ap.add_argument("--root", required=True)
    ap.add_argument("--keep")
    ap.add_argument("--only", choices=["identify", "no-contact"])
    a = ap.parse_args()
    L.MTCAL, L.ROOT = os.path.abspath(a.mtcal), os.path.abspath(a.root)
    if shutil.which("halcompile") is None or not os.path.exists("/usr/include/linuxcnc/hal.h"):
        print("FAIL linuxcnc-probe: halcompile or /usr/include/linuxcnc/hal.h missing: install Debian's linuxcnc-uspace-dev "
              "(scripts/install-deps --linuxcnc)")
        return 1
    base = os.path.abspath(a.keep) if a.keep else tempfile.mkdtemp(prefix="mtcal-lcnc-probe-", dir="/tmp")
    os.makedirs(base, exist_ok=True)
    passed = failed = 0
    with open(L.LOCK_FILE, "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        for name, fn in (("identify", identify_case), ("no-contact", no_contact_case)):
            if a.only and a.only != name:
                continue
            workdir = os.path.join(base, name)
            shutil.rmtree(workdir, ignore_errors=True)
            os.makedirs(workdir)
            print("-- %s" % name, flush=True)
            try:
                c = fn(workdir)
            except Failure as e:
                c = {"check": name, "ok": False, "why": str(e)}
            if c["ok"]:
                passed += 1
                print("PASS %s" % c["check"], flush=True)
            else:
                failed += 1
                print("FAIL %s: %s" % (c["check"], c.get("why") or json.dumps(c)), flush=True)
    if not a.keep and not failed:
        shutil.rmtree(base, ignore_errors=True)
    elif failed:
        print("files of this run kept in %s" % base)
    print("linuxcnc-probe: %d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
