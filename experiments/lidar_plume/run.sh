#!/usr/bin/env bash
# One frame of the plume scene (smoke clouds drifting before walls, t = 20 s) from 3D lidars,
# mounted where the scene's Sick LMS200 stands, looking where it looks. Writes next to this script:
#  - os1_128/000000.pcd, os1_range.png, os1_top.png: an Ouster OS1-128, dual return;
#  - first_top.png, last_top.png: a generic 32-channel lidar's first and last returns.
# The README's pictures are these (copied to docs/images/ by `run.sh --docs`).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
[ -x "$top/build/smokescan" ] || bash "$top/scripts/setup.sh"
s="$top/build/smokescan"
for d in os1_128 first last; do rm -rf "${here:?}/$d"; done
"$s" scan plume --sensor os1-128 --returns dual --from 20 --points "$here/os1_128" \
  --range-image "$here/os1_range.png" --top-view "$here/os1_top.png" --top-view-width 8
for mode in first last; do
  "$s" scan plume --sensor "$here/first_last.toml" --returns $mode --from 20 --points "$here/$mode" \
    --top-view "$here/${mode}_top.png" --top-view-width 8
done
if [ "${1:-}" = "--docs" ]; then
  for f in os1_range os1_top first_top last_top; do cp "$here/$f.png" "$top/docs/images/lidar_$f.png"; done
fi
