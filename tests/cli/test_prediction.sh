#!/usr/bin/env bash
# Command-line tests of regress, predict, separate (Yaqoob 2017): exit codes, one-line errors,
# JSON keys, values against the thesis' tables, no partial outputs.
# Needs MTCAL (the binary) and EXAMPLES (the examples folder). Prints "N passed, N failed".
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
P="$EXAMPLES/prediction"
M="$P/yaqoob2017-model.yaml"

for c in regress predict separate; do
  expect_exit 0 "$c --help" -- "$MTCAL" $c --help
done

# regress: synthetic exp_approach data (eq. 5.6's parameters) are recovered; JSON keys.
python3 -c "
import math
print('t,e')
for i in range(12):
    t = i * 10.0
    print(f'{t},{0.0333374 - 0.0333374*math.exp(-0.0188882*t):.12g}')" >"$tmp/exp.csv"
expect_exit 0 "regress --json" -- "$MTCAL" regress "$tmp/exp.csv" --x t --y e --models "exp_approach,polynomial(2)" --json
[ "$(json_get "sorted(d.keys())")" = "['best_backward', 'best_loocv', 'file', 'fits', 'n', 'skipped', 'x', 'y']" ] && ok || bad "regress JSON keys: $(head -c 300 "$tmp/out")"
python3 -c "
import json; d=json.load(open('$tmp/out'))
f=[f for f in d['fits'] if f['model']=='exp_approach'][0]
assert abs(f['parameters']['c']['value']-0.0188882) < 1e-8, f
assert d['best_backward']=='exp_approach' and d['best_loocv']=='exp_approach', d
assert sorted(f.keys())==['aicc','backward','dof','form','identifiable','loocv_rmse','model','parameters','r_squared','rss','sigma'], f.keys()
" && ok || bad "regress recovers eq. 5.6"
expect_exit 0 "regress Table 5.8 with report" -- "$MTCAL" regress "$P/yaqoob2017-table5_8.csv" --x t --y e_splz --report "$tmp/r.html"
[ -s "$tmp/r.html" ] && grep -q "backward" "$tmp/r.html" && ok || bad "regress report written"
expect_error "regress unknown model" "found 'cubic'" -- "$MTCAL" regress "$tmp/exp.csv" --x t --y e --models cubic
expect_error "regress unknown column" "no column 'q'" -- "$MTCAL" regress "$tmp/exp.csv" --x q --y e
expect_error "regress report over the data" "" -- "$MTCAL" regress "$tmp/exp.csv" --x t --y e --report "$tmp/exp.csv"

