"""The last parity gaps (issue 34): compensate --gcode, the reports of eval, toolpath and regress, the
verdict on the volumetric report, history import of result files with the command told from their
keys, linuxcnc-probe. Each against the built command on the same input: its --json (exact), the
files it writes (byte for byte) and its reports (byte for byte, the date fixed by
SOURCE_DATE_EPOCH and the command line given as the command's, the note on static copies aside).
"""
import json
import os
import re
import shlex
import shutil
import subprocess

import numpy as np
import pytest

import mtcal
from conftest import EXAMPLES, MACHINES, MTCAL, assert_same, cli, cli_error, cli_json

VMC = MACHINES / "vmc-3axis.yaml"
POCKET = EXAMPLES / "gcode" / "pocket.nc"
ORIGIN = "X=-40,Y=-25,Z=-400"
ORIGIN_DICT = {"X": -40, "Y": -25, "Z": -400}
GRID = "X=-400:400:4,Y=-250:250:3,Z=-500:0:3"
INSTRUMENTS = EXAMPLES / "instruments"
LASER = INSTRUMENTS / "x-axis.rtl"
EPOCH = "1790000000"


def strip_volatile(html):
    """A report without the note on static copies (it names the command's options or Python's call)."""
    return re.sub(r"<noscript>.*?</noscript>", "", html, flags=re.S)


def command_report(tmp_path, args, name="cli.html"):
    """Runs mtcal ARGS --report FILE with the date fixed; returns the page and the command line it names."""
    out = tmp_path / name
    full = [*map(str, args), "--report", str(out)]
    p = subprocess.run([MTCAL, *full], capture_output=True, text=True, env=dict(os.environ, SOURCE_DATE_EPOCH=EPOCH))
    assert p.returncode in (0, 3) and out.exists(), p.stderr  # 3: a verdict of FAIL, the report written
    return out.read_text(), shlex.join(["mtcal", *full])


def python_report(tmp_path, result, command, **kw):
    os.environ["SOURCE_DATE_EPOCH"] = EPOCH
    try:
        mtcal.write_report(result, str(tmp_path / "py.html"), command=command, **kw)
    finally:
        del os.environ["SOURCE_DATE_EPOCH"]
    return (tmp_path / "py.html").read_text()


# ---------------------------------------------------------------- compensate --gcode

# A drilling cycle: one block, several moves, so the program is written anew (expanded).
CYCLE = "G21 G90 G17\nG0 X0 Y0 Z10\nG98 G81 X10 Y10 Z-2 R2 F150\nX60\nY60\nG80\nG0 Z20\nM30\n"


@pytest.mark.parametrize("case", ["in place", "options", "expanded"])
def test_correct_gcode_is_compensate_gcode(tmp_path, vmc, case):
    program, options, kw = POCKET, ["--origin", ORIGIN], {"origin": ORIGIN_DICT}
    if case == "options":
        options += ["--no-direction", "--linearise-arcs", "--decimals", "4", "--max-deviation", "0.002"]
        kw.update(directions=False, linearise_arcs=True, decimals=4, max_deviation=0.002)
    elif case == "expanded":
        program = tmp_path / "cycle.nc"
        program.write_text(CYCLE)
    out = tmp_path / "cli.nc"
    ref = cli_json("compensate", "-m", VMC, "--gcode", program, *options, "--out", out)
    assert ref["written"] == ("expanded" if case == "expanded" else "in_place")
    c = mtcal.correct_gcode(vmc, str(program), **kw)
    assert_same(c.to_dict(out=str(out)), ref, tol=0)
    assert c.text == out.read_text()
    assert c.expanded == (case == "expanded")
    c.write(str(tmp_path / "py.nc"))
    assert (tmp_path / "py.nc").read_bytes() == out.read_bytes()


