#!/usr/bin/env bash
# Reports from example data: every report type is written, is deterministic apart from its date
# line, escapes hostile names, and renders in headless Chromium without JavaScript errors
# (browser_check.mjs; screenshots into $SHOTS). Needs MTCAL, EXAMPLES, WEB, SHOTS, HISTORY_FIXTURE.
# Exit 77 (SKIPPED) when the browser part cannot run; prints "N passed, N failed".
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
M5="$EXAMPLES/hu40t-wCBXfYZt.yaml"
M3="$EXAMPLES/vmc-3axis.yaml"

run() { "$@" >"$tmp/out" 2>"$tmp/err" || bad "$*: $(cat "$tmp/err")"; }

# Every report type from the shipped examples.
run "$MTCAL" eval -m "$M3" --grid "X=-400:400:21,Y=-250:250:21,Z=-500:0:21" --report "$tmp/eval-grid.html"
printf 'X,Y,Z,B,C,dirX\n0,0,0,0,0,1\n100,50,-20,30,90,-1\n-200,100,50,-45,180,1\n' >"$tmp/points.csv"
run "$MTCAL" eval -m "$M5" --points "$tmp/points.csv" --report "$tmp/eval-points.html"
run "$MTCAL" effects -m "$M5" --at "X=100,B=30,C=90" --report "$tmp/effects.html"
run "$MTCAL" errors -m "$M5" --nonzero --report "$tmp/errors.html"
run "$MTCAL" probe-sim -m "$M5" --axis C --noise 0.001 --out "$tmp/contacts.csv"
run "$MTCAL" rotary-axis --axis C --contacts "$tmp/contacts.csv" --sphere-diameter 30 --stylus-diameter 6 \
  --machine "$M5" --report "$tmp/rotary-axis.html"
printf 'target,run,direction,measured\n0,1,up,0.001\n0,2,up,0.003\n0,1,down,-0.001\n0,2,down,0.001\n10,1,up,10.004\n10,2,up,10.006\n10,1,down,10.002\n10,2,down,10.002\n' >"$tmp/positions.csv"
run "$MTCAL" iso230-2 "$tmp/positions.csv" --report "$tmp/iso230-2.html"
# An acceptance report: 5 runs over 11 targets of a 1 m axis, metadata and tolerances from the examples.
python3 - "$tmp/positions5.csv" <<'PY'
import math, sys
with open(sys.argv[1], "w") as f:
    f.write("target,run,direction,measured\n")
    for i in range(11):
        t = 100.0 * i
        for j in range(5):
            for d, sign in (("up", 1), ("down", -1)):
                dev = 0.004 * math.sin(t / 160) + 0.000006 * t + sign * 0.0015 + 0.0008 * math.sin(7 * i + 3 * j + sign)
                f.write(f"{t},{j + 1},{d},{t + dev:.6f}\n")
PY
run "$MTCAL" iso230-2 "$tmp/positions5.csv" --report "$tmp/iso230-2-acceptance.html" \
  --meta-file "$EXAMPLES/../acceptance/metadata.yaml" --tolerance-file "$EXAMPLES/../acceptance/tolerances.yaml"
# ISO 230-2 from a laser file (its header fills the metadata) and from the real 9-target log of
# ../shared/data: the per-target table in the standard's layout must fit the page too.
run "$MTCAL" iso230-2 "$EXAMPLES/../instruments/x-axis.rtl" --report "$tmp/iso230-2-laser.html" --meta "feed=2000 mm/min" --meta "dwell=2 s" \
  --tolerance-file "$EXAMPLES/../acceptance/tolerances.yaml"
run "$MTCAL" iso230-2 "$EXAMPLES/../../../shared/data/iso230-2/b02_x_axis.dat" --report "$tmp/iso230-2-b02.html"
grep -qF '<th>target i</th><th>1</th><th>2</th>' "$tmp/iso230-2-laser.html" && grep -qF 'targets 7 to 11 of 11' "$tmp/iso230-2-laser.html" \
  && grep -qF '<th>Test date</th><td>2026-11-20</td>' "$tmp/iso230-2-laser.html" && ok || bad "laser ISO 230-2 report lacks the table or the file's metadata"
