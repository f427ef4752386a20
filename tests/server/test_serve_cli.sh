#!/usr/bin/env bash
# mtcal serve against the commands it stands for, on the real command and a SQLite store, with
# curl as the client (every call bounded by --max-time): uploads of a ballbar trace and of probe
# contacts are recorded as `mtcal ballbar --record` and `mtcal rotary-axis --record` record them
# (the same content hash); "write compensation" is a zip of exactly the files `mtcal compensate
# --out` writes; the fleet's ranking is `mtcal history rank`'s; intervals per machine; then the
# faults: a server killed with uploads in flight leaves whole records only, and starts again.
# Needs MTCAL, ROOT (the source tree), DATA (an ISO 230-2 .dat of ../shared/data).
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
EX="$ROOT/examples"
store=sqlite:$tmp/shop.db
cli=sqlite:$tmp/cli.db
tol="$EX/acceptance/tolerances.yaml"
curl() { command curl --silent --show-error --max-time 60 "$@"; }

MTCAL_PASSWORD='cli-test-password' "$MTCAL" serve --store "$store" --add-user ada --role admin >/dev/null 2>"$tmp/err" \
  && ok || bad "--add-user: $(cat "$tmp/err")"
# Two ISO 230-2 calibrations of B02 (the same runs, two dates) and one of B03, for the ranking.
for m in "B02 2025-10-20" "B02 2026-04-20" "B03 2026-02-01"; do
  set -- $m
  "$MTCAL" history import "$DATA" --store "$store" --meta "machine=$1" --meta "date=$2" --meta axis=X >/dev/null \
    2>"$tmp/err" || bad "history import: $(cat "$tmp/err")"
done

pid=
start_server() {
  # The log emptied here, before the server's shell opens it: a log left by a server killed before
  # would give its port (CI saw a restart read the dead server's port and then SIGTERM the new one
  # while it was still bash, whose EXIT trap removed $tmp).
  : >"$tmp/serve.log"
  # Reports dated as the commands' below (SOURCE_DATE_EPOCH): a record's report page is byte for byte theirs.
  SOURCE_DATE_EPOCH=1764000000 "$MTCAL" serve --store "$store" --listen 127.0.0.1:0 --tolerance-file "$tol" \
    --interval-days 200 2>"$tmp/serve.log" &
  pid=$!
  port=
  for _ in $(seq 1 150); do
    port=$(sed -n 's|.*://127.0.0.1:\([0-9]*\)/.*|\1|p' "$tmp/serve.log")
    [ -n "$port" ] && break
    sleep 0.1
  done
  [ -n "$port" ] || { bad "the server did not start: $(cat "$tmp/serve.log")"; kill "$pid"; summary_and_exit; exit 1; }
  base="http://127.0.0.1:$port"
}
stop_server() { kill "$pid" 2>/dev/null; wait "$pid" 2>/dev/null; }
start_server

