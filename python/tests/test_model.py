"""Machine, MachineBuilder, parameters and the exceptions, against the command's output."""
import copy
import math

import numpy as np
import pytest

import mtcal
from conftest import MACHINES, assert_same, cli_error, cli_json


def test_load_and_parameters_match_mtcal_errors(hu40t):
    listed = cli_json("errors", "-m", MACHINES / "hu40t-wCBXfYZt.yaml")
    assert_same(hu40t.to_dict(), listed)
    assert list(hu40t.parameters) == [p["name"] for p in listed["parameters"]]
    assert [hu40t.parameters[p["name"]] for p in listed["parameters"]] == [p["value"] for p in listed["parameters"]]
    assert hu40t.parameter_names == list(hu40t.parameters)
    np.testing.assert_array_equal(hu40t.parameter_values, list(hu40t.parameters.values()))
    assert hu40t.axis_letters == "CBXYZ" and hu40t.topology == "wCBXfYZt" and hu40t.axis_count == 5
    assert [a.kind for a in hu40t.axes] == ["rotary", "rotary", "linear", "linear", "linear"]
    assert [a.unit for a in hu40t.axes] == ["deg", "deg", "mm", "mm", "mm"]
    assert hu40t.axes[2].travel == (-300.0, 300.0)
    assert hu40t.axes[0].travel == pytest.approx((-2 * math.pi, 2 * math.pi), abs=1e-15)


def test_nonzero_listing_matches(vmc):
    assert_same(vmc.to_dict(nonzero=True), cli_json("errors", "-m", MACHINES / "vmc-3axis.yaml", "--nonzero"))
    assert all(p.value != 0 for p in vmc.parameter_table(nonzero=True))


def test_with_params_is_a_copy_as_set_option(hu40t):
    m = hu40t.with_params({"EC0Y": 2e-5, "EXX.1": 5e-6})
    assert m.parameters["EC0Y"] == 2e-5 and m.parameters["EXX.1"] == 5e-6
    assert hu40t.parameters["EC0Y"] != 2e-5  # the original is unchanged
    at = "X=100,Y=50,Z=-20,B=30,C=90"
    ref = cli_json("eval", "-m", MACHINES / "hu40t-wCBXfYZt.yaml", "--set", "EC0Y=2e-5", "--set", "EXX.1=5e-6",
                   "--at", at)
    e = mtcal.evaluate(m, m.parse_joints(at))
    assert_same(dict(zip(["dx", "dy", "dz", "rx", "ry", "rz"], e.tolist())), ref)
    # keyword form and units
    assert hu40t.with_params(EC0Y=20, unit="urad").parameters["EC0Y"] == pytest.approx(2e-5, rel=1e-15)


def test_with_only_and_without_errors(hu40t):
    only = hu40t.with_only(["EXX", "EC0Y"])
    ref = cli_json("errors", "-m", MACHINES / "hu40t-wCBXfYZt.yaml", "--only", "EXX,EC0Y", "--nonzero")
    assert_same(only.to_dict(nonzero=True), ref)
    assert not any(hu40t.without_errors().parameter_values)


def test_with_parameter_file(hu40t, tmp_path):
    p = tmp_path / "p.yaml"
    p.write_text(hu40t.with_params({"EX0C": 3e-3}).parameters_yaml(["EX0C"], "a comment"))
    m = hu40t.with_parameter_file(str(p))
    assert m.parameters["EX0C"] == 3e-3
    ref = cli_json("eval", "-m", MACHINES / "hu40t-wCBXfYZt.yaml", "--params", p, "--at", "X=10,C=45")
    assert_same(dict(zip(ref, mtcal.evaluate(m, m.parse_joints("X=10,C=45")).tolist())), ref)
    assert mtcal.Machine.load(str(MACHINES / "hu40t-wCBXfYZt.yaml"), params=[str(p)]).parameters["EX0C"] == 3e-3


def test_yaml_round_trip_and_copy(hu40t, tmp_path):
    back = mtcal.Machine.parse(hu40t.to_yaml(), "round trip")
    assert back.parameters == hu40t.parameters and back.topology == hu40t.topology
    path = tmp_path / "m.yaml"
    hu40t.save(str(path))
    assert mtcal.Machine.load(str(path)).parameters == hu40t.parameters
    c = copy.deepcopy(hu40t)
    assert c.parameters == hu40t.parameters and c is not hu40t


VMC_LIKE = """mtcal_machine: 1
name: built
topology: wXYfZt
axes:
  X: {travel: [-400, 400]}
  Y: {travel: [-250, 250], direction: -y}
  Z: {travel: [-500, 0], point: [0, 0, -250]}
tool: {length: 100, spindle_point: [0, 0, 10]}
workpiece: {origin: [0, 0, -450]}
errors:
  EXX: {unit: mm, polynomial: [0.0005, 8.0e-6, -1.2e-8, 4.0e-12], reversal: 0.001}
  EYY: {unit: mm, table: {positions: [-250, 0, 250], forward: [-0.002, 0, 0.003], backward: [-0.001, 0.0005, 0.0035]}}
  EC0Y: {value: 2.0e-5, unit: rad}
  EXt: {value: 4, unit: um}
"""


