#!/usr/bin/env python3
"""Issue 16, item 6: every option that takes a value, given a bad value, is refused with one line
on stderr that names that option (or the file it names), a non-zero exit and no output file.

The options are read from each command's --help (and the global ones from mtcal --help), so a
new option is covered without editing this file; only the valid starting invocation of each
command (BASES) is written here, and a command without one fails the test. Each bad value is
given as --option=VALUE (so that '-inf' is not read as an option) to the first base invocation
that has the option, replacing its value there, or appended to the first one.

Bad values, by the type the help shows:
  numbers (FLOAT, INT, UINT ...): '1x', 'nan', '-inf', '1e999' and, for whole numbers, '2.5';
  a choice TEXT:{a,b}: 'bogus';
  other TEXT: '<fixtures>/notadir/b@d' below a regular file (a missing file, an output that cannot
  be made, even by an option that makes missing folders such as --report-png, a malformed
  specification);
  a TEXT whose value in the base invocation has numbers: each number replaced by 1e308 (and by
  nan): the command may accept it (a huge but valid value), but if it fails, the message must
  name the option (the audit found '--centre Z=1e308' blamed on '--at').
Checks per case: exit status not 0; stderr, warnings aside, is one line 'mtcal: error: ...' that
contains the option's name or the whole bad value (a file name), and names no other option of
the command unless it names this one too; nothing is left in the working folder.

Needs MTCAL and EXAMPLES. Prints one line per failure and a summary; exit 1 on any failure.

Three ways to run it (about 1,100 mtcal runs in all):
  test_option_errors.py              makes the fixtures in a temporary folder and checks every case;
  test_option_errors.py --setup DIR  makes the fixtures in DIR, reads every --help, runs every base
                                     invocation and writes the cases to DIR/cases.json (ctest
                                     option_errors_cli_setup, the fixture of the shards);
  test_option_errors.py --check DIR  checks the cases of DIR/cases.json.
With MTCAL_TEST_SHARD=K/N a run checks every N-th case from the K-th on, in one fixed order, so that
N shards (ctest option_errors_cli_KofN) check every case exactly once; the fixtures, the help texts
and the base invocations are made and run once, by the setup, not once per shard.
"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

MTCAL = os.environ["MTCAL"]
E = os.environ["EXAMPLES"]
M3 = f"{E}/machines/vmc-3axis.yaml"
M5 = f"{E}/machines/hu40t-wCBXfYZt.yaml"
MR = f"{E}/machines/rrttt-table-table.yaml"
PLAN = f"{E}/plans/hu40t-samba-tango.csv"
EST = "EC0Y,EB0Z,EA0Z,EX0C,EY0C,EA0C,EB0C,EX0B,EZ0B,EA0B,EC0B,EXX.1,EYY.1,EZZ.1"
P = f"{E}/prediction"
GRID = "X=-400:400:5,Y=-250:250:5,Z=-500:0:5"

MODE, SETUP_DIR = (sys.argv[1], sys.argv[2]) if len(sys.argv) == 3 else (None, None)
if MODE not in (None, "--setup", "--check") or (MODE is None) != (len(sys.argv) == 1):
    sys.exit("usage: test_option_errors.py [--setup DIR | --check DIR]")
if MODE is None:
    fix = tempfile.mkdtemp(prefix="mtcal-opt-fix-")
else:
    fix = os.path.join(os.path.abspath(SETUP_DIR), "fix")
work = tempfile.mkdtemp(prefix="mtcal-opt-work-")
BAD_PATH = f"{fix}/notadir/b@d"


def make_fixtures():
    """The files the base invocations read, in fix."""
    # A path no command can read or make: its parent is a regular file.
    with open(f"{fix}/notadir", "w") as f:
        f.write("a regular file\n")

    # Inputs the commands read that examples/ does not have, made by mtcal itself.
    with open(f"{fix}/points.csv", "w") as f:
        f.write("X,Y,Z\n0,0,0\n100,50,-20\n")
    for args in (
        ["probe-sim", "-m", M5, "--axis", "C", "--angles", "0:350:36", "--noise", "0.001", "--out",
         f"{fix}/contacts.csv"],
        ["simulate", "-m", M5, "--plan", PLAN, "--artefact-error-um", "50", "--scale-bar", "1:2:304.8", "--out",
         f"{fix}/meas.csv"],
        ["ballbar", "--predict", "-m", M3, "--plane", "XY", "--radius", "100", "--centre", "Z=-200", "--out",
         f"{fix}/trace.csv"],
    ):
        subprocess.run([MTCAL, *args], check=True, stdout=subprocess.DEVNULL)

    # A drawn truth and what identify printed, for campaign (docs/campaign.md).
    subprocess.run([MTCAL, "errors", "-m", M5, "--draw", "3", "--draw-only", "EX0C,EY0C", "--out",
                    f"{fix}/truth.yaml"], check=True, stdout=subprocess.DEVNULL)
    with open(f"{fix}/id.json", "w") as f:
        subprocess.run([MTCAL, "identify", "-m", M5, "--measurements", f"{fix}/meas.csv", "--estimate", EST,
                        "--scale-bar", "1:2:304.8", "--json"], check=True, stdout=f)

    # A probing plan and its program (mtcal plan), and a probe log in LinuxCNC's form made from the
    # program: each G38.2 move's end, the rotary axes where the program left them. Those points lie on
    # a sphere about each ball (its radius plus the overshoot), so probe-log reads and fits them.
    subprocess.run([MTCAL, "plan", "-m", MR, "--artefact", f"{E}/plans/rrttt-viprey-sphere.csv", "--estimate",
                    "EY0C,EZ0A", "--poses", "12", "--out", f"{fix}/plan.csv", "--gcode", f"{fix}/probe.ngc"],
                   check=True, stdout=subprocess.DEVNULL)
    at, log = dict.fromkeys("XYZABC", 0.0), []
    for line in open(f"{fix}/probe.ngc"):
        line = line.split("(")[0].strip()
        words = {m.group(1): float(m.group(2)) for m in re.finditer(r"([XYZABC])(-?[\d.]+)", line)}
        if line.startswith("G38.2"):
            p = {**at, **words}
            log.append(" ".join(f"{p[a]:.6f}" for a in "XYZABC") + " 0 0 0")
        at.update(words)
    with open(f"{fix}/probe-log.txt", "w") as f:
        f.write("\n".join(log) + "\n")


# serve --add-user reads the new user's password from here.
os.environ["MTCAL_PASSWORD"] = "a-long-enough-test-password"

# A valid invocation of each command, writing its outputs into the working folder (relative
# names). Several for a command whose options belong to different modes.
BASES = {
    # serve's base saves a user and exits (a server would not); its serving options are refused
    # with --add-user, which names them.
    "serve": [["--store", "s.db", "--add-user", "ann", "--role", "admin"]],
    "eval": [["-m", M3, "--grid", "X=-100:100:3,Y=-50:50:3", "--out", "o.csv", "--report", "o.html",
              "--meta", "machine=m1"],
             ["-m", M3, "--at", "X=100,Y=50,Z=-20"],
             ["-m", M3, "--points", f"{fix}/points.csv"]],
    "errors": [["-m", M3, "--report", "o.html", "--set", "EXX.1=5ppm", "--tool-length", "100"],
               ["-m", M5, "--draw", "7", "--draw-only", "EX0C,EY0C", "--draw-table", "ECC", "--draw-table-points", "9",
                "--draw-length-um", "5:50", "--draw-angle-urad", "10:100", "--out", "t.yaml", "--out-nominal",
                "n.yaml"]],
    "effects": [["-m", M5, "--at", "X=100,B=30", "--report", "o.html", "--errors", "EXX,EC0Y"]],
    "rotary-axis": [["--axis", "C", "--contacts", f"{fix}/contacts.csv", "--sphere-diameter", "30",
                     "--stylus-diameter", "6", "--machine", M5, "--out", "o.yaml", "--report", "o.html",
                     "--frame", "0,0,0"]],
    "probe-sim": [["-m", M5, "--axis", "C", "--angles", "0:350:36", "--hold", "B=0", "--sphere", "150,0,50",
                   "--out", "o.csv"]],
    "linuxcnc-probe": [["-m", M5, "--sphere", "150,0,50", "--sphere", "0,0,0", "--sphere-diameter", "25",
                        "--stylus-diameter", "3", "--out", "o"]],
    "iso230-2": [[f"{E}/data/iso230-2-x-axis.csv", "--report", "o.html", "--tolerance", "A=10"]],
    "ballbar": [[f"{fix}/trace.csv", "--radius", "100", "--report", "o.html", "--to-params", "o.yaml",
                 "--tolerance", "G=10"],
                ["--predict", "-m", M3, "--radius", "100", "--centre", "Z=-200", "--out", "o.csv"]],
    "fit-motion": [[f"{E}/instruments/x-axis.rtl", "--out", "o.yaml"]],
    "compare": [[f"{E}/data/mohammed2019-ballbar-vs-samba.csv", "--report", "o.html"]],
    "volumetric": [["-m", M3, "--grid", GRID, "--box", "X=-200:200,Y=-125:125", "--box-scan", "3", "--centre",
                    "X=0,Y=0,Z=-250", "--out", "o.csv", "--report", "o.html"]],
    "contributions": [["-m", M3, "--grid", GRID, "--report", "o.html"],
                      ["-m", M3, "--at", "X=100,Y=50,Z=-20"],
                      ["-m", M3, "--pair", "X=0,Y=0,Z=0;X=300,Y=200,Z=-300"]],
    "diagonals": [["-m", M3, "--box", "X=-400:400,Y=-250:250,Z=-500:0", "--points", "11", "--out", "o.csv",
                   "--report", "o.html"]],
    "toolpath": [["-m", M3, "--gcode", f"{E}/gcode/pocket.nc", "--origin", "X=-40,Y=-25,Z=-400", "--step", "0.5",
                  "--out", "o.csv", "--report", "o.html"]],
    "compensate": [["-m", M3, "--format", "linuxcnc", "--points", "11", "--range", "X=-300:300",
                    "--reference", "Z=-250", "--out", "odir", "--report", "o.html"],
                   ["-m", M3, "--gcode", f"{E}/gcode/pocket.nc", "--origin", "X=-40,Y=-25,Z=-400", "--out",
                    "o.nc"]],
    "regress": [[f"{P}/yaqoob2017-table5_8.csv", "--x", "t", "--y", "e_splz", "--report", "o.html"]],
    "predict": [["--model", f"{P}/yaqoob2017-model.yaml", "--points", f"{P}/yaqoob2017-w2-points.csv", "--out",
                 "o.csv", "--compensation", "c.csv", "--report", "o.html"]],
    "separate": [["position", f"{P}/yaqoob2017-table5_3.csv", "--out", "o.csv"],
                 ["control", f"{P}/yaqoob2017-table5_6.csv", "--a", "W2", "--b", "W5", "--model",
                  f"{P}/yaqoob2017-model.yaml", "--out", "o.csv"]],
    "process-error": [["--feed", "100,200,400"]],
    "simulate": [["-m", M5, "--plan", PLAN, "--artefact-error-um", "50", "--scale-bar", "1:2:304.8", "--out",
                  "o.csv"]],
    "identify": [["-m", M5, "--measurements", f"{fix}/meas.csv", "--estimate", EST, "--scale-bar", "1:2:304.8",
                  "--out", "o.yaml", "--report", "o.html"]],
    "identifiability": [["-m", M5, "--plan", PLAN, "--estimate", "EX0C,EX0B,EX0X,EXt"]],
    "plan": [["-m", MR, "--artefact", f"{E}/plans/rrttt-viprey-sphere.csv", "--estimate", "EY0C,EZ0A", "--poses",
              "12", "--out", "o.csv", "--gcode", "o.ngc"],
             # --ballbar and --laser: candidate circles and lines only, one pose.
             ["-m", M3, "--estimate", "EC0Y", "--ballbar", "150", "--laser", "X", "--poses", "1", "--out", "o.csv"]],
    "probe-log": [["-m", MR, "--plan", f"{fix}/plan.csv", "--log", f"{fix}/probe-log.txt", "--out", "o.csv"]],
    "pose-check": [["-m", M5, "--poses", f"{E}/campaign/hu40t-reached-nominal.csv"]],
    "campaign": [["-m", M5, "--before", f"{fix}/meas.csv", "--after", f"{fix}/meas.csv", "--identified",
                  f"{fix}/id.json", "--truth", f"{fix}/truth.yaml", "--poses-before",
                  f"{E}/campaign/hu40t-reached-nominal.csv", "--poses-after", f"{E}/campaign/hu40t-reached-nominal.csv",
                  "--reference", "identified", "--noise-um", "0.5", "--report", "o.html"]],
    # The history's own commands are subcommands (list, show ...; tests/cli/test_history.sh): the
    # group's options (--precision) checked through one of them.
    "history": [["list", "--store", "h.db"]],
}

# Options whose every value is valid text (none so far): a bad value cannot fail.
# plan --log-name is a file name on the controller's machine (written into the program's PROBEOPEN
# comment, never opened by mtcal): any path text is valid there; only an empty name, parentheses
# and line breaks are refused. serve --add-user is a user name (an e-mail address, say): '/' and '@'
# are valid in it; the server refuses an empty or unprintable one.
FREE_TEXT = {"--log-name", "--add-user"}


def help_text(*cmd):
    return subprocess.run([MTCAL, *cmd, "--help"], capture_output=True, text=True, check=True).stdout


def parse_help(text):
    """[(name, type)] of the options and positionals that take a value; positionals' names have no '--'."""
    out, section = [], None
    for line in text.splitlines():
        if re.match(r"^[A-Z][A-Za-z ]*:$", line):
            section = line[:-1]
            continue
        if section not in ("Options", "Positionals") or not line.startswith("  ") or line.startswith("   "):
            continue
        left = re.split(r"\s{2,}", line.strip())[0].split(" ")
        names = left[0].split(",")
        long = [n for n in names if n.startswith("--")]
        name = long[0] if long else names[0]
        if name in ("--help", "--version"):
            continue
        kind = left[1] if len(left) > 1 and re.match(r"^(TEXT|FLOAT|INT|UINT|BOOLEAN)", left[1]) else None
        if section == "Positionals":
            out.append((name, kind or "TEXT"))
        elif kind:
            out.append((name, kind))
    return out


