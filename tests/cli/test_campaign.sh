#!/usr/bin/env bash
# A rehearsed calibration campaign (issue 33; docs/campaign.md): errors --draw (a seeded truth, its
# parameter files), pose-check and campaign, their JSON keys, bad inputs with nothing written.
# Needs MTCAL and EXAMPLES (examples/). Prints "N passed, N failed".
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
H="$EXAMPLES/machines/hu40t-wCBXfYZt.yaml"
P="$EXAMPLES/plans/hu40t-samba-tango.csv"
R="$EXAMPLES/campaign/hu40t-reached-nominal.csv"
EST=EC0Y,EB0Z,EA0Z,EX0C,EY0C,EA0C,EB0C

for c in pose-check campaign; do
  expect_exit 0 "$c --help" -- "$MTCAL" $c --help
  grep -q -- 'Examples:' "$tmp/out" && ok || bad "$c --help has examples"
done
"$MTCAL" errors --help | grep -q -- '--draw-only' && ok || bad "errors --help lists --draw-only"

# The draw: the same seed the same files, another seed others; the truth file read back by --params.
D=(errors -m "$H" --draw 7 --draw-only "$EST" --draw-table ECC --draw-table-points 13)
expect_exit 0 "errors --draw" -- "$MTCAL" "${D[@]}" --out "$tmp/truth.yaml" --out-nominal "$tmp/nominal.yaml" --json
cp "$tmp/out" "$tmp/draw.json"
expect_exit 0 "errors --draw again" -- "$MTCAL" "${D[@]}" --out "$tmp/truth2.yaml"
cmp -s "$tmp/truth.yaml" "$tmp/truth2.yaml" && ok || bad "the same seed wrote another truth"
expect_exit 0 "errors --draw 8" -- "$MTCAL" errors -m "$H" --draw 8 --draw-only "$EST" --draw-table ECC --out "$tmp/truth8.yaml"
cmp -s "$tmp/truth.yaml" "$tmp/truth8.yaml" && bad "seeds 7 and 8 drew the same truth" || ok
python3 - "$tmp/draw.json" "$EST" <<'PY' && ok || bad "the draw's JSON: the selection, sizes in range, ECC a table"
import json, sys
d = json.load(open(sys.argv[1]))
want = set(sys.argv[2].split(",")) | {"ECC"}
assert d["draw"]["seed"] == 7
drawn = {e["error"]: e for e in d["draw"]["drawn"]}
assert set(drawn) == want, set(drawn) ^ want
for name, e in drawn.items():
    lo, hi = (10, 100) if e["unit"] == "urad" else (5, 50)
    assert lo <= e["size"] <= hi, (name, e)
assert drawn["ECC"]["table"] and len(drawn["ECC"]["parameters"]) == 13
names = {p["error"] for p in d["parameters"]}
assert names <= want, names - want
assert d["out"].endswith("truth.yaml") and d["out_nominal"].endswith("nominal.yaml")
PY
# --params truth.yaml on the example machine (its own errors not zero) lists exactly the draw.
expect_exit 0 "errors --params truth" -- "$MTCAL" errors -m "$H" --params "$tmp/truth.yaml" --nonzero --json
python3 - "$tmp/draw.json" "$tmp/out" <<'PY' && ok || bad "the truth file reads back to the drawn parameters"
import json, sys
a = {p["name"]: p["value"] for p in json.load(open(sys.argv[1]))["parameters"]}
b = {p["name"]: p["value"] for p in json.load(open(sys.argv[2]))["parameters"]}
assert a == b, set(a) ^ set(b)
PY
expect_exit 0 "errors --params nominal" -- "$MTCAL" errors -m "$H" --params "$tmp/nominal.yaml" --nonzero --json
[ "$(json_get 'len(d["parameters"])')" = 0 ] && ok || bad "the nominal file leaves errors"
# Bad input: each names its option, nothing written.
expect_error "--draw-only unknown" "--draw-only" -- "$MTCAL" errors -m "$H" --draw 1 --draw-only EX0Q --out "$tmp/bad1.yaml"
expect_error "--draw-table of a location error" "--draw-table" -- "$MTCAL" errors -m "$H" --draw 1 --draw-table EX0C --out "$tmp/bad2.yaml"
expect_error "--draw-length-um reversed" "--draw-length-um" -- "$MTCAL" errors -m "$H" --draw 1 --draw-length-um 50:5 --out "$tmp/bad3.yaml"
expect_error "--draw-angle-urad malformed" "--draw-angle-urad" -- "$MTCAL" errors -m "$H" --draw 1 --draw-angle-urad 10 --out "$tmp/bad4.yaml"
expect_error "--out-nominal without --draw" "--out-nominal" -- "$MTCAL" errors -m "$H" --out-nominal "$tmp/bad5.yaml"
for f in bad1 bad2 bad3 bad4 bad5; do [ ! -e "$tmp/$f.yaml" ] && ok || bad "$f.yaml written"; done

