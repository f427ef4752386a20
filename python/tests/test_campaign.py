"""The campaign bindings (issue 34) against the command on the same input: fit-motion, laser files,
ballbar parameters, Etalon files, the history store, acceptance tolerances, reports.

Every comparison is with the built command's --json (exact: both print the library's doubles at
full precision and json.loads reads them back bit for bit) or with the files it writes.
"""
import json
import os
import re
import shlex

import numpy as np
import pytest

import mtcal
from conftest import EXAMPLES, MACHINES, SHARED_DATA, assert_same, cli, cli_error, cli_json

INSTRUMENTS = EXAMPLES / "instruments"
LASER = INSTRUMENTS / "x-axis.rtl"
TRACE = INSTRUMENTS / "xy-ballbar.csv"
TOLERANCES = EXAMPLES / "acceptance" / "tolerances.yaml"
ISO_RUNS = sorted((SHARED_DATA / "iso230-2").glob("*")) if (SHARED_DATA / "iso230-2").is_dir() else []


def values_only(text):
    """A parameter file without its comments (they carry the command line)."""
    return [line for line in text.splitlines() if not line.lstrip().startswith("#")]


# ---------------------------------------------------------------- laser files and fit-motion

def test_read_laser_file_is_what_iso230_2_reads():
    lf = mtcal.read_laser_file(str(LASER))
    runs = mtcal.read_positioning(str(LASER))
    assert lf.kind == "linear" and lf.axis == "X" and lf.error_name == "EXX"
    np.testing.assert_array_equal(lf.runs.targets, runs.targets)
    np.testing.assert_array_equal(lf.runs.up, runs.up)
    np.testing.assert_array_equal(lf.runs.down, runs.down)
    # The header's fields are what the command puts into its JSON's metadata.
    meta = cli_json("iso230-2", LASER)["metadata"]
    assert lf.report_metadata["machine"] == "VMC 800 (example)"
    for k, v in lf.report_metadata.items():
        assert meta[k] == v, k


def test_read_laser_file_bad_input(tmp_path):
    bad = tmp_path / "bad.rtl"
    bad.write_text(LASER.read_text().replace("Target-count: 11", "Target-count: 12"))
    with pytest.raises(mtcal.InputError) as e:
        mtcal.read_laser_file(str(bad))
    assert e.value.file == str(bad) and e.value.line > 0
    assert str(e.value) in cli_error("fit-motion", bad)


@pytest.mark.parametrize("args,kw", [
    ([], {}),
    (["--form", "table"], {"form": "table"}),
    (["--form", "polynomial", "--degree", "2"], {"form": "polynomial", "degree": 2}),
])
def test_fit_motion_matches_cli(tmp_path, args, kw):
    out = tmp_path / "cli.yaml"
    ref = cli_json("fit-motion", LASER, *args, "--out", out)
    r = mtcal.fit_motion([str(LASER)], **kw)
    assert_same(r.to_dict(out=str(out)), ref, tol=0)
    mine = tmp_path / "py.yaml"
    r.write_parameters(str(mine))
    assert values_only(mine.read_text()) == values_only(out.read_text())
    # The file is one --params reads: the machine gets the fitted error.
    m = mtcal.Machine.load(str(INSTRUMENTS / "mill.yaml"), params=[str(mine)])
    assert any(k.startswith("EXX") and v != 0 for k, v in m.parameters.items())


def test_fit_motion_named_table_and_errors(tmp_path):
    ref = cli_json("fit-motion", f"EXX={LASER}")
    assert_same(mtcal.fit_motion([f"EXX={LASER}"]).to_dict(), ref, tol=0)
    with pytest.raises(mtcal.InputError) as e:  # the same error twice
        mtcal.fit_motion([str(LASER), f"EXX={LASER}"])
    assert str(e.value) == cli_error("fit-motion", LASER, f"EXX={LASER}")
    with pytest.raises(ValueError, match="degree"):
        mtcal.fit_motion([str(LASER)], degree=4)


