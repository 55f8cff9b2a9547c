#include "render/sampler.h"

#include "base/check.h"
#include "base/simd_clones.h"

namespace raycast {

// Built for AVX-512, AVX2 and the baseline (base/simd_clones.h): these two loops were a fifth of
// an ambient-occlusion render at 1k triangles, and eight lanes with a 32-bit multiply (for the
// hashes) do them in fewer steps than SSE2's four lanes without one. Every copy gives each
// direction the same bits; sampler_test compares them with the formula.
RAYCAST_SIMD_CLONES
void draw_cosine_directions(Sampler& sampler, const HemisphereBasis& basis, int count, float* x_out, float* y_out,
                            float* z_out) {
    float u0[kMaxDirectionsAtOnce], u1[kMaxDirectionsAtOnce];
    RAYCAST_DCHECK(count <= kMaxDirectionsAtOnce);
    sampler.next_2d_n(count, u0, u1);
    sample_cosine_hemisphere_n(basis, count, u0, u1, x_out, y_out, z_out);
}

}  // namespace raycast
