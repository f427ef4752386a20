#!/usr/bin/env python3
"""Writes python/mtcal/_mtcal.pyi, the type stubs of the compiled module, from the module itself.

    PYTHONPATH=build/python python3 python/generate_stubs.py            # rewrite the stub file
    PYTHONPATH=build/python python3 python/generate_stubs.py --check    # exit 1 if it is out of date

pybind11 puts each function's signature with C++-derived types on the first line of its
docstring; this turns them into Python typing (NumPy arrays, Machine instead of
mtcal._mtcal.Machine, ArrayLike for array arguments taken as any object) and keeps the rest of
the docstring, so that editors show what help() shows. The ctest python_stubs runs --check: a
binding changed without regenerating the stubs fails it.
"""
import argparse
import inspect
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
# The built package (PYTHONPATH), not the sources beside this script, which lack the extension.
sys.path = [p for p in sys.path if Path(p or ".").resolve() != HERE]
import mtcal._mtcal as ext  # noqa: E402
STUB = HERE / "mtcal" / "_mtcal.pyi"

# Arguments bound as py::handle / py::object (shown as "object"): their Python types.
ARG_TYPES = {
    "model": "Machine | ErrorModel",
    "directions": "npt.ArrayLike | None",
    "grid": "str | Mapping[str, npt.ArrayLike] | None",
    "box": "str | Mapping[str, tuple[float, float]] | None",
    "histogram": "bool | int | str | None",
    "grouping": "bool | Mapping[str, float] | None",
    "values": "Mapping[str, float] | None",
    "errors": "npt.ArrayLike",
    "estimate": "str | Sequence[str] | None",
    "candidates": "Sequence[str] | None",
    "always": "Sequence[str] | None",
    "scale_bars": "Sequence[str | tuple[str, str, float]] | None",
    "workspace": "str | Mapping[str, npt.ArrayLike] | None",
    "pair": "tuple[npt.ArrayLike, npt.ArrayLike] | None",
    "program": "str | GcodeProgram",
    "origin": "Mapping[str, float] | None",
    "work_offsets": "Mapping[str, Mapping[str, float]] | None",
    "g28": "Mapping[str, float] | None",
    "g30": "Mapping[str, float] | None",
    "frame": "Sequence[float] | None",
    "points": "PredictionPoints | Mapping[str, npt.ArrayLike]",
    "data": "ContactSet | IndexedCentres",
    "spec": "str | Mapping[str, npt.ArrayLike]",
    "polynomial": "Sequence[float] | None",
    "table": "Mapping[str, Sequence[float]] | None",
    "fourier": "Mapping[str, float | Sequence[float]] | None",
    "travel": "tuple[float, float] | None",
    "point": "Sequence[float] | None",
    "spindle_point": "Sequence[float] | None",
    "reference": "npt.ArrayLike | None",
    "measured": "npt.ArrayLike | None",
    "held": "npt.ArrayLike | None",
    "approaches": "npt.ArrayLike | None",
    "centre": "npt.ArrayLike | None",
    "out": "npt.NDArray[np.float64] | None",
    "array": "npt.ArrayLike",
    "metadata": "Mapping[str, str] | None",
}
# The same for one function's or method's argument, where the name means something else elsewhere.
FUNC_ARG_TYPES = {
    ("inverse", "points"): "npt.ArrayLike",
    ("inverse", "rotary"): "npt.ArrayLike | None",
    ("nominal_inverse", "point"): "npt.ArrayLike",
    ("nominal_inverse", "rotary"): "npt.ArrayLike | None",
    ("write_report", "result"): ("PositioningEvaluation | BallbarResult | MethodComparison | HistoryTrends | "
                                 "VolumetricResult | ContributionResult | DiagonalsResult | Effects | EvaluationRun | "
                                 "ToolpathResult | ModelComparison | IdentificationRun | PredictionRun | "
                                 "RotaryAxisResult | TargetOutput | CampaignResult | Machine"),
    ("write_report", "runs"): "PositioningRuns | None",
    ("write_report", "pdf"): "str | None",
    ("write_report", "png_dir"): "str | None",
    ("write_report", "acceptance"): "AcceptanceVerdict | None",
    ("evaluate_tolerances", "result"): "PositioningEvaluation | BallbarResult | VolumetricResult",
    ("import_", "files"): "str | Sequence[str]",
    ("linuxcnc_probe", "spheres"): "npt.ArrayLike",
    ("evaluate_tolerances", "tolerances"): "Mapping[str, float] | None",
    ("trend", "tolerances"): "Mapping[str, float | tuple[float, float]] | Sequence[str] | None",
    ("rank", "tolerances"): "Mapping[str, float | tuple[float, float]] | Sequence[str] | None",
    ("record", "result"): "Mapping[str, Any] | str",
    ("export", "path"): "str | None",
    ("design_plan", "artefact"): "ProbingPlan | None",
    ("design_plan", "against"): "ProbingPlan | None",
    ("design_plan", "target_u"): "Mapping[str, float] | None",
    ("design_plan", "ball_region"): "tuple[float, float, float, float, float] | None",
}
ARRAY_ARGS = {"configs", "at", "q", "user", "internal", "x", "y", "targets", "runs", "up", "down", "angles",
              "radii", "centres", "angles_deg", "feeds", "origin_xyz", "sphere"}


