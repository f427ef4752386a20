#!/usr/bin/python3
# mtcal's test in the real controller: `mtcal compensate --format linuxcnc` writes compensation,
# LinuxCNC (Debian's linuxcnc-uspace, sim configuration, no hardware) loads it, and what the
# controller applies is compared with the machine model's correction, to 1e-6 mm.
#
# Run through tests/linuxcnc/run (make test-linuxcnc); docs/compensation-linuxcnc-test.md says what
# it proves, how the expected values are computed and which LinuxCNC source facts it relies on.
#
# The expected values never come from the files under test: they come from the model, through
# `mtcal eval` (the tool point's error e = actual - nominal in the workpiece frame, docs/conventions.md),
# and, for the 5-axis case, from this script's own nominal kinematics of the machine file.
import argparse
import csv
import fcntl
import json
import math
import os
import pwd
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
TOLERANCE_MM = 1e-6  # issue 14: what the controller applies must equal the model's correction to 1e-6 mm
LOCK_FILE = "/tmp/mtcal-linuxcnc-test.lock"  # one LinuxCNC at a time on this machine
LINUXCNC_TIMEOUT_S = 300
MAX_NODES = 25  # table nodes visited per joint (a 256-line table is sampled, to keep a run near 20 s)
JOINT_ACCELERATION_FACTOR = int(os.environ.get("MTCAL_LCNC_JOINT_ACCEL_FACTOR", "20"))  # see write_config()

# ---------------------------------------------------------------------------------------------
# The cases. Joint-compensation cases: the 3-axis example at both COMP_FILE_TYPEs. Kinematics
# cases: a 5-axis table-table example reduced to the errors a trt-kins configuration holds
# exactly (the positions of its two rotary axis lines), see derived_machine().
CASES = {
    "vmc3-type0": {"kind": "joint", "machine": "examples/machines/vmc-3axis.yaml", "type": 0, "points": 21},
    "vmc3-type1": {"kind": "joint", "machine": "examples/machines/vmc-3axis.yaml", "type": 1, "points": 21},
    "rrttt-xyzac": {"kind": "kins", "machine": "examples/machines/rrttt-table-table.yaml", "poses": 24},
    "hu40t-xyzbc": {"kind": "kins", "machine": "examples/machines/hu40t-wCBXfYZt.yaml", "poses": 24},
}

# ISO 230-7 positions of a rotary axis line across it (two per axis): what trt-kins' rot-point and
# offset pins describe (src/emc/kinematics/trtfuncs.c). Orientations and zero positions are not.
LINE_POSITIONS = {"A": ("EY0A", "EZ0A"), "B": ("EX0B", "EZ0B"), "C": ("EX0C", "EY0C")}
# xyzac/xyzbc-trt-kins: C rides on the tilting A (or B) axis, both on the table.
TRT_KINS = {("C", "A"): "xyzac-trt-kins", ("C", "B"): "xyzbc-trt-kins"}
TRT_PINS = ("x-rot-point", "y-rot-point", "z-rot-point", "x-offset", "y-offset", "z-offset")
UNIT_VECTOR = {"x": np.array([1.0, 0, 0]), "y": np.array([0, 1.0, 0]), "z": np.array([0, 0, 1.0])}
AXIS_OF_LETTER = {"X": "x", "Y": "y", "Z": "z", "A": "x", "B": "y", "C": "z"}


class Failure(Exception):
    """A check of the test failed (the message says what was expected and what was found)."""


# ---------------------------------------------------------------------------------------------
# The machine file, read for its nominal geometry only (docs/machine-file.md).
class Machine:
    def __init__(self, path):
        with open(path) as f:
            self.doc = yaml.safe_load(f)
        self.path = path
        units = self.doc.get("units", {})
        if units.get("length", "mm") != "mm" or units.get("angle", "deg") != "deg":
            raise Failure("%s: this test handles machine files in mm and deg only" % path)
        topo = self.doc["topology"]
        self.chain = [ch for ch in topo if ch not in "wft"]  # workpiece to tool
        self.table_side = [ch for ch in topo[1:topo.index("f")]]  # between w and f: carry the workpiece
        self.axes = {}
        for letter in self.chain:
            a = self.doc["axes"].get(letter, {}) or {}
            d = str(a.get("direction", "+" + AXIS_OF_LETTER[letter])).lower()
            sign = -1.0 if d.startswith("-") else 1.0
            self.axes[letter] = {
                "rotary": letter in "ABC",
                "sign": sign,
                "dir": sign * UNIT_VECTOR[d[-1]],
                "point": np.array(a.get("point", [0, 0, 0]), dtype=float),
                "travel": a.get("travel"),
            }
        tool = self.doc.get("tool", {}) or {}
        tool_axis = UNIT_VECTOR[str(tool.get("axis", "+z"))[-1].lower()]
        self.tool_point = np.array(tool.get("spindle_point", [0, 0, 0]), dtype=float) - float(tool.get("length", 0)) * tool_axis
        self.workpiece_origin = np.array((self.doc.get("workpiece", {}) or {}).get("origin", [0, 0, 0]), dtype=float)

    def travel(self, letter):
        t = self.axes[letter]["travel"]
        if t is None:
            return (0.0, 360.0) if self.axes[letter]["rotary"] else None
        return float(t[0]), float(t[1])

    def nominal_tool_point(self, q, line_shift=None):
        """Tool point in the workpiece frame with the joints at q (mm, deg): the nominal chain of
        docs/conventions.md ("The chain") without errors, T = W^-1 J_1 ... J_n S Trans(-l a), each J the
        tool side relative to the workpiece side: a linear axis translates by q along its direction,
        a rotary axis turns by q about its line (right-hand rule about its direction).
        line_shift: {letter: vector} moves a rotary axis line (its ISO 230-7 position errors)."""
        p = self.tool_point.copy()
        for letter in reversed(self.chain):  # innermost (tool end) first
            ax = self.axes[letter]
            v = q.get(letter, 0.0)
            if not ax["rotary"]:
                p = p + v * ax["dir"]
            else:
                c = ax["point"] + (line_shift or {}).get(letter, np.zeros(3))
                p = c + rotation(ax["dir"], math.radians(v)) @ (p - c)
        return p - self.workpiece_origin


