"""Parity: every command of `mtcal --help` (and every `compensate --format` target, every `history`
subcommand) has its Python face, and every long option of every command its Python argument, or an
explicit exception documented in docs/python.md.

The command and option lists are read from the built command's help, so a new command or option
fails this test until its entry is added here (and its function or argument bound, tested against
the command and listed in docs/python.md).
"""
import functools
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
    "rotary-axis": ["read_contacts_csv", "read_contacts_log", "read_centres_csv", "rotary_axis",
                    "RotaryAxisResult.write_parameters", "write_report"],
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
    "campaign": ["campaign", "read_identification_json", "CampaignResult.write_report", "write_report"],
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


@functools.lru_cache(maxsize=None)
def help_text(*cmd):
    """A command's --help, read once for the tests of this file."""
    return cli(*cmd, "--help").stdout


def subcommands(*cmd):
    """The subcommands a --help lists (the 'Subcommands:' block)."""
    text = help_text(*cmd)
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
    text = help_text("compensate")
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
        if re.search(r"^\s+--report\b", help_text(*cmd), flags=re.M):
            with_report.append(" ".join(cmd))
    assert "eval" in with_report and "history trend" in with_report, with_report
    # write_report(result, path) or the result's own method (CampaignResult.write_report).
    missing = [c for c in with_report
               if not any(f == "write_report" or f.endswith(".write_report") for f in PARITY.get(c, []))]
    assert not missing, f"commands with --report whose PARITY entry lacks write_report: {missing}"


# ---------------------------------------------------------------- every option of every command

# Where each long option of a command (`mtcal CMD --help`, "Options:") is in Python: "func" (a function,
# class or Class.method of mtcal), "func(arg)" (an argument of it), or a list of those. The groups
# below are shared by the commands that have the options; the command's own table wins.
MODEL = {  # --machine --params --set --only --tool-length: the Machine the functions take
    "machine": "Machine.load", "params": ["Machine.load(params)", "Machine.with_parameter_file"],
    "set": "Machine.with_params", "only": "Machine.with_only", "tool-length": "Machine.with_tool_length",
}
REPORT = {  # --report and its static copies
    "report": "write_report", "report-pdf": "write_report(pdf)", "report-png": "write_report(png_dir)",
    "browser-timeout": "write_report(browser_timeout)", "meta": ["write_report(metadata)", "HistoryStore.record(metadata)"],
}
TOLERANCE = {
    "tolerance": "evaluate_tolerances(tolerances)", "tolerance-file": "evaluate_tolerances(tolerance_file)",
    "fail-on-tolerance": "AcceptanceVerdict.passed",
}
# On every command that has them.
EVERY = {
    "precision": "set_precision",
    "meta": "HistoryStore.record(metadata)",  # kept with the result where it is recorded (its to_dict() has none)
    "meta-file": "read_metadata_file",
}
GCODE_INPUT = ["interpreter", "rs274", "rs274-timeout", "tool-table", "tool-units", "parameters", "parameter-units",
               "work-offset", "g28", "g30"]


def gcode_input(func):
    names = {"work-offset": "work_offsets"}
    return {o: f"{func}({names.get(o, o.replace('-', '_'))})" for o in GCODE_INPUT}


CYCLE = ["approach", "touches", "ball-diameter", "tip-diameter", "overtravel", "clearance"]

