#!/usr/bin/env bash
# mtcal volumetric, contributions and diagonals: figures against an independent Python brute
# force over the written error map, JSON keys, bad input, no partial outputs.
# Needs MTCAL (the binary) and EXAMPLES (examples/machines). Prints "N passed, N failed".
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
M3="$EXAMPLES/vmc-3axis.yaml"
M5="$EXAMPLES/hu40t-wCBXfYZt.yaml"
GRID="X=-400:400:7,Y=-250:250:5,Z=-500:0:4"

for c in volumetric contributions diagonals; do
  expect_exit 0 "$c --help" -- "$MTCAL" $c --help
  grep -q -- '--json' "$tmp/out" && ok || bad "$c --help lists --json"
done

# VA, per component, box and histogram against a brute force over the map written by --out.
expect_exit 0 "volumetric --json" -- "$MTCAL" volumetric -m "$M3" --grid "$GRID" --out "$tmp/map.csv" \
  --box "X=-200:400,Z=-500:-100" --histogram 20 --group-angle 0.1 --group-magnitude 0.9 --json
cp "$tmp/out" "$tmp/va.json"
for k in points pairs va va_x va_y va_z critical_pair box histogram error_distribution grouping contributions; do
  json_get "d['$k']" >/dev/null 2>&1 && ok || bad "volumetric JSON lacks '$k'"
done
python3 - "$tmp/map.csv" "$tmp/va.json" <<'PY' && ok || bad "volumetric figures differ from the brute force"
import csv, itertools, json, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
d = json.load(open(sys.argv[2]))
e = [(float(r["dx"]), float(r["dy"]), float(r["dz"])) for r in rows]
assert d["points"] == len(e) == 140, d["points"]
assert d["pairs"] == 140 * 139 / 2
dist = [math.dist(a, b) for a, b in itertools.combinations(e, 2)]
# The CSV holds 10 significant digits: agree to 1e-9 mm.
assert abs(max(dist) - d["va"]) < 1e-9, (max(dist), d["va"])
for c, k in enumerate(("va_x", "va_y", "va_z")):
    col = [v[c] for v in e]
    assert abs(max(col) - min(col) - d[k]) < 1e-9, k
cp = d["critical_pair"]
diff = [cp["error_to"][c] - cp["error_from"][c] for c in range(3)]
assert abs(math.hypot(*diff) - d["va"]) < 1e-12
# The box: X in [-200, 400] and Z in [-500, -100], Y free.
inside = [v for r, v in zip(rows, e) if -200 <= float(r["X"]) <= 400 and -500 <= float(r["Z"]) <= -100]
assert d["box"]["points"] == len(inside) == 5 * 5 * 3, d["box"]["points"]
assert abs(max(math.dist(a, b) for a, b in itertools.combinations(inside, 2)) - d["box"]["va"]) < 1e-9
assert "Y" not in d["box"]["lo"] and d["box"]["lo"]["X"] == -200
h = d["histogram"]
assert sum(h["counts"]) == h["count"] == len(dist)
assert abs(h["mean"] - sum(dist) / len(dist)) < 1e-9
w = h["bin_width"]
assert abs(w * 20 - d["va"]) < 1e-15
ref = [0] * 20
for x in dist:
    ref[min(19, int(x / w))] += 1
assert sum(abs(a - b) for a, b in zip(ref, h["counts"])) <= 2, (ref, h["counts"])
assert sum(d["error_distribution"]["counts"]) == 140
g = d["grouping"]
assert g["records"] <= 140 and g["va"] <= d["va"] + 1e-15 and g["comparisons"] == g["records"] * (g["records"] - 1) / 2
# The contributions' first-order sum is close to the exact difference.
c = d["contributions"]
assert math.dist(c["exact"], diff) < 1e-12 and c["residual"] < 0.01 * d["va"]
PY

# The map read back as --points gives the same VA.
expect_exit 0 "volumetric --points" -- "$MTCAL" volumetric -m "$M3" --points "$tmp/map.csv" --json
[ "$(json_get "d['va'] == $(python3 -c "import json; print(json.load(open('$tmp/va.json'))['va'])")")" = "True" ] && ok || bad "--points VA equals --grid VA"