def rotation(axis, angle):
    """Rotation matrix by `angle` (rad) about the unit vector `axis`, right-hand rule (Rodrigues)."""
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k)


def derived_machine(src, dst):
    """The example machine with only the errors a trt-kins configuration represents exactly: the
    positions across their lines of its two table rotary axes (ISO 230-7, e.g. EX0C EY0C EY0A EZ0A).
    Everything else of the file (axes, tool, workpiece) is kept. Returns the kept error names."""
    with open(src) as f:
        doc = yaml.safe_load(f)
    m = Machine(src)
    rot = [l for l in m.table_side if l in "ABC"]
    keep = [n for l in rot for n in LINE_POSITIONS[l]]
    doc["errors"] = {n: v for n, v in (doc.get("errors") or {}).items() if n in keep}
    doc["name"] = doc.get("name", "") + " - rotary axis line positions only (mtcal LinuxCNC test)"
    doc.pop("description", None)
    with open(dst, "w") as f:
        f.write("# Derived by tests/linuxcnc/lcnc_test.py from %s: only %s.\n" % (os.path.relpath(src, ROOT), ", ".join(sorted(doc["errors"]))))
        yaml.safe_dump(doc, f, sort_keys=False)
    return sorted(doc["errors"])


# ---------------------------------------------------------------------------------------------
# The model through `mtcal eval` (batch: --points CSV, --out CSV).
def mtcal_eval(machine_path, letters, rows, workdir, tag):
    """rows: list of (values {letter: mm|deg}, dirs {letter: +1|-1}). Returns an (n, 3) array of the
    tool point's error dx dy dz (mm, workpiece frame), and (n, 3) rx ry rz (rad)."""
    dir_letters = sorted({l for _, d in rows for l in d})
    pin = os.path.join(workdir, "eval-%s-in.csv" % tag)
    pout = os.path.join(workdir, "eval-%s-out.csv" % tag)
    with open(pin, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(list(letters) + ["dir" + l for l in dir_letters])
        for values, dirs in rows:
            w.writerow([repr(float(values.get(l, 0.0))) for l in letters] + [dirs.get(l, 0) for l in dir_letters])
    run([MTCAL, "eval", "--machine", machine_path, "--points", pin, "--out", pout], "mtcal eval (%s)" % tag)
    with open(pout) as f:
        out = list(csv.DictReader(f))
    if len(out) != len(rows):
        raise Failure("mtcal eval (%s): expected %d rows in %s, found %d" % (tag, len(rows), pout, len(out)))
    for (values, _), o in zip(rows, out):
        for l in letters:
            if abs(float(o[l]) - float(values.get(l, 0.0))) > 1e-9:
                raise Failure("mtcal eval (%s): row for %s=%r came back as %r" % (tag, l, values.get(l), o[l]))
    e = np.array([[float(o[k]) for k in ("dx", "dy", "dz")] for o in out])
    r = np.array([[float(o[k]) for k in ("rx", "ry", "rz")] for o in out])
    return e, r


def run(cmd, what, **kw):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, **kw)
    if p.returncode != 0:
        raise Failure("%s failed (exit %d): %s\n%s" % (what, p.returncode, " ".join(cmd), p.stdout[-3000:]))
    return p.stdout


# ---------------------------------------------------------------------------------------------
# What `mtcal compensate --format linuxcnc` wrote, read by this test's own readers.
def read_ini_snippet(path, coordinates, kinematics):
    """The INI snippet mtcal writes, merged by this test into its own configuration. Returns
    ({joint n: {"COMP_FILE": name, "COMP_FILE_TYPE": t}}, [HALFILE names]). Besides [JOINT_n] with
    COMP_FILE / COMP_FILE_TYPE it may say how to load the rest ([HAL] HALFILE, [KINS] KINEMATICS and
    JOINTS, [TRAJ] COORDINATES): those must agree with the configuration the test builds from the
    machine file. Anything else is refused by name, so that the test runs what it says it runs."""
    joints, halfiles, cur = {}, [], None
    if not os.path.exists(path):
        return joints, halfiles
    with open(path) as f:
        for lineno, raw in enumerate(f, 1):
            line = raw.strip()
            if not line or line[0] in "#;":
                continue
            where = "%s:%d" % (path, lineno)
            if line.startswith("["):
                cur = line.strip("[]").strip()
                if cur.startswith("JOINT_"):
                    joints.setdefault(int(cur[6:]), {})
                elif cur not in ("HAL", "KINS", "TRAJ"):
                    raise Failure("%s: expected sections [JOINT_n], [HAL], [KINS] or [TRAJ], found [%s]" % (where, cur))
                continue
            if cur is None or "=" not in line:
                raise Failure("%s: expected KEY = VALUE inside a section, found %r" % (where, line))
            k, v = (x.strip() for x in line.split("=", 1))
            if cur.startswith("JOINT_") and k in ("COMP_FILE", "COMP_FILE_TYPE"):
                joints[int(cur[6:])][k] = v
            elif cur == "HAL" and k == "HALFILE":
                halfiles.append(v)
            elif cur == "KINS" and k == "KINEMATICS":
                if v.split()[0] != kinematics:
                    raise Failure("%s: KINEMATICS = %s, this machine needs %s" % (where, v, kinematics))
            elif cur == "KINS" and k == "JOINTS":
                if int(v) != len(coordinates):
                    raise Failure("%s: JOINTS = %s, the machine has %d (%s)" % (where, v, len(coordinates), coordinates))
            elif cur == "TRAJ" and k == "COORDINATES":
                if v.replace(" ", "").upper() != coordinates:
                    raise Failure("%s: COORDINATES = %s, expected %s" % (where, v, " ".join(coordinates)))
            else:
                raise Failure("%s: [%s] %s is not a key this test merges (COMP_FILE, COMP_FILE_TYPE, HALFILE, KINEMATICS, JOINTS, COORDINATES)" % (where, cur, k))
    return joints, halfiles


