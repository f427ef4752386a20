"""Probing plans, probe logs and the commanded-joint solver (mtcal plan, probe-log; compensate
--format linuxcnc-kins' inverse) against the command, and the solver against the exact model."""
import re

import numpy as np
import pytest

import mtcal
from conftest import EXAMPLES, MACHINES, assert_same, cli, cli_json

RRTTT = MACHINES / "rrttt-table-table.yaml"
SPHERE = EXAMPLES / "plans" / "rrttt-viprey-sphere.csv"


@pytest.fixture(scope="module")
def rrttt():
    return mtcal.Machine.load(str(RRTTT))


def test_design_plan_matches_cli(tmp_path, rrttt):
    out = tmp_path / "cli.csv"
    ref = cli_json("plan", "-m", RRTTT, "--artefact", SPHERE, "--estimate", "EY0C,EZ0A", "--poses", 12,
                   "--out", out)
    artefact = mtcal.read_probing_plan(rrttt, str(SPHERE))
    r = mtcal.design_plan(rrttt, artefact, estimate=["EY0C", "EZ0A"], poses=12)
    assert_same(r.to_dict(out=str(out)), ref, tol=0)
    mine = tmp_path / "py.csv"
    mtcal.write_probing_csv(str(mine), rrttt, r.plan)
    data = lambda p: [l for l in p.read_text().splitlines() if not l.startswith("#")]  # noqa: E731
    assert data(mine) == data(out)
    with pytest.raises(mtcal.InputError, match="budget"):
        mtcal.design_plan(rrttt, artefact, estimate=["EY0C"])
    with pytest.raises(ValueError, match="'max-u' or 'va'"):
        mtcal.design_plan(rrttt, artefact, estimate=["EY0C"], poses=3, criterion="e")


def test_design_plan_options_match_cli(rrttt):
    """The options of mtcal plan beyond a pose budget, each against the command's --json exactly:
    parameters chosen among candidates (with the program's feeds and cycle in the time), the VA's
    uncertainty over a workspace (criterion va), and a region where balls may go."""
    artefact = mtcal.read_probing_plan(rrttt, str(SPHERE))
    ref = cli_json("plan", "-m", RRTTT, "--artefact", SPHERE, "--estimate", "EX0C,EY0C",
                   "--candidates", "EA0C,EB0C,EY0A,EZ0A,EB0A,EC0A", "--choose", 4, "--poses", 14,
                   "--rotary-step-deg", 30, "--move-feed", 900, "--rapid", 8000, "--approach", 2,
                   "--clearance", 6, "--ball-diameter", 20)
    r = mtcal.design_plan(rrttt, artefact, estimate=["EX0C", "EY0C"],
                          candidates=["EA0C", "EB0C", "EY0A", "EZ0A", "EB0A", "EC0A"], choose=4, poses=14,
                          rotary_step=np.radians(30), move_feed=900, rapid=8000, approach=2, clearance=6,
                          ball_diameter=20)
    assert_same(r.to_dict(), ref, tol=0)
    assert r.estimate == ref["parameters_chosen"]["estimate"] and r.va_u is None
    workspace = "X=-200:200:3,Y=-200:200:3,Z=-400:-100:3,A=-60:60:3,C=-180:120:5"
    est = ["EX0C", "EY0C", "EA0C", "EB0C", "EY0A", "EZ0A", "EB0A", "EC0A"]
    ref = cli_json("plan", "-m", RRTTT, "--artefact", SPHERE, "--estimate", ",".join(est), "--poses", 12,
                   "--criterion", "va", "--workspace", workspace, "--va-tie-um", 2, "--rotary-step-deg", 30)
    r = mtcal.design_plan(rrttt, artefact, estimate=est, poses=12, criterion="va", workspace=workspace,
                          va_tie=2e-3, rotary_step=np.radians(30))
    assert_same(r.to_dict(), ref, tol=0)
    assert r.va_u == ref["va"]["u"]
    ref = cli_json("plan", "-m", RRTTT, "--ball-region", "-100:100,-100:100,50", "--ball-spacing", 200,
                   "--estimate", "EX0C,EY0C,EA0C,EB0C", "--poses", 10, "--rotary-step-deg", 30)
    r = mtcal.design_plan(rrttt, estimate=["EX0C", "EY0C", "EA0C", "EB0C"], ball_region=(-100, 100, -100, 100, 50),
                          ball_spacing=200, poses=10, rotary_step=np.radians(30))
    assert_same(r.to_dict(), ref, tol=0)
    assert ref["ball_region"]["positions"] == 4
    with pytest.raises(ValueError, match="choose"):
        mtcal.design_plan(rrttt, artefact, estimate=["EY0C"], candidates=["EZ0A"], poses=3)
    with pytest.raises(ValueError, match="ball_region"):
        mtcal.design_plan(rrttt, estimate=["EY0C"], ball_region=(0, 1, 0, 1), poses=3)
    with pytest.raises(mtcal.InputError, match="spacing"):
        mtcal.design_plan(rrttt, estimate=["EY0C"], ball_region=(0, 1, 0, 1, 0), ball_spacing=-1, poses=3)