def commands():
    text = help_text()
    subs = re.search(r"^Subcommands:\n(.*?)\n\n", text, re.S | re.M).group(1)
    return [line.split()[0] for line in subs.splitlines() if re.match(r"^  \S", line)], parse_help(text)


def bad_values(kind, base_value):
    if re.match(r"^(FLOAT|INT|UINT)", kind):
        vals = ["1x", "nan", "-inf", "1e999"]
        if not kind.startswith("FLOAT"):
            vals.append("2.5")
        return [(v, True) for v in vals]
    choice = re.search(r"\{([^}]*)\}", kind)
    if choice:
        return [("bogus", True)]
    vals = [(BAD_PATH, True)]
    # Numbers in a specification (not in a file name): each one, on its own, made huge or nan.
    number = r"(?<![\w.])-?\d+(\.\d+)?([eE][-+]?\d+)?"
    if base_value and "/" not in base_value and re.search(number, base_value):
        for huge in ("1e308", "nan"):
            vals.append((re.sub(number, huge, base_value), False))  # may be accepted; if refused, named
    return vals


passed, failed = 0, []


def check(cmd, name, value, must_fail, argv, other_options):
    global passed
    for f in os.listdir(work):
        shutil.rmtree(os.path.join(work, f), ignore_errors=True) if os.path.isdir(os.path.join(work, f)) else \
            os.remove(os.path.join(work, f))
    try:
        r = subprocess.run([MTCAL, *argv], cwd=work, capture_output=True, text=True, errors="replace", timeout=120)
    except subprocess.TimeoutExpired:
        failed.append(f"{cmd} {name}={value!r}: no answer in 120 s")
        return
    what = f"{cmd} {name}={value!r}"
    left = sorted(os.listdir(work))
    if r.returncode == 0:
        if must_fail and name not in FREE_TEXT:
            failed.append(f"{what}: exit 0")
        else:
            passed += 1  # a huge but valid value, accepted
        return
    err = [line for line in r.stderr.splitlines() if not line.startswith("mtcal: warning: ")]
    problems = []
    if len(err) != 1 or not err[0].startswith("mtcal: error: "):
        problems.append(f"stderr is not one error line: {r.stderr[:300]!r}")
    else:
        msg = err[0]
        named = (name.startswith("--") and re.search(re.escape(name) + r"(?![\w-])", msg)) or \
                value in msg
        if not named:
            problems.append(f"the message names neither {name} nor the value: {msg[:300]!r}")
        else:
            wrong = [o for o in other_options if o != name and re.search(re.escape(o) + r"(?![\w-])", msg)]
            if wrong and not (name.startswith("--") and re.search(re.escape(name) + r"(?![\w-])", msg)):
                problems.append(f"the message blames {wrong}: {msg[:300]!r}")
    if left:
        problems.append(f"left {left} in the working folder")
    if problems:
        failed.append(f"{what}: " + "; ".join(problems))
    else:
        passed += 1


