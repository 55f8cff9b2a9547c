#!/usr/bin/env bash
# The performance benchmark of docs/performance.md, rerunnable on any machine:
#   bash bench/run.sh            # bumpy spheres of 1k, 100k, 1M and 5M triangles, then the course scenes
#   bash bench/run.sh --quick    # 1k and 100k only
# Builds Release in build-bench/, generates the meshes once (cached in build-bench/meshes/), renders
# each at 1024x1024 on 2 threads with --stats, runs raycast_embree_bench and raycast_tinyobj_bench on
# the same meshes when they were built (libembree-dev, libtinyobjloader-dev), and prints Markdown
# tables, also written to build-bench/results.md. Run it on a quiet machine: every figure is a
# wall-clock time.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

quick=0
for arg in "$@"; do
    case "$arg" in
        --quick) quick=1 ;;
        -h|--help) sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) echo "bench/run.sh: unknown argument '$arg' (use --quick)" >&2; exit 2 ;;
    esac
done

build=build-bench
threads=2
size=1024x1024
repeat=3
seed=1
log() { echo "bench: $*" >&2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# --- Build ----------------------------------------------------------------------------------
log "building Release in $build/"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DRAYCAST_BUILD_TESTS=OFF >"$tmp/configure.log" 2>&1 || {
    cat "$tmp/configure.log" >&2; exit 1; }
cp "$tmp/configure.log" "$build/configure.log"
cmake --build "$build" -j "$(nproc 2>/dev/null || echo 2)" >"$build/build.log" 2>&1 || {
    tail -30 "$build/build.log" >&2; echo "bench/run.sh: build failed (see $build/build.log)" >&2; exit 1; }
raycast=$root/$build/raycast
meshgen=$root/$build/raycast_meshgen
embree_bench=$root/$build/bench/raycast_embree_bench
tinyobj_bench=$root/$build/bench/raycast_tinyobj_bench
[ -x "$embree_bench" ] || { embree_bench=""; log "raycast_embree_bench was not built (no libembree-dev): no Embree columns"; }
[ -x "$tinyobj_bench" ] || { tinyobj_bench=""; log "raycast_tinyobj_bench was not built (no libtinyobjloader-dev): no tinyobjloader column"; }

# Peak memory comes from GNU time's %M (maximum resident set size, KiB).
if [ ! -x /usr/bin/time ] && command -v apt-get >/dev/null && [ "$(id -u)" = 0 ]; then
    log "installing GNU time for peak-memory figures"
    apt-get install -y time >/dev/null 2>&1 || true
fi
have_time=0
[ -x /usr/bin/time ] && have_time=1
[ "$have_time" = 1 ] || log "/usr/bin/time is missing: no peak-memory figures (apt-get install time)"

mkdir -p "$build/meshes" "$build/out"

# --- Helpers ----------------------------------------------------------------------------------
# field LINE KEY: the value of KEY=value in a key=value line.
field() { sed -n "s/.* $2=\([^ ]*\).*/\1/p" <<<" $1"; }
# calc EXPR: floating-point arithmetic.
calc() { awk "BEGIN { printf \"%s\", $1 }" </dev/null; }
fmt() { awk -v x="$2" "BEGIN { printf \"$1\", x }" </dev/null; }
min() { awk -v a="$1" -v b="$2" 'BEGIN { print (a == "" || b + 0 < a + 0) ? b : a }' </dev/null; }
max() { awk -v a="$1" -v b="$2" 'BEGIN { print (a == "" || b + 0 > a + 0) ? b : a }' </dev/null; }
now() { if [ -n "${EPOCHREALTIME:-}" ]; then echo "${EPOCHREALTIME/,/.}"; else date +%s.%N; fi; }

# timed DIR CMD...: runs CMD in DIR; sets run_out (stdout), run_wall_ms and run_rss_kib (or "").
timed() {
    local dir=$1; shift
    local start end status=0
    start=$(now)
    if [ "$have_time" = 1 ]; then
        (cd "$dir" && /usr/bin/time -f %M -o "$tmp/rss" "$@" >"$tmp/out" 2>"$tmp/err") || status=$?
    else
        (cd "$dir" && "$@" >"$tmp/out" 2>"$tmp/err") || status=$?
    fi
    end=$(now)
    run_out=$(cat "$tmp/out")
    run_wall_ms=$(calc "($end - $start) * 1000")
    run_rss_kib=""
    [ "$have_time" = 1 ] && run_rss_kib=$(tail -1 "$tmp/rss")
    if [ "$status" != 0 ]; then
        log "failed (exit $status): $*"
        sed 's/^/    /' "$tmp/err" >&2
    fi
    return "$status"
}

# --- Meshes and scenes ------------------------------------------------------------------------
# A camera at distance d on the z axis looking at the origin sees a sphere of radius R under the
# angular radius asin(R/d); with a vertical field of view F on a square image the sphere's disc
# covers pi/4 * (tan(asin(R/d)) / tan(F/2))^2 of the frame. Solving for 40% with R = 1 (the bumpy
# sphere's mean radius) and F = 30 degrees gives d:
fov=30
distance=$(awk -v f="$fov" 'BEGIN { pi = atan2(0, -1); k = sqrt(0.4 * 4 / pi) * sin(f * pi / 360) / cos(f * pi / 360);
    a = atan2(k, 1); printf "%.4f", 1 / sin(a) }')

write_scene() {  # write_scene NAME: build-bench/NAME.txt frames meshes/NAME.obj
    cat >"$build/$1.txt" <<EOF
# Written by bench/run.sh: a bumpy sphere (radius about 1) filling about 40% of the frame.
PerspectiveCamera {
    center 0 0 $distance
    direction 0 0 -1
    up 0 1 0
    angle $fov
    width 1024
    height 1024
}
Lights {
    numLights 1
    DirectionalLight {
        direction -0.5 -0.6 -1
        color 0.9 0.9 0.9
    }
}
Background {
    color 0.1 0.1 0.15
    ambientLight 0.1 0.1 0.1
}
Materials {
    numMaterials 1
    PhongMaterial {
        diffuseColor 0.7 0.6 0.5
        specularColor 0.3 0.3 0.3
        shininess 20
    }
}
Group {
    numObjects 1
    MaterialIndex 0
    TriangleMesh {
        obj_file meshes/$1.obj
    }
}
EOF
}

make_mesh() {  # make_mesh NAME TRIANGLES: cached; regenerated when the seed or count changed
    local obj=$build/meshes/$1.obj
    if [ -f "$obj" ] && head -1 "$obj" | grep -q "bumpy-sphere .* seed $seed\$" && [ -f "$obj.target" ] &&
        [ "$(cat "$obj.target")" = "$2" ]; then
        return 0
    fi
    log "generating $obj ($2 triangles, seed $seed)"
    "$meshgen" bumpy-sphere "$2" "$obj.partial" --seed "$seed" >/dev/null
    mv "$obj.partial" "$obj"
    echo "$2" >"$obj.target"
}

names=(bumpy_1k bumpy_100k bumpy_1m bumpy_5m)
counts=(1000 100000 1000000 5000000)
if [ "$quick" = 1 ]; then
    names=(bumpy_1k bumpy_100k)
    counts=(1000 100000)
fi

# --- Machine ----------------------------------------------------------------------------------
cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -1)
[ -n "$cpu" ] || cpu=$(uname -m)
compiler_path=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$build/CMakeCache.txt")
[ -n "$compiler_path" ] || compiler_path=c++
compiler=$("$compiler_path" --version 2>/dev/null | head -1)
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
[ -z "$(git status --porcelain --untracked-files=no 2>/dev/null)" ] || commit="$commit (with local changes)"
version=$("$raycast" --version)
load_before=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown)