def test_correct_gcode_refuses_as_the_command(tmp_path, vmc):
    bad = tmp_path / "bad.nc"
    bad.write_text("G1 X10 Yz\n")
    msg = cli_error("compensate", "-m", VMC, "--gcode", bad, "--out", tmp_path / "o.nc")
    with pytest.raises(mtcal.InputError) as e:
        mtcal.correct_gcode(vmc, str(bad))
    assert str(e.value) == msg and e.value.line == 1
    with pytest.raises(mtcal.InputError, match="max deviation"):
        mtcal.correct_gcode(vmc, str(POCKET), origin=ORIGIN_DICT, max_deviation=0)
    with pytest.raises(ValueError, match="origin"):
        mtcal.correct_gcode(vmc, str(POCKET), origin={"B": 1})


# ---------------------------------------------------------------- eval: summary, errors, report

def test_evaluate_configurations_is_eval(tmp_path, vmc):
    ref = cli_json("eval", "-m", VMC, "--grid", GRID, "--out", tmp_path / "cli.csv")
    r = mtcal.evaluate_configurations(vmc, grid=GRID)
    assert_same(r.to_dict(), {k: v for k, v in ref.items() if k != "out"}, tol=0)
    assert len(r) == ref["configurations"] == 4 * 3 * 3
    # The grid's order (last axis fastest) and the numbers of evaluate and of the command's --out.
    np.testing.assert_array_equal(r.configs, vmc.grid(GRID))
    np.testing.assert_allclose(r.errors, mtcal.evaluate(vmc, r.configs), rtol=0, atol=1e-12)
    mtcal.write_errors_csv(str(tmp_path / "py.csv"), vmc, r.configs, r.errors)
    assert (tmp_path / "py.csv").read_bytes() == (tmp_path / "cli.csv").read_bytes()
    # A points file (with directions), and the same configurations given as arrays.
    points = tmp_path / "points.csv"
    points.write_text("X,Y,Z,dirX,dirY,dirZ\n0,0,-100,1,1,-1\n100,50,-20,-1,1,1\n-300,200,-450,1,-1,-1\n")
    ref = cli_json("eval", "-m", VMC, "--points", points)
    p = mtcal.evaluate_configurations(vmc, points=str(points))
    assert_same(p.to_dict(), ref, tol=0)
    a = mtcal.evaluate_configurations(vmc, p.configs, p.directions)
    np.testing.assert_array_equal(a.errors, p.errors)
    np.testing.assert_array_equal(a.directions, p.directions)
    with pytest.raises(ValueError, match="exactly one"):
        mtcal.evaluate_configurations(vmc, p.configs, grid=GRID)


@pytest.mark.parametrize("source", ["grid", "points"])
def test_eval_report_is_the_commands(tmp_path, vmc, source):
    if source == "grid":
        html, command = command_report(tmp_path, ["eval", "-m", VMC, "--grid", GRID])
        r = mtcal.evaluate_configurations(vmc, grid=GRID)
    else:
        points = tmp_path / "points.csv"
        points.write_text("X,Y,Z\n0,0,-100\n100,50,-20\n-300,200,-450\n")
        html, command = command_report(tmp_path, ["eval", "-m", VMC, "--points", points])
        r = mtcal.evaluate_configurations(vmc, points=str(points))
    assert strip_volatile(python_report(tmp_path, r, command)) == strip_volatile(html)


# ---------------------------------------------------------------- toolpath and regress reports

def test_toolpath_report_is_the_commands(tmp_path, vmc):
    html, command = command_report(tmp_path, ["toolpath", "-m", VMC, "--gcode", POCKET, "--origin", ORIGIN,
                                              "--step", "1"])
    r = mtcal.toolpath(vmc, str(POCKET), step=1, origin=ORIGIN_DICT)
    assert strip_volatile(python_report(tmp_path, r, command)) == strip_volatile(html)
    # A program read whole first: the same page.
    p = mtcal.read_gcode(str(POCKET), axes="XYZ")
    r = mtcal.toolpath(vmc, p, step=1, origin=ORIGIN_DICT)
    assert strip_volatile(python_report(tmp_path, r, command)) == strip_volatile(html)


