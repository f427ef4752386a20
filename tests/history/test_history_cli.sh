#!/usr/bin/env bash
# mtcal history diff | trend | rank on a store holding a known fleet (history_fixture: values in
# its header), every figure below computed by hand; bad input named in one line. Needs MTCAL,
# FIXTURE, ROOT.
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
store="$tmp/fleet.db"
"$FIXTURE" "$store" || { echo "FAIL: fixture"; exit 1; }
tol="$ROOT/examples/acceptance/tolerances.yaml"

# --- trend ------------------------------------------------------------------------------------
# HU40T EC0Y 20, 26, 30 urad (u = 2) at t = 0, 1, 2 mean years from 2021-01-01: weighted fit,
# tm = 1, level 76/3, rate (30 - 20) / 2 = 5 urad/year, u(rate) = 1 / sqrt(2 / 4) = sqrt 2;
# residuals -1/3, 2/3, -1/3: chi2 = 1/6, Birge ratio 0.408 (not inflated).
# |EC0Y| <= 40 is reached at 1 + (40 - 76/3) / 5 = 3.9333 years: 2024-12-07; rates 5 +- 2 sqrt 2
# give 2.8735 years (2023-11-16) and 7.7539 years (2028-10-03).
expect_exit 0 "trend json" -- "$MTCAL" history trend --store "$store" --machine HU40T --parameter EC0Y \
  --tolerance EC0Y=40 --json
cp "$tmp/out" "$tmp/trend.json"
[ "$(json_get 'd["series"][0]["trend"]["fit"]')" = weighted ] && ok || bad "fit kind"
[ "$(json_get 'round(d["series"][0]["trend"]["rate_per_year"], 9)')" = 5.0 ] && ok || bad "rate"
[ "$(json_get 'round(d["series"][0]["trend"]["u_rate_per_year"], 9)')" = 1.414213562 ] && ok || bad "u(rate)"
[ "$(json_get 'round(d["series"][0]["trend"]["birge_ratio"], 4)')" = 0.4082 ] && ok || bad "Birge ratio"
[ "$(json_get 'd["series"][0]["trend"]["crossing"]["status"]')" = predicted ] && ok || bad "status"
[ "$(json_get 'd["series"][0]["trend"]["crossing"]["date"][:10]')" = 2024-12-07 ] && ok || bad "crossing date"
[ "$(json_get 'd["series"][0]["trend"]["crossing"]["earliest"][:10]')" = 2023-11-16 ] && ok || bad "earliest"
[ "$(json_get 'd["series"][0]["trend"]["crossing"]["latest"][:10]')" = 2028-10-03 ] && ok || bad "latest"
[ "$(json_get 'd["series"][0]["trend"]["utilisation"]')" = 0.75 ] && ok || bad "utilisation"
[ "$(json_get 'd["serial"]')" = 4711 ] && ok || bad "serial"
[ "$(json_get 'len(d["events"])')" = 2 ] && ok || bad "events"
[ "$(json_get 'd["events"][0]["kind"]')" = crash ] && ok || bad "event kind"
[ "$(json_get 'list(d)')" = "['machine', 'serial', 'series', 'events', 'metadata']" ] ||
  [ "$(json_get 'list(d)')" = "['machine', 'serial', 'series', 'events']" ] && ok || bad "trend keys: $(json_get 'list(d)')"
r1=$(json_get 'd["series"][0]["samples"][0]["record"]')
r2=$(json_get 'd["series"][0]["samples"][1]["record"]')
r3=$(json_get 'd["series"][0]["samples"][2]["record"]')

# A_X 8, 9, 11 um without u: ordinary fit, rate 1.5 um/year, residuals 1/6, -1/3, 1/6: s^2 = (1/6) / 1,
# u(rate) = s / sqrt 2 = 0.288675; the tolerance file's X A = 16 um: value <= 16, 11/16 used,
# reached at 1 + (16 - 28/3) / 1.5 = 5.4444 years.
expect_exit 0 "trend figure from the tolerance file" -- "$MTCAL" history trend --store "$store" --machine HU40T \
  --figure A_X --tolerance-file "$tol" --json
[ "$(json_get 'd["series"][0]["trend"]["fit"]')" = ordinary ] && ok || bad "A_X fit"
[ "$(json_get 'round(d["series"][0]["trend"]["u_rate_per_year"], 6)')" = 0.288675 ] && ok || bad "A_X u(rate)"
[ "$(json_get 'd["series"][0]["trend"]["tolerance"]')" = "{'lo': None, 'hi': 16.0}" ] && ok || bad "A_X band"
[ "$(json_get 'd["series"][0]["trend"]["utilisation"]')" = 0.6875 ] && ok || bad "A_X used"
[ "$(json_get 'round(d["series"][0]["trend"]["crossing"]["years_from_last"], 4)')" = 3.4444 ] && ok || bad "A_X years"
[ "$(json_get 'd["series"][0]["trend"]["note"]')" = "no sample states an uncertainty: ordinary least squares, uncertainty from the scatter about the line" ] && ok || bad "A_X note"

