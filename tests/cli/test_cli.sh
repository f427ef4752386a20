#!/usr/bin/env bash
# Command-line tests: exit codes, one-line errors, JSON keys, CSV in/out, no partial outputs.
# Needs MTCAL (the binary) and EXAMPLES (examples/machines). Prints "N passed, N failed".
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
M5="$EXAMPLES/hu40t-wCBXfYZt.yaml"
M3="$EXAMPLES/vmc-3axis.yaml"

expect_exit 0 "--version" -- "$MTCAL" --version
grep -q '^mtcal [0-9]' "$tmp/out" && ok || bad "--version prints mtcal VERSION"
grep -q '^error kernels: [a-z0-9]* (this processor: baseline' "$tmp/out" && ok || bad "--version names the kernels' level: $(cat "$tmp/out")"

# The kernels' instruction-set levels (MTCAL_KERNEL_ISA, docs/performance.md) give the same bytes;
# a level that is not one, or that the processor lacks, is refused in the variable's words.
expect_error "MTCAL_KERNEL_ISA unknown" "MTCAL_KERNEL_ISA: expected baseline, avx2 or avx512, found \"sse9\"" -- \
  env MTCAL_KERNEL_ISA=sse9 "$MTCAL" eval -m "$M5" --at X=0
isa_grid="X=-300:300:7,Y=-250:250:5,Z=-300:0:4,B=-90:90:7,C=0:360:9"
python3 -c "
import random; random.seed(4); print('X,Y,Z,B,C')
for i in range(333): print(','.join(str(round(random.uniform(a, b), 6)) for a, b in ((-300, 300), (-250, 250), (-300, 0), (-90, 90), (0, 360))))
" >"$tmp/isa_points.csv"
levels=$(sed -n 's/^error kernels: .*(this processor:\([a-z0-9 ]*\);.*/\1/p' <("$MTCAL" --version))
[ -n "$levels" ] && ok || bad "--version lists the processor's levels"
for isa in $levels; do
  # .npy: the doubles themselves, so that cmp compares every bit.
  MTCAL_KERNEL_ISA=$isa "$MTCAL" eval -m "$M5" --grid "$isa_grid" --out "$tmp/isa_grid_$isa.npy" >/dev/null 2>"$tmp/err" &&
    cmp -s "$tmp/isa_grid_baseline.npy" "$tmp/isa_grid_$isa.npy" && ok || bad "eval --grid with MTCAL_KERNEL_ISA=$isa differs from baseline or fails: $(cat "$tmp/err")"
  MTCAL_KERNEL_ISA=$isa "$MTCAL" eval -m "$M5" --points "$tmp/isa_points.csv" --out "$tmp/isa_points_$isa.npy" >/dev/null 2>"$tmp/err" &&
    cmp -s "$tmp/isa_points_baseline.npy" "$tmp/isa_points_$isa.npy" && ok || bad "eval --points with MTCAL_KERNEL_ISA=$isa differs from baseline or fails: $(cat "$tmp/err")"
done
expect_exit 0 "--help" -- "$MTCAL" --help
grep -q 'eval' "$tmp/out" && grep -q 'errors' "$tmp/out" && ok || bad "--help lists commands"
expect_exit 0 "eval --help" -- "$MTCAL" eval --help
grep -q -- '--points' "$tmp/out" && ok || bad "eval --help lists --points"
expect_exit 0 "errors --help" -- "$MTCAL" errors --help
expect_error "no command" "subcommand is required" -- "$MTCAL"
expect_error "unknown command" "frob" -- "$MTCAL" frob
expect_error "unknown option" "--bogus" -- "$MTCAL" eval -m "$M5" --at X=0 --bogus
expect_error "non-numeric option" "tool-length" -- "$MTCAL" eval -m "$M5" --at X=0 --tool-length abc
expect_error "infinite tool length" "expected a length" -- "$MTCAL" eval -m "$M5" --at X=0 --tool-length inf
expect_error "negative tool length" "expected a length" -- "$MTCAL" eval -m "$M5" --at X=0 --tool-length -5
expect_error "threads out of range" "threads" -- "$MTCAL" eval -m "$M5" --grid X=0 --threads -1

# eval --at, text and JSON.
expect_exit 0 "eval --at" -- "$MTCAL" eval -m "$M5" --at "X=100,Y=50,Z=-20,B=30,C=90"
[ "$(grep -cE '^(dx|dy|dz|rx|ry|rz) ' "$tmp/out")" -eq 6 ] && ok || bad "eval prints 6 components"
expect_exit 0 "eval --at --json" -- "$MTCAL" eval -m "$M5" --at "X=100,Y=50,Z=-20,B=30,C=90" --json
[ "$(json_get "sorted(d.keys())")" = "['dx', 'dy', 'dz', 'rx', 'ry', 'rz']" ] && ok || bad "eval JSON keys: $(cat "$tmp/out")"

# --only: with only the X positioning error, only dx is non-zero and equals the polynomial.
expect_exit 0 "eval --only" -- "$MTCAL" eval -m "$M3" --at "X=100,Y=50,Z=-20" --only EXX --json
[ "$(json_get "(d['dy'], d['dz'], d['rx'], d['ry'], d['rz'])")" = "(0.0, 0.0, 0.0, 0.0, 0.0)" ] && ok || bad "--only EXX leaves other components zero: $(cat "$tmp/out")"
# --set on a zeroed machine: EC0Y = 1e-5 at Y=200 gives dx = -200 sin(1e-5).
expect_exit 0 "eval --set" -- "$MTCAL" eval -m "$M3" --at "Y=200" --only EC0Y --set EC0Y=1e-5 --json
python3 -c "import json,math; d=json.load(open('$tmp/out')); assert abs(d['dx'] + 200*math.sin(1e-5)) < 1e-15, d" && ok || bad "--set EC0Y value"
# --tool-length changes the effect of a tool tilt: EAt=1e-4 with L=200 gives dy = 200 sin(1e-4).
expect_exit 0 "eval --tool-length" -- "$MTCAL" eval -m "$M3" --at "X=0" --only EAt --set EAt=1e-4 --tool-length 200 --json
python3 -c "import json,math; d=json.load(open('$tmp/out')); assert abs(d['dy'] - 200*math.sin(1e-4)) < 1e-15, d" && ok || bad "--tool-length"

