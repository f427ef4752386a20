#!/usr/bin/env bash
# mtcal serve end to end: the real command on a loopback port (SQLite, or STORE=postgresql://...),
# the first admin made with --add-user, driven by headless Chromium (serve_browser.mjs); then
# garbage on the socket gets a 4xx and the server serves on. Every client is bounded in time (the
# browser by `timeout`, curl by --max-time). Needs MTCAL, WEB, DATA (the ISO 230-2 file), SHOTS,
# MACHINE (a machine file for the compensation download).
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
store=sqlite:$tmp/shop.db
if [ -n "${PG_FIXTURE:-}" ]; then
  # A PostgreSQL server of its own for this run; it stops when its input closes at exit.
  coproc PG { "$PG_FIXTURE"; }
  read -r store <&"${PG[0]}"
  case "$store" in SKIPPED:*) echo "PostgreSQL tests skipped: $store"; exit 77 ;; esac
fi
count_records() { "$MTCAL" history list --store "$store" --machine "B02 <test stand>" --json | python3 -c 'import json,sys; print(len(json.load(sys.stdin)["records"]))'; }

MTCAL_PASSWORD='browser-test-pass' "$MTCAL" serve --store "$store" --add-user ada --role admin >"$tmp/out" 2>"$tmp/err" \
  && ok || bad "--add-user: $(cat "$tmp/err")"
expect_error "a short password is refused" "at least 10 characters" -- env MTCAL_PASSWORD=short "$MTCAL" serve --store "$store" --add-user bob
expect_error "an unreachable store is one line at start" "cannot connect" -- \
  "$MTCAL" serve --store "postgresql://x@127.0.0.1:1/none?connect_timeout=2" --listen 127.0.0.1:0

start_server() {
  : >"$tmp/serve.log"  # emptied before the server's shell opens it (see test_serve_cli.sh)
  "$MTCAL" serve --store "$store" --listen 127.0.0.1:0 2>"$tmp/serve.log" &
  pid=$!
  for _ in $(seq 1 100); do
    port=$(sed -n 's|.*://127.0.0.1:\([0-9]*\)/.*|\1|p' "$tmp/serve.log")
    [ -n "$port" ] && break
    sleep 0.1
  done
  [ -n "$port" ] || { bad "the server did not start: $(cat "$tmp/serve.log")"; summary_and_exit; exit 1; }
}
start_server
base="http://127.0.0.1:$port"

# A result recorded from the command line with its machine file (schema 5's model files): the
# browser writes compensation from its record page.
"$MTCAL" volumetric -m "$MACHINE" --grid X=-400:400:3,Y=0,Z=-100 --meta machine=VMC1 --meta date=2022-09-01 \
  --record "$store" >/dev/null 2>"$tmp/err" || bad "volumetric --record: $(cat "$tmp/err")"
vrec=$("$MTCAL" history list --store "$store" --machine VMC1 --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["records"][0]["id"])')
timeout 480 node "$(dirname "$0")/serve_browser.mjs" "$base" ada browser-test-pass "$DATA" "$SHOTS" "$MACHINE" "$vrec" >"$tmp/browser" 2>&1
rc=$?
cat "$tmp/browser"
if [ $rc -eq 77 ]; then kill "$pid"; wait "$pid"; echo "SKIPPED: browser part"; exit 77; fi
[ $rc -eq 0 ] && ok || bad "browser run"
before=$(count_records)
[ "$before" = 1 ] && ok || bad "after the browser's upload the store holds $before records, expected 1"
# Evaluated exactly as the command does: `mtcal history import` of the same file with the same
# metadata into another store gives the same content hash (inputs' SHA-256, metadata, result JSON).
"$MTCAL" history import "$DATA" --store "sqlite:$tmp/cli.db" --meta "machine=B02 <test stand>" --meta date=2022-10-20 \
  --meta "operator=browser test" >/dev/null 2>"$tmp/err" || bad "history import: $(cat "$tmp/err")"
hash_of() { "$MTCAL" history list --store "$1" --machine "B02 <test stand>" --json | python3 -c 'import json,sys; print([r["content_hash"] for r in json.load(sys.stdin)["records"]])'; }
[ "$(hash_of "$store")" = "$(hash_of "sqlite:$tmp/cli.db")" ] && ok || bad "the server's record differs from history import's: $(hash_of "$store") vs $(hash_of "sqlite:$tmp/cli.db")"

# Garbage: 4xx, one line, and the server serves on.
reply=$(printf 'NOT HTTP AT ALL\r\n\r\n' | timeout 5 python3 -c "
import socket,sys; s=socket.create_connection(('127.0.0.1',$port), timeout=5); s.sendall(sys.stdin.buffer.read()); print(s.recv(200).decode(errors='replace').splitlines()[0])")
case "$reply" in "HTTP/1.1 4"*) ok ;; *) bad "garbage got '$reply'" ;; esac
curl -s --max-time 30 -o /dev/null -w '%{http_code}' "$base/login" | grep -q 200 && ok || bad "the server stopped serving after garbage"

# (A server killed with uploads in flight: server_cli, tests/server/test_serve_cli.sh.)
kill "$pid"
wait "$pid"
grep -q "server stopped" "$tmp/serve.log" && ok || bad "SIGTERM did not stop the server cleanly: $(cat "$tmp/serve.log")"
summary_and_exit
