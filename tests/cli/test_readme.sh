#!/usr/bin/env bash
# README's tour, run as a new user pastes it: every shell block that README marks with the line
# `<!-- readme-test -->` is extracted and run in order, in a fresh folder laid out like a clone
# after `make demo` (examples/ and build/apps/mtcal/mtcal, nothing else), with `set -e`: a command
# that fails, or a file a line names that no earlier line made, fails this test. README can
# therefore not drift from what mtcal accepts.
# Needs MTCAL (the built binary) and SRC (the source tree). Prints "N passed, N failed".
set -u
source "$(dirname "$0")/../testing/cli_lib.sh"
readme="$SRC/README.md"

# The marked blocks: the fence after a marker line, up to the closing fence.
awk '
  /^<!-- readme-test -->$/ { armed = 1; next }
  armed && /^```(sh|bash)$/ { inside = 1; armed = 0; blocks++; print "# --- README block " blocks; next }
  inside && /^```$/ { inside = 0; next }
  inside { print }
' "$readme" >"$tmp/tour.sh"
blocks=$(grep -c '^# --- README block' "$tmp/tour.sh")
[ "$blocks" -ge 1 ] && ok || bad "README has no block marked <!-- readme-test -->"
grep -q '^export PATH=' "$tmp/tour.sh" && ok || bad "README's tour does not say how mtcal gets on PATH"

# A clone after `make demo`: the examples and the binary where the build puts it. The tour must
# not write into examples/: it is a read-only copy here.
clone="$tmp/clone"
mkdir -p "$clone/build/apps/mtcal"
cp -r "$SRC/examples" "$clone/examples"
chmod -R a-w "$clone/examples"
ln -s "$MTCAL" "$clone/build/apps/mtcal/mtcal"

# The tour in a shell with nothing of ours on PATH but what README itself adds.
(cd "$clone" && env -i HOME="$tmp" PATH=/usr/bin:/bin LANG=C.UTF-8 bash -e -o pipefail -x "$tmp/tour.sh") \
  >"$tmp/tour.out" 2>"$tmp/tour.err"
rc=$?
if [ "$rc" -eq 0 ]; then
  ok
else
  bad "README's tour stopped (exit $rc) at: $(grep '^+' "$tmp/tour.err" | tail -1)"
  tail -5 "$tmp/tour.err"
fi

# Each command of the tour ran: as many mtcal invocations in the trace as in the blocks (a block
# joined by backslashes counts once in both).
want=$(grep -cE '^(mtcal|  *mtcal) ' "$tmp/tour.sh")
got=$(grep -cE '^\+ mtcal ' "$tmp/tour.err")
[ "$want" -ge 10 ] && [ "$got" -eq "$want" ] && ok || bad "ran $got of $want mtcal commands"

# The files the tour says it writes are there and not empty.
for f in configs.csv errors.csv contacts.csv c-axis.yaml iso230-2.html trace.csv ballbar.html va.html \
  path-errors.csv samba.csv identified.yaml pocket-c.nc; do
  [ -s "$clone/$f" ] && ok || bad "the tour did not write $f"
done
# Every command's --help ends with examples, and each of them runs in the same folder after the
# tour (some read files the tour made: contacts.csv, trace.csv, samba.csv).
commands=$("$MTCAL" --help | awk '/^Subcommands:/ { on = 1; next } on && /^  [a-z]/ { print $1 } on && /^$/ { on = 0 }')
[ "$(echo "$commands" | wc -w)" -ge 19 ] && ok || bad "mtcal --help lists $(echo "$commands" | wc -w) commands"
for c in $commands; do
  "$MTCAL" "$c" --help >"$tmp/help" 2>&1
  if ! grep -q '^Examples:' "$tmp/help"; then
    bad "mtcal $c --help has no examples"
    continue
  fi
  # The example lines, continuation lines joined.
  awk '/^Examples:/ { on = 1; next } on && /^  / { sub(/^  +/, ""); line = line $0; if (line ~ /\\$/) { sub(/\\$/, "", line); next } print line; line = "" }' \
    "$tmp/help" >"$tmp/examples-$c.sh"
  n=$(grep -c '^mtcal ' "$tmp/examples-$c.sh")
  [ "$n" -ge 1 ] && ok || bad "mtcal $c --help: no example starts with 'mtcal '"
  # probe-log reads the log a controller wrote while it ran the probing program: nothing here makes
  # one, so its example is not run (the reader is tested on logs in test_planning: ProbeLog.*).
  if [ "$c" = probe-log ]; then
    echo "note: the example of mtcal probe-log needs a controller's probe log; not run here"
    continue
  fi
  # serve runs until it is stopped: its examples are run by server_cli (tests/server), which starts
  # the server on a loopback port, drives it with curl and stops it.
  if [ "$c" = serve ]; then
    echo "note: the examples of mtcal serve run until stopped; server_cli runs them"
    continue
  fi
  (cd "$clone" && env -i HOME="$tmp" PATH="$clone/build/apps/mtcal:/usr/bin:/bin" LANG=C.UTF-8 \
    bash -e -o pipefail "$tmp/examples-$c.sh") >"$tmp/ex.out" 2>"$tmp/ex.err" && ok ||
    bad "an example of mtcal $c --help fails: $(tail -1 "$tmp/ex.err")"
done
chmod -R u+w "$clone/examples"
summary_and_exit