def test_regress_report_is_the_commands(tmp_path):
    data = EXAMPLES / "prediction" / "yaqoob2017-table5_8.csv"
    html, command = command_report(tmp_path, ["regress", data, "--x", "t", "--y", "e_splz"])
    t = mtcal.read_csv(str(data))
    r = mtcal.compare_models(t["t"], t["e_splz"], file=str(data), x_name="t", y_name="e_splz")
    assert strip_volatile(python_report(tmp_path, r, command)) == strip_volatile(html)
    assert_same(r.to_dict(), cli_json("regress", data, "--x", "t", "--y", "e_splz"))
    # Data given in memory name no file: the page says so by leaving it out.
    bare = mtcal.compare_models(t["t"], t["e_splz"])
    mtcal.write_report(bare, str(tmp_path / "bare.html"))
    assert "SHA-256" not in (tmp_path / "bare.html").read_text()


# ---------------------------------------------------------------- the verdict on the volumetric report

@pytest.mark.parametrize("limit", ["VA=1000", "VAz=0.5"])
def test_volumetric_report_verdict_is_the_commands(tmp_path, vmc, limit):
    html, command = command_report(tmp_path, ["volumetric", "-m", VMC, "--grid", GRID, "--tolerance", limit,
                                              "--meta", "operator=A. Smith"])
    r = mtcal.volumetric(vmc, grid=GRID)
    q, v = limit.split("=")
    verdict = mtcal.evaluate_tolerances(r, {q: float(v)}, metadata={"operator": "A. Smith"})
    mine = python_report(tmp_path, r, command, acceptance=verdict)
    assert strip_volatile(mine) == strip_volatile(html)
    assert ('class="verdict pass"' in mine) == verdict.passed
    with pytest.raises(ValueError, match="another test"):
        b = mtcal.ballbar(mtcal.read_ballbar_csv(str(INSTRUMENTS / "xy-ballbar.csv")), radius=100)
        mtcal.write_report(r, str(tmp_path / "x.html"), acceptance=mtcal.evaluate_tolerances(b, {"G": 15}))


# ---------------------------------------------------------------- history import with the command told

def test_history_import_of_result_files_is_the_commands(tmp_path):
    x = tmp_path / "x.json"
    x.write_text(cli("iso230-2", LASER, "--json").stdout)
    files = [x, LASER]
    meta = {"machine": "VMC-800", "date": "2026-10-01"}
    ref = cli_json("history", "import", *files, "--store", tmp_path / "cli.db", "--meta", "machine=VMC-800",
                   "--meta", "date=2026-10-01")
    st = mtcal.HistoryStore(str(tmp_path / "py.db"))
    got = st.import_([str(f) for f in files], metadata=meta)
    drop = {"store", "id", "recorded_at"}
    assert_same(got, ref, tol=0, skip=drop)
    assert got["records_added"] == 2 and [r["file"] for r in got["records"]] == [str(f) for f in files]
    cli_store = mtcal.HistoryStore(str(tmp_path / "cli.db"))
    # One date: the list's order among the two is by their (random) ids, so compare them by content.
    by_hash = lambda records: sorted(records, key=lambda r: r["content_hash"])  # noqa: E731
    assert_same(by_hash(st.list()), by_hash(cli_store.list()), tol=0, skip=drop)
    assert [r["command"] for r in st.list()] == ["iso230-2", "iso230-2"]
    # Again: both are duplicates, skipped and listed.
    again = st.import_(str(x), metadata=meta)
    assert again["records_added"] == 0 and "duplicate of record" in again["skipped"][0]
    # Keys no command documents: refused, nothing stored; named, the command is taken.
    what = tmp_path / "what.json"
    what.write_text('{"hello": 1, "machine": "M"}')
    msg = cli_error("history", "import", what, "--store", tmp_path / "c2.db")
    with pytest.raises(mtcal.InputError) as e:
        mtcal.HistoryStore(str(tmp_path / "p2.db")).import_(str(what))
    assert msg == str(e.value) + " (--command)"
    assert mtcal.HistoryStore(str(tmp_path / "p2.db")).list() == []
    nameless = json.loads(x.read_text())
    nameless.pop("machine", None)
    nameless.get("metadata", {}).pop("machine", None)
    y = tmp_path / "y.json"
    y.write_text(json.dumps(nameless))
    msg = cli_error("history", "import", y, "--store", tmp_path / "c3.db")
    with pytest.raises(mtcal.InputError, match="names no machine") as e:
        mtcal.HistoryStore(str(tmp_path / "p3.db")).import_(str(y))
    assert msg == str(e.value) + " (--meta machine=NAME)"


