#!/usr/bin/env bash
# Re-renders tests/references/*.png from tests/image_regression_cases.txt. Run it only after a
# change that is meant to alter images, then look at every changed picture before committing:
# the image regression test trusts these files.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" --target raycast >/dev/null
grep -v '^#' tests/image_regression_cases.txt | while IFS='|' read -r name arguments scene; do
  name=$(echo "$name" | xargs); scene=$(echo "$scene" | xargs)
  # shellcheck disable=SC2086  # the arguments are meant to split
  build/raycast --quiet "$scene" "tests/references/$name.png" $arguments
  echo "tests/references/$name.png"
done
