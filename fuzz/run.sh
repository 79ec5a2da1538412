#!/usr/bin/env bash
# Runs each reader's fuzzer on its seed corpus for a bounded time: bash fuzz/run.sh BUILD_DIR [SECONDS].
# A crash, a sanitizer report, a hang (over 10 s per input) or a memory blow-up (over 2 GB) fails
# the run and leaves the input in fuzz/findings/; each one found becomes a regression test.
# The fuzzers run as many at a time as the machine has cores (each is single-threaded); every one
# gets its full SECONDS, and their reports are printed in the list's order.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=$1
seconds=${2:-30}
jobs=$(nproc)
mkdir -p "$here/findings"
work=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$work"' EXIT
targets=(scene_toml laser_log saturation_csv sensor_file vdb_header lidar_preset point_cloud mcap cdr ros1_bag)

# One fuzzer on a copy of its corpus; its exit status goes to $work/$t.status.
fuzz_one() {
  local t=$1 corpus="$work/$t.corpus" status=0
  mkdir -p "$corpus"
  cp "$here/corpus/$t/"* "$corpus/"
  if [ "$t" = vdb_header ]; then cp "$here/../volumes/"*.vdb "$corpus/"; fi
  "$build/fuzz_$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
    -artifact_prefix="$here/findings/${t}-" -print_final_stats=0 "$corpus" >"$work/$t.log" 2>&1 ||
    status=$?
  echo "$status" >"$work/$t.status"
}

for t in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do sleep 0.2; done
  fuzz_one "$t" &
done
wait
failed=0
for t in "${targets[@]}"; do
  echo "fuzz_$t: ${seconds} s"
  grep -E "Done [0-9]+ runs|ERROR|SUMMARY|crash-|timeout-|oom-|leak-" "$work/$t.log" || true
  status=$(cat "$work/$t.status" 2>/dev/null || echo "no status")
  if [ "$status" != 0 ]; then
    tail -40 "$work/$t.log"
    echo "fuzz_$t found a problem (exit $status): see fuzz/findings/"
    failed=1
  fi
done
[ "$failed" -eq 0 ] || exit 1
echo "fuzzers: no findings"
