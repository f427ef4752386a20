#!/usr/bin/env bash
# mtcal compensate --format: help lists the targets, JSON keys, the files, the residual of a
# positioning-only model, bad input with one-line errors and no output directory left.
# Needs MTCAL (the binary) and EXAMPLES (examples/machines). Prints "N passed, N failed".
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
M3="$EXAMPLES/vmc-3axis.yaml"
M5="$EXAMPLES/hu40t-wCBXfYZt.yaml"

expect_exit 0 "help" -- "$MTCAL" compensate --help
for word in --format linuxcnc siemens isg etalon heidenhain fanuc klipper marlin rrf fluidnc --fanuc-unit \
  --points --range --reference --linuxcnc-type --skew-reference-length --gcode Examples; do
  grep -q -- "$word" "$tmp/out" && ok || bad "help lacks $word"
done

expect_exit 0 "linuxcnc json" -- "$MTCAL" compensate -m "$M3" --only EXX,EYY,EZZ --format linuxcnc --points 11 \
  --out "$tmp/lc" --json
[ "$(json_get "list(d)[:7]")" = "['target', 'quantity', 'sign_source', 'files', 'not_compensated', 'warnings', 'residual']" ] \
  && ok || bad "json keys: $(json_get "list(d)")"
[ "$(json_get "d['quantity']")" = "correction" ] && ok || bad "quantity"
[ "$(json_get "d['residual']['max_norm_after_mm'] < 0.01 * d['residual']['max_norm_before_mm']")" = "True" ] \
  && ok || bad "residual of a positioning-only model: $(json_get "d['residual']")"
for f in X.comp Y.comp Z.comp linuxcnc.ini; do [ -f "$tmp/lc/$f" ] && ok || bad "no $f"; done
[ "$(wc -l <"$tmp/lc/X.comp")" -eq 11 ] && ok || bad "X.comp has $(wc -l <"$tmp/lc/X.comp") lines"
# Three numbers a line and nothing else (LinuxCNC stops reading silently at anything else).
awk 'NF != 3 || $1 !~ /^-?[0-9.]+$/ {exit 1}' "$tmp/lc/X.comp" && ok || bad "X.comp is not three numbers a line"

expect_exit 0 "type 0 text" -- "$MTCAL" compensate -m "$M3" --format linuxcnc --linuxcnc-type 0 --out "$tmp/lc0"
grep -q "actual position" "$tmp/out" && ok || bad "type 0 says what its numbers are"
grep -q "not held     EC0Y" "$tmp/out" && ok || bad "squareness listed as not held"
expect_exit 0 "5-axis trt" -- "$MTCAL" compensate -m "$M5" --format linuxcnc --residual-points 3 --out "$tmp/lc5"
grep -q "setp xyzbc-trt-kins.x-rot-point" "$tmp/lc5/linuxcnc-kins.hal" && ok || bad "trt pins"

expect_exit 0 "report" -- "$MTCAL" compensate -m "$M3" --format linuxcnc --out "$tmp/rep" --report "$tmp/rep.html"
grep -q "What the target cannot hold" "$tmp/rep.html" && grep -q "EC0Y" "$tmp/rep.html" && ok || bad "report sections"
expect_error "report onto the machine file" "" -- "$MTCAL" compensate -m "$M3" --format linuxcnc --out "$tmp/rep2" \
  --report "$M3"
