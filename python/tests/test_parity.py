"""Parity: every command of `mtcal --help` (and every `compensate --format` target, every `history`
subcommand) has its Python face, or an explicit exception documented in docs/python.md.

The command list is read from the built command's help, so a new command fails this test until its
entry is added here (and its function bound, tested against the command and listed in docs/python.md).
"""
import re

import mtcal
from conftest import REPO, cli

# Command -> the functions (or Class.method) of mtcal that do its work.
PARITY = {
    "eval": ["evaluate", "ErrorModel.evaluate", "evaluate_configurations", "Machine.parse_joints", "read_configurations",
             "write_errors_csv", "write_report"],
    "errors": ["Machine.parameter_table", "Machine.to_dict", "write_report", "draw_errors", "ErrorDraw.write_truth",
               "ErrorDraw.write_nominal"],
    "effects": ["effects", "write_report"],
    "rotary-axis": ["read_contacts_csv", "read_centres_csv", "rotary_axis", "RotaryAxisResult.write_parameters", "write_report"],
    "probe-sim": ["simulate_sphere_probing"],
    "linuxcnc-probe": ["linuxcnc_probe", "LinuxcncProbe.write"],
    "iso230-2": ["read_positioning", "iso230_2", "evaluate_tolerances", "write_report"],
    "ballbar": ["read_ballbar_csv", "ballbar", "predict_ballbar", "ballbar_parameters", "write_parameters",
                "evaluate_tolerances", "write_report"],
    "fit-motion": ["fit_motion", "read_laser_file", "MotionFitResult.write_parameters"],
    "compare": ["read_comparison_csv", "compare_methods", "write_report"],
    "volumetric": ["volumetric", "evaluate_tolerances", "write_report"],
    "contributions": ["contributions", "write_report"],
    "diagonals": ["diagonals", "write_report"],
    "toolpath": ["read_gcode", "toolpath", "ToolpathResult.write_csv", "write_report"],
    "compensate": ["compensate", "compensation_targets", "TargetOutput.write", "write_etalon", "read_etalon",
                   "CommandedJointSolver", "write_report", "correct_gcode", "CorrectedGcode.write"],
    "regress": ["fit_model", "compare_models", "write_report"],
    "predict": ["read_prediction_model", "read_prediction_points", "predict", "write_report"],
    "separate": ["separate_position", "separate_control"],
    "process-error": ["process_error"],
    "simulate": ["simulate"],
    "identify": ["identify", "write_report"],
    "identifiability": ["identifiability"],
    "plan": ["design_plan", "probing_part", "locate_plan", "locate_program"],
    "probe-log": ["read_probe_log", "measurements_from_contacts", "locate_spheres", "LocateResult.write"],
    "pose-check": ["read_reached_poses", "check_reached_poses"],
    "campaign": ["campaign", "read_identification_json", "CampaignResult.write_report"],
    "history": ["HistoryStore"],
    "history list": ["HistoryStore.list"],
    "history show": ["HistoryStore.show"],
    "history import": ["HistoryStore.import_", "HistoryStore.record"],
    "history export": ["HistoryStore.export"],
    "history event": ["HistoryStore.add_event", "HistoryStore.events"],
    "history diff": ["HistoryStore.diff"],
    "history trend": ["HistoryStore.trend", "write_report"],
    "history rank": ["HistoryStore.rank"],
}

# Work of a command that has no Python face, each with its reason; every one is listed in
# docs/python.md ("Not in Python").
EXCEPTIONS = {
    "serve": "a server (mtcal serve) is a program, not a function: Python reads and writes the same store with HistoryStore",
}


def subcommands(*cmd):
    """The subcommands a --help lists (the 'Subcommands:' block)."""
    text = cli(*cmd, "--help").stdout
    block = text.split("Subcommands:", 1)[1] if "Subcommands:" in text else ""
    names = []
    for line in block.splitlines():
        if not line.strip():
            if names:
                break
            continue
        m = re.match(r"^  ([a-z0-9][a-z0-9-]*)\s", line)
        if m:
            names.append(m.group(1))
    return names


def resolve(name):
    obj = mtcal
    for part in name.split("."):
        obj = getattr(obj, part)
    return obj


def test_every_command_has_its_python_face():
    commands = subcommands()
    assert "eval" in commands and "history" in commands, commands
    history = subcommands("history")
    assert "trend" in history, history
    listed = commands + [f"history {h}" for h in history]
    missing = [c for c in listed if c not in PARITY and c not in EXCEPTIONS]
    assert not missing, f"commands without a Python entry in test_parity.PARITY: {missing}"
    stale = [c for c in PARITY if c not in listed]
    assert not stale, f"PARITY names commands mtcal does not have: {stale}"
    for command, names in PARITY.items():
        for name in names:
            try:
                resolve(name)
            except AttributeError:
                raise AssertionError(f"{command}: mtcal.{name} does not exist")


def test_every_compensation_target_is_reachable():
    text = cli("compensate", "--help").stdout
    block = text.split("--format TEXT", 1)[1].split("\n  --", 1)[0]
    formats = re.findall(r"^\s{10,}([a-z][a-z0-9-]+)", block, flags=re.M)
    assert "linuxcnc" in formats and "linuxcnc-kins" in formats, formats
    assert list(mtcal.compensation_targets()) == formats


def test_exceptions_are_documented():
    doc = (REPO / "docs" / "python.md").read_text()
    section = doc.split("## Not in Python", 1)[1]
    for command in EXCEPTIONS:
        assert f"`{command}`" in section, f"docs/python.md, 'Not in Python', does not list {command}"
    for command in PARITY:
        assert f"`{command}`" in doc, f"docs/python.md does not list the command {command}"


def test_every_report_has_write_report():
    """A command (or history subcommand) whose --help offers --report lists write_report (or a
    result's write_report method) among its Python faces, so that a report added to a command fails here until Python writes it too."""
    commands = [c for c in subcommands() if c not in EXCEPTIONS]
    listed = [(c,) for c in commands] + [("history", h) for h in subcommands("history")]
    with_report = []
    for cmd in listed:
        if re.search(r"^\s+--report\b", cli(*cmd, "--help").stdout, flags=re.M):
            with_report.append(" ".join(cmd))
    assert "eval" in with_report and "history trend" in with_report, with_report
    # write_report(result, path) or the result's own method (CampaignResult.write_report).
    missing = [c for c in with_report
               if not any(f == "write_report" or f.endswith(".write_report") for f in PARITY.get(c, []))]
    assert not missing, f"commands with --report whose PARITY entry lacks write_report: {missing}"