def test_record_keeps_the_model_files_as_the_command_does(tmp_path):
    """HistoryStore.record(machine_file=, parameter_files=) keeps the model's files as `--record` does
    (docs/history.md, "Model files"): the same inputs first, the same model_file lines in the export."""
    m = MACHINES / "vmc-3axis.yaml"
    params = tmp_path / "prior.yaml"
    params.write_text("mtcal_parameters: 1\nerrors:\n  EZY: {unit: um, argument_unit: m, polynomial: [0, 0, -30]}\n")
    grid = "X=-100:100:3,Y=0,Z=-100"
    cli_store = tmp_path / "cli.db"
    result = cli("volumetric", "-m", m, "--params", params, "--grid", grid, "--record", cli_store,
                 "--meta", "date=2026-11-01", "--json").stdout
    st = mtcal.HistoryStore(str(tmp_path / "py.db"))
    rid = st.record("volumetric", result, metadata={"date": "2026-11-01", "machine": "vmc-3axis"},
                    machine_file=str(m), parameter_files=[str(params)])
    ref = mtcal.HistoryStore(str(cli_store))
    lines = lambda store: [json.loads(x) for x in store.export().splitlines()]  # noqa: E731
    files = lambda store: [x for x in lines(store) if x["type"] == "model_file"]  # noqa: E731
    assert files(st) == files(ref) and sorted(f["kind"] for f in files(st)) == ["machine", "parameters"]
    assert next(f for f in files(st) if f["kind"] == "machine")["content"] == m.read_text()
    assert st.show(rid)["inputs"] == ref.show(ref.list()[0]["id"])["inputs"]
    # A file that is not UTF-8 is not kept: a warning, the record stored without it.
    latin = tmp_path / "latin1.yaml"
    latin.write_bytes(params.read_bytes() + b"# r\xe9glage\n")
    with pytest.warns(UserWarning, match="not UTF-8"):
        st.record("volumetric", result, metadata={"date": "2026-11-02", "machine": "vmc-3axis"},
                  machine_file=str(m), parameter_files=[str(latin)])
    assert len(files(st)) == 2


# ---------------------------------------------------------------- linuxcnc-probe

def test_linuxcnc_probe_is_the_commands(tmp_path):
    m = MACHINES / "rrttt-table-table.yaml"
    out = tmp_path / "cli"
    ref = cli_json("linuxcnc-probe", "-m", m, "--sphere", "120,-80,60", "--sphere", "0,0,40",
                   "--sphere-diameter", "30", "--stylus-diameter", "6", "--out", out)
    p = mtcal.linuxcnc_probe(mtcal.Machine.load(str(m)), [[120, -80, 60], [0, 0, 40]], sphere_diameter=30,
                             stylus_diameter=6)
    assert_same(p.to_dict(out=str(out)), ref, tol=0)
    assert sorted(p.files) == sorted(f.name for f in out.iterdir())
    p.write(str(tmp_path / "py"))
    for name in p.files:
        assert (tmp_path / "py" / name).read_bytes() == (out / name).read_bytes(), name
    with pytest.raises(mtcal.InputError, match="spheres"):
        mtcal.linuxcnc_probe(mtcal.Machine.load(str(m)), np.zeros((17, 3)))
    with pytest.raises(mtcal.InputError, match="diameter"):
        mtcal.linuxcnc_probe(mtcal.Machine.load(str(m)), [0, 0, 40], sphere_diameter=-1)