# effects: per 1 um / 1 urad about the nominal machine; hand values for the mill at
# X=300,Y=200,Z=-400 (tool 100 mm): EC0Y tilts Y, dx = -Y * 1 urad = -0.2 um.
expect_exit 0 "effects" -- "$MTCAL" effects -m "$M3" --at "X=300,Y=200,Z=-400"
grep -qE '^EC0Y +location +urad +-0.2 ' "$tmp/out" && ok || bad "effects EC0Y row: $(grep EC0Y "$tmp/out")"
expect_exit 0 "effects --json" -- "$MTCAL" effects -m "$M5" --at "X=100,B=30,C=90" --errors EX0C,ECC --json
[ "$(json_get "[e['error'] for e in d['effects']]")" = "['ECC', 'EX0C']" ] && ok || bad "effects --errors filter"
[ "$(json_get "sorted(d['effects'][0].keys())")" = "['dx', 'dy', 'dz', 'error', 'kind', 'per', 'rx', 'ry', 'rz']" ] && ok || bad "effects JSON keys"
[ "$(json_get "d['at']['B']")" = "30.0" ] && ok || bad "effects 'at' in user units"
# EX0C at C=90 deg: (I - Rz(90)) e = (e, -e, 0).
python3 -c "import json; d=json.load(open('$tmp/out')); e=[x for x in d['effects'] if x['error']=='EX0C'][0]; assert abs(e['dx']-1)<1e-12 and abs(e['dy']+1)<1e-12, e" && ok || bad "effects EX0C at C=90"
expect_error "effects unknown error" "unknown error name 'EQQ'" -- "$MTCAL" effects -m "$M5" --at X=0 --errors EQQ
expect_exit 0 "effects --around actual" -- "$MTCAL" effects -m "$M5" --at "X=100" --around actual --json
[ "$(json_get "d['around']")" = "actual" ] && ok || bad "effects --around"

# errors.
expect_exit 0 "errors" -- "$MTCAL" errors -m "$M5"
grep -q '^EX0C ' "$tmp/out" && grep -q '^EXX.1 ' "$tmp/out" && ok || bad "errors lists EX0C and EXX.1"
expect_exit 0 "errors --json" -- "$MTCAL" errors -m "$M5" --json
[ "$(json_get "sorted(d['parameters'][0].keys())")" = "['error', 'kind', 'name', 'unit', 'value']" ] && ok || bad "errors JSON keys"
[ "$(json_get "d['topology']")" = "wCBXfYZt" ] && ok || bad "errors JSON topology"

# CSV points in, CSV out.
printf 'X,Y,Z,B,C,dirX\n0,0,0,0,0,1\n100,50,-20,30,90,-1\n' >"$tmp/p.csv"
expect_exit 0 "eval --points" -- "$MTCAL" eval -m "$M5" --points "$tmp/p.csv" --out "$tmp/o.csv" --json
[ "$(head -1 "$tmp/o.csv")" = "C,B,X,Y,Z,dirC,dirB,dirX,dirY,dirZ,dx,dy,dz,rx,ry,rz" ] && ok || bad "output header: $(head -1 "$tmp/o.csv")"
[ "$(wc -l <"$tmp/o.csv")" -eq 3 ] && ok || bad "output rows"
[ "$(json_get "d['configurations']")" = "2" ] && ok || bad "batch JSON configurations"
# --out FILE.npy: the same rows as the CSV, as float64, read by numpy.load (the reference reader
# of the .npy format); the CSV's numbers are its 10 significant digits of these doubles.
expect_exit 0 "eval --points --out .npy" -- "$MTCAL" eval -m "$M5" --points "$tmp/p.csv" --out "$tmp/o.npy"
expect_exit 0 "eval --grid --out .npy" -- "$MTCAL" eval -m "$M5" --grid "X=-300:300:4,Y=0:100:3,B=-30:30:2" --out "$tmp/g.npy"
"$MTCAL" eval -m "$M5" --grid "X=-300:300:4,Y=0:100:3,B=-30:30:2" --out "$tmp/g.csv" >/dev/null
/usr/bin/python3 - "$tmp" <<'PY' && ok || bad "--out .npy equals the CSV (numpy.load)"
import sys, numpy as np
t = sys.argv[1]
for name, cols in (("o", 16), ("g", 11)):
    a = np.load(f"{t}/{name}.npy")
    c = np.loadtxt(f"{t}/{name}.csv", delimiter=",", skiprows=1, ndmin=2)
    assert a.dtype == np.float64 and a.shape == c.shape and a.shape[1] == cols, (a.shape, c.shape)
    assert np.allclose(a, c, rtol=1e-9, atol=1e-15), np.abs(a - c).max()
    assert np.any(a[:, -6:] != 0)
with open(f"{t}/g.npy", "rb") as f:
    head = f.read(128)
assert head[:8] == b"\x93NUMPY\x01\x00" and head[127:128] == b"\n"
PY
# A batch row without directions agrees with --at to the printed precision.
printf 'X,Y,Z,B,C\n100,50,-20,30,90\n' >"$tmp/p2.csv"
"$MTCAL" eval -m "$M5" --points "$tmp/p2.csv" --out "$tmp/o2.csv" >/dev/null
"$MTCAL" eval -m "$M5" --at "X=100,Y=50,Z=-20,B=30,C=90" --json >"$tmp/at.json"
python3 - "$tmp/o2.csv" "$tmp/at.json" <<'PY' && ok || bad "batch row equals --at"
import csv, json, sys
row = list(csv.DictReader(open(sys.argv[1])))[0]
at = json.load(open(sys.argv[2]))
for k in ("dx", "dy", "dz", "rx", "ry", "rz"):
    assert abs(float(row[k]) - at[k]) <= 1e-9 * abs(at[k]) + 1e-15, (k, row[k], at[k])
