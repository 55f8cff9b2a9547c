// The single-ray kernel compiled for avx2 (see ray_kernel.inl; build flags in src/CMakeLists.txt).
#include <immintrin.h>

#include <cstddef>

#include "scene/packet_view.h"

namespace raycast::ray_avx2 {
namespace {
#include "scene/packet_simd_avx2.h"
namespace sse {
#include "scene/packet_simd_sse2.h"
}  // namespace sse
#include "scene/ray_simd_avx2.h"
}  // namespace
#include "scene/ray_kernel.inl"
}  // namespace raycast::ray_avx2
