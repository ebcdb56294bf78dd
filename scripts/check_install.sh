#!/usr/bin/env bash
# Installs a build (default build/release) into a fresh temporary prefix and uses it as a user
# would, with no LD_LIBRARY_PATH: `fieldlidar --help`, `fieldlidar legs` with its shipped
# classifier (on ../shared/data/legs_2d when it is there) and the consumer project
# examples/consumer built against the installed package with find_package(fieldlidar).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/release}
unset LD_LIBRARY_PATH
prefix=$(mktemp -d "${TMPDIR:-/tmp}/fieldlidar_install.XXXXXX")
trap 'rm -rf "$prefix"' EXIT
prefix=$(cd "$prefix" && pwd -P)
cmake --install "$build" --prefix "$prefix" >/dev/null

"$prefix/bin/fieldlidar" --help >/dev/null
echo "installed fieldlidar --help: ok"

bag="${FIELDLIDAR_DATA_DIR:-../shared/data}/legs_2d/positive_1_extracted.bag"
if [ -f "$bag" ]; then
  out=$("$prefix/bin/fieldlidar" legs "$bag" --topic /training_scan --out "$prefix/legs.csv")
  echo "$out"
  classifier="$prefix/share/fieldlidar/config/legs_2d_classifier.yaml"
  if ! grep -qF "classifier $classifier" <<<"$out"; then
    echo "installed fieldlidar legs did not use its shipped classifier $classifier" >&2
    exit 1
  fi
  echo "installed fieldlidar legs with its shipped classifier: ok"
else
  echo "installed fieldlidar legs: skipped, $bag is absent"
fi

cmake -S examples/consumer -B "$prefix/consumer_build" -G Ninja \
  -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$prefix/consumer_build" >/dev/null
"$prefix/consumer_build/consumer_example"
echo "consumer example against the installed package: ok"
