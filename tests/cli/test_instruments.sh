#!/usr/bin/env bash
# Instrument files through the command line: Renishaw exports evaluated with their metadata,
# fit-motion merging several files, ballbar --to-params, and every bad input as one line on stderr
# with file, line and field, nothing written. Needs MTCAL, ROOT.
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
X="$ROOT/examples/instruments/x-axis.rtl"

# The laser export: evaluated through ISO 230-2, metadata in JSON, numbers in um in text.
expect_exit 0 "iso230-2 .rtl" -- "$MTCAL" iso230-2 "$X" --json
json_get "d['unit'] == 'um' and d['target_unit'] == 'mm' and d['runs'] == 5 and d['metadata']['USER-TEXT/Serial'] == '4711' and d['metadata']['ENVIRONMENT/Air temperature'] == '20.4 C' and d['warnings'] == []" \
  | grep -qx True && ok || bad "iso230-2 .rtl JSON: $(head -c 400 "$tmp/out")"
expect_exit 0 "iso230-2 .rtl text" -- "$MTCAL" iso230-2 "$X"
grep -q 'deviations in um' "$tmp/out" && grep -Eq '^B [0-9]+\.[0-9]{2} ' "$tmp/out" && ok || bad "iso230-2 .rtl text: $(cat "$tmp/out")"

# A straightness export naming its error, and an angular table named on the command line, merged
# with the positioning file into one parameter file.
cat >"$tmp/ystr.rtl" <<'R'
HEADER::
Type: Straightness
TARGET DATA::
Target-count: 5
Targets :
0 125 250 375 500
USER-TEXT::
Axis: X
Error: EYX
RUNS::
Run-count: 2
DEVIATIONS::
Run Target Data:
1 1 0.0
1 2 2.1
1 3 3.0
1 4 2.0
1 5 0.1
2 1 0.1
2 2 2.0
2 3 3.1
2 4 2.1
2 5 0.0
R
printf 'target [mm];dir;deviation [arcsec]\n0;up;0,0\n0;up;0,2\n250;up;1,0\n250;up;1,2\n500;up;2,0\n500;up;2,2\n' >"$tmp/pitch.csv"
expect_exit 0 "fit-motion three files" -- "$MTCAL" fit-motion "$X" "$tmp/ystr.rtl" "EBX=$tmp/pitch.csv" --out "$tmp/x.yaml" --json
json_get "[e['error'] for e in d['errors']] == ['EXX', 'EYX', 'EBX'] and d['out'] == '$tmp/x.yaml'" | grep -qx True && ok || bad "fit-motion JSON: $(head -c 600 "$tmp/out")"
# The file loads as --params: EYX at mid-travel is the bow less the line (3.05 - mean line ~ 1.05 um).
expect_exit 0 "eval with the fitted params" -- "$MTCAL" eval -m "$ROOT/examples/instruments/mill.yaml" --params "$tmp/x.yaml" --at "X=250,Y=0,Z=0" --json
json_get "abs(d['dx']) < 0.02 and abs(d['dy']) > 0.0005" | grep -qx True && ok || bad "eval with fit-motion params: $(cat "$tmp/out")"

# Bad inputs: one line, the file's line and field, nothing written.
sed 's/^Target-count: 11/Target-count: 12/' "$X" >"$tmp/badcount.rtl"
expect_error "Target-count vs targets" "badcount.rtl:8: field 'Targets': 11 targets given, Target-count (line 7) says 12" -- "$MTCAL" iso230-2 "$tmp/badcount.rtl"
grep -v '^10 11 ' "$X" >"$tmp/norun.rtl"
expect_error "a run missing a target" "field 'Run Target Data': run 10 lacks target 11" -- "$MTCAL" fit-motion "$tmp/norun.rtl" --out "$tmp/none.yaml"
[ ! -e "$tmp/none.yaml" ] && ok || bad "fit-motion wrote --out on bad input"
sed 's/^3 4 .*/3 4 abc/' "$X" >"$tmp/nan.rtl"
expect_error "non-numeric deviation" "field 'Deviation': expected a number, found 'abc'" -- "$MTCAL" iso230-2 "$tmp/nan.rtl"
sed 's/^3 4 \(.*\)/3 4 \1arcsec/' "$X" >"$tmp/mixed.rtl"
expect_error "mixed units" "mixed units" -- "$MTCAL" iso230-2 "$tmp/mixed.rtl"
grep -v '^Run-count' "$X" >"$tmp/nocount.rtl"
expect_error "missing Run-count" "field 'Run-count': missing" -- "$MTCAL" iso230-2 "$tmp/nocount.rtl"
printf 'UNIT=mm\nTGT_DATA[1]=0\nTGT_DATA[2]=10\nREF_DATA_FWD[1,1]=0\nREF_DATA_FWD[2,1]=10\n' >"$tmp/x.dat"
expect_error "fit-motion without an error name" "name it, e.g. EXX=" -- "$MTCAL" fit-motion "$tmp/x.dat" --out "$tmp/none.yaml"
expect_error "fit-motion one error twice" "EXX is estimated twice" -- "$MTCAL" fit-motion "$X" "EXX=$tmp/x.dat" --out "$tmp/none.yaml"
[ ! -e "$tmp/none.yaml" ] && ok || bad "fit-motion wrote --out on bad input"
expect_error "fit-motion units that do not fit the error" "expected its deviations in an angle unit" -- "$MTCAL" fit-motion "EAX=$X"
printf 'REF_PV=a\nUNIT=mm\nTGT_DATA[1]=0\nREF_DATA_FWD[1,1]=x\n' >"$tmp/warn-then-bad.dat"
expect_error "a bad .dat with unknown keys: the error only" "warn-then-bad.dat:4" -- "$MTCAL" iso230-2 "$tmp/warn-then-bad.dat"

# ballbar --to-params: the example trace's squareness, and its refusals.
B="$ROOT/examples/instruments/xy-ballbar.csv"
expect_exit 0 "ballbar --to-params --json" -- "$MTCAL" ballbar "$B" --radius 100 --to-params "$tmp/xy.yaml" --json
json_get "abs(d['parameters']['EC0Y']['value'] - 35e-6) < 1e-6 and d['parameters']['EC0Y']['u'] > 0 and 'EXX.b' in d['parameters']" | grep -qx True && ok || bad "ballbar --to-params JSON: $(json_get "d.get('parameters')")"
grep -q '^  EC0Y: {value: ' "$tmp/xy.yaml" && ok || bad "ballbar --to-params file: $(cat "$tmp/xy.yaml")"
expect_error "--to-params with one direction" "needs both directions" -- "$MTCAL" ballbar "$B" --radius 100 --direction cw --to-params "$tmp/xy2.yaml"
expect_error "--terms unknown" "expected squareness, scale or backlash" -- "$MTCAL" ballbar "$B" --radius 100 --to-params "$tmp/xy2.yaml" --terms skew
[ ! -e "$tmp/xy2.yaml" ] && ok || bad "ballbar wrote --to-params on bad input"
expect_error "--to-params onto the trace" "" -- "$MTCAL" ballbar "$B" --radius 100 --to-params "$B"

summary_and_exit