run "$MTCAL" ballbar --predict -m "$M3" --plane XY --radius 150 --centre "X=0,Y=0,Z=-250" --out "$tmp/trace.csv"
run "$MTCAL" ballbar "$tmp/trace.csv" --radius 150 --feed 1000 --report "$tmp/ballbar.html" --tolerance G=15
run "$MTCAL" eval -m "$EXAMPLES/hu40t-wCBXfYZt.yaml" --grid "X=-200:200:5,Y=-200:200:5,Z=-300:0:3,B=-30:30:3,C=0:270:4" --report "$tmp/eval-hu40t.html"
run "$MTCAL" compare "$EXAMPLES/../data/mohammed2019-ballbar-vs-samba.csv" --report "$tmp/compare.html"
run "$MTCAL" volumetric -m "$M3" --grid "X=-400:400:11,Y=-250:250:11,Z=-500:0:11" --histogram auto --box-scan 5 \
  --group-angle 0.1 --report "$tmp/volumetric.html"
run "$MTCAL" contributions -m "$M3" --grid "X=-400:400:11,Y=-250:250:11,Z=-500:0:11" --report "$tmp/contributions.html"
run "$MTCAL" diagonals -m "$M3" --box "X=-400:400,Y=-250:250,Z=-500:0" --report "$tmp/diagonals.html"
run "$MTCAL" toolpath -m "$M3" --gcode "$EXAMPLES/../gcode/pocket.nc" --step 2 --origin "X=-100,Y=-50,Z=-300" --report "$tmp/toolpath.html"
run "$MTCAL" simulate -m "$M5" --plan "$EXAMPLES/../plans/hu40t-samba-tango.csv" --noise-um 1 --scale-bar 1:2:304.8 --out "$tmp/samba.csv"
run "$MTCAL" identify -m "$M5" --measurements "$tmp/samba.csv" --estimate EC0Y,EB0Z,EA0Z,EX0C,EY0C,EA0C,EB0C,EX0B,EZ0B,EA0B,EC0B \
  --scale-bar 1:2:304.8 --report "$tmp/identify.html"
# A rehearsed campaign (docs/campaign.md): a drawn truth probed before, a perfect compensation after.
E7=EC0Y,EB0Z,EA0Z,EX0C,EY0C,EA0C,EB0C
run "$MTCAL" errors -m "$M5" --draw 7 --draw-only "$E7" --out "$tmp/truth.yaml" --out-nominal "$tmp/nominal.yaml"
run "$MTCAL" simulate -m "$M5" --params "$tmp/truth.yaml" --plan "$EXAMPLES/../plans/hu40t-samba-tango.csv" --noise-um 0.5 \
  --scale-bar 1:2:304.8 --out "$tmp/before.csv"
run "$MTCAL" simulate -m "$M5" --params "$tmp/nominal.yaml" --plan "$EXAMPLES/../plans/hu40t-samba-tango.csv" --noise-um 0.5 \
  --seed 2 --scale-bar 1:2:304.8 --out "$tmp/after.csv"
"$MTCAL" identify -m "$M5" --params "$tmp/nominal.yaml" --measurements "$tmp/before.csv" --estimate "$E7" --scale-bar 1:2:304.8 \
  --json >"$tmp/identified.json" 2>"$tmp/err" || bad "identify --json: $(cat "$tmp/err")"
run "$MTCAL" campaign -m "$M5" --params "$tmp/nominal.yaml" --before "$tmp/before.csv" --after "$tmp/after.csv" \
  --identified "$tmp/identified.json" --truth "$tmp/truth.yaml" --poses-before "$EXAMPLES/../campaign/hu40t-reached-nominal.csv" \
  --noise-um 0.5 --report "$tmp/campaign.html"
run "$MTCAL" regress "$EXAMPLES/../prediction/yaqoob2017-table5_8.csv" --x t --y e_splz --report "$tmp/regress.html"
run "$MTCAL" predict --model "$EXAMPLES/../prediction/yaqoob2017-model.yaml" --points "$EXAMPLES/../prediction/yaqoob2017-w2-points.csv" \
  --report "$tmp/predict.html"
run "$MTCAL" compensate -m "$M3" --format linuxcnc --out "$tmp/comp" --report "$tmp/compensate.html"
# The calibration history's trend report, from a store holding a known fleet (tests/history).
"$HISTORY_FIXTURE" "$tmp/history.db" || bad "history fixture"
run "$MTCAL" history trend --store "$tmp/history.db" --machine HU40T --tolerance EC0Y=40 \
  --tolerance-file "$EXAMPLES/../acceptance/tolerances.yaml" --report "$tmp/history-trend.html"
for f in eval-grid eval-points effects errors rotary-axis iso230-2 iso230-2-acceptance iso230-2-laser iso230-2-b02 ballbar eval-hu40t compare volumetric contributions diagonals toolpath identify campaign regress predict compensate history-trend; do
  [ -s "$tmp/$f.html" ] && ok || bad "$f.html not written"
