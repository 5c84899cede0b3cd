#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# Installs what is missing, then configures and builds DeepCut Studio into build/.
#
#   bash scripts/build.sh [--no-validator]
#
# Flags are passed to scripts/deps.sh. Environment:
#   DEEPCUT_CMAKE_ARGS  extra arguments appended to the CMake configure step
#                       (whitespace-separated, e.g. "-DDEEPCUT_BUILD_VTK=OFF -DDEEPCUT_STRICT=OFF")
#   DEEPCUT_JOBS        parallel build jobs (default: nproc)
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd -P)"
BUILD="$ROOT/build"

log() { echo "[deepcut] $*" >&2; }

log "build: checking dependencies"
bash "$ROOT/scripts/deps.sh" "$@"

# A build/ configured earlier with another generator can't be reconfigured with Ninja:
# drop only CMake's cache (build/tools and other outputs stay).
if [[ -f "$BUILD/CMakeCache.txt" ]] && ! grep -qx 'CMAKE_GENERATOR:INTERNAL=Ninja' "$BUILD/CMakeCache.txt"; then
  log "build: build/ was configured with another generator; clearing its CMake cache"
  rm -rf "$BUILD/CMakeCache.txt" "$BUILD/CMakeFiles"
fi

extra_args=()
if [[ -n "${DEEPCUT_CMAKE_ARGS:-}" ]]; then
  read -r -a extra_args <<<"$DEEPCUT_CMAKE_ARGS"
fi

log "build: configuring (cmake -G Ninja, Release${extra_args[*]:+, ${extra_args[*]}})"
cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release "${extra_args[@]}"

jobs="${DEEPCUT_JOBS:-$(nproc)}"
log "build: compiling with $jobs jobs"
cmake --build "$BUILD" -j"$jobs"

log "build: done ($BUILD)"
