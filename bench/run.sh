#!/usr/bin/env bash
# The performance benchmark of docs/performance.md, rerunnable on any machine:
#   bash bench/run.sh                      # bumpy spheres of 1k, 100k, 1M and 5M triangles, then the course scenes
#   bash bench/run.sh --quick              # 1k and 100k only
#   bash bench/run.sh --baseline OLD/raycast   # also time another raycast binary in the same run
#   bash bench/run.sh --repeat 5           # best of 5 runs per figure (default 3), for a noisy machine
#                                          # (in rounds: each round runs every kind once, Embree's too)
# Builds Release in build-bench/, generates the meshes once (cached in build-bench/meshes/), renders
# each at 1024x1024 on 2 threads with --stats (primary rays with and without packets, --spp 16,
# --shadows with a directional and a point light, and --mode ao when the build has it), runs
# raycast_embree_bench (Embree's rays, then the same kinds of rays through raycast's own queries;
# then Embree's passes and raycast's renders in pairs, in one process) and raycast_tinyobj_bench
# on the same meshes when they were built (libembree-dev, libtinyobjloader-dev), and prints
# Markdown tables, also written to build-bench/results.md. Run it on a quiet machine: every figure
# is a wall-clock time.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

quick=0
baseline=""
repeat=3
while [ $# -gt 0 ]; do
    case "$1" in
        --quick) quick=1 ;;
        --baseline)
            [ $# -ge 2 ] || { echo "bench/run.sh: --baseline needs a raycast binary" >&2; exit 2; }
            baseline=$(cd "$(dirname "$2")" && pwd)/$(basename "$2"); shift ;;
        --repeat)
            [[ $# -ge 2 && $2 =~ ^[1-9][0-9]*$ ]] || { echo "bench/run.sh: --repeat needs a count of runs" >&2; exit 2; }
            repeat=$2; shift ;;
        -h|--help) sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) echo "bench/run.sh: unknown argument '$1' (use --quick, --baseline BINARY or --repeat N)" >&2; exit 2 ;;
    esac
    shift
done
[ -z "$baseline" ] || [ -x "$baseline" ] || { echo "bench/run.sh: $baseline is not an executable" >&2; exit 2; }

build=build-bench
threads=2
size=1024x1024
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

directional_light='    DirectionalLight {
        direction -0.5 -0.6 -1
        color 0.9 0.9 0.9
    }'
point_light='    PointLight {
        position 2 3 4
        color 0.6 0.6 0.6
    }'
