#!/usr/bin/env bash
# Command-line tests of regress, predict, separate (Yaqoob 2017): exit codes, one-line errors,
# JSON keys, values against the thesis' tables, no partial outputs.
# Needs MTCAL (the binary) and EXAMPLES (the examples folder). Prints "N passed, N failed".
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
P="$EXAMPLES/prediction"
M="$P/yaqoob2017-model.yaml"

for c in regress predict separate process-error; do
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
assert sorted(f.keys())==['aicc','backward','dof','form','identifiable','loocv_method','loocv_rmse','model','parameters','r_squared','rss','sigma'], f.keys()
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
# A rapid (G0) cuts nothing: it advances the time at --rapid-feed and gives no point. G0 to
# (5, 5) is sqrt(50) mm at 10000 mm/min = 0.000707107 min, then G1 X10 at 200 mm/min 0.025 min:
# one point at t = 30.025707107 with F = 200; --strict passes (no point at F = 10000).
printf 'G21 G90\nG0 X5 Y5\nG1 X10 F200\n' >"$tmp/g0.nc"
expect_exit 0 "predict --gcode with a G0" -- "$MTCAL" predict --model "$M" --gcode "$tmp/g0.nc" --speed 3500 --start-time 30 --set h_tt=10,h_spd=9 --strict --json
python3 -c "
import json; d=json.load(open('$tmp/out')); p=d['points']
assert len(p)==1 and p[0]['line']==3, p
assert abs(p[0]['input']['t']-(30+50**0.5/10000+0.025))<1e-12 and p[0]['input']['F']==200, p[0]['input']
assert abs(p[0]['ex']) < 0.05, p[0]['ex']
" && ok || bad "predict --gcode: G0 gives no point: $(head -c 400 "$tmp/out")"
printf 'G21 G90\nG0 X5 Y5\nG0 X10\n' >"$tmp/rapids.nc"
expect_error "predict --gcode with rapids only" "no cutting move" -- "$MTCAL" predict --model "$M" --gcode "$tmp/rapids.nc" --speed 3500 --set h_tt=10,h_spd=9
# Edge inputs: a points file with only a header; a spindle speed <= 0.
printf 't,S,F,dx,dy,dz,h_tt,h_spd\n' >"$tmp/empty.csv"
rm -f "$tmp/never.csv"
expect_error "predict points with only a header" "expected at least one point" -- "$MTCAL" predict --model "$M" --points "$tmp/empty.csv" --compensation "$tmp/never.csv"
[ ! -e "$tmp/never.csv" ] && ok || bad "compensation written for no points"
printf 'step,t,S,F,dx,dy,dz,h_tt,h_spd\n1,10,0,200,29,29,9,10,9\n' >"$tmp/s0.csv"
expect_error "predict S = 0" "expected a spindle speed S > 0" -- "$MTCAL" predict --model "$M" --points "$tmp/s0.csv"
grep -q "s0.csv:2" "$tmp/err" && ok || bad "S = 0 error names file:line: $(cat "$tmp/err")"
# A model file with a parameter outside its form's domain: file, line, key.
sed 's/parameters: {a: 0.0231491, b: 0.0211986, k: 2.86166, x0: 100}/parameters: {a: 0.0231491, b: 0.0211986, k: 2.86166, x0: -100}/' "$M" >"$tmp/x0.yaml"
expect_error "model x0 <= 0" "x0 > 0" -- "$MTCAL" predict --model "$tmp/x0.yaml" --points "$P/yaqoob2017-w2-points.csv"
grep -q "x0.yaml:71: field .components.e_pt_y.stages.1.parameters." "$tmp/err" && ok || bad "x0 error names file:line:key: $(cat "$tmp/err")"

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
# Eq. 3.15 with the model: e_cpr = e_ctrl - e_ctrl_x(2400-100) at W2's nominal, X step 3 (79 mm):
# eq. 5.53 by hand -0.036 + 0.036 / (1 + (79 / 77.1779)^7.60716), the feed ramp at 1.
expect_exit 0 "separate control --model" -- "$MTCAL" separate control "$P/yaqoob2017-table5_6.csv" --a W2 --b W5 --model "$M" --json
python3 -c "
import json, math; d=json.load(open('$tmp/out'))
s=[s for s in d['steps'] if s['axis']=='X' and s['step']==3][0]
nom=79
h=(79.0570-79.0526)-(0.017652045-0.002923753)-(0.025097789-0.024940679)
ctrl=-0.036+0.036/(1+math.exp(7.60716*math.log(nom/77.1779)))
assert abs(s['e_cpr']-(h-ctrl)) < 1e-9, (s, h, ctrl)
assert d['quantity']=='e_cpr' and d['warnings']==[]
" && ok || bad "separate control eq. 3.15 with the model: $(head -c 400 "$tmp/out")"
# The component's scale is applied, as in predict: scale 2 doubles what is subtracted.
python3 -c "
t=open('$M').read().replace('    source: eq. 5.53, 5.55\n', '    source: eq. 5.53, 5.55\n    scale: 2\n'); open('$tmp/scaled.yaml','w').write(t)"
cp "$tmp/out" "$tmp/cpr1.json"
expect_exit 0 "separate control --model scaled" -- "$MTCAL" separate control "$P/yaqoob2017-table5_6.csv" --a W2 --b W5 --model "$tmp/scaled.yaml" --json
python3 -c "
import json; a=json.load(open('$tmp/cpr1.json')); b=json.load(open('$tmp/out'))
sa=[s for s in a['steps'] if s['axis']=='X' and s['step']==3][0]['e_cpr']
sb=[s for s in b['steps'] if s['axis']=='X' and s['step']==3][0]['e_cpr']
import math; ctrl=-0.036+0.036/(1+math.exp(7.60716*math.log(79/77.1779)))
assert abs((sa-sb)-ctrl) < 1e-9, (sa, sb, ctrl)
" && ok || bad "separate control uses the component's scale"
expect_error "separate control W8 has no components" "component is empty" -- "$MTCAL" separate control "$P/yaqoob2017-table5_6.csv" --a W2 --b W8
expect_error "separate bad kind" "KIND" -- "$MTCAL" separate thermal "$P/yaqoob2017-table5_3.csv"

