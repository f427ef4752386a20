"""evaluate, jacobian and effects: the same numbers as mtcal eval / effects, checked inputs, no needless copies."""
import threading
import time
import tracemalloc

import numpy as np
import pytest

import mtcal
from conftest import MACHINES, assert_same, cli_json

KEYS = ["dx", "dy", "dz", "rx", "ry", "rz"]
MACHINE_FILES = sorted(p.name for p in MACHINES.glob("*.yaml"))


def random_configs(m, n, seed):
    """n configurations inside the travels (rotary axes without travel: +-pi), internal units."""
    rng = np.random.default_rng(seed)
    lo = np.array([a.travel[0] if a.travel else -np.pi for a in m.axes])
    hi = np.array([a.travel[1] if a.travel else np.pi for a in m.axes])
    return lo + (hi - lo) * rng.random((n, m.axis_count))


@pytest.mark.parametrize("name", MACHINE_FILES)
def test_evaluate_equals_mtcal_eval(name):
    m = mtcal.Machine.load(str(MACHINES / name))
    q = random_configs(m, 4, 11)
    e = mtcal.evaluate(m, q)
    assert e.shape == (4, 6) and e.dtype == np.float64
    for row, err in zip(q, e):
        ref = cli_json("eval", "-m", MACHINES / name, "--at", m.format_joints(row))
        # the command rounds the configuration to 12 digits in the --at text: evaluate the same point
        at = m.parse_joints(m.format_joints(row))
        assert_same(dict(zip(KEYS, mtcal.evaluate(m, at).tolist())), ref)
        np.testing.assert_allclose(err, mtcal.evaluate(m, row), rtol=0, atol=0)


def test_directions_and_batch_summary_equal_mtcal_eval_points(hu40t, tmp_path):
    q = random_configs(hu40t, 500, 3)
    d = np.random.default_rng(4).integers(-1, 2, size=q.shape).astype(np.int8)
    user = hu40t.to_user(q)
    path = tmp_path / "points.csv"
    header = ",".join(list(hu40t.axis_letters) + ["dir" + c for c in hu40t.axis_letters])
    np.savetxt(path, np.hstack([user, d]), delimiter=",", header=header, comments="", fmt="%.17g")
    ref = cli_json("eval", "-m", MACHINES / "hu40t-wCBXfYZt.yaml", "--points", path)
    listed = mtcal.read_configurations(hu40t, str(path))
    np.testing.assert_array_equal(listed.directions, d)
    e = mtcal.evaluate(hu40t, listed.configs, listed.directions)
    assert ref["configurations"] == len(e)
    assert np.linalg.norm(e[:, :3], axis=1).max() == pytest.approx(ref["max_translation"]["value"], rel=1e-12, abs=0)
    assert np.linalg.norm(e[:, 3:], axis=1).max() == pytest.approx(ref["max_rotation"]["value"], rel=1e-12, abs=0)
    # directions change the result (reversal terms), and threads do not
    assert np.abs(e - mtcal.evaluate(hu40t, listed.configs)).max() > 1e-4
    np.testing.assert_array_equal(e, mtcal.evaluate(hu40t, listed.configs, listed.directions, threads=1))
    model = mtcal.ErrorModel(hu40t)
    np.testing.assert_array_equal(e, model.evaluate(listed.configs, listed.directions))
    np.testing.assert_array_equal(e, mtcal.evaluate(model, listed.configs, listed.directions))


def test_pose_difference_is_the_error(hu40t):
    model = mtcal.ErrorModel(hu40t)
    q = random_configs(hu40t, 1, 5)[0]
    a, n = model.actual_pose(q), model.nominal_pose(q)
    np.testing.assert_allclose(mtcal.evaluate(model, q)[:3], a[:3, 3] - n[:3, 3], rtol=0, atol=1e-12)