# Text output; every quantity when none is named; --from leaves one calibration: no line, said so.
expect_exit 0 "trend text" -- "$MTCAL" history trend --store "$store" --machine HU40T --tolerance EC0Y=40
grep -q "EC0Y (parameter, urad): 3 samples, latest 30 urad on 2023-01-01; drift 5 ± 1.414 urad/year" "$tmp/out" && ok || bad "trend text: $(cat "$tmp/out")"
grep -q "leaves it 2024-12-07 (between 2023-11-16 and 2028-10-03)" "$tmp/out" && ok || bad "crossing text"
grep -q "^A_X (figure, um)" "$tmp/out" && ok || bad "all quantities"
grep -q "event 2021-06-01 crash: spindle crash" "$tmp/out" && ok || bad "events listed"
expect_exit 0 "trend --from" -- "$MTCAL" history trend --store "$store" --machine HU40T --parameter EC0Y --from 2022-06-01 --json
[ "$(json_get 'd["series"][0]["trend"]["n"]')" = 1 ] && ok || bad "--from"
[ "$(json_get 'd["series"][0]["trend"]["note"]')" = "1 sample: no line (2 needed)" ] && ok || bad "--from note"

# The report is written (its rendering is checked by reports_in_browser).
expect_exit 0 "trend report" -- "$MTCAL" history trend --store "$store" --machine HU40T --tolerance EC0Y=40 \
  --tolerance-file "$tol" --report "$tmp/trend.html"
grep -q "predicted crossing 2024-12-07" "$tmp/trend.html" && ok || bad "report crossing"
grep -q "spindle crash into the fixture, &lt;b&gt;Y axis&lt;/b&gt;" "$tmp/trend.html" && ok || bad "report event note escaped"

# --- diff -------------------------------------------------------------------------------------
# HU40T first and last: EC0Y 20 -> 30, u 2 and 2: change 10, u = 2.828427, E_n = 10 / 5.656854 = 1.767767.
expect_exit 0 "diff json" -- "$MTCAL" history diff "$r1" "$r3" --store "$store" --json
[ "$(json_get 'd["parameters"]["changes"][0]["verdict"]')" = significant ] && ok || bad "diff verdict"
[ "$(json_get 'round(d["parameters"]["changes"][0]["en"], 6)')" = 1.767767 ] && ok || bad "E_n"
[ "$(json_get 'round(d["parameters"]["changes"][0]["u_delta"], 6)')" = 2.828427 ] && ok || bad "u(delta)"
[ "$(json_get 'd["figures"]["changes"][0]["verdict"]')" = not_assessable ] && ok || bad "figure not assessable"
[ "$(json_get 'd["figures"]["changes"][0]["delta"]')" = 3.0 ] && ok || bad "figure change"
[ "$(json_get 'list(d)[:6]')" = "['first', 'second', 'coverage_factor', 'en_limit', 'parameters', 'figures']" ] && ok || bad "diff keys"
# With k = 3: E_n = 10 / (3 * 2.828427) = 1.178511, still significant; text names the rule.
expect_exit 0 "diff text" -- "$MTCAL" history diff "$r1" "$r3" --store "$store" --coverage-factor 3
grep -q "EC0Y.*1.18  significant" "$tmp/out" && ok || bad "diff text: $(cat "$tmp/out")"
grep -q "A_X.*not assessable (no uncertainty in either calibration)" "$tmp/out" && ok || bad "diff figure text"
# HU40T against LATHE-3: different machines warned, EC0Y removed, EXX added.
lathe=$("$MTCAL" history trend --store "$store" --machine LATHE-3 --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["series"][0]["samples"][0]["record"])')
expect_exit 0 "diff across machines" -- "$MTCAL" history diff "$r2" "$lathe" --store "$store" --json
grep -q "different machines" "$tmp/err" && ok || bad "no warning for different machines"
[ "$(json_get 'd["parameters"]["summary"]')" = "{'significant': 0, 'not_significant': 0, 'not_assessable': 0, 'added': 1, 'removed': 1}" ] && ok || bad "added/removed"