# --- Bumpy spheres ----------------------------------------------------------------------------
declare -A result
embree_version="not built"
for i in "${!names[@]}"; do
    name=${names[$i]}
    make_mesh "$name" "${counts[$i]}"
    write_scene "$name"
    scene=$name.txt
    log "$name: raycast, $repeat runs with packets and $repeat without"
    load="" build_ms="" render="" wall="" rss="" render_single="" line=""
    for run in $(seq "$repeat"); do
        timed "$build" "$raycast" "$scene" "out/$name.bmp" --stats --threads "$threads" --size "$size" --quiet
        line=$run_out
        load=$(min "$load" "$(field "$line" load_ms)")
        build_ms=$(min "$build_ms" "$(field "$line" build_ms)")
        render=$(min "$render" "$(field "$line" render_ms)")
        wall=$(min "$wall" "$run_wall_ms")
        [ -z "$run_rss_kib" ] || rss=$(max "$rss" "$run_rss_kib")
    done
    rays=$(field "$line" rays)
    triangles=$(field "$line" triangles)
    hit_fraction=$(field "$line" hit_fraction)
    traversal=$(field "$line" traversal)
    for run in $(seq "$repeat"); do
        timed "$build" "$raycast" "$scene" "out/${name}_single.bmp" --stats --threads "$threads" --size "$size" --quiet --no-packets
        render_single=$(min "$render_single" "$(field "$run_out" render_ms)")
        single_hits=$(field "$run_out" hit_fraction)
        [ "$single_hits" = "$hit_fraction" ] || log "$name: hit fraction $single_hits with --no-packets, $hit_fraction with packets"
    done
    result[$name,triangles]=$triangles
    result[$name,load]=$(fmt %.1f "$load")
    result[$name,build]=$(fmt %.1f "$build_ms")
    result[$name,render]=$(fmt %.1f "$render")
    result[$name,mrays]=$(fmt %.2f "$(calc "$rays / ($render * 1000)")")
    result[$name,mrays_single]=$(fmt %.2f "$(calc "$rays / ($render_single * 1000)")")
    result[$name,hit]=$hit_fraction
    result[$name,wall]=$(fmt %.2f "$(calc "$wall / 1000")")
    result[$name,traversal]=$traversal
    if [ -n "$rss" ]; then
        result[$name,rss]=$(fmt %.1f "$(calc "$rss / 1024")")
        result[$name,bpt]=$(fmt %.0f "$(calc "$rss * 1024 / $triangles")")
    else
        result[$name,rss]=n/a
        result[$name,bpt]=n/a
    fi

    if [ -n "$embree_bench" ]; then
        log "$name: Embree"
        status=0
        timed "$build" "$embree_bench" "$scene" --size "$size" --threads "$threads" --repeat "$repeat" \
            --expect-hit-fraction "$hit_fraction" || status=$?
        if [ "$status" = 0 ] || [ "$status" = 3 ]; then
            embree_version=$(field "$run_out" embree)
            result[$name,e_build]=$(fmt %.1f "$(field "$run_out" build_ms)")
            result[$name,e_single]=$(fmt %.2f "$(field "$run_out" single_mrays_per_s)")
            result[$name,e_packet]=$(fmt %.2f "$(field "$run_out" packet16_mrays_per_s)")
            result[$name,e_hit]=$(field "$run_out" hit_fraction)
            result[$name,e_match]=$(field "$run_out" hit_match)
            if [ -n "$run_rss_kib" ]; then
                result[$name,e_bpt]=$(fmt %.0f "$(calc "$run_rss_kib * 1024 / $triangles")")
            else
                result[$name,e_bpt]=n/a
            fi
        fi
    fi
    if [ -n "$tinyobj_bench" ]; then
        log "$name: tinyobjloader"
        if timed "$build" "$tinyobj_bench" "meshes/$name.obj" --repeat "$repeat" --threads "$threads"; then
            result[$name,t_tiny]=$(fmt %.1f "$(field "$run_out" tinyobj_ms)")
            result[$name,t_ours1]=$(fmt %.1f "$(field "$run_out" raycast_1t_ms)")
            result[$name,t_ours]=$(fmt %.1f "$(field "$run_out" raycast_ms)")
            result[$name,t_speedup]=$(fmt %.1f "$(field "$run_out" speedup)")
        fi
    fi
