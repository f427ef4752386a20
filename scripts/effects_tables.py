#!/usr/bin/env python3
"""Writes the single-error effect tables of docs/conventions.md from `mtcal effects`.

Each table sits between `<!-- effects MACHINE AT -->` and `<!-- end effects -->`. With --check
nothing is written and the exit status says whether the document matches the program.
Usage: effects_tables.py MTCAL EXAMPLES_DIR DOC [--check]
"""
import json
import os
import re
import subprocess
import sys


def table(mtcal, machine, at):
    out = subprocess.run([mtcal, "effects", "--machine", machine, "--at", at, "--json"],
                         check=True, capture_output=True, text=True).stdout
    d = json.loads(out)

    def f(v):
        return "0" if abs(v) < 5e-12 else f"{v:.4g}"

    rows = ["| error | kind | per | dx µm | dy µm | dz µm | rx µrad | ry µrad | rz µrad |",
            "|---|---|---|---:|---:|---:|---:|---:|---:|"]
    for e in d["effects"]:
        per = "µm" if e["per"] == "um" else "µrad"
        rows.append("| {} | {} | 1 {} | {} |".format(
            e["error"], e["kind"], per, " | ".join(f(e[k]) for k in ("dx", "dy", "dz", "rx", "ry", "rz"))))
    return "\n".join(rows)


def main():
    if len(sys.argv) < 4:
        print(__doc__, file=sys.stderr)
        return 2
    mtcal, examples, doc = sys.argv[1:4]
    check = "--check" in sys.argv[4:]
    text = open(doc, encoding="utf-8").read()
    pattern = re.compile(r"(<!-- effects (\S+) (\S+) -->\n)(.*?)(<!-- end effects -->)", re.S)

    def repl(m):
        return m.group(1) + table(mtcal, f"{examples}/{m.group(2)}", m.group(3)) + "\n" + m.group(5)

    machines = sorted(f for f in os.listdir(examples) if f.endswith(".yaml"))
    tabled = sorted(set(m.group(2) for m in pattern.finditer(text)))
    if tabled != machines:
        print(f"{doc}: effect tables are for {tabled}, the examples are {machines}", file=sys.stderr)
        return 1
    new = pattern.sub(repl, text)
    if check:
        if new != text:
            print(f"{doc}: effect tables differ from `mtcal effects`; run "
                  f"scripts/effects_tables.py {mtcal} {examples} {doc}", file=sys.stderr)
            return 1
        print("1 passed, 0 failed")
        return 0
    open(doc, "w", encoding="utf-8").write(new)
    return 0


if __name__ == "__main__":
    sys.exit(main())
