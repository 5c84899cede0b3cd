#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# Installs what is missing, builds, and runs every test (benchmarks excluded).
# This is the README's test command, and .ci/run calls exactly this.
#
#   bash scripts/test.sh [--no-validator]
#
# Flags are passed to scripts/build.sh. Tests that need a display start Xvfb themselves.
# Exits with ctest's status; a run that finds no test at all fails.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd -P)"
BUILD="$ROOT/build"

log() { echo "[deepcut] $*" >&2; }

bash "$ROOT/scripts/build.sh" "$@"

log "test: running ctest (benchmarks excluded)"
ctest_log="$BUILD/ctest-output.log"
set +e
ctest --test-dir "$BUILD" --output-on-failure --no-tests=error -j2 --timeout 900 -LE bench 2>&1 |
  tee "$ctest_log"
status=${PIPESTATUS[0]}
set -e

# Summary from ctest's own closing line: "NN% tests passed, F tests failed out of T".
total="$(sed -n 's/.*tests passed, [0-9]* tests\{0,1\} failed out of \([0-9]*\).*/\1/p' "$ctest_log" | tail -n 1)"
failed="$(sed -n 's/.*tests passed, \([0-9]*\) tests\{0,1\} failed out of.*/\1/p' "$ctest_log" | tail -n 1)"
skipped="$(grep -c '\*\*\*Skipped' "$ctest_log" || true)"
if [[ -n "$total" && -n "$failed" ]]; then
  passed=$((total - failed - skipped))
  echo "deepcut: $passed passed, $failed failed, $skipped skipped"
fi
if [[ $status -eq 0 ]]; then
  log "test: PASSED (ctest exit 0; log in $ctest_log)"
else
  log "test: FAILED (ctest exit $status; log in $ctest_log)"
fi
exit "$status"