def read_comp_file(path):
    """LinuxCNC's comp file as the controller reads it (src/emc/motion/usrmotintf.cc, usrmotLoadComp():
    fgets + sscanf("%lf %lf %lf") until the first line that is not three numbers), with the checks the
    controller makes (src/emc/motion/command.c, EMCMOT_SET_JOINT_COMP: at most EMCMOT_COMP_SIZE = 256
    entries, nominals strictly increasing) made errors here instead of silent truncation."""
    rows = []
    with open(path) as f:
        for lineno, raw in enumerate(f, 1):
            parts = raw.split()
            try:
                if len(parts) != 3:
                    raise ValueError
                rows.append(tuple(float(p) for p in parts))
            except ValueError:
                raise Failure("%s:%d: expected three numbers 'nominal forward reverse', found %r "
                              "(LinuxCNC stops reading silently there)" % (path, lineno, raw.rstrip("\n")))
    if not 2 <= len(rows) <= 256:
        raise Failure("%s: expected 2 to 256 lines (EMCMOT_COMP_SIZE), found %d" % (path, len(rows)))
    for i in range(1, len(rows)):
        if not rows[i][0] > rows[i - 1][0]:
            raise Failure("%s:%d: nominal %r is not greater than the previous %r" % (path, i + 1, rows[i][0], rows[i - 1][0]))
    a = np.array(rows)
    return a[:, 0], a[:, 1], a[:, 2]


def interpolate_held(x, y, p):
    """Linear interpolation with the end values held outside the table: the rule of LinuxCNC's
    compute_screw_comp() (src/emc/motion/control.c) on the table that usrmotLoadComp() sends."""
    if p <= x[0]:
        return float(y[0])
    if p >= x[-1]:
        return float(y[-1])
    i = int(np.searchsorted(x, p, side="right")) - 1
    return float(y[i] + (y[i + 1] - y[i]) * (p - x[i]) / (x[i + 1] - x[i]))


# ---------------------------------------------------------------------------------------------
# The sim configuration and one LinuxCNC run.
def fill(template, fields):
    with open(os.path.join(HERE, template)) as f:
        text = f.read()
    for k, v in fields.items():
        text = text.replace("@%s@" % k, str(v))
    if "@" in text.replace("@@", ""):
        left = [w for w in text.split() if w.count("@") >= 2]
        if left:
            raise Failure("template %s: unfilled fields %s" % (template, left))
    return text


def write_config(cfg, case, coordinates, kinematics, joint_limits, axis_limits, snippet, extra_halfiles, comp_files,
                 speeds=None, tool_table=""):
    """joint_limits/axis_limits: per coordinate letter (lo, hi). snippet: {joint: {KEY: value}}.
    speeds: {"linear": (mm/s, mm/s^2), "angular": (deg/s, deg/s^2)}, default 500, 5000 and 3600, 36000.
    tool_table: the text of tool.tbl ([EMCIO]TOOL_TABLE, LinuxCNC's format, machine units); empty by default."""
    os.makedirs(cfg)
    speeds = dict({"linear": (500, 5000), "angular": (3600, 36000)}, **(speeds or {}))
    blocks = []
    for j, letter in enumerate(coordinates):
        rotary = letter in "ABC"
        vel, acc = speeds["angular"] if rotary else speeds["linear"]
        blocks.append(fill("axis.ini.in", {"AXIS": letter, "AXIS_MIN": axis_limits[letter][0], "AXIS_MAX": axis_limits[letter][1],
                                           "VELOCITY": vel, "ACCELERATION": acc}))
        # The joint's MAX_ACCELERATION also sets how the controller ramps a change of the correction
        # (control.c, compute_screw_comp(): a_max = 0.5 * acc_limit). From rest, a step of the correction
        # up to acc*T^2/4 (T = servo period) is applied in one cycle, but a step between acc*T^2/4 and
        # acc*T^2/2 is never applied: the "constant velocity" branch adds backlash_vel * T = 0 forever
        # (found by this test: with 5000 mm/s^2 a 2 um reversal step stayed unapplied). 20x the axis
        # acceleration puts the window at 25-50 um, above every step of the example machines.
        block = fill("joint.ini.in", {"JOINT": j, "AXIS": letter, "TYPE": "ANGULAR" if rotary else "LINEAR",
                                      "JOINT_MIN": joint_limits[letter][0], "JOINT_MAX": joint_limits[letter][1],
                                      "VELOCITY": vel, "ACCELERATION": JOINT_ACCELERATION_FACTOR * acc})
        for k, v in snippet.get(j, {}).items():  # the snippet's lines, merged into the joint's section
            block += "%s = %s\n" % (k, v)
        blocks.append(block)
    unknown = set(snippet) - set(range(len(coordinates)))
    if unknown:
        raise Failure("the INI snippet names joints %s; this configuration has joints 0..%d (%s)" % (sorted(unknown), len(coordinates) - 1, coordinates))
    ini = fill("sim.ini.in", {
        "CASE": case, "COORDINATES": " ".join(coordinates), "KINEMATICS": kinematics, "JOINTS": len(coordinates),
        "LINEAR_VELOCITY": speeds["linear"][0], "LINEAR_ACCELERATION": speeds["linear"][1],
        "ANGULAR_VELOCITY": speeds["angular"][0],
        "EXTRA_HALFILES": "\n".join("HALFILE = %s" % h for h in extra_halfiles),
        "AXES_AND_JOINTS": "\n".join(blocks)})
    with open(os.path.join(cfg, "test.ini"), "w") as f:
        f.write(ini)
    loop = "\n".join("net j%d-loop joint.%d.motor-pos-cmd => joint.%d.motor-pos-fb" % (j, j, j) for j in range(len(coordinates)))
    with open(os.path.join(cfg, "sim.hal"), "w") as f:
        f.write(fill("sim.hal.in", {"LOOPBACK": loop}))
    for src in comp_files + [os.path.join(HERE, "driver.py")]:
        shutil.copy(src, cfg)
    with open(os.path.join(cfg, "tool.tbl"), "w") as f:
        f.write(tool_table)
    open(os.path.join(cfg, "sim.var"), "w").close()


