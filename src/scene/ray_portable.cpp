// The single-ray kernel compiled for portable (see ray_kernel.inl; build flags in src/CMakeLists.txt).
#include <cstddef>

#include "scene/packet_view.h"

namespace raycast::ray_portable {
namespace {
#include "scene/packet_simd_portable.h"
#include "scene/ray_simd_portable.h"
}  // namespace
#include "scene/ray_kernel.inl"
}  // namespace raycast::ray_portable