[ ! -e "$tmp/rep2" ] && ok || bad "output left when the report path is refused"
expect_exit 0 "isg" -- "$MTCAL" compensate -m "$M5" --format isg --points 11 --residual-points 3 --out "$tmp/isg"
grep -q "^X EXX" "$tmp/isg/volcomp.csv" && grep -q "^#$" "$tmp/isg/volcomp.csv" && ok || bad "ISG CSV blocks"
expect_exit 0 "marlin" -- "$MTCAL" compensate -m "$M3" --format marlin --out "$tmp/ma"
grep -q "^M852 I-0.000015000 J0.000020000 K0.000012000$" "$tmp/ma/marlin.gcode" && ok || bad "M852 line: $(cat "$tmp/ma/marlin.gcode")"
expect_exit 0 "klipper" -- "$MTCAL" compensate -m "$M3" --format klipper --out "$tmp/kl"
grep -q "^SKEW_PROFILE LOAD=mtcal$" "$tmp/kl/skew.gcode" && ok || bad "klipper profile load"
expect_error "klipper on a 5-axis machine" "rotary axis" -- "$MTCAL" compensate -m "$M5" --format klipper --out "$tmp/x6"
expect_exit 0 "siemens" -- "$MTCAL" compensate -m "$M3" --format siemens --points 9 --out "$tmp/si" --json
grep -q "^\$AA_ENC_COMP\[0,8,AX1\]=" "$tmp/si/AX_EEC.INI" && ok || bad "siemens table"
[ "$(json_get "d['files']")" = "['AX_EEC.INI', 'NC_CEC.INI']" ] && ok || bad "siemens files: $(json_get "d['files']")"
# Six cross tables on vmc-3axis (straightness/squareness between every pair), each 9 points, M17 last.
[ "$(grep -c '^\$AN_CEC_OUTPUT_AXIS\[[0-9]\]=(AX[123])$' "$tmp/si/NC_CEC.INI")" -eq 6 ] && ok || bad "6 CEC tables"
grep -q '^\$AN_CEC\[5,8\]=-\?[0-9.]*$' "$tmp/si/NC_CEC.INI" && [ "$(tail -n1 "$tmp/si/NC_CEC.INI")" = "M17" ] \
  && [ "$(head -n1 "$tmp/si/NC_CEC.INI")" = "%_N_NC_CEC_INI" ] && ok || bad "NC_CEC.INI layout"
[ "$(json_get "'EYX' in [n['what'] for n in d['not_compensated']]")" = "False" ] && ok || bad "EYX listed as not held"
[ "$(json_get "'EAX' in [n['what'] for n in d['not_compensated']]")" = "True" ] && ok || bad "EAX not listed"
expect_exit 0 "rrf" -- "$MTCAL" compensate -m "$M3" --format rrf --out "$tmp/rrf" --json
[ "$(json_get "list(d)[:7]")" = "['target', 'quantity', 'sign_source', 'files', 'not_compensated', 'warnings', 'residual']" ] \
  && ok || bad "rrf json keys: $(json_get "list(d)")"
[ "$(json_get "d['quantity']")" = "correction" ] && ok || bad "rrf quantity"
grep -q "^M556 S100 X0.0015 Y-0.0012 Z-0.002000018 P0$" "$tmp/rrf/rrf.gcode" && ok || bad "M556 line: $(cat "$tmp/rrf/rrf.gcode")"
expect_exit 0 "fluidnc" -- "$MTCAL" compensate -m "$M3" --format fluidnc --skew-reference-length 200 --out "$tmp/fl"
grep -q "^  Skewed:$" "$tmp/fl/fluidnc-kinematics.yaml" && grep -q "^      offset_x_mm: 0.003$" "$tmp/fl/fluidnc-kinematics.yaml" \
  && ok || bad "fluidnc yaml: $(cat "$tmp/fl/fluidnc-kinematics.yaml")"
grep -q "FluidNC/pull/849" "$tmp/fl/fluidnc-kinematics.yaml" && grep -q "warning .*#849" "$tmp/out" && ok || bad "fluidnc needs PR 849"
expect_error "rrf reference length 0" "reference length" -- "$MTCAL" compensate -m "$M3" --format rrf \
  --skew-reference-length 0 --out "$tmp/x7"
