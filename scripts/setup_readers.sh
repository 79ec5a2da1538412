#!/usr/bin/env bash
# Installs the independent readers the bag tests use (tests/js: Foxglove's @mcap/core and
# @foxglove/rosmsg2-serialization, versions pinned by its package-lock.json) into DIR/npm with
# the machine's node and npm. Without npm, or offline, it says so and the bag tests skip
# (CI sets SMOKESCAN_REQUIRE_READERS=1, which makes them fail instead).
# Usage: bash scripts/setup_readers.sh BUILD_DIR
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
dest="$1/npm"
if ! command -v npm >/dev/null || ! command -v node >/dev/null; then
  echo "node/npm not found: the bag tests' independent readers are not installed"
  exit 0
fi
mkdir -p "$dest"
cp "$here/tests/js/package.json" "$here/tests/js/package-lock.json" "$here"/tests/js/*.mjs "$dest/"
if [ -d "$dest/node_modules/@mcap/core" ] && cmp -s "$here/tests/js/package-lock.json" "$dest/node_modules/.package-lock.json.smokescan" 2>/dev/null; then
  exit 0
fi
log=$(mktemp)
if (cd "$dest" && npm ci --no-audit --no-fund >"$log" 2>&1); then
  cp "$here/tests/js/package-lock.json" "$dest/node_modules/.package-lock.json.smokescan"
else
  tail -5 "$log"
  echo "npm ci failed in $dest: the bag tests' independent readers are not installed"
fi
rm -f "$log"
