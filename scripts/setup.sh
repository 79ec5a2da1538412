#!/usr/bin/env bash
# Installs what smokescan needs from Debian 12's packages (only what is missing) and builds it.
# --no-build: install only (scripts/test.sh --sanitize builds its own tree).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
pkgs=(build-essential cmake ninja-build pkg-config
  libopenvdb-dev libopenvdb-tools libboost-iostreams-dev libembree-dev libtbb-dev
  libopenimageio-dev openimageio-tools libceres-dev libeigen3-dev
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev libtomlplusplus-dev libtinyobjloader-dev
  nlohmann-json3-dev fonts-dejavu-core clang clang-format libclang-rt-14-dev llvm
  python3-open3d zlib1g-dev libzstd-dev liblz4-dev libyaml-cpp-dev libbz2-dev
  librosbag-storage-dev libsensor-msgs-dev librcpputils-dev libament-index-cpp-dev python3-rosbag python3-sensor-msgs
  python3-tf2-msgs pybind11-dev python3-dev python3-numpy python3-pytest python3-distributed)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
fi
[ "${1:-}" = "--no-build" ] && exit 0
bash "$here/scripts/setup_readers.sh" "$here/build"
# SMOKESCAN_CMAKE_ARGS: extra configure options (CI: -DSMOKESCAN_WERROR=ON).
cmake -S "$here" -B "$here/build" -G Ninja -DCMAKE_BUILD_TYPE=Release ${SMOKESCAN_CMAKE_ARGS:-} >/dev/null
cmake --build "$here/build" -j "$(nproc)"