# pose-check: nominal joints on the truth (before a compensation); on the nominal machine every error is 0.
expect_exit 0 "pose-check" -- "$MTCAL" pose-check -m "$H" --params "$tmp/truth.yaml" --poses "$R" --json --per-pose
for k in poses tool_length max_um max_pose rms_um va_um va_pair max_direction_urad errors; do
  json_get "d['$k']" >/dev/null 2>&1 && ok || bad "pose-check JSON lacks '$k'"
done
python3 -c "import json; d=json.load(open('$tmp/out')); assert d['poses'] >= 20 and d['max_um'] > 5 and d['va_um'] >= d['max_um'] * 0.5" \
  && ok || bad "pose-check: the truth's errors at the reached poses"
expect_exit 0 "pose-check nominal" -- "$MTCAL" pose-check -m "$H" --params "$tmp/nominal.yaml" --poses "$R" --json
python3 -c "import json; d=json.load(open('$tmp/out')); assert d['max_um'] < 1e-6, d['max_um']" && ok || bad "pose-check: nominal machine, nominal joints not 0"
printf 'X,Y,Z,B,C,qX,qY,qZ,qB\n0,0,0,0,0,0,0,0,0\n' >"$tmp/short.csv"
expect_error "pose-check missing column" "qC" -- "$MTCAL" pose-check -m "$H" --poses "$tmp/short.csv"

# campaign: the truth probed before, a perfect compensation after (simulate on the nominal model).
sed '/^  Z:/s/travel: \[-300, 300\]}$/travel: [-500, 300]}/' "$H" >"$tmp/long-z.yaml"
expect_exit 0 "simulate before" -- "$MTCAL" simulate -m "$tmp/long-z.yaml" --params "$tmp/truth.yaml" --plan "$P" --noise-um 0.3 --seed 1 --scale-bar 1:2:304.8 --out "$tmp/before.csv"
expect_exit 0 "simulate after" -- "$MTCAL" simulate -m "$tmp/long-z.yaml" --params "$tmp/nominal.yaml" --plan "$P" --noise-um 0.3 --seed 2 --scale-bar 1:2:304.8 --out "$tmp/after.csv"
"$MTCAL" identify -m "$tmp/long-z.yaml" --params "$tmp/nominal.yaml" --measurements "$tmp/before.csv" --estimate "$EST" --scale-bar 1:2:304.8 --json >"$tmp/identified.json" && ok || bad "identify"
expect_exit 0 "campaign" -- "$MTCAL" campaign -m "$tmp/long-z.yaml" --before "$tmp/before.csv" --after "$tmp/after.csv" \
  --identified "$tmp/identified.json" --truth "$tmp/truth.yaml" --poses-before "$R" --poses-after "$R" --noise-um 0.3 \
  --report "$tmp/campaign.html" --json
for k in machine reference facets before after improvement probed identification parameters not_estimated max_ratio beyond_3u random_poses probing_noise_um goals report; do
  json_get "d['$k']" >/dev/null 2>&1 && ok || bad "campaign JSON lacks '$k'"
