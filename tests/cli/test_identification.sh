#!/usr/bin/env bash
# mtcal simulate, identify, identifiability on the HU40T SAMBA/TANGO plan: recovery, JSON keys,
# parameter files that eval reads back, bad measurement files, no partial outputs.
# Needs MTCAL and EXAMPLES (examples/). Prints "N passed, N failed".
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
H="$EXAMPLES/machines/hu40t-wCBXfYZt.yaml"
P="$EXAMPLES/plans/hu40t-samba-tango.csv"
EST=EC0Y,EB0Z,EA0Z,EX0C,EY0C,EA0C,EB0C,EX0B,EZ0B,EA0B,EC0B,EXX.1,EYY.1,EZZ.1
ZERO=()
for p in ${EST//,/ }; do ZERO+=(--set "$p=0"); done

for c in simulate identify identifiability; do
  expect_exit 0 "$c --help" -- "$MTCAL" $c --help
  grep -q -- '--json' "$tmp/out" && ok || bad "$c --help lists --json"
done

# Noise-free simulation, identified from a prior that lacks the 14 parameters: recovered.
expect_exit 0 "simulate" -- "$MTCAL" simulate -m "$H" --plan "$P" --artefact-error-um 50 --scale-bar 1:2:304.8 --out "$tmp/m0.csv" --json
[ "$(json_get "(d['records'], d['residuals'])")" = "(76, 188)" ] && ok || bad "simulate counts: $(cat "$tmp/out")"
[ "$(grep -vc '^#' "$tmp/m0.csv")" -eq 77 ] && ok || bad "measurement rows"
expect_exit 0 "identify noise-free" -- "$MTCAL" identify -m "$H" "${ZERO[@]}" --measurements "$tmp/m0.csv" --estimate "$EST" \
  --scale-bar 1:2:304.8 --truth "$H" --workspace "X=-300:300:3,Y=-250:250:3,Z=-300:300:3,B=0:90:2,C=0:180:2" \
  --out "$tmp/id.yaml" --json
for k in termination converged iterations residuals unknowns rank condition singular_values rms_um parameters correlation unidentifiable artefact va e_v; do
  json_get "d['$k']" >/dev/null 2>&1 && ok || bad "identify JSON lacks '$k'"
done
python3 - "$tmp/out" "$H" <<'PY' && ok || bad "identify recovers the imposed values"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["converged"] and d["rank"] == d["unknowns"] == 33, (d["rank"], d["unknowns"])
assert len(d["parameters"]) == 14
for name, p in d["parameters"].items():
    assert abs(p["value"] - p["imposed"]) <= 1e-8 * abs(p["imposed"]) + 1e-15, (name, p)
assert d["e_v"]["max"] < 1e-9
PY
# The parameter file (written from the identified machine) gives the imposed errors back.
expect_exit 0 "eval with identified params" -- "$MTCAL" eval -m "$H" --params "$tmp/id.yaml" --at "X=100,Y=50,Z=-20,B=30,C=90" --json
cp "$tmp/out" "$tmp/a.json"
expect_exit 0 "eval imposed" -- "$MTCAL" eval -m "$H" --at "X=100,Y=50,Z=-20,B=30,C=90" --json
python3 -c "import json; a=json.load(open('$tmp/a.json')); b=json.load(open('$tmp/out')); assert all(abs(a[k]-b[k])<1e-12 for k in a), (a,b)" && ok || bad "identified parameter file reproduces the machine"

# With 1 um noise: uncertainties, Monte Carlo and a report.
expect_exit 0 "simulate noisy" -- "$MTCAL" simulate -m "$H" --plan "$P" --noise-um 1 --seed 7 --artefact-error-um 50 --scale-bar 1:2:304.8 --out "$tmp/m1.csv"
expect_exit 0 "identify noisy" -- "$MTCAL" identify -m "$H" "${ZERO[@]}" --measurements "$tmp/m1.csv" --estimate "$EST" \
  --scale-bar 1:2:304.8 --monte-carlo 50 --report "$tmp/id.html" --json
python3 - "$tmp/out" <<'PY' && ok || bad "noisy identification: rms, u and Monte Carlo"
import json, sys
d = json.load(open(sys.argv[1]))
assert 0.5 < d["rms_um"]["ball"] < 1.5 and 0.5 < d["rms_um"]["facet"] < 1.5, d["rms_um"]
for name, p in d["parameters"].items():
    assert p["u"] > 0 and 0.5 < p["u_monte_carlo"] / p["u"] < 2, (name, p)
assert d["monte_carlo"]["runs"] == 50 and d["monte_carlo"]["failed"] == 0
PY
[ -s "$tmp/id.html" ] && ok || bad "identify report written"

# Unidentifiable requests are reported, never solved.
expect_exit 0 "identify unidentifiable" -- "$MTCAL" identify -m "$H" --measurements "$tmp/m0.csv" --estimate EX0X,EXt,EXw --json
[ "$(json_get "(sorted(d['parameters']), d['unidentifiable'])")" = "(['EX0X'], ['EXt', 'EXw'])" ] && ok || bad "unidentifiable: $(cat "$tmp/out")"
expect_exit 0 "identifiability" -- "$MTCAL" identifiability -m "$H" --plan "$P" --estimate "$EST,EX0X,EXt" --scale-bar 1:2:304.8 --json
[ "$(json_get "d['unidentifiable']")" = "['EX0X', 'EXt']" ] && ok || bad "identifiability: $(json_get "d['unidentifiable']")"
[ "$(json_get "d['rank'] == d['unknowns'] - 2")" = "True" ] && ok || bad "identifiability rank"
expect_exit 0 "identifiability text" -- "$MTCAL" identifiability -m "$H" --plan "$P" --estimate EX0C,EX0B,EX0X
grep -q 'cannot be separated: EX0X =' "$tmp/out" && ok || bad "null direction printed: $(cat "$tmp/out")"

# Combinatorial analysis: C(19,8) subsets; the listed ones are full rank when identified alone.
L19=EX0C,EY0C,EA0C,EB0C,EC0C,EX0B,EZ0B,EA0B,EB0B,EC0B,EX0X,EB0X,EC0X,EY0Y,EA0Y,EC0Y,EZ0Z,EA0Z,EB0Z
expect_exit 0 "subsets" -- "$MTCAL" identifiability -m "$H" --plan "$P" --candidates "$L19" --choose 8 --always EXt,EYt,EZt \
  --scale-bar 1:2:304.8 --list 3 --json
[ "$(json_get "d['examined']")" = "75582" ] && ok || bad "C(19,8) = 75582"
cp "$tmp/out" "$tmp/subsets.json"
first=$(python3 -c "import json; print(','.join(json.load(open('$tmp/subsets.json'))['subsets'][0]['parameters']))")
expect_exit 0 "best subset alone" -- "$MTCAL" identifiability -m "$H" --plan "$P" --estimate "EXt,EYt,EZt,$first" --scale-bar 1:2:304.8 --json
[ "$(json_get "d['unidentifiable']")" = "[]" ] && ok || bad "best subset is identifiable: $(json_get "d['unidentifiable']")"

# Candidates given twice or as an error and its parameter are resolved once, and named right.
expect_exit 0 "subsets with duplicates" -- "$MTCAL" identifiability -m "$H" --plan "$P" --candidates EXX,EXX.1,EY0C,EX0C,EX0C --choose 2 --json
[ "$(json_get "d['candidates']")" = "['EXX.0', 'EXX.1', 'EXX.2', 'EXX.3', 'EXX.b', 'EY0C', 'EX0C']" ] && ok || bad "resolved candidates: $(json_get "d['candidates']")"
[ "$(json_get "all(len(set(s['parameters'])) == 2 for s in d['subsets'])")" = "True" ] && ok || bad "no subset names a parameter twice"

# Pre-travel with free facet offsets: reported and excluded, the rest identified.
expect_exit 0 "pre-travel excluded" -- "$MTCAL" identify -m "$H" --measurements "$tmp/m0.csv" --estimate EX0C --pretravel --json
[ "$(json_get "(d['unidentifiable'], 'pretravel' in d, list(d['parameters']))")" = "(['pre-travel'], False, ['EX0C'])" ] && ok || bad "pre-travel: $(json_get "d['unidentifiable']")"

# Bad input: one line, non-zero exit, no output file.
head -12 "$tmp/m0.csv" | sed 's/,ball,/,sphere,/' >"$tmp/bad1.csv"
expect_error "unknown kind" "expected ball, facet, ballbar or laser" -- "$MTCAL" identify -m "$H" --measurements "$tmp/bad1.csv" --estimate EX0C
grep -v '^#' "$tmp/m0.csv" | cut -d, -f1-16 >"$tmp/bad2.csv"
expect_error "missing reading column" "X, Y, Z or none" -- "$MTCAL" identify -m "$H" --measurements "$tmp/bad2.csv" --estimate EX0C
sed '12s/,[^,]*$/,nan/' "$tmp/m0.csv" >"$tmp/bad3.csv"
expect_error "NaN reading" "expected a finite number" -- "$MTCAL" identify -m "$H" --measurements "$tmp/bad3.csv" --estimate EX0C --out "$tmp/never.yaml"
[ ! -e "$tmp/never.yaml" ] && ok || bad "a failed identify leaves no output"
expect_error "plan instead of measurements" "found a plan" -- "$MTCAL" identify -m "$H" --measurements "$P" --estimate EX0C
expect_error "unknown parameter" "unknown parameter or error 'EQQ'" -- "$MTCAL" identify -m "$H" --measurements "$tmp/m0.csv" --estimate EQQ
expect_error "unknown scale-bar ball" "no ball '9'" -- "$MTCAL" identify -m "$H" --measurements "$tmp/m0.csv" --estimate EX0C --scale-bar 1:9:300
expect_error "bad scale bar" "BALL:BALL:LENGTH" -- "$MTCAL" identify -m "$H" --measurements "$tmp/m0.csv" --estimate EX0C --scale-bar 1-2
grep -v '^#' "$tmp/m0.csv" | head -2 >"$tmp/few.csv"
expect_error "too few measurements" "too few measurements" -- "$MTCAL" identify -m "$H" --measurements "$tmp/few.csv" --estimate EX0C,EY0C
expect_error "choose without candidates" "--choose needs --candidates" -- "$MTCAL" identifiability -m "$H" --plan "$P" --choose 3

summary_and_exit