# ---------------------------------------------------------------- the setup a program runs under (issue 34)

DRILL = EXAMPLES / "gcode" / "drill-plate.nc"
TOOLS = EXAMPLES / "gcode" / "tools.tbl"


def setup_files(tmp_path, inches=False):
    """A LinuxCNC parameter file (G54 at 5221-5223, G28 at 5161-5163) and the tool table, in mm or inches."""
    k = 25.4 if inches else 1.0
    var = tmp_path / ("setup-in.var" if inches else "setup.var")
    var.write_text("".join(f"{n} {v / k:.10g}\n" for n, v in
                           [(5161, -10), (5162, 20), (5163, -60), (5221, -150), (5222, -100), (5223, -460)]))
    tools = TOOLS
    if inches:
        tools = tmp_path / "tools-in.tbl"
        tools.write_text("T1 P1 Z3.3464566929 D0.124\nT2 P2 Z4.4291338583 D0.3346\nT3 P3 Z3.7795275591 D0.3937\n")
    return var, tools


@pytest.mark.parametrize("units", ["mm", "in"])
def test_toolpath_and_correct_gcode_take_the_commands_setup(tmp_path, vmc, units):
    var, tools = setup_files(tmp_path, inches=units == "in")
    options = ["--tool-table", tools, "--tool-units", units, "--parameters", var, "--parameter-units", units,
               "--work-offset", "G54:Z=-450", "--work-offset", "G55:X=10", "--g28", "Z=-50", "--g30", "X=1,Y=2"]
    kw = dict(tool_table=str(tools), tool_units=units, parameters=str(var), parameter_units=units,
              work_offsets={"G54": {"Z": -450}, "G55": {"X": 10}}, g28={"Z": -50}, g30={"X": 1, "Y": 2})
    # toolpath: its --json and every point of --out, byte for byte.
    ref = cli_json("toolpath", "-m", VMC, "--gcode", DRILL, *options, "--step", "2", "--out", tmp_path / "cli.csv")
    r = mtcal.toolpath(vmc, str(DRILL), step=2, **kw)
    assert_same(r.to_dict(), {k: v for k, v in ref.items() if k != "out"}, tol=0)
    assert ref["interpreter"] == "mtcal" and ref["points"] > 100
    r.write_csv(str(tmp_path / "py.csv"))
    assert (tmp_path / "py.csv").read_bytes() == (tmp_path / "cli.csv").read_bytes()
    # Without the setup the tool lengths and offsets are missing: another result (or a refusal).
    try:
        bare = mtcal.toolpath(vmc, str(DRILL), step=2, travel_check=False).to_dict()
    except mtcal.InputError:
        bare = None
    assert bare != r.to_dict()
    # compensate --gcode: its --json and the corrected program, byte for byte (SOURCE_DATE_EPOCH as the reports).
    out = tmp_path / "cli.nc"
    env = dict(os.environ, SOURCE_DATE_EPOCH=EPOCH)
    p = subprocess.run([MTCAL, "compensate", "-m", str(VMC), "--gcode", str(DRILL), *map(str, options),
                        "--out", str(out), "--json"], capture_output=True, text=True, env=env)
    assert p.returncode == 0, p.stderr
    ref = json.loads(p.stdout)
    os.environ["SOURCE_DATE_EPOCH"] = EPOCH
    try:
        c = mtcal.correct_gcode(vmc, str(DRILL), **kw)
    finally:
        del os.environ["SOURCE_DATE_EPOCH"]
    assert_same(c.to_dict(out=str(out)), ref, tol=0)
    assert c.text.encode() == out.read_bytes() and c.expanded


