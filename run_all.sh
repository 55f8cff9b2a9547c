#!/usr/bin/env bash
# Builds raycast with CMake (Release) and renders the seven test scenes into output/, as the
# course's run_all.sh does: testcases/sceneNN_<name>.txt -> output/sceneNN.bmp, run from the
# folder that holds testcases/ and mesh/. The course's own file names are used when present
# (drop the course's testcases/ and mesh/ here to render its scenes); otherwise the project's
# own scene with that number.
set -u
cd "$(dirname "$0")"

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null || { echo "run_all.sh: cmake configure failed" >&2; exit 1; }
cmake --build build --target raycast --parallel "$jobs" >/dev/null || {
    echo "run_all.sh: build failed; rerun 'cmake --build build --target raycast' to see why" >&2
    exit 1
}

course_names=(scene01_basic scene02_cube scene03_sphere scene04_axes scene05_bunny_200 scene06_bunny_1k scene07_shine)
mkdir -p output
failed=0
for i in 1 2 3 4 5 6 7; do
    number=$(printf '%02d' "$i")
    scene="testcases/${course_names[$((i - 1))]}.txt"
    if [ ! -f "$scene" ]; then
        matches=(testcases/scene"${number}"_*.txt)
        scene=${matches[0]}
    fi
    if [ ! -f "$scene" ]; then
        echo "run_all.sh: no testcases/scene${number}_*.txt" >&2
        failed=1
        continue
    fi
    if build/raycast "$scene" "output/scene${number}.bmp"; then
        echo "rendered $scene -> output/scene${number}.bmp"
    else
        failed=1
    fi
done
exit "$failed"