# Log in as a browser does: the login form's token (cookie + field), then the session's token.
jar=$tmp/jar
login_token=$(curl -c "$jar" -b "$jar" "$base/login" | sed -n 's/.*name="csrf" value="\([0-9a-f]*\)".*/\1/p')
curl -c "$jar" -b "$jar" -o /dev/null -d "csrf=$login_token" -d user=ada -d password=cli-test-password "$base/login"
csrf=$(curl -c "$jar" -b "$jar" "$base/fleet" | sed -n 's/.*name="csrf" value="\([0-9a-f]*\)".*/\1/p' | head -1)
[ ${#csrf} = 64 ] && ok || bad "login: no session token"
api() { curl -b "$jar" -H "X-CSRF-Token: $csrf" "$@"; }
hash_of() { "$MTCAL" history list --store "$1" --machine "$2" --json | python3 -c 'import json,sys; print([r["content_hash"] for r in json.load(sys.stdin)["records"]])'; }

# A ballbar trace, evaluated as `mtcal ballbar` evaluates and records it.
api -o "$tmp/bb.json" -w '%{http_code}' -F kind=ballbar -F radius=100 -F plane=XY -F machine=BB1 -F date=2026-01-05 \
  -F operator=cli -F confirm=1 -F "file=@$EX/instruments/xy-ballbar.csv" "$base/api/upload" >"$tmp/code"
[ "$(cat "$tmp/code")" = 200 ] && ok || bad "ballbar upload: $(cat "$tmp/code") $(cat "$tmp/bb.json")"
"$MTCAL" ballbar "$EX/instruments/xy-ballbar.csv" --radius 100 --plane XY --meta machine=BB1 --meta date=2026-01-05 \
  --meta operator=cli --record "$cli" >/dev/null 2>"$tmp/err" || bad "ballbar --record: $(cat "$tmp/err")"
[ "$(hash_of "$store" BB1)" = "$(hash_of "$cli" BB1)" ] && ok \
  || bad "the server's ballbar record differs from the command's: $(hash_of "$store" BB1) vs $(hash_of "$cli" BB1)"

# Probe contacts on the RRTTT example's C table (probe-sim), evaluated as `mtcal rotary-axis`.
"$MTCAL" probe-sim -m "$EX/machines/rrttt-table-table.yaml" --axis C --angles 0:350:36 --sphere 150,-40,80 \
  --out "$tmp/contacts.csv" >/dev/null || bad "probe-sim"
api -o "$tmp/ra.json" -w '%{http_code}' -F kind=rotary-axis -F rotary_axis=C -F sphere_diameter=30 -F stylus_diameter=6 \
  -F machine=RT1 -F date=2026-01-06 -F confirm=1 -F "file=@$tmp/contacts.csv" "$base/api/upload" >"$tmp/code"
[ "$(cat "$tmp/code")" = 200 ] && ok || bad "contacts upload: $(cat "$tmp/code") $(cat "$tmp/ra.json")"
"$MTCAL" rotary-axis --axis C --contacts "$tmp/contacts.csv" --sphere-diameter 30 --stylus-diameter 6 \
  --meta machine=RT1 --meta date=2026-01-06 --record "$cli" >/dev/null 2>"$tmp/err" || bad "rotary-axis --record: $(cat "$tmp/err")"
[ "$(hash_of "$store" RT1)" = "$(hash_of "$cli" RT1)" ] && ok \
  || bad "the server's rotary-axis record differs from the command's: $(hash_of "$store" RT1) vs $(hash_of "$cli" RT1)"
# A trace without --radius, contacts with a wrong kind: 400/415, nothing recorded.
code=$(api -o /dev/null -w '%{http_code}' -F kind=ballbar -F machine=BB2 -F confirm=1 -F "file=@$EX/instruments/xy-ballbar.csv" "$base/api/upload")
[ "$code" = 400 ] && ok || bad "ballbar without radius: $code"
code=$(api -o /dev/null -w '%{http_code}' -F kind=rotary-axis -F rotary_axis=C -F sphere_diameter=30 -F machine=RT2 -F confirm=1 -F "file=@$DATA" "$base/api/upload")
[ "$code" = 415 ] && ok || bad "a .dat as contacts: $code"

# write compensation: the zip holds what `mtcal compensate --out DIR` writes, byte for byte.
api -o "$tmp/comp.zip" -w '%{http_code}' -F "machine_file=@$EX/machines/vmc-3axis.yaml" -F format=linuxcnc \
  "$base/api/compensation" >"$tmp/code"
[ "$(cat "$tmp/code")" = 200 ] && ok || bad "compensation: $(cat "$tmp/code")"
"$MTCAL" compensate -m "$EX/machines/vmc-3axis.yaml" --format linuxcnc --out "$tmp/comp-cli" >/dev/null 2>"$tmp/err" \
  || bad "compensate: $(cat "$tmp/err")"
python3 - "$tmp/comp.zip" "$tmp/comp-cli" <<'PY' && ok || bad "the zip differs from compensate --out"
import os, sys, zipfile
z = zipfile.ZipFile(sys.argv[1])
assert z.testzip() is None
names = sorted(n for n in z.namelist() if not n.endswith('/'))
cli = sorted(os.listdir(sys.argv[2]))
folder = {n.split('/')[0] for n in names}
assert len(folder) == 1, folder
assert [n.split('/', 1)[1] for n in names] == cli, (names, cli)
for n in names:
    assert z.read(n) == open(os.path.join(sys.argv[2], n.split('/', 1)[1]), 'rb').read(), n
PY
code=$(api -o /dev/null -w '%{http_code}' -F "machine_file=@$DATA" -F format=linuxcnc "$base/api/compensation")
[ "$code" = 422 ] && ok || bad "compensation of a file that is no machine: $code"
code=$(api -o /dev/null -w '%{http_code}' -F "machine_file=@$EX/machines/vmc-3axis.yaml" -F format=nonesuch "$base/api/compensation")
[ "$code" = 400 ] && ok || bad "compensation for an unknown controller: $code"

# write compensation from a recorded identification (schema 5's model files): identify --record
# keeps its machine file and prior parameter file in the store; the record's zip holds byte for
# byte what `mtcal compensate -m MACHINE --params PRIOR --params IDENTIFY_OUT --out DIR` writes.
# (The 3-axis mill's ballbar and laser plan: its compensation takes a fraction of the 5-axis one's.)
H="$EX/machines/vmc-3axis.yaml"
EST=EC0Y,EA0Z,EB0Z,EXX.1,EZZ.1
SB=1:2:489.89794855663564
printf 'mtcal_parameters: 1\nerrors:\n  EZY: {unit: um, argument_unit: m, polynomial: [0, 0, -30]}\n' >"$tmp/prior.yaml"
"$MTCAL" simulate -m "$H" --plan "$EX/plans/vmc-ballbar-laser.csv" --noise-um 1 --seed 7 --artefact-error-um 5 \
  --scale-bar $SB --out "$tmp/m1.csv" >/dev/null 2>"$tmp/err" || bad "simulate: $(cat "$tmp/err")"
for run in 1 2; do  # the same files twice: the store keeps each file once
  SOURCE_DATE_EPOCH=1764000000 "$MTCAL" identify -m "$H" --params "$tmp/prior.yaml" --measurements "$tmp/m1.csv" \
    --estimate "$EST" --scale-bar $SB --out "$tmp/id.yaml" --meta machine=HU1 --meta date=2026-02-0$run \
    --report "$tmp/HU1.html" --record "$store" >/dev/null 2>"$tmp/err" || bad "identify --record: $(cat "$tmp/err")"
done
idrec=$("$MTCAL" history list --store "$store" --machine HU1 --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["records"][-1]["id"])')
python3 - "$tmp/shop.db" <<'PY' && ok || bad "model files are not kept once each"
import sqlite3, sys
rows = sqlite3.connect(sys.argv[1]).execute("SELECT kind, COUNT(*) FROM model_files GROUP BY kind ORDER BY kind").fetchall()
# measurements: the ballbar and contacts uploads, identify's measurements
assert rows == [("machine", 1), ("measurements", 3), ("parameters", 1)], rows
PY
# The identification's own report, made from the stored machine, parameter and measurement files.
curl -b "$jar" -o "$tmp/HU1-page.html" "$base/record/report?id=$idrec"
[ -s "$tmp/HU1.html" ] && cmp -s "$tmp/HU1.html" "$tmp/HU1-page.html" && ok \
  || bad "HU1: the record's report differs from identify --report's: $(cmp "$tmp/HU1.html" "$tmp/HU1-page.html" 2>&1 | head -c 300)"
# With --set (a model change the store does not keep): no report, and the page says why.
"$MTCAL" identify -m "$H" --params "$tmp/prior.yaml" --measurements "$tmp/m1.csv" --estimate "$EST" --scale-bar $SB \
  --set EXY.1=1um/m --meta machine=HU2 --meta date=2026-02-03 --record "$store" >/dev/null 2>"$tmp/err" \
  || bad "identify --set --record: $(cat "$tmp/err")"
hu2=$("$MTCAL" history list --store "$store" --machine HU2 --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["records"][-1]["id"])')
code=$(curl -b "$jar" -o "$tmp/hu2.txt" -w '%{http_code}' "$base/record/report?id=$hu2")
[ "$code" = 404 ] && grep -q "depends on --set of its command line, which the store does not keep" "$tmp/hu2.txt" \
  && ok || bad "report of an identify with --set: $code $(cat "$tmp/hu2.txt")"
api -o "$tmp/rec.zip" -w '%{http_code}' -F "record=$idrec" -F format=linuxcnc "$base/api/compensation" >"$tmp/code"
[ "$(cat "$tmp/code")" = 200 ] && ok || bad "compensation of record $idrec: $(cat "$tmp/code") $(head -c 400 "$tmp/rec.zip")"
"$MTCAL" compensate -m "$H" --params "$tmp/prior.yaml" --params "$tmp/id.yaml" --format linuxcnc --out "$tmp/rec-cli" \
  >/dev/null 2>"$tmp/err" || bad "compensate: $(cat "$tmp/err")"
python3 - "$tmp/rec.zip" "$tmp/rec-cli" <<'PY' && ok || bad "the record's zip differs from compensate --out"
import os, sys, zipfile
z = zipfile.ZipFile(sys.argv[1])
names = sorted(n for n in z.namelist() if not n.endswith('/'))
cli = sorted(os.listdir(sys.argv[2]))
assert cli and [n.split('/', 1)[1] for n in names] == cli, (names, cli)
for n in names:
    assert z.read(n) == open(os.path.join(sys.argv[2], n.split('/', 1)[1]), 'rb').read(), n
PY
# Without the identification's parameters (compensate -m MACHINE --params PRIOR) the files differ:
# the comparison above can fail.
"$MTCAL" compensate -m "$H" --params "$tmp/prior.yaml" --format linuxcnc --out "$tmp/prior-cli" >/dev/null 2>&1
! diff -rq "$tmp/rec-cli" "$tmp/prior-cli" >/dev/null && ok || bad "the identification changed no compensation file"
# A record without stored model files (the ballbar upload): 404 naming its input's SHA-256.
bbrec=$("$MTCAL" history list --store "$store" --machine BB1 --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["records"][0]["id"])')
code=$(api -o "$tmp/nofile.json" -w '%{http_code}' -F "record=$bbrec" -F format=linuxcnc "$base/api/compensation")
bbsha=$(sha256sum "$EX/instruments/xy-ballbar.csv" | cut -c1-64)
[ "$code" = 404 ] && grep -q "has no machine file in the store.*$bbsha" "$tmp/nofile.json" && ok \
  || bad "compensation of a record without model files: $code $(cat "$tmp/nofile.json")"
curl -b "$jar" "$base/record?id=$idrec" >"$tmp/rec.html"
grep -q 'id="rec-comp-write"' "$tmp/rec.html" && grep -q 'machine file, held in the store' "$tmp/rec.html" \
  && grep -q 'id="report-link"' "$tmp/rec.html" && ok || bad "the record page lacks the compensation form or the report link"
# history export/import carry the model files: a copy exports the same bytes.
"$MTCAL" history export --store "$store" --out "$tmp/all.jsonl" >/dev/null 2>"$tmp/err" || bad "export: $(cat "$tmp/err")"
grep -c '"type":"model_file"' "$tmp/all.jsonl" | grep -qx 5 && ok || bad "the export lacks the model files"
"$MTCAL" history import "$tmp/all.jsonl" --store "sqlite:$tmp/copy.db" --json >"$tmp/imp.json" 2>"$tmp/err" \
  || bad "import: $(cat "$tmp/err")"
python3 -c 'import json,sys; assert json.load(open(sys.argv[1]))["model_files_added"] == 5' "$tmp/imp.json" && ok \
  || bad "import: $(cat "$tmp/imp.json")"
"$MTCAL" history export --store "sqlite:$tmp/copy.db" --out "$tmp/copy.jsonl" >/dev/null 2>&1
cmp -s "$tmp/all.jsonl" "$tmp/copy.jsonl" && ok || bad "the imported copy exports other bytes"

# Each result's report: `mtcal iso230-2|ballbar|compare|regress|rotary-axis FILE --record --report F`
# keeps the measurements (model file kind measurements), the machine file (rotary-axis --machine) and
# how the command ran; the record's report page is F byte for byte: the .dat of ../shared/data with
# tolerances checked, a laser file whose header fills the report's metadata, a ballbar trace, a
# method comparison's data, a regression's data, probe contacts read on a machine's axis through an
# instrument frame.
declare -A recid
for spec in "R1|iso230-2|$DATA|--tolerance-file $tol" "R2|iso230-2|$EX/instruments/x-axis.rtl|--meta operator=cli" \
  "R3|ballbar|$EX/instruments/xy-ballbar.csv|--radius 100" "R4|compare|$EX/data/mohammed2019-ballbar-vs-samba.csv|" \
  "R5|regress|$EX/prediction/yaqoob2017-table5_8.csv|--x t --y e_splz --models exp_approach,polynomial(2)" \
  "R6|rotary-axis --contacts|$tmp/contacts.csv|--axis C --sphere-diameter 30 --stylus-diameter 6 --machine $EX/machines/rrttt-table-table.yaml --frame 0.01,0,0,0,0,0.5 --method lsq"; do
  IFS='|' read -r m cmd f args <<<"$spec"
  # shellcheck disable=SC2086 # args: the command's options, split into words
  SOURCE_DATE_EPOCH=1764000000 "$MTCAL" $cmd "$f" $args --meta machine=$m --meta date=2026-03-01 \
    --meta axis=X --report "$tmp/$m.html" --record "$store" >/dev/null 2>"$tmp/err" || bad "$cmd --record: $(cat "$tmp/err")"
  id=$("$MTCAL" history list --store "$store" --machine $m --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["records"][-1]["id"])')
  curl -b "$jar" -D "$tmp/$m.head" -o "$tmp/$m-page.html" "$base/record/report?id=$id"
  [ -s "$tmp/$m.html" ] && cmp -s "$tmp/$m.html" "$tmp/$m-page.html" && ok \
    || bad "$m: the record's report differs from $cmd --report's: $(cmp "$tmp/$m.html" "$tmp/$m-page.html" 2>&1 | head -c 300)"
  grep -qi "^content-security-policy: default-src 'none'; script-src 'unsafe-inline'" "$tmp/$m.head" && ok \
    || bad "$m: the report is not served with the reports' CSP: $(cat "$tmp/$m.head")"
  curl -b "$jar" "$base/record?id=$id" | grep -q 'id="report-link"' && ok || bad "$m: the record page does not link its report"
  recid[$m]=$id
done
grep -q 'class="verdict' "$tmp/R1.html" && ok || bad "R1's report shows no verdict"
# A store without a record's file (removed by hand): no report, and the page names the file: R4's
# data (a measurement file), R6's machine file.
cmpsha=$(sha256sum "$EX/data/mohammed2019-ballbar-vs-samba.csv" | cut -c1-64)
rtsha=$(sha256sum "$EX/machines/rrttt-table-table.yaml" | cut -c1-64)
python3 -c 'import sqlite3,sys; c=sqlite3.connect(sys.argv[1]); c.execute("DELETE FROM model_files WHERE sha256 IN (?,?)", sys.argv[2:]); c.commit()' \
  "$tmp/shop.db" "$cmpsha" "$rtsha"
code=$(curl -b "$jar" -o "$tmp/nodata.txt" -w '%{http_code}' "$base/record/report?id=${recid[R4]}")
[ "$code" = 404 ] && grep -q "does not hold the measurement file $EX/data/mohammed2019-ballbar-vs-samba.csv (SHA-256 $cmpsha)" "$tmp/nodata.txt" \
  && ok || bad "report of a record whose data file the store lacks: $code $(cat "$tmp/nodata.txt")"
code=$(curl -b "$jar" -o "$tmp/nomachine.txt" -w '%{http_code}' "$base/record/report?id=${recid[R6]}")
[ "$code" = 404 ] && grep -q "does not hold the machine file $EX/machines/rrttt-table-table.yaml (SHA-256 $rtsha)" "$tmp/nomachine.txt" \
  && ok || bad "report of a record whose machine file the store lacks: $code $(cat "$tmp/nomachine.txt")"
curl -b "$jar" "$base/record?id=${recid[R6]}" | grep -q "does not hold the machine file" && ok \
  || bad "the record page of R6 does not say which file its report lacks"
# Uploads keep their files too: the report of `mtcal iso230-2 NAME --meta ...` (ballbar: `mtcal ballbar
# NAME --radius R --plane P --meta ...`, the upload of BB1 above).
api -o "$tmp/up.json" -F machine=U1 -F date=2026-03-02 -F axis=X -F confirm=1 -F "file=@$DATA" "$base/api/upload"
upid=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["record"])' "$tmp/up.json")
code=$(curl -b "$jar" -o "$tmp/up.html" -w '%{http_code}' "$base/record/report?id=$upid")
[ "$code" = 200 ] && grep -q "mtcal iso230-2 $(basename "$DATA") --meta axis=X --meta date=2026-03-02 --meta machine=U1" "$tmp/up.html" \
  && ok || bad "report of an uploaded record: $code $(head -c 300 "$tmp/up.html")"
rarec=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["record"])' "$tmp/ra.json")
code=$(curl -b "$jar" -o "$tmp/raup.html" -w '%{http_code}' "$base/record/report?id=$rarec")
[ "$code" = 200 ] && grep -q "mtcal rotary-axis --axis C --contacts contacts.csv --sphere-diameter 30 --stylus-diameter 6 --meta date=2026-01-06" "$tmp/raup.html" \
  && ok || bad "report of an uploaded rotary-axis record: $code $(head -c 300 "$tmp/raup.html")"
