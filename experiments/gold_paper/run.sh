#!/usr/bin/env bash
# The gold paper reads long in smoke (the smoke paper, section 5: up to +10 % near the Hokuyo's
# threshold), which the paper model cannot produce. This worked example closes the loop on a run
# in which that effect is PLANTED (see README.md): a BOCAS run of the URG-04LX is simulated, the gold
# target's readings are lengthened by this script (not by smokescan), the run is diagnosed, the
# extended sensor file is rescanned, and the rescanned run is diagnosed with that file.
# One command; writes everything under out/ next to this script.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
[ -x "$top/build/smokescan" ] || bash "$top/scripts/setup.sh"
smokescan="$top/build/smokescan"
out="$here/out"
rm -rf "$out"
mkdir -p "$out"
# +10 % at the threshold column P = 0.007 density·m: reading × (1 + beta·column), beta = 0.10 / P.
beta=14.2857

echo "== 1. a BOCAS run (URG-04LX at 1 Hz, the camera's saturation at 5 Hz), every beam's truth kept"
"$smokescan" scan bocas --sensor urg04lx --rate 1 --seed 11 --quiet --out "$out/simulated.log" --tau "$out/beams.csv" \
  --saturation-out "$out/saturation.csv" --saturation-sigma 0.01 --saturation-rate 5

echo "== 2. planted: the gold's valid readings lengthened by beta x the smoke column (beta = $beta per density·m)"
awk -F, -v beta="$beta" '
  FNR == NR { if (FNR == 1) next
              if ($1 != last) { k++; last = $1 }
              if ($7 == "target_gold" && $5 == 0) v[k "," $2] = int($4 * (1 + beta * $9) + 0.5)
              next }
  /^#/ { print; next }
  { FS = " "; $0 = $0; k2++
    for (i = 0; 2 * i + 3 <= NF; i++) if ((k2 "," i) in v) $(2 * i + 3) = v[k2 "," i]
    print }' "$out/beams.csv" "$out/simulated.log" > "$out/recorded.log"

echo "== 3. diagnosed: what the paper model gets wrong, named, the extended model's held-out gain"
"$smokescan" diagnose --laser "$out/recorded.log" --saturation "$out/saturation.csv" --scene bocas \
  --out "$out/diagnosis" "$@"

echo "== 4. rescanned with the extended sensor file (another seed): the scan simulates what was learned"
"$smokescan" scan bocas --sensor urg04lx --rate 1 --seed 12 --quiet --sensor-file "$out/diagnosis/sensor.toml" \
  --out "$out/rescan.log" --saturation-out "$out/rescan_saturation.csv" --saturation-sigma 0.01 --saturation-rate 5

echo "== 5. the rescanned run diagnosed with that file: nothing more to name"
"$smokescan" diagnose --laser "$out/rescan.log" --saturation "$out/rescan_saturation.csv" --scene bocas \
  --sensor-file "$out/diagnosis/sensor.toml" --out "$out/rediagnosis" "$@"
