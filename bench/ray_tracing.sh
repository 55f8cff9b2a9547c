#!/usr/bin/env bash
# The ray-tracing benchmark of docs/performance.md: how fast raycast traces every kind of ray, not
# only camera rays, counted as all rays traced (camera, shadow, reflected, transmitted) per second.
#   bash bench/ray_tracing.sh            # MIT 6.837's assignment-4 scenes (when ../shared is there)
#                                        # and a 1M-triangle mesh in a glass ball over a mirror floor
#   bash bench/ray_tracing.sh --quick    # the same with a 100k-triangle mesh
# Builds Release in build-bench/ (as bench/run.sh does), renders each scene at 1024x1024 on 2
# threads with --stats, best of 3, and prints a Markdown table (also build-bench/ray_tracing.md).
# Every figure is a wall-clock time: run it on an otherwise idle machine.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

triangles=1000000
for arg in "$@"; do
    case "$arg" in
        --quick) triangles=100000 ;;
        -h|--help) sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) echo "bench/ray_tracing.sh: unknown argument '$arg' (use --quick)" >&2; exit 2 ;;
    esac
done

build=build-bench
threads=2
repeat=3
log() { echo "bench: $*" >&2; }

log "building Release in $build/"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DRAYCAST_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" -j "$(nproc 2>/dev/null || echo 2)" --target raycast raycast_meshgen >/dev/null
raycast=$root/$build/raycast
mkdir -p "$build/meshes" "$build/out"

field() { sed -n "s/.* $2=\([^ ]*\).*/\1/p" <<<" $1"; }

# best_stats DIR ARGS...: runs raycast ARGS --stats in DIR `repeat` times; prints the stats line
# of the fastest render.
best_stats() {
    local dir=$1; shift
    local best="" best_ms=""
    for _ in $(seq "$repeat"); do
        local line
        line=$(cd "$dir" && "$raycast" "$@" --stats -q --threads "$threads")
        local ms
        ms=$(field "$line" render_ms)
        if [ -z "$best_ms" ] || awk -v a="$ms" -v b="$best_ms" 'BEGIN { exit !(a < b) }'; then
            best=$line
            best_ms=$ms
        fi
    done
    echo "$best"
}

rows=()
# row NAME OPTIONS DIR ARGS...: one table row from the best of `repeat` renders.
row() {
    local name=$1 options=$2 dir=$3; shift 3
    local line
    line=$(best_stats "$dir" "$@")
    local rays primary shadow secondary ms mrays
    rays=$(field "$line" rays)
    primary=$(field "$line" primary_rays)
    shadow=$(field "$line" shadow_rays)
    secondary=$(field "$line" secondary_rays)
    ms=$(field "$line" render_ms)
    mrays=$(field "$line" mrays_per_s)
    local per_pixel
    per_pixel=$(awk -v r="$rays" -v p="$primary" 'BEGIN { printf "%.2f", r / p }')
    rows+=("| $name | \`$options\` | $primary | $shadow | $secondary | $per_pixel | $(printf '%.0f' "$ms") | $mrays |")
    log "$name $options: $mrays Mrays/s"
}

# --- A mesh in a glass ball over a mirror floor -------------------------------------------------
mesh=$build/meshes/bumpy_rt_$triangles.obj
if [ ! -f "$mesh" ]; then
    log "generating a $triangles-triangle bumpy sphere"
    "$build/raycast_meshgen" bumpy-sphere "$triangles" "$mesh" --seed 1 >/dev/null
fi
cat >"$build/glass_$triangles.txt" <<EOF
# Written by bench/ray_tracing.sh: a bumpy sphere mesh inside a glass ball over a mirror floor.
PerspectiveCamera { center 0 1.2 6 direction 0 -0.2 -1 up 0 1 0 angle 35 width 1024 height 1024 }
Lights {
    numLights 2
    PointLight { position -4 6 5 color 0.8 0.8 0.75 }
    DirectionalLight { direction 0.4 -1 -0.5 color 0.3 0.3 0.35 }
}
Background { color 0.4 0.5 0.7 }
Materials {
    numMaterials 3
    Material { diffuseColor 0.4 0.4 0.4 reflectiveColor 0.5 0.5 0.5 }
    Material { diffuseColor 0 0 0 specularColor 0.8 0.8 0.8 shininess 80
               reflectiveColor 0.1 0.1 0.1 transparentColor 0.9 0.9 0.9 indexOfRefraction 1.5 }
    Material { diffuseColor 0.8 0.4 0.2 specularColor 0.3 0.3 0.3 shininess 20 }
}
Group {
    numObjects 3
    MaterialIndex 0
    Plane { normal 0 1 0 offset -1.5 }
    MaterialIndex 1
    Sphere { center 0 0 0 radius 1.45 }
    MaterialIndex 2
    Transform { UniformScale 0.8 TriangleMesh { obj_file meshes/$(basename "$mesh") } }
}
EOF
row "mesh ($triangles triangles) in glass, mirror floor" "(camera rays only)" "$build" "glass_$triangles.txt" out/glass.bmp
row "mesh ($triangles triangles) in glass, mirror floor" "--shadows" "$build" "glass_$triangles.txt" out/glass.bmp --shadows
row "mesh ($triangles triangles) in glass, mirror floor" "--shadows --bounces 5" "$build" "glass_$triangles.txt" out/glass.bmp --shadows --bounces 5
row "mesh ($triangles triangles) in glass, mirror floor" "--shadows --transparent-shadows --bounces 5" "$build" "glass_$triangles.txt" out/glass.bmp --shadows --transparent-shadows --bounces 5

# --- MIT 6.837 assignment 4, at 1024x1024 with the course's own options -----------------------------
a4=../shared/reference/mit6837-f04/a4
if [ -d "$a4" ]; then
    for scene in scene4_03_mirrored_floor scene4_05_transparent_bar scene4_07_transparent_sphere_1.0 \
                 scene4_09_transparent_sphere_2.0 scene4_14_faceted_gem; do
        case "$scene" in
            scene4_03*) options="-shadows -bounces 1 -weight 0.01" ;;
            scene4_05*) options="-shadows -bounces 10 -weight 0.01 -shade_back" ;;
            scene4_14*) options="-shadows -shade_back -bounces 5 -weight 0.01" ;;
            *) options="-shadows -bounces 5 -weight 0.01 -shade_back" ;;
        esac
        # shellcheck disable=SC2086
        row "MIT $scene" "$options" "$a4" -input "$scene.txt" -size 1024 1024 -output "$root/$build/out/a4.ppm" $options
    done
else
    log "../shared is not here: no MIT assignment-4 rows"
fi

{
    echo "Ray tracing, $(date -u +%Y-%m-%d), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'),"
    echo "$threads threads, 1024x1024, best of $repeat, commit $(git rev-parse --short HEAD 2>/dev/null || echo '?'), load average $(cut -d' ' -f1-3 /proc/loadavg)"
    echo
    echo "| scene | options | camera rays | shadow rays | reflected + transmitted | rays per camera ray | render ms | Mrays/s (all rays) |"
    echo "|---|---|---:|---:|---:|---:|---:|---:|"
    printf '%s\n' "${rows[@]}"
} | tee "$build/ray_tracing.md"