done
python3 - "$tmp/out" <<'PY' && ok || bad "campaign: before > after, ECC not estimated listed, the reached poses"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["before"]["max_um"] > 2 * d["after"]["max_um"], (d["before"], d["after"])
assert d["after"]["rms_um"] < 1.0
assert {p["name"] for p in d["not_estimated"]} and all(p["name"].startswith("ECC") for p in d["not_estimated"])
assert len(d["parameters"]) == 7 and all(p["truth"] is not None for p in d["parameters"])
assert d["random_poses"]["before"]["poses"] >= 20
assert d["goals"]["residual"] is not None
PY
[ -s "$tmp/campaign.html" ] && grep -q 'Calibration campaign' "$tmp/campaign.html" && ok || bad "campaign report"
# Not the same plan; reached poses without a truth; nothing written.
head -n -3 "$tmp/after.csv" >"$tmp/short-after.csv"
expect_error "campaign: plans differ" "short-after.csv" -- "$MTCAL" campaign -m "$tmp/long-z.yaml" --before "$tmp/before.csv" --after "$tmp/short-after.csv" --report "$tmp/bad.html"
expect_error "campaign: poses without truth" "--truth" -- "$MTCAL" campaign -m "$tmp/long-z.yaml" --before "$tmp/before.csv" --after "$tmp/after.csv" --poses-before "$R" --report "$tmp/bad.html"
echo '{"converged": true}' >"$tmp/bad.json"
expect_error "campaign: not identify's JSON" "bad.json" -- "$MTCAL" campaign -m "$tmp/long-z.yaml" --before "$tmp/before.csv" --after "$tmp/after.csv" --identified "$tmp/bad.json" --report "$tmp/bad.html"
[ ! -e "$tmp/bad.html" ] && ok || bad "a failed campaign wrote its report"

# --record (issue 33): pose-check and campaign in the history, with their kind; list and show them.
store="sqlite:$tmp/history.db"
"$MTCAL" pose-check -m "$H" --params "$tmp/truth.yaml" --poses "$R" --record="$store" >"$tmp/out" 2>"$tmp/err" \
  && grep -q "^mtcal: recorded [0-9a-f]* in " "$tmp/err" && ok || bad "pose-check --record: $(cat "$tmp/err")"
pc=$(sed -n 's/^mtcal: recorded \([0-9a-f]*\) in .*/\1/p' "$tmp/err")
grep -q "^max |e| " "$tmp/out" && ok || bad "pose-check --record still prints its text"
"$MTCAL" campaign -m "$tmp/long-z.yaml" --before "$tmp/before.csv" --after "$tmp/after.csv" --identified "$tmp/identified.json" \
  --truth "$tmp/truth.yaml" --noise-um 0.3 --record="$store" --json >"$tmp/out" 2>"$tmp/err" \
  && grep -q "^mtcal: recorded [0-9a-f]* in " "$tmp/err" && ok || bad "campaign --record: $(cat "$tmp/err")"
cp=$(sed -n 's/^mtcal: recorded \([0-9a-f]*\) in .*/\1/p' "$tmp/err")
expect_exit 0 "history list" -- "$MTCAL" history list --store "$store" --json
python3 - "$tmp/out" "$pc" "$cp" <<'PY' && ok || bad "history list: the pose-check and campaign records with their kinds"
import json, sys
d = json.load(open(sys.argv[1]))
rows = d["records"] if isinstance(d, dict) else d
kinds = {r["id"]: r["command"] for r in rows}
assert kinds[sys.argv[2]] == "pose-check" and kinds[sys.argv[3]] == "campaign", kinds
PY
expect_exit 0 "history show pose-check" -- "$MTCAL" history show "$pc" --store "$store" --json
python3 - "$tmp/out" <<'PY' && ok || bad "history show: pose-check's figures max_um rms_um va_um in um"
import json, sys
d = json.load(open(sys.argv[1]))
f = {x["name"]: x for x in d["figures"]}
assert set(f) == {"max_um", "rms_um", "va_um"} and all(x["unit"] == "um" for x in f.values()), f
assert f["max_um"]["value"] > 1, f
PY
expect_exit 0 "history show campaign" -- "$MTCAL" history show "$cp" --store "$store" --json
python3 - "$tmp/out" <<'PY' && ok || bad "history show: the campaign's identified parameters with u"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["command"] == "campaign" and len(d["parameters"]) == 7 and all(p["uncertainty"] is not None for p in d["parameters"]), d
PY
summary_and_exit