# predict: Table 5.7 values at W2 step 1 (e_pos_x 0.006423335 at 29 mm; e_pf_x is half the
# two-wall 0.000191988), CSV and compensation outputs.
expect_exit 0 "predict --json" -- "$MTCAL" predict --model "$M" --points "$P/yaqoob2017-w2-points.csv" --json
[ "$(json_get "sorted(d.keys())")" = "['components', 'model', 'points', 'source', 'warnings']" ] && ok || bad "predict JSON keys"
python3 -c "
import json; d=json.load(open('$tmp/out')); p=d['points'][0]
assert abs(p['components']['e_pos_x']-0.006423335) < 1e-9, p
assert abs(p['components']['e_pf_x']-0.000191988/2) < 1e-9, p
assert abs(p['components']['e_pt_y']-0.001950791) < 1e-9, p
s=sum(v for k,v in p['components'].items() if [c for c in d['components'] if c['name']==k][0]['axis']=='x')
assert abs(s-p['ex']) < 1e-12
" && ok || bad "predict Table 5.7 values and sums: $(head -c 400 "$tmp/out")"
expect_exit 0 "predict --out --compensation" -- "$MTCAL" predict --model "$M" --points "$P/yaqoob2017-w2-points.csv" --out "$tmp/p.csv" --compensation "$tmp/c.csv" --report "$tmp/p.html"
[ "$(head -1 "$tmp/c.csv")" = "step,offset_x,offset_y,offset_z" ] && [ "$(wc -l <"$tmp/c.csv")" -eq 5 ] && ok || bad "compensation CSV"
python3 -c "
import csv; r=list(csv.DictReader(open('$tmp/p.csv'))); c=list(csv.DictReader(open('$tmp/c.csv')))
assert len(r)==4 and 'e_ctrl_x' in r[0] and 'ez' in r[0]
assert abs(float(c[1]['offset_x']) + float(r[1]['ex'])) < 1e-8
" && ok || bad "points CSV and compensation = -error"
# Outside the validity range: a warning, or an error with --strict.
printf 't,S,F,dx,dy,dz,h_tt,h_spd\n150,3500,200,29,29,9,10,9\n' >"$tmp/late.csv"
expect_exit 0 "predict extrapolates with a warning" -- "$MTCAL" predict --model "$M" --points "$tmp/late.csv"
grep -q "warning: line 2: e_pt_x: t = 150 is outside the validity range" "$tmp/out" && ok || bad "validity warning: $(cat "$tmp/out")"
expect_error "predict --strict" "outside the validity range" -- "$MTCAL" predict --model "$M" --points "$tmp/late.csv" --strict
printf 't,S,dx,dy,dz,h_tt,h_spd\n10,3500,29,29,9,10,9\n' >"$tmp/nof.csv"
expect_error "predict missing column" "missing column 'F' needed by" -- "$MTCAL" predict --model "$M" --points "$tmp/nof.csv"
expect_exit 0 "predict --set supplies a constant" -- "$MTCAL" predict --model "$M" --points "$tmp/nof.csv" --set F=200
sed 's/form: saturation/form: hyperbola/' "$M" >"$tmp/bad.yaml"
expect_error "unknown model form" "unknown model form 'hyperbola'" -- "$MTCAL" predict --model "$tmp/bad.yaml" --points "$P/yaqoob2017-w2-points.csv"
grep -q "bad.yaml:[0-9]" "$tmp/err" && ok || bad "model error names file:line: $(cat "$tmp/err")"
rm -f "$tmp/never.csv"
expect_error "no partial output" "missing column" -- "$MTCAL" predict --model "$M" --points "$tmp/nof.csv" --out "$tmp/never.csv"
[ ! -e "$tmp/never.csv" ] && ok || bad "output written despite an error"
# --gcode: a point per move; G-code that moves along X at 200 mm/min for 10 mm takes 0.05 min.
printf 'G21 G90\nG1 X10 F200\nG1 Y10\n' >"$tmp/p.nc"
expect_exit 0 "predict --gcode" -- "$MTCAL" predict --model "$M" --gcode "$tmp/p.nc" --speed 3500 --start-time 30 --set h_tt=10,h_spd=9 --json
python3 -c "
import json; d=json.load(open('$tmp/out')); p=d['points']
assert len(p)==2 and abs(p[0]['input']['t']-30.05)<1e-12 and abs(p[1]['input']['t']-30.1)<1e-12, p
assert p[0]['input']['dx']==10 and p[1]['input']['dy']==10
" && ok || bad "predict --gcode time stamps"
expect_error "predict --gcode needs --speed" "--speed" -- "$MTCAL" predict --model "$M" --gcode "$tmp/p.nc"

# separate position: Table 5.3 step 2 Y = 0.0137833 mm (hand); control with eq. 3.15.
expect_exit 0 "separate position --json" -- "$MTCAL" separate position "$P/yaqoob2017-table5_3.csv" --json
python3 -c "
import json; d=json.load(open('$tmp/out'))
s=[s for s in d['steps'] if s['axis']=='Y' and s['step']==2][0]
assert abs(s['e_pos']-0.0137833333) < 1e-9 and s['count']==6, s
assert set(d['fits'])=={'e_pos_x','e_pos_y','e_pos_z'}
" && ok || bad "separate position values"
expect_exit 0 "separate control" -- "$MTCAL" separate control "$P/yaqoob2017-table5_6.csv" --a W2 --b W5 --json
python3 -c "
import json; d=json.load(open('$tmp/out'))
s=[s for s in d['steps'] if s['axis']=='X' and s['step']==3][0]
h=(79.0570-79.0526)-(0.017652045-0.002923753)-(0.025097789-0.024940679)
assert abs(s['e_ctrl']-h) < 1e-9, s
" && ok || bad "separate control eq. 3.12"
expect_error "separate control W8 has no components" "component is empty" -- "$MTCAL" separate control "$P/yaqoob2017-table5_6.csv" --a W2 --b W8
expect_error "separate bad kind" "KIND" -- "$MTCAL" separate thermal "$P/yaqoob2017-table5_3.csv"

summary_and_exit
