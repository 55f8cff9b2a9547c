#!/usr/bin/env bash
# Surfaces of revolution, exact or tessellated (docs/performance.md): the course's scene10 (two
# wine glasses; ../shared/course-pa3, else the project's scenes/revolution.txt) rendered at
# 1024x1024 on 2 threads as RevSurfaces, and as triangle meshes from raycast_revolve fine enough to
# look the same (at least 99.9% of the pixels within one level of the exact image, the bar of the
# course's references). Best of 3 runs each; a Markdown table on stdout.
#   bash bench/rev_surface.sh [BUILD]      (default build-bench; configured and built here)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
build=${1:-build-bench}

scene=$root/../shared/course-pa3/testcases/scene10_wineglass.txt
[ -f "$scene" ] || scene=$root/scenes/revolution.txt
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DRAYCAST_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" -j "$(nproc 2>/dev/null || echo 2)" --target raycast raycast_revolve >/dev/null
raycast=$root/$build/raycast
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

field() { sed -n "s/.* $2=\([^ ]*\).*/\1/p" <<<" $1"; }
# best LABEL SCENE [OPTIONS]: best of 3 renders; prints a table row.
best() {
    local label=$1 file=$2; shift 2
    local best_render="" line rss best_rss=""
    for _ in 1 2 3; do
        line=$(/usr/bin/time -f "rss=%M" "$raycast" "$file" "$work/out.ppm" --size 1024x1024 --threads 2 --stats -q "$@" 2>&1 |
               tr '\n' ' ')
        local render=$(field "$line" render_ms)
        rss=$(field "$line" rss)
        if [ -z "$best_render" ] || awk -v a="$render" -v b="$best_render" 'BEGIN { exit !(a < b) }'; then
            best_render=$render
            best_line=$line
            best_rss=$rss
        fi
    done
    local load=$(field "$best_line" load_ms) build_ms=$(field "$best_line" build_ms)
    printf '| %s | %s | %.0f | %.0f | %.0f | %.2f | %.0f |\n' "$label" "$(field "$best_line" triangles)" "$load" \
        "$build_ms" "$best_render" "$(field "$best_line" mrays_per_s)" "$(awk -v k="$best_rss" 'BEGIN { print k / 1024 }')"
}

echo "scene: $scene; load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| surfaces | triangles | load ms | build ms | render ms | Mrays/s | peak MiB |"
echo "|---|---|---|---|---|---|---|"
best "exact (RevSurface), packets" "$scene"
best "exact (RevSurface), --no-packets" "$scene" --no-packets
"$raycast" "$scene" "$work/exact.ppm" --size 1024x1024 -q
for grid in "320 160" "512 256"; do
    set -- $grid
    "$root/$build/raycast_revolve" "$scene" "$work/mesh_$1.txt" --along "$1" --around "$2" >/dev/null
    "$raycast" "$work/mesh_$1.txt" "$work/mesh.ppm" --size 1024x1024 -q
    off=$("$raycast" compare "$work/exact.ppm" "$work/mesh.ppm" | sed -n 's/pixels off by more than 1 level: //p')
    best "tessellated $1 × $2 ($off pixels off by more than 1), packets" "$work/mesh_$1.txt"
    best "tessellated $1 × $2, --no-packets" "$work/mesh_$1.txt" --no-packets
done
echo
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