PY

# Grid summary.
expect_exit 0 "eval --grid" -- "$MTCAL" eval -m "$M5" --grid "X=-100:100:3,B=-90:90:5,C=0:270:4" --json
[ "$(json_get "d['configurations']")" = "60" ] && ok || bad "grid count"
[ "$(json_get "sorted(d['max_translation']['at'].keys())")" = "['B', 'C', 'X', 'Y', 'Z']" ] && ok || bad "grid JSON 'at' keys"

# Errors: one line on stderr, non-zero exit, no partial output file.
expect_error "missing machine file" "nope.yaml" -- "$MTCAL" eval -m "$tmp/nope.yaml" --at X=0
printf 'mtcal_machine: 1\ntopology: wXfYZt\naxes: {X: {}, Y: {}, Z: {}}\nerrors:\n  EXX: {unit: furlong, polynomial: [1]}\n' >"$tmp/badunit.yaml"
expect_error "bad unit" "badunit.yaml:5" -- "$MTCAL" errors -m "$tmp/badunit.yaml"
expect_error "unknown axis in --at" "axis 'Q'" -- "$MTCAL" eval -m "$M5" --at "Q=1"
expect_error "non-numeric --at" "expected a number" -- "$MTCAL" eval -m "$M5" --at "X=abc"
expect_error "outside travel" "outside the travel" -- "$MTCAL" eval -m "$M3" --at "X=5000"
expect_exit 0 "--no-travel-check" -- "$MTCAL" eval -m "$M3" --at "X=5000" --no-travel-check
expect_error "unknown --set" "unknown parameter 'EQQ.1'" -- "$MTCAL" eval -m "$M5" --at X=0 --set EQQ.1=1
expect_error "bad --set value" "expected a number" -- "$MTCAL" eval -m "$M5" --at X=0 --set EXX.1=x
expect_error "unknown --only" "unknown error name 'EXQ'" -- "$MTCAL" eval -m "$M5" --at X=0 --only EXQ
expect_error "two modes" "exactly one" -- "$MTCAL" eval -m "$M5" --at X=0 --grid X=0
printf 'X,Y,Z,B,C\n0,0,0,0,0\n1,2,zz,4,5\n' >"$tmp/badpoints.csv"
expect_error "bad CSV value" "badpoints.csv:3" -- "$MTCAL" eval -m "$M5" --points "$tmp/badpoints.csv" --out "$tmp/partial.csv"
[ ! -e "$tmp/partial.csv" ] && ok || bad "no partial output file after a failure"
printf 'X,Y,Q\n0,0,0\n' >"$tmp/badcol.csv"
expect_error "unknown CSV column" "unknown column 'Q'" -- "$MTCAL" eval -m "$M5" --points "$tmp/badcol.csv"
printf 'X,dirX\n0,2\n' >"$tmp/baddir.csv"
expect_error "bad direction" "expected +1, -1 or 0" -- "$MTCAL" eval -m "$M5" --points "$tmp/baddir.csv"
expect_error "unwritable output" "cannot write" -- "$MTCAL" eval -m "$M5" --points "$tmp/p.csv" --out "/nonexistent-dir/o.csv"
expect_error "output is a directory" "is a directory" -- "$MTCAL" eval -m "$M5" --points "$tmp/p.csv" --out "$tmp"
expect_error "machine is a directory" "is a directory" -- "$MTCAL" errors -m "$tmp"
printf 'dx,dy\n0,0\n' >"$tmp/noaxis.csv"
expect_error "CSV without axis columns" "no axis column" -- "$MTCAL" eval -m "$M5" --points "$tmp/noaxis.csv"
expect_error "overflowing grid" "not a joint position" -- "$MTCAL" eval -m "$M5" --grid "X=-1e308:1e308:3" --no-travel-check
expect_error "huge angle" "not a joint position" -- "$MTCAL" eval -m "$M5" --at "C=1e20" --no-travel-check
expect_error "empty --only" "found none" -- "$MTCAL" eval -m "$M5" --at X=0 --only ,
if [ -w /dev/full ]; then
  "$MTCAL" eval -m "$M5" --at X=0 >/dev/full 2>"$tmp/err"; rc=$?
  [ "$rc" -ne 0 ] && grep -q "standard output" "$tmp/err" && ok || bad "full stdout: exit $rc"
fi
# --set applies after --only: an error --only dropped can still be given a value.
"$MTCAL" eval -m "$M3" --at "X=100,Y=200" --only EXX --json >"$tmp/only.json"
expect_exit 0 "--only then --set" -- "$MTCAL" eval -m "$M3" --at "X=100,Y=200" --only EXX --set EC0Y=1e-5 --json
python3 -c "
import json, math
a = json.load(open('$tmp/only.json')); b = json.load(open('$tmp/out'))
assert abs(b['dx'] - (a['dx'] - 200 * math.sin(1e-5))) < 1e-12, (a, b)
" && ok || bad "--set after --only"

