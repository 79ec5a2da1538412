#!/usr/bin/env bash
# Fitting the Hokuyo's smoke threshold from a recorded run, as the smoke paper's authors did by hand
# for BOCAS: a run simulated with known penetration power 0.007 density·m (the laser log at 10 Hz,
# the camera's target saturation at 10 Hz with noise 0.01 and its clock 4.2 s ahead) is fitted back.
# Writes the sensor file, report, aligned streams, covariates and Fig. 5/9 next to this script.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
[ -x "$top/build/smokescan" ] || bash "$top/scripts/setup.sh"
"$top/build/smokescan" scan bocas --sensor urg04lx --rate 10 --seed 3 --quiet --out "$here/run.log" \
  --saturation-out "$here/saturation.csv" --saturation-sigma 0.01 --saturation-rate 10 --camera-offset 4.2
"$top/build/smokescan" fit --laser "$here/run.log" --saturation "$here/saturation.csv" --scene bocas \
  --out "$here/fitted_urg04lx.toml" --aligned "$here/aligned.csv" --covariates "$here/covariates.csv" "$@"