# regress on Table 5.8: stretched_exp and logistic_ln have no interior optimum (an offset power
# law is their limit); said, not hidden. A parameter at its bound has no uncertainty.
expect_exit 0 "regress Table 5.8 --json" -- "$MTCAL" regress "$P/yaqoob2017-table5_8.csv" --x t --y e_splz --json
python3 -c "
import json; d=json.load(open('$tmp/out'))
sk={s['model']: s['reason'] for s in d['skipped']}
assert set(sk)=={'stretched_exp','logistic_ln'}, sk
assert all('no interior optimum' in r and 'offset power law' in r for r in sk.values()), sk
p=[f for f in d['fits'] if f['model']=='polynomial(1)'][0]['parameters']
assert abs(p['c1']['value']-7.34899e-5) < 5e-10 and p['c1']['at_bound'] is False and p['c1']['identified'] is True, p
" && ok || bad "regress Table 5.8 skipped reasons: $(head -c 600 "$tmp/out")"
printf 'x,y\n0,1\n1,1\n2,1\n3,1\n4,1\n' >"$tmp/flat.csv"
expect_exit 0 "regress power at its bound" -- "$MTCAL" regress "$tmp/flat.csv" --x x --y y --models power --json
python3 -c "
import json; d=json.load(open('$tmp/out')); p=d['fits'][0]['parameters']
assert p['b']['at_bound'] is True and p['b']['stddev'] is None, p
assert abs(p['a']['stddev']-(1/12)**0.5) < 1e-5, p
" && ok || bad "regress at bound: $(head -c 400 "$tmp/out")"
expect_exit 0 "regress power at its bound, text" -- "$MTCAL" regress "$tmp/flat.csv" --x x --y y --models power
grep -q "b=1e-09 (at bound)" "$tmp/out" && ok || bad "at bound in the text: $(cat "$tmp/out")"