done

# --- Course scenes (or the project's own test scenes) -----------------------------------------
if [ -d ../shared/course/testcases ]; then
    course_dir=$(cd ../shared/course && pwd)
    course_label="the course's scenes (../shared/course)"
else
    course_dir=$root
    course_label="the project's own test scenes (testcases/; ../shared/course is absent)"
fi
course_rows=()
for scene in "$course_dir"/testcases/scene*.txt; do
    [ -f "$scene" ] || continue
    base=$(basename "$scene" .txt)
    log "course scene $base"
    wall="" load="" build_ms="" render="" ok=1
    for run in $(seq "$repeat"); do
        if ! timed "$course_dir" "$raycast" "testcases/$base.txt" "$root/$build/out/course_$base.bmp" \
            --stats --threads "$threads" --quiet; then
            ok=0; break
        fi
        wall=$(min "$wall" "$run_wall_ms")
        load=$(min "$load" "$(field "$run_out" load_ms)")
        build_ms=$(min "$build_ms" "$(field "$run_out" build_ms)")
        render=$(min "$render" "$(field "$run_out" render_ms)")
    done
    if [ "$ok" = 1 ]; then
        course_rows+=("| $base | $(field "$run_out" rays) | $(field "$run_out" triangles) | $(fmt %.2f "$load") | $(fmt %.2f "$build_ms") | $(fmt %.2f "$render") | $(fmt %.1f "$wall") |")
    else
        course_rows+=("| $base | failed | | | | | |")
    fi
done
load_after=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown)

