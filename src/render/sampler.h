// Random numbers for rendering, all counter-based: a number depends only on the pixel, the sample
// and which number of that sample it is, never on the thread or the order in which pixels were
// rendered. So an image is the same on any number of threads, and `raycast explain` can re-trace
// one pixel alone and get exactly what the image shows.
#pragma once

#include <cmath>
#include <cstdint>

#include "math/vec.h"

namespace raycast {

/// A small, well-mixed hash (the "lowbias32" of Chris Wellons' hash prospector).
constexpr uint32_t hash32(uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

/// The top 24 bits of `bits` as a float in [0, 1): every value exactly representable.
inline float unit_float(uint32_t bits) { return static_cast<float>(bits >> 8) * (1.0f / 16777216.0f); }

/// How `spp` samples share a pixel: an n×n grid when spp = n², else a 1×spp row.
struct SampleGrid {
    int columns = 1, rows = 1;
    explicit SampleGrid(int spp) {
        columns = static_cast<int>(std::lround(std::sqrt(static_cast<double>(spp))));
        if (columns * columns != spp) columns = spp;
        rows = spp / columns;
    }
};

/// Where sample `s` of a pixel falls inside its cell of the grid, in [0, 1)².
inline Vec2f sample_jitter(uint32_t pixel_index, int s) {
    const uint32_t seed = hash32(pixel_index * 0x9e3779b9U + static_cast<uint32_t>(s));
    return {unit_float(hash32(seed ^ 0x68bc21ebU)), unit_float(hash32(seed ^ 0x02e5be93U))};
}

/// Sample `s`'s cell of the grid, the same for every pixel: its column and row, and the grid's
/// columns and rows, as the offsets' arithmetic uses them.
struct SampleCell {
    float column, row, columns, rows;
};
inline SampleCell sample_cell(const SampleGrid& grid, int s) {
    return {static_cast<float>(s % grid.columns), static_cast<float>(s / grid.columns),
            static_cast<float>(grid.columns), static_cast<float>(grid.rows)};
}

/// Where a sample jittered by `jitter` (sample_jitter) in `cell` falls inside its pixel, in [0, 1)².
inline Vec2f offset_in_cell(const SampleCell& cell, Vec2f jitter) {
    return {(cell.column + jitter.x) / cell.columns, (cell.row + jitter.y) / cell.rows};
}

/// Where sample `s` falls inside its pixel, in [0, 1)²: one jittered point per cell of the grid.
/// A grid of one cell gives the pixel's own point (½, ½).
inline Vec2f pixel_sample_offset(const SampleGrid& grid, uint32_t pixel_index, int s) {
    if (grid.columns * grid.rows == 1) return {0.5f, 0.5f};
    return offset_in_cell(sample_cell(grid, s), sample_jitter(pixel_index, s));
}

/// The same for `spp` samples (the grid found anew: renderers keep one SampleGrid instead).
inline Vec2f pixel_sample_offset(uint32_t pixel_index, int s, int spp) {
    return pixel_sample_offset(SampleGrid(spp), pixel_index, s);
}

/// The point on a thin lens for sample `s` of a pixel, in [0, 1)² (camera_ray maps it to the disk).
inline Vec2f lens_sample(uint32_t pixel_index, int s) {
    const uint32_t seed = hash32(pixel_index ^ hash32(static_cast<uint32_t>(s) + 0x5bd1e995U));
    return {unit_float(hash32(seed)), unit_float(hash32(seed + 1))};
}

/// sin and cos of the angle 2π·turns, for turns in [0, 1): the nearest quarter turn is taken off
/// exactly, and what is left (at most π/4) goes through the Taylor series to degree 9 and 10,
/// which are within 2e-10 of the exact values before rounding. Written out, not std::sin and
/// std::cos: the two library calls cost more than the rest of a sample (8% of an ambient
/// occlusion render), and the same arithmetic gives the same bits with any C library.
inline void sincos_of_turns(float turns, float& sine, float& cosine) {
    const float quarters = 4 * turns;
    const int quarter = static_cast<int>(quarters + 0.5f);
    const float r = (quarters - static_cast<float>(quarter)) * 1.57079632679489662f;  // |r| <= π/4
    const float r2 = r * r;
    const float s = r * (1 + r2 * (-1.0f / 6 + r2 * (1.0f / 120 + r2 * (-1.0f / 5040 + r2 * (1.0f / 362880)))));
    const float c =
        1 + r2 * (-0.5f + r2 * (1.0f / 24 + r2 * (-1.0f / 720 + r2 * (1.0f / 40320 + r2 * (-1.0f / 3628800)))));
    // Quarter 0: (s, c); 1: (c, −s); 2: (−s, −c); 3: (−c, s). Selected on integers, which the
    // compiler does without branches (a random quarter would mispredict three times in four).
    const bool odd = (quarter & 1) != 0;
    const float a = odd ? c : s, b = odd ? s : c;
    sine = (quarter & 2) != 0 ? -a : a;
    cosine = ((quarter + 1) & 2) != 0 ? -b : b;
}

/// The orthonormal basis of Duff et al. (2017) around a unit normal: the directions that
/// sample_cosine_hemisphere turns its disk's x and y into.
struct HemisphereBasis {
    Vec3f tangent, bitangent, normal;
    explicit HemisphereBasis(Vec3f n) : normal(n) {
        const float sign = std::copysign(1.0f, n.z);
        const float a = -1 / (sign + n.z);
        const float b = n.x * n.y * a;
        tangent = {1 + sign * n.x * n.x * a, sign * b, -sign * n.x};
        bitangent = {b, sign + n.y * n.y * a, -n.y};
    }
};

/// Directions about a unit normal with density cos θ / π (the cosine-weighted hemisphere), for
/// `count` points u in [0, 1)² at once, from arrays to arrays (direction i from u0[i], u1[i]):
/// Malley's method, a uniform point on the disk (r = √u₀, φ = 2πu₁) lifted to the hemisphere, in
/// the basis around the normal. A loop over independent lanes, which the compiler vectorises (an
/// ambient-occlusion hit draws 16); one direction is the same loop with one lane, and so the same
/// bits. z = √(1 − u₀) is clamped at 0 by a comparison, not std::fmax, which would not vectorise:
/// the two agree for every value of 1 − u₀ (NaN included; −0 cannot arise from 1 − u₀).
inline void sample_cosine_hemisphere_n(const HemisphereBasis& basis, int count, const float* u0, const float* u1,
                                       float* x_out, float* y_out, float* z_out) {
    for (int i = 0; i < count; ++i) {
        const float r = std::sqrt(u0[i]);
        float sin_phi, cos_phi;
        sincos_of_turns(u1[i], sin_phi, cos_phi);
        const float x = r * cos_phi, y = r * sin_phi;
        const float rest = 1 - u0[i];
        const float z = std::sqrt(rest > 0 ? rest : 0.0f);
        x_out[i] = basis.tangent.x * x + basis.bitangent.x * y + basis.normal.x * z;
        y_out[i] = basis.tangent.y * x + basis.bitangent.y * y + basis.normal.y * z;
        z_out[i] = basis.tangent.z * x + basis.bitangent.z * y + basis.normal.z * z;
    }
}

/// One direction of sample_cosine_hemisphere_n about the unit `normal`, from u in [0, 1)².
inline Vec3f sample_cosine_hemisphere(Vec3f normal, Vec2f u) {
    Vec3f direction;
    sample_cosine_hemisphere_n(HemisphereBasis(normal), 1, &u.x, &u.y, &direction.x, &direction.y, &direction.z);
    return direction;
}

/// What Sampler hashes the seed with for its number `index`.
constexpr uint32_t sampler_index_hash(uint32_t index) { return hash32(index * 0x9e3779b9U + 0x165667b1U); }

/// sampler_index_hash of the first 2·kPairs indices, the even ones and the odd ones apart, made
/// by the compiler: they do not depend on the pixel or the sample, so Sampler::next_2d_n looks
/// them up instead of hashing each index again (half the hashing of its numbers, the same numbers).
struct SamplerIndexHashes {
    static constexpr uint32_t kPairs = 64;
    uint32_t even[kPairs], odd[kPairs];
};
constexpr SamplerIndexHashes make_sampler_index_hashes() {
    SamplerIndexHashes table{};
    for (uint32_t i = 0; i < SamplerIndexHashes::kPairs; ++i) {
        table.even[i] = sampler_index_hash(2 * i);
        table.odd[i] = sampler_index_hash(2 * i + 1);
    }
    return table;
}
inline constexpr SamplerIndexHashes kSamplerIndexHashes = make_sampler_index_hashes();

/// The random numbers an integrator draws while it traces one camera sample (directions for
/// ambient occlusion, paths later): the i-th number of sample s of a pixel is a hash of the three,
/// independent of the pixel's position offsets and lens point above.
class Sampler {
public:
    // The seed is found at the first draw: most camera samples (a Whitted render's) draw none.
    Sampler(uint32_t pixel_index, int sample_index)
        : pixel_index_(pixel_index), sample_index_(static_cast<uint32_t>(sample_index)) {}

    float next_1d() {
        find_seed();
        return number(index_++);
    }
    Vec2f next_2d() {
        const float u = next_1d();
        return {u, next_1d()};
    }
    /// What `count` calls of next_2d() would return, as two arrays (u0[i], u1[i] the i-th pair):
    /// independent hashes, in a loop the compiler vectorises.
    void next_2d_n(int count, float* u0, float* u1) {
        if (count <= 0) return;
        find_seed();
        const uint32_t first = index_;
        if (first % 2 == 0 && first / 2 + static_cast<uint32_t>(count) <= SamplerIndexHashes::kPairs) {
            const uint32_t* even = kSamplerIndexHashes.even + first / 2;
            const uint32_t* odd = kSamplerIndexHashes.odd + first / 2;
            for (int i = 0; i < count; ++i) {
                u0[i] = number_of_hash(even[i]);
                u1[i] = number_of_hash(odd[i]);
            }
        } else {
            for (int i = 0; i < count; ++i) {
                u0[i] = number(first + 2 * static_cast<uint32_t>(i));
                u1[i] = number(first + 2 * static_cast<uint32_t>(i) + 1);
            }
        }
        index_ = first + 2 * static_cast<uint32_t>(count);
    }

private:
    void find_seed() {
        if (index_ == 0) seed_ = hash32(pixel_index_ * 0x85ebca6bU ^ hash32(sample_index_ + 0x27d4eb2fU));
    }
    // Number `index` of this camera sample, from its index's hash (sampler_index_hash).
    float number_of_hash(uint32_t index_hash) const { return unit_float(hash32(seed_ ^ index_hash)); }
    float number(uint32_t index) const { return number_of_hash(sampler_index_hash(index)); }

    uint32_t pixel_index_, sample_index_;
    uint32_t seed_ = 0;
    uint32_t index_ = 0;
};

/// The most directions draw_cosine_directions draws at once.
constexpr int kMaxDirectionsAtOnce = 16;

/// `count` (at most kMaxDirectionsAtOnce) cosine-distributed directions about `basis` from the
/// sampler's next `count` pairs of numbers: next_2d_n, then sample_cosine_hemisphere_n, the same
/// bits. Built for AVX-512 and AVX2 as well where the compiler can (base/simd_clones.h).
void draw_cosine_directions(Sampler& sampler, const HemisphereBasis& basis, int count, float* x_out, float* y_out,
                            float* z_out);

}  // namespace raycast
