#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# Builds DeepCut Studio with AddressSanitizer + UndefinedBehaviorSanitizer into build-asan/ and
# runs the whole test suite there (benchmarks and fuzzers excluded). Independent of CTest labels
# and of the default build/: what docs/RELIABILITY.md reports as "the sanitizer run".
#
#   bash scripts/sanitize.sh [ctest arguments...]     e.g.  bash scripts/sanitize.sh -R BadInput
#
# Environment:
#   DEEPCUT_ASAN_BUILD  build folder (default: build-asan in the repository)
#   DEEPCUT_JOBS        parallel build jobs (default: nproc)
#   DEEPCUT_CMAKE_ARGS  extra configure arguments, whitespace-separated (e.g. "-DDEEPCUT_BUILD_VTK=OFF"
#                       for a quicker core + CLI run without the VTK widgets and the studio)
# Any sanitizer report aborts the process that made it, so the test running it fails; the
# reports are in the ctest log (build-asan/ctest-output.log).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd -P)"
BUILD="${DEEPCUT_ASAN_BUILD:-$ROOT/build-asan}"

log() { echo "[deepcut] $*" >&2; }

bash "$ROOT/scripts/deps.sh"

# Leaks are reported too; third-party libraries that keep allocations until exit (Mesa, Qt,
# fontconfig, VTK's factories) are suppressed in scripts/lsan.supp, our own code is not.
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}abort_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:+$UBSAN_OPTIONS:}print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="${LSAN_OPTIONS:+$LSAN_OPTIONS:}suppressions=$ROOT/scripts/lsan.supp:print_suppressions=0"

extra_args=()
if [[ -n "${DEEPCUT_CMAKE_ARGS:-}" ]]; then
  read -r -a extra_args <<<"$DEEPCUT_CMAKE_ARGS"
fi

log "sanitize: configuring $BUILD (ASan + UBSan, RelWithDebInfo${extra_args[*]:+, ${extra_args[*]}})"
# Warnings are not errors here (the default build enforces them; sanitizer instrumentation makes
# gcc warn spuriously).
cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDEEPCUT_SANITIZE=ON -DDEEPCUT_STRICT=OFF "${extra_args[@]}"
jobs="${DEEPCUT_JOBS:-$(nproc)}"
log "sanitize: building with $jobs jobs"
cmake --build "$BUILD" -j"$jobs"

log "sanitize: running ctest (benchmarks and fuzzers excluded)"
ctest_log="$BUILD/ctest-output.log"
set +e
# Everything but the GUI tests, with every check on.
ctest --test-dir "$BUILD" --output-on-failure --no-tests=ignore -j2 --timeout 1800 -LE 'bench|fuzz|gui' "$@" 2>&1 |
  tee "$ctest_log"
status=${PIPESTATUS[0]}
# The GUI tests (Qt on X11, VTK on Mesa) with two checks off, both for third-party code:
# libxkbcommon-x11 calls strndup on unterminated buffers (a false report under
# strict_string_checks), and Mesa's DRI driver is unloaded at exit, so its allocations show as
# leaks of "<unknown module>" that no suppression can name. Our own code is leak-checked by
# the run above (core, CLI, plugins, formats, widgets without a display).
ASAN_OPTIONS="$ASAN_OPTIONS:strict_string_checks=0:detect_leaks=0" \
  ctest --test-dir "$BUILD" --output-on-failure --no-tests=ignore -j1 --timeout 1800 -L gui -LE 'bench|fuzz' "$@" 2>&1 |
  tee -a "$ctest_log"
gui_status=${PIPESTATUS[0]}
[[ $status -eq 0 ]] && status=$gui_status
set -e
if [[ $status -eq 0 ]]; then
  log "sanitize: PASSED, no sanitizer report (log in $ctest_log)"
else
  log "sanitize: FAILED (ctest exit $status; sanitizer reports, if any, in $ctest_log)"
fi
exit "$status"
