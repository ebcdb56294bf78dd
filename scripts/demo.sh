#!/usr/bin/env bash
# One command on a fresh Debian 12 machine: install dependencies, build, run the built-in demo.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup_deps.sh
scripts/build.sh
exec build/release/apps/fieldlidar/fieldlidar "$@"