code=$(curl -b "$jar" -o "$tmp/bbup.html" -w '%{http_code}' "$base/record/report?id=$bbrec")
[ "$code" = 200 ] && grep -q "mtcal ballbar xy-ballbar.csv --radius 100 --plane XY --meta date=2026-01-05" "$tmp/bbup.html" \
  && ok || bad "report of an uploaded ballbar record: $code $(head -c 300 "$tmp/bbup.html")"
# A record made without (history import, as before schema version 6): 404 saying so (its runs are
# held by now, recorded by R1 above: the record still does not say how they were evaluated).
b02=$("$MTCAL" history list --store "$store" --machine B02 --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["records"][0]["id"])')
datasha=$(sha256sum "$DATA" | cut -c1-64)
code=$(curl -b "$jar" -o "$tmp/norep.txt" -w '%{http_code}' "$base/record/report?id=$b02")
[ "$code" = 404 ] && grep -q "does not say how its command ran" "$tmp/norep.txt" && ok || bad "report of an imported record: $code $(cat "$tmp/norep.txt")"
curl -b "$jar" "$base/record?id=$b02" >"$tmp/b02.html"
grep -q 'id="report-why"' "$tmp/b02.html" && grep -q "$datasha" "$tmp/b02.html" && ok \
  || bad "the record page of an imported record does not say why there is no report"

