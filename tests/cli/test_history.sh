#!/usr/bin/env bash
# The calibration history through the command line (docs/history.md): --record on result
# commands, the default store from $MTCAL_HISTORY and the configuration file, a failing command
# recording nothing, duplicates, two commands recording at once, import of result JSON and
# instrument files, export and re-import byte for byte, events, bad input. Needs MTCAL, ROOT.
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
X="$ROOT/examples/data/iso230-2-x-axis.csv"
RTL="$ROOT/examples/instruments/x-axis.rtl"
H="$tmp/h.db"
export MTCAL_CONFIG="$tmp/no-config.yaml" MTCAL_HISTORY=""
count() { "$MTCAL" history list --store "$1" --json | python3 -c "import json,sys; print(len(json.load(sys.stdin)['records']))"; }

# A result recorded: machine, date, axis from --meta; the figures named with the axis; the input's SHA-256.
expect_exit 0 "iso230-2 --record" -- "$MTCAL" iso230-2 "$X" --meta machine=VMC-800 --meta serial=4711 \
  --meta date=2026-11-01 --meta axis=X --record="$H"
grep -q "^mtcal: recorded [0-9a-f]\{16\} in sqlite:$H" "$tmp/err" && ok || bad "record message: $(cat "$tmp/err")"
grep -q '^A ' "$tmp/out" && ok || bad "iso230-2 text output kept: $(cat "$tmp/out")"
sum=$(sha256sum "$X" | cut -d' ' -f1)
expect_exit 0 "history list --json" -- "$MTCAL" history list --store "$H" --json
json_get "len(d['records']) == 1 and d['records'][0]['machine'] == 'VMC-800' and d['records'][0]['serial'] == '4711' and d['records'][0]['measured_at'] == '2026-11-01' and d['records'][0]['command'] == 'iso230-2' and abs(d['records'][0]['figures']['A_X']['value'] - 0.014465958714053885) < 1e-15" \
  | grep -qx True && ok || bad "list JSON: $(cat "$tmp/out")"
id=$(json_get "d['records'][0]['id']")
expect_exit 0 "history show --json" -- "$MTCAL" history show "$id" --store "$H" --json
json_get "d['inputs'][0]['sha256'] == '$sum' and d['metadata']['operator'] if 'operator' in d['metadata'] else d['inputs'][-1]['sha256'] == '$sum' and d['result']['E'] == 0.011780000000008914 and d['metadata']['axis'] == 'X'" \
  | grep -qx True && ok || bad "show JSON: $(head -c 600 "$tmp/out")"
expect_exit 0 "history show text" -- "$MTCAL" history show "$id" --store "$H"
grep -q "SHA-256 $sum" "$tmp/out" && grep -q '^A_X ' "$tmp/out" && ok || bad "show text: $(cat "$tmp/out")"

# The same result again: a duplicate, not recorded twice. --json output is unchanged by --record.
expect_exit 0 "duplicate" -- "$MTCAL" iso230-2 "$X" --meta machine=VMC-800 --meta serial=4711 --meta date=2026-11-01 \
  --meta axis=X --record="$H" --json
grep -q "recorded already as $id" "$tmp/err" && ok || bad "duplicate message: $(cat "$tmp/err")"
json_get "d['A'] == 0.014465958714053885" | grep -qx True && ok || bad "--json with --record: $(head -c 300 "$tmp/out")"
[ "$(count "$H")" = 1 ] && ok || bad "duplicate stored"

# A failing command records nothing: a bad input, a report that cannot be written, a result
# without a machine name, a --record that took the command's input file, a command without a result.
printf 'target,run,direction,deviation\n0,1,up,abc\n' >"$tmp/bad.csv"
expect_error "bad input" "bad.csv" -- "$MTCAL" iso230-2 "$tmp/bad.csv" --meta machine=M --record="$H"
expect_error "unwritable report" "" -- "$MTCAL" iso230-2 "$X" --meta machine=M --meta date=2026-11-02 \
  --report "$tmp/no/such/dir/r.html" --record="$H"
expect_error "no machine" "--meta machine=NAME" -- "$MTCAL" iso230-2 "$X" --record="$H"
expect_error "--record took the input" "write --record=STORE" -- "$MTCAL" iso230-2 --record "$X" "$X"
expect_error "no result to record" "produces no calibration result" -- "$MTCAL" errors \
  -m "$ROOT/examples/machines/vmc-3axis.yaml" --record="$H"
expect_error "bad metadata date" "ISO 8601" -- "$MTCAL" iso230-2 "$X" --meta machine=M --meta date=01.11.2026 \
  --record="$H"
[ "$(count "$H")" = 1 ] && ok || bad "a failing command recorded something: $(count "$H") records"
expect_error "unopenable store" "cannot open" -- "$MTCAL" iso230-2 "$X" --meta machine=M --record="$tmp/no/dir/h.db"

# The default store: $MTCAL_HISTORY, then the configuration file (record: always; --no-record).
expect_exit 0 "MTCAL_HISTORY" -- env MTCAL_HISTORY="$tmp/env.db" "$MTCAL" iso230-2 "$X" --meta machine=E \
  --meta date=2026-01-01 --record
[ "$(count "$tmp/env.db")" = 1 ] && ok || bad "MTCAL_HISTORY store"
printf 'history:\n  store: %s\n  record: always\n' "$tmp/cfg.db" >"$tmp/config.yaml"
expect_exit 0 "config record: always" -- env MTCAL_CONFIG="$tmp/config.yaml" "$MTCAL" iso230-2 "$X" --meta machine=C \
  --meta date=2026-01-01