@pytest.mark.skipif(not shutil.which("rs274"), reason="LinuxCNC's interpreter rs274 is not installed")
def test_toolpath_and_correct_gcode_through_linuxcncs_interpreter(tmp_path, vmc):
    # RS274NGC that mtcal's reader does not read (a parameter, an expression), a tool and a work offset.
    program = tmp_path / "param.ngc"
    program.write_text("G21 G90 G17\nT1 M6\nG43 H1\nG0 X0 Y0 Z20\n#1 = 10\nG1 Z-1 F100\nG1 X#1\n"
                       "G1 Y[#1 * 2]\nG0 Z20\nM30\n")
    options = ["--interpreter", "rs274", "--tool-table", TOOLS, "--work-offset", "G54:X=-150,Y=-100,Z=-450",
               "--rs274-timeout", "60"]
    kw = dict(interpreter="rs274", tool_table=str(TOOLS), work_offsets={"G54": {"X": -150, "Y": -100, "Z": -450}},
              rs274_timeout=60)
    ref = cli_json("toolpath", "-m", VMC, "--gcode", program, *options, "--step", "1")
    r = mtcal.toolpath(vmc, str(program), step=1, **kw)
    assert ref["interpreter"] == "rs274" and ref["points"] > 20
    assert_same(r.to_dict(), ref, tol=0)
    # auto: the program needs the interpreter, so it is the one that reads it.
    assert_same(mtcal.toolpath(vmc, str(program), step=1, **{**kw, "interpreter": "auto"}).to_dict(), ref, tol=0)
    out = tmp_path / "cli.nc"
    ref = cli_json("compensate", "-m", VMC, "--gcode", program, *options, "--out", out)
    c = mtcal.correct_gcode(vmc, str(program), **kw)
    assert_same(c.to_dict(out=str(out)), ref, tol=0)
    assert c.text.encode() == out.read_bytes()
    # The tool missing: the interpreter's message, where tools come from in the module's words.
    with pytest.raises(mtcal.InputError, match="not found in the tool table") as e:
        mtcal.toolpath(vmc, str(program), interpreter="rs274", work_offsets=kw["work_offsets"])
    assert "no tool table was given" in str(e.value) and e.value.line == 2


def test_program_setup_refusals(tmp_path, vmc):
    # An interpreter named must exist, as --rs274 (the module names its argument).
    msg = cli_error("toolpath", "-m", VMC, "--gcode", POCKET, "--rs274", tmp_path / "no-rs274")
    with pytest.raises(mtcal.InputError) as e:
        mtcal.toolpath(vmc, str(POCKET), rs274=str(tmp_path / "no-rs274"))
    assert msg == "--" + str(e.value)
    with pytest.raises(ValueError, match="work_offsets: expected a system"):
        mtcal.correct_gcode(vmc, str(POCKET), work_offsets={"G60": {"X": 1}})
    with pytest.raises(ValueError, match=r"work_offsets\[G55\]: axis 'B'"):
        mtcal.toolpath(vmc, str(POCKET), work_offsets={"G55": {"B": 1}})
    with pytest.raises(ValueError, match="g28: axis 'A'"):
        mtcal.toolpath(vmc, str(POCKET), g28={"A": 1})
    with pytest.raises(ValueError, match="tool_units: expected 'mm' or 'in'"):
        mtcal.toolpath(vmc, str(POCKET), tool_units="cm")
    with pytest.raises(mtcal.InputError, match="interpreter: expected auto, mtcal or rs274"):
        mtcal.toolpath(vmc, str(POCKET), interpreter="fanuc")
    with pytest.raises(ValueError, match="a GcodeProgram is read already"):
        mtcal.toolpath(vmc, mtcal.read_gcode(str(POCKET), axes="XYZ"), tool_table=str(TOOLS))
    # A bad tool table: the library's message and location, as the command's.
    bad = tmp_path / "bad.tbl"
    bad.write_text("T1 Zx\n")
    msg = cli_error("toolpath", "-m", VMC, "--gcode", DRILL, "--tool-table", bad)
    with pytest.raises(mtcal.InputError) as e:
        mtcal.toolpath(vmc, str(DRILL), tool_table=str(bad))
    assert str(e.value) == msg and e.value.line == 1


