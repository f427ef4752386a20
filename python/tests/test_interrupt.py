"""Ctrl-C stops a long computation of the module (issue 16: long work checks for interruption).

The computations run without the GIL, where Python's own SIGINT handler only records the signal
until they return: a Monte Carlo of 100,000 runs (minutes) would run to its end. The module's
handler asks the library's loops to stop; KeyboardInterrupt is raised within a few seconds.
"""
import os
import signal
import subprocess
import sys
import textwrap
import time

from conftest import EXAMPLES, MACHINES, cli

HU40T = MACHINES / "hu40t-wCBXfYZt.yaml"
PLAN = EXAMPLES / "plans" / "hu40t-samba-tango.csv"


def test_sigint_stops_a_long_monte_carlo(tmp_path):
    meas = tmp_path / "m.csv"
    cli("simulate", "-m", HU40T, "--plan", PLAN, "--artefact-error-um", "50", "--scale-bar", "1:2:304.8",
        "--noise-um", "1", "--seed", "7", "--out", meas)
    script = textwrap.dedent(f"""
        import sys, time
        import mtcal
        m = mtcal.Machine.load({str(HU40T)!r})
        meas = mtcal.read_probing_plan(m, {str(meas)!r})
        print("started", flush=True)
        t0 = time.monotonic()
        try:
            mtcal.identify(m, meas, ["EX0C", "EY0C", "EXX.1"], scale_bars=["1:2:304.8"], monte_carlo=100000, threads=2)
        except KeyboardInterrupt:
            took = time.monotonic() - t0
            # No stale request: the next computation runs to its end.
            r = mtcal.identify(m, meas, ["EX0C", "EY0C", "EXX.1"], scale_bars=["1:2:304.8"], monte_carlo=2)
            assert r.monte_carlo["samples"].shape == (2, 3)
            # Python's handler is back: a SIGINT outside the module raises KeyboardInterrupt as usual.
            import os, signal
            try:
                os.kill(os.getpid(), signal.SIGINT)
                time.sleep(5)
            except KeyboardInterrupt:
                print(f"interrupted after {{took:.1f}} s", flush=True)
                sys.exit(42)
            sys.exit(43)
        print("finished", flush=True)
    """)
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=os.environ.copy())
    assert p.stdout.readline().strip() == "started"
    time.sleep(1.0)  # inside identify by now: the fit itself takes milliseconds
    p.send_signal(signal.SIGINT)
    t_signal = time.monotonic()
    try:
        out, err = p.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        p.kill()
        raise AssertionError("SIGINT did not stop the Monte Carlo within 60 s")
    stopped_in = time.monotonic() - t_signal
    assert p.returncode == 42, (p.returncode, out, err)
    assert out.startswith("interrupted after"), out
    assert stopped_in < 30, stopped_in