# probe-sim and rotary-axis: simulated contacts on the RRTTT example's C table.
MR="$EXAMPLES/rrttt-table-table.yaml"
expect_exit 0 "probe-sim" -- "$MTCAL" probe-sim -m "$MR" --axis C --angles 0:350:36 --sphere 150,-40,80 --out "$tmp/contacts.csv"
[ "$(head -1 "$tmp/contacts.csv")" = "C,x,y,z,approach_x,approach_y,approach_z" ] && ok || bad "contacts header: $(head -1 "$tmp/contacts.csv")"
[ "$(tail -n +2 "$tmp/contacts.csv" | wc -l)" -eq 180 ] && ok || bad "contacts rows: $(wc -l <"$tmp/contacts.csv")"
[ "$(cut -d, -f1 "$tmp/contacts.csv" | tail -n +2 | sort -u | wc -l)" -eq 36 ] && ok || bad "contacts: 36 distinct C angles"
expect_exit 0 "rotary-axis --json" -- "$MTCAL" rotary-axis --axis C --contacts "$tmp/contacts.csv" --sphere-diameter 30 --stylus-diameter 6 --machine "$MR" --json
[ "$(json_get "d['axis']")" = "C" ] && ok || bad "rotary-axis JSON axis"
[ "$(json_get "d['indexations']")" = "36" ] && ok || bad "rotary-axis JSON indexations"
[ "$(json_get "d['triples']['triples']")" = "7140" ] && ok || bad "rotary-axis JSON triples count"
json_get "all(k in d['triples'] for k in ('EX0C', 'EX0C_u', 'EX0C_spread', 'histograms'))" | grep -qx True && ok || bad "rotary-axis JSON triples keys: $(json_get "list(d['triples'])")"
json_get "all(k + s in d['least_squares'] for k in ('EX0C', 'EY0C', 'EA0C', 'EB0C') for s in ('', '_u'))" | grep -qx True && ok || bad "rotary-axis JSON least_squares keys: $(json_get "list(d['least_squares'])")"
[ "$(json_get "len(d['centres'])")" = "36" ] && ok || bad "rotary-axis JSON centres"
json_get "all(k in d['centres'][0] for k in ('angle', 'x', 'y', 'z', 'least_squares', 'rms', 'effective_radius'))" | grep -qx True && ok || bad "rotary-axis JSON centre keys: $(json_get "list(d['centres'][0])")"
expect_exit 0 "rotary-axis text" -- "$MTCAL" rotary-axis --axis C --contacts "$tmp/contacts.csv" --sphere-diameter 30 --stylus-diameter 6
grep -q '^EX0C ' "$tmp/out" && grep -q '^EB0C ' "$tmp/out" && ok || bad "rotary-axis text lists EX0C .. EB0C: $(cat "$tmp/out")"

# Noise-free recovery: a machine whose only errors are C's location errors, given by a
# parameter file on top of an error-free machine file.
cat >"$tmp/clean.yaml" <<'YAML'
mtcal_machine: 1
name: "C location errors only"
topology: wCAYXfZt
axes:
  C: {point: [0, 0, 0]}
  A: {point: [0, 0, -50]}
  Y: {}
  X: {}
  Z: {point: [0, 0, 300]}
tool: {length: 100, spindle_point: [0, 0, 400]}
YAML
cat >"$tmp/truth.yaml" <<'YAML'
mtcal_parameters: 1
description: the truth of the simulation
errors:
  EX0C: 12 um
  EY0C: -8 um
  EA0C: 25 urad
  EB0C: -40 urad
YAML
# The same errors written into a machine file, for comparison.
{ cat "$tmp/clean.yaml"; echo "errors:"; sed -n '/^errors:/,$p' "$tmp/truth.yaml" | tail -n +2; } >"$tmp/cerr.yaml"
expect_exit 0 "machine with C errors only" -- "$MTCAL" errors -m "$tmp/clean.yaml" --params "$tmp/truth.yaml" --nonzero --json
"$MTCAL" errors -m "$tmp/cerr.yaml" --nonzero --json >"$tmp/cerr.json"
cmp -s <(json_get "d['parameters']") <(python3 -c "import json; print(json.load(open('$tmp/cerr.json'))['parameters'])") && ok || bad "--params gives the machine-file errors"
[ "$(json_get "sorted(p['name'] for p in d['parameters'])")" = "['EA0C', 'EB0C', 'EX0C', 'EY0C']" ] && ok || bad "only C location errors: $(cat "$tmp/out")"
expect_exit 0 "probe-sim --noise 0 --params" -- "$MTCAL" probe-sim -m "$tmp/clean.yaml" --params "$tmp/truth.yaml" --axis C --angles 0:350:36 --sphere 150,-40,80 --noise 0 --out "$tmp/c0.csv"
expect_exit 0 "probe-sim --noise 0" -- "$MTCAL" probe-sim -m "$tmp/cerr.yaml" --axis C --angles 0:350:36 --sphere 150,-40,80 --noise 0 --out "$tmp/c0m.csv"
cmp -s "$tmp/c0.csv" "$tmp/c0m.csv" && ok || bad "probe-sim --params equals the errors in the machine file"
expect_exit 0 "probe-sim without errors" -- "$MTCAL" probe-sim -m "$tmp/clean.yaml" --axis C --angles 0:350:36 --sphere 150,-40,80 --out "$tmp/cnone.csv"
! cmp -s "$tmp/c0.csv" "$tmp/cnone.csv" && ok || bad "probe-sim sees the --params errors"
expect_exit 0 "rotary-axis recovery" -- "$MTCAL" rotary-axis --axis C --contacts "$tmp/c0.csv" --sphere-diameter 30 --stylus-diameter 6 --machine "$tmp/clean.yaml" --json --out "$tmp/params.yaml"
cp "$tmp/out" "$tmp/recovered.json"
python3 - "$tmp/recovered.json" <<'PY' && ok || bad "noise-free recovery of EX0C EY0C EA0C EB0C"
import json, sys
d = json.load(open(sys.argv[1]))
truth = {"EX0C": 12e-3, "EY0C": -8e-3, "EA0C": 25e-6, "EB0C": -40e-6}
for est in ("least_squares", "triples"):
    for k, v in truth.items():
        tol = 1e-6 if k in ("EX0C", "EY0C") else 1e-8
        assert abs(d[est][k] - v) <= tol, (est, k, d[est][k], v)
