#!/usr/bin/env bash
# Configures and builds fieldlidar in Release into build/release (assertions kept on).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_FLAGS_RELEASE="-O2 -g0" -DFIELDLIDAR_WERROR=ON "$@" >/dev/null
cmake --build build/release -j "$jobs"
