"""Volumetric accuracy, contributions, histograms, diagonals, tool paths, ISO 230-2, ISO 230-4, method
comparison: to_dict() equals the command's --json."""
import itertools
import math

import numpy as np
import pytest

import mtcal
from conftest import EXAMPLES, MACHINES, SHARED_DATA, TIMING_KEYS, assert_same, cli, cli_error, cli_json

VMC = MACHINES / "vmc-3axis.yaml"
HU40T = MACHINES / "hu40t-wCBXfYZt.yaml"
GRID = "X=-400:400:9,Y=-250:250:7,Z=-500:0:6"


def test_volumetric_equals_mtcal_volumetric(vmc):
    ref = cli_json("volumetric", "-m", VMC, "--grid", GRID, "--histogram", "20", "--box", "X=0:400,Y=0:250",
                   "--group-angle", "0.2")
    r = mtcal.volumetric(vmc, grid=GRID, histogram=20, box="X=0:400,Y=0:250", grouping={"angle": 0.2})
    # The CLI streams the map (two passes, the exact search over the few candidates): the same
    # numbers as the module's map held in memory, with fewer distances computed by the search.
    assert_same(r.to_dict(), ref, skip=TIMING_KEYS | {"distance_evaluations"})
    assert r.va == ref["va"] and r.va_xyz.tolist() == [ref["va_x"], ref["va_y"], ref["va_z"]]
    i, j = r.critical_pair
    assert np.linalg.norm(r.map.errors[j] - r.map.errors[i]) == pytest.approx(r.va, rel=1e-15)
    assert r.histogram.counts.sum() == len(r.map) * (len(r.map) - 1) // 2
    # the same map from an array of configurations, and the VA of its error vectors alone
    q = vmc.grid(GRID)
    assert_same(mtcal.volumetric(vmc, q).to_dict(), cli_json("volumetric", "-m", VMC, "--grid", GRID),
                skip=TIMING_KEYS | {"distance_evaluations"})
    assert mtcal.volumetric_accuracy(r.map.errors).va.value == r.va


def test_volumetric_accuracy_is_the_largest_pair_difference():
    """Brute force over every pair of a small random set: the independent reference."""
    e = np.random.default_rng(1).normal(size=(300, 3))
    best = max(np.linalg.norm(e[a] - e[b]) for a, b in itertools.combinations(range(len(e)), 2))
    v = mtcal.volumetric_accuracy(e)
    assert v.va.value == pytest.approx(best, rel=1e-15)
    assert v.points == 300 and v.pairs == 300 * 299 / 2
    d = mtcal.pair_histogram(e, 10)
    assert d.counts.sum() == 300 * 299 // 2 and d.max == pytest.approx(best, rel=1e-15)
    with pytest.raises(ValueError, match=r"errors: expected an array of shape \(N, 3\)"):
        mtcal.volumetric_accuracy(np.zeros((4, 2)))


def test_contributions_equal_mtcal_contributions(hu40t):
    at = "X=100,Y=50,Z=-20,B=30,C=90"
    assert_same(mtcal.contributions(hu40t, at=hu40t.parse_joints(at)).to_dict(top=5),
                cli_json("contributions", "-m", HU40T, "--at", at, "--top", "5"))
    a, b = "X=0,Y=0,Z=0", "X=200,Y=100,Z=-150,B=45"
    assert_same(mtcal.contributions(hu40t, pair=(hu40t.parse_joints(a), hu40t.parse_joints(b))).to_dict(),
                cli_json("contributions", "-m", HU40T, "--pair", f"{a};{b}"))
    grid = "X=-300:300:3,Y=-250:250:3,Z=-300:300:3"
    r = mtcal.contributions(hu40t, grid=grid)
    assert_same(r.to_dict(top=8), cli_json("contributions", "-m", HU40T, "--grid", grid, "--top", "8"))
    assert r.mode == "critical_pair" and len(r.what_if) > 0


def test_diagonals_equal_mtcal_diagonals(vmc):
    box = "X=-400:400,Y=-250:250,Z=-500:0"
    r = mtcal.diagonals(vmc, box, points=11)
    assert_same(r.to_dict(), cli_json("diagonals", "-m", VMC, "--box", box, "--points", "11"))
    assert len(r.profiles) == 16 and r.profiles[0].deviation[0] == 0
    with pytest.raises(mtcal.InputError) as e:
        mtcal.diagonals(vmc, "X=-400:400,Y=-250:250")
    assert str(e.value) == cli_error("diagonals", "-m", VMC, "--box", "X=-400:400,Y=-250:250").replace("--box", "box")


def test_toolpath_equals_mtcal_toolpath(vmc):
    program = EXAMPLES / "gcode" / "pocket.nc"
    ref = cli_json("toolpath", "-m", VMC, "--gcode", str(program), "--step", "2", "--origin", "Z=-400", "--no-travel-check")
    r = mtcal.toolpath(vmc, str(program), step=2, origin={"Z": -400}, travel_check=False)
    assert_same(r.to_dict(), ref)
    assert r.errors.shape == (ref["points"], 6) and r.configs.shape == (ref["points"], 3)
    # the errors along the path are the model's at those configurations
    np.testing.assert_allclose(r.errors, mtcal.evaluate(vmc, r.configs, r.directions), rtol=0, atol=1e-15)
    p = mtcal.read_gcode(str(program), axes="XYZ")
    assert_same(mtcal.toolpath(vmc, p, step=2, origin={"Z": -400}, travel_check=False).to_dict(), ref)


