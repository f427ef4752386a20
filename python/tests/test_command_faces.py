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
