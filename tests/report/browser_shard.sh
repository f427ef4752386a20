#!/usr/bin/env bash
# The browser half of tests/report/test_reports.sh in shards: loads every N-th report that
# `REPORTS_OUT=DIR test_reports.sh` left in DIR (its list DIR/specs), from the K-th on, in headless
# Chromium (browser_check.mjs). ctest runs the shards side by side (reports_in_browser_KofN).
# Usage: browser_shard.sh DIR K N. Needs WEB and SHOTS. Exit 77 (SKIPPED) without node or Chromium.
set -u
dir=${1:?usage: browser_shard.sh DIR K N} k=${2:?K} n=${3:?N}
[ -s "$dir/specs" ] || { echo "FAIL: no report list $dir/specs (the test reports_make writes it)"; exit 1; }
mapfile -t all <"$dir/specs"
mine=()
for i in "${!all[@]}"; do
  [ $((i % n)) -eq $((k - 1)) ] && mine+=("${all[$i]}")
done
[ "${#mine[@]}" -gt 0 ] || { echo "FAIL: shard $k of $n has no report (${#all[@]} in $dir/specs)"; exit 1; }
if ! command -v node >/dev/null; then
  echo "SKIPPED: node is not installed (Debian: nodejs npm; scripts/install-deps installs them)"
  exit 77
fi
echo "shard $k of $n: ${#mine[@]} of ${#all[@]} reports"
cd "$WEB" && MTCAL_WEB="$WEB" exec node "$(dirname "$(realpath "$0")")/browser_check.mjs" "$SHOTS" "${mine[@]}"