OPTIONS = {
    "": {  # mtcal's own options, before the command
        "version": "__version__", "record": "HistoryStore.record",
    },
    "eval": {**MODEL, **REPORT, "at": ["Machine.parse_joints", "evaluate_configurations(configs)"],
             "points": "evaluate_configurations(points)", "grid": "evaluate_configurations(grid)",
             "out": "write_errors_csv", "no-travel-check": "evaluate_configurations(travel_check)",
             "threads": "evaluate_configurations(threads)"},
    "errors": {**MODEL, **REPORT, "nonzero": ["Machine.to_dict(nonzero)", "write_report(nonzero_only)"],
               "out": ["Machine.parameters_yaml", "ErrorDraw.write_truth"], "draw": "draw_errors(seed)",
               "draw-only": "draw_errors(only)", "draw-table": "draw_errors(tables)",
               "draw-table-points": "draw_errors(table_points)", "draw-length-um": "draw_errors(length_um)",
               "draw-angle-urad": "draw_errors(angle_urad)", "out-nominal": "ErrorDraw.write_nominal"},
    "effects": {**MODEL, **REPORT, "at": "effects(at)", "errors": "effects(errors)", "around": "effects(around)",
                "no-travel-check": "effects(travel_check)"},
    "rotary-axis": {**REPORT, "axis": ["rotary_axis(axis)", "read_contacts_csv(axis)"],
                    "contacts": ["read_contacts_csv", "read_contacts_log"],
                    "contacts-dialect": "read_contacts_log(dialect)", "centres": "read_centres_csv",
                    "sphere-diameter": "rotary_axis(sphere_diameter)", "stylus-diameter": "rotary_axis(stylus_diameter)",
                    "machine": ["rotary_axis(machine)", "read_contacts_log(machine)"], "method": "rotary_axis(method)",
                    "reject-sigma": "rotary_axis(reject_sigma)", "max-rms": "rotary_axis(max_rms)",
                    "bins": "rotary_axis(bins)", "threads": "rotary_axis(threads)",
                    "out": "RotaryAxisResult.write_parameters", "frame": "rotary_axis(frame)"},
    "probe-sim": {**MODEL, "axis": "simulate_sphere_probing(axis)", "angles": "simulate_sphere_probing(angles)",
                  "hold": "simulate_sphere_probing(held)", "sphere": "simulate_sphere_probing(sphere)",
                  "sphere-diameter": "simulate_sphere_probing(sphere_diameter)",
                  "stylus-diameter": "simulate_sphere_probing(stylus_diameter)",
                  "noise": "simulate_sphere_probing(noise)", "trigger-bias": "simulate_sphere_probing(trigger_bias)",
                  "seed": "simulate_sphere_probing(seed)", "out": "SimulatedContacts.write_csv"},
    "linuxcnc-probe": {**MODEL, "sphere": "linuxcnc_probe(spheres)", "sphere-diameter": "linuxcnc_probe(sphere_diameter)",
                       "stylus-diameter": "linuxcnc_probe(stylus_diameter)", "out": "LinuxcncProbe.write"},
    "iso230-2": {**REPORT, **TOLERANCE, "unit": "read_positioning(unit)", "target-unit": "read_positioning(target_unit)",
                 "format": "read_positioning(format)", "wrap": "read_positioning(wrap)"},
    "ballbar": {**REPORT, **TOLERANCE, "radius": "ballbar(radius)", "plane": "ballbar(plane)", "feed": "ballbar(feed)",
                "overshoot-start": "ballbar(overshoot_start)", "overshoot-stop": "ballbar(overshoot_stop)",
                "direction": "ballbar(direction)", "predict": "predict_ballbar", "machine": "predict_ballbar(machine)",
                "params": "Machine.load(params)", "centre": "predict_ballbar(centre)", "step-deg": "predict_ballbar(step)",
                "out": "write_ballbar_csv", "to-params": ["ballbar_parameters", "write_parameters"],
                "terms": ["ballbar_parameters(squareness)", "ballbar_parameters(scale)", "ballbar_parameters(backlash)"]},
    "fit-motion": {"out": "MotionFitResult.write_parameters", "form": "fit_motion(form)", "degree": "fit_motion(degree)",
                   "coverage": "fit_motion(coverage)", "unit": "fit_motion(unit)", "target-unit": "fit_motion(target_unit)",
                   "format": "fit_motion(format)", "wrap": "fit_motion(wrap)"},
    "compare": {**REPORT},
    "volumetric": {**MODEL, **REPORT, **TOLERANCE, "grid": "volumetric(grid)",
                   "points": ["read_configurations", "volumetric(configs)"],
                   "no-travel-check": "volumetric(travel_check)", "threads": "volumetric(threads)",
                   "box": "volumetric(box)", "box-scan": "volumetric(box_scan)", "centre": "volumetric(centre)",
                   "histogram": "volumetric(histogram)", "group-angle": "volumetric(grouping)",
                   "group-magnitude": "volumetric(grouping)", "out": "write_error_map_csv"},
    "contributions": {**MODEL, **REPORT, "grid": "contributions(grid)",
                      "points": ["read_configurations", "contributions(configs)"],
                      "no-travel-check": "contributions(travel_check)", "threads": "contributions(threads)",
                      "at": "contributions(at)", "pair": "contributions(pair)", "top": "ContributionResult.to_dict(top)",
                      "no-what-if": "contributions(what_if)", "target-va": "contributions(target_va)"},
    "diagonals": {**MODEL, **REPORT, "box": "diagonals(box)", "points": "diagonals(points)", "no-face": "diagonals(face)",
                  "no-travel-check": "diagonals(travel_check)", "out": "DiagonalsResult.write_csv"},
    "toolpath": {**MODEL, **REPORT, **gcode_input("toolpath"), "gcode": "toolpath(program)", "step": "toolpath(step)",
                 "angle-step": "toolpath(angle_step)", "origin": "toolpath(origin)",
                 "skip-rapids": "toolpath(skip_rapids)", "no-direction": "toolpath(directions)",
                 "no-travel-check": "toolpath(travel_check)", "threads": "toolpath(threads)",
                 "out": "ToolpathResult.write_csv"},
    "compensate": {**MODEL, **REPORT, **gcode_input("correct_gcode"), "gcode": "correct_gcode(program)",
                   "out": ["TargetOutput.write", "CorrectedGcode.write"],
                   "max-deviation": "correct_gcode(max_deviation)", "linearise-arcs": "correct_gcode(linearise_arcs)",
                   "origin": "correct_gcode(origin)", "decimals": "correct_gcode(decimals)",
                   "no-direction": "correct_gcode(directions)", "no-orientation": "correct_gcode(orientation)",
                   "no-travel-check": "correct_gcode(travel_check)", "format": "compensate(target)",
                   "points": "compensate(points)", "range": ["compensate(sampling)", "AxisSampling"],
                   "reference": "compensate(reference)", "linuxcnc-type": "compensate(linuxcnc_type)",
                   "skew-reference-length": "compensate(skew_reference_length)",
                   "fanuc-unit": "compensate(fanuc_unit)", "residual-points": "compensate(residual_points)",
                   "threads": "compensate(threads)", "report": "write_report(machine)"},
    "regress": {**REPORT, "x": ["compare_models(x)", "compare_models(x_name)"],
                "y": ["compare_models(y)", "compare_models(y_name)"], "models": "compare_models(models)"},
    "predict": {**REPORT, "model": "read_prediction_model", "points": "read_prediction_points",
                "gcode": ["read_gcode", "points_from_gcode"], "start-time": "points_from_gcode(start_time)",
                "speed": "points_from_gcode(speed)", "rapid-feed": "points_from_gcode(rapid_feed)",
                "set": "predict(constants)", "strict": "predict(strict)", "out": "PredictionRun.csv",
                "compensation": ["predict(compensation)", "PredictionRun.compensation_csv"]},
    "separate": {"a": "separate_control(a)", "b": "separate_control(b)", "model": "separate_control(model)",
                 "out": ["PositionSeparation.csv", "ControlSeparation.csv"]},
    "process-error": {"feed": "process_error(feeds)", **{o: "process_error(cut)" for o in
                                                          ["speed", "ae", "ap", "up-milling"]},
                      **{o: "process_error(tool)" for o in ["diameter", "teeth", "helix", "overhang", "flute-length",
                                                            "flute-ratio", "young"]},
                      **{o: "process_error(coefficients)" for o in ["ktc", "krc", "kte", "kre"]},
                      "measured": "process_error(measured)", "form": "process_error(form)"},
    "simulate": {**MODEL, "plan": "read_probing_plan", "noise-um": "simulate(noise)",
                 "artefact-error-um": "simulate(artefact_error)", "seed": "simulate(seed)",
                 "scale-bar": "simulate(scale_bars)", "out": "write_probing_csv"},
    "identify": {**MODEL, **REPORT, "measurements": "read_probing_plan", "estimate": "identify(estimate)",
                 "scale-bar": "identify(scale_bars)", "pretravel": "identify(pretravel)", "sigma-um": "identify(sigma)",
                 "rank-tolerance": "identify(rank_tolerance)", "loss": "identify(loss)",
                 "monte-carlo": "identify(monte_carlo)", "seed": "identify(seed)", "workspace": "identify(workspace)",
                 "truth": "identify(truth)", "threads": "identify(threads)", "out": "IdentificationRun.write_parameters",
                 "require-fit": "identify(require_fit)"},
    "identifiability": {**MODEL, "plan": "read_probing_plan", "estimate": "identifiability(estimate)",
                        **{o: f"identifiability({o.replace('-', '_')})" for o in
                           ["pretravel", "rank-tolerance", "choose", "candidates", "always", "list", "sort", "threads"]},
                        "scale-bar": "identifiability(scale_bars)", "sigma-um": "identifiability(sigma)"},
    "plan": {**MODEL, **{o: f"design_plan({o.replace('-', '_')})" for o in
                         ["estimate", "choose", "candidates", "against", "poses", "target-u", "target-va-u", "workspace",
                          "criterion", "ball-region", "ball-spacing", "max-tilt-deg", "stylus-length", "holder-radius",
                          "table-z", "rapid", "rotary-speed", "probe-feed", "monte-carlo", "seed", "threads",
                          "move-feed", *CYCLE]},
             "scale-bar": "design_plan(scale_bars)", "sigma-um": "design_plan(sigma)",
             "artefact": ["read_probing_plan", "design_plan(artefact)"], "va-tie-um": "design_plan(va_tie)",
             "rotary-step-deg": "design_plan(rotary_step)", "out": ["PlanResult.plan", "write_probing_csv"],
             "gcode": "probe_program", "dialect": "probe_program(dialect)", "log-name": "probe_program(log)",
             "program-coordinates": ["design_plan(program_coordinates)", "probe_program(program_coordinates)"],
             "ballbar": "design_plan(ballbar)", "ballbar-points": "design_plan(ballbar_points)",
             "ballbar-feed": "design_plan(ballbar_feed)", "ballbar-setup-s": "design_plan(ballbar_setup)",
             "laser": "design_plan(laser)", "laser-points": "design_plan(laser_points)",
             "laser-setup-s": "design_plan(laser_setup)", "laser-dwell-s": "design_plan(laser_dwell)",
             "locate": ["locate_plan", "locate_program"], "locate-within": "locate_program(within)",
             "locate-at": "locate_plan(at)"},
    "probe-log": {**MODEL, "plan": "read_probing_plan", "log": ["read_probe_log", "measurements_from_contacts(log)"],
                  "dialect": "measurements_from_contacts(dialect)",
                  "program-coordinates": "measurements_from_contacts(program_coordinates)",
                  **{o: f"measurements_from_contacts({o.replace('-', '_')})" for o in CYCLE},
                  "out": ["write_probing_csv", "LocateResult.write"], "locate": "locate_spheres",
                  "locate-within": "locate_spheres(within)"},
    "pose-check": {**MODEL, "tool-length": ["Machine.with_tool_length", "check_reached_poses(tool_length)"],
                   "poses": "read_reached_poses", "per-pose": "PoseCheck.to_dict(per_pose)"},
    "campaign": {**MODEL, **REPORT, "report": ["CampaignResult.write_report", "write_report"],
                 "before": ["read_probing_plan", "campaign(before)"], "after": "campaign(after)",
                 "identified": ["read_identification_json", "campaign(identified)"], "truth": "campaign(truth)",
                 "poses-before": ["read_reached_poses", "campaign(poses_before)"],
                 "poses-after": "campaign(poses_after)", "reference": "campaign(reference)",
                 "noise-um": "campaign(noise)"},
    "history": {},
    "history list": {"machine": "HistoryStore.list(machine)", "command": "HistoryStore.list(command)",
                     "from": "HistoryStore.list(from_)", "to": "HistoryStore.list(to)"},
    "history show": {},
    "history import": {"command": "HistoryStore.import_(command)", "meta": "HistoryStore.import_(metadata)"},
    "history export": {"out": "HistoryStore.export(path)"},
    "history event": {},
    "history event add": {"machine": "HistoryStore.add_event(machine)", "date": "HistoryStore.add_event(date)",
                          "kind": "HistoryStore.add_event(kind)", "note": "HistoryStore.add_event(note)"},
    "history diff": {"coverage-factor": "HistoryStore.diff(coverage_factor)"},
    "history trend": {"report": "write_report", "machine": "HistoryStore.trend(machine)",
                      "parameter": "HistoryStore.trend(parameters)", "figure": "HistoryStore.trend(figures)",
                      "tolerance": "HistoryStore.trend(tolerances)",
                      "tolerance-file": "HistoryStore.trend(tolerance_file)", "from": "HistoryStore.trend(from_)",
                      "to": "HistoryStore.trend(to)"},
    "history rank": {"tolerance": "HistoryStore.rank(tolerances)", "tolerance-file": "HistoryStore.rank(tolerance_file)",
                     "by": "HistoryStore.rank(by)", "threads": "HistoryStore.rank(threads)"},
}
# Every history subcommand opens its store as HistoryStore(connection) does.
for _cmd, _table in OPTIONS.items():
    if _cmd.startswith("history"):
        _table.setdefault("store", "HistoryStore")

