#!/usr/bin/env bash
# Renders the pictures in README.md and docs/ (PNG, so raycast must be built with libpng) from the
# project's own scenes, plus, when ../shared is present, course and MIT 6.837 scenes. Rerun after a
# change to what the pictures show; the files are committed.
set -euo pipefail
cd "$(dirname "$0")/.."

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" --target raycast >/dev/null
raycast=build/raycast
out=docs/images
mkdir -p "$out"
render() { "$raycast" --quiet "$@"; }
# The showcase frames are 640x360: their pictures keep square pixels (--fov vertical), where the
# course's default reading would stretch them.
showcase() { render "$@" --fov vertical; }

showcase scenes/showcase.txt "$out/showcase.png" --shadows --spp 16
showcase scenes/showcase.txt "$out/showcase_course.png"                 # the course's defaults
showcase scenes/showcase.txt "$out/showcase_shadows.png" --shadows
showcase scenes/showcase.txt "$out/showcase_spp16.png" --spp 16
showcase scenes/showcase.txt "$out/mode_normals.png" --mode normals
showcase scenes/showcase.txt "$out/mode_depth.png" --mode depth --depth-range 6,16
showcase scenes/showcase.txt "$out/mode_material.png" --mode material
showcase scenes/showcase.txt "$out/mode_cost.png" --mode cost
showcase scenes/showcase.txt "$out/thin_lens.png" --aperture 0.6 --focus-distance 7.2 --spp 64 --shadows
showcase scenes/showcase_ortho.txt "$out/orthographic.png" --shadows --spp 16
render scenes/raytracing.txt "$out/raytracing.png" --shadows --transparent-shadows --bounces 8 --spp 16
showcase scenes/revolution.txt "$out/revolution.png" --shadows --spp 16
render scenes/goblet.txt "$out/goblet.png" --shadows --transparent-shadows --bounces 10 --spp 16
showcase scenes/revolution.txt "$out/revolution_normals.png" --mode normals
"$raycast" compare "$out/showcase_course.png" "$out/showcase_spp16.png" --diff "$out/compare_diff.png" >/dev/null

if [ -d ../shared/course/testcases ]; then
  root="$PWD"; (cd ../shared/course && "$root/$raycast" --quiet testcases/scene06_bunny_1k.txt "$root/$out/course_scene06.png") ||
    echo "make_doc_images: course scene failed" >&2
fi
if [ -d ../shared/course-pa3/testcases ]; then
  render ../shared/course-pa3/testcases/scene10_wineglass.txt "$out/course_scene10.png" ||
    echo "make_doc_images: course scene 10 failed" >&2
fi
if [ -d ../shared/reference/mit6837-f04/a2 ]; then
  root="$PWD"
  (cd ../shared/reference/mit6837-f04/a2 &&
   "$root/$raycast" --quiet -input scene2_15_crazy_transforms.txt -size 200 200 -output "$root/$out/mit_scene2_15.png" &&
   "$root/$raycast" --quiet -input scene2_07_sphere_triangles.txt -size 200 200 -output "$root/$out/mit_scene2_07.png" \
     -normals "$root/$out/mit_scene2_07_normals.png" -shade_back)
fi
ls -l "$out"
