#!/usr/bin/env bash
# The smoke paper's Fig. 10 (section 5): a Sick LMS200 in the open while smoke clouds drift across
# its field on a slow wind, paper model. Writes the laser log and the Fig. 10-style picture next to
# this script.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
[ -x "$top/build/smokescan" ] || bash "$top/scripts/setup.sh"
"$top/build/smokescan" scan plume --sensor lms200 --from 0 --to 150 --rate 2 \
  --out "$here/plume_lms200.log" --image "$here/plume_lms200.png" --image-range 8 "$@"