# ---------------------------------------------------------------- ballbar -> parameters

def test_ballbar_parameters_match_cli(tmp_path):
    out = tmp_path / "cli.yaml"
    ref = cli_json("ballbar", TRACE, "--radius", 100, "--to-params", out)
    r = mtcal.ballbar(mtcal.read_ballbar_csv(str(TRACE)), radius=100)
    params = mtcal.ballbar_parameters(r)
    assert_same(mtcal.estimated_parameters_dict(params), ref["parameters"], tol=0)
    mine = tmp_path / "py.yaml"
    mtcal.write_parameters(str(mine), params, "ballbar parameters")
    assert values_only(mine.read_text()) == values_only(out.read_text())
    only = mtcal.ballbar_parameters(r, scale=False, backlash=False)
    ref_sq = cli_json("ballbar", TRACE, "--radius", 100, "--to-params", tmp_path / "sq.yaml", "--terms", "squareness")
    assert_same(mtcal.estimated_parameters_dict(only), ref_sq["parameters"], tol=0)
    assert [p.name for p in only] == ["EC0Y"]
    one = mtcal.ballbar(mtcal.read_ballbar_csv(str(TRACE)), radius=100, direction="cw")
    with pytest.raises(ValueError, match="both directions"):
        mtcal.ballbar_parameters(one)


# ---------------------------------------------------------------- Etalon files

def test_write_etalon_is_compensate_etalon_and_reads_back(tmp_path):
    # A small machine and few points: the residual the target computes is not what is tested here.
    vmc = mtcal.Machine.load(str(MACHINES / "vmc-3axis.yaml"))
    cli("compensate", "-m", MACHINES / "vmc-3axis.yaml", "--format", "etalon", "--points", 5, "--out", tmp_path / "cli")
    out = mtcal.write_etalon(vmc, str(tmp_path / "py"), points=5)
    for name in out.files:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes(), name
    path = str(tmp_path / "py" / "volcomp.etalon")
    blocks = mtcal.read_etalon(path)
    assert blocks and all(b.line > 0 for b in blocks)
    assert any(b.table for b in blocks) and any(not b.table for b in blocks)
    ref = cli_json("errors", "-m", MACHINES / "vmc-3axis.yaml", "--params", path)
    assert_same(vmc.with_parameter_file(path).to_dict(), ref, tol=0)
    with pytest.raises(mtcal.InputError) as e:
        mtcal.parse_etalon("[C0B]\nVALUE = x\n", "bad.etalon")
    assert e.value.file == "bad.etalon" and e.value.line == 2


# ---------------------------------------------------------------- acceptance and reports

def test_evaluate_tolerances_match_cli():
    runs = mtcal.read_positioning(str(LASER))
    e = mtcal.iso230_2(runs)
    ref = cli_json("iso230-2", LASER, "--tolerance-file", TOLERANCES, "--tolerance", "A=3", "--meta", "axis=X")
    v = mtcal.evaluate_tolerances(e, {"A": 3}, tolerance_file=str(TOLERANCES), metadata={"axis": "X"})
    assert_same(v.to_dict(), ref["tolerances"], tol=0)
    assert v.passed == (ref["tolerances"]["verdict"] == "pass")
    assert v.metadata == {"axis": "X"} and any("date" in s for s in v.missing_metadata)
    b = mtcal.ballbar(mtcal.read_ballbar_csv(str(TRACE)), radius=100)
    ref = cli_json("ballbar", TRACE, "--radius", 100, "--tolerance", "G=15", "--tolerance", "H=1")
    assert_same(mtcal.evaluate_tolerances(b, {"G": 15, "H": 1}).to_dict(), ref["tolerances"], tol=0)
    with pytest.raises(mtcal.InputError, match="VA"):
        mtcal.evaluate_tolerances(b, {"VA": 1})
    grid = "X=-400:400:3,Y=-250:250:3,Z=-500:0:3"
    ref = cli_json("volumetric", "-m", MACHINES / "vmc-3axis.yaml", "--grid", grid, "--tolerance-file", TOLERANCES,
                   "--tolerance", "VAz=5")
    vr = mtcal.volumetric(mtcal.Machine.load(str(MACHINES / "vmc-3axis.yaml")), grid=grid)
    assert_same(mtcal.evaluate_tolerances(vr, {"VAz": 5}, tolerance_file=str(TOLERANCES)).to_dict(), ref["tolerances"],
                tol=0)
    with pytest.raises(mtcal.InputError):
        mtcal.evaluate_tolerances(e, metadata={"colour": "red"})