@pytest.mark.parametrize("name", ["x_axis_ild50.dat", "z_axis_ild2300.dat", "b02_x_axis.dat"])
def test_iso230_2_on_real_data_equals_mtcal(name):
    path = SHARED_DATA / "iso230-2" / name
    # The command adds what the file says beside the runs (metadata, warnings); the evaluation is the rest.
    ref = {k: v for k, v in cli_json("iso230-2", path).items() if k not in ("metadata", "warnings")}
    runs = mtcal.read_positioning(str(path))
    assert runs.metadata == [] and runs.warnings == []
    e = mtcal.iso230_2(runs)
    assert_same(e.to_dict(), ref)
    # from arrays: the same evaluation
    again = mtcal.iso230_2(runs.targets, runs.up, runs.down, unit=runs.unit)
    assert_same(again.to_dict(), ref)
    assert e.A == ref["A"] and e.table["mean_up"].shape == runs.targets.shape


def test_iso230_2_by_hand():
    """Two targets, two runs: the standard's formulas worked by hand (PRODUCT.md)."""
    e = mtcal.iso230_2([0.0, 10.0], [[0.001, 0.003], [10.002, 10.004]], [[-0.001, 0.001], [10.0, 10.002]])
    # x_up = (0.002, 0.003), x_down = (0.0, 0.001); s = sqrt(2e-6) everywhere
    s = math.sqrt(2e-6)
    assert e.table["mean_up"] == pytest.approx([0.002, 0.003], abs=1e-15)
    assert e.B == pytest.approx(0.002, abs=1e-15)
    assert e.R_up == pytest.approx(4 * s, rel=1e-12)
    assert e.R == pytest.approx(max(4 * s + 0.002, 4 * s), rel=1e-12)
    assert e.E == pytest.approx(0.003 - 0.0, abs=1e-15)
    assert e.M == pytest.approx(0.002 - 0.001, abs=1e-15)
    assert e.A == pytest.approx((0.003 + 2 * s) - (0.0 - 2 * s), rel=1e-12)
    with pytest.raises(mtcal.InputError) as err:
        mtcal.iso230_2([0.0], [[0.0, 0.1]], [[0.0, 0.1]])
    assert "target" in str(err.value)
    with pytest.raises(ValueError, match="up: expected one row per target"):
        mtcal.iso230_2([0.0, 1.0], [[0.0, 0.1]], [[0.0, 0.1]])


def test_ballbar_predicted_trace_equals_mtcal(hu40t, tmp_path):
    centre = "X=0,Y=0,Z=-100"
    trace = mtcal.predict_ballbar(hu40t, "XY", hu40t.parse_joints(centre), radius=100, step=math.radians(2))
    path = tmp_path / "trace.csv"
    cli("ballbar", "--predict", "-m", HU40T, "--plane", "XY", "--centre", centre, "--radius", "100",
        "--step-deg", "2", "--out", path)
    from_cli = mtcal.read_ballbar_csv(str(path))
    assert from_cli.directions == trace.directions
    np.testing.assert_allclose(from_cli.angles, trace.angles, rtol=0, atol=1e-8)
    np.testing.assert_allclose(from_cli.radii, trace.radii, rtol=0, atol=1e-9)
    ref = cli_json("ballbar", path, "--radius", "100", "--plane", "XY")
    r = mtcal.ballbar(from_cli, radius=100, plane="XY")
    assert_same(r.to_dict(), ref)
    assert r.G_b == ref["G_b"] and r.cw.G == ref["cw"]["G"]
    # from arrays, written and read back
    again = mtcal.BallbarTrace(trace.directions, trace.angles, trace.radii)
    mtcal.write_ballbar_csv(str(tmp_path / "again.csv"), again)
    assert_same(mtcal.ballbar(mtcal.read_ballbar_csv(str(tmp_path / "again.csv")), radius=100).to_dict(), ref)


def test_ballbar_radius_is_required(hu40t):
    # The bar's length defines the test: no default radius, as `mtcal ballbar --radius`.
    trace = mtcal.predict_ballbar(hu40t, "XY", hu40t.parse_joints("X=0,Y=0,Z=-100"), radius=100,
                                  step=math.radians(10))
    with pytest.raises(TypeError, match="radius"):
        mtcal.ballbar(trace)
    with pytest.raises(TypeError, match="radius"):
        mtcal.predict_ballbar(hu40t, "XY", hu40t.parse_joints("X=0,Y=0,Z=-100"))
    for bad in (0.0, -150.0, math.nan):
        with pytest.raises(ValueError, match="radius: expected the nominal radius"):
            mtcal.ballbar(trace, radius=bad)
    with pytest.raises(ValueError, match="radius: expected the nominal radius"):
        mtcal.predict_ballbar(hu40t, "XY", hu40t.parse_joints("X=0,Y=0,Z=-100"), radius=0)
    # The radius given is the one evaluated: 100 mm traces read against 150 mm deviate by -50 mm.
    assert mtcal.ballbar(trace, radius=150).F_min == pytest.approx(-50, abs=0.1)


def test_compare_methods_equals_mtcal_compare():
    path = EXAMPLES / "data" / "mohammed2019-ballbar-vs-samba.csv"
    assert_same(mtcal.compare_methods(mtcal.read_comparison_csv(str(path))).to_dict(), cli_json("compare", path))



