#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
#
# Installs what DeepCut Studio needs to build and test, and only what is missing.
# This is the ONE place that names Debian packages.
#
#   bash scripts/deps.sh [--no-validator]
#
#   --no-validator  skip the Khronos glTF validator and three.js (npm) and the Node.js packages
#                   they need.
#
# Debian packages come from apt (sudo is used only when not root). The glTF validator and
# three.js (the second glTF client the tests pose exports with, scripts/pose_three.mjs) come
# from the npm registry, pinned, into build/tools/node_modules/{gltf-validator,three}.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd -P)"

# Pinned: bump deliberately (check `npm view gltf-validator version`) and re-run the tests.
readonly GLTF_VALIDATOR_VERSION="2.0.0-dev.3.10"
# Pinned likewise (`npm view three version`).
readonly THREE_VERSION="0.187.0"

# Build toolchain, libraries, test frameworks, and a virtual display for the GUI tests.
readonly APT_PACKAGES=(
  build-essential cmake ninja-build pkg-config git
  libglm-dev libtinygltf-dev nlohmann-json3-dev libstb-dev
  libdraco-dev libmeshoptimizer-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3
  libvtk9-dev libvtk9-qt-dev qtbase5-dev
  xvfb xauth libgl1-mesa-dri fonts-dejavu-core
)
# Only needed to run the glTF validator and three.js.
readonly NODE_PACKAGES=(nodejs npm)

log() { echo "[deepcut] $*" >&2; }
die() {
  echo "[deepcut] error: $*" >&2
  exit 1
}

usage() {
  sed -n '4,14s/^# \{0,1\}//p' "${BASH_SOURCE[0]}" >&2
}

with_validator=1
for arg in "$@"; do
  case "$arg" in
    --no-validator) with_validator=0 ;;
    -h | --help)
      usage
      exit 0
      ;;
    *)
      usage
      die "deps: unknown argument '$arg'"
      ;;
  esac
done

is_installed() {
  # Multi-arch packages may print one status per architecture; any installed one will do.
  dpkg-query -W -f='${Status}\n' "$1" 2>/dev/null | grep -qx 'install ok installed'
}

# Runs a command as root: directly when root, through sudo otherwise.
as_root() {
  if [[ $(id -u) -eq 0 ]]; then
    "$@"
  elif command -v sudo >/dev/null 2>&1; then
    sudo "$@"
  else
    die "deps: need root to run '$*' (not root and sudo is not installed)"
  fi
}

# ---- Debian packages --------------------------------------------------------------------------
wanted=("${APT_PACKAGES[@]}")
if [[ $with_validator -eq 1 ]]; then
  if command -v node >/dev/null 2>&1 && command -v npm >/dev/null 2>&1; then
    : # Node.js and npm are already here (possibly not from Debian): don't install Debian's.
  else
    wanted+=("${NODE_PACKAGES[@]}")
  fi
fi

missing=()
for pkg in "${wanted[@]}"; do
  is_installed "$pkg" || missing+=("$pkg")
done

if [[ ${#missing[@]} -eq 0 ]]; then
  log "deps: all ${#wanted[@]} Debian packages present"
else
  log "deps: installing missing Debian packages: ${missing[*]}"
  # apt's output goes to stderr so callers' stdout stays clean.
  as_root apt-get update >&2
  as_root env DEBIAN_FRONTEND=noninteractive \
    apt-get install -y --no-install-recommends "${missing[@]}" >&2
fi

# ---- glTF validator and three.js (npm) -------------------------------------------------------
if [[ $with_validator -eq 0 ]]; then
  log "deps: --no-validator: skipping gltf-validator and three"
  exit 0
fi

command -v node >/dev/null 2>&1 || die "deps: 'node' not found after installing nodejs"
command -v npm >/dev/null 2>&1 || die "deps: 'npm' not found after installing npm"

tools_dir="$ROOT/build/tools"

# Installs npm package $1 at version $2 into build/tools unless that version is there.
npm_package() {
  local name="$1" version="$2" dir="$tools_dir/node_modules/$1" installed=""
  if [[ -f "$dir/package.json" ]]; then
    installed="$(node -p 'require(process.argv[1]).version' "$dir/package.json" 2>/dev/null || true)"
  fi
  if [[ "$installed" == "$version" ]]; then
    log "deps: $name $version present in build/tools"
    return
  fi
  log "deps: installing $name@$version into build/tools${installed:+ (replacing $installed)}"
  mkdir -p "$tools_dir"
  # npm's own output goes to stderr so callers' stdout stays clean.
  npm install --prefix "$tools_dir" --no-audit --no-fund "$name@$version" >&2
  [[ -f "$dir/package.json" ]] || die "deps: npm did not install $name into $dir"
}

npm_package gltf-validator "$GLTF_VALIDATOR_VERSION"
npm_package three "$THREE_VERSION"
