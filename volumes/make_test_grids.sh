#!/usr/bin/env bash
# Regenerates volumes/fog_ball_float.vdb and volumes/ramp_block_double.vdb (the grids the tests
# read) from volumes/make_test_grids.cpp, with OpenVDB. Needs a configured build/ (scripts/setup.sh).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cmake --build "$here/build" --target smokescan_make_test_grids
"$here/build/smokescan_make_test_grids" "$here/volumes"