[ ! -e "$tmp/x7" ] && ok || bad "output left by a bad reference length"
expect_error "fluidnc on a 5-axis machine" "rotary axis" -- "$MTCAL" compensate -m "$M5" --format fluidnc --out "$tmp/x8"
[ ! -e "$tmp/x8" ] && ok || bad "output left by fluidnc on a 5-axis machine"
expect_error "siemens 201 points" "200" -- "$MTCAL" compensate -m "$M3" --format siemens --points 201 --out "$tmp/x9"
[ ! -e "$tmp/x9" ] && ok || bad "output left by too many siemens points"
# Etalon: the ISG parameters in the Etalon exchange format, read back as a parameter file.
KEYS="['target', 'quantity', 'sign_source', 'files', 'not_compensated', 'warnings', 'residual']"
expect_exit 0 "etalon json" -- "$MTCAL" compensate -m "$M5" --format etalon --points 11 --residual-points 3 \
  --out "$tmp/et" --json
[ "$(json_get "list(d)[:7]")" = "$KEYS" ] && ok || bad "etalon json keys: $(json_get "list(d)")"
[ "$(json_get "d['target'], d['quantity'], d['files']")" = "etalon error ['volcomp.etalon', 'README.txt']" ] \
  && ok || bad "etalon target: $(json_get "d['target'], d['quantity'], d['files']")"
grep -q "^\[C0Y\]$" "$tmp/et/volcomp.etalon" && grep -q "^Gridpoints = {$" "$tmp/et/volcomp.etalon" \
  && ok || bad "etalon blocks"
expect_exit 0 "etalon as --params" -- "$MTCAL" errors -m "$M5" --params "$tmp/et/volcomp.etalon"
grep -q "EC0Y" "$tmp/out" && ok || bad "errors with an Etalon parameter file"
printf '[C0Y]\nVALUE = 1e-5\n[EXX]\nGridpoints = {\n0 0\n10 zz\n}\n' >"$tmp/bad.etalon"
expect_error "bad etalon parameter file" "bad.etalon:6" -- "$MTCAL" compensate -m "$M5" --params "$tmp/bad.etalon" \
  --format etalon --out "$tmp/x17"
[ ! -e "$tmp/x17" ] && ok || bad "output left by a bad Etalon parameter file"
# HEIDENHAIN: *.COM per linear axis and config.cma, sign to be checked on the control.
expect_exit 0 "heidenhain json" -- "$MTCAL" compensate -m "$M3" --format heidenhain --points 21 --out "$tmp/hh" --json
[ "$(json_get "list(d)[:7]")" = "$KEYS" ] && ok || bad "heidenhain json keys"
[ "$(json_get "d['files']")" = "['X.COM', 'Y.COM', 'Z.COM', 'config.cma', 'README.txt']" ] && ok \
  || bad "heidenhain files: $(json_get "d['files']")"
for f in X.COM Y.COM Z.COM config.cma README.txt; do [ -f "$tmp/hh/$f" ] && ok || bad "no $f"; done
head -2 "$tmp/hh/X.COM" | grep -q "^NR    AXISPOS         X " && ok || bad "X.COM header: $(head -2 "$tmp/hh/X.COM")"
[ "$(tail -1 "$tmp/hh/X.COM")" = "[END]" ] && [ "$(grep -c '^[0-9]' "$tmp/hh/X.COM")" -eq 21 ] && ok || bad "X.COM rows"
grep -q "CHECKED ON THE CONTROL" "$tmp/hh/README.txt" && ok || bad "heidenhain sign warning"
expect_error "heidenhain too many points" "256" -- "$MTCAL" compensate -m "$M3" --format heidenhain --points 300 \
  --out "$tmp/x18"
[ ! -e "$tmp/x18" ] && ok || bad "output left by heidenhain --points 300"
# FANUC: parameters 3620-3625 and pitch values, corrections, sign to be checked.
expect_exit 0 "fanuc json" -- "$MTCAL" compensate -m "$M5" --format fanuc --residual-points 3 --out "$tmp/fa" --json
[ "$(json_get "list(d)[:7]")" = "$KEYS" ] && ok || bad "fanuc json keys"
[ "$(json_get "d['quantity'], d['files']")" = "correction ['fanuc-pitch.txt', 'README.txt']" ] && ok \
  || bad "fanuc: $(json_get "d['quantity'], d['files']")"