# --- Report -----------------------------------------------------------------------------------
get() { echo "${result[$1]:-n/a}"; }
verdict() { awk -v a="$1" -v b="$3" -v op="$2" 'BEGIN {
    if (a == "n/a" || b == "n/a" || a == "" || b == "") { print "not measured"; exit }
    ok = (op == ">=") ? (a + 0 >= b + 0) : (a + 0 < b + 0); print ok ? "met" : "NOT MET" }' </dev/null; }
{
    echo "## Results"
    echo
    echo "- Date: $(date -u '+%Y-%m-%d %H:%M UTC')"
    echo "- Machine: $(nproc) hardware threads, $cpu; $(uname -sr)"
    echo "- Compiler: $compiler; Release build; commit $commit"
    echo "- $version; Embree $embree_version"
    echo "- Load average (1, 5, 15 min) before: $load_before; after: $load_after"
    echo "- Every render: $size, $threads threads; times are the best of $repeat runs"
    echo
    echo "### raycast on bumpy spheres"
    echo
    echo "| triangles | load ms | build ms | render ms | Mrays/s packets | Mrays/s single | hit fraction | end-to-end s | peak MiB | bytes/triangle |"
    echo "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    for name in "${names[@]}"; do
        echo "| $(get "$name,triangles") | $(get "$name,load") | $(get "$name,build") | $(get "$name,render") | $(get "$name,mrays") | $(get "$name,mrays_single") | $(get "$name,hit") | $(get "$name,wall") | $(get "$name,rss") | $(get "$name,bpt") |"
    done
    echo
    echo "Packet traversal: $(get "${names[0]},traversal")."
    echo
    echo "### Against Embree and tinyobjloader (same meshes)"
    echo
    echo "| triangles | Embree build ms | Embree Mrays/s 1-ray | Embree Mrays/s 16-packet | Embree hit fraction | same hits | Embree bytes/triangle | tinyobjloader ms | raycast OBJ ms (1 thread) | raycast OBJ ms ($threads threads) | OBJ speed-up |"
    echo "|---:|---:|---:|---:|---:|:---:|---:|---:|---:|---:|---:|"
    for name in "${names[@]}"; do
        echo "| $(get "$name,triangles") | $(get "$name,e_build") | $(get "$name,e_single") | $(get "$name,e_packet") | $(get "$name,e_hit") | $(get "$name,e_match") | $(get "$name,e_bpt") | $(get "$name,t_tiny") | $(get "$name,t_ours1") | $(get "$name,t_ours") | $(get "$name,t_speedup") |"
    done
    echo
    echo "### Targets (issue: speed benchmarked against Embree)"
    echo
    echo "| target | measured | goal | verdict |"
    echo "|---|---:|---:|---|"
    echo "| 1M triangles: primary rays, Mrays/s (raycast packets, shaded, vs Embree rtcIntersect1) | $(get bumpy_1m,mrays) | $(get bumpy_1m,e_single) | $(verdict "$(get bumpy_1m,mrays)" ">=" "$(get bumpy_1m,e_single)") |"
    echo "| 1M triangles: BVH build, ms | $(get bumpy_1m,build) | 1000 | $(verdict "$(get bumpy_1m,build)" "<" 1000) |"
    echo "| 5M triangles: end to end, s | $(get bumpy_5m,wall) | 10 | $(verdict "$(get bumpy_5m,wall)" "<" 10) |"
    echo "| 1M triangles: peak memory, bytes/triangle | $(get bumpy_1m,bpt) | 100 | $(verdict "$(get bumpy_1m,bpt)" "<" 100) |"
    echo "| 5M triangles: peak memory, bytes/triangle | $(get bumpy_5m,bpt) | 100 | $(verdict "$(get bumpy_5m,bpt)" "<" 100) |"
    echo "| 1M triangles: OBJ load speed-up over tinyobjloader | $(get bumpy_1m,t_speedup) | 2 | $(verdict "$(get bumpy_1m,t_speedup)" ">=" 2) |"
    echo "| 5M triangles: OBJ load speed-up over tinyobjloader | $(get bumpy_5m,t_speedup) | 2 | $(verdict "$(get bumpy_5m,t_speedup)" ">=" 2) |"
    echo
    echo "### End to end: $course_label"
    echo
    echo "| scene | rays | triangles | load ms | build ms | render ms | end-to-end ms |"
    echo "|---|---:|---:|---:|---:|---:|---:|"
    for row in "${course_rows[@]}"; do echo "$row"; done
} >"$tmp/results.md"
cp "$tmp/results.md" "$build/results.md"
cat "$build/results.md"
log "written to $build/results.md"
