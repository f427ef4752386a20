"""Rotary-axis location from contacts, simulation, identification with covariance, identifiability:
to_dict() equals the command's --json."""
import math

import numpy as np
import pytest

import mtcal
from conftest import EXAMPLES, MACHINES, assert_same, cli, cli_error, cli_json

HU40T = MACHINES / "hu40t-wCBXfYZt.yaml"
PLAN = EXAMPLES / "plans" / "hu40t-samba-tango.csv"
EST = ["EC0Y", "EB0Z", "EA0Z", "EX0C", "EY0C", "EA0C", "EB0C", "EX0B", "EZ0B", "EA0B", "EC0B", "EXX.1", "EYY.1",
       "EZZ.1"]


def test_rotary_axis_from_contacts_equals_mtcal(hu40t, tmp_path):
    sim = mtcal.simulate_sphere_probing(hu40t, axis="C", angles=np.radians(np.arange(0, 360, 30)), noise=5e-4,
                                        seed=3)
    path = tmp_path / "contacts.csv"
    sim.write_csv(str(path))
    cli_path = tmp_path / "contacts-cli.csv"
    cli("probe-sim", "-m", HU40T, "--axis", "C", "--angles", "0:330:12", "--noise", "5e-4", "--seed", "3",
        "--out", cli_path)
    assert path.read_text() == cli_path.read_text()
    ref = cli_json("rotary-axis", "--axis", "C", "--contacts", path, "--sphere-diameter", "30",
                   "--stylus-diameter", "6", "--machine", HU40T)
    contacts = mtcal.read_contacts_csv(str(path), "C")
    r = mtcal.rotary_axis(contacts, axis="C", machine=hu40t, sphere_diameter=30, stylus_diameter=6)
    assert_same(r.to_dict(), ref)
    assert list(r.values) == ["EX0C", "EY0C", "EA0C", "EB0C", "radius", "tilt"]
    # the same contacts given as arrays
    again = mtcal.ContactSet(contacts.angles_deg, contacts.points, contacts.approaches, axis="C")
    assert_same(mtcal.rotary_axis(again, axis="C", machine=hu40t, sphere_diameter=30, stylus_diameter=6).to_dict(),
                ref, skip={"source", "seconds"})
    # parameter file: what --out writes
    out = tmp_path / "c.yaml"
    cli("rotary-axis", "--axis", "C", "--contacts", path, "--sphere-diameter", "30", "--stylus-diameter", "6",
        "--machine", HU40T, "--out", out)
    assert r.parameters_yaml() == out.read_text()


def test_rotary_axis_from_centres_and_bad_input():
    angles = np.radians([0, 90, 180, 270, 45])
    centres = np.c_[100 * np.cos(angles) + 0.01, 100 * np.sin(angles) - 0.02, np.zeros(5)]
    r = mtcal.rotary_axis(mtcal.IndexedCentres(angles, centres), axis="C", method="lsq")
    assert r.values["EX0C"] == pytest.approx(0.01, abs=1e-9) and r.values["EY0C"] == pytest.approx(-0.02, abs=1e-9)
    assert r.values["radius"] == pytest.approx(100, abs=1e-9)
    with pytest.raises(mtcal.InputError, match="3 centres|at least 3|centres"):
        mtcal.rotary_axis(mtcal.IndexedCentres(angles[:2], centres[:2]), axis="C")
    with pytest.raises(ValueError, match="axis: expected A, B or C"):
        mtcal.rotary_axis(mtcal.IndexedCentres(angles, centres), axis="X")
    with pytest.raises(ValueError, match=r"centres: expected 5 rows"):
        mtcal.IndexedCentres(angles, centres[:3])


def simulate(hu40t, tmp_path, noise=0.0):
    path = tmp_path / "m.csv"
    cli("simulate", "-m", HU40T, "--plan", PLAN, "--artefact-error-um", "50", "--scale-bar", "1:2:304.8",
        "--noise-um", str(noise * 1e3), "--seed", "7", "--out", path)
    return path


def test_simulate_equals_mtcal_simulate(hu40t, tmp_path):
    plan = mtcal.read_probing_plan(hu40t, str(PLAN))
    assert not plan.measured and len(plan) > 0
    s = mtcal.simulate(hu40t, plan, noise=1e-3, artefact_error=0.05, seed=7, scale_bars=["1:2:304.8"])
    ref = cli_json("simulate", "-m", HU40T, "--plan", PLAN, "--noise-um", "1", "--artefact-error-um", "50",
                   "--seed", "7", "--scale-bar", "1:2:304.8")
    assert_same(s.to_dict(), ref)
    # the measurement file it writes is what the command writes (comment aside)
    text = mtcal.probing_csv(hu40t, s.measurements)
    path = simulate(hu40t, tmp_path, 1e-3)
    body = [ln for ln in path.read_text().splitlines() if not ln.startswith("#")]
    assert text.splitlines() == body
    back = mtcal.parse_probing_plan(hu40t, text)
    assert back.measured and np.array_equal(back.configs, s.measurements.configs)