def raise_priority(increment):
    """preexec_fn of LinuxCNC's start: nice(increment) (negative: a higher CPU priority) for the
    linuxcnc script and everything it starts (rtapi_app, which runs motion's servo thread, task, io, the
    driver inherit it). A process that may not raise its priority (no CAP_SYS_NICE) runs as it is:
    its log then says so."""
    def apply():
        try:
            os.nice(increment)
        except OSError as e:
            # fd 2 is LinuxCNC's log here (the child, after its redirections, before exec)
            os.write(2, ("lcnc_test: could not change the priority by %d (%s): LinuxCNC runs at the default priority\n"
                         % (increment, e)).encode())
    return apply


def run_linuxcnc(cfg, plan, nice=0, timeout=LINUXCNC_TIMEOUT_S):
    """One LinuxCNC run of the sim configuration in cfg, driven by driver.py through plan. nice: the
    priority change for the whole run (0: none; examples/loop/lcnc-sim uses it, docs/workflows.md
    "Under load"); timeout: seconds before LinuxCNC is stopped."""
    with open(os.path.join(cfg, "plan.json"), "w") as f:
        json.dump(plan, f)
    env = dict(os.environ)
    env.pop("DISPLAY", None)  # headless: the linuxcnc script then cleans a stale lock by itself
    fifo_dir = tempfile.mkdtemp(prefix="rtfifo", dir="/tmp")
    os.chmod(fifo_dir, 0o777)
    # rtapi_app refuses to run as root unless RTAPI_UID names a non-root user to fall back to
    # (src/rtapi/uspace_rtapi_app.cc, main()); its FIFO then lives at RTAPI_FIFO_PATH.
    env["RTAPI_FIFO_PATH"] = os.path.join(fifo_dir, "rtapi_fifo")
    if os.getuid() == 0 and not env.get("RTAPI_UID"):
        env["RTAPI_UID"] = str(pwd.getpwnam("nobody").pw_uid)
    log = os.path.join(cfg, "linuxcnc.log")
    t0 = time.time()
    try:
        with open(log, "w") as out:
            p = subprocess.run(["linuxcnc", "-r", os.path.join(cfg, "test.ini")], cwd=cfg, env=env, stdin=subprocess.DEVNULL,
                               stdout=out, stderr=subprocess.STDOUT, timeout=timeout,
                               preexec_fn=raise_priority(nice) if nice else None)
        rc = p.returncode
    except subprocess.TimeoutExpired:
        rc = "timeout after %d s" % timeout
    finally:
        shutil.rmtree(fifo_dir, ignore_errors=True)
    seconds = time.time() - t0
    with open(log) as f:
        text = f.read()
    if rc != 0 or not os.path.exists(os.path.join(cfg, "readings.json")):
        lines = [l for l in text.splitlines() if "fallback_uid" not in l]
        raise Failure("LinuxCNC run failed (%s); log %s:\n  %s" % (rc, log, "\n  ".join(lines[-25:])))
    for line in text.splitlines():  # the loader's complaints (src/emc/motion/command.c) are errors here
        if "compensation" in line.lower() and ("must increase" in line or "too many" in line or "can't open" in line):
            raise Failure("LinuxCNC refused the compensation file: %s" % line.strip())
    with open(os.path.join(cfg, "readings.json")) as f:
        res = json.load(f)
    res["seconds"] = seconds
    return res


