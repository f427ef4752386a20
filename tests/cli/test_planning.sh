#!/usr/bin/env bash
# mtcal plan and probe-log (docs/planning.md): the designed plan read by simulate and identify, the
# comparison with the paper's plan, the probing program, the log back to measurements, bad inputs
# with nothing written. Needs MTCAL and EXAMPLES (examples/). Prints "N passed, N failed".
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
H="$EXAMPLES/machines/hu40t-wCBXfYZt.yaml"
P="$EXAMPLES/plans/hu40t-samba-tango.csv"
EST=EC0Y,EB0Z,EA0Z,EX0C,EY0C,EA0C,EB0C,EX0B,EZ0B,EA0B,EC0B,EXX.1,EYY.1,EZZ.1

for c in plan probe-log; do
  expect_exit 0 "$c --help" -- "$MTCAL" $c --help
  grep -q -- '--json' "$tmp/out" && ok || bad "$c --help lists --json"
  grep -q -- 'Examples:' "$tmp/out" && ok || bad "$c --help has examples"
done

# Against the paper's plan: its uncertainties as the budget, fewer poses. The example file's Z
# travel (+-300 mm) does not hold the paper's plan (Z down to -445 mm): Z opened to -500 mm.
sed '/^  Z:/s/travel: \[-300, 300\]}$/travel: [-500, 300]}/' "$H" >"$tmp/long-z.yaml"
grep -q 'Z: {direction: +z, point: \[0, 0, 300\], travel: \[-500, 300\]}' "$tmp/long-z.yaml" && ok || bad "long-Z machine"
expect_exit 0 "plan --against" -- "$MTCAL" plan -m "$tmp/long-z.yaml" --estimate "$EST" --scale-bar 1:2:304.8 --against "$P" \
  --rotary-step-deg 30 --out "$tmp/plan.csv" --gcode "$tmp/probe.ngc" --json
for k in criterion candidates poses target_met predicted best_reachable time against out gcode; do
  json_get "d['$k']" >/dev/null 2>&1 && ok || bad "plan JSON lacks '$k'"
done
python3 - "$tmp/out" <<'PY' && ok || bad "plan meets the paper's uncertainties with >= 30 % fewer poses"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["target_met"]
a = d["against"]
assert a["poses"] == 76
assert d["poses"] <= 53, d["poses"]
for name, p in d["predicted"]["parameters"].items():
    assert p["u"] <= a["predicted"]["parameters"][name]["u"] * (1 + 1e-6), name