def test_builder_equals_the_machine_file():
    """The builder from Python values and the YAML reader give the same machine (independent paths)."""
    built = (mtcal.MachineBuilder().name("built").topology("wXYfZt")
             .axis("X", travel=(-400, 400)).axis("Y", travel=(-250, 250), sign=-1)
             .axis("Z", travel=(-500, 0), point=[0, 0, -250])
             .tool(length=100, spindle_point=[0, 0, 10]).workpiece_origin([0, 0, -450])
             .motion("EXX", polynomial=[0.0005, 8.0e-6, -1.2e-8, 4.0e-12], reversal=0.001)
             .motion("EYY", table={"positions": [-250, 0, 250], "forward": [-0.002, 0, 0.003],
                                   "backward": [-0.001, 0.0005, 0.0035]})
             .error_value("EC0Y", 2e-5).parameter("EXt", 4, "um").build())
    parsed = mtcal.Machine.parse(VMC_LIKE)
    assert built.parameters == pytest.approx(parsed.parameters, rel=1e-15, abs=0)
    q = built.grid("X=-400:400:5,Y=-250:250:5,Z=-500:0:3")
    d = np.tile(np.array([1, -1, 1], dtype=np.int8), (len(q), 1))
    np.testing.assert_allclose(mtcal.evaluate(built, q, d), mtcal.evaluate(parsed, q, d), rtol=0, atol=1e-15)
    assert built.axes[1].direction.tolist() == [0, -1, 0]


def test_builder_refuses_with_the_library_message():
    with pytest.raises(mtcal.ModelError, match=r"axis 'B'.*not in the topology|axis 'B'"):
        mtcal.MachineBuilder().topology("wXYfZt").axis("B", travel=(0, 1))
    with pytest.raises(mtcal.ModelError, match="topology: none given"):
        mtcal.MachineBuilder().build()
    with pytest.raises(mtcal.ModelError, match="not a finite value"):
        mtcal.MachineBuilder().topology("wXYfZt").parameter("EXt", float("nan"))


def test_unknown_parameter_message_is_the_librarys(hu40t):
    msg = cli_error("eval", "-m", MACHINES / "hu40t-wCBXfYZt.yaml", "--set", "EQQ=1", "--at", "X=0")
    with pytest.raises(mtcal.ModelError) as e:
        hu40t.with_params({"EQQ": 1.0})
    assert str(e.value) == msg
    assert isinstance(e.value, mtcal.Error) and isinstance(e.value, ValueError)


def test_input_error_carries_file_line_field(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text(VMC_LIKE.replace("EC0Y: {value: 2.0e-5", "EC0Y: {value: fast"))
    msg = cli_error("errors", "-m", bad)
    with pytest.raises(mtcal.InputError) as e:
        mtcal.Machine.load(str(bad))
    assert str(e.value) == msg
    assert e.value.file == str(bad) and e.value.line == VMC_LIKE.splitlines().index("  EC0Y: {value: 2.0e-5, unit: rad}") + 1
    assert e.value.field != ""
    missing = tmp_path / "missing.yaml"
    with pytest.raises(mtcal.InputError, match="cannot open"):
        mtcal.Machine.load(str(missing))


def test_units_and_grids(hu40t):
    q = hu40t.to_internal([[90, 45, 1, 2, 3]])
    np.testing.assert_allclose(q, [[math.pi / 2, math.pi / 4, 1, 2, 3]], rtol=1e-15)
    np.testing.assert_allclose(hu40t.to_user(q), [[90, 45, 1, 2, 3]], rtol=1e-15)
    np.testing.assert_allclose(hu40t.joint_factors, [math.pi / 180, math.pi / 180, 1, 1, 1])
    g = hu40t.grid("X=-300:300:3,B=0:90:2")
    assert g.shape == (6, 5)
    # the last axis of the chain varies fastest; axes not named are 0
    np.testing.assert_allclose(g[:, 1], np.repeat([0, math.pi / 2], 3))
    np.testing.assert_allclose(g[:, 2], np.tile([-300, 0, 300], 2))
    same = hu40t.grid({"X": [-300, 0, 300], "B": [0, math.pi / 2]})
    np.testing.assert_array_equal(g, same)
    assert hu40t.format_joints(hu40t.parse_joints("X=100,B=30")) == "C=0,B=30,X=100,Y=0,Z=0"
    with pytest.raises(mtcal.InputError, match="outside the travel"):
        hu40t.grid("X=-900:0:2", travel_check=True)