PY
[ "$(json_get "d['out']")" = "$tmp/params.yaml" ] && ok || bad "rotary-axis JSON out"
grep -q '^mtcal_parameters: 1$' "$tmp/params.yaml" && ok || bad "--out writes a parameter file: $(cat "$tmp/params.yaml")"
expect_exit 0 "eval --params" -- "$MTCAL" eval -m "$tmp/clean.yaml" --params "$tmp/params.yaml" --at "X=100,Y=20,C=90" --json
cp "$tmp/out" "$tmp/eval-params.json"
"$MTCAL" eval -m "$tmp/cerr.yaml" --at "X=100,Y=20,C=90" --json >"$tmp/eval-truth.json"
python3 - "$tmp/eval-params.json" "$tmp/eval-truth.json" <<'PY' && ok || bad "eval with the identified parameters matches the truth"
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
assert abs(a["dx"]) > 1e-3, a  # the C errors do show
for k in ("dx", "dy", "dz"):
    assert abs(a[k] - b[k]) < 1e-6, (k, a[k], b[k])
for k in ("rx", "ry", "rz"):
    assert abs(a[k] - b[k]) < 1e-8, (k, a[k], b[k])
PY
expect_exit 0 "errors --params" -- "$MTCAL" errors -m "$tmp/clean.yaml" --params "$tmp/params.yaml" --json
python3 -c "
import json; d = json.load(open('$tmp/out')); r = json.load(open('$tmp/recovered.json'))
p = {x['name']: x['value'] for x in d['parameters']}
assert p['EX0C'] == r['least_squares']['EX0C'] and abs(p['EX0C'] - 0.012) < 1e-6, p
" && ok || bad "errors --params shows the new EX0C"
"$MTCAL" errors -m "$tmp/clean.yaml" --json >"$tmp/before.json"
python3 -c "import json; d = json.load(open('$tmp/before.json')); assert [x['value'] for x in d['parameters'] if x['name'] == 'EX0C'] == [0.0]" && ok || bad "EX0C is 0 without --params"
expect_exit 0 "effects --params" -- "$MTCAL" effects -m "$tmp/clean.yaml" --params "$tmp/params.yaml" --at "C=90" --errors EX0C --json
# --centres from the JSON centres gives the same least-squares values.
python3 -c "
import json
d = json.load(open('$tmp/recovered.json'))
with open('$tmp/centres.csv', 'w') as f:
    f.write('C,x,y,z\n')
    for c in d['centres']:
        f.write('%r,%r,%r,%r\n' % (c['angle'], c['x'], c['y'], c['z']))
"
expect_exit 0 "rotary-axis --centres" -- "$MTCAL" rotary-axis --axis C --centres "$tmp/centres.csv" --machine "$tmp/clean.yaml" --json
python3 - "$tmp/recovered.json" "$tmp/out" <<'PY' && ok || bad "--centres gives the same least-squares values"
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
assert b["indexations"] == 36 and b["centre_method"] == "given", b["centre_method"]
for k in ("EX0C", "EY0C", "EA0C", "EB0C", "radius"):
    assert abs(a["least_squares"][k] - b["least_squares"][k]) <= 1e-12 * max(1.0, abs(a["least_squares"][k])), (k, a["least_squares"][k], b["least_squares"][k])
PY

# rotary-axis / probe-sim / --params errors: one line, non-zero exit, no partial output.
C0="$tmp/c0.csv"
expect_error "rotary-axis without --sphere-diameter" "--sphere-diameter" -- "$MTCAL" rotary-axis --axis C --contacts "$C0" --stylus-diameter 6
expect_error "rotary-axis --contacts and --centres" "exactly one of --contacts and --centres" -- "$MTCAL" rotary-axis --axis C --contacts "$C0" --centres "$tmp/centres.csv" --sphere-diameter 30
expect_error "rotary-axis neither input" "exactly one of --contacts and --centres" -- "$MTCAL" rotary-axis --axis C
expect_error "rotary-axis --axis X" "expected A, B or C" -- "$MTCAL" rotary-axis --axis X --contacts "$C0" --sphere-diameter 30 --stylus-diameter 6
expect_error "contacts not on the sphere (too small)" "c0.csv:2 (C=0): the contacts are not on a sphere of diameter 20" -- "$MTCAL" rotary-axis --axis C --contacts "$C0" --sphere-diameter 20 --stylus-diameter 6 --machine "$MR" --out "$tmp/partial.yaml"
[ ! -e "$tmp/partial.yaml" ] && ok || bad "no partial --out after contacts off the sphere"
expect_error "contacts not on the sphere" "not on a sphere of diameter 28" -- "$MTCAL" rotary-axis --axis C --contacts "$C0" --sphere-diameter 28 --stylus-diameter 6
sed '1s/approach_z/approach_q/' "$C0" >"$tmp/unkcol.csv"
expect_error "contacts unknown column" "unknown column 'approach_q'" -- "$MTCAL" rotary-axis --axis C --contacts "$tmp/unkcol.csv" --sphere-diameter 30 --stylus-diameter 6
expect_error "contacts without the axis column" "missing column 'A'" -- "$MTCAL" rotary-axis --axis A --contacts "$C0" --sphere-diameter 30 --stylus-diameter 6
expect_exit 0 "probe-sim two indexations" -- "$MTCAL" probe-sim -m "$tmp/cerr.yaml" --axis C --angles 0:90:2 --out "$tmp/two.csv"
echo "keep me" >"$tmp/existing.yaml"
expect_error "fewer than 3 indexations" "at least 3" -- "$MTCAL" rotary-axis --axis C --contacts "$tmp/two.csv" --sphere-diameter 30 --stylus-diameter 6 --machine "$MR" --out "$tmp/partial.yaml"
[ ! -e "$tmp/partial.yaml" ] && ok || bad "no partial --out after too few indexations"
expect_error "fewer than 3 indexations, existing --out" "at least 3" -- "$MTCAL" rotary-axis --axis C --contacts "$tmp/two.csv" --sphere-diameter 30 --stylus-diameter 6 --machine "$MR" --out "$tmp/existing.yaml"
[ "$(cat "$tmp/existing.yaml")" = "keep me" ] && ok || bad "a failed rotary-axis leaves an existing --out alone"
head -3 "$tmp/centres.csv" >"$tmp/centres2.csv"
expect_error "two centres" "at least 3" -- "$MTCAL" rotary-axis --axis C --centres "$tmp/centres2.csv"
expect_error "probe-sim on a head axis" "carries the workpiece" -- "$MTCAL" probe-sim -m "$EXAMPLES/head-head-5axis.yaml" --axis C --out "$tmp/partial.csv"
[ ! -e "$tmp/partial.csv" ] && ok || bad "no partial probe-sim output after a failure"
expect_error "probe-sim unknown axis" "not in topology" -- "$MTCAL" probe-sim -m "$MR" --axis B --out "$tmp/partial.csv"
expect_error "probe-sim without --out" "--out" -- "$MTCAL" probe-sim -m "$MR"
[ -z "$(ls -A "$tmp" | grep -v -E '\.(csv|yaml|json|npy)$|^(out|err)$')" ] && ok || bad "temporary files left behind: $(ls -A "$tmp")"
printf 'mtcal_parameters: 1\nerrors:\n  EX0C: 12 um\n  EQQ: 1 um\n' >"$tmp/badparams.yaml"
expect_error "eval --params bad error name" "badparams.yaml:4: field 'errors.EQQ': unknown error name 'EQQ'" -- "$MTCAL" eval -m "$tmp/clean.yaml" --params "$tmp/badparams.yaml" --at X=0
expect_error "errors --params bad error name" "unknown error name 'EQQ'" -- "$MTCAL" errors -m "$tmp/clean.yaml" --params "$tmp/badparams.yaml"
expect_error "effects --params bad error name" "unknown error name 'EQQ'" -- "$MTCAL" effects -m "$tmp/clean.yaml" --params "$tmp/badparams.yaml" --at X=0
printf 'mtcal_parameters: 1\nerrors:\n  EX0B: 1 um\n' >"$tmp/badaxis.yaml"
expect_error "--params axis not in topology" "badaxis.yaml:3" -- "$MTCAL" errors -m "$tmp/clean.yaml" --params "$tmp/badaxis.yaml"
expect_error "--params missing file" "nope-params.yaml" -- "$MTCAL" errors -m "$tmp/clean.yaml" --params "$tmp/nope-params.yaml"
expect_error "--params given a machine file" "unknown key 'mtcal_machine'" -- "$MTCAL" errors -m "$tmp/clean.yaml" --params "$tmp/clean.yaml"
printf 'X,Y,Z\n0,0,0\n' >"$tmp/pts.csv"
expect_error "eval --params bad, batch output" "unknown error name" -- "$MTCAL" eval -m "$tmp/clean.yaml" --params "$tmp/badparams.yaml" --points "$tmp/pts.csv" --out "$tmp/partial-eval.csv"
[ ! -e "$tmp/partial-eval.csv" ] && ok || bad "no partial eval output after a bad --params"