def py_type(t):
    """A pybind11 type name as Python typing."""
    t = t.replace("mtcal._mtcal.", "")
    t = re.sub(r"numpy\.ndarray\[numpy\.(\w+)\]", r"npt.NDArray[np.\1]", t)
    t = t.replace("numpy.ndarray", "npt.NDArray[Any]")
    for a, b in (("List[", "list["), ("Dict[", "dict["), ("Tuple[", "tuple["), ("Set[", "set[")):
        t = t.replace(a, b)
    t = re.sub(r"Optional\[([^\[\]]*(?:\[[^\]]*\])?)\]", r"\1 | None", t)
    t = re.sub(r"\bobject\b|\bhandle\b", "Any", t)
    t = {"dict": "dict[str, Any]", "list": "list[Any]", "tuple": "tuple[Any, ...]"}.get(t, t)
    return t


def split_args(s):
    """Top-level comma split of an argument list."""
    out, depth, cur = [], 0, ""
    for ch in s:
        if ch in "[(<{":
            depth += 1
        elif ch in "])>}":
            depth -= 1
        if ch == "," and depth == 0:
            out.append(cur.strip())
            cur = ""
        else:
            cur += ch
    if cur.strip():
        out.append(cur.strip())
    return out


def signature(name, line, method):
    """'def name(args) -> ret: ...' from pybind11's 'name(args) -> ret'."""
    m = re.match(r"^\w+\((.*)\) -> (.*)$", line)
    if not m:
        raise SystemExit(f"cannot read the signature of {name}: {line!r}")
    args = []
    for a in split_args(m.group(1)):
        if a in ("*", "/"):
            args.append(a)
            continue
        if a.startswith("**"):
            args.append("**kwargs: float")
            continue
        am = re.match(r"^(\w+): ([^=]+?)(?: = (.*))?$", a)
        if not am:
            raise SystemExit(f"cannot read argument {a!r} of {name}")
        arg, typ, default = am.groups()
        if method and arg == "self":
            args.append("self")
            continue
        typ = typ.strip()
        if typ in ("object", "handle"):
            typ = FUNC_ARG_TYPES.get((name, arg)) or ARG_TYPES.get(arg, "npt.ArrayLike" if arg in ARRAY_ARGS else "Any")
        else:
            typ = py_type(typ)
        if default == "None" and "None" not in typ:
            typ += " | None"
        args.append(f"{arg}: {typ}" + (" = ..." if default is not None else ""))
    ret = py_type(m.group(2))
    if name == "__init__":
        ret = "None"
    elif name == "to_dict":
        ret = "dict[str, Any]"
    return f"def {name}({', '.join(args)}) -> {ret}: ..."


def doc_of(obj):
    """The signature lines (one per overload) and the prose of a pybind11 docstring."""
    doc = inspect.getdoc(obj) or ""
    lines = doc.splitlines()
    name = obj.__name__
    if len(lines) > 1 and lines[1].strip() == "Overloaded function.":
        sigs, prose = [], []
        for ln in lines[2:]:
            sm = re.match(rf"^\d+\. ({name}\(.*)$", ln)
            if sm:
                sigs.append(sm.group(1))
            elif ln.strip():
                prose.append(ln.strip())
        return sigs, "\n".join(prose)
    return [lines[0]], "\n".join(lines[1:]).strip()


