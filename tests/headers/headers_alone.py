#!/usr/bin/env python3
"""Every public header compiles alone (tests/headers/CMakeLists.txt), at a fraction of the cost.

A header that is the first #include of a unit this build compiles on its own (not in a unity
batch, no precompiled header forced in before it) has compiled alone already: nothing precedes it
in that unit (the reason the project's .cpp files include their own header first; Google's C++
style guide, "Names and Order of Includes"). Only the other headers are compiled alone here, each
from its generated one-line unit (Ninja builds that object file by its path). Compiling all 136
alone took ~215 CPU-seconds of the suite's time; nearly all of them are proven by the build.

Usage: headers_alone.py BUILD_DIR ALONE_OBJECT_DIR INCLUDE_DIRS HEADER...
  INCLUDE_DIRS: where the headers are, ':'-separated; HEADER as included (mtcal/x/y.hpp).
Exit 0 when every header is proven or compiles alone; 1 with the failing ones named.
"""
import json
import os
import re
import shlex
import shutil
import subprocess
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]')


def first_include(path):
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            for line in f:
                m = INCLUDE.match(line)
                if m:
                    return m.group(1)
    except OSError:
        return None
    return None


def proven_headers(build, includes):
    """Header -> a unit of this build that includes it first, compiled without anything before it."""
    try:
        with open(os.path.join(build, "compile_commands.json"), encoding="utf-8") as f:
            commands = json.load(f)
    except (OSError, ValueError):
        return {}
    proven = {}
    for c in commands:
        unit = c["file"]
        args = c.get("arguments") or shlex.split(c.get("command", ""))
        # A unity batch (unity_N_cxx.cxx) includes other units first; a precompiled header is
        # forced in with -include; a header unit of the alone target is what is checked here.
        if not unit.endswith(".cpp") or "/unity/" in unit or "-include" in args or "/alone/" in unit:
            continue
        path = unit if os.path.isabs(unit) else os.path.join(c["directory"], unit)
        h = first_include(path)
        if not h or not h.startswith("mtcal/") or h in proven:
            continue
        # Compiled since the unit and the header last changed: its object file is newer than both.
        try:
            obj = args[args.index("-o") + 1]
            built = os.path.getmtime(obj if os.path.isabs(obj) else os.path.join(c["directory"], obj))
            header = next(p for p in (os.path.join(d, h) for d in includes) if os.path.exists(p))
            if built >= os.path.getmtime(path) and built >= os.path.getmtime(header):
                proven[h] = unit
        except (ValueError, IndexError, OSError, StopIteration):
            continue
    return proven


def selftest():
    """proven_headers on a made-up build: which units prove their first include, and which do not."""
    import tempfile
    import time
    d = tempfile.mkdtemp(prefix="mtcal-headers-selftest-")
    inc = os.path.join(d, "include")
    os.makedirs(os.path.join(inc, "mtcal"))
    def write(path, text, age):
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
        t = time.time() - age
        os.utime(path, (t, t))
    units = {"a": "mtcal/a.hpp", "b": "mtcal/b.hpp", "c": "mtcal/c.hpp", "d": "mtcal/d.hpp", "e": "mtcal/e.hpp"}
    for h in units.values():
        write(os.path.join(inc, h), "#pragma once\n", 100)
    commands = []
    for name, h in units.items():
        unit = os.path.join(d, name + ".cpp")
        first = f'// {name}\n#include <vector>\n' if name == "c" else ""  # c: a standard header first
        write(unit, first + f'#include "{h}"\n', 100)
        obj = os.path.join(d, name + ".o")
        flags = ["-include", "pch.hxx"] if name == "d" else []  # d: a precompiled header first
        cmd = ["c++", *flags, "-o", obj, "-c", unit]
        commands.append({"directory": d, "file": unit, "command": " ".join(cmd)})
        if name != "e":  # e: never compiled
            write(obj, "", 50)
    # b's header changed after its object was made.
    write(os.path.join(inc, units["b"]), "#pragma once\nint x;\n", 10)
    with open(os.path.join(d, "compile_commands.json"), "w", encoding="utf-8") as f:
        json.dump(commands, f)
    got = sorted(proven_headers(d, [inc]))
    shutil.rmtree(d, ignore_errors=True)
    want = ["mtcal/a.hpp"]
    print(f"selftest: proven {got}, expected {want}")
    return 0 if got == want else 1


def main():
    if sys.argv[1:] == ["--selftest"]:
        return selftest()
    if len(sys.argv) < 5:
        print(__doc__)
        return 2
    build, objects, includes, headers = sys.argv[1], sys.argv[2], sys.argv[3].split(":"), sys.argv[4:]
    proven = proven_headers(build, includes)
    rest = [h for h in headers if h not in proven]
    print(f"{len(headers) - len(rest)} of {len(headers)} headers are the first include of a unit the build compiled "
          f"alone; compiling the other {len(rest)} alone")
    failed = []
    for h in rest:
        obj = os.path.join(objects, re.sub(r"[/.]", "_", h) + ".cpp.o")
        target = os.path.relpath(obj, build)
        r = subprocess.run(["cmake", "--build", build, "--target", target], capture_output=True, text=True)
        if r.returncode != 0:
            failed.append(h)
            print(f"FAIL {h}: does not compile alone\n{r.stdout[-4000:]}{r.stderr[-2000:]}")
        else:
            print(f"ok   {h}")
    print(f"{len(headers) - len(failed)} passed, {len(failed)} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