def strip_volatile(html):
    """A report without what differs between two writers: the date line, the command and the note on static copies."""
    html = re.sub(r"<noscript>.*?</noscript>", "", html, flags=re.S)
    return html


@pytest.mark.parametrize("kind", ["iso230-2", "ballbar"])
def test_write_report_is_the_commands(tmp_path, kind, monkeypatch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1790000000")
    cli_report = tmp_path / "cli.html"
    if kind == "iso230-2":
        args = ["iso230-2", LASER, "--tolerance", "A=3", "--meta", "operator=A. Smith"]
        runs = mtcal.read_positioning(str(LASER))
        result, kw = mtcal.iso230_2(runs), {"runs": runs}
        acceptance = mtcal.evaluate_tolerances(result, {"A": 3}, metadata={"operator": "A. Smith"})
    else:
        args = ["ballbar", TRACE, "--radius", 100, "--tolerance", "G=15", "--meta", "operator=A. Smith"]
        result, kw = mtcal.ballbar(mtcal.read_ballbar_csv(str(TRACE)), radius=100), {}
        acceptance = mtcal.evaluate_tolerances(result, {"G": 15}, metadata={"operator": "A. Smith"})
    env = dict(os.environ, SOURCE_DATE_EPOCH="1790000000")
    import subprocess
    from conftest import MTCAL
    subprocess.run([MTCAL, *map(str, args), "--report", str(cli_report)], check=True, env=env, capture_output=True)
    mine = tmp_path / "py.html"
    command = shlex.join(["mtcal", *map(str, args), "--report", str(cli_report)])
    mtcal.write_report(result, str(mine), acceptance=acceptance, command=command, **kw)
    a, b = strip_volatile(mine.read_text()), strip_volatile(cli_report.read_text())
    assert a == b


def test_write_report_refuses_what_has_none(tmp_path, vmc):
    with pytest.raises(TypeError, match="result"):
        mtcal.write_report(mtcal.read_positioning(str(LASER)), str(tmp_path / "r.html"))
    with pytest.raises(ValueError, match="machine"):
        mtcal.write_report(mtcal.compensate(vmc, "linuxcnc", points=5), str(tmp_path / "r.html"))
    with pytest.raises(ValueError, match="runs"):
        mtcal.write_report(mtcal.iso230_2(mtcal.read_positioning(str(LASER))), str(tmp_path / "r.html"))
    assert not (tmp_path / "r.html").exists()


# ---------------------------------------------------------------- the history store

@pytest.fixture
def store_with_history(tmp_path):
    """A SQLite store with three ISO 230-2 results of one machine and a ballbar of another (by the command)."""
    db = tmp_path / "h.db"
    for i, date in enumerate(["2026-01-10", "2026-04-10", "2026-07-10"]):
        runs = tmp_path / f"x{i}.rtl"
        # Each run a little worse: the deviations scaled (the file's numbers, not the model's).
        text = LASER.read_text()
        runs.write_text(re.sub(r"(?m)^(\d+ [\d.]+ )(-?[\d.]+)$",
                               lambda m: m.group(1) + f"{float(m.group(2)) * (1 + 0.3 * i):.4f}", text))
        cli("iso230-2", runs, "--meta", f"date={date}", "--meta", "machine=VMC-1", f"--record={db}")
    cli("ballbar", TRACE, "--radius", 100, "--meta", "machine=VMC-2", "--meta", "date=2026-05-01", f"--record={db}")
    return db


def test_history_store_matches_cli(store_with_history, tmp_path):
    db = store_with_history
    st = mtcal.HistoryStore(str(db))
    assert st.machines() == ["VMC-1", "VMC-2"]
    ref = cli_json("history", "list", "--store", db)
    assert_same(st.list(), ref["records"], tol=0)
    assert_same(st.list(machine="VMC-1", from_="2026-03-01"), cli_json("history", "list", "--store", db, "--machine", "VMC-1", "--from", "2026-03-01")["records"], tol=0)
    ids = [r["id"] for r in ref["records"]]
    assert_same(st.show(ids[0]), cli_json("history", "show", ids[0], "--store", db), tol=0)
    assert_same(st.diff(ids[0], ids[2]), cli_json("history", "diff", ids[0], ids[2], "--store", db), tol=0)
    assert_same(st.diff(ids[0], ids[2], coverage_factor=3),
                cli_json("history", "diff", ids[0], ids[2], "--store", db, "--coverage-factor", 3), tol=0)
    st.add_event("VMC-1", "2026-05-01", "repair", "ballscrew")
    t = st.trend("VMC-1", figures=["A_X", "E_X"], tolerances={"A_X": 0.02})
    ref = cli_json("history", "trend", "--machine", "VMC-1", "--figure", "A_X", "--figure", "E_X",
                   "--tolerance", "A_X=0.02", "--store", db)
    assert_same(t.to_dict(), ref, tol=0)
    assert_same(st.trend("VMC-1", tolerance_file=str(TOLERANCES)).to_dict(),
                cli_json("history", "trend", "--machine", "VMC-1", "--tolerance-file", TOLERANCES, "--store", db), tol=0)
    assert_same(st.rank(tolerance_file=str(TOLERANCES)),
                cli_json("history", "rank", "--tolerance-file", TOLERANCES, "--store", db), tol=0)
    assert_same(st.rank(tolerances=["A_X=0.02"], by="time"),
                cli_json("history", "rank", "--tolerance", "A_X=0.02", "--by", "time", "--store", db), tol=0)
    assert [e["note"] for e in st.events("VMC-1")] == ["ballscrew"]
    with pytest.raises(mtcal.InputError, match="no records of machine 'VMC-9'"):
        st.trend("VMC-9")
    with pytest.raises(mtcal.InputError, match="crash, repair or other"):
        st.add_event("VMC-1", "2026-05-01", "flood")
    # export: the command's bytes; import_ into a new store: the same records.
    cli("history", "export", "--store", db, "--out", tmp_path / "cli.jsonl")
    st.export(str(tmp_path / "py.jsonl"))
    assert (tmp_path / "py.jsonl").read_bytes() == (tmp_path / "cli.jsonl").read_bytes()
    other = mtcal.HistoryStore(str(tmp_path / "copy.db"))
    s = other.import_(str(tmp_path / "py.jsonl"))
    # The files: the three ISO 230-2 runs' and the ballbar trace, which --record keeps (schema 6).
    assert s == {"store": other.description, "records_added": 4, "events_added": 1, "model_files_added": 4, "skipped": [],
                 "records": []}
    assert other.export() == st.export()
    # The trend report: the command's page (the date fixed, the note on copies left aside).
    os.environ["SOURCE_DATE_EPOCH"] = "1790000000"
    try:
        cli("history", "trend", "--machine", "VMC-1", "--figure", "A_X", "--store", db, "--report", tmp_path / "cli.html")
        mtcal.write_report(st.trend("VMC-1", figures=["A_X"]), str(tmp_path / "py.html"),
                           command=f"mtcal history trend --machine VMC-1 --figure A_X --store {db} --report {tmp_path / 'cli.html'}")
    finally:
        del os.environ["SOURCE_DATE_EPOCH"]
    assert strip_volatile((tmp_path / "py.html").read_text()) == strip_volatile((tmp_path / "cli.html").read_text())


def test_history_record_is_the_commands_record(tmp_path):
    """A result recorded from Python is the record `--record` makes of the same run: same content hash."""
    db_cli, db_py = tmp_path / "cli.db", tmp_path / "py.db"
    cli("iso230-2", LASER, "--meta", "date=2026-01-10", f"--record={db_cli}")
    runs = mtcal.read_positioning(str(LASER))
    result = mtcal.iso230_2(runs).to_dict()
    result["metadata"] = dict(runs.metadata)
    lf = mtcal.read_laser_file(str(LASER))
    meta = dict(lf.report_metadata, date="2026-01-10")
    result["warnings"] = list(runs.warnings)
    st = mtcal.HistoryStore(str(db_py))
    rid = st.record("iso230-2", result, metadata=meta, inputs=[str(LASER)])
    a = st.show(rid)
    b = mtcal.HistoryStore(str(db_cli)).list()[0]
    assert a["content_hash"] == b["content_hash"]
    assert st.record("iso230-2", result, metadata=meta, inputs=[str(LASER)]) == rid  # stored once
    with pytest.raises(mtcal.InputError, match="machine"):
        st.record("iso230-2", {"A": 1.0}, metadata={"date": "2026-01-01"})


def report_parts(html):
    """What a report shows of its result: the title, the plots' figures (their JSON) and every table
    after the summary block (which names the inputs and the command line, and differs by writer)."""
    title = re.search(r"<title>(.*?)</title>", html).group(1)
    plots = re.findall(r"<script>\(function\(\)\{var f=(.*?);Plotly\.newPlot", html, flags=re.S)
    body = html.split("</table>", 1)[1] if "</table>" in html else html
    tables = re.findall(r"<table.*?</table>", body, flags=re.S)
    return title, plots, tables


VMC_GRID = "X=-400:400:3,Y=-250:250:3,Z=-500:0:3"
VMC_AT = "X=100,Y=50,Z=-20"
VMC_BOX = "X=-400:400,Y=-250:250,Z=-500:0"


@pytest.mark.parametrize("kind", ["volumetric", "contributions", "diagonals", "effects", "compensate", "errors",
                                  "predict"])
def test_write_report_of_model_results_shows_what_the_command_shows(tmp_path, vmc, kind):
    """The reports of results computed from a machine model: the same title, plots and tables as the
    command's report of the same request (the summary block names the command's inputs)."""
    m = ["-m", MACHINES / "vmc-3axis.yaml"]
    kw = {}
    if kind == "volumetric":
        args, result = ["volumetric", *m, "--grid", VMC_GRID], mtcal.volumetric(vmc, grid=VMC_GRID)
    elif kind == "contributions":
        args, result = ["contributions", *m, "--at", VMC_AT], mtcal.contributions(vmc, at=vmc.parse_joints(VMC_AT))
    elif kind == "diagonals":
        args, result = ["diagonals", *m, "--box", VMC_BOX], mtcal.diagonals(vmc, VMC_BOX)
    elif kind == "effects":
        args, result = ["effects", *m, "--at", VMC_AT], mtcal.effects(vmc, vmc.parse_joints(VMC_AT))
    elif kind == "errors":
        args, result = ["errors", *m], vmc
    elif kind == "predict":
        model, points = EXAMPLES / "prediction" / "yaqoob2017-model.yaml", EXAMPLES / "prediction" / "yaqoob2017-w2-points.csv"
        args = ["predict", "--model", model, "--points", points]
        result = mtcal.predict(mtcal.read_prediction_model(str(model)), mtcal.read_prediction_points(str(points)))
    else:
        args = ["compensate", *m, "--format", "linuxcnc", "--points", 5, "--out", tmp_path / "comp"]
        result, kw = mtcal.compensate(vmc, "linuxcnc", points=5), {"machine": vmc}
    cli(*args, "--report", tmp_path / "cli.html")
    mtcal.write_report(result, str(tmp_path / "py.html"), **kw)
    mine, ref = report_parts((tmp_path / "py.html").read_text()), report_parts((tmp_path / "cli.html").read_text())
    assert mine[0] == ref[0]
    assert mine[1] == ref[1]
    if kind == "compensate":  # the command names the files in the folder it wrote (--out)
        ref = (ref[0], ref[1], [t.replace(f"<td>{tmp_path / 'comp'}/", "<td>") for t in ref[2]])
    assert mine[2] == ref[2]


def test_write_report_of_rotary_axis_is_the_commands(tmp_path, hu40t, monkeypatch):
    """rotary-axis --report: the same page as the command's (the date fixed, the note on copies aside)."""
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1790000000")
    sim = mtcal.simulate_sphere_probing(hu40t, axis="C", angles=np.radians(np.arange(0, 360, 45)), noise=5e-4, seed=3)
    contacts = tmp_path / "contacts.csv"
    sim.write_csv(str(contacts))
    args = ["rotary-axis", "--axis", "C", "--contacts", str(contacts), "--sphere-diameter", "30",
            "--stylus-diameter", "6", "--machine", str(MACHINES / "hu40t-wCBXfYZt.yaml"),
            "--report", str(tmp_path / "cli.html")]
    cli(*args)
    r = mtcal.rotary_axis(mtcal.read_contacts_csv(str(contacts), "C"), axis="C", machine=hu40t, sphere_diameter=30,
                          stylus_diameter=6)
    mtcal.write_report(r, str(tmp_path / "py.html"), machine=hu40t, command=shlex.join(["mtcal", *args]))
    assert strip_volatile((tmp_path / "py.html").read_text()) == strip_volatile((tmp_path / "cli.html").read_text())


def test_write_report_static_copies_through_the_browser_it_finds(tmp_path, monkeypatch):
    """pdf= and png_dir= reach the library's static copies (the command's --report-pdf/--report-png,
    tested in the browser by reports_in_browser): here a stand-in for Chromium named by
    MTCAL_CHROMIUM writes what the browser would, so that no browser runs in this test."""
    fake = tmp_path / "chromium"
    png = "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAEhQGAhKmMIQAAAABJRU5ErkJggg=="
    fake.write_text("#!/bin/sh\nfor a in \"$@\"; do case \"$a\" in\n"
                    "  --print-to-pdf=*) printf '%%PDF-1.4 stand-in\\n' > \"${a#--print-to-pdf=}\";;\n"
                    f"  --dump-dom) printf '<html><body><img class=\"plot-print\" src=\"data:image/png;base64,{png}\">"
                    f"<img class=\"plot-print\" src=\"data:image/png;base64,{png}\"></body></html>';;\n"
                    "esac; done\n")
    fake.chmod(0o755)
    monkeypatch.setenv("MTCAL_CHROMIUM", str(fake))
    r = mtcal.ballbar(mtcal.read_ballbar_csv(str(TRACE)), radius=100)
    mtcal.write_report(r, str(tmp_path / "b.html"), pdf=str(tmp_path / "b.pdf"), png_dir=str(tmp_path / "png"))
    assert (tmp_path / "b.pdf").read_bytes().startswith(b"%PDF-1.4 stand-in")
    assert sorted(p.name for p in (tmp_path / "png").iterdir()) == ["b-plot-1.png", "b-plot-2.png"]
    assert (tmp_path / "b.html").read_text().startswith("<!DOCTYPE html>")
    # No browser: nothing written, the library's message.
    monkeypatch.setenv("MTCAL_CHROMIUM", str(tmp_path / "none"))
    with pytest.raises(mtcal.Error, match="MTCAL_CHROMIUM"):
        mtcal.write_report(r, str(tmp_path / "c.html"), pdf=str(tmp_path / "c.pdf"))
    assert not (tmp_path / "c.html").exists()
    with pytest.raises(ValueError, match="same file"):
        mtcal.write_report(r, str(tmp_path / "d.html"), pdf=str(tmp_path / "d.html"))
