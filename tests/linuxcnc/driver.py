#!/usr/bin/python3
# DISPLAY program of mtcal's LinuxCNC test (tests/linuxcnc/run): drives the sim through the moves of
# plan.json with the `linuxcnc` Python module and reads, after each move, what the motion
# controller applies, with the `hal` module (doubles, full precision). Writes readings.json.
# A move may bring MDI lines to run before it ("before": a tool change, G43, G49) and its motion
# words ("motion": default "G53 G1", machine coordinates; "G90 G1" commands program coordinates,
# where G43's tool offset applies).
# With "program" in plan.json (tests/linuxcnc/run-probe) it runs that G-code file in AUTO mode
# instead and records the messages LinuxCNC reports; with "program" and "moves" (examples/loop) the
# program first, then the moves.
#
# LinuxCNC starts it as `driver.py -ini FILE` from the configuration's folder (the linuxcnc script
# runs [DISPLAY]DISPLAY there); its exit status becomes LinuxCNC's.
#
# What is read, per joint n (LinuxCNC 2.9, src/emc/motion/control.c, output_to_hal()):
#   motor-pos-cmd = pos-cmd + backlash-filt + motor-offset
# so motor-pos-cmd - pos-cmd - motor-offset is the compensation the controller adds to the joint.
# backlash-filt is a ramped copy of backlash-corr (compute_screw_comp()); the driver waits until
# they are equal, i.e. the correction has settled, before it reads.
import json
import os
import subprocess
import sys
import time

import hal
import linuxcnc

# Timeouts for an idle machine. On a loaded one they stretch with the load (load_scale()): the sim is
# not real-time (rtapi_app says "Using POSIX non-realtime"), so every LinuxCNC thread waits its turn.
STARTUP_TIMEOUT_S = 30.0
MOVE_TIMEOUT_S = 30.0
SETTLE_TIMEOUT_S = 2.0
MAX_LOAD_SCALE = 4.0
# The end of a program: LinuxCNC's state must say so in this many polls in a row (10 ms apart).
END_POLLS = 5


def load_scale():
    """How much longer than on an idle machine a timeout waits: the 1-minute load average per core,
    between 1 and MAX_LOAD_SCALE. Read again at each check, so a load that rises mid-run counts."""
    try:
        per_core = os.getloadavg()[0] / (os.cpu_count() or 1)
    except OSError:
        return 1.0
    return min(MAX_LOAD_SCALE, max(1.0, per_core))


def fail(msg):
    print("driver: " + msg, file=sys.stderr, flush=True)
    sys.exit(1)


def names(prefix):
    """The linuxcnc module's constants of one kind by value: INTERP_IDLE ... for the words below."""
    return {getattr(linuxcnc, n): n for n in dir(linuxcnc) if n.startswith(prefix) and isinstance(getattr(linuxcnc, n), int)}


STATE_NAMES = {"task_state": names("STATE_"), "task_mode": names("MODE_"), "interp_state": names("INTERP_"),
               "exec_state": names("EXEC_"), "state": names("RCS_")}


def state_words(s):
    """LinuxCNC's own state, from its stat channel and motion's HAL pins: what a timeout reports, so
    that it says which part stopped (the interpreter waiting, task waiting for motion, motion's queue,
    the servo thread)."""
    try:
        s.poll()
    except linuxcnc.error as e:
        return "the stat channel does not answer (%s)" % e
    words = ["%s %s" % (k, STATE_NAMES[k].get(getattr(s, k), getattr(s, k))) for k in STATE_NAMES]
    words += ["motion queue %d%s" % (s.queue, " (full)" if s.queue_full else ""), "in position %s" % bool(s.inpos),
              "line read %d, in motion %d" % (s.read_line, s.motion_line),
              "probing %s, probe tripped %s" % (bool(s.probing), bool(s.probe_tripped))]
    # The servo thread: motion.servo.last-period is its last cycle's length (CPU clocks), written each
    # cycle; unchanged over 0.2 s means the thread did not run.
    try:
        periods = set()
        for _ in range(20):
            periods.add(hal.get_value("motion.servo.last-period"))
            time.sleep(0.01)
        words.append("servo thread %s" % ("running" if len(periods) > 1 else "not running over 0.2 s (motion.servo.last-period unchanged)"))
    except Exception as e:  # the HAL no longer answers
        words.append("HAL does not answer (%s)" % e)
    if os.path.exists("mtcal-contacts.txt"):
        with open("mtcal-contacts.txt") as f:
            words.append("%d contacts logged" % sum(1 for line in f if line.strip()))
    words.append("load %.1f" % os.getloadavg()[0])
    return "; ".join(words)


