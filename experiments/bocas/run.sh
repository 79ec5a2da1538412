#!/usr/bin/env bash
# The smoke paper's BOCAS run 1 (section 3, Fig. 5), paper model: a Hokuyo URG-04LX 2.5 m from the
# paper target while a smoke machine runs for 10 s and later 40 s. Writes the laser log and the
# per-beam optical-depth table next to this script and prints the error-code summary.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
[ -x "$top/build/smokescan" ] || bash "$top/scripts/setup.sh"
"$top/build/smokescan" scan bocas --sensor urg04lx --from 0 --to 360 --rate 3 \
  --out "$here/bocas_urg04lx.log" --tau "$here/bocas_urg04lx_tau.csv" "$@"
