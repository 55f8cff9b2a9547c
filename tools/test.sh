#!/usr/bin/env bash
# Builds raycast with its tests and runs them all: the command the README gives and CI calls.
#   bash tools/test.sh              # Release build in build-tests/, warnings are errors
#   bash tools/test.sh --sanitize   # the same under AddressSanitizer + UBSan, in build-asan/
# Tests that need ../shared (the course's scenes and reference images) skip when it is absent.
set -euo pipefail
cd "$(dirname "$0")/.."

mode="${1:-release}"
bash tools/install_test_deps.sh

jobs="$(nproc 2>/dev/null || echo 2)"
case "$mode" in
  release|"")
    build=build-tests
    cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DRAYCAST_WERROR=ON >/dev/null
    ;;
  --sanitize)
    build=build-asan
    # RelWithDebInfo keeps the sanitizer build fast enough for the image tests and gives
    # symbolised reports.
    cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRAYCAST_WERROR=ON \
          -DRAYCAST_SANITIZE=address,undefined >/dev/null
    export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
    ;;
  *)
    echo "usage: bash tools/test.sh [--sanitize]" >&2
    exit 2
    ;;
esac

cmake --build "$build" -j "$jobs"
(cd "$build" && ctest -j "$jobs" --output-on-failure --timeout 600)
