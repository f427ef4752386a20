#!/usr/bin/env bash
# Issue 29: rough edges a new user and an outside test battery found, one check (or a few) per
# item, each of which failed before the fix: names that are not UTF-8 in JSON, refusals naming the
# option that caused them, exact unit reading, LinuxCNC's "tool not found" message. (--report-png
# making its folder: tests/report/test_static_copies.sh; the ISO 230-2 labels: browser_check.mjs.)
# Needs MTCAL, EXAMPLES (examples/). Prints "N passed, N failed".
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
M3="$EXAMPLES/machines/vmc-3axis.yaml"
X="$EXAMPLES/data/iso230-2-x-axis.csv"
export MTCAL_CONFIG="$tmp/no-config.yaml" MTCAL_HISTORY=""
cd "$tmp" || exit 1
fffd=$'\xef\xbf\xbd'

# --- 1. Text that is not UTF-8 reaches JSON as U+FFFD (docs/reliability.md, "Text in JSON") ------
out=$'out\377.csv' rep=$'rep\377.html'
for cmd in eval volumetric; do
  expect_exit 0 "$cmd non-UTF-8 names --json" -- "$MTCAL" $cmd -m "$M3" --grid X=0:10:3,Y=0,Z=-100 \
    --out "$out" --report "$rep" --json
  [ -s "$out" ] && [ -s "$rep" ] && ok || bad "$cmd: the files with their own names were not written: $(ls)"
  [ "$(json_get "d['out']")" = "out$fffd.csv" ] && [ "$(json_get "d['report']")" = "rep$fffd.html" ] && ok ||
    bad "$cmd: JSON names: $(head -c 300 "$tmp/out")"
  rm -f "$out" "$rep"
done
# A machine name and metadata from files written in Latin-1, and a --meta value.
sed 's/^name: .*/name: "Fr\xe4se 800"/' "$M3" >latin1.yaml
expect_exit 0 "machine name in Latin-1" -- "$MTCAL" volumetric -m latin1.yaml --grid X=0:10:3,Y=0,Z=-100 --json
[ "$(json_get "d['machine']")" = "Fr${fffd}se 800" ] && ok || bad "machine name: $(head -c 300 "$tmp/out")"
expect_exit 0 "--meta in Latin-1" -- "$MTCAL" iso230-2 "$X" --meta $'operator=J\xe9r\xf4me' --json
[ "$(json_get "d['metadata']['operator']")" = "J${fffd}r${fffd}me" ] && ok || bad "--meta: $(head -c 300 "$tmp/out")"
# History: the record holds what its JSON holds; the export is JSON lines any parser reads.
expect_exit 0 "--record Latin-1" -- "$MTCAL" iso230-2 "$X" --meta $'machine=Fr\xe4se' --meta date=2026-11-01 \
  --meta $'operator=J\xe9r\xf4me' --record="$tmp/h.db"
expect_exit 0 "history export" -- "$MTCAL" history export --store "$tmp/h.db" --out export.jsonl
python3 -c "
import json, sys
recs = [json.loads(l) for l in open('export.jsonl', encoding='utf-8') if l.strip()]
r = [x for x in recs if 'machine_name' in x or 'machine' in x][0]
assert 'Fr\ufffdse' in json.dumps(r, ensure_ascii=False), r
" && ok || bad "history export: $(head -c 400 "$tmp/out")"
expect_error "event note not UTF-8" "field 'note': expected UTF-8 text" -- "$MTCAL" history event add \
  --store "$tmp/h.db" --machine VMC --date 2026-11-20 --kind repair --note $'new ball screw \xff'

# --- 2. A refusal caused by an option names it ---------------------------------------------------
# The long block first: a block before it would be simulated at this step (a 700 mm rapid is 7e8
# points, 45 s) before the refusal.
printf 'G21 G90\nG1 X-400 Y-250 Z-500 F1000\nG0 X400 Y250 Z0\nM30\n' >long.nc
expect_error "toolpath --step" "(--step, --angle-step)" -- "$MTCAL" toolpath -m "$M3" --gcode long.nc --step 5e-7
grep -qF "long.nc:2: this block would need" "$tmp/err" && ok || bad "located in the block: $(cat "$tmp/err")"
expect_error "compensate --points" "expected at most 256 positions per table (the controller's limit), found 300 (--points)" \
  -- "$MTCAL" compensate -m "$M3" --format linuxcnc --points 300 --out comp
[ ! -e comp ] && ok || bad "comp written"

# --- 3. A decimal unit reads exactly: 20urad is 2e-5, bit for bit ---------------------------------
"$MTCAL" eval -m "$M3" --at X=100,Y=200,Z=-100 --set EC0Y=20urad --json >a.json 2>&1
"$MTCAL" eval -m "$M3" --at X=100,Y=200,Z=-100 --set EC0Y=2e-5 --json >b.json 2>&1
cmp -s a.json b.json && ok || bad "--set EC0Y=20urad and 2e-5 differ: $(diff a.json b.json | head -5)"
"$MTCAL" eval -m "$M3" --at X=100,Y=200,Z=-100 --set EX0Y=20um --json >a.json 2>&1
"$MTCAL" eval -m "$M3" --at X=100,Y=200,Z=-100 --set EX0Y=0.02 --json >b.json 2>&1
cmp -s a.json b.json && ok || bad "--set EX0Y=20um and 0.02 differ"

# --- 5. LinuxCNC's "tool not found" says what to do ------------------------------------------------
NC=/usr/share/linuxcnc/ncfiles/skeleton.ngc  # T1 M06 G43 H1
SIM=/usr/share/doc/linuxcnc/examples/sample-configs/sim/axis/sim_mm.tbl
if command -v rs274 >/dev/null && [ -f "$NC" ] && [ -f "$SIM" ]; then
  expect_error "tool not found" "Requested tool 1 not found in the tool table" -- "$MTCAL" toolpath -m "$M3" \
    --gcode "$NC" --interpreter rs274 --no-travel-check
  grep -qF "(give the tools with --tool-table FILE in LinuxCNC's format, e.g. its sim configuration's $SIM)" "$tmp/err" &&
    ok || bad "tool table hint: $(cat "$tmp/err")"
  expect_exit 0 "with the sim tool table" -- "$MTCAL" toolpath -m "$M3" --gcode "$NC" --interpreter rs274 \
    --no-travel-check --tool-table "$SIM"
else
  echo "note: LinuxCNC (linuxcnc-uspace) not installed: the tool table message is not checked"
fi

summary_and_exit