# Text output, box scan and a report.
expect_exit 0 "volumetric text" -- "$MTCAL" volumetric -m "$M3" --grid "$GRID" --box-scan 4 --centre "X=0,Y=0,Z=-250" --report "$tmp/v.html"
grep -q '^VA  ' "$tmp/out" && grep -q 'box 1.000 of the map' "$tmp/out" && ok || bad "volumetric text: $(cat "$tmp/out")"
[ -s "$tmp/v.html" ] && ok || bad "volumetric report written"
expect_exit 0 "box scan JSON" -- "$MTCAL" volumetric -m "$M3" --grid "$GRID" --box-scan 4 --json
[ "$(json_get "[b['fraction'] for b in d['box_scan']]")" = "[0.25, 0.5, 0.75, 1.0]" ] && ok || bad "box_scan fractions"
[ "$(json_get "d['box_scan'][-1]['va'] == d['va']")" = "True" ] && ok || bad "box_scan at 1 equals VA"

# Bad input: one line, exit non-zero, no output left behind.
expect_error "grid and points" "exactly one of --grid, --points" -- "$MTCAL" volumetric -m "$M3" --grid "$GRID" --points "$tmp/map.csv"
expect_error "neither grid nor points" "exactly one of --grid, --points" -- "$MTCAL" volumetric -m "$M3"
expect_error "bad histogram" "expected a bin count" -- "$MTCAL" volumetric -m "$M3" --grid "$GRID" --histogram many
expect_error "huge histogram" "pairs would take minutes" -- "$MTCAL" volumetric -m "$M3" --grid "X=-400:400:101,Y=-250:250:101,Z=-500:0:101" --histogram auto
expect_error "centre without scan" "--centre goes with --box-scan" -- "$MTCAL" volumetric -m "$M3" --grid "$GRID" --centre X=0
expect_error "empty box" "no configuration of the map lies inside the box" -- "$MTCAL" volumetric -m "$M3" --grid "$GRID" --box "X=1:2"
expect_error "bad box" "expected lo <= hi" -- "$MTCAL" volumetric -m "$M3" --grid "$GRID" --box "X=5:1"
expect_error "bad group magnitude" "expected a fraction between 0 and 1" -- "$MTCAL" volumetric -m "$M3" --grid "$GRID" --group-magnitude 2
expect_error "grid outside travel" "outside the travel" -- "$MTCAL" volumetric -m "$M3" --grid "X=0:900:3"
expect_error "out is a directory" "$tmp" -- "$MTCAL" volumetric -m "$M3" --grid "$GRID" --out "$tmp"
expect_error "non-finite model" "non-finite" -- "$MTCAL" volumetric -m "$M3" --grid "$GRID" --set EXX.3=1e306 --out "$tmp/never.csv"
[ ! -e "$tmp/never.csv" ] && ok || bad "a failed volumetric leaves no output"
[ -z "$(ls "$tmp" | grep '\.tmp\|never')" ] && ok || bad "no temporary files left: $(ls "$tmp")"

# contributions: hand case (only EXX = 1e-5 x: at X=300, 3 um along X, all from EXX).
expect_exit 0 "contributions --at" -- "$MTCAL" contributions -m "$M3" --only EXX.1 --set EXX.1=1e-5 --at X=300 --json
[ "$(json_get "[i['error'] for i in d['items']]")" = "['EXX']" ] && ok || bad "contributions --at items: $(cat "$tmp/out")"
python3 -c "import json; d=json.load(open('$tmp/out')); assert abs(d['items'][0]['effect'][0]-0.003)<1e-15 and abs(d['items'][0]['share']-1)<1e-9, d" && ok || bad "contributions EXX value"
expect_exit 0 "contributions --pair" -- "$MTCAL" contributions -m "$M3" --pair "X=-400,Y=75,Z=-500;X=400,Y=-250,Z=0" --top 100 --json
python3 - "$tmp/out" <<'PY' && ok || bad "contributions --pair sums"
import json, math, sys
d = json.load(open(sys.argv[1]))
s = [sum(i["effect"][c] for i in d["items"]) for c in range(3)]
assert math.dist(s, d["first_order"]) < 1e-12, (s, d["first_order"])
assert math.dist(d["first_order"], d["exact"]) < 0.01 * math.hypot(*d["exact"])
assert abs(sum(i["share"] for i in d["items"]) - 1) < 0.01
assert d["from"]["X"] == -400 and d["at"]["X"] == 400
PY
expect_exit 0 "contributions --grid" -- "$MTCAL" contributions -m "$M3" --grid "$GRID" --json --report "$tmp/c.html"
python3 - "$tmp/out" "$tmp/va.json" <<'PY' && ok || bad "contributions --grid: critical pair and what-if"
import json, sys
d = json.load(open(sys.argv[1])); v = json.load(open(sys.argv[2]))
assert d["mode"] == "critical_pair" and abs(d["va"] - v["va"]) < 1e-15
w = d["what_if"]  # one per error; all 21 of the example are non-zero
assert len(w) == 21 and all(abs(x["gain"] - (d["va"] - x["va_without"])) < 1e-15 for x in w)
assert w == sorted(w, key=lambda x: x["va_without"])
PY
[ -s "$tmp/c.html" ] && ok || bad "contributions report written"
expect_error "contributions two modes" "expected exactly one of" -- "$MTCAL" contributions -m "$M3" --at X=0 --pair "X=0;X=1"
expect_error "contributions bad pair" "separated by ';'" -- "$MTCAL" contributions -m "$M3" --pair "X=0"
expect_error "contributions bad axis" "axis 'Q' is not in topology" -- "$MTCAL" contributions -m "$M3" --at Q=1

