#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# Installs what is missing, builds, and runs the main job.
#
#   bash scripts/run.sh [ARGS...]
#
# With build/bin/deepcut-studio built: opens the studio on $DISPLAY, or without a display runs it
# under Xvfb and saves a screenshot to build/demo-screenshot.png. ARGS go to the studio.
# Otherwise: runs `deepcut info MODEL` (MODEL = first argument, default assets/cactus.glb).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd -P)"
BUILD="$ROOT/build"

log() { echo "[deepcut] $*" >&2; }
die() {
  echo "[deepcut] error: $*" >&2
  exit 1
}

bash "$ROOT/scripts/build.sh"

studio="$BUILD/bin/deepcut-studio"
cli="$BUILD/bin/deepcut"

if [[ -x "$studio" ]]; then
  if [[ -n "${DISPLAY:-}" ]]; then
    log "run: $studio $*"
    exec "$studio" "$@"
  fi
  command -v xvfb-run >/dev/null 2>&1 || die "run: no \$DISPLAY and xvfb-run is missing (install xvfb)"
  screenshot="$BUILD/demo-screenshot.png"
  log "run: no \$DISPLAY: running the studio under Xvfb and saving a screenshot"
  xvfb-run -a -s "-screen 0 1600x1000x24" "$studio" --screenshot "$screenshot" "$@"
  log "run: screenshot saved to $screenshot"
elif [[ -x "$cli" ]]; then
  model="${1:-$ROOT/assets/cactus.glb}"
  log "run: deepcut-studio not built yet; running: deepcut info $model"
  exec "$cli" info "$model"
else
  die "run: neither $studio nor $cli was built"
fi
