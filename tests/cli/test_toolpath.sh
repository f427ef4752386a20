#!/usr/bin/env bash
# mtcal toolpath: help, JSON keys, CSV columns and values against a hand formula, bad programs
# (one-line errors with line and column, no output left), output paths, axes of the machine.
# Needs MTCAL (the binary) and EXAMPLES (examples/machines). Prints "N passed, N failed".
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
M3="$EXAMPLES/vmc-3axis.yaml"
M5="$EXAMPLES/hu40t-wCBXfYZt.yaml"
P="$EXAMPLES/../gcode/pocket.nc"
ORIGIN="X=-40,Y=-25,Z=-400"

expect_exit 0 "toolpath --help" -- "$MTCAL" toolpath --help
grep -q -- '--gcode' "$tmp/out" && grep -q -- '--step' "$tmp/out" && grep -q -- '--origin' "$tmp/out" &&
  grep -q -- '--skip-rapids' "$tmp/out" && ok || bad "toolpath --help lists its options"
expect_error "toolpath without --gcode" "--gcode" -- "$MTCAL" toolpath -m "$M3"

# Text summary.
expect_exit 0 "toolpath text" -- "$MTCAL" toolpath -m "$M3" --gcode "$P" --origin "$ORIGIN"
grep -q '^largest translational error' "$tmp/out" && ok || bad "text summary: $(cat "$tmp/out")"

# JSON keys and CSV columns.
expect_exit 0 "toolpath --json --out" -- "$MTCAL" toolpath -m "$M3" --gcode "$P" --origin "$ORIGIN" --step 0.5 \
  --json --out "$tmp/tp.csv"
[ "$(json_get "list(d.keys())")" = "['points', 'blocks', 'path_length', 'ignored_words', 'words', 'rapids_skipped', 'max_error', 'range', 'interpreter', 'out']" ] &&
  ok || bad "JSON keys: $(json_get "list(d.keys())")"
[ "$(json_get "sorted(d['max_error'].keys())")" = "['at', 'line', 'value']" ] && ok || bad "max_error keys"
[ "$(json_get "sorted(d['range'].keys())")" = "['dx', 'dy', 'dz', 'rx', 'ry', 'rz']" ] && ok || bad "range keys"
[ "$(json_get "d['ignored_words']")" = "10" ] && ok || bad "ignored words: S, T, M and G40 G49 G80 G94 of pocket.nc"
[ "$(head -1 "$tmp/tp.csv")" = "line,n,motion,s,X,Y,Z,dx,dy,dz,rx,ry,rz" ] && ok || bad "CSV header: $(head -1 "$tmp/tp.csv")"
cp "$tmp/out" "$tmp/tp.json"
python3 - "$tmp/tp.csv" "$tmp/tp.json" <<'PY' && ok || bad "CSV rows agree with the JSON summary and the program"
import csv, json, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
d = json.load(open(sys.argv[2]))
assert len(rows) == d["points"], (len(rows), d["points"])
s = [float(r["s"]) for r in rows]
assert all(b >= a for a, b in zip(s, s[1:])), "s decreases"
assert abs(s[-1] - d["path_length"]) < 1e-5
# Points never more than 0.5 mm apart along X Y Z (chords of arcs are shorter than their arcs).
for a, b in zip(rows, rows[1:]):
    dist = math.dist([float(a[k]) for k in "XYZ"], [float(b[k]) for k in "XYZ"])
    assert dist <= 0.5 + 1e-6, (a["line"], dist)
# N70 (line 13): G3 X80 Y10 I0 J10 from (70, 0): centre (70, 10) in program coordinates, so
# (30, -15) on the machine with the origin (-40, -25).
arc = [r for r in rows if r["n"] == "70"]
assert arc and all(r["motion"] == "arc_ccw" for r in arc)
for r in arc:
    assert abs(math.hypot(float(r["X"]) - 30, float(r["Y"]) + 15) - 10) < 1e-9, r
