// The course's surface of revolution: a profile curve in the z = 0 plane turned about the y axis,
// S(t, θ) = (x(t)·cos θ, y(t), x(t)·sin θ), intersected exactly.
//
// A ray o + t·d meets the surface where y(u) = o_y + t·d_y and x(u)² = (o_x + t·d_x)² + (o_z + t·d_z)².
// On each Bezier piece of the profile (degree m), eliminating t gives one polynomial of degree 2m
// in the piece's parameter u,
//     F(u) = d_y²·(X(u)² − |o_xz|²) − 2·d_y·(o_xz·d_xz)·D(u) − |d_xz|²·D(u)²,   D(u) = Y(u) − o_y,
// whose roots are exactly the hits (t = D(u)/d_y). F is built in Bernstein form, its roots are
// isolated by subdivision (no root can hide: the coefficients bound the polynomial), each is
// refined by bracketed Newton steps on u, and near-horizontal rays — where F's roots come in close
// pairs — are finished by Newton's method on (u, t). A ray with d_y ≈ 0 solves y(u) = o_y instead
// and takes t from the circle it meets. The profile is cut where x(u) or y(u) turns, and a small
// hierarchy of rings (y range × radius range) over those monotone pieces prunes the search.
// Entry points: make_rev_surface, intersect_rev_surface, rev_surface_normal, rev_surface_bounds.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/curve.h"
#include "geometry/triangle_mesh.h"
#include "math/bounds.h"
#include "math/mat4.h"
#include "math/ray.h"

namespace raycast {

/// A node of the profile's bounding hierarchy: the ring y ∈ [y_min, y_max], radius ∈ [radius_min,
/// radius_max] that holds the pieces below it. A leaf (count > 0) holds pieces [first, first +
/// count); an inner node has its children at `first` and `first + 1`.
struct ProfileNode {
    double y_min = 0, y_max = 0, radius_min = 0, radius_max = 0;
    uint32_t first = 0, count = 0;
};

/// A surface of revolution ready to intersect, in its object space.
struct RevSurface {
    int degree = 3;                      ///< of every piece
    std::vector<double> x, y;            ///< degree + 1 Bezier coefficients per piece
    std::vector<double> x_squared;       ///< X(u)² of each piece: 2·degree + 1 Bernstein coefficients
    std::vector<double> product_weights; ///< bernstein_product_weights(degree)
    std::vector<double> t_begin, t_end;  ///< the curve parameters where each piece starts and ends
    std::vector<ProfileNode> nodes;      ///< nodes[0] is the root; empty if the profile is a point
    double scale = 1;                    ///< the largest |coordinate| of the profile, for tolerances
    Bounds3f bounds;                     ///< object space

    uint32_t piece_count() const { return degree > 0 ? static_cast<uint32_t>(x.size()) / static_cast<uint32_t>(degree + 1) : 0; }
};

/// The surface of `profile` (its z coordinates are ignored: the parser insists they are 0).
RevSurface make_rev_surface(const Curve& profile);

/// Where a ray meets the surface: t along the ray, and the piece and its parameter u there.
struct RevSurfaceHit {
    float t = 0;
    float u = 0;
    uint32_t piece = 0;
};

/// Closest hit (any hit if `any_hit`) with t_min < t < t_max along a ray in object space (its
/// direction need not be unit length). If `nodes_visited` is given, each ring tested adds one.
bool intersect_rev_surface(const RevSurface& surface, const Ray& ray, float t_min, float t_max, bool any_hit,
                           RevSurfaceHit& hit, uint64_t* nodes_visited = nullptr);

/// The unit normal at a hit, in object space, oriented as the course's starter orients it: the
/// profile's tangent T (along increasing t) crossed with (0, 0, 1), turned with the point.
/// `point` is the hit point (object space), which gives the angle.
Vec3f rev_surface_normal(const RevSurface& surface, uint32_t piece, float u, Vec3f point);

/// A tight box around the surface placed by world_from_object: the union of the boxes of the
/// cylinders around its monotone pieces (each the box of its two end discs).
Bounds3f rev_surface_bounds(const RevSurface& surface, const Mat4& world_from_object);

/// What the intersections did on the calling thread since the last call (a thread-local tally,
/// so that no traversal path has to carry counters): tests run, Newton steps taken, and roots
/// whose Newton polish did not converge (they keep the bracketed estimate, which is still a hit).
struct RevSurfaceCounters {
    uint64_t tests = 0;
    uint64_t newton_iterations = 0;
    uint64_t newton_failures = 0;

    RevSurfaceCounters& operator+=(const RevSurfaceCounters& other) {
        tests += other.tests;
        newton_iterations += other.newton_iterations;
        newton_failures += other.newton_failures;
        return *this;
    }
};
RevSurfaceCounters take_rev_surface_counters();

/// Newton's method on (u, t) for the hit of the ray on one piece near (u, t): the step the
/// intersection uses to finish near-horizontal rays, exposed for tests. Returns whether it
/// converged (then u and t hold the root; else they are unchanged); `iterations` counts the steps.
bool polish_rev_surface_hit(const RevSurface& surface, uint32_t piece, const Ray& ray, double& u, double& t,
                            int& iterations);

/// The surface as a triangle mesh with its analytic normals at the vertices: `along` steps of the
/// curve parameter (evaluated with eval_curve, independently of the pieces) and `around` steps
/// of the angle. For tests, and for comparisons with renderers that only take meshes.
TriangleMesh tessellate_rev_surface(const Curve& profile, int along, int around);

}  // namespace raycast
