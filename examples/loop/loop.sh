#!/usr/bin/env bash
# The closed loop on one 5-axis machine in LinuxCNC (docs/workflows.md, "The closed loop"; issue 33):
#
#   plan --locate -> LinuxCNC runs the locating program -> probe-log --locate (the sphere found) ->
#   plan -> LinuxCNC runs the probing program -> probe-log -> identify -> compensate --format
#   linuxcnc-kins -> LinuxCNC restarts with the module -> the same probing program -> probe-log ->
#   identify of what is left -> history diff of before and after -> campaign report
#
# Each step is one mtcal command, or LinuxCNC running what mtcal wrote (lcnc-sim: Debian's LinuxCNC 2.9
# headless, sim configuration, the kinematics module mtcal wrote as KINEMATICS). The machine is a
# simulation: its true errors (TRUTH, drawn by `mtcal errors --draw SEED`) are read only by the
# simulated probe (mtcal linuxcnc-probe) and by the campaign report, which says how close the loop
# came; so is where the sphere really is (SPHERE_TRUE; ROUGH says where it was put by eye, within
# 3 mm). mtcal sees the nominal machine (MACHINE, with PARAMS: the forms of its errors, all zero)
# and what LinuxCNC logs.
#
# Needs: mtcal, Debian's linuxcnc-uspace and linuxcnc-uspace-dev (scripts/install-deps --linuxcnc).
# The module's own step, `sh DIR/build.sh` (halcompile --install into LinuxCNC's module folder: root),
# is run by lcnc-sim, under the lock the LinuxCNC tests share: another LinuxCNC run on a shared
# machine installs its own mtcal_kins into the same folder.
# Usage: [MTCAL=build/apps/mtcal/mtcal] [OUT=loop-out] [SEED=1] examples/loop/loop.sh
# Every input below can be given in the environment. About 4 minutes on a loaded 2-core machine.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
MTCAL=${MTCAL:-mtcal}
MACHINE=${MACHINE:-$here/rrttt-nominal.yaml}                 # what mtcal knows of the machine
ROUGH=${ROUGH:-$here/../plans/rrttt-viprey-sphere.csv}       # where the sphere was put by eye (+-3 mm)
LOCATE_WITHIN=${LOCATE_WITHIN:-3}
ESTIMATE=${ESTIMATE:-EX0C,EY0C,EA0C,EB0C,EY0A,EZ0A,EB0A,EC0A}  # location errors: drawn and estimated
# A motion error drawn as a table (errors --draw-table; empty: none) and the table's values estimated:
# every node but the one at the axis' zero, where the table is zero by construction (a constant
# angle of C there is the sphere's position turned about C: not identifiable from one sphere).
TABLE=${TABLE-ECC}
TABLE_POINTS=${TABLE_POINTS:-5}
TABLE_ESTIMATE=${TABLE_ESTIMATE-ECC.f0,ECC.f1,ECC.f3,ECC.f4}
POSES=${POSES:-12}
# The reading sigma: LinuxCNC sees the probe once a servo period T, so a contact is late by a uniform
# share of F T; a ball centre's largest component is F T sqrt(5/4) / sqrt(12) = 0.645 um at F = 120
# mm/min, T = 1 ms (docs/planning.md, "The trip is quantised by the servo period").
PROBE_FEED=${PROBE_FEED:-120}
# The locating touches need far less (their centre only has to fall well inside APPROACH): 600 mm/min,
# 2.9 um of quantisation, a fifth of the time.
LOCATE_FEED=${LOCATE_FEED:-600}
SIGMA_UM=${SIGMA_UM:-0.645}
APPROACH=${APPROACH:-0.5}
RANDOM_POSES=${RANDOM_POSES:-200}
# The module's commanded travel: compensate chooses the room its corrections need at each end of
# every axis (docs/compensation-linuxcnc-kins.md, "The commanded travel"); RANGE (compensate's
# --range, e.g. X=-350:350,...) overrides it.
RANGE=${RANGE:-}
range=()
[ -n "$RANGE" ] && range=(--range "$RANGE")
SEED=${SEED:-1}
OUT=${OUT:-loop-out}
# The simulation's secret: the machine's true errors (TRUTH: a parameter file; default, drawn with
# SEED, and then PARAMS the same errors at zero; a TRUTH of your own goes with the PARAMS and
# TABLE_ESTIMATE that match it, TABLE_ESTIMATE= for none) and where the sphere really is (ROUGH says
# 120,-80,60: 1.8 mm off).
TRUTH=${TRUTH:-}
PARAMS=${PARAMS:-}
SPHERE_TRUE=${SPHERE_TRUE:-121.2,-78.9,60.7}
SPHERE_DIAMETER=${SPHERE_DIAMETER:-25.4}
STYLUS_DIAMETER=${STYLUS_DIAMETER:-3}

