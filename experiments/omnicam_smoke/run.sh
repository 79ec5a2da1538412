#!/usr/bin/env bash
# The omnicam rangefinder beside the lasers, in and out of smoke (docs/omnicam.md, "In smoke").
# The robot learns its floor in clear air: the factory drive trains the colour histogram from the
# Sick's scans at three poses and reads every second, against the truth as well as the laser. Then
# the same drive through the hall filling with smoke (built-in scene factory_smoke: a thin haze
# and a plume from beside the machine; a URG-04LX above the Sick, both lasers on the physical
# model), read with that histogram at its exposure. Each sensor's failure rate and range error
# against the smoke column it looks through, in one figure (versus_smoke.png); the tables are
# printed and kept in tables.txt.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
[ -x "$top/build/smokescan" ] || bash "$top/scripts/setup.sh"
spp=${SPP:-8}
rate=${RATE:-1}
{
  echo "clear factory (Θ = 0.075):"
  "$top/build/smokescan" omnirange factory --train 0,20,40 --rate "$rate" --spp "$spp" --threshold 0.075 \
    --out "$here/clear_omnicam.log" --save-histogram "$here/clear_histogram.txt" \
    --truth "$here/versus_clear.png" "$@"
  echo
  echo "the same drive in smoke:"
  "$top/build/smokescan" omnirange factory_smoke --histogram "$here/clear_histogram.txt" --rate "$rate" \
    --spp "$spp" --threshold 0.075 --out "$here/smoke_omnicam.log" --laser-out "$here/smoke_sick.log" \
    --truth "$here/versus_smoke.png" "$@"
} | tee "$here/tables.txt.part"
mv "$here/tables.txt.part" "$here/tables.txt"
