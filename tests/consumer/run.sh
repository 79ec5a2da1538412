#!/usr/bin/env bash
# Installs the build tree into a scratch prefix, builds tests/consumer against it with
# find_package(smokescan) and runs it. Usage: run.sh BUILD_DIR SCRATCH_DIR [CXX [LINK_FLAGS]]
set -euo pipefail
build=$1 scratch=$2 cxx=${3:-c++} link_flags=${4:-}
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$scratch" && mkdir -p "$scratch"
cmake --install "$build" --prefix "$scratch/prefix" >/dev/null
cmake -S "$here" -B "$scratch/build" -DCMAKE_PREFIX_PATH="$scratch/prefix" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_EXE_LINKER_FLAGS="$link_flags" >/dev/null
cmake --build "$scratch/build" >/dev/null
"$scratch/build/consumer"
