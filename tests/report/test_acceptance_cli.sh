#!/usr/bin/env bash
# Acceptance options on the command line: --meta/--meta-file into the JSON, tolerances with
# pass/fail and the exit status (0, or 3 with --fail-on-tolerance), warnings for missing
# acceptance fields, one-line errors for bad metadata and tolerances. Needs MTCAL, EXAMPLES.
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
jcheck() { python3 -c "import json,sys; d=json.load(open('$tmp/out')); sys.exit(0 if ($1) else 1)"; }
# Hand calculation (mm): A = 10.657 µm, R = 7.657 µm, B = 3 µm, E = 5.5 µm, M = 2.5 µm.
printf 'target,run,direction,measured\n0,1,up,0.001\n0,2,up,0.003\n0,1,down,-0.001\n0,2,down,0.001\n10,1,up,10.004\n10,2,up,10.006\n10,1,down,10.002\n10,2,down,10.002\n20,1,up,20.002\n20,2,up,20.003\n20,1,down,19.999\n20,2,down,20.000\n' >"$tmp/p.csv"
printf 'machine: HU40T\nserial: "4711"\ndate: 2026-11-24\ntemperature_air: 20.1 °C\nfeed: 1000 mm/min\ndwell: 2 s\n' >"$tmp/meta.yaml"
printf 'unit: mm\niso230-2:\n  X: {A: 0.011, R: 0.008, B: 0.0025}\n  any: {A: 0.02}\n' >"$tmp/tol.yaml"

# Metadata from file and options (options win), kept under "metadata"; no warning when complete.
expect_exit 0 "metadata json" -- "$MTCAL" iso230-2 "$tmp/p.csv" --json --meta-file "$tmp/meta.yaml" --meta "operator=A. Smith" --meta serial=42
jcheck 'd["metadata"]["serial"] == "42" and d["metadata"]["operator"] == "A. Smith" and d["metadata"]["machine"] == "HU40T" and list(d["metadata"])[:2] == ["machine", "serial"]' \
  && ok || bad "metadata not kept in the JSON: $(cat "$tmp/out" | tail -12)"
[ ! -s "$tmp/err" ] && ok || bad "warnings with complete metadata: $(cat "$tmp/err")"
# Without metadata the JSON has no metadata key (stable keys for old callers).
expect_exit 0 "no metadata" -- "$MTCAL" iso230-2 "$tmp/p.csv" --json
jcheck 'd.get("metadata", {}) == {} and "tolerances" not in d' && ok || bad "metadata/tolerances keys without being asked for"
# A report without metadata: one warning per missing acceptance field.
expect_exit 0 "report warnings" -- "$MTCAL" iso230-2 "$tmp/p.csv" --report "$tmp/r.html"
for f in "(date)" "(machine)" "temperature" "(feed)" "(dwell)"; do
  grep -qF "warning: acceptance report: " "$tmp/err" && grep -qF "$f" "$tmp/err" && ok || bad "no warning for $f: $(cat "$tmp/err")"
done
# Tolerances: the file's X entry (axis from --meta), options over it, verdict in JSON and text.
expect_exit 0 "verdict fail, exit 0" -- "$MTCAL" iso230-2 "$tmp/p.csv" --json --tolerance-file "$tmp/tol.yaml" --meta axis=X
jcheck 'd["tolerances"]["verdict"] == "fail" and [c["quantity"] for c in d["tolerances"]["checks"]] == ["A", "R", "B"] and [c["pass"] for c in d["tolerances"]["checks"]] == [True, True, False] and abs(d["tolerances"]["checks"][0]["value"] - 10.657) < 1e-3 and d["tolerances"]["checks"][2]["limit"] == 2.5' \
  && ok || bad "verdict JSON: $(cat "$tmp/out" | tail -25)"
