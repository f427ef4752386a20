"""Regression, prediction, separation and process error; the compensation registry: to_dict() equals
the command's --json; the registry is read by name."""
import numpy as np
import pytest

import mtcal
from conftest import EXAMPLES, MACHINES, assert_same, cli, cli_error, cli_json

P = EXAMPLES / "prediction"
MODEL = P / "yaqoob2017-model.yaml"


def test_regress_equals_mtcal_regress():
    t = mtcal.read_csv(str(P / "yaqoob2017-table5_8.csv"))
    ref = cli_json("regress", P / "yaqoob2017-table5_8.csv", "--x", "t", "--y", "e_splz")
    r = mtcal.compare_models(t["t"], t["e_splz"])
    assert_same(r.to_dict(file=str(P / "yaqoob2017-table5_8.csv"), x="t", y="e_splz"), ref)
    best = r.best_backward
    assert best.label == ref["best_backward"]


def test_fit_model_recovers_a_known_curve():
    """exp_approach a - b exp(-c x) with the parameters of Yaqoob eq. 5.6 (order of magnitude), no noise."""
    x = np.linspace(0, 300, 25)
    y = 0.02 - 0.018 * np.exp(-0.012 * x)
    f = mtcal.fit_model(x, y, model="exp_approach")
    assert f.parameter_names == ["a", "b", "c"]
    np.testing.assert_allclose(f.parameters, [0.02, 0.018, 0.012], rtol=1e-8)
    np.testing.assert_allclose(f(x), y, atol=1e-12)
    assert f.covariance.shape == (3, 3)
    line = mtcal.fit_model([0, 1, 2, 3], [1, 3, 5, 7], model="polynomial(1)")
    np.testing.assert_allclose(line.parameters, [1, 2], atol=1e-14)
    with pytest.raises(mtcal.InputError, match="cubic"):
        mtcal.fit_model([0, 1, 2], [0, 1, 2], model="cubic")
    with pytest.raises(ValueError, match=r"y: expected an array of shape \(3,\)"):
        mtcal.fit_model([0, 1, 2], [0, 1])


def test_predict_equals_mtcal_predict():
    points = P / "yaqoob2017-w2-points.csv"
    ref = cli_json("predict", "--model", MODEL, "--points", points)
    m = mtcal.read_prediction_model(str(MODEL))
    pts = mtcal.read_prediction_points(str(points))
    r = mtcal.predict(m, pts)
    assert_same(r.to_dict(), ref)
    assert r.errors.shape == (len(pts.lines), 3)
    # the same points as a dict of columns
    cols = {c: pts.values[:, k] for k, c in enumerate(pts.columns)}
    again = mtcal.predict(m, cols).to_dict()
    assert_same(again, ref, skip={"line", "source"})
    with pytest.raises(mtcal.InputError, match="missing column"):
        mtcal.predict(m, {"t": [1.0]})


def test_separate_and_process_error_equal_mtcal():
    t53 = P / "yaqoob2017-table5_3.csv"
    assert_same(mtcal.separate_position(str(t53)).to_dict(str(t53)), cli_json("separate", "position", t53))
    t56 = P / "yaqoob2017-table5_6.csv"
    model = mtcal.read_prediction_model(str(MODEL))
    assert_same(mtcal.separate_control(str(t56), "W2", "W5", model=model).to_dict(str(t56)),
                cli_json("separate", "control", t56, "--a", "W2", "--b", "W5", "--model", MODEL))
    ref = cli_json("process-error", "--feed", "100,400,800")
    r = mtcal.process_error([100, 400, 800])
    assert_same(r.to_dict(), ref)
    assert r.e_prog.shape == (3,) and np.all(np.diff(r.e_prog) > 0)


def test_compensation_registry_by_name(vmc, hu40t, tmp_path):
    """Every target of the library's registry is reached by its name, whatever the targets are: each
    writes for at least one of the example machines, with the summary the library serialises."""
    targets = mtcal.compensation_targets()
    assert isinstance(targets, dict) and all(isinstance(d, str) for d in targets.values())
    for name in targets:
        written = []
        for m in (vmc, hu40t):
            try:
                out = mtcal.compensate(m, name, residual_points=3)  # the residual grid: 2 s a target at its default
            except mtcal.Error as e:  # a target for other kinematics refuses with a message
                assert str(e)
                continue
            d = out.to_dict()
            assert d["target"] == name and d["quantity"] == out.quantity
            assert d["files"] == list(out.files)
            where = tmp_path / f"{name}-{m.axis_count}"
            out.write(str(where))
            assert sorted(p.name for p in where.iterdir()) == sorted(out.files)
            assert all((where / f).read_text() == text for f, text in out.files.items())
            written.append(m)
        assert written, f"target {name} wrote for none of the example machines"
    # The firmware skew targets' reference length: M556 S and the deviations scale with it.
    gcode = mtcal.compensate(vmc, "rrf", skew_reference_length=200).files["rrf.gcode"]
    assert "\nM556 S200 X0.003 Y-0.0024 Z-0.004000036 P0\n" in gcode, gcode
    with pytest.raises(mtcal.InputError) as e:
        mtcal.compensate(vmc, "no-such-controller")
    assert "unknown compensation target 'no-such-controller'" in str(e.value) and e.value.field == "format"