def test_design_plan_instruments_match_cli(tmp_path, rrttt):
    """--ballbar and --laser (circles and lines as poses, their time, by_hand) against plan --json
    exactly; probe_program of probing_part(plan) is the command's program less its by-hand notes."""
    artefact = mtcal.read_probing_plan(rrttt, str(SPHERE))
    ref = cli_json("plan", "-m", RRTTT, "--artefact", SPHERE, "--estimate", "EY0C,EZ0A,EC0Y", "--poses", 10,
                   "--rotary-step-deg", 30, "--ballbar", 150, "--ballbar-points", 24, "--ballbar-feed", 1500,
                   "--ballbar-setup-s", 200, "--laser", "X", "--laser-points", 6, "--laser-setup-s", 600,
                   "--laser-dwell-s", 2, "--gcode", tmp_path / "bb.ngc")
    r = mtcal.design_plan(rrttt, artefact, estimate=["EY0C", "EZ0A", "EC0Y"], poses=10, rotary_step=np.radians(30),
                          ballbar=[150], ballbar_points=24, ballbar_feed=1500, ballbar_setup=200,
                          laser=["X"], laser_points=6, laser_setup=600, laser_dwell=2)
    assert_same(r.to_dict(gcode=str(tmp_path / "bb.ngc")), ref, tol=0)
    assert r.poses == 10 and ref["by_hand"], ref.get("by_hand")
    probing = mtcal.probing_part(r.plan)
    text = mtcal.probe_program(rrttt, probing, header=f"machine {rrttt.name}: 10 poses designed by mtcal plan")
    written = (tmp_path / "bb.ngc").read_text()
    assert [l for l in written.splitlines() if "by hand" not in l and not l.startswith("(  ")] == text.splitlines()
    with pytest.raises(mtcal.InputError, match="found 'W'"):
        mtcal.design_plan(rrttt, artefact, estimate=["EY0C"], poses=3, laser=["W"])


