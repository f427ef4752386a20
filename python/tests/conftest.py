"""Shared fixtures of the mtcal Python tests: the built command, the example files, JSON comparison.

ctest (python/CMakeLists.txt) sets MTCAL (the built command), MTCAL_EXAMPLES, MTCAL_SHARED_DATA
and PYTHONPATH=<build>/python. The reference of most tests is the command's --json output: the
same library reached through another path (CLI11 options, text parsing, JSON printing).
"""
import json
import math
import os
import subprocess
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
REPO = HERE.parent.parent
MTCAL = os.environ.get("MTCAL", str(REPO / "build" / "apps" / "mtcal" / "mtcal"))
EXAMPLES = Path(os.environ.get("MTCAL_EXAMPLES", REPO / "examples"))
SHARED_DATA = Path(os.environ.get("MTCAL_SHARED_DATA", REPO.parent / "shared" / "data"))
MACHINES = EXAMPLES / "machines"

# Timing keys differ from run to run; everything else must agree.
TIMING_KEYS = {"seconds", "monte_carlo_seconds"}


def cli(*args, check=True):
    """Runs the built mtcal; returns the CompletedProcess (text)."""
    p = subprocess.run([MTCAL, *map(str, args)], capture_output=True, text=True)
    if check and p.returncode != 0:
        raise AssertionError(f"mtcal {' '.join(map(str, args))} failed ({p.returncode}): {p.stderr}")
    return p


def cli_json(*args):
    return json.loads(cli(*args, "--json").stdout)


def cli_error(*args):
    """The one-line message of a failing command, without the 'mtcal: error: ' prefix."""
    p = cli(*args, check=False)
    assert p.returncode == 1, f"expected exit 1, got {p.returncode}: {p.stdout} {p.stderr}"
    line = p.stderr.strip()
    assert line.startswith("mtcal: error: "), line
    return line[len("mtcal: error: "):]


def assert_same(a, b, tol=1e-12, path="$", skip=TIMING_KEYS):
    """Recursive equality of JSON-like values; numbers to tol (absolute, and relative for large ones)."""
    if isinstance(a, dict):
        assert isinstance(b, dict), f"{path}: dict vs {type(b).__name__}"
        ka = [k for k in a if k not in skip]
        kb = [k for k in b if k not in skip]
        assert ka == kb, f"{path}: keys {ka} vs {kb}"
        for k in ka:
            assert_same(a[k], b[k], tol, f"{path}.{k}", skip)
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), f"{path}: list lengths {len(a)} vs {len(b) if isinstance(b, list) else b}"
        for i, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, tol, f"{path}[{i}]", skip)
    elif isinstance(a, bool) or a is None or isinstance(a, str):
        assert a == b, f"{path}: {a!r} vs {b!r}"
    elif isinstance(a, (int, float)):
        assert isinstance(b, (int, float)) and not isinstance(b, bool), f"{path}: {a!r} vs {b!r}"
        assert math.isclose(a, b, rel_tol=tol, abs_tol=tol), f"{path}: {a!r} vs {b!r} (differ by {abs(a - b):.3g})"
    else:
        raise AssertionError(f"{path}: unexpected type {type(a).__name__}")


@pytest.fixture(scope="session")
def hu40t():
    import mtcal
    return mtcal.Machine.load(str(MACHINES / "hu40t-wCBXfYZt.yaml"))


@pytest.fixture(scope="session")
def vmc():
    import mtcal
    return mtcal.Machine.load(str(MACHINES / "vmc-3axis.yaml"))
