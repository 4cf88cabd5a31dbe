#!/usr/bin/env bash
# Configures and builds shellfrac. Usage: scripts/build.sh [BUILD_TYPE] [extra cmake args...]
# BUILD_TYPE defaults to Release. The build tree is ./build (override with SHELLFRAC_BUILD_DIR).
set -euo pipefail
cd "$(dirname "$0")/.."
build_type=${1:-Release}
shift || true
build_dir=${SHELLFRAC_BUILD_DIR:-build}
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE="$build_type" "$@"
cmake --build "$build_dir" -j "$jobs"