expect_exit 0 "config --no-record" -- env MTCAL_CONFIG="$tmp/config.yaml" "$MTCAL" iso230-2 "$X" --meta machine=C \
  --meta date=2026-02-01 --no-record
expect_exit 0 "config: a command without a result runs" -- env MTCAL_CONFIG="$tmp/config.yaml" "$MTCAL" errors \
  -m "$ROOT/examples/machines/vmc-3axis.yaml"
expect_exit 0 "config store for history list" -- env MTCAL_CONFIG="$tmp/config.yaml" "$MTCAL" history list --json
json_get "len(d['records']) == 1 and d['records'][0]['machine'] == 'C'" | grep -qx True && ok || bad "config store: $(cat "$tmp/out")"
printf 'history:\n  store: x.db\n  record: sometimes\n' >"$tmp/bad-config.yaml"
expect_error "bad config" "bad-config.yaml:3: field 'history.record'" -- env MTCAL_CONFIG="$tmp/bad-config.yaml" \
  "$MTCAL" history list
expect_error "no store" "no history store given" -- "$MTCAL" history list

# Two commands recording at once, 25 results each (distinct dates): all 50 kept.
for w in 1 2; do
  (for i in $(seq 1 25); do
     "$MTCAL" iso230-2 "$X" --meta machine=W$w --meta date=2026-01-01T00:00:$(printf %02d "$i")Z \
       --record="$tmp/conc.db" >/dev/null 2>>"$tmp/conc-err-$w" || echo "fail $i" >>"$tmp/conc-err-$w"
   done) &
done
wait
[ "$(count "$tmp/conc.db")" = 50 ] && ! grep -q '^fail' "$tmp"/conc-err-* && ok || bad "concurrent CLI writers: $(count "$tmp/conc.db") records; $(cat "$tmp"/conc-err-*)"

# Import: a result JSON file, an instrument file (evaluated to ISO 230-2 with its header), a
# duplicate (skipped and listed); a file of unknown kind fails the whole import.
"$MTCAL" iso230-2 "$X" --json >"$tmp/x.json" 2>/dev/null
expect_exit 0 "import" -- "$MTCAL" history import "$tmp/x.json" "$RTL" --store "$tmp/imp.db" \
  --meta machine=VMC-800 --meta date=2026-10-01 --json
json_get "d['records_added'] == 2 and d['skipped'] == [] and len(d['records']) == 2" | grep -qx True && ok || bad "import: $(cat "$tmp/out")"
expect_exit 0 "import again" -- "$MTCAL" history import "$tmp/x.json" --store "$tmp/imp.db" --meta machine=VMC-800 \
  --meta date=2026-10-01
grep -q "skipped  .*x.json: duplicate of record" "$tmp/out" && grep -q "^0 record(s) added" "$tmp/out" && ok || bad "import duplicate: $(cat "$tmp/out")"
echo '{"hello": 1}' >"$tmp/what.json"
expect_error "import unknown JSON" "give the command that made it (--command)" -- "$MTCAL" history import "$tmp/x.json" "$tmp/what.json" \
  --store "$tmp/imp2.db" --meta machine=M
[ ! -e "$tmp/imp2.db" ] || [ "$(count "$tmp/imp2.db")" = 0 ] && ok || bad "a failed import stored records"

# Events; export; import into a fresh store; export again: the same bytes.
expect_exit 0 "event add" -- "$MTCAL" history event add --store "$H" --machine VMC-800 --date 2026-11-20 --kind crash \
  --note "Z hit the vice" --json
json_get "d['kind'] == 'crash' and len(d['id']) == 16" | grep -qx True && ok || bad "event JSON: $(cat "$tmp/out")"
expect_error "event kind" "expected compensation-loaded, crash, repair or other" -- "$MTCAL" history event add \
  --store "$H" --machine VMC-800 --date 2026-11-20 --kind explosion
expect_error "event date" "ISO 8601" -- "$MTCAL" history event add --store "$H" --machine VMC-800 --date 20.11.2026 \
  --kind crash
expect_exit 0 "export" -- "$MTCAL" history export --store "$H" --out "$tmp/a.jsonl"
# a record, an event and the record's measurement file (iso230-2 --record keeps its runs: schema version 6)
[ "$(wc -l <"$tmp/a.jsonl")" = 3 ] && ok || bad "export lines: $(cat "$tmp/a.jsonl")"
expect_exit 0 "re-import" -- "$MTCAL" history import "$tmp/a.jsonl" --store "$tmp/b.db"
expect_exit 0 "re-export" -- "$MTCAL" history export --store "$tmp/b.db" --out "$tmp/b.jsonl"
cmp -s "$tmp/a.jsonl" "$tmp/b.jsonl" && ok || bad "export, import, export differ"
sed 's/"VMC-800"/"VMC-801"/' "$tmp/a.jsonl" >"$tmp/tampered.jsonl"
expect_error "tampered line" "tampered.jsonl:1: field 'content_hash'" -- "$MTCAL" history import "$tmp/tampered.jsonl" \
  --store "$tmp/c.db"
expect_error "unknown id" "no record with id 'nope'" -- "$MTCAL" history show nope --store "$H"

# Every history command has --help with examples.
for c in list show import export "event add"; do
  # shellcheck disable=SC2086
  expect_exit 0 "history $c --help" -- "$MTCAL" history $c --help
  grep -q "^Examples:" "$tmp/out" && ok || bad "history $c --help has no examples"
done

summary_and_exit