# write_scene NAME FILE COUNT LIGHT...: FILE frames meshes/NAME.obj, lit by the COUNT lights given
write_scene() {
    local name=$1 file=$2 count=$3
    shift 3
    cat >"$file" <<EOF
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
    numLights $count
$(printf '%s\n' "$@")
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
        obj_file meshes/$name.obj
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
# --mode ao comes with the renderer's ambient-occlusion mode (issue #14); until the binary has it,
# its columns read n/a. Its rays= is whatever the renderer counts (primary and AO rays).
has_ao=0
"$raycast" --help 2>&1 | grep -- '--mode' | grep -qw ao && has_ao=1

# render_into KEY SCENE OUT BINARY -- OPTIONS...: one render, kept under KEY if it is KEY's fastest
# so far (best_of_line, best_of_ms), with the least wall, load and build times and the largest
# peak memory of KEY's runs. forget KEY... starts those keys afresh; use KEY sets best_line (the
# --stats line of the fastest), best_render_ms, best_wall_ms, best_load_ms, best_build_ms and
# peak_rss_kib from KEY's runs.
declare -A best_of_line best_of_ms best_of_wall best_of_load best_of_build best_of_rss
forget() {
    local key
    for key in "$@"; do
        best_of_line[$key]="" best_of_ms[$key]="" best_of_wall[$key]="" best_of_load[$key]=""
        best_of_build[$key]="" best_of_rss[$key]=""
    done
}
render_into() {
    local key=$1 scene=$2 out=$3 binary=$4
    shift 5
    timed "$build" "$binary" "$scene" "$out" --stats --threads "$threads" --size "$size" --quiet "$@"
    local ms
    ms=$(field "$run_out" render_ms)
    last_line=$run_out last_ms=$ms
    if [ -z "${best_of_ms[$key]}" ] || awk -v a="$ms" -v b="${best_of_ms[$key]}" 'BEGIN { exit !(a + 0 < b + 0) }'; then
        best_of_ms[$key]=$ms
        best_of_line[$key]=$run_out
    fi
    best_of_wall[$key]=$(min "${best_of_wall[$key]}" "$run_wall_ms")
    best_of_load[$key]=$(min "${best_of_load[$key]}" "$(field "$run_out" load_ms)")
    best_of_build[$key]=$(min "${best_of_build[$key]}" "$(field "$run_out" build_ms)")
    [ -z "$run_rss_kib" ] || best_of_rss[$key]=$(max "${best_of_rss[$key]}" "$run_rss_kib")
}
use() {
    best_line=${best_of_line[$1]} best_render_ms=${best_of_ms[$1]} best_wall_ms=${best_of_wall[$1]}
    best_load_ms=${best_of_load[$1]} best_build_ms=${best_of_build[$1]} peak_rss_kib=${best_of_rss[$1]}
}
# best_render SCENE OUT BINARY -- OPTIONS...: the best of $repeat renders in a row, as use() gives it.
best_render() {
    forget in_a_row
    for run in $(seq "$repeat"); do render_into in_a_row "$@"; done
    use in_a_row
}
mrays() { fmt %.2f "$(calc "$1 / ($2 * 1000)")"; }  # mrays RAYS MS
# keep_round KIND: the last render's Mrays/s as round[$name,KIND,$run] (nothing if it failed).
keep_round() {
    local rays
    rays=$(field "$last_line" rays)
    round[$name,$1,$run]=""
    [ -z "$rays" ] || [ -z "$last_ms" ] || round[$name,$1,$run]=$(mrays "$rays" "$last_ms")
}

# load_in_turn SCENE: loads and builds SCENE with raycast and the baseline in turn, $turns times
# each (a 64x64 image, so that the render adds little), and sets turn_load, turn_build,
# turn_b_load and turn_b_build to the best of each, and turn_runs to the runs each. Loading a
# 100k-triangle mesh takes about 6 ms: the machine's speed drifts more than that between two
# phases a minute apart. A scene whose first load takes under 10 ms gets ten times the runs: a
# 1k-triangle load (0.2 ms) is mostly the process's own noise, and its best of 11 moved by 10 µs
# from run to run.
turns=$((2 * repeat + 1))
load_in_turn() {
    turn_load="" turn_build="" turn_b_load="" turn_b_build="" turn_load_ratios="" turn_build_ratios=""
    turn_runs=$turns
    local our_load our_build
    for ((run = 1; run <= turn_runs; ++run)); do
        timed "$build" "$raycast" "$1" out/turn.bmp --stats --threads "$threads" --size 64x64 --quiet
        our_load=$(field "$run_out" load_ms) our_build=$(field "$run_out" build_ms)
        turn_load=$(min "$turn_load" "$our_load")
        turn_build=$(min "$turn_build" "$our_build")
        timed "$build" "$baseline" "$1" out/turn.bmp --stats --threads "$threads" --size 64x64 --quiet
        turn_b_load=$(min "$turn_b_load" "$(field "$run_out" load_ms)")
        turn_b_build=$(min "$turn_b_build" "$(field "$run_out" build_ms)")
        # Each turn's ratios (raycast's time over the baseline's, taken a moment apart).
        turn_load_ratios+="$(calc "$our_load / $(field "$run_out" load_ms)") "
        turn_build_ratios+="$(calc "$our_build / $(field "$run_out" build_ms)") "
        if [ "$run" -eq 1 ] && [ "$(calc "$turn_load < 10")" = 1 ]; then turn_runs=$((10 * turns)); fi
    done
}
# ratio_summary RATIOS OP: how many of the ratios (measured / goal) meet the target (OP ">=": at
# least 1; "<=": at most 1), and their median, as the targets table's per-round column has it.
ratio_summary() {
    [ -n "$1" ] || { echo "n/a"; return; }
    tr ' ' '\n' <<<"$1" | sed '/^$/d' | sort -g | awk -v op="$2" '{ r[NR] = $1; won += (op == ">=") ? ($1 >= 1) : ($1 <= 1) }
        END { m = NR % 2 ? r[(NR + 1) / 2] : (r[NR / 2] + r[NR / 2 + 1]) / 2; printf "%d of %d, median %.2f", won, NR, m }'
}

# embree_round SCENE HIT_FRACTION: one run of raycast_embree_bench (Embree's rays, then the same
# kinds through raycast's queries, each traced once), keeping each figure's best in e_best and
# this round's (round $run of mesh $name) in round[$name,e_KEY,$run], the least build time in e_build, the largest peak memory in e_rss and the last run's line in e_last;
# e_ok says whether any run succeeded (exit 3: the hit fractions differ, which the tables show).
e_keys=(single packet16 ao_single ao_packet16 raycast_single raycast_packet raycast_ao_single raycast_ao_packet
    raycast_shadow_single raycast_shadow_packet)
declare -A e_best
embree_forget() {
    e_ok=0 e_last="" e_build="" e_rss=""
    local key
    for key in "${e_keys[@]}"; do e_best[$key]=""; done
}
embree_round() {
    local status=0 key value
    timed "$build" "$embree_bench" "$1" --size "$size" --threads "$threads" --repeat 1 \
        --expect-hit-fraction "$2" --raycast || status=$?
    [ "$status" = 0 ] || [ "$status" = 3 ] || return 0
    e_ok=1
    e_last=$run_out
    e_build=$(min "$e_build" "$(field "$run_out" build_ms)")
    for key in "${e_keys[@]}"; do
        value=$(field "$run_out" "${key}_mrays_per_s")
        [ -z "$value" ] || e_best[$key]=$(max "${e_best[$key]}" "$value")
        round[$name,e_$key,$run]=$value
    done
    [ -z "$run_rss_kib" ] || e_rss=$(max "$e_rss" "$run_rss_kib")
}

declare -A result
# Each round's figures, as round[NAME,KIND,RUN] (Mrays/s), for the targets' per-round ratios:
# a ratio within one round compares two runs taken seconds apart, where the best of each kind
# may come from rounds minutes apart on a machine whose speed drifts.
declare -A round
embree_version="not built"
for i in "${!names[@]}"; do
    name=${names[$i]}
    make_mesh "$name" "${counts[$i]}"
    write_scene "$name" "$build/$name.txt" 1 "$directional_light"
    write_scene "$name" "$build/${name}_lights.txt" 2 "$directional_light" "$point_light"
    scene=$name.txt
    log "$name: $repeat rounds of one run each: raycast (packets, --no-packets, --spp 16, --shadows$([ "$has_ao" = 1 ] && echo ", --mode ao"))$([ -n "$embree_bench" ] && echo ", then Embree and the same kinds of rays through raycast's queries")"
    # In rounds, not each kind's runs in a row: this machine's speed drifts by 10% and more over
    # a minute (other guests on its host), and a figure is compared with another taken in the
    # same rounds, so that both had the same chances of a quiet moment.
    forget packets single spp16 shadows ao
    embree_forget
    for run in $(seq "$repeat"); do
        render_into packets "$scene" "out/$name.bmp" "$raycast" --
        keep_round packets
        render_into single "$scene" "out/${name}_single.bmp" "$raycast" -- --no-packets
        keep_round single
        render_into spp16 "$scene" "out/${name}_spp16.bmp" "$raycast" -- --spp 16
        keep_round spp16
        # Shadows: the rays traced as --stats counts them (at most one per hit and light: none
        # towards a light that adds nothing at the hit).
        render_into shadows "${name}_lights.txt" "out/${name}_shadows.bmp" "$raycast" -- --shadows
        keep_round shadows
        if [ "$has_ao" = 1 ]; then
            render_into ao "$scene" "out/${name}_ao.bmp" "$raycast" -- --mode ao
            keep_round ao
        fi
        [ -z "$embree_bench" ] || embree_round "$scene" "$(field "${best_of_line[packets]}" hit_fraction)"
    done
    use packets
    line=$best_line
    rays=$(field "$line" rays)
    triangles=$(field "$line" triangles)
    hit_fraction=$(field "$line" hit_fraction)
    result[$name,triangles]=$triangles
    result[$name,load]=$(fmt %.1f "$best_load_ms")
    result[$name,build]=$(fmt %.1f "$best_build_ms")
    result[$name,render]=$(fmt %.1f "$best_render_ms")
    result[$name,mrays]=$(mrays "$rays" "$best_render_ms")
    result[$name,hit]=$hit_fraction
    # The camera rays of windows found to see nothing (coloured without being traced one by one).
    skipped=$(field "$line" window_missed_rays)
    [ -z "$skipped" ] || result[$name,skipped]=$(fmt %.4f "$(calc "$skipped / $(field "$line" primary_rays)")")
    result[$name,wall]=$(fmt %.2f "$(calc "$best_wall_ms / 1000")")
    result[$name,traversal]=$(field "$line" traversal)
    if [ -n "$peak_rss_kib" ]; then
        result[$name,rss]=$(fmt %.1f "$(calc "$peak_rss_kib / 1024")")
        result[$name,bpt]=$(fmt %.1f "$(calc "$peak_rss_kib * 1024 / $triangles")")
    fi
    use single
    [ "$(field "$best_line" hit_fraction)" = "$hit_fraction" ] ||
        log "$name: hit fraction $(field "$best_line" hit_fraction) with --no-packets, $hit_fraction with packets"
    cmp -s "$build/out/$name.bmp" "$build/out/${name}_single.bmp" || log "$name: the --no-packets image differs!"
    result[$name,mrays_single]=$(mrays "$rays" "$best_render_ms")
    use spp16
    result[$name,mrays_spp16]=$(mrays "$(field "$best_line" rays)" "$best_render_ms")
    use shadows
    result[$name,mrays_shadows]=$(mrays "$(field "$best_line" rays)" "$best_render_ms")
    if [ "$has_ao" = 1 ]; then
        use ao
        result[$name,mrays_ao]=$(mrays "$(field "$best_line" rays)" "$best_render_ms")
    fi
    if [ -n "$baseline" ]; then
        log "$name: baseline raycast, $repeat runs with packets and $repeat without"
        best_render "$scene" "out/${name}_baseline.bmp" "$baseline" --
        result[$name,b_load]=$(fmt %.1f "$best_load_ms")
        result[$name,b_build]=$(fmt %.1f "$best_build_ms")
        result[$name,b_mrays]=$(mrays "$rays" "$best_render_ms")
        result[$name,b_wall]=$(fmt %.2f "$(calc "$best_wall_ms / 1000")")
        [ -z "$peak_rss_kib" ] || result[$name,b_bpt]=$(fmt %.1f "$(calc "$peak_rss_kib * 1024 / $triangles")")
        cmp -s "$build/out/$name.bmp" "$build/out/${name}_baseline.bmp" || log "$name: the baseline's image differs"
        best_render "$scene" "out/${name}_baseline_single.bmp" "$baseline" -- --no-packets
        result[$name,b_mrays_single]=$(mrays "$rays" "$best_render_ms")
        log "$name: load and build, raycast and the baseline in turn"
        load_in_turn "$scene"
        result[$name,turn_runs]=$turn_runs
        result[$name,turn_load]=$(fmt %.2f "$turn_load")
        result[$name,turn_build]=$(fmt %.2f "$turn_build")
        result[$name,turn_b_load]=$(fmt %.2f "$turn_b_load")
        result[$name,turn_b_build]=$(fmt %.2f "$turn_b_build")
        result[$name,turn_load_rounds]=$(ratio_summary "$turn_load_ratios" "<=")
        result[$name,turn_build_rounds]=$(ratio_summary "$turn_build_ratios" "<=")
    fi

    if [ -n "$embree_bench" ]; then
        # Both scenes in one process, Embree's pass and raycast's render a moment apart, $turns pairs.
        log "$name: Embree's rays and raycast's renders in pairs, in one process"
        if timed "$build" "$embree_bench" "$scene" --size "$size" --threads "$threads" --paired "$turns"; then
            for key in single ao packets; do
                result[$name,paired_$key]="$(ratio_summary "$(tr ',' ' ' <<<"$(field "$run_out" "paired_$key")")" ">="), best $(fmt %.2f "$(field "$run_out" "paired_${key}_best")")"
            done
        fi
    fi
    if [ "$e_ok" = 1 ]; then
        embree_version=$(field "$e_last" embree)
        result[$name,e_build]=$(fmt %.1f "$e_build")
        for key in "${e_keys[@]}"; do
            [ -z "${e_best[$key]}" ] || result[$name,e_$key]=$(fmt %.2f "${e_best[$key]}")
        done
        result[$name,e_hit]=$(field "$e_last" hit_fraction)
        result[$name,e_match]=$(field "$e_last" hit_match)
        result[$name,e_packets]=$(field "$e_last" raycast_packets)
        # Embree's phase comes first and needs about twice raycast's memory: the peak is Embree's.
        [ -z "$e_rss" ] || result[$name,e_bpt]=$(fmt %.0f "$(calc "$e_rss * 1024 / $triangles")")
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
# course_times BASE: the best of $course_repeat runs of one scene, the baseline's runs (if any)
# taken in turn with raycast's so that both see the same machine; sets c_ok, c_wall, c_load,
# c_build, c_render, c_line, and b_ok, b_wall for the baseline.
course_repeat=10
course_times() {
    c_ok=1 c_wall="" c_load="" c_build="" c_render="" b_ok=1 b_wall=""
    for run in $(seq "$course_repeat"); do
        if [ -n "$baseline" ] && [ "$b_ok" = 1 ]; then
            if timed "$course_dir" "$baseline" "testcases/$1.txt" "$root/$build/out/course_$1_baseline.bmp" --threads "$threads" --quiet; then
                b_wall=$(min "$b_wall" "$run_wall_ms")
            else
                b_ok=0
            fi
        fi
        if ! timed "$course_dir" "$raycast" "testcases/$1.txt" "$root/$build/out/course_$1.bmp" --stats --threads "$threads" --quiet; then
            c_ok=0
            return
        fi
        c_line=$run_out
        c_wall=$(min "$c_wall" "$run_wall_ms")
        c_load=$(min "$c_load" "$(field "$run_out" load_ms)")
        c_build=$(min "$c_build" "$(field "$run_out" build_ms)")
        c_render=$(min "$c_render" "$(field "$run_out" render_ms)")
    done
}
course_rows=()
course_total=0
course_baseline_total=0
for scene in "$course_dir"/testcases/scene*.txt; do
    [ -f "$scene" ] || continue
    base=$(basename "$scene" .txt)
    log "course scene $base"
    course_times "$base"
    baseline_cell=""
    if [ -n "$baseline" ]; then
        if [ "$b_ok" = 1 ]; then
            baseline_cell=" $(fmt %.1f "$b_wall") |"
            course_baseline_total=$(calc "$course_baseline_total + $b_wall")
        else
            baseline_cell=" failed |"
        fi
    fi
    if [ "$c_ok" = 1 ]; then
        course_total=$(calc "$course_total + $c_wall")
        course_rows+=("| $base | $(field "$c_line" rays) | $(field "$c_line" triangles) | $(fmt %.2f "$c_load") | $(fmt %.2f "$c_build") | $(fmt %.2f "$c_render") | $(fmt %.1f "$c_wall") |$baseline_cell")
    else
        course_rows+=("| $base | failed | | | | | |$baseline_cell")
    fi
done
load_after=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown)