for p in 3620 3621 3622 3623 3624 3625; do grep -q "^PARAMETER $p " "$tmp/fa/fanuc-pitch.txt" && ok || bad "no $p"; done
grep -q "CHECK IT ON THE CONTROL" "$tmp/fa/fanuc-pitch.txt" && ok || bad "fanuc sign warning"
awk '$1 == "PITCH" && ($3 > 127 || $3 < -128) {exit 1}' "$tmp/fa/fanuc-pitch.txt" && ok || bad "fanuc value range"
expect_error "fanuc too many points" "128" -- "$MTCAL" compensate -m "$M3" --format fanuc --points 129 --out "$tmp/x19"
[ ! -e "$tmp/x19" ] && ok || bad "output left by fanuc --points 129"
expect_error "fanuc nothing to compensate" "nothing to compensate" -- "$MTCAL" compensate -m "$M3" --only EC0Y \
  --format fanuc --out "$tmp/x20"
[ ! -e "$tmp/x20" ] && ok || bad "output left when fanuc has nothing to compensate"
expect_error "unknown format" "expected one of: linuxcnc" -- "$MTCAL" compensate -m "$M3" --format nope --out "$tmp/x1"
[ ! -e "$tmp/x1" ] && ok || bad "output left by an unknown format"
expect_error "too many points" "256" -- "$MTCAL" compensate -m "$M3" --format linuxcnc --points 300 --out "$tmp/x2"
[ ! -e "$tmp/x2" ] && ok || bad "output left by too many points"
expect_error "range beyond travel" "travel" -- "$MTCAL" compensate -m "$M3" --format linuxcnc --range "X=-900:0" \
  --out "$tmp/x3"
expect_error "non-empty output" "not empty" -- "$MTCAL" compensate -m "$M3" --format linuxcnc --out "$tmp/lc"
expect_error "nothing to compensate" "nothing to compensate" -- "$MTCAL" compensate -m "$M3" --only EXX --set EXX.0=0 \
  --set EXX.1=0 --set EXX.2=0 --set EXX.3=0 --set EXX.b=0 --format linuxcnc --out "$tmp/x4"
[ ! -e "$tmp/x4" ] && ok || bad "output left when nothing to compensate"
expect_error "no format, no program" "--format" -- "$MTCAL" compensate -m "$M3" --out "$tmp/x5"
# The library's message in the data's words; the command names the option that is the cause.
expect_error "fanuc steep table names --points" "more table points (--points)" -- "$MTCAL" compensate -m "$M3" \
  --set EXX.1=100ppm --format fanuc --fanuc-unit 0.000001 --points 2 --out "$tmp/x6"
[ ! -e "$tmp/x6" ] && ok || bad "output left by a fanuc table too steep"
"$MTCAL" compensate -m "$M5" --format heidenhain --out "$tmp/hh-ref" > "$tmp/out" 2>&1 \
  && grep -q "reference position (--reference)" "$tmp/out" && ok || bad "heidenhain warning names --reference"
# --format linuxcnc-kins (issue 30): the module's files, the largest correction in the INI, refusals.
expect_exit 0 "linuxcnc-kins" -- "$MTCAL" compensate -m "$M5" --format linuxcnc-kins --residual-points 3 --out "$tmp/lk"
for f in mtcal_kins.c build.sh linuxcnc-kins.ini linuxcnc-kins.hal README.txt; do [ -f "$tmp/lk/$f" ] && ok || bad "linuxcnc-kins: no $f"; done
grep -q "^KINEMATICS = mtcal_kins$" "$tmp/lk/linuxcnc-kins.ini" && grep -q "^#   joint 3 (B): " "$tmp/lk/linuxcnc-kins.ini" \
  && ok || bad "linuxcnc-kins INI: kinematics and largest correction per joint"
grep -q "halcompile --install mtcal_kins.c" "$tmp/lk/build.sh" && grep -q "linuxcnc-uspace-dev" "$tmp/lk/build.sh" \
  && ok || bad "linuxcnc-kins build line"