# ---------------------------------------------------------------------------------------------
def compensate(case, machine_path, outdir, extra):
    """The files under test: from `mtcal compensate`, or (debugging aid only) a folder of files
    written by other means, MTCAL_LCNC_COMP_DIR/<case>/."""
    dev = os.environ.get("MTCAL_LCNC_COMP_DIR")
    if dev:
        src = os.path.join(dev, case)
        print("  NOTE: MTCAL_LCNC_COMP_DIR is set: files from %s, not from mtcal compensate (debugging aid; this run does not test the writer)" % src)
        shutil.copytree(src, outdir)
        return
    cmd = [MTCAL, "compensate", "--machine", machine_path, "--format", "linuxcnc", "--out", outdir] + extra
    with open(os.path.join(os.path.dirname(outdir), "compensate.log"), "w") as f:
        f.write(" ".join(cmd) + "\n" + run(cmd, "mtcal compensate"))


def joint_case(name, spec, workdir):
    m_path = os.path.join(ROOT, spec["machine"])
    m = Machine(m_path)
    out = os.path.join(workdir, "out")
    compensate(name, m_path, out, ["--linuxcnc-type", str(spec["type"]), "--points", str(spec["points"])])
    coordinates = "".join(l for l in "XYZABC" if l in m.chain)
    if coordinates != "XYZ":
        raise Failure("joint case %s: this case expects a 3-axis XYZ machine, found %s" % (name, coordinates))
    if not os.path.exists(os.path.join(out, "linuxcnc.ini")):
        raise Failure("mtcal compensate wrote no linuxcnc.ini in %s" % out)
    snippet, halfiles = read_ini_snippet(os.path.join(out, "linuxcnc.ini"), coordinates, "trivkins")
    if halfiles:
        raise Failure("the INI snippet of a 3-axis machine names HAL files %s; nothing to load there" % halfiles)
    tables = {}  # joint -> (letter, nominal, forward, reverse)
    for j, keys in sorted(snippet.items()):
        if "COMP_FILE" not in keys:
            continue
        t = int(keys.get("COMP_FILE_TYPE", "0"))
        if t != spec["type"]:
            raise Failure("[JOINT_%d] COMP_FILE_TYPE = %d, asked for %d" % (j, t, spec["type"]))
        tables[j] = (coordinates[j],) + read_comp_file(os.path.join(out, keys["COMP_FILE"]))
    if not tables:
        raise Failure("the INI snippet %s names no COMP_FILE" % os.path.join(out, "linuxcnc.ini"))

    # The model at the table's nodes: the tool point's error along the joint's own axis when that
    # axis alone moves (every other axis at 0, not moving), approached moving + and moving -.
    # Correction c = -e (docs/conventions.md; PRODUCT.md's sign rule).
    node_corr, mid_model = {}, {}
    for j, (letter, nom, fwd, rev) in tables.items():
        comp_index = "XYZ".index(AXIS_OF_LETTER[letter].upper())
        sign = m.axes[letter]["sign"]
        rows = [({letter: p}, {letter: d}) for d in (+1, -1) for p in nom]
        mids = (nom[:-1] + nom[1:]) / 2
        rows += [({letter: p}, {letter: d}) for d in (+1, -1) for p in mids]
        e, _ = mtcal_eval(m_path, coordinates, rows, workdir, "joint%d" % j)
        n, k = len(nom), len(mids)
        along = -sign * e[:, comp_index]
        node_corr[j] = {+1: along[:n], -1: along[n:2 * n]}
        mid_model[j] = {+1: along[2 * n:2 * n + k], -1: along[2 * n + k:]}

    # The files themselves, read back by this test (no controller yet): type 0 holds actual
    # positions nom + e, the controller adds nom - column; type 1 holds corrections, added as they are
    # (src/emc/motion/usrmotintf.cc, usrmotLoadComp()).
    file_err = 0.0
    for j, (letter, nom, fwd, rev) in tables.items():
        for d, col in ((+1, fwd), (-1, rev)):
            implied = nom - col if spec["type"] == 0 else col
            file_err = max(file_err, float(np.max(np.abs(implied - node_corr[j][d]))))

    # Positions: the nodes (all of them, or MAX_NODES spread over a longer table, first and last
    # included), the midpoint after each, and one half-spacing beyond each end (held values);
    # swept up (each reached moving +) then down (each reached moving -), all joints together.
    positions, limits = {}, {}
    for j, (letter, nom, _, _) in tables.items():
        h0, h1 = (nom[1] - nom[0]) / 2, (nom[-1] - nom[-2]) / 2
        idx = sorted(set(np.round(np.linspace(0, len(nom) - 1, min(len(nom), MAX_NODES))).astype(int)))
        mids = [(nom[i] + nom[i + 1]) / 2 for i in idx if i + 1 < len(nom)]
        pts = sorted(set([float(nom[i]) for i in idx] + mids + [nom[0] - h0, nom[-1] + h1]))
        positions[j] = pts
        limits[letter] = (pts[0] - 2 * h0 - 1, pts[-1] + 2 * h1 + 1)
    for letter in coordinates:
        limits.setdefault(letter, (-1000, 1000))
    K = max(len(p) for p in positions.values())
    moves = []
    start = [0.0] * 3
    for j, pts in positions.items():
        start[j] = pts[0] - 1.0
    moves.append({"target": list(start), "read": False})
    for d in (+1, -1):
        if d == -1:
            top = [0.0] * 3
            for j, pts in positions.items():
                top[j] = pts[-1] + 1.0
            moves.append({"target": top, "read": False})
        for k in range(K):
            tgt = [0.0] * 3
            for j, pts in positions.items():
                seq = pts if d == +1 else pts[::-1]
                tgt[j] = seq[min(k, len(seq) - 1)]
            moves.append({"target": tgt, "read": True, "label": "%+d:%d" % (d, k)})
    cfg = os.path.join(workdir, "cfg")
    comp_files = [os.path.join(out, snippet[j]["COMP_FILE"]) for j in tables]
    # the COMP_FILE names are copied next to test.ini; LinuxCNC opens them relative to its folder
    write_config(cfg, name, coordinates, "trivkins coordinates=XYZ", limits, limits,
                 {j: {"COMP_FILE": os.path.basename(snippet[j]["COMP_FILE"]), "COMP_FILE_TYPE": snippet[j].get("COMP_FILE_TYPE", "0")}
                  for j in tables}, [], comp_files)
    res = run_linuxcnc(cfg, {"joints": 3, "coordinates": coordinates, "moves": moves, "feed": 30000})

    checks = []
    for j, (letter, nom, _, _) in tables.items():
        worst = {"node": 0.0, "between": 0.0, "held": 0.0}
        n_read, max_expected, max_interp = 0, 0.0, 0.0
        seen = set()
        for r in res["readings"]:
            d = +1 if r["label"].startswith("+") else -1
            k = int(r["label"].split(":")[1])
            seq = positions[j] if d == +1 else positions[j][::-1]
            if k >= len(seq) or (d, k) in seen:
                continue  # this joint stood still on that move
            seen.add((d, k))
            p = seq[k]
            jr = r["joints"][j]
            if abs(jr["pos_cmd"] - p) > 1e-9:
                raise Failure("joint %d (%s): pos-cmd %r after the move to %r" % (j, letter, jr["pos_cmd"], p))
            applied = jr["motor_pos_cmd"] - jr["pos_cmd"] - jr["motor_offset"]
            expected = interpolate_held(nom, node_corr[j][d], p)
            where = "node" if np.any(np.abs(nom - p) < 1e-12) else ("held" if p < nom[0] or p > nom[-1] else "between")
            worst[where] = max(worst[where], abs(applied - expected))
            max_expected = max(max_expected, abs(expected))
            n_read += 1
        for d in (+1, -1):
            interp = np.array([interpolate_held(nom, node_corr[j][d], p) for p in (nom[:-1] + nom[1:]) / 2])
            max_interp = max(max_interp, float(np.max(np.abs(interp - mid_model[j][d]))))
        worst_all = max(worst.values())
        ok = worst_all <= TOLERANCE_MM and n_read >= 40 and max_expected > 1e-4
        checks.append({
            "check": "%s joint %d (%s)" % (name, j, letter), "ok": ok, "readings": n_read,
            "positions": len(positions[j]), "max_abs_diff_mm": worst_all, "by_place": worst,
            "max_abs_correction_mm": max_expected, "file_vs_model_mm": file_err,
            "interpolation_error_vs_model_mm": max_interp,
            "why": "" if ok else ("|applied - expected| %.3g mm > %.0e" % (worst_all, TOLERANCE_MM) if worst_all > TOLERANCE_MM
                                  else "too few readings (%d) or a correction too small to test (%.3g mm)" % (n_read, max_expected))})
    if file_err > TOLERANCE_MM:
        checks.append({"check": "%s files vs model" % name, "ok": False, "why": "the file's corrections differ from the model's by %.3g mm" % file_err})
    return checks, res