# Options with no Python argument, each with its reason; every one is listed in docs/python.md
# ("Not in Python"). Keyed by option (every command) or "command --option".
OPTION_EXCEPTIONS = {
    "json": "the result's to_dict() is the command's --json (same keys); a function returns it, nothing is printed",
    "verbose": "the nonlinear solver's log on stderr is the command's; Python is quiet",
    "max-memory": "the command's refusal of a computation estimated too large; a Python program is limited as any",
    "max-time": "the command's refusal of a computation estimated too long; Ctrl-C stops a Python call",
    "max-output-size": "the command's limit on a streamed output file; Python writes what it is asked to",
    "max-input-size": "the command's limit on input files; the readers keep the library's default (256 MiB, YAML 16 MiB)",
    "no-record": "Python records only what HistoryStore.record is given",
    "volumetric --grid-kernel": "a speed option of the command's streamed evaluation; volumetric() evaluates the map "
                                "in memory configuration by configuration (the command's default numbers)",
    "contributions --grid-kernel": "as volumetric's: contributions() evaluates the map configuration by configuration",
}


# The shared groups as docs/python.md's "Options by command" lists them once each.
GROUPS = {"every command": EVERY, "model options": MODEL, "report options": REPORT, "tolerances": TOLERANCE}


def shared_group(option, entry):
    """The shared group whose entry for this option a command's table uses, or None (its own entry)."""
    return next((label for label, group in GROUPS.items() if group.get(option) == entry), None)