def cases_of(cmd, options, bases):
    """Every (name, value, must_fail, argv) case of one command, without running any."""
    out = []
    positionals = [n for n, _ in options if not n.startswith("--")]
    for name, kind in options:
        if name.startswith("--"):
            base, at = bases[0], None
            for b in bases:
                for i, a in enumerate(b):
                    if a == name or a in short_names.get((cmd, name), ()):
                        base, at = b, i
                        break
                if at is not None:
                    break
            base_value = base[at + 1] if at is not None else None
            for value, must_fail in bad_values(kind, base_value):
                argv = list(base)
                if at is not None:
                    argv[at:at + 2] = [f"{name}={value}"]
                else:
                    argv.append(f"{name}={value}")
                out.append((name, value, must_fail, [cmd, *argv]))
        else:
            # Positional: the n-th non-option word of the base invocation.
            index = positionals.index(name)
            base = bases[0]
            words = [i for i, a in enumerate(base) if not a.startswith("-") and (i == 0 or not base[i - 1].startswith("-")
                                                                               or base[i - 1] in flags.get(cmd, ()))]
            if index >= len(words):
                continue
            for value, must_fail in bad_values(kind, None):
                argv = list(base)
                argv[words[index]] = value
                out.append((name, value, must_fail, [cmd, *argv]))
    return out


