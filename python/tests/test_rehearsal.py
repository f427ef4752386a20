"""A rehearsed calibration campaign (issue 33, docs/campaign.md) from Python against the command:
errors --draw, pose-check, campaign give the same JSON, and the files written are the same bytes.
"""
import re

import pytest

import mtcal
from conftest import EXAMPLES, MACHINES, assert_same, cli, cli_json

H = MACHINES / "hu40t-wCBXfYZt.yaml"
PLAN = EXAMPLES / "plans" / "hu40t-samba-tango.csv"
REACHED = EXAMPLES / "campaign" / "hu40t-reached-nominal.csv"
EST = "EC0Y,EB0Z,EA0Z,EX0C,EY0C,EA0C,EB0C"


def test_draw_errors_as_the_command(tmp_path, hu40t):
    d = mtcal.draw_errors(hu40t, 7, only=EST.split(","), tables=["ECC"], table_points=9)
    j = cli_json("errors", "-m", H, "--draw", 7, "--draw-only", EST, "--draw-table", "ECC",
                 "--draw-table-points", 9, "--out", tmp_path / "cli.yaml")
    assert_same(d.to_dict(), j["draw"], tol=0)
    d.write_truth(str(tmp_path / "py.yaml"), "Drawn by mtcal errors --draw 7 from machine " + str(H))
    assert (tmp_path / "py.yaml").read_text() == (tmp_path / "cli.yaml").read_text()
    assert mtcal.draw_errors(hu40t, 8).to_dict() != mtcal.draw_errors(hu40t, 7).to_dict()
    with pytest.raises(mtcal.InputError, match="only"):
        mtcal.draw_errors(hu40t, 1, only=["EX0Q"])
    with pytest.raises(ValueError, match="length_um"):
        mtcal.draw_errors(hu40t, 1, length_um=(50, 5))


def test_pose_check_and_campaign_as_the_command(tmp_path, hu40t, monkeypatch):
    truth = tmp_path / "truth.yaml"
    nominal = tmp_path / "nominal.yaml"
    cli("errors", "-m", H, "--draw", 3, "--draw-only", EST, "--out", truth, "--out-nominal", nominal)
    t = mtcal.Machine.load(str(H), params=[str(truth)])
    poses = mtcal.read_reached_poses(t, str(REACHED))
    c = mtcal.check_reached_poses(t, poses)
    assert_same(c.to_dict(per_pose=True),
                {k: v for k, v in cli_json("pose-check", "-m", H, "--params", truth, "--poses", REACHED,
                                           "--per-pose").items() if k != "machine"})
    assert c.errors.shape == (len(poses), 3)
    for name, params in (("before", truth), ("after", nominal)):
        cli("simulate", "-m", H, "--params", params, "--plan", PLAN, "--noise-um", 0.3, "--seed", 1,
            "--scale-bar", "1:2:304.8", "--out", tmp_path / f"{name}.csv")
    ident = cli("identify", "-m", H, "--params", nominal, "--measurements", tmp_path / "before.csv",
                "--estimate", EST, "--scale-bar", "1:2:304.8", "--json").stdout
    (tmp_path / "id.json").write_text(ident)
    n = mtcal.Machine.load(str(H), params=[str(nominal)])
    r = mtcal.campaign(n, mtcal.read_probing_plan(n, str(tmp_path / "before.csv")),
                       mtcal.read_probing_plan(n, str(tmp_path / "after.csv")),
                       identified=mtcal.read_identification_json(str(tmp_path / "id.json")), truth=t,
                       poses_before=poses, noise=0.3e-3)
    j = cli_json("campaign", "-m", H, "--params", nominal, "--before", tmp_path / "before.csv", "--after",
                 tmp_path / "after.csv", "--identified", tmp_path / "id.json", "--truth", truth,
                 "--poses-before", REACHED, "--noise-um", 0.3)
    assert_same(r.to_dict(), j)
    r.write_report(str(tmp_path / "c.html"))
    assert "Calibration campaign" in (tmp_path / "c.html").read_text()
    # write_report takes a campaign too, with the static copies of campaign --report-pdf/--report-png:
    # the same page (the note on static copies aside), its PDF through a stand-in for Chromium.
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1790000000")
    fake = tmp_path / "chromium"
    fake.write_text("#!/bin/sh\nfor a in \"$@\"; do case \"$a\" in\n"
                    "  --print-to-pdf=*) printf '%%PDF-1.4 stand-in\\n' > \"${a#--print-to-pdf=}\";;\n"
                    "esac; done\n")
    fake.chmod(0o755)
    monkeypatch.setenv("MTCAL_CHROMIUM", str(fake))
    r.write_report(str(tmp_path / "own.html"), command="mtcal campaign")
    mtcal.write_report(r, str(tmp_path / "any.html"), pdf=str(tmp_path / "any.pdf"), command="mtcal campaign")
    strip = lambda html: re.sub(r"<noscript>.*?</noscript>", "", html, flags=re.S)  # noqa: E731
    assert strip((tmp_path / "any.html").read_text()) == strip((tmp_path / "own.html").read_text())
    assert (tmp_path / "any.pdf").read_bytes().startswith(b"%PDF-1.4 stand-in")
    with pytest.raises(ValueError, match="truth"):
        mtcal.campaign(n, mtcal.read_probing_plan(n, str(tmp_path / "before.csv")),
                       mtcal.read_probing_plan(n, str(tmp_path / "after.csv")), poses_before=poses)
