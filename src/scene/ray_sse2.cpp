// The single-ray kernel compiled for sse2 (see ray_kernel.inl; build flags in src/CMakeLists.txt).
#include <emmintrin.h>

#include <cstddef>

#include "scene/packet_view.h"

namespace raycast::ray_sse2 {
namespace {
#include "scene/packet_simd_sse2.h"
#include "scene/ray_simd_sse2.h"
}  // namespace
#include "scene/ray_kernel.inl"
}  // namespace raycast::ray_sse2