# process-error: a one-tooth straight end mill in a full slot without edge forces, uniform
# section (flute ratio 1). By hand: fz = 350 / (1 * 3500) = 0.1 mm, Fy = ap fz (Ktc sin^2 phi -
# Krc sin phi cos phi), largest ap fz / 2 (Ktc + sqrt(Ktc^2 + Krc^2)) = 324.924 N; tip deflection
# under it at ap / 2 = 2 mm (DeVor eq. 2.6): F / (6 E I) (2^3 - 40^3 + 3 40^2 (40 - 2)).
PE=(--teeth 1 --helix 0 --diameter 10 --overhang 40 --flute-length 22 --flute-ratio 1 --young 600000 --ae 10 --ap 4 --speed 3500 --ktc 800 --krc 200 --kte 0 --kre 0)
expect_exit 0 "process-error --json" -- "$MTCAL" process-error --feed 350 "${PE[@]}" --json
python3 -c "
import json, math; d=json.load(open('$tmp/out'))
assert sorted(d.keys())==['coefficients','cut','points','tool'], d.keys()
p=d['points'][0]
peak=4*0.1/2*(800+math.hypot(800,200)); I=math.pi*10**4/64
defl=peak/(6*600000*I)*(2**3-40**3+3*40**2*(40-2))
assert abs(p['fz']-0.1) < 1e-15 and abs(p['peak_fy']-peak) < 1e-4*peak, (p, peak)
assert abs(p['e_prog']-defl*p['peak_fy']/peak) < 1e-12 and abs(p['e_prog']-defl) < 1e-4*defl, (p, defl)
" && ok || bad "process-error by hand: $(head -c 600 "$tmp/out")"
# Calibration (eq. 5.49-5.51): without edge forces e_prog is proportional to the feed, e_prog =
# q F with q from the hand deflection above / 350; measured = 0.5 e / (2e-3 + e) (a saturation,
# the form of eq. 5.51) is recovered.
python3 -c "
import math
peak=4*0.1/2*(800+math.hypot(800,200)); I=math.pi*10**4/64
q=peak/(6*600000*I)*(2**3-40**3+3*40**2*(40-2))/350
F=[100,200,400,800,1600]
print(','.join(str(f) for f in F)); print(','.join(repr(0.5*q*f/(2e-3+q*f)) for f in F))" >"$tmp/cal.txt"
expect_exit 0 "process-error calibration" -- "$MTCAL" process-error --feed "$(sed -n 1p "$tmp/cal.txt")" --measured "$(sed -n 2p "$tmp/cal.txt")" --form saturation "${PE[@]}" --json
python3 -c "
import json; d=json.load(open('$tmp/out')); c=d['calibration']
assert c['model']=='saturation' and abs(c['parameters']['a']['value']-0.5) < 1e-4 and abs(c['parameters']['b']['value']-2e-3) < 1e-6, c
assert len(c['measured'])==5
" && ok || bad "process-error calibration: $(head -c 600 "$tmp/out")"
expect_exit 0 "process-error text" -- "$MTCAL" process-error --feed 100,200 
grep -q "e_prog (mm)" "$tmp/out" && ok || bad "process-error text table"
expect_error "process-error measured count" "one measured process error per feed" -- "$MTCAL" process-error --feed 100,200 --measured 0.001
expect_error "process-error bad feed" "comma list of numbers" -- "$MTCAL" process-error --feed 100,abc
expect_error "process-error ae > D" "radial depth" -- "$MTCAL" process-error --feed 100 --ae 20

summary_and_exit
