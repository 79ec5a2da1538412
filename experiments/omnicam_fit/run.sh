#!/usr/bin/env bash
# The omnicam's smoke onset fitted from its own log, as the smoke paper fitted the lasers'
# (docs/omnicam.md, "Its onset, fitted"). A robot stands in the court (smoky_court.toml) while a
# smoke machine fills it for 30 s and the smoke clears. A URG-04LX scans at 2 Hz and a camera
# watches a blue paper target on the east wall (its saturation predicted from the smoke on its line
# of sight, with noise 0.003); the omnicam, trained in clear air at t = 0, reads every RATE⁻¹ s from
# frames rendered through the smoke. `smokescan fit` then reads each log against the saturation:
# the URG's error codes on the target (its penetration power is set to 0.007 in the scene: a
# calibration, so its fit is a check), and the omnicam's readings that are more than 0.3 m off the
# court's truth, per wall. Then `smokescan diagnose` replays the omnicam's log with that onset as a
# laser's threshold and names what it gets wrong (diagnosis/report.md). About 4 min on two cores
# (SPP=32: the frames with less noise, about 12 min).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
[ -x "$top/build/smokescan" ] || bash "$top/scripts/setup.sh"
spp=${SPP:-8}
rate=${RATE:-0.5}
scene="$here/smoky_court.toml"
run() { "$top/build/smokescan" "$@"; }
{
  run scan "$scene" --sensor urg --rate 2 --out "$here/urg.log" --saturation-out "$here/saturation.csv" \
    --camera target_camera --saturation-rate 2 --saturation-sigma 0.003
  run omnirange "$scene" --train 0 --rate "$rate" --spp "$spp" --laser sick --out "$here/omnicam.log" \
    --truth "$here/versus_smoke.png"
  echo
  echo "the URG-04LX on the target:"
  run fit --laser "$here/urg.log" --saturation "$here/saturation.csv" --scene "$scene" --sensor urg \
    --out "$here/urg_fit.toml"
  echo
  echo "the omnicam, per wall:"
  run fit --laser "$here/omnicam.log" --saturation "$here/saturation.csv" --scene "$scene" \
    --sensor-type omnicam --sensor omni --target-prefix wall_ --out "$here/omnicam_fit.toml"
  echo
  echo "what the omnicam does in smoke that a laser's threshold does not:"
  rm -rf "$here/diagnosis"
  run diagnose --laser "$here/omnicam.log" --saturation "$here/saturation.csv" --scene "$scene" \
    --camera target_camera --sensor-type omnicam --sensor-file "$here/omnicam_fit.toml" --out "$here/diagnosis"
} | tee "$here/results.txt.part"
mv "$here/results.txt.part" "$here/results.txt"