def options(*cmd):
    """The long options of a --help's "Options:" block (not its examples), without --help."""
    text = help_text(*cmd)
    block = text.split("Options:", 1)[1]
    block = re.split(r"\n(?:Subcommands|Examples|Positionals)[^\n]*:", block)[0]
    names = re.findall(r"^  (?:-[A-Za-z],)?--([a-z0-9][a-z0-9-]*)", block, flags=re.M)
    return [n for n in names if n != "help"]


def commands_with_options():
    listed = [()] + [(c,) for c in subcommands() if c not in EXCEPTIONS]
    for h in subcommands("history"):
        listed.append(("history", h))
        listed += [("history", h, s) for s in subcommands("history", h)]
    return listed


def arguments(obj):
    """The argument names of a function or method of the module, from every signature of its docstring."""
    doc = getattr(obj, "__doc__", None) or ""
    name = getattr(obj, "__name__", "")
    found = set()
    for m in re.finditer(rf"^(?:\d+\. )?{re.escape(name)}\((.*)\) ->", doc, flags=re.M):
        for part in re.findall(r"(?:^|, )\*{0,2}(\w+)(?=:|$|,)", m.group(1)):
            found.add(part)
    return found


def face_exists(face):
    """'func', 'Class.method' or 'func(arg)': whether mtcal has it."""
    m = re.match(r"^([\w.]+)(?:\((\w+)\))?$", face)
    assert m, f"unreadable table entry {face!r}"
    try:
        obj = resolve(m.group(1))
    except AttributeError:
        return False
    if m.group(2) is None:
        return True
    if isinstance(obj, type):
        obj = obj.__init__
    return m.group(2) in arguments(obj)