def wait(predicate, timeout, what, s=None):
    t0 = time.time()
    while not predicate():
        if time.time() - t0 > timeout * load_scale():
            fail("timed out after %.0f s waiting for %s%s" % (time.time() - t0, what, ": LinuxCNC: " + state_words(s) if s else ""))
        time.sleep(0.005)


def snapshot(joints):
    g = hal.get_value
    return [{"pos_cmd": g("joint.%d.pos-cmd" % j),
             "motor_pos_cmd": g("joint.%d.motor-pos-cmd" % j),
             "motor_offset": g("joint.%d.motor-offset" % j),
             "backlash_corr": g("joint.%d.backlash-corr" % j),
             "backlash_filt": g("joint.%d.backlash-filt" % j)} for j in range(joints)]


def errors_in(messages):
    return [m for m in messages if m["kind"] in (linuxcnc.NML_ERROR, linuxcnc.OPERATOR_ERROR)]


def run_program(plan, c, s, err, stat):
    """AUTO mode: runs plan["program"] to its end (or until LinuxCNC stops it) and writes
    readings.json with the operator messages and errors LinuxCNC reported (e.g. "G38.2 move finished
    without making contact"), whether the program ran to its end, and the time it took."""
    path = os.path.abspath(plan["program"])
    c.mode(linuxcnc.MODE_AUTO)
    c.wait_complete()
    c.program_open(path)
    t0 = time.time()
    c.auto(linuxcnc.AUTO_RUN, 0)
    messages, started, ended = [], False, 0
    timeout = plan.get("timeout", 240)
    while True:
        stat()
        m = err.poll()
        if m:
            messages.append({"kind": m[0], "text": m[1]})
        # The end, in LinuxCNC's own words: the interpreter idle, task's execution done, motion's
        # queue empty and the controller in position (RCS_DONE) — END_POLLS times in a row, so that
        # one moment of task's status between two blocks is not taken for the end.
        at_rest = (s.interp_state == linuxcnc.INTERP_IDLE and s.exec_state == linuxcnc.EXEC_DONE and s.queue == 0
                   and s.inpos and s.state == linuxcnc.RCS_DONE)
        if s.interp_state != linuxcnc.INTERP_IDLE:
            started = True
        ended = ended + 1 if started and at_rest else 0
        if ended >= END_POLLS or (started and errors_in(messages) and s.interp_state == linuxcnc.INTERP_IDLE):
            break
        if not started and errors_in(messages):
            break
        if not started and time.time() - t0 > STARTUP_TIMEOUT_S * load_scale():
            # Under load the interpreter can take seconds to leave IDLE after AUTO_RUN: a fixed 2 s
            # here once took a program that had not started for one that had ended.
            fail("the program %s did not start within %.0f s: LinuxCNC: %s" % (path, time.time() - t0, state_words(s)))
        if time.time() - t0 > timeout * load_scale():
            fail("the program %s did not end within %.0f s (%d s at load %.1f on %d cores): LinuxCNC: %s%s" % (
                path, time.time() - t0, timeout, os.getloadavg()[0], os.cpu_count() or 1, state_words(s),
                "; it said: " + "; ".join(m["text"] for m in messages) if messages else "; it said nothing"))
        time.sleep(0.01)
    seconds = time.time() - t0
    t1 = time.time()
    while time.time() - t1 < 0.3:  # errors queued as the program stopped
        m = err.poll()
        if m:
            messages.append({"kind": m[0], "text": m[1]})
        time.sleep(0.01)
    errors = [m for m in messages if m["kind"] in (linuxcnc.NML_ERROR, linuxcnc.OPERATOR_ERROR)]
    stat()
    end = {"joint_position": list(s.joint_position[:plan["joints"]]), "position": list(s.position[:9]),
           "tool_offset": list(s.tool_offset[:9]),
           "pos_cmd": [hal.get_value("joint.%d.pos-cmd" % j) for j in range(plan["joints"])]}
    print("driver: program %s %s in %.1f s" % (os.path.basename(path), "ran to its end" if not errors else
                                                "stopped: " + "; ".join(m["text"] for m in errors), seconds), flush=True)
    return {"program": path, "messages": messages, "completed": not errors, "program_seconds": seconds, "end": end,
            "readings": []}