# The fleet's ranking is history rank's (same tolerance file).
api "$base/api/fleet" >"$tmp/fleet.json"
"$MTCAL" history rank --store "$store" --tolerance-file "$tol" --json >"$tmp/rank.json" 2>"$tmp/err" || bad "history rank: $(cat "$tmp/err")"
python3 - "$tmp/fleet.json" "$tmp/rank.json" <<'PY' && ok || bad "the fleet's ranking differs from history rank's"
import json, sys
fleet = json.load(open(sys.argv[1])); rank = json.load(open(sys.argv[2]))
assert fleet["ranked"], fleet
by = {m["machine"]: m["rank"] for m in fleet["machines"] if m["rank"] is not None}
assert len(rank["machines"]) >= 2, rank
assert sorted(by) == sorted(m["machine"] for m in rank["machines"]), (sorted(by), rank["machines"])
for m in rank["machines"]:
    f = by[m["machine"]]
    for k in ("rank", "utilisation", "years_to_limit", "outside", "quantities"):
        assert f[k] == m[k], (m["machine"], k, f[k], m[k])
PY
# B02: the same runs twice, no drift; the page shows the columns.
curl -b "$jar" "$base/fleet" >"$tmp/fleet.html"
grep -q 'Tolerance used (%)' "$tmp/fleet.html" && grep -q 'Out of tolerance' "$tmp/fleet.html" && ok || bad "fleet page lacks the rank columns"