def test_every_option_has_its_python_argument():
    missing, stale, absent = [], [], []
    seen = 0
    for cmd in commands_with_options():
        key = " ".join(cmd)
        table = {**EVERY, **OPTIONS.get(key, {})}
        have = options(*cmd)
        seen += len(have)
        for o in have:
            if o in OPTION_EXCEPTIONS or f"{key} --{o}" in OPTION_EXCEPTIONS:
                continue
            if o not in table:
                missing.append(f"{key or 'mtcal'} --{o}")
                continue
            faces = table[o] if isinstance(table[o], list) else [table[o]]
            absent += [f"{key or 'mtcal'} --{o}: mtcal.{f}" for f in faces if not face_exists(f)]
        stale += [f"{key} --{o}" for o in OPTIONS.get(key, {}) if o not in have and o not in EVERY
                  and o not in MODEL and o not in REPORT and o not in TOLERANCE and o != "store"]
    assert seen > 300, seen
    assert not missing, f"options without a Python entry in test_parity.OPTIONS (or OPTION_EXCEPTIONS): {missing}"
    assert not absent, f"table entries mtcal lacks: {absent}"
    assert not stale, f"OPTIONS names options the commands do not have: {stale}"


def test_option_table_reads_what_it_checks():
    """The checker itself: a known argument is found, an unknown one is not."""
    assert face_exists("toolpath(tool_table)") and face_exists("HistoryStore.list(from_)")
    assert face_exists("Machine.load(params)") and face_exists("write_report(pdf)")
    assert not face_exists("toolpath(no_such_argument)") and not face_exists("no_such_function")
    assert "require_fit" in arguments(mtcal.identify)