# ---------------------------------------------------------------- options that had no argument (issue 34)

def test_identify_require_fit_is_the_commands(tmp_path, hu40t):
    from test_probing_identification import EST, HU40T, simulate
    path = simulate(hu40t, tmp_path, 1e-3)
    args = ["identify", "-m", HU40T, "--measurements", path, "--estimate", ",".join(EST), "--scale-bar", "1:2:304.8",
            "--sigma-um", "0.01"]
    meas = mtcal.read_probing_plan(hu40t, str(path))
    kw = dict(scale_bars=["1:2:304.8"], sigma=1e-5)
    msg = cli_error(*args, "--require-fit")
    assert msg.endswith("; nothing written (--require-fit)"), msg
    with pytest.raises(mtcal.InputError) as e:
        mtcal.identify(hu40t, meas, EST, require_fit=True, **kw)
    # The command cuts a long message's middle on its one line ("…"); the module's is whole.
    head, _, tail = msg.partition("…")
    mine = str(e.value).replace("(require_fit)", "(--require-fit)")
    assert mine.startswith(head) and mine.endswith(tail) and "the fit is poor: sigma0" in mine
    # Without it: the command's warning, and the fit block of its --json.
    p = cli(*args, "--json")
    with pytest.warns(UserWarning) as w:
        r = mtcal.identify(hu40t, meas, EST, **kw)
    assert p.stderr.strip() == "mtcal: warning: " + str(w[0].message)
    ref = json.loads(p.stdout)
    assert ref["fit"]["poor"] and r.to_dict()["fit"] == ref["fit"]
    assert_same(r.to_dict(), ref)
    # A good fit: no warning, and require_fit changes nothing.
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        good = mtcal.identify(hu40t, meas, EST, scale_bars=["1:2:304.8"], require_fit=True)
    assert not good.to_dict()["fit"]["poor"]


def test_read_positioning_wrap_is_iso230_2_wrap(tmp_path):
    rng = np.random.default_rng(34)
    rows = ["target,run,direction,measured"]
    for run in (1, 2, 3, 4, 5):
        for direction in ("up", "down"):
            for t in (0, 90, 180, 270, 360):
                rows.append(f"{t},{run},{direction},{t + 1e-3 * np.sin(np.radians(t)) + 2e-4 * rng.normal():.6f}")
    path = tmp_path / "c-axis.csv"
    path.write_text("\n".join(rows) + "\n")
    ref = cli_json("iso230-2", path, "--unit", "deg", "--wrap", "360")
    runs = mtcal.read_positioning(str(path), unit="deg", wrap=360)
    assert len(runs.targets) == 4  # 0 and 360 pooled
    assert_same(mtcal.iso230_2(runs).to_dict(), {k: v for k, v in ref.items() if k not in ("metadata", "warnings")})
    with pytest.raises(ValueError, match="wrap"):
        mtcal.read_positioning(str(path), wrap=-1)