# Intervals: B03 (2026-02-01) with 30 days is overdue; with the default 200 days B02's 2026-04-20 is
# overdue only from 2026-11-06 on, so the check compares with the age the server reports.
code=$(api -o /dev/null -w '%{http_code}' -d machine=B03 -d days=30 "$base/api/intervals")
[ "$code" = 200 ] && ok || bad "set interval: $code"
api "$base/api/fleet" >"$tmp/fleet.json"
python3 - "$tmp/fleet.json" <<'PY' && ok || bad "intervals in the fleet: $(cat "$tmp/fleet.json" | head -c 600)"
import json, sys
f = {m["machine"]: m for m in json.load(open(sys.argv[1]))["machines"]}
b3, b2 = f["B03"], f["B02"]
assert b3["interval_days"] == 30 and b3["interval_own"] and b3["overdue"] == (b3["calibrations"][0]["age_days"] > 30)
assert b2["interval_days"] == 200 and not b2["interval_own"]
assert b2["overdue"] == (b2["calibrations"][0]["age_days"] > 200)
PY
"$MTCAL" history list --store "$store" --json >/dev/null  # the store is readable while served

# The server keeps the fleet between requests: writes by other programs on the same store (a
# command's --record, history import) show on the next fleet page, JSON and HTML.
curl -b "$jar" -o /dev/null "$base/fleet"
"$MTCAL" ballbar "$EX/instruments/xy-ballbar.csv" --radius 100 --plane XY --meta machine=CLI1 --meta date=2026-01-07 \
  --record "$store" >/dev/null 2>"$tmp/err" || bad "ballbar --record into the served store: $(cat "$tmp/err")"