# compare: two methods over repeated tests (Mohammed 2019's ballbar and SAMBA/TANGO example).
MOH="$EXAMPLES/../data/mohammed2019-ballbar-vs-samba.csv"
expect_exit 0 "compare" -- "$MTCAL" compare "$MOH"
grep -qE '^EXXb +4 +-0.81375 ' "$tmp/out" && ok || bad "compare text row EXXb: $(grep EXXb "$tmp/out")"
grep -q '^20 parameters, 20 measured by both methods; mean +- 1 stdev bands overlap for 10 of 20' "$tmp/out" && ok || bad "compare summary line: $(tail -1 "$tmp/out")"
expect_exit 0 "compare --json" -- "$MTCAL" compare "$MOH" --json
[ "$(json_get "d['methods']")" = "['ballbar', 'samba-tango']" ] && ok || bad "compare JSON methods"
[ "$(json_get "list(d['parameters'])[:3] + [len(d['parameters'])]")" = "['EXXb', 'EYYb', 'EXYb', 20]" ] && ok || bad "compare JSON parameters in file order"
[ "$(json_get "sorted(d['parameters']['EXX'].keys())")" = "['abs_diff', 'mean', 'n', 'overlap', 'paired', 'pearson_r', 'stdev']" ] && ok || bad "compare JSON parameter keys"
[ "$(json_get "sorted(d['parameters']['EXX']['mean'].keys()) == sorted(d['parameters']['EXX']['stdev'].keys()) == ['ballbar', 'samba-tango']")" = "True" ] && ok || bad "compare JSON mean/stdev keyed by method"
python3 -c "
import json; d = json.load(open('$tmp/out')); p = d['parameters']['EXX']
assert abs(p['mean']['ballbar'] + 4.6475) < 1e-12 and abs(p['abs_diff'] - 0.03) < 1e-12 and p['overlap'] is True, p
assert p['n'] == {'ballbar': 4, 'samba-tango': 4} and abs(p['pearson_r'] + 0.140) < 1e-3, p
s = d['summary']
assert (s['parameters'], s['overlap'], s['no_overlap'], s['strong_correlation']) == (20, 10, 10, 9), s
" && ok || bad "compare JSON values and summary"
printf '# two tests, one parameter of one method\nmethod,test,parameter,value\nA,1,P,1\nA,2,P,3\nB,1,P,2\nB,2,P,2\nA,1,Q,5\n' >"$tmp/cmp-missing.csv"
expect_exit 0 "compare with a one-method parameter" -- "$MTCAL" compare "$tmp/cmp-missing.csv" --json
python3 -c "
import json; d = json.load(open('$tmp/out')); q = d['parameters']['Q']
assert q['mean'] == {'A': 5.0, 'B': None} and q['stdev'] == {'A': None, 'B': None}, q
assert q['abs_diff'] is None and q['overlap'] is None and q['pearson_r'] is None and q['n'] == {'A': 1, 'B': 0}, q
assert d['parameters']['P']['pearson_r'] is None and d['summary']['one_method_only'] == ['Q'], d
" && ok || bad "compare JSON nulls for a one-method parameter"
expect_exit 0 "compare text with a one-method parameter" -- "$MTCAL" compare "$tmp/cmp-missing.csv"
grep -q '^only A measured Q$' "$tmp/out" && ok || bad "compare text names the one-method parameter: $(cat "$tmp/out")"
printf 'method,test,parameter,value\nA,1,P,1\nB,1,P,oops\n' >"$tmp/cmp-nonnum.csv"
expect_error "compare non-numeric value" "cmp-nonnum.csv:3: field 'value': expected a finite number, found 'oops'" -- "$MTCAL" compare "$tmp/cmp-nonnum.csv"
printf 'method,run,parameter,value\nA,1,P,1\n' >"$tmp/cmp-header.csv"
expect_error "compare wrong header" "cmp-header.csv:1: expected the header 'method,test,parameter,value'" -- "$MTCAL" compare "$tmp/cmp-header.csv"
printf 'method,test,parameter,value\nA,1,P,1\nA,2,P,2\n' >"$tmp/cmp-one.csv"
expect_error "compare one method" "only one method, 'A' (expected exactly two methods)" -- "$MTCAL" compare "$tmp/cmp-one.csv"
printf 'method,test,parameter,value\nA,1,P,1\nB,1,P,2\nC,1,P,3\n' >"$tmp/cmp-three.csv"
expect_error "compare three methods" "cmp-three.csv:4: field 'method': a third method 'C'" -- "$MTCAL" compare "$tmp/cmp-three.csv"
printf 'method,test,parameter,value\nA,1,P,1\nB,1,P,2\nA,1,P,3\n' >"$tmp/cmp-dup.csv"
expect_error "compare duplicate" "cmp-dup.csv:4: method 'A', test '1', parameter 'P' is given twice (first on line 2)" -- "$MTCAL" compare "$tmp/cmp-dup.csv"
expect_error "compare missing file" "nope-compare.csv" -- "$MTCAL" compare "$tmp/nope-compare.csv"
expect_error "compare without data" "DATA is required" -- "$MTCAL" compare
expect_exit 2 "compare usage error exit code" -- "$MTCAL" compare
expect_error "compare bad data, report" "expected a finite number" -- "$MTCAL" compare "$tmp/cmp-nonnum.csv" --report "$tmp/partial-compare.html"
[ ! -e "$tmp/partial-compare.html" ] && ok || bad "no partial compare report after a failure"
expect_exit 0 "compare --report" -- "$MTCAL" compare "$MOH" --report "$tmp/compare.html" --json
grep -q 'Plotly.newPlot' "$tmp/compare.html" && grep -q 'samba-tango' "$tmp/compare.html" && ok || bad "compare report holds the plot and the methods"
[ "$(json_get "d['report']")" = "$tmp/compare.html" ] && ok || bad "compare JSON report"