def test_rotary_axis_frame_and_probe_logs_are_the_commands(tmp_path, hu40t):
    from test_probing_identification import HU40T
    sim = mtcal.simulate_sphere_probing(hu40t, axis="C", angles=np.radians(np.arange(0, 360, 30)), noise=5e-4, seed=3)
    contacts = tmp_path / "contacts.csv"
    sim.write_csv(str(contacts))
    frame = "0.02,-0.01,0.5,1,2,3"
    ref = cli_json("rotary-axis", "--axis", "C", "--contacts", contacts, "--sphere-diameter", "30",
                   "--stylus-diameter", "6", "--machine", HU40T, "--frame", frame)
    r = mtcal.rotary_axis(mtcal.read_contacts_csv(str(contacts), "C"), axis="C", machine=hu40t, sphere_diameter=30,
                          stylus_diameter=6, frame=[float(v) for v in frame.split(",")])
    assert_same(r.to_dict(), ref)
    with pytest.raises(ValueError, match="frame"):
        mtcal.rotary_axis(mtcal.read_contacts_csv(str(contacts), "C"), axis="C", sphere_diameter=30, frame=[1, 2])
    # A LinuxCNC probe log (X Y Z A B C U V W a line): five touches of a sphere at each of six angles of C.
    lines = []
    for c in range(0, 360, 60):
        centre = np.array([100 * np.cos(np.radians(c)), 100 * np.sin(np.radians(c)), -100.0])
        for d in ([0, 0, 1], [1, 0, 1], [-1, 0, 1], [0, 1, 1], [0, -1, 1]):
            x, y, z = centre + 14.2 * np.asarray(d, float) / np.linalg.norm(d)
            lines.append(f"{x:.6f} {y:.6f} {z:.6f} 0 0 {c} 0 0 0")
    log = tmp_path / "probe.txt"
    log.write_text("\n".join(lines) + "\n")
    ref = cli_json("rotary-axis", "--axis", "C", "--contacts", log, "--contacts-dialect", "linuxcnc", "--machine",
                   HU40T, "--sphere-diameter", "25.4", "--stylus-diameter", "3")
    got = mtcal.read_contacts_log(hu40t, str(log), "C")
    assert len(got.angles_deg) == 30
    r = mtcal.rotary_axis(got, axis="C", machine=hu40t, sphere_diameter=25.4, stylus_diameter=3)
    assert_same(r.to_dict(), ref)
    with pytest.raises(ValueError, match="dialect"):
        mtcal.read_contacts_log(hu40t, str(log), "C", dialect="fanuc")


@pytest.mark.parametrize("target, option, kw", [("linuxcnc", ["--linuxcnc-type", "0"], {"linuxcnc_type": 0}),
                                                ("fanuc", ["--fanuc-unit", "0.0001"], {"fanuc_unit": 1e-4})])
def test_compensate_target_options_are_the_commands(tmp_path, vmc, target, option, kw):
    out = tmp_path / "cli"
    ref = cli_json("compensate", "-m", VMC, "--format", target, *option, "--residual-points", "3", "--out", out)
    t = mtcal.compensate(vmc, target, residual_points=3, **kw)
    default = mtcal.compensate(vmc, target, residual_points=3)
    assert sorted(t.files) == sorted(f.name for f in out.iterdir()) == sorted(ref["files"])
    for name, text in t.files.items():
        assert text == (out / name).read_text(), name
    assert t.files != default.files  # the option changes what is written
    with pytest.raises(ValueError, match=list(kw)[0]):
        mtcal.compensate(vmc, target, **{list(kw)[0]: 7})


def test_contributions_target_va_is_the_commands(vmc):
    ref = cli_json("contributions", "-m", VMC, "--grid", GRID, "--target-va", "5um")
    r = mtcal.contributions(vmc, grid=GRID, target_va=0.005)
    assert "correction_sequence" in ref
    assert_same(r.to_dict(), ref)
    with pytest.raises(ValueError, match="target_va"):
        mtcal.contributions(vmc, at=vmc.parse_joints("X=0"), target_va=0.005)


def test_set_precision_is_the_commands_precision(tmp_path, vmc):
    assert mtcal.precision() == 10
    cli("eval", "-m", VMC, "--grid", GRID, "--out", tmp_path / "cli.csv", "--precision", "17")
    r = mtcal.evaluate_configurations(vmc, grid=GRID)
    mtcal.set_precision(17)
    try:
        assert mtcal.precision() == 17
        mtcal.write_errors_csv(str(tmp_path / "py.csv"), vmc, r.configs, r.errors)
    finally:
        mtcal.set_precision(10)
    assert (tmp_path / "py.csv").read_bytes() == (tmp_path / "cli.csv").read_bytes()
    with pytest.raises(mtcal.InputError, match="precision"):
        mtcal.set_precision(18)