"$MTCAL" history import "$DATA" --store "$store" --meta machine=B03 --meta date=2026-03-01 --meta axis=X >/dev/null \
  2>"$tmp/err" || bad "history import into the served store: $(cat "$tmp/err")"
cli1=$("$MTCAL" history list --store "$store" --machine CLI1 --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["records"][0]["id"])')
api "$base/api/fleet" >"$tmp/fleet.json"
python3 - "$tmp/fleet.json" "$cli1" <<'PY' && ok || bad "the fleet after other programs' writes: $(head -c 600 "$tmp/fleet.json")"
import json, sys
f = {m["machine"]: m for m in json.load(open(sys.argv[1]))["machines"]}
c = f["CLI1"]["calibrations"]
assert [(x["command"], x["record"], x["count"]) for x in c] == [("ballbar", sys.argv[2], 1)], c
b3 = f["B03"]["calibrations"]
assert [(x["last"][:10], x["count"]) for x in b3] == [("2026-03-01", 2)], b3
PY
curl -b "$jar" "$base/fleet" >"$tmp/fleet.html"
grep -q "href=\"/record?id=$cli1\"" "$tmp/fleet.html" && ok || bad "the fleet page lacks the record $cli1 of another program"
# gzip'd when accepted (a user's header and the kept content joined): gzip -t checks its CRC and length.
curl -b "$jar" -H 'Accept-Encoding: gzip' -D "$tmp/gz.head" -o "$tmp/fleet.html.gz" "$base/fleet"
curl -b "$jar" -o "$tmp/fleet.html" "$base/fleet"
grep -qi '^content-encoding: gzip' "$tmp/gz.head" && gzip -t "$tmp/fleet.html.gz" && gzip -dc "$tmp/fleet.html.gz" | cmp -s - "$tmp/fleet.html" \
  && ok || bad "the gzip'd fleet page is not the page: $(cat "$tmp/gz.head")"

