// The single-ray kernel compiled for AVX-512VL: the AVX2 kernel's 8-lane code (nodes of 8
// children, groups of 8 triangles), whose two-register vertex lookups become one permute (see
// ray_simd_avx2.h), with AVX-512's 32 registers (see ray_kernel.inl; build flags in
// src/CMakeLists.txt).
#include <immintrin.h>

#include <cstddef>

#include "scene/packet_view.h"

namespace raycast::ray_avx512 {
namespace {
#include "scene/packet_simd_avx2.h"
namespace sse {
#include "scene/packet_simd_sse2.h"
}  // namespace sse
#include "scene/ray_simd_avx2.h"
}  // namespace
#include "scene/ray_kernel.inl"
}  // namespace raycast::ray_avx512
