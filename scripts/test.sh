#!/usr/bin/env bash
# One command on a fresh Debian 12 machine: install dependencies, then build and run the whole test
# suite: sanitizer build (ASan + UBSan, Debug), fuzz targets for a short budget (clang/libFuzzer),
# the installed package in a temporary prefix (scripts/check_install.sh: the CLI, `legs` with its
# shipped classifier and the consumer example, without LD_LIBRARY_PATH), and the Release build's
# tests last. Tests labelled "slow" (whole closed-loop runs, real-scan evaluations) and the
# end-to-end follow command run in the Release stage only: under the sanitizers they take minutes
# each. The sanitizer build (Debug, no compiler launcher) precompiles the widely included headers
# (FIELDLIDAR_PCH, cmake/FieldlidarPch.cmake) and builds the libraries and the CLI as unity builds
# (FIELDLIDAR_UNITY, cmake/FieldlidarUnity.cmake).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
FUZZ_SECONDS=${FIELDLIDAR_FUZZ_SECONDS:-10}

scripts/setup_deps.sh

echo "== sanitizer build (Debug, ASan+UBSan) =="
# The test executables whose tests are all labelled slow are not built here: this stage does not
# run them (the Release stage builds and runs them).
# -O1, as the AddressSanitizer documentation advises for reasonable speed: asserts stay on (no
# NDEBUG) and frame pointers are kept for the reports. GCC 12 raises false "maybe uninitialized"
# warnings inside Eigen at -O1 with the sanitizers; the Release build (-O2) still checks for them.
# -g1: line tables and function names, all the reports print (file:line, inlined frames too),
# without the variable locations that cost a third of each file's compile time at -O1.
# FIELDLIDAR_UNITY: the module libraries and the CLI compiled in batches of files
# (cmake/FieldlidarUnity.cmake).
cmake -S . -B build/asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-g1 -O1 -Wno-maybe-uninitialized" \
  -DFIELDLIDAR_SANITIZE=ON -DFIELDLIDAR_UNITY=ON \
  -DFIELDLIDAR_BUILD_BENCHMARKS=OFF -DFIELDLIDAR_WERROR=ON -DFIELDLIDAR_BUILD_SLOW_TESTS=OFF >/dev/null
cmake --build build/asan -j "$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  LSAN_OPTIONS=suppressions="$PWD/tests/lsan.supp":print_suppressions=0 \
  ctest --test-dir build/asan --output-on-failure -j "$jobs" -LE "slow|fuzz" -E "^CliFollow\."

if command -v clang++ >/dev/null; then
  echo "== fuzz targets (clang, libFuzzer, ${FUZZ_SECONDS} s each) =="
  CC=clang CXX=clang++ cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=Debug \
    -DFIELDLIDAR_FUZZ=ON -DFIELDLIDAR_FUZZ_SECONDS="$FUZZ_SECONDS" -DBUILD_TESTING=ON \
    -DFIELDLIDAR_BUILD_BENCHMARKS=OFF -DFIELDLIDAR_BUILD_APPS=OFF >/dev/null
  cmake --build build/fuzz -j "$jobs" --target fuzz_all
  ctest --test-dir build/fuzz --output-on-failure -j "$jobs" -L fuzz
else
  echo "== fuzz targets skipped: clang++ not found =="
fi

echo "== Release build =="
scripts/build.sh
echo "== the installed package in a temporary prefix (no LD_LIBRARY_PATH) =="
scripts/check_install.sh build/release

echo "== Release tests =="
ctest --test-dir build/release --output-on-failure -j "$jobs" -LE fuzz
