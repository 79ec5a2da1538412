#!/usr/bin/env bash
# The omnicam paper's Table II: the omnicam rangefinder against the laser, scanline by scanline,
# over the robot's drive through the built-in maze (Θ = 0.05) and factory (Θ = 0.075). Trains the
# colour histogram from the laser's scans at three poses, then reads a frame every second; writes
# both logs per scene next to this script, the histogram of the differences (Fig. 9) and the
# occupancy grids of both sensors with the true poses (Fig. 10), and prints the mean absolute and
# percentage differences (paper: maze 0.1375 m / 7.64 %, factory 0.0809 m / 4.49 %), then each
# sensor against the ground truth, which the paper did not have (maze_truth.png, factory_truth.png).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
[ -x "$top/build/smokescan" ] || bash "$top/scripts/setup.sh"
spp=${SPP:-8}
echo "maze:"
"$top/build/smokescan" omnirange maze --train 0,20,44 --from 0 --to 60 --rate 1 --spp "$spp" --threshold 0.05 \
  --out "$here/maze_omnicam.log" --laser-out "$here/maze_laser.log" --save-histogram "$here/maze_histogram.txt" \
  --plot "$here/maze_fig9.png" --map "$here/maze_fig10.png" --fig8 "$here/fig8.png" \
  --truth "$here/maze_truth.png" "$@"
echo "factory:"
"$top/build/smokescan" omnirange factory --train 0,20,40 --from 0 --to 48 --rate 1 --spp "$spp" --threshold 0.075 \
  --out "$here/factory_omnicam.log" --laser-out "$here/factory_laser.log" --save-histogram "$here/factory_histogram.txt" \
  --plot "$here/factory_fig9.png" --map "$here/factory_fig10.png" --truth "$here/factory_truth.png" "$@"