def test_jacobian_against_central_differences(vmc):
    """Column j of the Jacobian against (e(p + h) - e(p - h)) / 2h of the model with parameter j moved."""
    q = random_configs(vmc, 3, 9)
    d = np.array([[1, -1, 1], [-1, 1, -1], [0, 0, 1]], dtype=np.int8)
    J = mtcal.jacobian(vmc, q, d)
    assert J.shape == (3, 6, vmc.parameter_count)
    names = vmc.parameter_names
    for j in range(0, len(names), 3):
        unit = vmc.parameter_table()[j].unit
        # steps that move the tool by about 1e-4 mm over the travel: above rounding, below curvature
        h = {"": 1e-4, "/mm": 1e-7, "/mm^2": 1e-10, "/mm^3": 1e-13}[unit[unit.find("/"):] if "/" in unit else ""]
        p = vmc.parameters[names[j]]
        plus = mtcal.evaluate(vmc.with_params({names[j]: p + h}), q, d)
        minus = mtcal.evaluate(vmc.with_params({names[j]: p - h}), q, d)
        fd = (plus - minus) / (2 * h)
        np.testing.assert_allclose(J[:, :, j], fd, rtol=1e-5, atol=1e-6 * np.abs(fd).max() + 1e-9, err_msg=names[j])
    np.testing.assert_array_equal(mtcal.jacobian(vmc, q[1], d[1]), J[1])
    np.testing.assert_array_equal(mtcal.jacobian(vmc, q, d, threads=1), J)


def test_effects_equal_mtcal_effects(hu40t):
    at = "X=100,Y=50,Z=-20,B=30,C=90"
    for around in ("nominal", "actual"):
        ref = cli_json("effects", "-m", MACHINES / "hu40t-wCBXfYZt.yaml", "--at", at, "--around", around,
                       "--errors", "EXX,EC0Y,EX0C,EXt")
        r = mtcal.effects(hu40t, hu40t.parse_joints(at), errors=["EXX", "EC0Y", "EX0C", "EXt"], around=around)
        assert_same(r.to_dict(), ref)
        assert r.values.shape == (4, 6) and sorted(r.errors) == ["EC0Y", "EX0C", "EXX", "EXt"]
    with pytest.raises(mtcal.InputError, match="unknown error name 'EQQ'"):
        mtcal.effects(hu40t, np.zeros(5), errors=["EQQ"])


def test_bad_shapes_and_dtypes_name_the_argument(hu40t):
    with pytest.raises(ValueError, match=r"configs: expected an array of shape \(N, 5\).*found shape \(3, 4\)"):
        mtcal.evaluate(hu40t, np.zeros((3, 4)))
    with pytest.raises(ValueError, match=r"configs: .*found shape \(2, 3, 5\)"):
        mtcal.evaluate(hu40t, np.zeros((2, 3, 5)))
    with pytest.raises(ValueError, match="configs: expected real numbers .* found dtype complex128"):
        mtcal.evaluate(hu40t, np.zeros((3, 5), dtype=complex))
    with pytest.raises(ValueError, match="configs: expected real numbers"):
        mtcal.evaluate(hu40t, [["a"] * 5])
    with pytest.raises(ValueError, match="configs: expected finite numbers, found nan at row 1, column 2"):
        q = np.zeros((3, 5))
        q[1, 2] = np.nan
        mtcal.evaluate(hu40t, q)
    with pytest.raises(ValueError, match=r"directions: expected an array of shape \(3, 5\)"):
        mtcal.evaluate(hu40t, np.zeros((3, 5)), np.zeros((2, 5), dtype=np.int8))
    with pytest.raises(ValueError, match="directions: expected -1, 0 or \\+1, found 2"):
        mtcal.evaluate(hu40t, np.zeros((3, 5)), np.full((3, 5), 2, dtype=np.int8))
    with pytest.raises(ValueError, match="directions: expected -1, 0 or \\+1, found 256"):
        mtcal.evaluate(hu40t, np.zeros((3, 5)), np.full((3, 5), 256))
    with pytest.raises(ValueError, match="directions: expected -1, 0 or \\+1, found 0.5"):
        mtcal.evaluate(hu40t, np.zeros((3, 5)), np.full((3, 5), 0.5))
    with pytest.raises(ValueError, match="configs"):
        mtcal.jacobian(hu40t, np.zeros((3, 2)))
    with pytest.raises(TypeError, match="model: expected a Machine or an ErrorModel"):
        mtcal.evaluate("hu40t", np.zeros((3, 5)))
    with pytest.raises(mtcal.InputError, match=r"configs\[1\].*outside the travel"):
        mtcal.evaluate(hu40t, [[0, 0, 0, 0, 0], [0, 0, 900, 0, 0]], travel_check=True)


