#!/usr/bin/env bash
# Values with units where a user types them (--set, --at, --grid, --box, --centre, radii, noise,
# steps, --target-va), plausibility warnings, no silent ballbar radius, and "did you mean" for
# mistyped commands, options, parameter and error names.
# Needs MTCAL and EXAMPLES. Prints "N passed, N failed".
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
M3="$EXAMPLES/vmc-3axis.yaml"
M5="$EXAMPLES/hu40t-wCBXfYZt.yaml"

# The same configuration typed in mm/deg, with units, and in other units: identical output.
"$MTCAL" eval -m "$M5" --at "X=100,Y=50,Z=-20,B=30,C=90" --json >"$tmp/plain.json"
for at in "X=100mm,Y=50mm,Z=-20mm,B=30deg,C=90deg" "X=0.1m,Y=50000um,Z=-20000µm,B=0.5235987755982988rad,C=90 deg" \
  "X=3.937007874015748in,Y=50,Z=-0.02m,B=30,C=1.5707963267948966rad"; do
  "$MTCAL" eval -m "$M5" --at "$at" --json >"$tmp/units.json" 2>"$tmp/err"
  python3 - "$tmp/plain.json" "$tmp/units.json" <<'PY' && ok || bad "--at '$at' differs from mm/deg: $(cat "$tmp/err")"
import json, sys
a, b = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
assert all(abs(a[k] - b[k]) <= 1e-12 * max(1e-9, abs(a[k])) for k in a), (a, b)
PY
done
expect_error "--at length unit on a rotary axis" "'mm' is a length; expected an angle unit" -- "$MTCAL" eval -m "$M5" --at "B=30mm"
expect_error "--at slope on an axis" "'um/m' is a slope" -- "$MTCAL" eval -m "$M5" --at "X=3um/m"
expect_error "--at unknown unit" "unknown unit 'furlong'" -- "$MTCAL" eval -m "$M5" --at "X=3furlong"
grep -q "mm, um, nm, m, in" "$tmp/err" && ok || bad "the bad-unit message lists the length units: $(cat "$tmp/err")"

# --set: EC0Y = 20 urad in every spelling gives one answer; a bare number is the internal unit.
"$MTCAL" eval -m "$M3" --at "Y=200" --only EC0Y --set EC0Y=2e-5 --json >"$tmp/ref.json"
for v in 20urad 20µrad "20 urad" 20um/m 20ppm 0.02mm/m 0.00114591559deg; do
  "$MTCAL" eval -m "$M3" --at "Y=200" --only EC0Y --set "EC0Y=$v" --json >"$tmp/v.json" 2>"$tmp/err"
  python3 -c "
import json; a = json.load(open('$tmp/ref.json')); b = json.load(open('$tmp/v.json'))
assert abs(a['dx'] - b['dx']) < 1e-12 and abs(a['dx']) > 3e-3, (a, b)" && ok || bad "--set EC0Y=$v: $(cat "$tmp/err")"
  [ ! -s "$tmp/err" ] && ok || bad "--set EC0Y=$v warns: $(cat "$tmp/err")"
done
# A scale error in ppm and um/m, an offset in um: 5 ppm over 300 mm = 1.5 um.
for v in 5ppm 5um/m 5e-6; do
  "$MTCAL" eval -m "$M3" --at "X=300" --only EXX.1 --set "EXX.1=$v" --json >"$tmp/out" 2>"$tmp/err"
  python3 -c "import json; d = json.load(open('$tmp/out')); assert abs(d['dx'] - 1.5e-3) < 1e-12, d" && ok || bad "--set EXX.1=$v"
done
expect_error "--set length on an angle" "--set: field 'EC0Y': 'um' is a length; expected an angle unit" -- \
  "$MTCAL" eval -m "$M3" --at Y=1 --set EC0Y=20um
expect_error "--set bad unit" "unknown unit 'urads'" -- "$MTCAL" eval -m "$M3" --at Y=1 --set EC0Y=20urads

# Plausibility: a squareness of 20 rad (meant urad), an error of 1 m: warnings on stderr, exit 0.
"$MTCAL" eval -m "$M3" --at Y=200 --set EC0Y=20 >"$tmp/out" 2>"$tmp/err"
[ $? -eq 0 ] && grep -q "mtcal: warning: --set EC0Y=20: EC0Y = 20 rad" "$tmp/err" && grep -q "urad" "$tmp/err" && ok ||
  bad "no warning for EC0Y=20: $(cat "$tmp/err")"