def test_options_and_their_exceptions_are_documented():
    doc = (REPO / "docs" / "python.md").read_text()
    section = doc.split("## Not in Python", 1)[1].split("\n## ", 1)[0]
    for option in OPTION_EXCEPTIONS:
        words = option.split(" ")
        named = f"`--{words[0]}`" if len(words) == 1 else f"`{option}`"
        assert named in section, f"docs/python.md, 'Not in Python', does not list {named}"
    # "Options by command": a row per command (and one per shared group) naming each option it maps.
    table = doc.split("## Options by command", 1)[1].split("\n## ", 1)[0]
    rows = {}
    for line in table.splitlines():
        cells = line.split(" | ")
        if line.startswith("| ") and len(cells) >= 2:
            rows[cells[0][2:].strip().strip("`")] = line
    undocumented = []
    for cmd in commands_with_options():
        key = " ".join(cmd)
        own = {**EVERY, **OPTIONS.get(key, {})}
        for o in options(*cmd):
            if o in OPTION_EXCEPTIONS or f"{key} --{o}" in OPTION_EXCEPTIONS or o not in own:
                continue
            group = shared_group(o, own[o])
            row = rows.get(f"({group})" if group else (key or "mtcal"), "")
            if f"`--{o}`" not in row:
                undocumented.append(f"{key or 'mtcal'} --{o}")
    assert not undocumented, f"docs/python.md, 'Options by command', does not list: {undocumented}"
