#!/usr/bin/env bash
# The closed loop on one 5-axis machine in LinuxCNC (docs/workflows.md, "The closed loop"; issue 33):
#
#   plan -> LinuxCNC runs the probing program -> probe-log -> identify -> compensate --format
#   linuxcnc-kins -> LinuxCNC restarts with the module -> the same probing program -> probe-log ->
#   identify of what is left -> history diff of before and after
#
# Each step is one mtcal command, or LinuxCNC running what mtcal wrote (lcnc-sim: Debian's LinuxCNC 2.9
# headless, sim configuration, the kinematics module mtcal wrote as KINEMATICS). The machine is a
# simulation: its true errors (TRUTH, drawn by `mtcal errors --draw SEED`) are read only by the
# simulated probe (mtcal linuxcnc-probe) and by the campaign report, which says how close the loop
# came. mtcal sees the nominal machine (MACHINE) and what LinuxCNC logs.
#
# Needs: mtcal, Debian's linuxcnc-uspace and linuxcnc-uspace-dev (scripts/install-deps --linuxcnc).
# The module's own step, `sh DIR/build.sh` (halcompile --install into LinuxCNC's module folder: root),
# is run by lcnc-sim, under the lock the LinuxCNC tests share: another LinuxCNC run on a shared
# machine installs its own mtcal_kins into the same folder.
# Usage: [MTCAL=build/apps/mtcal/mtcal] [OUT=loop-out] [SEED=1] examples/loop/loop.sh
# Every input below can be given in the environment. About 2 minutes on a 2-core machine.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
MTCAL=${MTCAL:-mtcal}
MACHINE=${MACHINE:-$here/rrttt-nominal.yaml}                 # what mtcal knows of the machine
ARTEFACT=${ARTEFACT:-$here/../plans/rrttt-viprey-sphere.csv} # where the plan puts the sphere
ESTIMATE=${ESTIMATE:-EX0C,EY0C,EA0C,EB0C,EY0A,EZ0A,EB0A,EC0A}
POSES=${POSES:-12}
# The reading sigma: LinuxCNC sees the probe once a servo period T, so a contact is late by a uniform
# share of F T; a ball centre's largest component is F T sqrt(5/4) / sqrt(12) = 0.645 um at F = 120
# mm/min, T = 1 ms (docs/planning.md, "The trip is quantised by the servo period").
PROBE_FEED=${PROBE_FEED:-120}
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
# SEED) and where the sphere really is (the plan says 120,-80,60).
TRUTH=${TRUTH:-}
SPHERE_TRUE=${SPHERE_TRUE:-120.035,-80.042,60.021}
SPHERE_DIAMETER=${SPHERE_DIAMETER:-25.4}
STYLUS_DIAMETER=${STYLUS_DIAMETER:-3}

step() { printf '\n== %s\n' "$*" >&2; }
run() { printf '+ %s\n' "$*" >&2; "$@"; }
mkdir -p "$OUT"
store="sqlite:$OUT/history.db"
cycle=(--approach "$APPROACH" --ball-diameter "$SPHERE_DIAMETER" --tip-diameter "$STYLUS_DIAMETER")

step "0. The simulated machine (simulation only): its true errors, and the probe of it for LinuxCNC's probe input"
# The truth holds only what the estimate can absorb (--draw-only the estimated errors): an error the
# loop does not estimate would bias what it does (tests/linuxcnc/run-loop's poor-fit case shows how).
if [ -z "$TRUTH" ]; then
  TRUTH=$OUT/truth.yaml
  run "$MTCAL" errors -m "$MACHINE" --draw "$SEED" --draw-only "$ESTIMATE" --out "$TRUTH" >/dev/null
fi
run "$MTCAL" linuxcnc-probe -m "$MACHINE" --params "$TRUTH" --sphere "$SPHERE_TRUE" \
    --sphere-diameter "$SPHERE_DIAMETER" --stylus-diameter "$STYLUS_DIAMETER" --out "$OUT/probe"

step "1. The plan and its probing program, in the tool-point world of the kinematics module"
run "$MTCAL" plan -m "$MACHINE" --artefact "$ARTEFACT" --estimate "$ESTIMATE" --poses "$POSES" \
    --sigma-um "$SIGMA_UM" --probe-feed "$PROBE_FEED" --move-feed 30000 "${cycle[@]}" \
    --program-coordinates tool-point --out "$OUT/plan.csv" --gcode "$OUT/probe.ngc"

