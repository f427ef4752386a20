# Shared pieces of the command-line test scripts (sourced): counters, a temporary folder, and
# checks of exit codes and one-line error messages. Each script ends with summary_and_exit.
pass=0
fail=0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

# expect_exit CODE DESCRIPTION -- command...: stdout in $tmp/out, stderr in $tmp/err.
expect_exit() {
  local code=$1 what=$2
  shift 3
  "$@" >"$tmp/out" 2>"$tmp/err"
  local got=$?
  if [ "$got" -eq "$code" ]; then ok; else bad "$what: exit $got, expected $code; stderr: $(cat "$tmp/err")"; fi
}
# expect_error DESCRIPTION SUBSTRING -- command...: non-zero exit, one stderr line containing SUBSTRING.
expect_error() {
  local what=$1 sub=$2
  shift 3
  "$@" >"$tmp/out" 2>"$tmp/err"
  local got=$?
  if [ "$got" -eq 0 ]; then bad "$what: exit 0"; return; fi
  if [ "$(wc -l <"$tmp/err")" -ne 1 ]; then bad "$what: stderr is not one line: $(cat "$tmp/err")"; return; fi
  if ! grep -qF -- "$sub" "$tmp/err"; then bad "$what: stderr lacks '$sub': $(cat "$tmp/err")"; return; fi
  ok
}
# json_get EXPRESSION: a Python expression over d, the JSON in $tmp/out.
json_get() { python3 -c "import json,sys; d=json.load(open('$tmp/out')); print($1)"; }

# Prints the closing line ctest reads and exits non-zero on any failure.
summary_and_exit() {
  echo "$pass passed, $fail failed"
  [ "$fail" -eq 0 ]
}