# Killed with uploads in flight: four confirmed uploads sent at once, SIGKILL while they run.
# Every record in the store afterwards is whole (its figures are there), the store passes
# SQLite's integrity check, and the server starts again on it.
before=$("$MTCAL" history list --store "$store" --json | python3 -c 'import json,sys; print(len(json.load(sys.stdin)["records"]))')
for i in 1 2 3 4; do
  api -o /dev/null -F machine=K$i -F "date=2026-0$i-01" -F confirm=1 -F "file=@$DATA" "$base/api/upload" 2>/dev/null &
done
sleep 0.3
kill -9 "$pid"
wait "$pid" 2>/dev/null
wait 2>/dev/null
"$MTCAL" history list --store "$store" --json >"$tmp/after.json" 2>"$tmp/err" || bad "history list after the kill: $(cat "$tmp/err")"
python3 - "$tmp/after.json" "$before" "${store#sqlite:}" <<'PY' && ok || bad "a killed server left a half record"
import json, sqlite3, sys
recs = json.load(open(sys.argv[1]))["records"]
before = int(sys.argv[2])
assert before <= len(recs) <= before + 4, (before, len(recs))
for r in recs:
    if r["machine"].startswith("K"):
        assert r["command"] == "iso230-2" and len(r["figures"]) >= 5, r
db = sqlite3.connect(sys.argv[3])
assert db.execute("PRAGMA integrity_check").fetchone()[0] == "ok"
# Every figure row belongs to a record, every K record has its latest_records row.
assert db.execute("SELECT COUNT(*) FROM figures WHERE record_id NOT IN (SELECT id FROM records)").fetchone()[0] == 0
PY
start_server
code=$(curl -o /dev/null -w '%{http_code}' "$base/login")
[ "$code" = 200 ] && ok || bad "the server does not start again on the same store ($code)"
stop_server
grep -q "server stopped" "$tmp/serve.log" && ok || bad "SIGTERM did not stop the server cleanly: $(cat "$tmp/serve.log")"
summary_and_exit