# --- rank -------------------------------------------------------------------------------------
# VMC-2's A_X 17 > 16: outside (17/16 = 1.0625 used) -> first; HU40T: EC0Y 30/40 = 0.75, earliest
# crossing 1.9333 years (EC0Y; A_X 3.4444); LATHE-3 has no quantity with a tolerance.
expect_exit 0 "rank json" -- "$MTCAL" history rank --store "$store" --tolerance EC0Y=40 --tolerance-file "$tol" --json
[ "$(json_get '[m["machine"] for m in d["machines"]]')" = "['VMC-2', 'HU40T']" ] && ok || bad "rank order"
[ "$(json_get 'd["machines"][0]["utilisation"]')" = 1.0625 ] && ok || bad "VMC-2 used"
[ "$(json_get 'd["machines"][0]["outside"]')" = True ] && ok || bad "VMC-2 outside"
[ "$(json_get 'd["machines"][1]["quantities"][0]["quantity"]')" = EC0Y ] && ok || bad "HU40T deciding quantity"
[ "$(json_get 'round(d["machines"][1]["years_to_limit"], 4)')" = 1.9333 ] && ok || bad "HU40T years"
[ "$(json_get 'd["not_ranked"]')" = "['LATHE-3']" ] && ok || bad "not ranked"
[ "$(json_get 'd["order"]')" = utilisation ] && ok || bad "order key"
expect_exit 0 "rank by time" -- "$MTCAL" history rank --store "$store" --tolerance EC0Y=40 --by time --json
# EC0Y only: HU40T 0.75 crossing in 1.93 years; VMC-2 11/40, rate 0.5/year reaches 40 in 58 years.
[ "$(json_get '[m["machine"] for m in d["machines"]]')" = "['HU40T', 'VMC-2']" ] && ok || bad "rank by time"
[ "$(json_get 'round(d["machines"][1]["years_to_limit"], 4)')" = 58.0 ] && ok || bad "VMC-2 years: $(json_get 'd["machines"][1]["years_to_limit"]')"
[ "$(json_get 'd["order"]')" = time_to_limit ] && ok || bad "order key by time"
expect_exit 0 "rank text" -- "$MTCAL" history rank --store "$store" --tolerance EC0Y=40 --tolerance-file "$tol"
grep -q "1  VMC-2 .* 106% *0 (outside)  A_X: 17 um" "$tmp/out" && ok || bad "rank text: $(cat "$tmp/out")"
grep -q "not ranked (no quantity with a tolerance): LATHE-3" "$tmp/out" && ok || bad "rank text not ranked"
# The store from the environment.
MTCAL_HISTORY="$store" "$MTCAL" history rank --tolerance EC0Y=40 >/dev/null 2>&1 && ok || bad "MTCAL_HISTORY"

# --- errors: one line, naming the data ----------------------------------------------------------
expect_error "unknown record" "no record '999999'" -- "$MTCAL" history diff "$r1" 999999 --store "$store"
expect_error "unknown machine" "machines in the store: HU40T, LATHE-3, VMC-2" -- "$MTCAL" history trend --store "$store" --machine HU41T
expect_error "missing parameter" "has no parameter EXX" -- "$MTCAL" history trend --store "$store" --machine HU40T --parameter EXX
expect_error "bad tolerance" "expected QUANTITY=VALUE or QUANTITY=LO:HI" -- "$MTCAL" history trend --store "$store" --machine HU40T --tolerance EC0Y
expect_error "tolerance not a number" "expected a number, found 'x'" -- "$MTCAL" history trend --store "$store" --machine HU40T --tolerance EC0Y=1:x
expect_error "tolerance range upside down" "lower limit must be below" -- "$MTCAL" history trend --store "$store" --machine HU40T --tolerance EC0Y=5:1
expect_error "tolerance of another quantity" "not among the quantities" -- "$MTCAL" history trend --store "$store" --machine HU40T --parameter EC0Y --tolerance A_X=5
expect_error "rank without tolerances" "needs tolerances" -- "$MTCAL" history rank --store "$store"
expect_error "rank unknown quantity" "no machine in the store has a parameter or figure named EZZ" -- "$MTCAL" history rank --store "$store" --tolerance EZZ=1
expect_error "no store" "no history store given" -- env -u MTCAL_HISTORY MTCAL_CONFIG=/nonexistent/config.yaml "$MTCAL" history rank --tolerance EC0Y=1
expect_error "bad date" "ISO 8601" -- "$MTCAL" history trend --store "$store" --machine HU40T --from 1.1.2022
# Help has examples.
for c in diff trend rank; do
  "$MTCAL" history $c --help | grep -q "^Examples:" && ok || bad "history $c --help has no examples"
done

summary_and_exit