def kins_case(name, spec, workdir):
    src = os.path.join(ROOT, spec["machine"])
    m_path = os.path.join(workdir, "machine.yaml")
    kept = derived_machine(src, m_path)
    m = Machine(m_path)
    rot = [l for l in m.table_side if l in "ABC"]
    kins = TRT_KINS.get(tuple(rot))
    lin = [l for l in m.chain if l in "XYZ"]
    if kins is None or sorted(lin) != ["X", "Y", "Z"] or any(l in "ABC" for l in m.chain if l not in rot):
        raise Failure("%s: topology %s is not a table-table machine that xyzac/xyzbc-trt-kins describes" % (spec["machine"], m.doc["topology"]))
    if any(m.axes[l]["sign"] < 0 for l in lin):
        raise Failure("%s: a linear axis with a negative direction; this test maps X Y Z to joints 0 1 2 as they are" % spec["machine"])
    coordinates = "XYZ" + "".join(sorted(rot))  # joints X=0, Y=1, Z=2, then the rotary axes (the contract)
    out = os.path.join(workdir, "out")
    compensate(name, m_path, out, [])
    kins_hal = os.path.join(out, "linuxcnc-kins.hal")
    if not os.path.exists(kins_hal):
        raise Failure("mtcal compensate wrote no linuxcnc-kins.hal for %s" % spec["machine"])
    with open(kins_hal) as f:
        for lineno, raw in enumerate(f, 1):
            line = raw.split("#", 1)[0].strip()
            if not line:
                continue
            w = line.split()
            if len(w) != 3 or w[0] != "setp" or "." not in w[1]:
                raise Failure("%s:%d: expected 'setp %s.PIN VALUE', found %r" % (kins_hal, lineno, kins, raw.rstrip()))
            comp, pin = w[1].split(".", 1)
            if comp != kins or pin not in TRT_PINS:
                raise Failure("%s:%d: expected a pin of %s (%s), found %s" % (kins_hal, lineno, kins, ", ".join(TRT_PINS), w[1]))
            float(w[2])
    snippet, halfiles = read_ini_snippet(os.path.join(out, "linuxcnc.ini"), coordinates, kins)
    for h in halfiles:
        if os.path.basename(h) != "linuxcnc-kins.hal":
            raise Failure("the INI snippet loads %s; expected only linuxcnc-kins.hal" % h)
    comp_files = [os.path.join(out, k["COMP_FILE"]) for k in snippet.values() if "COMP_FILE" in k]

    # Mapping between LinuxCNC's world/joints and mtcal's axes, from the two sources:
    # - trtfuncs.c, xyzacKinematicsInverse()/xyzbcKinematicsInverse(): joints = R(a) R(c) (pos - rot point)
    #   + ..., i.e. the table turns the workpiece by +a, +c about +x (+y), +z;
    # - docs/conventions.md: a positive rotary command turns the tool about the axis direction relative
    #   to the workpiece, i.e. the table the other way.
    # So LinuxCNC's angle = -sign(direction) * mtcal's angle. LinuxCNC's linear joints are mtcal's
    # X Y Z (joints home at mtcal's zero), and its world position is the tool point in the
    # workpiece frame less the tool point at all-zero joints (world = joints at zero angles).
    t0 = m.nominal_tool_point({})

    def to_mtcal(pose):  # LinuxCNC world (x y z, angles) -> mtcal rotary values and target tool point
        q = {l: -m.axes[l]["sign"] * pose[3 + i] for i, l in enumerate(sorted(rot))}
        return q, np.array(pose[:3]) + t0

    def linear_solve(q_rot, target, e):
        """Linear joints X Y Z that put the nominal tool point + e at target, rotary axes at q_rot.
        The nominal tool point is affine in the linear joints once the rotary ones are fixed."""
        b = m.nominal_tool_point(dict(q_rot))
        M = np.column_stack([m.nominal_tool_point(dict(q_rot, **{l: 1.0})) - b for l in "XYZ"])
        return np.linalg.solve(M, target - b - e)

    # Poses: spread over the rotary travels, tool points within 90 mm of the rotary axes' crossing,
    # kept where the nominal joints stay within the machine's travel.
    poses, k = [], 0
    lo = {l: m.travel(l) for l in "XYZ"}
    rot_travel = {l: m.travel(l) for l in rot}
    centre = m.axes[rot[1]]["point"] - m.tool_point  # where the tilting axis crosses, in LinuxCNC joint coordinates
    while len(poses) < spec["poses"] and k < 2000:
        fa, fc = (0.5 + 0.4 * math.sin(1.7 * k + 0.3)), (0.5 + 0.45 * math.sin(0.9 * k + 1.1))
        tilt = rot_travel[rot[1]][0] + fa * (rot_travel[rot[1]][1] - rot_travel[rot[1]][0])
        turn = max(rot_travel[rot[0]][0], -175.0) + fc * (min(rot_travel[rot[0]][1], 175.0) - max(rot_travel[rot[0]][0], -175.0))
        mt = {rot[0]: turn, rot[1]: tilt}
        ang = [-m.axes[l]["sign"] * mt[l] for l in sorted(rot)]
        off = 90.0 * np.array([math.sin(2.3 * k), math.cos(1.3 * k + 0.5), math.sin(0.7 * k + 2.0)])
        pose = [round(v, 3) for v in list(centre + off) + ang]
        q_rot, tgt = to_mtcal(pose)
        jn = linear_solve(q_rot, tgt, np.zeros(3))
        if all(lo[l][0] + 5 <= jn[i] <= lo[l][1] - 5 for i, l in enumerate("XYZ")):
            poses.append(pose)
        k += 1
    if len(poses) < spec["poses"]:
        raise Failure("%s: found only %d poses within the travel" % (name, len(poses)))

    # Self-check of this script's nominal chain against mtcal's exact model: the line positions
    # applied as moved axis lines must give mtcal eval's error at every pose (1e-9 mm).
    errs = m.doc.get("errors") or {}
    shift = {}
    for l in rot:
        v = np.zeros(3)
        for n in LINE_POSITIONS[l]:
            if n in errs:  # a quantity: "3 um" or {value: 3, unit: um} (docs/machine-file.md)
                q = errs[n]
                val, unit = (q["value"], q["unit"]) if isinstance(q, dict) else str(q).split()
                v["XYZ".index(n[1])] += float(val) * {"nm": 1e-6, "um": 1e-3, "mm": 1.0, "m": 1e3}[unit]
        shift[l] = v

    # Expected joints: solve nominal(q) + e(q) = target for the linear joints with mtcal eval's e.
    # With line-position errors only, e depends on the rotary angles alone, so one pass is exact;
    # three passes are made anyway and the last change must be below 1e-12 mm.
    letters = "".join(l for l in "XYZABC" if l in m.chain)
    q_lin = [linear_solve(*to_mtcal(p), np.zeros(3)) for p in poses]
    q_nominal = [q.copy() for q in q_lin]
    for it in range(3):
        rows = [(dict(to_mtcal(p)[0], X=q[0], Y=q[1], Z=q[2]), {}) for p, q in zip(poses, q_lin)]
        e, _ = mtcal_eval(m_path, letters, rows, workdir, "kins%d" % it)
        new = [linear_solve(*to_mtcal(p), ei) for p, ei in zip(poses, e)]
        change = max(float(np.max(np.abs(a - b))) for a, b in zip(new, q_lin))
        q_lin = new
    if change > 1e-12:
        raise Failure("%s: the expected joints did not converge (last change %.3g mm)" % (name, change))
    self_err = 0.0
    for (values, _), ei in zip(rows, e):
        mine = m.nominal_tool_point(values, shift) - m.nominal_tool_point(values)
        self_err = max(self_err, float(np.max(np.abs(mine - ei))))
    if self_err > 1e-9:
        raise Failure("%s: this test's nominal chain disagrees with mtcal eval by %.3g mm (test bug)" % (name, self_err))

    limits = {}
    for l in "XYZ":  # the poses are within the travel; the moves between them need not be
        limits[l] = (lo[l][0] - 1000, lo[l][1] + 1000)
    for l in rot:
        a, b = sorted(-m.axes[l]["sign"] * v for v in rot_travel[l])
        limits[l] = (a - 10, b + 10)
    axis_limits = {l: (-2000, 2000) for l in "XYZ"}
    axis_limits.update({l: limits[l] for l in rot})
    cfg = os.path.join(workdir, "cfg")
    write_config(cfg, name, coordinates, kins, limits, axis_limits,
                 {j: {k2: (os.path.basename(v) if k2 == "COMP_FILE" else v) for k2, v in keys.items()} for j, keys in snippet.items()},
                 ["linuxcnc-kins.hal"], comp_files + [kins_hal])
    moves = [{"target": p, "read": True, "label": "pose%d" % i} for i, p in enumerate(poses)]
    res = run_linuxcnc(cfg, {"joints": len(coordinates), "coordinates": coordinates, "moves": moves, "feed": 30000})

    worst, worst_rot, max_corr = 0.0, 0.0, 0.0
    for r, p, qe, qn in zip(res["readings"], poses, q_lin, q_nominal):
        cmd = [jr["motor_pos_cmd"] - jr["motor_offset"] for jr in r["joints"]]
        worst = max(worst, float(np.max(np.abs(np.array(cmd[:3]) - qe))))
        worst_rot = max(worst_rot, max(abs(cmd[3 + i] - p[3 + i]) for i in range(len(rot))))
        max_corr = max(max_corr, float(np.max(np.abs(qe - qn))))
    ok = worst <= TOLERANCE_MM and worst_rot <= 1e-9 and len(res["readings"]) == len(poses) and max_corr > 1e-3
    return [{"check": "%s %s joints X Y Z" % (name, kins), "ok": ok, "readings": len(res["readings"]), "positions": len(poses),
             "max_abs_diff_mm": worst, "max_abs_rotary_diff_deg": worst_rot, "max_abs_correction_mm": max_corr,
             "errors_in_model": kept, "self_check_mm": self_err,
             "why": "" if ok else "|joints - expected| %.3g mm (rotary %.3g deg), %d readings, correction %.3g mm" % (worst, worst_rot, len(res["readings"]), max_corr)}], res