def test_other_layouts_are_converted_with_the_same_result(hu40t):
    q = random_configs(hu40t, 50, 1)
    ref = mtcal.evaluate(hu40t, q)
    np.testing.assert_array_equal(mtcal.evaluate(hu40t, np.asfortranarray(q)), ref)
    np.testing.assert_array_equal(mtcal.evaluate(hu40t, q.astype(np.float32).astype(np.float64)),
                                  mtcal.evaluate(hu40t, q.astype(np.float32)))
    np.testing.assert_array_equal(mtcal.evaluate(hu40t, q.tolist()), ref)
    wide = np.zeros((50, 10))
    wide[:, ::2] = q
    np.testing.assert_array_equal(mtcal.evaluate(hu40t, wide[:, ::2]), ref)
    assert mtcal.evaluate(hu40t, np.zeros((0, 5))).shape == (0, 6)


def test_c_contiguous_float64_input_is_not_copied(hu40t):
    q = random_configs(hu40t, 1000, 2)
    assert mtcal._mtcal._input_address(q, 5) == q.__array_interface__["data"][0]
    f = np.asfortranarray(q)
    assert mtcal._mtcal._input_address(f, 5) != f.__array_interface__["data"][0]  # the check can fail
    # Memory: evaluating 200 000 configurations (8 MB in) allocates the 9.6 MB output and nothing
    # of the input's size (NumPy reports its buffers to tracemalloc; a converted copy is seen).
    big = random_configs(hu40t, 200_000, 3)
    out_bytes = 200_000 * 6 * 8
    for arr, copies in ((big, False), (np.asfortranarray(big), True)):
        tracemalloc.start()
        mtcal.evaluate(hu40t, arr)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        if copies:
            assert peak >= out_bytes + big.nbytes
        else:
            assert peak < out_bytes + big.nbytes // 4, peak


def test_gil_is_released(hu40t):
    """While evaluate works in another thread, Python code in this one keeps running."""
    q = random_configs(hu40t, 2_000_000, 8)
    ticks = 0
    t = threading.Thread(target=mtcal.evaluate, args=(hu40t, q), kwargs={"threads": 1})
    t0 = time.perf_counter()
    t.start()
    while t.is_alive():
        ticks += 1
    elapsed = time.perf_counter() - t0
    t.join()
    assert elapsed > 0.05, elapsed  # long enough to measure
    assert ticks > 1000, ticks


def test_out_argument_is_filled_in_place(hu40t):
    q = random_configs(hu40t, 100, 6)
    buf = np.full((100, 6), np.nan)
    r = mtcal.evaluate(hu40t, q, out=buf)
    assert r is buf or np.shares_memory(r, buf)
    np.testing.assert_array_equal(buf, mtcal.evaluate(hu40t, q))
    with pytest.raises(ValueError, match=r"out: expected a writeable C-contiguous float64 array of shape \(100, 6\)"):
        mtcal.evaluate(hu40t, q, out=np.empty((100, 6), dtype=np.float32))
    with pytest.raises(ValueError, match="out:"):
        mtcal.evaluate(hu40t, q, out=np.empty((6, 100)).T)


def test_help_explains_units_and_shapes():
    doc = mtcal.evaluate.__doc__
    for words in ("(N, k)", "(N, 6)", "mm", "rad", "C-contiguous float64", "directions", "-1, 0 or +1"):
        assert words in doc, words
    assert "(N, 6, P)" in mtcal.jacobian.__doc__
    assert mtcal.evaluate.__module__ == "mtcal" and mtcal.Machine.__module__ == "mtcal"