expect_exit 3 "--fail-on-tolerance" -- "$MTCAL" iso230-2 "$tmp/p.csv" --tolerance-file "$tmp/tol.yaml" --meta axis=X --fail-on-tolerance
grep -q "^verdict FAIL:.*B 3.00 > 2.5 um FAIL" "$tmp/out" && ok || bad "text verdict: $(cat "$tmp/out")"
expect_exit 0 "pass with option over file" -- "$MTCAL" iso230-2 "$tmp/p.csv" --tolerance-file "$tmp/tol.yaml" --meta axis=X --tolerance B=3.1um --fail-on-tolerance
grep -q "^verdict PASS:" "$tmp/out" && ok || bad "option did not replace the file's B: $(cat "$tmp/out")"
expect_exit 0 "any entry" -- "$MTCAL" iso230-2 "$tmp/p.csv" --json --tolerance-file "$tmp/tol.yaml" --meta axis=Y
jcheck 'd["tolerances"]["verdict"] == "pass" and d["tolerances"]["checks"][0]["limit"] == 20' && ok || bad "'any' entry not used"
# The report carries the banner and the metadata.
expect_exit 0 "report with verdict" -- "$MTCAL" iso230-2 "$tmp/p.csv" --report "$tmp/v.html" --meta-file "$tmp/meta.yaml" --tolerance A=8
grep -qF '<div class="verdict fail">FAIL' "$tmp/v.html" && grep -qF '<th>Serial number</th><td>4711</td>' "$tmp/v.html" && ok || bad "report lacks banner or metadata"
# Ballbar and volumetric take tolerances too.
expect_exit 0 "volumetric VA" -- "$MTCAL" volumetric -m "$EXAMPLES/vmc-3axis.yaml" --grid "X=-400:400:5,Y=-250:250:5,Z=-500:0:5" --json --tolerance VA=1mm
jcheck 'd["tolerances"]["checks"][0]["quantity"] == "VA" and d["tolerances"]["checks"][0]["limit"] == 1000 and d["tolerances"]["verdict"] == "pass"' && ok || bad "volumetric verdict"
# Errors: one line, non-zero, no output.
expect_error "unknown metadata key" "unknown metadata field 'sreial'" -- "$MTCAL" iso230-2 "$tmp/p.csv" --meta sreial=1
expect_error "meta without =" "expected key=value" -- "$MTCAL" iso230-2 "$tmp/p.csv" --meta serial
printf 'machine: M\nopertor: X\n' >"$tmp/badmeta.yaml"
expect_error "bad metadata file" "badmeta.yaml:2" -- "$MTCAL" iso230-2 "$tmp/p.csv" --meta-file "$tmp/badmeta.yaml"
expect_error "unknown quantity" "does not give" -- "$MTCAL" iso230-2 "$tmp/p.csv" --tolerance G=3
expect_error "negative tolerance" ">= 0" -- "$MTCAL" iso230-2 "$tmp/p.csv" --tolerance A=-3
printf 'iso230-2:\n  X: {Q: 1}\n' >"$tmp/badtol.yaml"
expect_error "bad tolerance file" "badtol.yaml:2" -- "$MTCAL" iso230-2 "$tmp/p.csv" --tolerance-file "$tmp/badtol.yaml"
[ ! -e "$tmp/none.html" ] && expect_error "no report on error" "unknown metadata" -- "$MTCAL" iso230-2 "$tmp/p.csv" --meta x=1 --report "$tmp/none.html"
[ ! -e "$tmp/none.html" ] && ok || bad "a report was written despite the error"
expect_exit 0 "example files" -- "$MTCAL" iso230-2 "$tmp/p.csv" --json --meta-file "$EXAMPLES/../acceptance/metadata.yaml" --tolerance-file "$EXAMPLES/../acceptance/tolerances.yaml"
jcheck 'd["metadata"]["axis"] == "X" and d["tolerances"]["checks"][0]["limit"] == 16 and [c["quantity"] for c in d["tolerances"]["checks"]] == ["A", "E", "M", "R", "B"] and [c["pass"] for c in d["tolerances"]["checks"]] == [True, True, True, False, True]' && ok || bad "example metadata/tolerance files"
# A laser file's header fills the report's metadata (machine, serial, date, axis, operator,
# temperatures, humidity, instrument); --meta wins over the file; the axis picks the tolerances.
RTL="$EXAMPLES/../instruments/x-axis.rtl"
expect_exit 0 "laser metadata json" -- "$MTCAL" iso230-2 "$RTL" --json --meta "operator=A. Smith"
jcheck 'd["metadata"]["machine"] == "VMC 800 (example)" and d["metadata"]["serial"] == "4711" and d["metadata"]["date"] == "2026-11-20" and d["metadata"]["axis"] == "X" and d["metadata"]["operator"] == "A. Smith" and d["metadata"]["temperature_air"] == "20.4 C" and d["metadata"]["temperature_material"] == "20.2 C" and d["metadata"]["humidity"] == "46 %" and d["metadata"]["instrument"] == "XL-80 s/n 000000 (example); Compensator XC-80 s/n 000000 (example)" and d["metadata"]["USER-TEXT/Machine"] == "VMC 800 (example)"' \
  && ok || bad "laser header not mapped into the metadata: $(head -c 1500 "$tmp/out")"
expect_exit 0 "laser metadata report" -- "$MTCAL" iso230-2 "$RTL" --report "$tmp/laser.html" --meta machine=HU40T --tolerance-file "$tmp/tol.yaml"
grep -qF '<th>Machine</th><td>HU40T</td>' "$tmp/laser.html" && grep -qF '<th>Test date</th><td>2026-11-20</td>' "$tmp/laser.html" \
  && grep -qF '<th>Air temperature</th><td>20.4 C</td>' "$tmp/laser.html" && grep -qF '<th>Axis tested</th><td>X</td>' "$tmp/laser.html" && ok || bad "laser report metadata: $(grep -F '<th>' "$tmp/laser.html" | head -20)"
# The header states date, machine and temperatures: only feed and dwell are missing (ISO 230-2 clause 7).
grep -qF "(feed)" "$tmp/err" && ! grep -qF "(date)" "$tmp/err" && ! grep -qF "(machine)" "$tmp/err" && ! grep -qF "temperature" "$tmp/err" \
  && ok || bad "laser report warnings: $(cat "$tmp/err")"
# The file's Axis: X picked the X entry of the tolerance file (A 11 um, R 8 um, B 2.5 um).
grep -qF '<td>B</td><td>' "$tmp/laser.html" && ok || bad "axis from the laser file did not pick the X tolerances"
summary_and_exit
