#!/usr/bin/env bash
# Puts the seed inputs of the fuzz targets into BUILD/corpus-<target>/, next to whatever earlier
# runs found there (so repeated runs grow the corpus; delete the folders to start afresh):
#   corpus-fuzz_scene_parser: testcases/*.txt and scenes/revolution.txt (curves, RevSurface)
#   corpus-fuzz_obj_loader:   mesh/*.obj and a few small files for the index forms
#   corpus-fuzz_image_decode: a small render of testcases/scene01_basic.txt written by the
#                             raycast program of BUILD as .bmp .ppm .tga (and .png when built
#                             with libpng), plus a text P3 PPM, a top-down 32-bit BMP and an RLE TGA
#   corpus-fuzz_render_pipeline: its bytes are choices, not text: a few fixed byte patterns
#   corpus-fuzz_view_query:   the query strings of the page's requests and of docs/viewer.md
# Nothing is taken from ../shared.
#   bash fuzz/seed_corpus.sh [BUILD]   (default build-fuzz; BUILD/raycast must be built)
set -euo pipefail
cd "$(dirname "$0")/.."

build="${1:-build-fuzz}"
raycast="$build/raycast"
[ -x "$raycast" ] || raycast="$build/src/raycast"
if [ ! -x "$raycast" ]; then
  echo "seed_corpus.sh: no raycast program in $build (build the 'raycast' target first)" >&2
  exit 1
fi

scene_dir="$build/corpus-fuzz_scene_parser"
obj_dir="$build/corpus-fuzz_obj_loader"
image_dir="$build/corpus-fuzz_image_decode"
pipeline_dir="$build/corpus-fuzz_render_pipeline"
query_dir="$build/corpus-fuzz_view_query"
mkdir -p "$scene_dir" "$obj_dir" "$image_dir" "$pipeline_dir" "$query_dir"

# ---- scenes and meshes: the project's own files ----
cp testcases/*.txt scenes/revolution.txt "$scene_dir/"
tr '\n' '\r' <testcases/scene01_basic.txt >"$scene_dir/seed-cr-only.txt"  # classic Mac line breaks
cp mesh/*.obj "$obj_dir/"
# Index forms the project's meshes do not use: v/t/n, v//n, v/t, negative indices, polygons,
# comments, CRLF and a byte order mark.
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n# a quad\nf 1/1/1 2/2/1 3/3/1 4/1/1\n' \
  >"$obj_dir/seed-vtn.obj"
printf 'v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nvn 0 0 1\r\nf -3//1 -2//1 -1//1\r\nf 1/1 2/1 3/1 # note\r\nvt 0.5 0.5\r\n' \
  >"$obj_dir/seed-negative-crlf.obj"
printf '\xef\xbb\xbfo thing\ng part\nusemtl red\nv 1e3 -2.5E-2 .5\nv +1 2. 3\nv 0 0 0\ns off\nf 1 2 3\nl 1 2\n' \
  >"$obj_dir/seed-bom-other-statements.obj"
# Classic Mac line breaks (CR alone) with a DOS end mark, and Microsoft's NaN text and a line
# continuation.
printf 'v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r\x1a' >"$obj_dir/seed-cr-only-dos-end.obj"
printf 'v 0 0 0\nv 1 0 0 \\\nv 0 1.#IND 0\nvn -1.#INF 0 1\nf 1 2 3#c\n' >"$obj_dir/seed-msvc-nan-continuation.obj"

# ---- images: what the program writes, at a small size ----
formats=(bmp ppm tga)
if "$raycast" --help 2>&1 | grep -q 'png (when built'; then
  formats+=(png)
fi
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
for format in "${formats[@]}"; do
  # PNG fails (exit 1, no file) when this build has no libpng: skip it quietly then.
  if "$raycast" -q --threads 1 --size 7x5 testcases/scene01_basic.txt "$tmp/seed-render.$format" >/dev/null 2>&1; then
    cp "$tmp/seed-render.$format" "$image_dir/"
  fi
done
"$raycast" -q --threads 1 --size 3x2 --mode normals testcases/scene03_sphere.txt "$tmp/seed-normals.tga" >/dev/null 2>&1 &&
  cp "$tmp/seed-normals.tga" "$image_dir/"
# Variants the program does not write but the readers accept.
printf 'P3\n# a comment\n2 2\n255\n255 0 0  0 255 0\n0 0 255  255 255 255\n' >"$image_dir/seed-text.ppm"
printf 'P6 1 1 65535\n\x12\x34\x56\x78\x9a\xbc' >"$image_dir/seed-16bit.ppm"
# BMP: 2x1, 32 bits, top-down (height -1), 40-byte header, pixels at 54.
{
  printf 'BM\x3e\x00\x00\x00\x00\x00\x00\x00\x36\x00\x00\x00'
  printf '\x28\x00\x00\x00\x02\x00\x00\x00\xff\xff\xff\xff\x01\x00\x20\x00\x00\x00\x00\x00'
  printf '\x08\x00\x00\x00\x13\x0b\x00\x00\x13\x0b\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00'
  printf '\x01\x02\x03\xff\x04\x05\x06\xff'
} >"$image_dir/seed-topdown32.bmp"
# TGA: type 10 (RLE), 3x1, 24 bits, top-left origin: one run of 2 pixels and one raw pixel.
{
  printf '\x00\x00\x0a\x00\x00\x00\x00\x00\x00\x00\x00\x00\x03\x00\x01\x00\x18\x20'
  printf '\x81\x10\x20\x30\x00\x40\x50\x60'
} >"$image_dir/seed-rle.tga"

# ---- choices for the pipeline: each byte picks something, so a few patterns start it off ----
for byte in 00 01 55 aa ff; do
  printf "$(printf '\\x%s' "$byte")%.0s" $(seq 1 256) >"$pipeline_dir/seed-$byte"
done
LC_ALL=C awk 'BEGIN { for (i = 0; i < 512; ++i) printf "%c", (i * 37 + 11) % 256 }' >"$pipeline_dir/seed-ramp"

# ---- the viewer's query strings: what the page asks, and each parameter on its own ----
n=0
for query in \
  'mode=shaded&shadows=1&transparent_shadows=0&bounces=3&conventions=course&fov=both&spp=4' \
  'mode=ao&spp=1&ao_samples=4&ao_distance=2' \
  'eye=0.5,1,9&dir=-0.1,-0.1,-1&up=0,1,0&angle=40&light0=-2,4,3&light1=0.5,-2,0.25&shadows=1' \
  'x=3&y=2&bounces=2&shadows=1&spp=1' \
  'conventions=mit6837&shade_back=1&mode=normals&width=10&height=7' \
  'mode=cost' 'mode=depth' 'mode=material&weight=0.5' 'size=2' 'light2=1,2,3' 'light1=0,0,0' \
  'eye=1e30,0,0' 'spp=1=2' 'width=%38' 'a=1&&b=2' '~size=3&eye=0,2,20&light0=0,1,1&shadows=1' \
  '~conventions=mit6837&mode=depth'; do
  printf '%s' "$query" >"$query_dir/seed-$n"
  n=$((n + 1))
done

count() { find "$1" -type f | wc -l; }
echo "seed_corpus.sh: $(count "$scene_dir") scene, $(count "$obj_dir") OBJ, $(count "$image_dir") image," \
  "$(count "$pipeline_dir") pipeline and $(count "$query_dir") query inputs in $build/corpus-*/"
