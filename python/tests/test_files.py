"""Readers and writers of the file formats: what Python writes the command reads, and the reverse."""
import numpy as np
import pytest

import mtcal
from conftest import EXAMPLES, MACHINES, cli, cli_json

VMC = MACHINES / "vmc-3axis.yaml"


def test_errors_csv_round_trip(vmc, tmp_path):
    q = vmc.grid("X=-400:400:5,Y=-250:250:3,Z=-500:0:2")
    d = np.tile(np.array([1, -1, 0], dtype=np.int8), (len(q), 1))
    e = mtcal.evaluate(vmc, q, d)
    path = tmp_path / "out.csv"
    mtcal.write_errors_csv(str(path), vmc, q, e, d)
    back = mtcal.read_configurations(vmc, str(path))
    np.testing.assert_allclose(back.configs, q, rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(back.directions, d)
    table = mtcal.read_csv(str(path))
    assert table.columns == ["X", "Y", "Z", "dirX", "dirY", "dirZ", "dx", "dy", "dz", "rx", "ry", "rz"]
    np.testing.assert_allclose(table.values[:, 6:], e, rtol=1e-9, atol=1e-15)  # written with 10 digits
    # the command reads it as its --points
    ref = cli_json("eval", "-m", VMC, "--points", path)
    assert ref["configurations"] == len(q)


def test_error_map_csv_equals_mtcal_volumetric_out(vmc, tmp_path):
    grid = "X=-400:400:3,Y=-250:250:3,Z=-500:0:2"
    cli("volumetric", "-m", VMC, "--grid", grid, "--out", tmp_path / "cli.csv")
    mtcal.write_error_map_csv(str(tmp_path / "py.csv"), vmc, mtcal.error_map(vmc, grid=grid))
    assert (tmp_path / "py.csv").read_text() == (tmp_path / "cli.csv").read_text()


def test_csv_reader_errors_name_file_line_column(tmp_path):
    path = tmp_path / "t.csv"
    path.write_text("a,b\n1,2\n3,x\n")
    with pytest.raises(mtcal.InputError) as e:
        mtcal.read_csv(str(path))
    assert e.value.file == str(path) and e.value.line == 3 and e.value.field == "b"
    t = mtcal.parse_csv("a,b\n1,2\n3,4\n")
    np.testing.assert_array_equal(t["b"], [2, 4])
    assert t.lines == [2, 3]
    with pytest.raises(KeyError):
        t["c"]


def test_gcode_reader(tmp_path):
    p = mtcal.parse_gcode("G21 G90\nG0 X10 Y0\nG1 X20 F100\nG2 X30 Y10 I0 J10\nM30\n", "prog")
    assert p.moves == 3 and p.counts["lines"] == 5
    np.testing.assert_allclose(p.end_points[-1, :3], [30, 10, 0])
    with pytest.raises(mtcal.InputError) as e:
        mtcal.parse_gcode("G1 X10 F100\nG1 Yq\n", "prog", axes="XYZ")
    assert e.value.file == "prog" and e.value.line == 2
    # A word that is not simulated is a warning naming file, line, column and word (docs/gcode.md).
    w = mtcal.parse_gcode("G1 X10 F100\nG1 X20 Q5\n", "prog", axes="XYZ")
    assert w.warnings == ["prog:2: column 8: 'Q5' has no meaning in this block and is skipped"]
    assert w.counts["warnings"] == 1
    # A canned cycle expanded: G81 from Z10 with R2 to Z-3, G98 (LinuxCNC G-code reference).
    c = mtcal.parse_gcode("G0 X0 Y0 Z10\nG98 G81 X1 Y2 Z-3 R2 F100\nG80\n", "prog")
    np.testing.assert_allclose(c.end_points[:, :3], [[0, 0, 10], [1, 2, 10], [1, 2, 2], [1, 2, -3], [1, 2, 10]])
    assert c.counts["cycles"] == 1


def test_prediction_csv_equals_mtcal_predict_out(tmp_path):
    model = EXAMPLES / "prediction" / "yaqoob2017-model.yaml"
    points = EXAMPLES / "prediction" / "yaqoob2017-w2-points.csv"
    cli("predict", "--model", model, "--points", points, "--out", tmp_path / "p.csv")
    r = mtcal.predict(mtcal.read_prediction_model(str(model)), mtcal.read_prediction_points(str(points)))
    assert r.csv() == (tmp_path / "p.csv").read_text()


def test_text_written_atomically(tmp_path):
    mtcal.write_text_file(str(tmp_path / "a.txt"), "hello\n")
    assert (tmp_path / "a.txt").read_text() == "hello\n"
    with pytest.raises(mtcal.Error):
        mtcal.write_text_file(str(tmp_path / "missing" / "a.txt"), "x")


def test_diagonals_and_toolpath_csv_equal_the_commands(vmc, tmp_path):
    box = "X=-400:400,Y=-250:250,Z=-500:0"
    cli("diagonals", "-m", VMC, "--box", box, "--points", "5", "--out", tmp_path / "d-cli.csv")
    mtcal.diagonals(vmc, box, points=5).write_csv(str(tmp_path / "d-py.csv"))
    assert (tmp_path / "d-py.csv").read_text() == (tmp_path / "d-cli.csv").read_text()
    program = EXAMPLES / "gcode" / "pocket.nc"
    cli("toolpath", "-m", VMC, "--gcode", program, "--step", "5", "--origin", "Z=-400", "--out", tmp_path / "t-cli.csv")
    mtcal.toolpath(vmc, str(program), step=5, origin={"Z": -400}).write_csv(str(tmp_path / "t-py.csv"))
    assert (tmp_path / "t-py.csv").read_text() == (tmp_path / "t-cli.csv").read_text()


def test_separation_records():
    p = EXAMPLES / "prediction"
    obs = mtcal.read_position_observations(str(p / "yaqoob2017-table5_3.csv"))
    assert obs and obs[0].axis in "XYZ" and obs[0].line > 0
    assert mtcal.separate_position(obs).csv() == mtcal.separate_position(str(p / "yaqoob2017-table5_3.csv")).csv()
    rec = mtcal.read_dimension_table(str(p / "yaqoob2017-table5_6.csv"))
    assert {r.workpiece for r in rec} >= {"W2", "W5"}
    assert mtcal.separate_control(rec, "W2", "W5").csv() == \
        mtcal.separate_control(str(p / "yaqoob2017-table5_6.csv"), "W2", "W5").csv()