def all_cases():
    """Every case of every command, in one fixed order: [cmd, name, value, must_fail, argv, other options].
    Reads the commands and their options from --help; a command without a base invocation is a failure."""
    out = []
    cmds, global_options = commands()
    for cmd in cmds:
        text = help_text(cmd)
        for line in text.splitlines():
            m = re.match(r"^  (-\w),(--[\w-]+)", line)
            if m:
                short_names[(cmd, m.group(2))] = (m.group(1),)
            m = re.match(r"^  (--[\w-]+)\s{2,}", line)
            if m:
                flags.setdefault(cmd, set()).add(m.group(1))
        if cmd not in BASES:
            failed.append(f"{cmd}: no base invocation in tests/cli/test_option_errors.py (add one)")
            continue
        options = parse_help(text)
        others = [n for n, _ in options if n.startswith("--")]
        out += [[cmd, name, value, must_fail, argv, others]
                for name, value, must_fail, argv in cases_of(cmd, options, BASES[cmd])]
    # The global options (limits, --max-input-size), given before the command's name.
    for name, kind in global_options:
        for value, must_fail in bad_values(kind, None):
            out.append(["mtcal", name, value, must_fail, [f"{name}={value}", "errors", "-m", M3],
                        [n for n, _ in global_options]])
    return out