# Outputs never replace inputs, nor each other; rotary-axis refuses what would give nonsense.
expect_error "report over its input" "would replace the input" -- "$MTCAL" eval -m "$M5" --points "$tmp/p.csv" --report "$tmp/p.csv"
[ "$(head -1 "$tmp/p.csv")" = "X,Y,Z,B,C,dirX" ] && ok || bad "the input survived"
expect_error "report over the machine" "would replace the input" -- "$MTCAL" errors -m "$M5" --report "$M5"
expect_error "two outputs, one path" "two outputs" -- "$MTCAL" eval -m "$M5" --points "$tmp/p.csv" --out "$tmp/same.out" --report "$tmp/same.out"
"$MTCAL" probe-sim -m "$MR" --axis C --out "$tmp/rc.csv" >/dev/null
expect_error "rotary --out needs --machine" "needs --machine" -- "$MTCAL" rotary-axis --axis C --contacts "$tmp/rc.csv" --sphere-diameter 30 --stylus-diameter 6 --out "$tmp/x.yaml"
expect_error "rotary wrong axis" "missing column 'A'" -- "$MTCAL" rotary-axis --axis A --contacts "$tmp/rc.csv" --sphere-diameter 30 --stylus-diameter 6
python3 - "$tmp/rc.csv" "$tmp/rc_tilted.csv" <<'PY'
import sys
rows = open(sys.argv[1]).read().splitlines()
out = [rows[0]]
for r in rows[1:]:   # rotate every contact 90 deg about x: the circle now turns about y
    c, x, y, z, ax, ay, az = r.split(',')
    out.append(','.join([c, x, str(-float(z)), y, ax, str(-float(az)), ay]))