done
# The points report names its input with the input's SHA-256.
sum=$(sha256sum "$tmp/points.csv" | cut -d' ' -f1)
grep -q "$sum" "$tmp/eval-points.html" && ok || bad "input hash missing from the report"
# Self-contained: outside the inlined Plotly library, no script, stylesheet or image from elsewhere
# (the browser check below also fails on any request that is not file: or data:).
python3 - "$WEB/node_modules/plotly.js-dist-min/plotly.min.js" "$tmp"/*.html <<'PY' && ok || bad "a report refers to something outside it"
import re, sys
lib = open(sys.argv[1], encoding="utf-8").read()
for f in sys.argv[2:]:
    html = open(f, encoding="utf-8").read()
    assert html.count(lib) == 1, f"{f}: Plotly is not inlined exactly once"
    rest = html.replace(lib, "")
    bad = re.findall(r'<(?:script|img|iframe)[^>]+src=|<link[^>]+href=|https?://', rest)
    assert not bad, f"{f}: {bad[:3]}"
PY

# Deterministic apart from the date line (same command, same output path, two dates).
grid="X=-400:400:21,Y=-250:250:21,Z=-500:0:21"
SOURCE_DATE_EPOCH=1000000000 "$MTCAL" eval -m "$M3" --grid "$grid" --report "$tmp/same.html" >/dev/null
mv "$tmp/same.html" "$tmp/a.html"
SOURCE_DATE_EPOCH=2000000000 "$MTCAL" eval -m "$M3" --grid "$grid" --report "$tmp/same.html" >/dev/null
grep -q '2001-09-09 01:46:40 UTC' "$tmp/a.html" && ok || bad "SOURCE_DATE_EPOCH not used for the date"
if cmp -s "$tmp/a.html" "$tmp/same.html"; then bad "the date line did not change"; else ok; fi
if cmp -s <(grep -v 'class="date"' "$tmp/a.html") <(grep -v 'class="date"' "$tmp/same.html"); then ok; else bad "reports differ beyond the date line"; fi

# Hostile names: a machine name and a file name that are HTML and script.
hostile_dir="$tmp/<b>dir & 'quote'"
mkdir -p "$hostile_dir"
python3 - "$M3" "$hostile_dir/m.yaml" <<'PY'
import re, sys
text = open(sys.argv[1], encoding="utf-8").read()
name = "</script><script>alert(1)</script><img src=x onerror=alert(2)> & \"q\" 'a'"
text = re.sub(r"^name: .*$", "name: " + '"' + name.replace("\\", "\\\\").replace('"', '\\"') + '"', text, count=1, flags=re.M)
open(sys.argv[2], "w", encoding="utf-8").write(text)
PY
run "$MTCAL" eval -m "$hostile_dir/m.yaml" --grid "X=-400:400:5,Y=0,Z=-100" --report "$tmp/hostile.html"
if grep -qF '<script>alert(1)' "$tmp/hostile.html" || grep -qF '<img src=x' "$tmp/hostile.html" || grep -qF '<b>dir' "$tmp/hostile.html"; then
  bad "a hostile name reached the HTML unescaped"
else
  ok
fi
grep -qF '&lt;/script&gt;&lt;script&gt;alert(1)' "$tmp/hostile.html" && ok || bad "hostile machine name not shown escaped"

# In a real browser: no JavaScript error, no dialog (the hostile one), every plot rendered.
node_rc=0
if command -v node >/dev/null; then
  (cd "$WEB" && MTCAL_WEB="$WEB" node "$(dirname "$0")/browser_check.mjs" "$SHOTS" \
    "$tmp/eval-grid.html:2" "$tmp/eval-points.html:2" "$tmp/effects.html:1" "$tmp/errors.html:1" \
    "$tmp/rotary-axis.html:6" "$tmp/iso230-2.html:1" "$tmp/iso230-2-acceptance.html:1" "$tmp/iso230-2-laser.html:1" "$tmp/iso230-2-b02.html:1" "$tmp/ballbar.html:2" "$tmp/eval-hu40t.html:2" "$tmp/compare.html:1" "$tmp/hostile.html:2" \
    "$tmp/volumetric.html:5" "$tmp/contributions.html:2" "$tmp/diagonals.html:2" "$tmp/toolpath.html:2" \
    "$tmp/identify.html:2" "$tmp/campaign.html:3" "$tmp/regress.html:1" "$tmp/predict.html:3" "$tmp/compensate.html:1" \
    "$tmp/history-trend.html:2") >"$tmp/browser" 2>&1
  node_rc=$?
  cat "$tmp/browser"
else
  echo "SKIPPED: node is not installed (Debian: nodejs npm; scripts/install-deps installs them)"
  node_rc=77
fi
echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ] || exit 1
exit "$node_rc"