def docstring(text, indent):
    if not text:
        return []
    text = text.replace("\\", "\\\\").replace('"""', "'''")
    body = text.splitlines()
    pad = " " * indent
    if len(body) == 1:
        return [f'{pad}"""{body[0]}"""']
    return [f'{pad}"""{body[0]}'] + [f"{pad}{ln}" if ln else "" for ln in body[1:]] + [f'{pad}"""']


def function(name, obj, indent, method):
    sigs, prose = doc_of(obj)
    out = []
    pad = " " * indent
    for sig in sigs:
        if len(sigs) > 1:
            out.append(f"{pad}@overload")
        out.append(pad + signature(name, sig, method).removesuffix(" ..."))
        out.extend(docstring(prose, indent + 4) or [f"{pad}    ..."])
        if prose:
            out[-1] = out[-1]
    return out


def prop(name, p, indent):
    pad = " " * indent
    ret = "Any"
    if p.fget is not None and p.fget.__doc__:
        m = re.match(r"^\w*\((?:self|arg0): [\w.]+\) -> (.*)$", p.fget.__doc__.splitlines()[0])
        if m:
            ret = py_type(m.group(1))
    out = [f"{pad}@property", f"{pad}def {name}(self) -> {ret}:"]
    prose = (p.__doc__ or "").strip() if p.__doc__ and not p.__doc__.startswith("(self") else ""
    out.extend(docstring(prose, indent + 4) or [f"{pad}    ..."])
    return out


def cls(name, c):
    bases = [b.__name__ for b in c.__bases__ if b.__module__.startswith("mtcal")]
    out = [f"class {name}({', '.join(bases)}):" if bases else f"class {name}:"]
    doc = (c.__doc__ or "").strip()
    out.extend(docstring(doc, 4))
    for attr, v in sorted(vars(c).items(), key=lambda kv: (not kv[0].startswith("__init__"), kv[0])):
        if attr.startswith("_") and attr not in ("__init__", "__call__", "__getitem__", "__len__", "__iter__",
                                                 "__copy__", "__deepcopy__"):
            continue
        if isinstance(v, property):
            out.extend(prop(attr, v, 4))
        elif callable(v) and v.__doc__ and re.match(rf"^{attr}\(|^{attr}\(\*args", v.__doc__.lstrip()):
            static = isinstance(vars(c)[attr], staticmethod)
            fn = getattr(c, attr)
            if static:
                out.append("    @staticmethod")
            out.extend(function(attr, fn, 4, method=not static))
    if len(out) == 1:
        out.append("    ...")
    return out


HEADER = '''"""Type stubs of mtcal's compiled module (generated by python/generate_stubs.py: do not edit)."""
from typing import Any, Iterator, Mapping, Sequence, overload

import numpy as np
import numpy.typing as npt

__version__: str

class Error(RuntimeError):
    """Base class of every exception mtcal raises on purpose."""

class InputError(Error, ValueError):
    """Malformed or inconsistent input data; file, line (0: unknown) and field say where."""
    file: str
    line: int
    field: str

class ModelError(Error, ValueError):
    """A request the model cannot satisfy (unknown parameter name, axis not in the topology ...)."""
'''


def generate():
    out = [HEADER]
    names = sorted(n for n in dir(ext) if not n.startswith("__") and n not in ("Error", "InputError", "ModelError"))
    classes = [n for n in names if isinstance(getattr(ext, n), type)]
    # base classes first
    classes.sort(key=lambda n: (len(getattr(ext, n).__mro__), n))
    for n in classes:
        out.extend(cls(n, getattr(ext, n)))
        out.append("")
    for n in names:
        obj = getattr(ext, n)
        if not isinstance(obj, type) and callable(obj):
            out.extend(function(n, obj, 0, method=False))
            out.append("")
    return "\n".join(out).rstrip() + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true", help="compare with the stub file instead of writing it")
    args = ap.parse_args()
    text = generate()
    compile(text, str(STUB), "exec")  # valid Python
    if args.check:
        if STUB.read_text() != text:
            print(f"{STUB} is out of date: run PYTHONPATH=build/python python3 {Path(__file__).name}", file=sys.stderr)
            return 1
        print(f"{STUB.name} is up to date")
        return 0
    STUB.write_text(text)
    print(f"wrote {STUB}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