open(sys.argv[2], 'w').write('\n'.join(out) + '\n')
PY
# An axis far from its nominal direction: the measured line is given, the location errors are not.
expect_exit 0 "rotary tilted data" -- "$MTCAL" rotary-axis --axis C --contacts "$tmp/rc_tilted.csv" --sphere-diameter 30 --stylus-diameter 6 --json
json_get "d['located'] is False and abs(abs(d['axis_direction'][1]) - 1) < 1e-6 and abs(d['tilt'] - 1.5707963) < 1e-4" | grep -qx True && ok || bad "rotary tilted line: $(cat "$tmp/out")"
expect_error "rotary tilted data, --out" "wrong --axis" -- "$MTCAL" rotary-axis --axis C --contacts "$tmp/rc_tilted.csv" --sphere-diameter 30 --stylus-diameter 6 --machine "$MR" --out "$tmp/tilted.yaml"
[ ! -e "$tmp/tilted.yaml" ] && ok || bad "a tilted axis wrote --out"
# The instrument's frame given: the contacts were turned +90 deg about x, so the frame turns them back.
expect_exit 0 "rotary tilted data with --frame" -- "$MTCAL" rotary-axis --axis C --contacts "$tmp/rc_tilted.csv" --sphere-diameter 30 --stylus-diameter 6 --frame "-90,0,0" --json
cp "$tmp/out" "$tmp/framed.json"
expect_exit 0 "rotary untilted data" -- "$MTCAL" rotary-axis --axis C --contacts "$tmp/rc.csv" --sphere-diameter 30 --stylus-diameter 6 --json
python3 -c "
import json, sys
a, b = json.load(open('$tmp/framed.json')), json.load(open('$tmp/out'))
assert all(abs(a['least_squares'][k] - b['least_squares'][k]) < 1e-9 for k in ('EX0C', 'EY0C', 'EA0C', 'EB0C')), (a['least_squares'], b['least_squares'])
" && ok || bad "--frame gives the untilted result"
expect_error "reject-sigma below 1" "at least 1" -- "$MTCAL" rotary-axis --axis C --contacts "$tmp/rc.csv" --sphere-diameter 30 --stylus-diameter 6 --reject-sigma 0.5
expect_error "reject-sigma nan" "finite" -- "$MTCAL" rotary-axis --axis C --contacts "$tmp/rc.csv" --sphere-diameter 30 --stylus-diameter 6 --reject-sigma nan
expect_error "max-rms nan" "finite" -- "$MTCAL" rotary-axis --axis C --contacts "$tmp/rc.csv" --sphere-diameter 30 --stylus-diameter 6 --max-rms nan
{ head -6 "$tmp/rc.csv"; tail -n +12 "$tmp/rc.csv"; sed -n 2,6p "$tmp/rc.csv"; } >"$tmp/rc_repeat.csv"
expect_exit 0 "an angle probed twice" -- "$MTCAL" rotary-axis --axis C --contacts "$tmp/rc_repeat.csv" --sphere-diameter 30 --stylus-diameter 6
grep -q "note: indexations at 0, 0 deg are one position of the axis" "$tmp/err" && ok || bad "an angle probed twice: note: $(cat "$tmp/err")"
printf 'C,x,y,z\n0,1,0,0\n120,-0.5,0.8,0\n0,-0.5,-0.8,0\n' >"$tmp/dupc.csv"
expect_error "a centre angle given twice" "at least 3 positions of the axis, found 2" -- "$MTCAL" rotary-axis --axis C --centres "$tmp/dupc.csv"
printf 'C,x,y,z\n0,100,0,0\n120,-50,86.6025403784,0\n240,-50,-86.6025403784,0\n' >"$tmp/three.csv"
expect_exit 0 "three centres" -- "$MTCAL" rotary-axis --axis C --centres "$tmp/three.csv" --json
python3 -c "import json; d=json.load(open('$tmp/out')); assert d['least_squares']['EX0C_u'] is None and d['triples']['EX0C_u'] is None, d" && ok || bad "three centres: uncertainty not null"

# Ballbar: prediction from a model, evaluation, JSON keys, errors.
expect_exit 0 "ballbar --predict" -- "$MTCAL" ballbar --predict -m "$M3" --plane XY --radius 100 --centre "Z=-200" --out "$tmp/trace.csv"
[ "$(head -1 "$tmp/trace.csv")" = "direction,angle_deg,radius_mm" ] && [ "$(wc -l <"$tmp/trace.csv")" -eq 721 ] && ok || bad "predicted trace format"
expect_exit 0 "ballbar --json" -- "$MTCAL" ballbar "$tmp/trace.csv" --radius 100 --json
[ "$(json_get "[k for k in d if k in ('G_cw','G_ccw','G_b','H','F_max','F_min','F_mean_bidirectional')]")" = "['G_cw', 'G_ccw', 'G_b', 'H', 'F_max', 'F_min', 'F_mean_bidirectional']" ] && ok || bad "ballbar JSON keys"
[ "$(json_get "sorted(d['diagnostics']['squareness XY'].keys())")" = "['share', 'u', 'unit', 'value']" ] && ok || bad "ballbar diagnostics keys"
# The vmc example's X reversal (EXX reversal 1 um) comes out of its predicted trace as a lost
# motion of -2 um (its squareness term also carries the angular errors' effect, so not checked).
python3 -c "import json; d=json.load(open('$tmp/out')); v=d['diagnostics']['backlash X']['value']; assert abs(v+2.0) < 0.01, v" && ok || bad "ballbar diagnostics backlash of the example"
# Both paths' zone about any centre is at least each path's minimum zone; the minimum zone is at most G.
python3 -c "import json; d=json.load(open('$tmp/out')); assert d['G_b'] >= max(d['cw']['G_minimum_zone'], d['ccw']['G_minimum_zone']) - 1e-7 and d['cw']['G_minimum_zone'] <= d['cw']['G'] + 1e-12, d" && ok || bad "ballbar G(b) >= minimum zones and minimum zone <= G"
awk -F, 'NR==1 || $1=="ccw"' "$tmp/trace.csv" >"$tmp/ccw.csv"
expect_error "ballbar one direction" "both directions" -- "$MTCAL" ballbar "$tmp/ccw.csv" --radius 100
expect_exit 0 "ballbar --direction ccw" -- "$MTCAL" ballbar "$tmp/ccw.csv" --radius 100 --direction ccw --json
[ "$(json_get "d['H']")" = "None" ] && ok || bad "one direction: no H"
awk -F, 'NR==1 || $2 < 180' "$tmp/trace.csv" >"$tmp/half.csv"
expect_error "ballbar half circle" "gap" -- "$MTCAL" ballbar "$tmp/half.csv" --radius 100
printf 'direction,angle_deg,radius_mm\nsideways,0,100\n' >"$tmp/badtrace.csv"
expect_error "ballbar bad direction" "badtrace.csv:2" -- "$MTCAL" ballbar "$tmp/badtrace.csv" --radius 100
expect_error "ballbar predict with a huge centre" "--centre: field 'Z'" -- "$MTCAL" ballbar --predict -m "$M3" --plane XY \
  --radius 100 --centre "Z=1e308" --out "$tmp/nan-trace.csv"
[ ! -e "$tmp/nan-trace.csv" ] && ok || bad "a trace was written for a huge centre"
expect_error "ballbar predict without machine" "needs --machine" -- "$MTCAL" ballbar --predict --radius 150 --out "$tmp/x.csv"
expect_error "ballbar predict bad plane" "plane" -- "$MTCAL" ballbar --predict -m "$M5" --plane XB --out "$tmp/x.csv"

summary_and_exit
