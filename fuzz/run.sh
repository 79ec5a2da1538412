#!/usr/bin/env bash
# Runs each reader's fuzzer on its seed corpus for a bounded time: bash fuzz/run.sh BUILD_DIR [SECONDS].
# A crash, a sanitizer report, a hang (over 10 s per input) or a memory blow-up (over 2 GB) fails
# the run and leaves the input in fuzz/findings/; each one found becomes a regression test.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=$1
seconds=${2:-30}
mkdir -p "$here/findings"
for t in scene_toml laser_log saturation_csv sensor_file vdb_header; do
  corpus=$(mktemp -d)
  cp "$here/corpus/$t/"* "$corpus/"
  [ "$t" = vdb_header ] && cp "$here/../volumes/"*.vdb "$corpus/"
  echo "fuzz_$t: ${seconds} s"
  "$build/fuzz_$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
    -artifact_prefix="$here/findings/${t}-" -print_final_stats=0 "$corpus" 2>&1 | grep -E "^#[0-9]+ +DONE|ERROR|SUMMARY|crash|timeout|oom" || true
  status=${PIPESTATUS[0]}
  rm -rf "$corpus"
  [ "$status" -eq 0 ] || { echo "fuzz_$t found a problem (exit $status): see fuzz/findings/"; exit 1; }
done
echo "fuzzers: no findings"
