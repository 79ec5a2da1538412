#!/usr/bin/env bash
# Checks that the C++ sources follow .clang-format (exit 1 naming the files that do not);
# exit 77 (skipped) when clang-format is not installed. Fix with: clang-format -i FILE...
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format >/dev/null || { echo "clang-format not installed: style not checked"; exit 77; }
files=$(git ls-files 'src/*.cpp' 'src/*.hpp' 'include/*.hpp' 'tests/*.cpp' 'tests/*.hpp' 'bench/*.cpp' 'fuzz/*.cpp' \
        'fuzz/*.hpp' 'volumes/*.cpp' 2>/dev/null || true)
[ -n "$files" ] || { echo "not a git checkout: style not checked"; exit 77; }
bad=()
for f in $files; do
  clang-format --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if [ ${#bad[@]} -gt 0 ]; then
  echo "not formatted (.clang-format): ${bad[*]}"
  exit 1
fi
echo "formatted: $(echo "$files" | wc -w) files"