def test_identify_equals_mtcal_identify_with_covariance(hu40t, tmp_path):
    path = simulate(hu40t, tmp_path, 1e-3)
    ref = cli_json("identify", "-m", HU40T, "--measurements", path, "--estimate", ",".join(EST),
                   "--scale-bar", "1:2:304.8")
    meas = mtcal.read_probing_plan(hu40t, str(path))
    r = mtcal.identify(hu40t, meas, EST, scale_bars=["1:2:304.8"])
    assert_same(r.to_dict(), ref)
    assert r.converged and r.names == EST
    P = len(EST)
    assert r.covariance.shape == (P, P) and r.correlation.shape == (P, P)
    np.testing.assert_allclose(np.sqrt(np.diag(r.covariance)), r.uncertainties, rtol=1e-14)
    np.testing.assert_allclose(r.covariance, r.covariance.T, rtol=1e-12, atol=0)
    np.testing.assert_allclose(r.correlation, r.covariance / np.outer(r.uncertainties, r.uncertainties),
                               rtol=1e-12, atol=1e-12)
    assert np.all(np.linalg.eigvalsh(r.covariance) > 0)
    for name, (value, u) in r.parameters.items():
        assert ref["parameters"][name]["value"] == value
    # the identified machine evaluates as the command with the parameter file
    out = tmp_path / "id.yaml"
    r.write_parameters(str(out), str(path))
    cli("identify", "-m", HU40T, "--measurements", path, "--estimate", ",".join(EST), "--scale-bar", "1:2:304.8",
        "--out", tmp_path / "id-cli.yaml", "--report", tmp_path / "id-cli.html")
    assert out.read_text() == (tmp_path / "id-cli.yaml").read_text()
    # its report: the command's plots and tables (the summary block names the command's inputs)
    from test_campaign import report_parts
    mtcal.write_report(r, str(tmp_path / "id.html"))
    assert report_parts((tmp_path / "id.html").read_text()) == report_parts((tmp_path / "id-cli.html").read_text())
    at = "X=100,Y=50,Z=-20,B=30,C=90"
    e = mtcal.evaluate(r.machine, r.machine.parse_joints(at))
    assert_same(dict(zip(["dx", "dy", "dz", "rx", "ry", "rz"], e.tolist())),
                cli_json("eval", "-m", HU40T, "--params", out, "--at", at), tol=1e-9)


def test_identify_monte_carlo_and_truth(hu40t, tmp_path):
    path = simulate(hu40t, tmp_path, 1e-3)
    ws = "X=-300:300:3,Y=-250:250:3,Z=-300:300:3"
    args = ["identify", "-m", HU40T, "--measurements", path, "--estimate", "EX0C,EY0C,EXX.1", "--scale-bar",
            "1:2:304.8", "--monte-carlo", "5", "--seed", "2", "--workspace", ws, "--truth", HU40T]
    ref = cli_json(*args)
    meas = mtcal.read_probing_plan(hu40t, str(path))
    r = mtcal.identify(hu40t, meas, ["EX0C", "EY0C", "EXX.1"], scale_bars=["1:2:304.8"], monte_carlo=5, seed=2,
                       workspace=ws, truth=hu40t)
    assert_same(r.to_dict(), ref, tol=1e-9)
    assert r.monte_carlo["samples"].shape == (5, 3) and r.va == pytest.approx(ref["va"]["identified_mm"]
                                                                              if isinstance(ref["va"], dict)
                                                                              else ref["va"], rel=1e-9)


def test_identifiability_equals_mtcal(hu40t):
    plan = mtcal.read_probing_plan(hu40t, str(PLAN))
    est = EST + ["EX0X", "EXt"]
    ref = cli_json("identifiability", "-m", HU40T, "--plan", PLAN, "--estimate", ",".join(est), "--scale-bar",
                   "1:2:304.8")
    i = mtcal.identifiability(hu40t, plan, est, scale_bars=["1:2:304.8"])
    assert_same(i.to_dict(), ref)
    assert i.rank == ref["rank"] and len(i.unidentifiable) >= 1
    cand = ["EXX", "EXX.1", "EY0C", "EX0C", "EX0C"]
    ref = cli_json("identifiability", "-m", HU40T, "--plan", PLAN, "--candidates", ",".join(cand), "--choose", "2")
    s = mtcal.identifiability(hu40t, plan, candidates=cand, choose=2)
    assert_same(s.to_dict(), ref)


def test_identification_errors_are_the_librarys(hu40t, tmp_path):
    path = simulate(hu40t, tmp_path)
    meas = mtcal.read_probing_plan(hu40t, str(path))
    msg = cli_error("identify", "-m", HU40T, "--measurements", path, "--estimate", "EQQ")
    with pytest.raises(mtcal.InputError) as e:
        mtcal.identify(hu40t, meas, ["EQQ"])
    assert str(e.value) == msg.replace("--estimate", "estimate")
    plan = mtcal.read_probing_plan(hu40t, str(PLAN))
    msg = cli_error("identify", "-m", HU40T, "--measurements", PLAN, "--estimate", "EX0C")
    with pytest.raises(mtcal.InputError) as e:
        mtcal.identify(hu40t, plan, ["EX0C"])
    assert str(e.value) == msg
