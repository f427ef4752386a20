#!/usr/bin/env bash
# mtcal serve end to end: the real command on a loopback port (SQLite, or STORE=postgresql://...),
# the first admin made with --add-user, driven by headless Chromium (serve_browser.mjs); then the
# faults: garbage on the socket, a server killed in the middle of an upload records nothing and
# the store opens again. Needs MTCAL, WEB, DATA (the ISO 230-2 file), SHOTS.
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
store=sqlite:$tmp/shop.db
if [ -n "${PG_FIXTURE:-}" ]; then
  # A PostgreSQL server of its own for this run; it stops when its input closes at exit.
  coproc PG { "$PG_FIXTURE"; }
  read -r store <&"${PG[0]}"
  case "$store" in SKIPPED:*) echo "PostgreSQL tests skipped: $store"; exit 77 ;; esac
fi
count_records() { "$MTCAL" history list --store "$store" --json | python3 -c 'import json,sys; print(len(json.load(sys.stdin)["records"]))'; }

MTCAL_PASSWORD='browser-test-pass' "$MTCAL" serve --store "$store" --add-user ada --role admin >"$tmp/out" 2>"$tmp/err" \
  && ok || bad "--add-user: $(cat "$tmp/err")"
expect_error "a short password is refused" "at least 10 characters" -- env MTCAL_PASSWORD=short "$MTCAL" serve --store "$store" --add-user bob
expect_error "an unreachable store is one line at start" "cannot connect" -- \
  "$MTCAL" serve --store "postgresql://x@127.0.0.1:1/none?connect_timeout=2" --listen 127.0.0.1:0

start_server() {
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

node "$(dirname "$0")/serve_browser.mjs" "$base" ada browser-test-pass "$DATA" "$SHOTS" >"$tmp/browser" 2>&1
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
hash_of() { "$MTCAL" history list --store "$1" --json | python3 -c 'import json,sys; print([r["content_hash"] for r in json.load(sys.stdin)["records"]])'; }
[ "$(hash_of "$store")" = "$(hash_of "sqlite:$tmp/cli.db")" ] && ok || bad "the server's record differs from history import's: $(hash_of "$store") vs $(hash_of "sqlite:$tmp/cli.db")"

# Garbage: 4xx, one line, and the server serves on.
reply=$(printf 'NOT HTTP AT ALL\r\n\r\n' | timeout 5 python3 -c "
import socket,sys; s=socket.create_connection(('127.0.0.1',$port)); s.sendall(sys.stdin.buffer.read()); print(s.recv(200).decode(errors='replace').splitlines()[0])")
case "$reply" in "HTTP/1.1 4"*) ok ;; *) bad "garbage got '$reply'" ;; esac
curl -s -o /dev/null -w '%{http_code}' "$base/login" | grep -q 200 && ok || bad "the server stopped serving after garbage"

# Killed in the middle of an upload: half a multipart body sent, then SIGKILL. Nothing recorded.
python3 - "$port" "$DATA" "$tmp/sent" <<'PY' &
import socket, sys, time
port, path = int(sys.argv[1]), sys.argv[2]
body = open(path, 'rb').read()
head = (f"POST /api/upload HTTP/1.1\r\nHost: x\r\nContent-Type: multipart/form-data; boundary=BB\r\n"
        f"Content-Length: {len(body) * 2 + 400}\r\n\r\n").encode()
s = socket.create_connection(('127.0.0.1', port))
s.sendall(head + b'--BB\r\nContent-Disposition: form-data; name="file"; filename="x.dat"\r\n\r\n' + body[: len(body) // 2])
open(sys.argv[3], 'w').close()
time.sleep(3)
PY
sender=$!
for _ in $(seq 1 100); do [ -e "$tmp/sent" ] && break; sleep 0.1; done
[ -e "$tmp/sent" ] && ok || bad "the half upload was not sent"
kill -9 "$pid"
wait "$pid" 2>/dev/null
wait "$sender" 2>/dev/null
after=$(count_records)
[ "$after" = "$before" ] && ok || bad "a killed upload left $after records, expected $before"
start_server
curl -s -o /dev/null -w '%{http_code}' "$base/login" >/dev/null
code=$(curl -s -o /dev/null -w '%{http_code}' "http://127.0.0.1:$port/login")
[ "$code" = 200 ] && ok || bad "the server does not start again on the same store ($code)"
kill "$pid"
wait "$pid"
grep -q "server stopped" "$tmp/serve.log" && ok || bad "SIGTERM did not stop the server cleanly: $(cat "$tmp/serve.log")"
summary_and_exit