def test_probe_program_and_log_match_cli(tmp_path, rrttt):
    cli("plan", "-m", RRTTT, "--artefact", SPHERE, "--estimate", "EY0C,EZ0A", "--poses", 12,
        "--out", tmp_path / "plan.csv", "--gcode", tmp_path / "probe.ngc")
    designed = mtcal.design_plan(rrttt, mtcal.read_probing_plan(rrttt, str(SPHERE)), estimate=["EY0C", "EZ0A"], poses=12)
    text = mtcal.probe_program(rrttt, designed.plan, header=f"machine {rrttt.name}: 12 poses designed by mtcal plan")
    cli("plan", "-m", RRTTT, "--artefact", SPHERE, "--estimate", "EY0C,EZ0A", "--poses", 12,
        "--gcode", tmp_path / "slow.ngc", "--move-feed", 700, "--probe-feed", 90)
    assert mtcal.probe_program(rrttt, designed.plan, move_feed=700, probe_feed=90,
                               header=f"machine {rrttt.name}: 12 poses designed by mtcal plan") == \
        (tmp_path / "slow.ngc").read_text()
    assert text == (tmp_path / "probe.ngc").read_text()
    # --program-coordinates tool-point: the program, and the time of that program in the design.
    ref = cli_json("plan", "-m", RRTTT, "--artefact", SPHERE, "--estimate", "EY0C,EZ0A", "--poses", 12,
                   "--gcode", tmp_path / "tp.ngc", "--program-coordinates", "tool-point")
    tp = mtcal.design_plan(rrttt, mtcal.read_probing_plan(rrttt, str(SPHERE)), estimate=["EY0C", "EZ0A"], poses=12,
                           program_coordinates="tool-point")
    assert_same(tp.to_dict(gcode=str(tmp_path / "tp.ngc")), ref, tol=0)
    assert ref["time"]["total_s"] != designed.to_dict()["time"]["total_s"]
    assert mtcal.probe_program(rrttt, tp.plan, program_coordinates="tool-point",
                               header=f"machine {rrttt.name}: 12 poses designed by mtcal plan") == \
        (tmp_path / "tp.ngc").read_text()
    with pytest.raises(ValueError, match="'axes' or 'tool-point'"):
        mtcal.probe_program(rrttt, tp.plan, program_coordinates="world")
    # Its log (world positions) back to measurements, as probe-log --program-coordinates tool-point.
    at, tp_log = {}, []
    for line in (tmp_path / "tp.ngc").read_text().splitlines():
        words = {k: float(v) for k, v in re.findall(r"([XYZABC])(-?[\d.]+)", line.split("(")[0])}
        if line.startswith("G38.2"):
            p = {**at, **words}
            tp_log.append(" ".join(f"{p.get(a, 0.0):.6f}" for a in "XYZABC") + " 0 0 0")
        at.update(words)
    (tmp_path / "tp-log.txt").write_text("\n".join(tp_log) + "\n")
    mtcal.write_probing_csv(str(tmp_path / "tp-plan.csv"), rrttt, tp.plan)
    cli("probe-log", "-m", RRTTT, "--plan", tmp_path / "tp-plan.csv", "--log", tmp_path / "tp-log.txt",
        "--program-coordinates", "tool-point", "--out", tmp_path / "tp-cli-meas.csv")
    tp_meas = mtcal.measurements_from_contacts(rrttt, mtcal.read_probing_plan(rrttt, str(tmp_path / "tp-plan.csv")),
                                               str(tmp_path / "tp-log.txt"), program_coordinates="tool-point")
    mtcal.write_probing_csv(str(tmp_path / "tp-py-meas.csv"), rrttt, tp_meas)
    data = lambda p: [l for l in p.read_text().splitlines() if not l.startswith("#")]  # noqa: E731
    assert data(tmp_path / "tp-py-meas.csv") == data(tmp_path / "tp-cli-meas.csv")
    # A LinuxCNC probe log of that program: each G38.2 move's end (as tests/cli/test_option_errors.py makes it).
    at, log = {}, []
    for line in text.splitlines():
        words = {k: float(v) for k, v in re.findall(r"([XYZABC])(-?[\d.]+)", line.split("(")[0])}
        if line.startswith("G38.2"):
            p = {**at, **words}
            log.append(" ".join(f"{p.get(a, 0.0):.6f}" for a in "XYZABC") + " 0 0 0")
        at.update(words)
    (tmp_path / "log.txt").write_text("\n".join(log) + "\n")
    contacts = mtcal.read_probe_log(rrttt, str(tmp_path / "log.txt"))
    assert contacts.shape == (len(log), rrttt.axis_count)
    ref = cli_json("probe-log", "-m", RRTTT, "--plan", tmp_path / "plan.csv", "--log", tmp_path / "log.txt",
                   "--out", tmp_path / "cli-meas.csv")
    plan = mtcal.read_probing_plan(rrttt, str(tmp_path / "plan.csv"))
    meas = mtcal.measurements_from_contacts(rrttt, plan, str(tmp_path / "log.txt"))
    assert ref["contacts"] == len(log) and ref["records"] == len(meas.configs)
    mtcal.write_probing_csv(str(tmp_path / "py-meas.csv"), rrttt, meas)
    data = lambda p: [l for l in p.read_text().splitlines() if not l.startswith("#")]  # noqa: E731
    assert data(tmp_path / "py-meas.csv") == data(tmp_path / "cli-meas.csv")
    (tmp_path / "bad.txt").write_text(log[0] + "\n1 2 x\n")
    with pytest.raises(mtcal.InputError) as e:
        mtcal.read_probe_log(rrttt, str(tmp_path / "bad.txt"))
    assert e.value.line == 2