def main():
    with open("plan.json") as f:
        plan = json.load(f)
    joints = plan["joints"]
    letters = plan["coordinates"]  # "XYZ", "XYZAC" ...

    comp = hal.component("mtcal-driver")  # hal.get_value needs a component of this process
    comp.ready()
    s = linuxcnc.stat()
    c = linuxcnc.command()
    err = linuxcnc.error_channel()

    def stat():
        s.poll()
        return s

    # Up and idle: task in ESTOP, interpreter idle (as LinuxCNC's own tests wait, tests/abort/*).
    wait(lambda: stat().task_state == linuxcnc.STATE_ESTOP and s.exec_state == linuxcnc.EXEC_DONE
         and s.interp_state == linuxcnc.INTERP_IDLE and s.joints == joints,
         STARTUP_TIMEOUT_S, "LinuxCNC to start", s)
    c.state(linuxcnc.STATE_ESTOP_RESET)
    c.state(linuxcnc.STATE_ON)
    c.wait_complete()
    c.home(-1)  # HOME_SEARCH_VEL = 0: every joint homes where it stands, at 0
    wait(lambda: all(stat().homed[j] for j in range(joints)), MOVE_TIMEOUT_S, "homing", s)
    c.mode(linuxcnc.MODE_MDI)
    c.wait_complete()
    # Feed and rapid overrides at 100 %, as a GUI sets them. They scale the ramp that brings the
    # applied correction (backlash-filt) to the table's value (control.c, compute_screw_comp(): v_max =
    # 0.5 * vel_limit * net_feed_scale); with the scale at 0 the correction would never be applied.
    print("driver: overrides at start: feed %.3f, rapid %.3f" % (stat().feedrate, s.rapidrate), flush=True)
    c.feedrate(1.0)
    c.rapidrate(1.0)
    wait(lambda: stat().feedrate == 1.0 and s.rapidrate == 1.0, STARTUP_TIMEOUT_S, "feed and rapid overrides at 100 %", s)

    result = {"readings": []}
    if "program" in plan:
        # With "moves" too (examples/loop: the probing program, then the random-pose check on the same
        # kinematics), the moves follow a program that ran to its end.
        result = run_program(plan, c, s, err, stat)
        if not plan.get("moves") or not result["completed"]:
            with open("readings.json", "w") as f:
                json.dump(result, f, indent=1)
            c.state(linuxcnc.STATE_OFF)
            c.wait_complete()
            return 0
        c.mode(linuxcnc.MODE_MDI)
        c.wait_complete()
        # The moves after a probing program go anywhere over the travel, through the simulated probe's
        # sphere too: LinuxCNC would stop them ("Probe tripped during non-probe move"). Its pin is
        # unlinked for them (halcmd, LinuxCNC's own HAL command).
        if plan.get("unlink_probe_for_moves"):
            subprocess.run(["halcmd", "unlinkp", "motion.probe-input"], check=True)

    g = hal.get_value

    def settled():
        return all(g("joint.%d.backlash-filt" % j) == g("joint.%d.backlash-corr" % j) for j in range(joints))

    readings = []
    t_moves = time.time()
    for k, move in enumerate(plan["moves"]):
        # MDI lines before the move (a tool change, G43, G49), each run to its end.
        for line in move.get("before", []):
            c.mdi(line)
            if c.wait_complete(MOVE_TIMEOUT_S * load_scale()) == -1:
                fail("MDI %r before move %d did not complete: LinuxCNC: %s" % (line, k, state_words(s)))
            wait(lambda: stat().exec_state == linuxcnc.EXEC_DONE and s.interp_state == linuxcnc.INTERP_IDLE,
                 MOVE_TIMEOUT_S, "MDI %r to end" % line, s)
            msg = err.poll()
            if msg:
                fail("LinuxCNC error after MDI %r: %s" % (line, msg[1]))
        # G53 G1 (machine coordinates: LinuxCNC's world, no tool offset) unless the move says "G90 G1"
        # (program coordinates: G54, which these configurations leave at 0, plus the tool offset).
        words = " ".join("%s%.9f" % (letter, move["target"][i]) for i, letter in enumerate(letters))
        c.mdi("%s %s F%.0f" % (move.get("motion", "G53 G1"), words, plan["feed"]))
        if c.wait_complete(MOVE_TIMEOUT_S * load_scale()) == -1:
            said = []
            for _ in range(20):  # what LinuxCNC said, if anything (a joint limit, a kinematics failure)
                msg = err.poll()
                if msg:
                    said.append(msg[1])
                time.sleep(0.01)
            fail("move %d (%s) did not complete within %.0f s%s; LinuxCNC's state: %s" % (
                k, words, MOVE_TIMEOUT_S * load_scale(), ": LinuxCNC: " + "; ".join(said) if said else " (LinuxCNC said nothing)",
                state_words(s)))
        wait(lambda: stat().inpos and s.exec_state == linuxcnc.EXEC_DONE, MOVE_TIMEOUT_S, "move %d in position" % k, s)
        msg = err.poll()
        if msg:
            fail("LinuxCNC error after move %d (%s): %s" % (k, words, msg[1]))
        if not move.get("read", True):
            continue
        # Stopped and settled: every joint's velocity command 0, the correction equal to the table's
        # value, and nothing changed over 20 servo cycles (the status flags can say "in position"
        # a few cycles before the last micrometre of the move, seen here).
        t0 = time.time()
        while True:
            t1 = time.time()
            while not settled():
                if time.time() - t1 > SETTLE_TIMEOUT_S:
                    fail("the correction did not settle %.0f s after move %d (%s): backlash-corr / backlash-filt %s"
                         % (SETTLE_TIMEOUT_S, k, words, ", ".join("j%d %.9f / %.9f" % (j, g("joint.%d.backlash-corr" % j),
                                                                                      g("joint.%d.backlash-filt" % j)) for j in range(joints))))
                time.sleep(0.005)
            before = snapshot(joints)
            time.sleep(0.02)
            after = snapshot(joints)
            if before == after and all(g("joint.%d.vel-cmd" % j) == 0.0 for j in range(joints)):
                break
            if time.time() - t0 > MOVE_TIMEOUT_S * load_scale():
                fail("joints still moving %.0f s after move %d: LinuxCNC: %s" % (time.time() - t0, k, state_words(s)))
        r = {"label": move.get("label", ""), "target": move["target"], "joints": after,
             "seconds": time.time() - t_moves}  # since the first move: what each part of a run costs
        stat()
        r["world"] = list(s.position[:9])
        r["actual"] = list(s.actual_position[:9])  # kinematicsForward of the joints' feedback
        r["joint_position"] = list(s.joint_position[:joints])
        r["tool_offset"] = list(s.tool_offset[:9])  # what G43 applies (stat), and the HAL pin it reaches
        r["tooloffset_pin"] = [g("motion.tooloffset.%s" % a) for a in "xyz"]
        readings.append(r)
    elapsed = time.time() - t_moves

    result.update({"readings": readings, "moves_seconds": elapsed})
    with open("readings.json", "w") as f:
        json.dump(result, f, indent=1)
    c.state(linuxcnc.STATE_OFF)
    c.wait_complete()
    print("driver: %d moves, %d readings in %.1f s" % (len(plan["moves"]), len(readings), elapsed), flush=True)
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except linuxcnc.error as e:
        fail("linuxcnc: %s" % e)
