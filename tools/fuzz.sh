#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/) with clang, ASan and UBSan in build-fuzz/, puts the seed
# inputs into build-fuzz/corpus-<target>/ and fuzzes each target for SECONDS (default 60).
#   bash tools/fuzz.sh [SECONDS]                           # what CI runs: bash tools/fuzz.sh 60
#   FUZZ_TARGETS="fuzz_obj_loader" bash tools/fuzz.sh 600  # only some targets
# The corpus folders are kept between runs, so repeated runs grow them (delete them to start
# afresh). Prints, per target, the executions, exec/s, coverage (cov: and ft: of libFuzzer's
# last stats line) and corpus size. Exits 1 when any target finds a crash, sanitizer report,
# leak, timeout or out-of-memory input, and prints the path of the input that shows it
# (build-fuzz/findings-<target>/); see docs/reliability.md for reproducing and minimising.
# Before fuzzing, each target runs the minimised inputs of past findings, fuzz/regressions/<target>-*.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds="${1:-60}"
case "$seconds" in
  '' | *[!0-9]*)
    echo "usage: bash tools/fuzz.sh [SECONDS_PER_TARGET]" >&2
    exit 2
    ;;
esac
targets=(${FUZZ_TARGETS:-fuzz_scene_parser fuzz_obj_loader fuzz_image_decode fuzz_render_pipeline fuzz_view_query})
build=build-fuzz
max_len=65536

bash tools/install_test_deps.sh --fuzz

jobs="$(nproc 2>/dev/null || echo 2)"
CC=clang CXX=clang++ cmake -S . -B "$build" -DRAYCAST_FUZZ=ON -DRAYCAST_BUILD_TESTS=OFF \
  -DRAYCAST_SANITIZE=address,undefined -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" -j "$jobs" --target raycast "${targets[@]}"
bash fuzz/seed_corpus.sh "$build"

export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export ASAN_OPTIONS="abort_on_error=1:detect_leaks=1"

failed=0
summary=()
for target in "${targets[@]}"; do
  corpus="$build/corpus-$target"
  findings="$build/findings-$target"
  log="$build/fuzz-$target.log"
  mkdir -p "$corpus" "$findings"
  extra=()
  [ "$target" = fuzz_scene_parser ] && extra+=(-dict=fuzz/scene.dict)
  [ "$target" = fuzz_view_query ] && extra+=(-dict=fuzz/view.dict)
  target_max_len="$max_len"
  [ "$target" = fuzz_view_query ] && target_max_len=4096  # it reads no longer input
  # First the inputs of past findings (fuzz/regressions/<target>-*): each must now pass.
  regressions=(fuzz/regressions/"$target"-*)
  if [ -e "${regressions[0]}" ]; then
    if ! "$build/fuzz/$target" "${regressions[@]}" >"$build/regressions-$target.log" 2>&1; then
      failed=1
      echo "fuzz.sh: $target fails on a past finding in fuzz/regressions/:" >&2
      grep -E 'Running: |ERROR: |FINDING: |runtime error: |SUMMARY: ' "$build/regressions-$target.log" | tail -n 20 >&2 || true
      summary+=("$target: FAILED on fuzz/regressions/ (log: $build/regressions-$target.log)")
      continue
    fi
  fi
  echo "fuzz.sh: $target for ${seconds}s (log: $log)"
  status=0
  "$build/fuzz/$target" "$corpus" "${extra[@]}" -max_total_time="$seconds" -max_len="$target_max_len" -timeout=10 \
    -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$findings/" >"$log" 2>&1 || status=$?

  stats_line="$(grep -E '(pulse|NEW|REDUCE|DONE|INITED).*cov: ' "$log" | tail -n 1 || true)"
  cov="$(sed -nE 's/.* cov: ([0-9]+).*/\1/p' <<<"$stats_line")"
  ft="$(sed -nE 's/.* ft: ([0-9]+).*/\1/p' <<<"$stats_line")"
  runs="$(sed -nE 's/^stat::number_of_executed_units: *([0-9]+).*/\1/p' "$log" | tail -n 1)"
  rate="$(sed -nE 's/^stat::average_exec_per_sec: *([0-9]+).*/\1/p' "$log" | tail -n 1)"
  files="$(find "$corpus" -type f | wc -l)"
  bytes="$(du -sk "$corpus" | cut -f1)"
  line="$target: ${runs:-?} executions, ${rate:-?} exec/s, cov ${cov:-?}, ft ${ft:-?}, corpus $files files (${bytes} KiB)"
  artifacts="$(sed -nE 's/.*Test unit written to (.*)$/\1/p' "$log")"
  if [ "$status" -ne 0 ] || [ -n "$artifacts" ]; then
    failed=1
    line="$line: FAILED (libFuzzer exit $status)"
    echo "fuzz.sh: $target FAILED; the report:" >&2
    grep -E 'ERROR: |FINDING: |runtime error: |SUMMARY: |deadly signal|internal error' "$log" | head -n 20 >&2 || true
    if [ -n "$artifacts" ]; then
      while IFS= read -r artifact; do
        echo "fuzz.sh: input that shows it: $artifact" >&2
        echo "fuzz.sh: reproduce: $build/fuzz/$target $artifact" >&2
      done <<<"$artifacts"
    else
      tail -n 30 "$log" >&2
    fi
  fi
  summary+=("$line")
done

echo
echo "fuzz.sh: summary (${seconds}s per target)"
printf '  %s\n' "${summary[@]}"
if [ "$failed" -ne 0 ]; then
  echo "fuzz.sh: FAILED: see the inputs listed above (in $build/findings-*/)" >&2
  exit 1
fi
