#!/usr/bin/env bash
# Regenerates the golden files tests/parse_errors/NAME.expected: the exact output of
# `raycast NAME.txt OUT.bmp` run from tests/parse_errors/ (so file names in the messages are the
# bare NAME.txt, as the user typed it), the command tests/parse_errors_test.cpp runs and compares.
#
#   bash tools/update_parse_error_goldens.sh [path/to/raycast]     (default: build-tests/raycast)
#
# The test only checks that the output has not changed: it cannot tell a wrong message from a right
# one. After regenerating, READ every new or changed .expected by hand (git diff tests/parse_errors)
# and check the line, the column, the caret and the wording against the .txt before committing.
# Scenes named DISABLED_*.txt reproduce known bugs: their .expected files hold the CORRECT output,
# written by hand, and this script leaves them alone (the test is disabled until the bug is fixed;
# then drop the DISABLED_ prefix from both files and regenerate).
# The image goes to a temporary folder: a scene with an error must never produce one (the script
# warns if it does, and if raycast does not exit with status 1).
set -euo pipefail
cd "$(dirname "$0")/.."

raycast="${1:-build-tests/raycast}"
if [ ! -x "$raycast" ]; then
  echo "update_parse_error_goldens.sh: no raycast program at '$raycast': build it (bash tools/test.sh) or pass its path" >&2
  exit 2
fi
raycast="$(cd "$(dirname "$raycast")" && pwd)/$(basename "$raycast")"

out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

cd tests/parse_errors
count=0
for scene in *.txt; do
  name="${scene%.txt}"
  case "$name" in DISABLED_*) echo "kept hand-written $name.expected (known bug)"; continue ;; esac
  code=0
  "$raycast" "$scene" "$out/$name.bmp" >"$name.expected" 2>&1 || code=$?
  [ "$code" -eq 1 ] || echo "warning: $scene: raycast exited with status $code, not 1" >&2
  [ ! -e "$out/$name.bmp" ] || echo "warning: $scene: raycast wrote an image" >&2
  count=$((count + 1))
done
# Goldens whose scene is gone.
for golden in *.expected; do
  [ -e "${golden%.expected}.txt" ] || { rm -f "$golden"; echo "removed $golden: its scene is gone"; }
done
echo "wrote $count golden files in tests/parse_errors/: review every change by hand (git diff tests/parse_errors)"
