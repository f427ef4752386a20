#!/usr/bin/env bash
# mtcal compensate: help, JSON keys, a zero-error model gives the same file, the corrected
# coordinates against a hand formula (squareness EC0Y alone), the corrected program read back by
# mtcal toolpath, bad input (one-line errors, no output left).
# Needs MTCAL (the binary) and EXAMPLES (examples/machines). Prints "N passed, N failed".
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
M3="$EXAMPLES/vmc-3axis.yaml"
M5="$EXAMPLES/head-head-5axis.yaml"
P="$EXAMPLES/../gcode/pocket.nc"
ORIGIN="X=-40,Y=-25,Z=-400"

expect_exit 0 "compensate --help" -- "$MTCAL" compensate --help
for opt in --gcode --out --max-deviation --linearise-arcs --json --origin Examples; do
  grep -q -- "$opt" "$tmp/out" && ok || bad "help lacks $opt"
done
expect_error "without --out" "--out" -- "$MTCAL" compensate -m "$M3" --gcode "$P"

# JSON summary and the file.
expect_exit 0 "json" -- "$MTCAL" compensate -m "$M3" --gcode "$P" --origin "$ORIGIN" --out "$tmp/c.nc" \
  --no-direction --json
[ "$(json_get "list(d.keys())")" = "['machine', 'program', 'interpreter', 'written', 'correction', 'rewrite', 'seconds', 'out']" ] && ok ||
  bad "JSON keys: $(json_get "list(d.keys())")"
[ "$(json_get "list(d['correction'].keys())")" = "['moves', 'moves_corrected', 'subdivisions', 'transitions', 'arcs_kept', 'arcs_linearised', 'direction_conflicts', 'points_solved', 'max_correction', 'max_rotary_correction', 'max_iterations', 'max_residual', 'max_orientation_left', 'max_error_before', 'max_deviation_after', 'warnings']" ] &&
  ok || bad "correction keys: $(json_get "list(d['correction'].keys())")"
[ "$(json_get "d['correction']['moves']")" = "25" ] && ok || bad "moves: pocket.nc has 25"
[ "$(json_get "d['correction']['max_residual'] <= 1e-9")" = "True" ] && ok || bad "residual"
# Comments, N words, S T M lines kept; the corrected program reads back.
grep -q '^N20 T1 M6 (10 mm end mill)$' "$tmp/c.nc" && grep -q '^; contour, counter-clockwise' "$tmp/c.nc" && ok ||
  bad "comments and non-motion lines kept"
expect_exit 0 "toolpath reads the corrected program" -- "$MTCAL" toolpath -m "$M3" --gcode "$tmp/c.nc" --origin "$ORIGIN"

# Zero errors: the same bytes.
expect_exit 0 "zero-error model" -- "$MTCAL" compensate -m "$M3" --only EC0Y --set EC0Y=0 --gcode "$P" \
  --origin "$ORIGIN" --out "$tmp/z.nc"
cmp -s "$P" "$tmp/z.nc" && ok || bad "zero-error output differs from the input"

# EC0Y alone (1e-4): the tool's x error is -Y sin(EC0Y) with Y the machine position (the tool-path
# test's hand formula), so the command moves X by Y_machine * 1e-4 in size and leaves Y and Z.
expect_exit 0 "EC0Y only" -- "$MTCAL" compensate -m "$M3" --only EC0Y --set EC0Y=1e-4 --gcode "$P" \
  --origin "$ORIGIN" --out "$tmp/sq.nc" --no-direction --linearise-arcs
python3 - "$P" "$tmp/sq.nc" <<'PY' && ok || bad "EC0Y: |X_cmd - X| = |Y_machine| 1e-4"
import re, sys
def blocks(path):
    out = {}
    for line in open(path):
        m = re.match(r"N(\d+) ", line)
        if m: out[m.group(1)] = dict((w[0], float(w[1:])) for w in re.findall(r"[XYZ]-?[\d.]+", line.split("(")[0]))
    return out
a, b = blocks(sys.argv[1]), blocks(sys.argv[2])
checked = 0
for n in ["40", "150", "200", "220"]:  # absolute G0/G1 blocks that name X and Y
    y = a[n]["Y"] - 25
    assert abs(abs(b[n]["X"] - a[n]["X"]) - abs(y) * 1e-4) < 1.5e-6, (n, a[n], b[n])
    assert abs(b[n]["Y"] - a[n]["Y"]) < 1.5e-6, (n, a[n], b[n])
    checked += 1
assert checked == 4
PY

# 5-axis: runs, corrects the rotary axes too.
printf 'G0 X0 Y0 Z-300 C0 A0\nG1 X100 Y50 A20 F1000\nG1 C90\n' >"$tmp/five.nc"
expect_exit 0 "5-axis" -- "$MTCAL" compensate -m "$M5" --gcode "$tmp/five.nc" --out "$tmp/five-c.nc" --json
[ "$(json_get "d['correction']['max_rotary_correction'] > 0")" = "True" ] && ok || bad "5-axis rotary correction"

# Bad input: one line, no output file.
printf 'G1 X10 Yz\n' >"$tmp/bad.nc"
expect_error "bad program" "bad.nc:1: column 8" -- "$MTCAL" compensate -m "$M3" --gcode "$tmp/bad.nc" \
  --out "$tmp/bad-out.nc"
[ ! -e "$tmp/bad-out.nc" ] && ok || bad "a bad program left an output file"
expect_error "max deviation 0" "--max-deviation" -- "$MTCAL" compensate -m "$M3" --gcode "$P" \
  --origin "$ORIGIN" --out "$tmp/d0.nc" --max-deviation 0
[ ! -e "$tmp/d0.nc" ] && ok || bad "a refused run left an output file"
expect_error "output replaces input" "would replace the input" -- "$MTCAL" compensate -m "$M3" --gcode "$P" \
  --out "$P"
expect_error "outside the travel" "outside the travel" -- "$MTCAL" compensate -m "$M3" --gcode "$P" \
  --out "$tmp/t.nc"

summary_and_exit
