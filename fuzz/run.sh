#!/usr/bin/env bash
# Runs each reader's fuzzer on its seed corpus for a bounded time: bash fuzz/run.sh BUILD_DIR [SECONDS].
# A crash, a sanitizer report, a hang (over 10 s per input) or a memory blow-up (over 2 GB) fails
# the run and leaves the input in fuzz/findings/; each one found becomes a regression test.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=$1
seconds=${2:-30}
mkdir -p "$here/findings"
for t in scene_toml laser_log saturation_csv sensor_file vdb_header lidar_preset point_cloud mcap cdr ros1_bag; do
  corpus=$(mktemp -d)
  log=$(mktemp)
  cp "$here/corpus/$t/"* "$corpus/"
  if [ "$t" = vdb_header ]; then cp "$here/../volumes/"*.vdb "$corpus/"; fi
  echo "fuzz_$t: ${seconds} s"
  status=0
  "$build/fuzz_$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
    -artifact_prefix="$here/findings/${t}-" -print_final_stats=0 "$corpus" >"$log" 2>&1 || status=$?
  grep -E "Done [0-9]+ runs|ERROR|SUMMARY|crash-|timeout-|oom-|leak-" "$log" || true
  if [ "$status" -ne 0 ]; then
    tail -40 "$log"
    echo "fuzz_$t found a problem (exit $status): see fuzz/findings/"
    rm -rf "$corpus" "$log"
    exit 1
  fi
  rm -rf "$corpus" "$log"
done
echo "fuzzers: no findings"