"$MTCAL" eval -m "$M3" --at Y=200 --set EXX.0=1m >"$tmp/out" 2>"$tmp/err"
grep -q "warning: --set EXX.0=1m: EXX.0 = 1000 mm" "$tmp/err" && ok || bad "no warning for a 1 m error: $(cat "$tmp/err")"
"$MTCAL" eval -m "$M3" --at Y=200 --set EXX.1=20 >"$tmp/out" 2>"$tmp/err"
grep -q "warning: .*um/m" "$tmp/err" && ok || bad "no warning for a scale error of 20: $(cat "$tmp/err")"
# A grid typed in metres on a machine in mm (X travels 800 mm).
"$MTCAL" eval -m "$M3" --grid "X=-0.4:0.4:5,Y=-250:250:3" >"$tmp/out" 2>"$tmp/err"
grep -q "warning: --grid: axis X spans 0.8 mm, under 1% of its 800 mm travel" "$tmp/err" && ok ||
  bad "no warning for a grid in metres: $(cat "$tmp/err")"
"$MTCAL" eval -m "$M3" --grid "X=-0.4m:0.4m:5,Y=-250:250:3" --out "$tmp/g.csv" >"$tmp/out" 2>"$tmp/err"
[ ! -s "$tmp/err" ] && head -2 "$tmp/g.csv" | tail -1 | grep -q "^-400,-250," && ok || bad "grid in metres with units: $(cat "$tmp/err")"
# The grid's order: the later axis of the chain (wXYfZt: Y after X) varies fastest.
python3 - "$tmp/g.csv" <<'PY' && ok || bad "grid order"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert [(r["X"], r["Y"]) for r in rows[:4]] == [("-400", "-250"), ("-400", "0"), ("-400", "250"), ("-200", "-250")], rows[:4]
PY

# Options with units: ballbar radius, probe diameters and noise, toolpath step, identification noise.
expect_error "ballbar without radius" "expected the nominal radius of the test" -- "$MTCAL" ballbar "$tmp/none.csv"
"$MTCAL" ballbar --predict -m "$M5" --plane XY --radius 150 --centre "Z=-100" --out "$tmp/t1.csv" >/dev/null &&
  "$MTCAL" ballbar --predict -m "$M5" --plane XY --radius 0.15m --centre "Z=-0.1m" --out "$tmp/t2.csv" >/dev/null &&
  cmp -s "$tmp/t1.csv" "$tmp/t2.csv" && ok || bad "ballbar --radius 0.15m differs from 150"
"$MTCAL" ballbar "$tmp/t1.csv" --radius 150 --json >"$tmp/b1.json" && "$MTCAL" ballbar "$tmp/t1.csv" --radius 150mm --json >"$tmp/b2.json" &&
  cmp -s "$tmp/b1.json" "$tmp/b2.json" && ok || bad "ballbar --radius 150mm"
expect_error "ballbar radius in deg" "'deg' is an angle" -- "$MTCAL" ballbar "$tmp/t1.csv" --radius 150deg
"$MTCAL" probe-sim -m "$M5" --axis C --angles 0:350:36 --noise 1um --sphere-diameter 30mm --stylus-diameter 0.25in --out "$tmp/p1.csv" >/dev/null &&
  "$MTCAL" probe-sim -m "$M5" --axis C --angles 0:350:36 --noise 0.001 --sphere-diameter 30 --stylus-diameter 6.35 --out "$tmp/p2.csv" >/dev/null &&
  cmp -s "$tmp/p1.csv" "$tmp/p2.csv" && ok || bad "probe-sim with units differs"
P="$EXAMPLES/../plans/hu40t-samba-tango.csv"
"$MTCAL" simulate -m "$M5" --plan "$P" --noise-um 1 --out "$tmp/s1.csv" >/dev/null &&
  "$MTCAL" simulate -m "$M5" --plan "$P" --noise-um 0.001mm --out "$tmp/s2.csv" >/dev/null &&
  cmp -s "$tmp/s1.csv" "$tmp/s2.csv" && ok || bad "simulate --noise-um 0.001mm differs from 1"