step() { printf '\n== %s\n' "$*" >&2; }
run() { printf '+ %s\n' "$*" >&2; "$@"; }
mkdir -p "$OUT"
store="sqlite:$OUT/history.db"
cycle=(--approach "$APPROACH" --ball-diameter "$SPHERE_DIAMETER" --tip-diameter "$STYLUS_DIAMETER")
estimate=$ESTIMATE${TABLE_ESTIMATE:+,$TABLE_ESTIMATE}

step "0. The simulated machine (simulation only): its true errors, and the probe of it for LinuxCNC's probe input"
# The truth holds only what the estimate can absorb (--draw-only the estimated errors): an error the
# loop does not estimate would bias what it does (tests/linuxcnc/run-loop's poor-fit case shows how).
# The table's truth is a smooth curve (docs/campaign.md); the model mtcal starts from (PARAMS) has
# the same table at zero, so that identify can estimate its values.
if [ -z "$TRUTH" ]; then
  TRUTH=$OUT/truth.yaml
  table=()
  [ -n "$TABLE" ] && table=(--draw-table "$TABLE" --draw-table-points "$TABLE_POINTS")
  PARAMS=$OUT/nominal.yaml
  run "$MTCAL" errors -m "$MACHINE" --draw "$SEED" --draw-only "$ESTIMATE" "${table[@]}" --out "$TRUTH" \
      --out-nominal "$PARAMS" >/dev/null
fi
model=(-m "$MACHINE")
[ -n "$PARAMS" ] && model+=(--params "$PARAMS")
run "$MTCAL" linuxcnc-probe -m "$MACHINE" --params "$TRUTH" --sphere "$SPHERE_TRUE" \
    --sphere-diameter "$SPHERE_DIAMETER" --stylus-diameter "$STYLUS_DIAMETER" --out "$OUT/probe"

step "1. The nominal machine's kinematics module; the sphere found by a first coarse touch; the plan"
# LinuxCNC runs every program of the loop before compensation on the module of the nominal machine:
# the same tool-point world as the compensating module's, so one program serves both.
run "$MTCAL" compensate "${model[@]}" --format linuxcnc-kins "${range[@]}" --out "$OUT/kins-nominal"
# The locating program: 9 touches from the rough position (at the rotary axes' zero); its log fitted
# to a sphere gives the artefact file the plan takes. A sphere not within LOCATE_WITHIN: LinuxCNC
# stops at a touch that finds nothing, probe-log --locate names it and writes nothing, the loop stops.
run "$MTCAL" plan "${model[@]}" --artefact "$ROUGH" --locate --locate-within "$LOCATE_WITHIN" --probe-feed "$LOCATE_FEED" \
    --move-feed 30000 "${cycle[@]}" --program-coordinates tool-point --out "$OUT/locate-plan.csv" --gcode "$OUT/locate.ngc"
lcnc_status=0
run "$here/lcnc-sim" --machine "$MACHINE" --kins "$OUT/kins-nominal" --probe "$OUT/probe" --program "$OUT/locate.ngc" \
    --out "$OUT/locate" || lcnc_status=$?
[ "$lcnc_status" -le 2 ] || exit "$lcnc_status"
locate_status=0
run "$MTCAL" probe-log "${model[@]}" --locate --locate-within "$LOCATE_WITHIN" --plan "$OUT/locate-plan.csv" \
    --log "$OUT/locate/mtcal-contacts.txt" "${cycle[@]}" --program-coordinates tool-point \
    --out "$OUT/located-sphere.csv" || locate_status=$?
[ "$lcnc_status" -eq 0 ] && [ "$locate_status" -eq 0 ] || exit 2
run "$MTCAL" plan "${model[@]}" --artefact "$OUT/located-sphere.csv" --estimate "$estimate" --poses "$POSES" \
    --sigma-um "$SIGMA_UM" --probe-feed "$PROBE_FEED" --move-feed 30000 "${cycle[@]}" \
    --program-coordinates tool-point --out "$OUT/plan.csv" --gcode "$OUT/probe.ngc"

