#!/usr/bin/env bash
# Installs the Debian 12 packages fieldlidar needs to build, test and benchmark. Idempotent: does
# nothing when every package is already installed.
set -euo pipefail

packages=(
  build-essential cmake ninja-build git pkg-config
  libeigen3-dev libpcl-dev libnanoflann-dev libembree-dev libtbb-dev
  libcli11-dev libfmt-dev nlohmann-json3-dev libyaml-cpp-dev
  libcairo2-dev libpcap-dev librosbag-storage-dev pluginlib-dev libgdal-dev
  libgtest-dev libgmock-dev libbenchmark-dev libompl-dev libceres-dev
  clang libclang-rt-14-dev
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  exit 0
fi
echo "fieldlidar: installing Debian packages: ${missing[*]}"
SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