# The end of the last block: G0 Z5 from N290 -> machine Z = -395.
assert rows[-1]["n"] == "290" and float(rows[-1]["Z"]) == -395.0
best = max(rows, key=lambda r: math.hypot(float(r["dx"]), float(r["dy"]), float(r["dz"])))
assert abs(math.hypot(float(best["dx"]), float(best["dy"]), float(best["dz"])) - d["max_error"]["value"]) < 1e-11
assert int(best["line"]) == d["max_error"]["line"]
PY

# Values against a hand formula: the squareness EC0Y alone gives dx = -Y sin(EC0Y) at every point.
expect_exit 0 "toolpath EC0Y only" -- "$MTCAL" toolpath -m "$M3" --gcode "$P" --origin "$ORIGIN" --only EC0Y \
  --set EC0Y=1e-5 --out "$tmp/sq.csv"
python3 - "$tmp/sq.csv" <<'PY' && ok || bad "EC0Y: dx = -Y sin(1e-5) at every point"
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) > 1000
for r in rows:
    assert abs(float(r["dx"]) + float(r["Y"]) * math.sin(1e-5)) < 1e-12, r
    assert float(r["dz"]) == 0 and float(r["rz"]) == 0, r
PY

# Rapids left out.
expect_exit 0 "toolpath --skip-rapids" -- "$MTCAL" toolpath -m "$M3" --gcode "$P" --origin "$ORIGIN" --skip-rapids --json
[ "$(json_get "d['rapids_skipped']")" = "6" ] && ok || bad "rapids_skipped: $(json_get "d['rapids_skipped']")"

# Report.
expect_exit 0 "toolpath --report" -- "$MTCAL" toolpath -m "$M3" --gcode "$P" --origin "$ORIGIN" --report "$tmp/tp.html"
grep -q 'Tool-path simulation' "$tmp/tp.html" && grep -q 'pocket.nc' "$tmp/tp.html" && ok || bad "report content"

# The ISO dialect: a canned cycle expanded and counted; a word not simulated is a warning on stderr
# naming file, line, column and word.
printf 'O100\nG21 G90 G17 F100\nG0 X0 Y0 Z10\nG64 P0.01\nG98 G81 X10 Y5 Z-3 R2\nX20\nG80 M30\n' >"$tmp/cycle.nc"
expect_exit 0 "canned cycle" -- "$MTCAL" toolpath -m "$M3" --gcode "$tmp/cycle.nc" --origin "$ORIGIN" --json
[ "$(json_get "d['words']['cycles']")" = 2 ] && [ "$(json_get "d['interpreter']")" = mtcal ] && ok ||
  bad "canned cycle: $(cat "$tmp/out")"
grep -qF "mtcal: warning: $tmp/cycle.nc:4: column 5: 'G64 P0.01' (path blending tolerance) is not simulated" "$tmp/err" &&
  ok || bad "G64 P warning: $(cat "$tmp/err")"
# RS274NGC beyond the ISO dialect without LinuxCNC's interpreter: a message that says what to install.
printf 'G21\n#1 = 5\nG1 X#1 F100\nM2\n' >"$tmp/param.ngc"
expect_error "no rs274 (auto)" "$tmp/param.ngc:2: column 1: '#' parameter" -- "$MTCAL" toolpath -m "$M3" \
  --gcode "$tmp/param.ngc" --origin "$ORIGIN" --rs274 /nonexistent/rs274
grep -qF "LinuxCNC's interpreter '/nonexistent/rs274' is not installed (Debian package linuxcnc-uspace)" "$tmp/err" &&
  ok || bad "no rs274 message: $(cat "$tmp/err")"
expect_error "no rs274 (asked for)" "LinuxCNC's interpreter '/nonexistent/rs274' is not installed" -- "$MTCAL" \
  toolpath -m "$M3" --gcode "$tmp/cycle.nc" --origin "$ORIGIN" --interpreter rs274 --rs274 /nonexistent/rs274