step "2. LinuxCNC on the nominal machine's kinematics runs the probing program"
lcnc_status=0
run "$here/lcnc-sim" --machine "$MACHINE" --kins "$OUT/kins-nominal" --probe "$OUT/probe" --program "$OUT/probe.ngc" \
    --out "$OUT/before" || lcnc_status=$?
[ "$lcnc_status" -le 2 ] || exit "$lcnc_status"

step "3. The contacts LinuxCNC logged, identified"
# A program that LinuxCNC stopped (status 2: a probe that never tripped) leaves a log cut short:
# probe-log names the contact that is missing, writes nothing, and the loop stops (status 2).
if [ "$lcnc_status" -ne 0 ]; then
  run "$MTCAL" probe-log "${model[@]}" --plan "$OUT/plan.csv" --log "$OUT/before/mtcal-contacts.txt" "${cycle[@]}" \
      --program-coordinates tool-point --out "$OUT/measured-before.csv" || true
  exit 2
fi
run "$MTCAL" probe-log "${model[@]}" --plan "$OUT/plan.csv" --log "$OUT/before/mtcal-contacts.txt" "${cycle[@]}" \
    --program-coordinates tool-point --out "$OUT/measured-before.csv"
run "$MTCAL" identify "${model[@]}" --measurements "$OUT/measured-before.csv" --estimate "$estimate" \
    --sigma-um "$SIGMA_UM" --require-fit --out "$OUT/identified.yaml" --json --record="$store" \
    >"$OUT/identify-before.json" 2>"$OUT/identify-before.log" || { cat "$OUT/identify-before.log" >&2; exit 1; }
cat "$OUT/identify-before.log" >&2
first=$(sed -n 's/^mtcal: recorded \([0-9a-f]*\) in .*/\1/p' "$OUT/identify-before.log")

step "4. The compensation: a kinematics module of the identified machine"
run "$MTCAL" compensate "${model[@]}" --params "$OUT/identified.yaml" --format linuxcnc-kins "${range[@]}" \
    --out "$OUT/kins-identified"

step "5. LinuxCNC restarted with the module runs the same probing program, then $RANDOM_POSES random poses"
run "$here/lcnc-sim" --machine "$MACHINE" --kins "$OUT/kins-identified" --probe "$OUT/probe" --program "$OUT/probe.ngc" \
    --out "$OUT/after" --random-poses "$RANDOM_POSES" --seed "$SEED"
run "$MTCAL" probe-log "${model[@]}" --plan "$OUT/plan.csv" --log "$OUT/after/mtcal-contacts.txt" "${cycle[@]}" \
    --program-coordinates tool-point --out "$OUT/measured-after.csv"

step "6. What is left, identified the same way, and the history's diff of before and after"
run "$MTCAL" identify "${model[@]}" --measurements "$OUT/measured-after.csv" --estimate "$estimate" \
    --sigma-um "$SIGMA_UM" --json --record="$store" >"$OUT/identify-after.json" 2>"$OUT/identify-after.log" \
    || { cat "$OUT/identify-after.log" >&2; exit 1; }
cat "$OUT/identify-after.log" >&2
second=$(sed -n 's/^mtcal: recorded \([0-9a-f]*\) in .*/\1/p' "$OUT/identify-after.log")
run "$MTCAL" history diff "$first" "$second" --store "$store" | tee "$OUT/history-diff.txt"
run "$MTCAL" history diff "$first" "$second" --store "$store" --json >"$OUT/history-diff.json"

step "7. The campaign report: before/after at the probed points, identified against the truth, the random poses"
run "$MTCAL" campaign "${model[@]}" --before "$OUT/measured-before.csv" --after "$OUT/measured-after.csv" \
    --identified "$OUT/identify-before.json" --truth "$TRUTH" --poses-before "$OUT/after/poses-nominal.csv" \
    --poses-after "$OUT/after/poses.csv" --noise-um "$SIGMA_UM" --reference mean --report "$OUT/campaign.html"
run "$MTCAL" campaign "${model[@]}" --before "$OUT/measured-before.csv" --after "$OUT/measured-after.csv" \
    --identified "$OUT/identify-before.json" --truth "$TRUTH" --poses-before "$OUT/after/poses-nominal.csv" \
    --poses-after "$OUT/after/poses.csv" --noise-um "$SIGMA_UM" --reference mean --json --record="$store" >"$OUT/campaign.json"