# Directions of motion from --points reach the contributions and the what-if maps.
printf 'X,Y,Z,dirX\n-400,0,-100,1\n-400,0,-100,-1\n400,0,-100,1\n400,0,-100,-1\n0,0,-100,1\n' >"$tmp/dir.csv"
expect_exit 0 "volumetric with dir" -- "$MTCAL" volumetric -m "$M3" --only EXX.b --set EXX.b=0.005 --points "$tmp/dir.csv" --json --out "$tmp/dirmap.csv"
python3 - "$tmp/out" <<'PY' && ok || bad "reversal term in VA and contributions"
import json, math, sys
d = json.load(open(sys.argv[1]))
assert abs(d["va"] - 0.010) < 1e-12, d["va"]          # +5 um against -5 um
c = d["contributions"]
assert math.dist(c["exact"], d["critical_pair"]["difference"]) < 1e-15
assert abs(abs(c["items"][0]["effect"][0]) - 0.010) < 1e-12 and c["items"][0]["error"] == "EXX"
PY
[ "$(head -1 "$tmp/dirmap.csv")" = "X,Y,Z,dirX,dirY,dirZ,dx,dy,dz" ] && ok || bad "map CSV keeps the directions: $(head -1 "$tmp/dirmap.csv")"
expect_exit 0 "contributions with dir" -- "$MTCAL" contributions -m "$M3" --only EXX.b --set EXX.b=0.005 --points "$tmp/dir.csv" --json
[ "$(json_get "(round(d['va'], 12), [(w['error'], round(w['va_without'], 12)) for w in d['what_if']])")" = "(0.01, [('EXX', 0.0)])" ] && ok || bad "what-if with directions: $(cat "$tmp/out")"

# diagonals.
expect_exit 0 "diagonals --json" -- "$MTCAL" diagonals -m "$M3" --box "X=-400:400,Y=-250:250,Z=-500:0" --points 11 --out "$tmp/d.csv" --json
[ "$(json_get "len(d['diagonals'])")" = "16" ] && ok || bad "16 diagonals"
[ "$(json_get "sorted(d['diagonals'][0].keys())")" = "['deviation', 'direction', 'from', 'length', 'name', 'position', 'range', 'to']" ] && ok || bad "diagonal JSON keys"
[ "$(json_get "all(abs(max(x['deviation'])-min(x['deviation'])-x['range'])<1e-15 and x['deviation'][0]==0 for x in d['diagonals'])")" = "True" ] && ok || bad "diagonal range and zero start"
[ "$(wc -l <"$tmp/d.csv")" -eq $((16 * 11 + 1)) ] && ok || bad "diagonals CSV rows"
expect_exit 0 "diagonals --no-face" -- "$MTCAL" diagonals -m "$M5" --box "X=-300:300,Y=-250:250,Z=-300:300,B=30" --no-face --json
[ "$(json_get "[x['name'] for x in d['diagonals']]")" = "['body PPP', 'body NPP', 'body PNP', 'body PPN']" ] && ok || bad "body diagonals only"
[ "$(json_get "d['diagonals'][0]['from']['B']")" = "30.0" ] && ok || bad "rotary axis held at its box value"
expect_error "diagonals missing Z" "expected a range lo:hi for Z" -- "$MTCAL" diagonals -m "$M3" --box "X=0:100,Y=0:100"
expect_error "diagonals flat box" "expected a range lo < hi for Z" -- "$MTCAL" diagonals -m "$M3" --box "X=0:100,Y=0:100,Z=-5"
expect_error "diagonals outside travel" "outside the travel" -- "$MTCAL" diagonals -m "$M3" --box "X=0:1000,Y=0:100,Z=-100:0"

summary_and_exit