# Did you mean: commands, options, parameter and error names (case-insensitive edit distance).
expect_error "mistyped command" "unknown command 'evl' (did you mean 'eval'?)" -- "$MTCAL" evl
expect_error "mistyped option" "(did you mean '--grid' for '--grdi'?)" -- "$MTCAL" eval -m "$M3" --grdi X=1
grep -q "see 'mtcal eval --help'" "$tmp/err" && ok || bad "the option error points at the command's help"
expect_error "lower-case parameter" "unknown parameter 'ec0y' (did you mean 'EC0Y'?)" -- "$MTCAL" eval -m "$M3" --at X=1 --set ec0y=1urad
expect_error "mistyped coefficient" "(did you mean 'EXX.1'?)" -- "$MTCAL" eval -m "$M3" --at X=1 --set EXX.l=1e-6
expect_error "mistyped --only" "unknown error name 'EC0U' (did you mean 'EC0Y'?)" -- "$MTCAL" eval -m "$M3" --at X=1 --only EC0U
expect_error "mistyped --errors" "(did you mean 'EXX'?)" -- "$MTCAL" effects -m "$M3" --at X=1 --errors exx
expect_error "mistyped --estimate" "(did you mean 'EX0C'?)" -- "$MTCAL" identifiability -m "$M5" --plan "$P" --estimate EXOC
expect_error "nothing close" "unknown parameter 'QQQQ' for machine" -- "$MTCAL" eval -m "$M3" --at X=1 --set QQQQ=1
grep -q "did you mean" "$tmp/err" && bad "a suggestion for a name nothing is close to" || ok
# --precision: 10 significant digits by default in CSV cells; 17 round-trips every double bit for
# bit (checked against the JSON of the same configurations, which nlohmann writes exactly).
"$MTCAL" eval -m "$M5" --grid "X=-300:300:3,B=-90:90:3,C=0:270:4" --out "$tmp/p10.csv" >/dev/null &&
  "$MTCAL" eval -m "$M5" --grid "X=-300:300:3,B=-90:90:3,C=0:270:4" --out "$tmp/p17.csv" --precision 17 >/dev/null && ok ||
  bad "eval --precision"
python3 - "$tmp/p10.csv" <<'PY' && ok || bad "default CSV cells do not carry 10 significant digits"
import csv, re, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for r in rows:
    for k in ("dx", "dy", "dz", "rx", "ry", "rz"):
        m = re.fullmatch(r"-?(\d)\.(\d+)e[-+]\d+", r[k])
        assert m and len(m.group(1) + m.group(2)) == 10, r[k]
PY
# Bit for bit: the same diagonals written as CSV with 17 digits and as JSON (exact) read back equal;
# with the default 10 digits they do not (so the check can fail).
"$MTCAL" diagonals -m "$M3" --box "X=-400:400,Y=-250:250,Z=-500:0" --points 11 --out "$tmp/d17.csv" --precision 17 \
  --json >"$tmp/d.json" && "$MTCAL" diagonals -m "$M3" --box "X=-400:400,Y=-250:250,Z=-500:0" --points 11 \
  --out "$tmp/d10.csv" >/dev/null && ok || bad "diagonals --precision 17"
python3 - "$tmp/d17.csv" "$tmp/d10.csv" "$tmp/d.json" <<'PY' && ok || bad "--precision 17 does not round-trip"
import csv, json, sys
d = json.load(open(sys.argv[3]))
exact = {(g["name"], i): (p, v) for g in d["diagonals"] for i, (p, v) in enumerate(zip(g["position"], g["deviation"]))}
def read(path):
    rows, count = {}, {}
    for r in csv.reader(open(path)):
        if r[0] == "diagonal": continue
        i = count.get(r[0], 0); count[r[0]] = i + 1
        rows[(r[0], i)] = (float(r[1]), float(r[2]))
    return rows
r17, r10 = read(sys.argv[1]), read(sys.argv[2])
assert len(r17) == len(exact) == 16 * 11, len(r17)  # 4 body and 12 face diagonals
assert all(r17[k][0].hex() == exact[k][0].hex() and r17[k][1].hex() == exact[k][1].hex() for k in exact)  # bit for bit
assert any(r10[k][1] != exact[k][1] for k in exact)  # 10 digits are not
PY
"$MTCAL" eval -m "$M5" --at "X=100,B=30,C=90" --precision 17 >"$tmp/out" &&
  python3 - "$tmp/out" "$MTCAL" "$M5" <<'PY' && ok || bad "eval --at --precision 17 text is not exact"
import json, subprocess, sys
text = {l.split()[0]: l.split()[1] for l in open(sys.argv[1])}
j = json.loads(subprocess.run([sys.argv[2], "eval", "-m", sys.argv[3], "--at", "X=100,B=30,C=90", "--json"],
                              check=True, capture_output=True, text=True).stdout)
assert all(float(text[k]) == j[k] for k in j), (text, j)
PY
expect_error "precision 18" "--precision" -- "$MTCAL" eval -m "$M5" --at X=1 --precision 18
for c in $("$MTCAL" --help | awk '/^Subcommands:/ { on = 1; next } on && /^  [a-z]/ { print $1 } on && /^$/ { on = 0 }'); do
  "$MTCAL" "$c" --help | grep -q -- "--precision" && ok || bad "mtcal $c has no --precision"
done
summary_and_exit