def main():
    global MTCAL, ROOT
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--mtcal", required=True)
    ap.add_argument("--root", required=True)
    ap.add_argument("--case", action="append", help="run only these cases (default: all)")
    ap.add_argument("--keep", help="keep every case's files (configuration, log, readings) under this folder")
    ap.add_argument("--results", help="write the figures as JSON here")
    a = ap.parse_args()
    MTCAL, ROOT = os.path.abspath(a.mtcal), os.path.abspath(a.root)
    names = a.case or list(CASES)
    base = os.path.abspath(a.keep) if a.keep else tempfile.mkdtemp(prefix="mtcal-lcnc-", dir="/tmp")
    os.makedirs(base, exist_ok=True)
    passed = failed = 0
    all_checks = []
    t_all = time.time()
    with open(LOCK_FILE, "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # one LinuxCNC instance at a time
        for name in names:
            spec = CASES[name]
            workdir = os.path.join(base, name)
            shutil.rmtree(workdir, ignore_errors=True)
            os.makedirs(workdir)
            t0 = time.time()
            print("-- %s: %s, %s" % (name, spec["machine"], "COMP_FILE_TYPE %d" % spec["type"] if spec["kind"] == "joint" else "trt kinematics"), flush=True)
            try:
                checks, res = (joint_case if spec["kind"] == "joint" else kins_case)(name, spec, workdir)
                for c in checks:
                    c["linuxcnc_seconds"] = round(res["seconds"], 1)
            except Failure as e:
                checks = [{"check": name, "ok": False, "why": str(e)}]
            for c in checks:
                c["case_seconds"] = round(time.time() - t0, 1)
                all_checks.append(c)
                if c["ok"]:
                    passed += 1
                    extra = ""
                    if "by_place" in c:
                        extra = " (nodes %.2g, between %.2g, held ends %.2g); file vs model %.2g mm; table interpolation vs model %.2g mm" % (
                            c["by_place"]["node"], c["by_place"]["between"], c["by_place"]["held"], c["file_vs_model_mm"], c["interpolation_error_vs_model_mm"])
                    else:
                        extra = "; rotary joints %.2g deg; nominal chain vs mtcal eval %.2g mm; model errors %s" % (
                            c["max_abs_rotary_diff_deg"], c["self_check_mm"], " ".join(c["errors_in_model"]))
                    print("PASS %s: %d readings at %d positions, max |applied - expected| %.3g mm%s, largest correction %.4f mm, LinuxCNC run %.1f s"
                          % (c["check"], c["readings"], c["positions"], c["max_abs_diff_mm"], extra, c["max_abs_correction_mm"], c["linuxcnc_seconds"]), flush=True)
                else:
                    failed += 1
                    print("FAIL %s: %s" % (c["check"], c["why"]), flush=True)
    total = time.time() - t_all
    if a.results:
        with open(a.results, "w") as f:
            json.dump({"checks": all_checks, "seconds": total, "tolerance_mm": TOLERANCE_MM}, f, indent=1)
    if failed and not a.keep:
        print("files of this run kept in %s" % base)
    elif not a.keep:
        shutil.rmtree(base, ignore_errors=True)
    print("total %.1f s" % total)
    print("linuxcnc: %d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