def broken_bases(cmds):
    """The base invocations must work, or every case would fail for the wrong reason: the commands
    whose base invocation fails (each a failure)."""
    broken = set()
    for cmd in cmds:
        for b in BASES[cmd]:
            r = subprocess.run([MTCAL, cmd, *b], cwd=work, capture_output=True, text=True, timeout=300)
            if r.returncode != 0:
                failed.append(f"{cmd}: the base invocation fails: {r.stderr.strip()[:300]}")
                broken.add(cmd)
                break
    return broken


short_names, flags = {}, {}
if MODE == "--check":
    try:
        with open(os.path.join(SETUP_DIR, "cases.json")) as f:
            cases = json.load(f)
    except OSError as e:
        shutil.rmtree(work, ignore_errors=True)
        sys.exit(f"FAIL: no case list ({e}): the test option_errors_cli_setup writes it "
                 f"(test_option_errors.py --setup {SETUP_DIR})")
else:
    if MODE == "--setup":
        shutil.rmtree(SETUP_DIR, ignore_errors=True)
        os.makedirs(fix)
    make_fixtures()
    cases = all_cases()
    broken = broken_bases(sorted({c[0] for c in cases if c[0] in BASES}))
    cases = [c for c in cases if c[0] not in broken]
    if MODE == "--setup":
        with open(os.path.join(SETUP_DIR, "cases.json"), "w") as f:
            json.dump(cases, f)
        for f in failed:
            print("FAIL:", f)
        print(f"{len(cases)} cases written to {SETUP_DIR}/cases.json; the fixtures and every base invocation made: "
              f"{len(failed)} failed")
        shutil.rmtree(work, ignore_errors=True)
        sys.exit(1 if failed else 0)

