#!/usr/bin/env bash
# mtcal iso230-2 on the real runs of ../shared/data/iso230-2 against an independent Python
# evaluation of the PRODUCT.md formulas; JSON keys; bad inputs. Needs MTCAL, DATA.
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"

if [ -d "$DATA" ]; then
  for f in "$DATA"/*.dat; do
    "$MTCAL" iso230-2 "$f" --json >"$tmp/out.json" 2>"$tmp/err" || { bad "$f: $(cat "$tmp/err")"; continue; }
    python3 - "$f" "$tmp/out.json" <<'PY' && ok || bad "$f differs from the reference"
import json, re, statistics as st, sys
tg, vals = {}, {}
for line in open(sys.argv[1]):
    m = re.match(r'TGT_DATA\[(\d+)\]=(.*)', line)
    if m:
        tg[int(m[1])] = float(m[2])
        continue
    m = re.match(r'REF_DATA_(FWD|BWD)\[(\d+),(\d+)\]=(.*)', line)
    if m:
        vals.setdefault((m[1], int(m[2])), []).append(float(m[4]))
T = sorted(tg)
up = {i: [v - tg[i] for v in vals[('FWD', i)]] for i in T}   # forward = positive direction
dn = {i: [v - tg[i] for v in vals[('BWD', i)]] for i in T}
mu = {i: st.mean(up[i]) for i in T}                          # over runs, not targets
md = {i: st.mean(dn[i]) for i in T}
su = {i: st.stdev(up[i]) for i in T}
sd = {i: st.stdev(dn[i]) for i in T}
B = {i: mu[i] - md[i] for i in T}
ref = {
    'A_up': max(mu[i] + 2 * su[i] for i in T) - min(mu[i] - 2 * su[i] for i in T),
    'A_down': max(md[i] + 2 * sd[i] for i in T) - min(md[i] - 2 * sd[i] for i in T),
    'A': max(max(mu[i] + 2 * su[i], md[i] + 2 * sd[i]) for i in T) - min(min(mu[i] - 2 * su[i], md[i] - 2 * sd[i]) for i in T),
    'B': max(abs(B[i]) for i in T), 'B_mean': st.mean(B.values()),
    'R': max(max(2 * su[i] + 2 * sd[i] + abs(B[i]), 4 * su[i], 4 * sd[i]) for i in T),   # not R_up
    'R_up': max(4 * su[i] for i in T), 'R_down': max(4 * sd[i] for i in T),
    'E_up': max(mu.values()) - min(mu.values()), 'E_down': max(md.values()) - min(md.values()),
    'E': max(max(mu.values()), max(md.values())) - min(min(mu.values()), min(md.values())),
    'M': max((mu[i] + md[i]) / 2 for i in T) - min((mu[i] + md[i]) / 2 for i in T),
}
got = json.load(open(sys.argv[2]))
keys = [k for k in got if k not in ('unit', 'target_unit', 'runs', 'directions', 'notes', 'metadata', 'warnings', 'targets')]
assert got['notes'] == [] and got['metadata'] == {} and got['warnings'] == [] and got['directions'] == 'both', got
assert keys == ['A', 'A_up', 'A_down', 'B', 'B_mean', 'R', 'R_up', 'R_down', 'E', 'E_up', 'E_down', 'M'], keys
for k, v in ref.items():
    assert abs(got[k] - v) < 1e-12, (k, got[k], v)
assert len(got['targets']) == len(T)
assert sorted(got['targets'][0]) == sorted(['target', 'n_up', 'n_down', 'mean_up', 'mean_down', 'mean', 'B', 's_up', 's_down', 'R_up', 'R_down', 'R'])
for t, i in zip(got['targets'], T):
    assert abs(t['mean_up'] - mu[i]) < 1e-12 and abs(t['s_down'] - sd[i]) < 1e-12
PY
  done
else
  echo "no shared data at $DATA: the real-data checks are skipped"
fi

# CSV form, unit option, report.
printf 'target,run,direction,measured\n0,1,up,1\n0,2,up,3\n0,1,down,-1\n0,2,down,1\n10,1,+,14\n10,2,+,16\n10,1,-,12\n10,2,-,12\n' >"$tmp/p.csv"
"$MTCAL" iso230-2 "$tmp/p.csv" --unit um --json --report "$tmp/r.html" >"$tmp/out.json" 2>"$tmp/err" && ok || bad "csv: $(cat "$tmp/err")"
python3 -c "import json; d=json.load(open('$tmp/out.json')); assert d['unit']=='um' and abs(d['E']-5)<1e-12 and abs(d['B_mean']-2.5)<1e-12, d" && ok || bad "csv values"
grep -q 'Plotly.newPlot' "$tmp/r.html" && ok || bad "report not written"

# Bad inputs: one line on stderr, non-zero exit.
# Tests ISO 230-2 does not define in full: evaluated as far as they define the quantities, with
# notes; undefined quantities are null in JSON and n/a in text.
printf 'target,run,direction,measured\n0,1,up,1\n0,2,up,3\n0,1,down,-1\n10,1,up,14\n10,2,up,16\n10,1,down,12\n10,2,down,12\n' >"$tmp/unequal.csv"
"$MTCAL" iso230-2 "$tmp/unequal.csv" --json >"$tmp/out.json" 2>"$tmp/err" && ok || bad "unequal runs: $(cat "$tmp/err")"
python3 -c "import json; d=json.load(open('$tmp/out.json')); assert d['runs']==1 and d['R'] is None and any('differs' in n for n in d['notes']) and abs(d['B']-3)<1e-12, d" && ok || bad "unequal runs values"
printf 'target,run,direction,measured\n0,1,up,1\n0,2,up,3\n10,1,up,14\n10,2,up,16\n' >"$tmp/oneway.csv"
"$MTCAL" iso230-2 "$tmp/oneway.csv" --json >"$tmp/out.json" 2>"$tmp/err" && ok || bad "unidirectional: $(cat "$tmp/err")"
python3 -c "import json; d=json.load(open('$tmp/out.json')); assert d['directions']=='up' and d['B'] is None and d['M'] is None and abs(d['E_up']-3)<1e-12 and abs(d['R_up']-4*2**0.5)<1e-12, d" && ok || bad "unidirectional values"
printf 'target,run,direction,measured\n0,1,up,1\n0,1,down,3\n10,1,up,14\n10,1,down,16\n' >"$tmp/onerun.csv"
"$MTCAL" iso230-2 "$tmp/onerun.csv" --unit um >"$tmp/out" 2>"$tmp/err" && ok || bad "one run: $(cat "$tmp/err")"
grep -q '^A n/a' "$tmp/out" && grep -q 'ISO 230-2 asks for 5 runs' "$tmp/out" && grep -q '^B 2.0 (mean -2.0)' "$tmp/out" && ok || bad "one run text: $(cat "$tmp/out")"
# .dat files as other tools write them: unknown keys kept with a warning, same figures.
printf 'REF_PV=IOC:m1\nDEC=3\nUNIT=um\nTGT_DATA[1]=0\nTGT_DATA[2]=10\nREF_DATA_FWD[1,1]=1\nREF_DATA_FWD[1,2]=3\nREF_DATA_BWD[1,1]=-1\nREF_DATA_BWD[1,2]=1\nREF_DATA_FWD[2,1]=14\nREF_DATA_FWD[2,2]=16\nREF_DATA_BWD[2,1]=12\nREF_DATA_BWD[2,2]=12\n' >"$tmp/tagged.dat"
"$MTCAL" iso230-2 "$tmp/tagged.dat" --json >"$tmp/out.json" 2>"$tmp/err" && ok || bad "tagged dat: $(cat "$tmp/err")"
grep -q 'warning: .*tagged.dat:1: key REF_PV' "$tmp/err" && ok || bad "tagged dat warning: $(cat "$tmp/err")"
python3 -c "import json; d=json.load(open('$tmp/out.json')); assert d['metadata']=={'REF_PV':'IOC:m1','DEC':'3'} and abs(d['E']-5)<1e-12, d" && ok || bad "tagged dat values"
printf 'TGT_DATA[1]=0\nREF_DATA_FWD[1,1]=oops\n' >"$tmp/bad.dat"
expect_error "bad dat value" "bad.dat:2" -- "$MTCAL" iso230-2 "$tmp/bad.dat"
expect_error "missing file" "cannot open" -- "$MTCAL" iso230-2 "$tmp/none.csv"
expect_error "report to a directory" "directory" -- "$MTCAL" iso230-2 "$tmp/p.csv" --report "$tmp"

summary_and_exit