expect_error "bad tool table" "tools.tbl:1: column 4: expected a number after 'Z'" -- bash -c \
  "printf 'T1 Zx\n' >'$tmp/tools.tbl'; '$MTCAL' toolpath -m '$M3' --gcode '$tmp/cycle.nc' --origin '$ORIGIN' --tool-table '$tmp/tools.tbl'"
expect_error "bad work offset" "--work-offset" -- "$MTCAL" toolpath -m "$M3" --gcode "$tmp/cycle.nc" \
  --origin "$ORIGIN" --work-offset "G60:X=1"

# A bad program: one line naming file, line and column; exit 1; no output file, no temporary left.
printf 'G21 G90\nG1 X1 F100\nG1 X2 Yq\n' >"$tmp/bad.nc"
mkdir "$tmp/outdir"
expect_error "bad word" "bad.nc:3: column 7: expected a number after 'Y', found 'q'" -- "$MTCAL" toolpath -m "$M3" --gcode "$tmp/bad.nc" \
  --origin "Z=-400" --out "$tmp/outdir/bad.csv"
[ "$(grep -c . "$tmp/err")" -eq 1 ] && ok || bad "one error line"
"$MTCAL" toolpath -m "$M3" --gcode "$tmp/bad.nc" --origin "Z=-400" --out "$tmp/outdir/bad.csv" >/dev/null 2>&1
[ $? -eq 1 ] && ok || bad "exit status 1 for a bad program"
[ -z "$(ls -A "$tmp/outdir")" ] && ok || bad "output left behind: $(ls -A "$tmp/outdir")"
printf 'G0 X10\nG2 X0 Y10.5 I-10\n' >"$tmp/arc.nc"
expect_error "arc off its circle" "arc.nc:2: column 13: the arc's start radius 10 mm and end radius 10.5 mm" -- \
  "$MTCAL" toolpath -m "$M3" --gcode "$tmp/arc.nc" --origin "Z=-400"
printf 'G1 X1 (no end\n' >"$tmp/cmt.nc"
expect_error "unterminated comment" "cmt.nc:1: column 7: unterminated comment" -- \
  "$MTCAL" toolpath -m "$M3" --gcode "$tmp/cmt.nc" --origin "Z=-400"

# An axis the machine does not have.
printf 'G1 X10 B5 F100\n' >"$tmp/b.nc"
expect_error "B word on a 3-axis machine" "b.nc:1: column 8: axis word 'B' for an axis this machine does not have (its axes: XYZ)" -- \
  "$MTCAL" toolpath -m "$M3" --gcode "$tmp/b.nc" --origin "Z=-400"
# ... which a 5-axis machine has.
expect_exit 0 "B word on a 5-axis machine" -- "$MTCAL" toolpath -m "$M5" --gcode "$tmp/b.nc" --json --no-travel-check
[ "$(json_get "d['points']")" -ge 20 ] && ok || bad "5-axis points"

# Output paths and options.
expect_error "--out a directory" "is a directory" -- "$MTCAL" toolpath -m "$M3" --gcode "$P" --origin "$ORIGIN" --out "$tmp/outdir"
expect_error "--out over the program" "would replace the input" -- "$MTCAL" toolpath -m "$M3" --gcode "$P" --out "$P"
expect_error "--step 0" "expected a step > 0" -- "$MTCAL" toolpath -m "$M3" --gcode "$P" --step 0
expect_error "--origin unknown axis" "axis 'B' is not in topology" -- "$MTCAL" toolpath -m "$M3" --gcode "$P" --origin "B=5"
expect_error "missing program" "cannot open G-code program" -- "$MTCAL" toolpath -m "$M3" --gcode "$tmp/none.nc"
# Travel: without the origin the program's Z=5 is above the column's travel [-500, 0].
expect_error "travel" "pocket.nc:9: field 'Z': Z=0.217391 mm is outside the travel" -- "$MTCAL" toolpath -m "$M3" --gcode "$P"
expect_exit 0 "--no-travel-check" -- "$MTCAL" toolpath -m "$M3" --gcode "$P" --no-travel-check --json

summary_and_exit
