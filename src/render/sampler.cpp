#include "render/sampler.h"

#include "base/check.h"

namespace raycast {

// On x86 this is built twice, for AVX2 and for the baseline, and the loader picks one when the
// program starts (GCC's and Clang's target_clones): these two loops were a fifth of an ambient-
// occlusion render at 1k triangles, and eight lanes with a 32-bit multiply (for the hashes) do
// them in fewer steps than SSE2's four lanes without one. Both copies do the same operations in
// the same order (AVX2 alone brings no fused multiply-add, and the build forbids contraction), so
// every direction has the same bits; sampler_test compares them with the formula.
#if (defined(__x86_64__) || defined(__i386__)) && defined(__GNUC__)
[[gnu::target_clones("avx2", "default")]]
#endif
void draw_cosine_directions(Sampler& sampler, const HemisphereBasis& basis, int count, float* x_out, float* y_out,
                            float* z_out) {
    float u0[kMaxDirectionsAtOnce], u1[kMaxDirectionsAtOnce];
    RAYCAST_DCHECK(count <= kMaxDirectionsAtOnce);
    sampler.next_2d_n(count, u0, u1);
    sample_cosine_hemisphere_n(basis, count, u0, u1, x_out, y_out, z_out);
}

}  // namespace raycast