# --- Report -----------------------------------------------------------------------------------
get() { echo "${result[$1]:-n/a}"; }
# verdict A OP B: A >= B or A <= B (A < B for "<")
verdict() { awk -v a="$1" -v b="$3" -v op="$2" 'BEGIN {
    if (a == "n/a" || b == "n/a" || a == "" || b == "") { print "not measured"; exit }
    ok = (op == ">=") ? (a + 0 >= b + 0) : (op == "<=") ? (a + 0 <= b + 0) : (a + 0 < b + 0); print ok ? "met" : "NOT MET" }' </dev/null; }
# per_round NAME KIND GOAL_KIND FACTOR: in how many rounds KIND's figure reached FACTOR times
# GOAL_KIND's of the same round, and the median of those rounds' ratios (KIND / (FACTOR x GOAL)).
per_round() {
    local run a b ratios=""
    for run in $(seq "$repeat"); do
        a=${round[$1,$2,$run]:-} b=${round[$1,$3,$run]:-}
        [ -n "$a" ] && [ -n "$b" ] || continue
        ratios+="$(calc "$a / ($4 * $b)") "
    done
    ratio_summary "$ratios" ">="
}
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (a == "n/a" || b == "n/a" || a == "" || b == "" || b + 0 == 0) print "n/a"; else printf "%.2f", a / b }' </dev/null; }
{
    echo "## Results"
    echo
    echo "- Date: $(date -u '+%Y-%m-%d %H:%M UTC')"
    echo "- Machine: $(nproc) hardware threads, $cpu; $(uname -sr)"
    echo "- Compiler: $compiler; Release build; commit $commit"
    echo "- $version; Embree $embree_version"
    [ -z "$baseline" ] || echo "- Baseline (same run): $baseline ($("$baseline" --version))"
    echo "- Load average (1, 5, 15 min) before: $load_before; after: $load_after"
    echo "- Every render: $size, $threads threads; times are the best of $repeat runs, taken in rounds of one run of each kind and one of Embree's comparison (course scenes: of $course_repeat, taken in turn with the baseline's; the load and build targets: of $turns at 64x64, ten times as many for meshes that load in under 10 ms, in turn with the baseline's)"
    echo
    echo "### raycast on bumpy spheres"
    echo
    echo "| triangles | load ms | build ms | render ms | Mrays/s packets | Mrays/s single | hit fraction | window-missed fraction | end-to-end s | peak MiB | bytes/triangle |"
    echo "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    for name in "${names[@]}"; do
        echo "| $(get "$name,triangles") | $(get "$name,load") | $(get "$name,build") | $(get "$name,render") | $(get "$name,mrays") | $(get "$name,mrays_single") | $(get "$name,hit") | $(get "$name,skipped") | $(get "$name,wall") | $(get "$name,rss") | $(get "$name,bpt") |"
    done
    echo
    echo "Packet traversal: $(get "${names[0]},traversal")."
    if [ -n "$baseline" ]; then
        echo
        echo "### The baseline binary, same run"
        echo
        echo "| triangles | load ms | build ms | Mrays/s packets | Mrays/s single | end-to-end s | bytes/triangle |"
        echo "|---:|---:|---:|---:|---:|---:|---:|"
        for name in "${names[@]}"; do
            echo "| $(get "$name,triangles") | $(get "$name,b_load") | $(get "$name,b_build") | $(get "$name,b_mrays") | $(get "$name,b_mrays_single") | $(get "$name,b_wall") | $(get "$name,b_bpt") |"
        done
    fi
    echo
    echo "### Rendering modes (raycast, shaded, all rays counted)"
    echo
    echo "| triangles | primary Mrays/s | --spp 16 Mrays/s | ratio | --shadows (2 lights) Mrays/s | ratio | --mode ao Mrays/s |"
    echo "|---:|---:|---:|---:|---:|---:|---:|"
    for name in "${names[@]}"; do
        echo "| $(get "$name,triangles") | $(get "$name,mrays") | $(get "$name,mrays_spp16") | $(ratio "$(get "$name,mrays_spp16")" "$(get "$name,mrays")") | $(get "$name,mrays_shadows") | $(ratio "$(get "$name,mrays_shadows")" "$(get "$name,mrays")") | $(get "$name,mrays_ao") |"
    done
    echo
    echo "### Against Embree and tinyobjloader (same meshes)"
    echo
    echo "| triangles | Embree build ms | Embree Mrays/s 1-ray | Embree Mrays/s 16-packet | Embree AO Mrays/s 1-ray | Embree AO Mrays/s 16-packet | Embree hit fraction | same hits | Embree bytes/triangle | tinyobjloader ms | raycast OBJ ms (1 thread) | raycast OBJ ms ($threads threads) | OBJ speed-up |"
    echo "|---:|---:|---:|---:|---:|---:|---:|:---:|---:|---:|---:|---:|---:|"
    for name in "${names[@]}"; do
        echo "| $(get "$name,triangles") | $(get "$name,e_build") | $(get "$name,e_single") | $(get "$name,e_packet16") | $(get "$name,e_ao_single") | $(get "$name,e_ao_packet16") | $(get "$name,e_hit") | $(get "$name,e_match") | $(get "$name,e_bpt") | $(get "$name,t_tiny") | $(get "$name,t_ours1") | $(get "$name,t_ours") | $(get "$name,t_speedup") |"
    done
    echo
    echo "### The same kinds of rays, tracing only (raycast_embree_bench --raycast)"
    echo
    echo "No shading and no image on either side. AO: every primary ray, then 16 AO rays per hit, all rays counted."
    echo
    echo "| triangles | primary 1-ray: raycast / Embree | primary packets: raycast / Embree 16 | AO 1-ray: raycast / Embree | AO packets: raycast / Embree 16 | shadow rays (1 light): raycast 1-ray / packets |"
    echo "|---:|---:|---:|---:|---:|---:|"
    for name in "${names[@]}"; do
        echo "| $(get "$name,triangles") | $(get "$name,e_raycast_single") / $(get "$name,e_single") | $(get "$name,e_raycast_packet") / $(get "$name,e_packet16") | $(get "$name,e_raycast_ao_single") / $(get "$name,e_ao_single") | $(get "$name,e_raycast_ao_packet") / $(get "$name,e_ao_packet16") | $(get "$name,e_raycast_shadow_single") / $(get "$name,e_raycast_shadow_packet") |"
    done
    echo
    echo "raycast's packets: $(get "${names[0]},e_packets")."
    echo
    echo "### Targets"
    echo
    echo "Issue #14 (every kind of ray), then the earlier issue's targets."
    echo
    echo "The verdict compares the best of each figure's $repeat runs. \"Per round\" compares the figures of each round, taken seconds apart (the best figures may come from rounds minutes apart): the rounds in which the target was met, and the median of the rounds' ratios of measured to goal (for the load and build targets, each turn's raycast time over the baseline's: at most 1 meets them). \"Paired\" compares, in one process holding both scenes, $turns pairs of an Embree pass and a raycast render taken a moment apart (each after a rest and an untimed pass of its own): the pairs in which raycast was at least as fast, the median of the pairs' ratios, and the ratio of the two sides' best passes."
    echo
    echo "| target | measured | goal | verdict | per round | paired |"
    echo "|---|---:|---:|---|---|---|"
    for name in "${names[@]}"; do
        echo "| $(get "$name,triangles") triangles: --no-packets render (shaded), Mrays/s, vs Embree rtcIntersect1 | $(get "$name,mrays_single") | $(get "$name,e_single") | $(verdict "$(get "$name,mrays_single")" ">=" "$(get "$name,e_single")") | $(per_round "$name" single e_single 1) | $(get "$name,paired_single") |"
    done
    for name in bumpy_1m bumpy_5m; do
        echo "| $(get "$name,triangles") triangles: --mode ao (all rays), Mrays/s, vs Embree primary + rtcOccluded1 | $(get "$name,mrays_ao") | $(get "$name,e_ao_single") | $(verdict "$(get "$name,mrays_ao")" ">=" "$(get "$name,e_ao_single")") | $(per_round "$name" ao e_ao_single 1) | $(get "$name,paired_ao") |"
    done
    for name in "${names[@]}"; do
        spp_goal=$(awk -v m="$(get "$name,mrays")" 'BEGIN { if (m == "n/a") print "n/a"; else printf "%.2f", 0.8 * m }' </dev/null)
        echo "| $(get "$name,triangles") triangles: --spp 16, Mrays/s, vs 80% of primary | $(get "$name,mrays_spp16") | $spp_goal | $(verdict "$(get "$name,mrays_spp16")" ">=" "$spp_goal") | $(per_round "$name" spp16 packets 0.8) | |"
        echo "| $(get "$name,triangles") triangles: --shadows (directional + point light), Mrays/s, vs 80% of primary | $(get "$name,mrays_shadows") | $spp_goal | $(verdict "$(get "$name,mrays_shadows")" ">=" "$spp_goal") | $(per_round "$name" shadows packets 0.8) | |"
    done
    echo "| 1M triangles: primary packets (shaded), Mrays/s, vs Embree rtcIntersect16 | $(get bumpy_1m,mrays) | $(get bumpy_1m,e_packet16) | $(verdict "$(get bumpy_1m,mrays)" ">=" "$(get bumpy_1m,e_packet16)") | $(per_round bumpy_1m packets e_packet16 1) | $(get bumpy_1m,paired_packets) |"
    echo "| 5M triangles: peak memory, bytes/triangle | $(get bumpy_5m,bpt) | 64 | $(verdict "$(get bumpy_5m,bpt)" "<=" 64) | | |"
    if [ -n "$baseline" ]; then
        for name in "${names[@]}"; do
            echo "| $(get "$name,triangles") triangles: build ms, vs the baseline's (in turn, best of $(get "$name,turn_runs")) | $(get "$name,turn_build") | $(get "$name,turn_b_build") | $(verdict "$(get "$name,turn_build")" "<=" "$(get "$name,turn_b_build")") | $(get "$name,turn_build_rounds") | |"
            echo "| $(get "$name,triangles") triangles: load ms, vs the baseline's (in turn, best of $(get "$name,turn_runs")) | $(get "$name,turn_load") | $(get "$name,turn_b_load") | $(verdict "$(get "$name,turn_load")" "<=" "$(get "$name,turn_b_load")") | $(get "$name,turn_load_rounds") | |"
        done
        echo "| course scenes: end to end, sum of the best of $course_repeat, ms, vs the baseline's | $(fmt %.1f "$course_total") | $(fmt %.1f "$course_baseline_total") | $(verdict "$course_total" "<=" "$course_baseline_total") | | |"
    fi
    echo "| 1M triangles: primary rays, Mrays/s (raycast packets, shaded, vs Embree rtcIntersect1) | $(get bumpy_1m,mrays) | $(get bumpy_1m,e_single) | $(verdict "$(get bumpy_1m,mrays)" ">=" "$(get bumpy_1m,e_single)") | | |"
    echo "| 1M triangles: BVH build, ms | $(get bumpy_1m,build) | 1000 | $(verdict "$(get bumpy_1m,build)" "<" 1000) | | |"
    echo "| 5M triangles: end to end, s | $(get bumpy_5m,wall) | 10 | $(verdict "$(get bumpy_5m,wall)" "<" 10) | | |"
    echo "| 1M triangles: peak memory, bytes/triangle | $(get bumpy_1m,bpt) | 100 | $(verdict "$(get bumpy_1m,bpt)" "<" 100) | | |"
    echo "| 1M triangles: OBJ load speed-up over tinyobjloader | $(get bumpy_1m,t_speedup) | 2 | $(verdict "$(get bumpy_1m,t_speedup)" ">=" 2) | | |"
    echo "| 5M triangles: OBJ load speed-up over tinyobjloader | $(get bumpy_5m,t_speedup) | 2 | $(verdict "$(get bumpy_5m,t_speedup)" ">=" 2) | | |"
    echo
    echo "### End to end: $course_label"
    echo
    if [ -n "$baseline" ]; then
        echo "| scene | rays | triangles | load ms | build ms | render ms | end-to-end ms | baseline end-to-end ms |"
        echo "|---|---:|---:|---:|---:|---:|---:|---:|"
    else
        echo "| scene | rays | triangles | load ms | build ms | render ms | end-to-end ms |"
        echo "|---|---:|---:|---:|---:|---:|---:|"
    fi
    for row in "${course_rows[@]}"; do echo "$row"; done
} >"$tmp/results.md"
cp "$tmp/results.md" "$build/results.md"
cat "$build/results.md"
log "written to $build/results.md"
