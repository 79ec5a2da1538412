#!/usr/bin/env bash
# Builds smokescan (installing what is missing) and runs its tests (labels: tests/CMakeLists.txt).
#   bash scripts/test.sh             every test, the Release build in build/ (CI's first leg)
#   bash scripts/test.sh --fast      the unit and cli tests only (the loop between commits: about
#                                    2 minutes on 2 cores)
#   bash scripts/test.sh --sanitize  the unit, cli, workflow and package tests built with clang,
#                                    AddressSanitizer and UndefinedBehaviorSanitizer in
#                                    build-sanitize/, then each reader's fuzzer for a bounded time
#                                    (fuzz/run.sh); the statistical tests are the Release leg's
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
if [ "${1:-}" = "--sanitize" ]; then
  "$here/scripts/setup.sh" --no-build
  cmake -S "$here" -B "$here/build-sanitize" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_CXX_COMPILER=clang++ -DSMOKESCAN_SANITIZE=ON -DSMOKESCAN_BUILD_FUZZ=ON \
    -DSMOKESCAN_BUILD_BENCH=OFF ${SMOKESCAN_CMAKE_ARGS:-} >/dev/null
  cmake --build "$here/build-sanitize" -j "$(nproc)"
  bash "$here/scripts/setup_readers.sh" "$here/build-sanitize"
  export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1:detect_container_overflow=0
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  (cd "$here/build-sanitize" && ctest --output-on-failure -j "$(nproc)" -L 'unit|cli|workflow|package')
  bash "$here/fuzz/run.sh" "$here/build-sanitize" "${SMOKESCAN_FUZZ_SECONDS:-30}"
  exit 0
fi
"$here/scripts/setup.sh"
cd "$here/build"
if [ "${1:-}" = "--fast" ]; then
  ctest --output-on-failure -j "$(nproc)" -L 'unit|cli'
else
  ctest --output-on-failure -j "$(nproc)"
fi
