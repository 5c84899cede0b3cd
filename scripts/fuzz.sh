#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# Builds the libFuzzer targets with clang into build-fuzz/ (ASan + UBSan + coverage; VTK on for
# the static mesh readers, the studio off; only the fuzz targets are compiled) and runs them:
# `ctest -L fuzz`, i.e. each target fuzzes for SECONDS from its seed
# corpus (tests/fuzz/corpus/<target>/), then replays the seeds and saved regressions.
#
#   bash scripts/fuzz.sh [SECONDS]          default 60
#
# Warnings are not errors here: clang warns about things gcc (the project's compiler) does not.
# Environment: DEEPCUT_FUZZ_BUILD (default build-fuzz in the repository), DEEPCUT_JOBS.
# clang and libclang-rt-14-dev are installed here when missing; scripts/deps.sh does not name
# them because the default test run does not fuzz.
# A crash leaves its input in build-fuzz/fuzz-artifacts/<target>/: minimise it, copy it to
# tests/fuzz/regressions/<target>/ and fix the bug (the core and fuzz replay tests run it).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd -P)"
BUILD="${DEEPCUT_FUZZ_BUILD:-$ROOT/build-fuzz}"
SECONDS_PER_TARGET="${1:-60}"

log() { echo "[deepcut] $*" >&2; }
die() {
  echo "[deepcut] error: $*" >&2
  exit 1
}
[[ "$SECONDS_PER_TARGET" =~ ^[0-9]+$ ]] || die "fuzz: SECONDS must be a whole number, got '$SECONDS_PER_TARGET'"

bash "$ROOT/scripts/deps.sh" --no-validator
missing=()
for pkg in clang libclang-rt-14-dev; do
  dpkg-query -W -f='${Status}\n' "$pkg" 2>/dev/null | grep -qx 'install ok installed' || missing+=("$pkg")
done
if [[ ${#missing[@]} -gt 0 ]]; then
  log "fuzz: installing ${missing[*]}"
  sudo_cmd=()
  [[ $(id -u) -eq 0 ]] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update >&2
  "${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}" >&2
fi

log "fuzz: configuring $BUILD (clang, libFuzzer, ASan + UBSan)"
cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DDEEPCUT_FUZZ=ON -DDEEPCUT_FUZZ_SECONDS="$SECONDS_PER_TARGET" \
  -DDEEPCUT_BUILD_VTK=ON -DDEEPCUT_BUILD_STUDIO=OFF -DDEEPCUT_BUILD_TESTS=ON -DDEEPCUT_STRICT=OFF
cmake --build "$BUILD" -j"${DEEPCUT_JOBS:-$(nproc)}" --target deepcut_fuzzers

log "fuzz: running ctest -L fuzz ($SECONDS_PER_TARGET s per target)"
fuzz_log="$BUILD/fuzz-output.log"
set +e
ctest --test-dir "$BUILD" -L fuzz --no-tests=error -V 2>&1 | tee "$fuzz_log"
status=${PIPESTATUS[0]}
set -e

# libFuzzer's -print_final_stats lines, one summary per target.
echo "fuzz summary:"
awk '/Test command:/ { n = $0; sub(/.*\/fuzz_/, "", n); sub(/ .*/, "", n); target = n }
     /stat::number_of_executed_units:/ { runs[target] = $NF }
     /stat::average_exec_per_sec:/ { speed[target] = $NF }
     /stat::new_units_added:/ { added[target] = $NF }
     END { for (t in runs) printf "  %s: %s executions (%s/s), %s new corpus units\n", t, runs[t], speed[t], added[t] }' "$fuzz_log"
crashes="$(find "$BUILD/fuzz-artifacts" -type f 2>/dev/null | wc -l)"
echo "  crash/leak/timeout artifacts: $crashes (in $BUILD/fuzz-artifacts)"
exit "$status"