# Without linuxcnc-uspace-dev (no halcompile on the PATH): one line naming the package.
PATH=/nonexistent /bin/sh "$tmp/lk/build.sh" >"$tmp/out" 2>"$tmp/err" && bad "build.sh without halcompile: exit 0" \
  || { [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q "install Debian's linuxcnc-uspace-dev" "$tmp/err" && ok \
  || bad "build.sh without halcompile: $(cat "$tmp/err")"; }
printf 'mtcal_machine: 1\nname: two\ntopology: wXfYt\nunits: {length: mm, angle: deg}\naxes:\n  X: {direction: +x, travel: [-100, 100]}\n  Y: {direction: +y, travel: [-100, 100]}\ntool: {length: 0, spindle_point: [0, 0, 0], axis: +z}\nerrors:\n  EXX: {unit: um, argument_unit: m, polynomial: [0, 5]}\n' >"$tmp/two.yaml"
expect_error "linuxcnc-kins two linear axes" "exactly three" -- "$MTCAL" compensate -m "$tmp/two.yaml" --format linuxcnc-kins \
  --out "$tmp/x30"
[ ! -e "$tmp/x30" ] && ok || bad "output left by a topology the module cannot represent"
expect_error "linuxcnc-kins no room" "leaves its travel" -- "$MTCAL" compensate -m "$M3" --format linuxcnc-kins \
  --range "X=-400:400" --out "$tmp/x31"
[ ! -e "$tmp/x31" ] && ok || bad "output left when a corrected joint leaves its travel"
# 0.6 rad of squareness (with the CLI's plausibility warning): the fixed cap of steps is not enough.
"$MTCAL" compensate -m "$M3" --format linuxcnc-kins --set EC0Y=0.6rad --out "$tmp/x32" >"$tmp/out" 2>"$tmp/err" \
  && bad "linuxcnc-kins not converging: exit 0" || { grep -q "error: .*does not converge at X=" "$tmp/err" && ok \
  || bad "linuxcnc-kins not converging: $(cat "$tmp/err")"; }
[ ! -e "$tmp/x32" ] && ok || bad "output left when the inverse does not converge"
# Its commanded travel (issue 33): without --range the travel less the room the corrections need, said in
# the summary, the JSON and the INI; a squareness of 1 mm/m corrects X by 0.25 mm, more than the old fixed 0.1 mm.
expect_exit 0 "linuxcnc-kins chooses its range" -- "$MTCAL" compensate -m "$M3" --format linuxcnc-kins --set EC0Y=1e-3rad \
  --residual-points 3 --out "$tmp/lk-room" --json
python3 - "$tmp/out" <<'PY' && ok || bad "linuxcnc-kins: commanded_range computed, X's room >= 1.25 x its correction > 0.2 mm"
import json, sys
d = json.load(open(sys.argv[1]))
r = {c["axis"]: c for c in d["commanded_range"]}
assert set(r) == {"X", "Y", "Z"} and not any(c["given"] for c in r.values()), r
x = r["X"]
assert x["largest_correction"] > 0.2 and x["margin"] >= 1.25 * x["largest_correction"], x
assert abs(x["lo"] - (-400 + x["margin"])) < 1e-9 and abs(x["hi"] - (400 - x["margin"])) < 1e-9, x
assert "largest correction over the travel" in x["why"] and x["unit"] == "mm", x
PY
grep -q "^#   X -399\.[0-9]* to 399\.[0-9]* mm (the travel less " "$tmp/lk-room/linuxcnc-kins.ini" && ok || bad "INI: the commanded travel"
expect_exit 0 "linuxcnc-kins --range given" -- "$MTCAL" compensate -m "$M3" --format linuxcnc-kins --set EC0Y=1e-3rad \
  --range "Y=-200:200" --residual-points 3 --out "$tmp/lk-given"
grep -q "^range        Y -200:200 mm (--range)$" "$tmp/out" && grep -q "^range        X -399.* mm (the travel less" "$tmp/out" \
  && ok || bad "linuxcnc-kins summary: the range given and the ranges computed"
summary_and_exit
