#!/usr/bin/env bash
# The smoke paper's Fig. 7: density ↔ saturation of the BOCAS target, from rendered frames, fitted
# with Ceres. Writes calibration.json and fig7.png next to this script (the committed reference is
# calib/bocas.json). About 85 s on 2 cores.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
[ -x "$top/build/smokescan" ] || bash "$top/scripts/setup.sh"
"$top/build/smokescan" calibrate bocas --out "$here/calibration.json" --plot "$here/fig7.png" "$@"