step "2. LinuxCNC on the nominal machine's kinematics runs the probing program"
run "$MTCAL" compensate -m "$MACHINE" --format linuxcnc-kins "${range[@]}" --out "$OUT/kins-nominal"
lcnc_status=0
run "$here/lcnc-sim" --machine "$MACHINE" --kins "$OUT/kins-nominal" --probe "$OUT/probe" --program "$OUT/probe.ngc" \
    --out "$OUT/before" || lcnc_status=$?
[ "$lcnc_status" -le 2 ] || exit "$lcnc_status"

step "3. The contacts LinuxCNC logged, identified"
# A program that LinuxCNC stopped (status 2: a probe that never tripped) leaves a log cut short:
# probe-log names the contact that is missing, writes nothing, and the loop stops (status 2).
if [ "$lcnc_status" -ne 0 ]; then
  run "$MTCAL" probe-log -m "$MACHINE" --plan "$OUT/plan.csv" --log "$OUT/before/mtcal-contacts.txt" "${cycle[@]}" \
      --program-coordinates tool-point --out "$OUT/measured-before.csv" || true
  exit 2
fi
run "$MTCAL" probe-log -m "$MACHINE" --plan "$OUT/plan.csv" --log "$OUT/before/mtcal-contacts.txt" "${cycle[@]}" \
    --program-coordinates tool-point --out "$OUT/measured-before.csv"
run "$MTCAL" identify -m "$MACHINE" --measurements "$OUT/measured-before.csv" --estimate "$ESTIMATE" \
    --sigma-um "$SIGMA_UM" --require-fit --out "$OUT/identified.yaml" --json --record="$store" \
    >"$OUT/identify-before.json" 2>"$OUT/identify-before.log" || { cat "$OUT/identify-before.log" >&2; exit 1; }
cat "$OUT/identify-before.log" >&2
first=$(sed -n 's/^mtcal: recorded \([0-9a-f]*\) in .*/\1/p' "$OUT/identify-before.log")

step "4. The compensation: a kinematics module of the identified machine"
run "$MTCAL" compensate -m "$MACHINE" --params "$OUT/identified.yaml" --format linuxcnc-kins "${range[@]}" \
    --out "$OUT/kins-identified"

step "5. LinuxCNC restarted with the module runs the same probing program, then $RANDOM_POSES random poses"
run "$here/lcnc-sim" --machine "$MACHINE" --kins "$OUT/kins-identified" --probe "$OUT/probe" --program "$OUT/probe.ngc" \
    --out "$OUT/after" --random-poses "$RANDOM_POSES" --seed "$SEED"
run "$MTCAL" probe-log -m "$MACHINE" --plan "$OUT/plan.csv" --log "$OUT/after/mtcal-contacts.txt" "${cycle[@]}" \
    --program-coordinates tool-point --out "$OUT/measured-after.csv"

step "6. What is left, identified the same way, and the history's diff of before and after"
run "$MTCAL" identify -m "$MACHINE" --measurements "$OUT/measured-after.csv" --estimate "$ESTIMATE" \
    --sigma-um "$SIGMA_UM" --json --record="$store" >"$OUT/identify-after.json" 2>"$OUT/identify-after.log" \
    || { cat "$OUT/identify-after.log" >&2; exit 1; }
cat "$OUT/identify-after.log" >&2
second=$(sed -n 's/^mtcal: recorded \([0-9a-f]*\) in .*/\1/p' "$OUT/identify-after.log")
run "$MTCAL" history diff "$first" "$second" --store "$store" | tee "$OUT/history-diff.txt"
run "$MTCAL" history diff "$first" "$second" --store "$store" --json >"$OUT/history-diff.json"

step "7. The campaign report: before/after at the probed points, identified against the truth, the random poses"
run "$MTCAL" campaign -m "$MACHINE" --before "$OUT/measured-before.csv" --after "$OUT/measured-after.csv" \
    --identified "$OUT/identify-before.json" --truth "$TRUTH" --poses-before "$OUT/after/poses-nominal.csv" \
    --poses-after "$OUT/after/poses.csv" --noise-um "$SIGMA_UM" --reference mean --report "$OUT/campaign.html"
run "$MTCAL" campaign -m "$MACHINE" --before "$OUT/measured-before.csv" --after "$OUT/measured-after.csv" \
    --identified "$OUT/identify-before.json" --truth "$TRUTH" --poses-before "$OUT/after/poses-nominal.csv" \
    --poses-after "$OUT/after/poses.csv" --noise-um "$SIGMA_UM" --reference mean --json --record="$store" >"$OUT/campaign.json"