# MTCAL_TEST_SHARD=K/N (ctest runs option_errors_cli_1of4 ... in parallel): this run checks every
# N-th case from the K-th on, in the fixed order, so the N shards together check every case exactly
# once. Without it, one run checks all.
_shard = os.environ.get("MTCAL_TEST_SHARD", "1/1")
SHARD_K, SHARD_N = (int(x) for x in _shard.split("/"))
assert 1 <= SHARD_K <= SHARD_N, f"MTCAL_TEST_SHARD={_shard}: expected K/N with 1 <= K <= N"
slowest = []
for cmd, name, value, must_fail, argv, others in cases[SHARD_K - 1::SHARD_N]:
    start = time.monotonic()
    check(cmd, name, value, must_fail, argv, others)
    slowest.append((time.monotonic() - start, f"{cmd} {name}={value!r}"))

for f in failed:
    print("FAIL:", f)
print("slowest cases:", "; ".join(f"{what} {s:.2f} s" for s, what in sorted(slowest, reverse=True)[:5]))
print(f"{passed} passed, {len(failed)} failed (shard {SHARD_K} of {SHARD_N}: {len(cases)} cases in all)")
if MODE is None:
    shutil.rmtree(fix, ignore_errors=True)
shutil.rmtree(work, ignore_errors=True)
sys.exit(1 if failed else 0)
