#!/usr/bin/env bash
# Are the fit's reported errors the right size? RUNS independent BOCAS runs (their own seeds, from
# SEED0; the URG-04LX at 2 Hz, the paper model at P = 0.007, the camera's target saturation at
# 10 Hz with noise SIGMA and its clock 7.3 s ahead) are fitted, and the pulls (fitted − true)/error
# of the clock offset and of S* (one strip per run, in turn: a run's strips share its saturation
# series) are pooled. S*'s truth is the fit of the same run with noise-free saturation (its own
# scatter is a fifteenth of the noisy one's; docs/fitting.md). Unit pulls: mean 0, spread 1.
# Prints the pulls' mean and spread; the runs' logs stay in a temporary folder.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
[ -x "$top/build/smokescan" ] || bash "$top/scripts/setup.sh"
runs=${RUNS:-40}
seed0=${SEED0:-1000}
sigma=${SIGMA:-0.01}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
s="$top/build/smokescan"
for ((k = 0; k < runs; k++)); do
  seed=$((seed0 + k))
  for noise in "$sigma" 0; do
    "$s" scan bocas --sensor urg04lx --rate 2 --seed "$seed" --quiet --out "$work/run_$noise.log" \
      --saturation-out "$work/sat_$noise.csv" --saturation-sigma "$noise" --saturation-rate 10 --camera-offset 7.3 >/dev/null
    "$s" fit --laser "$work/run_$noise.log" --saturation "$work/sat_$noise.csv" --scene bocas \
      --out "$work/fit_$noise.toml" >/dev/null
  done
  python3 - "$work/fit_$sigma""_report.json" "$work/fit_0_report.json" "$k" >>"$work/pulls.txt" <<'PY'
import json, sys
fit, ref, k = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), int(sys.argv[3])
off = fit["offset"]["offset_s"]
g = k % len(fit["groups"])
th, th0 = fit["groups"][g]["threshold"], ref["groups"][g]["threshold"]
print((off["value"] - 7.3) / off["std_error"], (th["S_star"]["value"] - th0["S_star"]["value"]) / th["S_star"]["std_error"])
PY
done
python3 - "$work/pulls.txt" "$runs" "$seed0" "$sigma" <<'PY'
import statistics, sys
rows = [tuple(map(float, l.split())) for l in open(sys.argv[1])]
print(f"{len(rows)} runs from seed {sys.argv[3]}, saturation noise {sys.argv[4]}")
for i, name in enumerate(["offset", "S*"]):
    v = [r[i] for r in rows]
    print(f"{name:7s} pulls: mean {statistics.mean(v):+.2f}, spread {statistics.stdev(v):.2f}")
PY