def test_locate_program_and_spheres_match_cli(tmp_path):
    # plan --locate / probe-log --locate (the first coarse touch): the same program and the same sphere.
    loop = EXAMPLES / "loop" / "rrttt-nominal.yaml"
    m = mtcal.Machine.load(str(loop))
    rough = tmp_path / "rough.csv"
    rough.write_text("indexation,A,C,feature,kind,x,y,z,nx,ny,nz,dirX,dirY,dirZ\n1,0,0,S,ball,121,-79,60.5,,,,,,\n")
    cli("plan", "-m", loop, "--artefact", rough, "--locate", "--locate-within", 2.5, "--program-coordinates", "tool-point",
        "--out", tmp_path / "lp.csv", "--gcode", tmp_path / "locate.ngc")
    plan = mtcal.locate_plan(m, mtcal.read_probing_plan(m, str(rough)))
    text = mtcal.locate_program(m, plan, within=2.5, program_coordinates="tool-point",
                                header=f"machine {m.name}: 1 ball located from rough positions by mtcal plan --locate")
    assert text == (tmp_path / "locate.ngc").read_text()
    # The log of a sphere at 120.5,-79.5,60 (tool-point coordinates: the program's X Y Z are the tool point
    # in the workpiece frame): where each G38.2 move first comes (25.4 + 3) / 2 from it.
    centre, rho, at, log = np.array([120.5, -79.5, 60.0]), 14.2, {}, []
    for line in text.splitlines():
        words = {k: float(v) for k, v in re.findall(r"([XYZAC])(-?[\d.]+)", line.split("(")[0])}
        if line.startswith("G38.2"):
            a = np.array([at[k] for k in "XYZ"])
            d = np.array([words[k] for k in "XYZ"]) - a
            f = a - centre
            A, B, C = d @ d, 2 * f @ d, f @ f - rho * rho
            p = a + (-B - np.sqrt(B * B - 4 * A * C)) / (2 * A) * d
            log.append(" ".join(f"{v:.6f}" for v in p) + " 0 0 0 0 0 0")
        at.update(words)
    (tmp_path / "log.txt").write_text("\n".join(log) + "\n")
    ref = cli_json("probe-log", "-m", loop, "--locate", "--locate-within", 2.5, "--plan", tmp_path / "lp.csv",
                   "--log", tmp_path / "log.txt", "--program-coordinates", "tool-point", "--out", tmp_path / "cli-located.csv")
    got = mtcal.locate_spheres(m, mtcal.read_probing_plan(m, str(tmp_path / "lp.csv")), str(tmp_path / "log.txt"),
                               within=2.5, program_coordinates="tool-point")
    assert got.to_dict()["spheres"] == ref["spheres"]
    assert np.allclose(ref["spheres"][0]["centre"], centre, atol=1e-5)
    got.write(m, str(tmp_path / "py-located.csv"))
    data = lambda p: [l for l in p.read_text().splitlines() if not l.startswith("#")]  # noqa: E731
    assert data(tmp_path / "py-located.csv") == data(tmp_path / "cli-located.csv")
    (tmp_path / "short.txt").write_text("\n".join(log[:3]) + "\n")
    with pytest.raises(mtcal.InputError, match="contact 4 is missing"):
        mtcal.locate_spheres(m, plan, str(tmp_path / "short.txt"), within=2.5, program_coordinates="tool-point")


def test_compensate_states_its_commanded_range(tmp_path, vmc):
    # compensate --format linuxcnc-kins chooses the module's commanded travel (issue 33): as the command says.
    out = mtcal.compensate(vmc, "linuxcnc-kins", residual_points=3)
    ref = cli_json("compensate", "-m", MACHINES / "vmc-3axis.yaml", "--format", "linuxcnc-kins", "--residual-points", 3,
                   "--out", tmp_path / "lk")
    rows = out.commanded_range
    assert [r["axis"] for r in rows] == ["X", "Y", "Z"] and rows == ref["commanded_range"]
    assert all(not r["given"] and r["margin"] >= 1.25 * r["largest_correction"] for r in rows), rows
    assert mtcal.compensate(vmc, "linuxcnc", residual_points=3).commanded_range == []


def test_commanded_joints_put_the_actual_tool_on_the_commanded_point(hu40t):
    """inverse() against the exact model: the model's actual tool point at the joints found is the
    commanded point (to the solver's tolerance), and forward() gives it back."""
    s = mtcal.CommandedJointSolver(hu40t)
    assert mtcal.CommandedJointSolver.unsupported(hu40t) is None and s.rotary_count == 2
    rng = np.random.default_rng(7)
    lo = np.array([a.travel[0] for a in hu40t.axes])
    hi = np.array([a.travel[1] for a in hu40t.axes])
    q0 = lo + (hi - lo) * rng.uniform(0.2, 0.8, size=(20, hu40t.axis_count))
    tool = 100.0
    points, rotary = s.forward(q0, tool_length=tool)
    r = s.inverse(points, rotary, tool_length=tool)
    assert all(r["converged"]) and np.max(r["point_residual"]) < 1e-9
    np.testing.assert_allclose(r["q"], q0, atol=1e-9)
    m = mtcal.ErrorModel(hu40t.with_tool_length(tool))
    for q, p in zip(r["q"], points):
        assert np.allclose(m.actual_pose(q)[:3, 3], p, atol=1e-9)
    one = s.inverse(points[0], rotary[0], tool_length=tool)
    np.testing.assert_array_equal(one["q"], r["q"][0])
    with pytest.raises(ValueError, match="rotary"):
        s.inverse(points, tool_length=tool)


def test_commanded_joints_of_a_three_axis_machine(vmc):
    s = mtcal.CommandedJointSolver(vmc)
    assert s.rotary_count == 0 and s.rotary_axes == []
    q0 = np.array([[100.0, 50.0, -20.0], [-300.0, 200.0, -400.0]])
    points, rotary = s.forward(q0, tool_length=0.0)
    assert rotary.shape == (2, 0)
    r = s.inverse(points, tool_length=0.0)
    np.testing.assert_allclose(r["q"], q0, atol=1e-9)
    m = mtcal.ErrorModel(vmc.with_tool_length(0.0))
    np.testing.assert_allclose([m.actual_pose(q)[:3, 3] for q in r["q"]], points, atol=1e-9)