PY
# The plan file goes through simulate and identify.
ZERO=()
for p in ${EST//,/ }; do ZERO+=(--set "$p=0"); done
expect_exit 0 "simulate the designed plan" -- "$MTCAL" simulate -m "$H" --plan "$tmp/plan.csv" --noise-um 1 --scale-bar 1:2:304.8 --out "$tmp/meas.csv"
expect_exit 0 "identify from it" -- "$MTCAL" identify -m "$H" "${ZERO[@]}" --measurements "$tmp/meas.csv" --estimate "$EST" --scale-bar 1:2:304.8 --json
[ "$(json_get "len(d['parameters'])")" = 14 ] && ok || bad "identify estimates the 14 parameters"
grep -q '^G38.2 ' "$tmp/probe.ngc" && grep -q '(PROBEOPEN ' "$tmp/probe.ngc" && ok || bad "the program probes and logs"

# Bad inputs: a clear one-line error and no file written.
expect_error "unreachable target" "best reachable" -- "$MTCAL" plan -m "$H" --estimate "$EST" --scale-bar 1:2:304.8 \
  --artefact "$P" --rotary-step-deg 45 --target-u EX0C=1e-9mm --out "$tmp/no1.csv"
[ ! -e "$tmp/no1.csv" ] && ok || bad "nothing written for an unreachable target"
expect_error "not identifiable" "EXw is not identifiable" -- "$MTCAL" plan -m "$H" --estimate EX0C,EXw --artefact "$P" \
  --rotary-step-deg 45 --poses 10 --out "$tmp/no2.csv"
[ ! -e "$tmp/no2.csv" ] && ok || bad "nothing written for an unidentifiable parameter"
grep -v ',facet,' "$P" >"$tmp/balls.csv"   # balls only: the table rule applies to every candidate
expect_error "no candidate" "no candidate configuration is left" -- "$MTCAL" plan -m "$H" --estimate "$EST" --artefact "$tmp/balls.csv" \
  --rotary-step-deg 45 --poses 10 --table-z 1000 --out "$tmp/no3.csv"
[ ! -e "$tmp/no3.csv" ] && ok || bad "nothing written without candidates"
expect_error "no budget" "expected a budget" -- "$MTCAL" plan -m "$H" --estimate "$EST" --artefact "$P"
expect_error "bad target" "unknown parameter 'EQQ'" -- "$MTCAL" plan -m "$H" --estimate "$EST" --artefact "$P" --target-u EQQ=1um

# --target-va-u: the standard uncertainty of the VA over the workspace as the budget (45 deg grid:
# about a second). The reported u is sqrt(g^T C g) of the designed plan; met; the VA positive.
EST10=EC0Y,EB0Z,EA0Z,EX0C,EY0C,EA0C,EB0C,EXX.1,EYY.1,EZZ.1
expect_exit 0 "plan --target-va-u" -- "$MTCAL" plan -m "$H" --estimate "$EST10" --scale-bar 1:2:304.8 --artefact "$P" \
  --rotary-step-deg 45 --target-va-u 3um --out "$tmp/va-plan.csv" --json
python3 - "$tmp/out" <<'PY' && ok || bad "plan --target-va-u: va {value, u <= target, u_best, workspace, pairs}, target met"
import json, sys
d = json.load(open(sys.argv[1]))
v = d["va"]
assert d["target_met"] and d["criterion"] == "max-u", d["criterion"]
assert v["target"] == 0.003 and v["u"] <= 0.003 * (1 + 1e-6) and v["u_best"] <= v["u"], v
assert v["value"] > 0.05 and v["pairs"] >= 1 and v["workspace"].startswith("the travels"), v
assert d["poses"] < d["candidates"]["kept"]
PY
[ -s "$tmp/va-plan.csv" ] && ok || bad "the VA-budget plan is written"
expect_error "unreachable VA target" "best reachable" -- "$MTCAL" plan -m "$H" --estimate "$EST10" --scale-bar 1:2:304.8 \
  --artefact "$P" --rotary-step-deg 45 --target-va-u 0.01um --out "$tmp/no6.csv"
[ ! -e "$tmp/no6.csv" ] && ok || bad "nothing written for an unreachable VA target"
expect_error "VA target with --poses" "excludes" -- "$MTCAL" plan -m "$H" --estimate "$EST10" --artefact "$P" --poses 10 --target-va-u 3um
expect_error "bad VA target" "--target-va-u" -- "$MTCAL" plan -m "$H" --estimate "$EST10" --artefact "$P" --target-va-u 3parsecs
expect_error "bad workspace" "--workspace" -- "$MTCAL" plan -m "$H" --estimate "$EST10" --artefact "$P" --target-va-u 3um --workspace Q=1:2:3
# A machine without errors has a VA of 0: nothing to linearise about.
sed '/^errors:/,$d' "$H" >"$tmp/clean.yaml"
expect_error "VA of an error-free machine" "must not all vanish" -- "$MTCAL" plan -m "$tmp/clean.yaml" --estimate EX0C,EY0C \
  --artefact "$P" --rotary-step-deg 45 --target-va-u 3um

# --candidates --choose: the parameters chosen by the subset search, stated.
V="$EXAMPLES/machines/rrttt-table-table.yaml"
VP="$EXAMPLES/plans/rrttt-viprey-sphere.csv"
expect_exit 0 "plan --candidates" -- "$MTCAL" plan -m "$V" --artefact "$VP" --estimate EX0C,EY0C \
  --candidates EA0C,EB0C,EY0A,EZ0A,EB0A,EC0A,EXw,EC0C --choose 5 --poses 20 --rotary-step-deg 30 --json
python3 - "$tmp/out" <<'PY' && ok || bad "plan --candidates: parameters_chosen and the estimate predicted"
import json, sys
d = json.load(open(sys.argv[1]))
c = d["parameters_chosen"]
assert len(c["chosen"]) == 5 and c["estimate"][:2] == ["EX0C", "EY0C"] and c["examined"] == 56 and c["full_rank"] >= 1, c
assert "EXw" not in c["chosen"]
assert list(d["predicted"]["parameters"]) == c["estimate"], d["predicted"]["parameters"]
PY
expect_error "no identifiable subset" "EXw = 1 ball S x" -- "$MTCAL" plan -m "$V" --artefact "$VP" --estimate EX0C \
  --candidates EXw,EYw --choose 1 --poses 10 --rotary-step-deg 30
expect_error "--candidates without --choose" "--choose" -- "$MTCAL" plan -m "$V" --artefact "$VP" --candidates EXw --poses 10
expect_error "nothing to identify" "expected the parameters to identify" -- "$MTCAL" plan -m "$V" --artefact "$VP" --poses 10

# --ball-region: candidate balls on a grid of the table, counted; the plan goes through simulate.
expect_exit 0 "plan --ball-region" -- "$MTCAL" plan -m "$V" --ball-region -100:100,-100:100,50 --ball-spacing 100 \
  --estimate EX0C,EY0C,EA0C,EB0C,EY0A,EZ0A,EB0A,EC0A --poses 16 --rotary-step-deg 30 --out "$tmp/region.csv" --json
python3 - "$tmp/out" <<'PY' && ok || bad "plan --ball-region: ball_region {positions 9, reachable, used}"
import json, sys
d = json.load(open(sys.argv[1]))
r = d["ball_region"]
assert r["positions"] == 9 and 1 <= r["used"] <= r["reachable"] <= 9, r
assert d["poses"] == 16
PY
expect_exit 0 "simulate the region plan" -- "$MTCAL" simulate -m "$V" --plan "$tmp/region.csv" --noise-um 1 --out "$tmp/region-meas.csv"
expect_error "bad region" "expected XMIN:XMAX,YMIN:YMAX,Z" -- "$MTCAL" plan -m "$V" --ball-region -100:100,50 \
  --estimate EX0C --poses 4
expect_error "empty region" "min <= max" -- "$MTCAL" plan -m "$V" --ball-region 100:-100,-100:100,50 --estimate EX0C --poses 4

# Ballbar circles and a laser line as measurement records (docs/identification.md): simulate writes
# their readings, identify reads them and recovers what probing alone cannot; plan refuses them.
M3="$EXAMPLES/machines/vmc-3axis.yaml"
BL="$EXAMPLES/plans/vmc-ballbar-laser.csv"
SQ=EC0Y,EA0Z,EB0Z,EXX.1,EZZ.1
expect_exit 0 "simulate ballbar and laser records" -- "$MTCAL" simulate -m "$M3" --plan "$BL" --noise-um 1 --artefact-error-um 5 \
  --scale-bar 1:2:489.89794855663564 --out "$tmp/bl-meas.csv"
grep -q ',radius,angle,along,reading$' "$tmp/bl-meas.csv" && grep -q ',ballbar,' "$tmp/bl-meas.csv" && ok || bad "their readings written"
ZERO3=()
for p in ${SQ//,/ }; do ZERO3+=(--set "$p=0"); done
expect_exit 0 "identify from ballbar and laser records" -- "$MTCAL" identify -m "$M3" "${ZERO3[@]}" --measurements "$tmp/bl-meas.csv" \
  --estimate "$SQ" --scale-bar 1:2:489.89794855663564 --truth "$M3" --workspace X=-100:100:2,Y=-100:100:2,Z=-400:-100:2 --json
python3 - "$tmp/out" <<'PY' && ok || bad "identify: the 5 squarenesses and scales within 3 u of the truth; ballbar and laser rms"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["converged"] and not d["unidentifiable"], d["unidentifiable"]
assert len(d["parameters"]) == 5
for name, p in d["parameters"].items():
    assert abs(p["value"] - p["imposed"]) < 3 * p["u"], (name, p)
assert 0 < d["rms_um"]["ballbar"] < 3 and 0 < d["rms_um"]["laser"] < 3, d["rms_um"]
assert set(d["artefact"]["ballbars"]) == {"XY", "YZ", "ZX"} and set(d["artefact"]["lasers"]) == {"LX"}
PY
expect_error "plan with a ballbar feature" "not proposed" -- "$MTCAL" plan -m "$M3" --artefact "$BL" --estimate EC0Y --poses 4

# plan --ballbar --laser: circles and lines proposed beside the two balls (docs/planning.md,
# "Ballbar circles and laser lines"); the plan file carries them through simulate and identify, the
# program probes the balls and names the setups left to do by hand.
head -n 8 "$BL" >"$tmp/bl-balls.csv"
expect_exit 0 "plan --ballbar --laser" -- "$MTCAL" plan -m "$M3" --artefact "$tmp/bl-balls.csv" --estimate "$SQ" \
  --scale-bar 1:2:489.89794855663564 --ballbar 150 --laser X,Z --poses 6 --out "$tmp/bl-plan.csv" --gcode "$tmp/bl.ngc" --json
python3 - "$tmp/out" "$tmp/bl.ngc" "$tmp/bl-plan.csv" <<'PY' && ok || bad "plan --ballbar --laser: 6 poses, by_hand in the JSON and the program, their time"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["poses"] == 6 and d["candidates"]["considered"] == 31 and d["candidates"]["kept"] == 31, d["candidates"]
hand = d["by_hand"]
kinds = [h["kind"] for h in hand]
assert len(hand) >= 3 and set(kinds) <= {"ballbar", "laser"}, kinds
t = d["time"]
assert t["ballbar_circles"] == kinds.count("ballbar") and t["laser_lines"] == kinds.count("laser"), t
assert abs(t["total_s"] - (t["moves_s"] + t["probing_s"] + t["indexing_s"] + t["instruments_s"])) < 1e-6, t
assert t["instruments_s"] > 300 * len(hand), t
ngc = open(sys.argv[2]).read()
assert "by hand, beside it" in ngc and all(h["text"] in ngc for h in hand), ngc[:1500]
moves = sum(l.startswith("G38.2") for l in ngc.splitlines())
assert "ballbar" not in ngc.split("G21")[1] and moves == 5 * (d["poses"] - len(hand)), moves
plan = open(sys.argv[3]).read()
assert plan.count(",ballbar,") + plan.count(",laser,") > 36, plan[:500]
PY
SB=()
[ "$(grep -c ',ball,' "$tmp/bl-plan.csv")" = 2 ] && SB=(--scale-bar 1:2:489.89794855663564)
expect_exit 0 "simulate the planned circles and lines" -- "$MTCAL" simulate -m "$M3" --plan "$tmp/bl-plan.csv" --noise-um 1 \
  --artefact-error-um 5 "${SB[@]}" --seed 3 --out "$tmp/bl-plan-meas.csv"
expect_exit 0 "identify from the planned circles and lines" -- "$MTCAL" identify -m "$M3" "${ZERO3[@]}" \
  --measurements "$tmp/bl-plan-meas.csv" --estimate "$SQ" "${SB[@]}" --truth "$M3" \
  --workspace X=-100:100:2,Y=-100:100:2,Z=-400:-100:2 --json
python3 - "$tmp/out" <<'PY' && ok || bad "identify on the designed plan: the 5 parameters within 3 u of the truth"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["converged"] and not d["unidentifiable"], d["unidentifiable"]
for name, p in d["parameters"].items():
    assert abs(p["value"] - p["imposed"]) < 3 * p["u"], (name, p)
PY
# probe-log on a plan with a circle: the log holds the probing part's contacts (here each G38.2
# move's end, on a sphere about the ball), the circle's records are named as done by hand.
expect_exit 0 "plan with a circle and its program" -- "$MTCAL" plan -m "$V" --artefact "$VP" --estimate EY0C,EZ0A,EC0Y \
  --poses 10 --rotary-step-deg 30 --ballbar 150 --laser X --out "$tmp/pc-plan.csv" --gcode "$tmp/pc.ngc" --json
python3 - "$tmp/pc.ngc" "$tmp/pc-log.txt" <<'PY' && ok || bad "the program of a plan with a circle: G38.2 moves, logged"
import re, sys
at, log = dict.fromkeys("XYZABC", 0.0), []
for line in open(sys.argv[1]):
    line = line.split("(")[0].strip()
    words = {m.group(1): float(m.group(2)) for m in re.finditer(r"([XYZABC])(-?[\d.]+)", line)}
    if line.startswith("G38.2"):
        p = {**at, **words}
        log.append(" ".join(f"{p[a]:.6f}" for a in "XYZABC") + " 0 0 0")
    at.update(words)
assert log
open(sys.argv[2], "w").write("\n".join(log) + "\n")
PY
HAND=$(json_get 'sum(h["readings"] for h in d["by_hand"])')
expect_exit 0 "probe-log of a plan with a circle" -- "$MTCAL" probe-log -m "$V" --plan "$tmp/pc-plan.csv" --log "$tmp/pc-log.txt" \
  --out "$tmp/pc-meas.csv" --json
[ "$(json_get 'd["by_hand_records"]')" = "$HAND" ] && [ "$HAND" -gt 0 ] && ! grep -q ',ballbar,' "$tmp/pc-meas.csv" && ok \
  || bad "probe-log: the plan's ballbar and laser records counted as by hand, not in its --out"
expect_error "ballbar radius beyond the travel" "a circle of radius 400 mm needs" -- "$MTCAL" plan -m "$M3" --estimate EC0Y \
  --ballbar 400 --poses 1
expect_error "unknown laser axis" "(X, Y, Z), found 'Q'" -- "$MTCAL" plan -m "$M3" --estimate EC0Y --laser X,Q --poses 1

# probe-log: a log with a bad line, located; nothing written.
printf '1 2 3 0 0 0 0 0 0\nx 2 3 0 0 0 0 0 0\n' >"$tmp/bad.txt"
expect_error "bad log line" "bad.txt:2" -- "$MTCAL" probe-log -m "$H" --plan "$tmp/plan.csv" --log "$tmp/bad.txt" --out "$tmp/no4.csv"
[ ! -e "$tmp/no4.csv" ] && ok || bad "nothing written for a bad log"
printf '1 2 3 0 0 0 0 0 0\n' >"$tmp/short.txt"
expect_error "short log" "contacts" -- "$MTCAL" probe-log -m "$H" --plan "$tmp/plan.csv" --log "$tmp/short.txt" --out "$tmp/no5.csv"

# plan --locate, probe-log --locate: the first coarse touch (docs/planning.md, "Locating the sphere").
# The loop's RRTTT, its program in tool-point coordinates; the log a perfect machine writes is
# computed here from the program's text: each G38.2 move trips where the tool point first comes
# (ball + tip) / 2 from the real centre.
L="$EXAMPLES/loop/rrttt-nominal.yaml"
printf 'indexation,A,C,feature,kind,x,y,z,nx,ny,nz,dirX,dirY,dirZ\n1,0,0,S,ball,121,-79,60.5,,,,,,\n' >"$tmp/rough.csv"
expect_exit 0 "plan --locate" -- "$MTCAL" plan -m "$L" --artefact "$tmp/rough.csv" --locate --locate-within 3 --approach 0.5 \
  --program-coordinates tool-point --out "$tmp/locate-plan.csv" --gcode "$tmp/locate.ngc" --json
python3 - "$tmp/out" <<'PY' && ok || bad "plan --locate JSON: locate{balls touches within_mm at} out gcode"
import json, sys
d = json.load(open(sys.argv[1]))
l = d["locate"]
assert l["balls"] == [{"id": "S", "rough": [121, -79, 60.5]}] and l["touches"] == 9 and l["within_mm"] == 3, l
assert "A=0" in l["at"] and "C=0" in l["at"], l
PY
[ "$(grep -c '^G38.2 ' "$tmp/locate.ngc")" = 9 ] && grep -q '(PROBEOPEN ' "$tmp/locate.ngc" && ok || bad "the locating program probes 9 times and logs"
cat >"$tmp/trip.py" <<'PY'
import math, re, sys
centre = [float(v) for v in sys.argv[2].split(",")]
rho = (float(sys.argv[3]) + 3.0) / 2
pos = {}
for line in open(sys.argv[1]):
    if not line.startswith("G"):
        continue
    w = {m.group(1): float(m.group(2)) for m in re.finditer(r"([XYZAC])(-?[0-9.]+)", line)}
    if line.startswith("G38.2"):
        a = [pos[k] for k in "XYZ"]
        d = [w[k] - pos[k] for k in "XYZ"]
        f = [ai - ci for ai, ci in zip(a, centre)]
        A, B, C = sum(x * x for x in d), 2 * sum(x * y for x, y in zip(f, d)), sum(x * x for x in f) - rho * rho
        if B * B - 4 * A * C < 0:
            break  # no contact: LinuxCNC stops the program
        t = (-B - math.sqrt(B * B - 4 * A * C)) / (2 * A)
        if not 0 <= t <= 1:
            break
        p = [ai + t * di for ai, di in zip(a, d)]
        print("%.6f %.6f %.6f %.6f 0 %.6f 0 0 0" % (p[0], p[1], p[2], w.get("A", pos.get("A", 0)), w.get("C", pos.get("C", 0))))
    pos.update(w)
PY
python3 "$tmp/trip.py" "$tmp/locate.ngc" 120.035,-80.042,60.021 25.4 >"$tmp/locate-log.txt"
[ "$(wc -l <"$tmp/locate-log.txt")" = 9 ] && ok || bad "the simulated locating log has 9 contacts"
expect_exit 0 "probe-log --locate" -- "$MTCAL" probe-log -m "$L" --locate --plan "$tmp/locate-plan.csv" --log "$tmp/locate-log.txt" \
  --approach 0.5 --program-coordinates tool-point --out "$tmp/located.csv" --json
python3 - "$tmp/out" <<'PY' && ok || bad "probe-log --locate: the sphere's centre and diameter (to the log's decimals)"
import json, math, sys
d = json.load(open(sys.argv[1]))
s = d["spheres"][0]
assert s["id"] == "S" and s["contacts"] == 9 and not s["beyond"], s
assert max(abs(a - b) for a, b in zip(s["centre"], [120.035, -80.042, 60.021])) < 1e-5, s["centre"]
assert abs(s["ball_diameter_mm"] - 25.4) < 1e-5 and s["rms_um"] < 0.01, s
assert abs(s["offset_mm"] - math.dist(s["centre"], [121, -79, 60.5])) < 1e-9, s
PY
grep -q '^1,0,0,S,ball,120.03' "$tmp/located.csv" && ok || bad "located.csv: the ball at its located centre"
expect_exit 0 "plan --artefact located" -- "$MTCAL" plan -m "$L" --artefact "$tmp/located.csv" --estimate EX0C,EY0C --poses 4 \
  --rotary-step-deg 45 --out "$tmp/located-plan.csv"
python3 - "$tmp/located-plan.csv" <<'PY' && ok || bad "the plan puts the ball where it was located"
import csv, sys
rows = [r for r in csv.DictReader(l for l in open(sys.argv[1]) if not l.startswith("#"))]
assert rows and all(max(abs(float(r[k]) - v) for k, v in zip("xyz", (120.035, -80.042, 60.021))) < 1e-5 for r in rows), rows[0]
PY
# Bad inputs, nothing written: a log cut short (the probe did not trip), a sphere of another diameter,
# a sphere beyond reach, the design options with --locate, a distance over the limit.
head -n 4 "$tmp/locate-log.txt" >"$tmp/cut-log.txt"
expect_error "locate: log cut short" "contact 5 is missing (touch 5 of 9 locating ball S)" -- "$MTCAL" probe-log -m "$L" --locate \
  --plan "$tmp/locate-plan.csv" --log "$tmp/cut-log.txt" --approach 0.5 --program-coordinates tool-point --out "$tmp/no-l1.csv"
[ ! -e "$tmp/no-l1.csv" ] && ok || bad "nothing written for a short locating log"
python3 "$tmp/trip.py" "$tmp/locate.ngc" 120.035,-80.042,60.021 20 >"$tmp/small-log.txt"
expect_error "locate: another diameter" "no sphere of the ball's diameter found" -- "$MTCAL" probe-log -m "$L" --locate \
  --plan "$tmp/locate-plan.csv" --log "$tmp/small-log.txt" --approach 0.5 --program-coordinates tool-point --out "$tmp/no-l2.csv"
[ ! -e "$tmp/no-l2.csv" ] && ok || bad "nothing written when no sphere is found"
python3 "$tmp/trip.py" "$tmp/locate.ngc" 127,-79,60.5 25.4 >"$tmp/far-log.txt"
expect_error "locate: sphere not within reach" "no sphere found within 3 mm" -- "$MTCAL" probe-log -m "$L" --locate \
  --plan "$tmp/locate-plan.csv" --log "$tmp/far-log.txt" --approach 0.5 --program-coordinates tool-point --out "$tmp/no-l3.csv"
expect_error "locate with --estimate" "excludes" -- "$MTCAL" plan -m "$L" --artefact "$tmp/rough.csv" --locate --estimate EX0C \
  --out "$tmp/no-l4.csv" --gcode "$tmp/no-l4.ngc"
expect_error "locate too far" "--locate-within" -- "$MTCAL" plan -m "$L" --artefact "$tmp/rough.csv" --locate --locate-within 8 \
  --out "$tmp/no-l5.csv" --gcode "$tmp/no-l5.ngc"
[ ! -e "$tmp/no-l5.csv" ] && [ ! -e "$tmp/no-l5.ngc" ] && ok || bad "nothing written for a locating distance over the limit"
expect_error "locate without --gcode" "--gcode" -- "$MTCAL" plan -m "$L" --artefact "$tmp/rough.csv" --locate --out "$tmp/no-l6.csv"

summary_and_exit
