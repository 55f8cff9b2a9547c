#include "geometry/rev_surface.h"

#include <algorithm>
#include <cmath>

#include "base/check.h"
#include "base/limits.h"
#include "geometry/bernstein.h"

namespace raycast {

static_assert(2 * (kMaxBezierControlPoints - 1) <= kMaxBernsteinDegree,
              "F of the highest-degree profile must fit the Bernstein routines");

namespace {

thread_local RevSurfaceCounters tally;

// |d_y| below 1e-5·|d| (squared here): F's roots pair up too closely for double precision to tell
// them apart, so the ray is solved as horizontal, y(u) = o_y, and finished by Newton's method.
constexpr double kHorizontalSquared = 1e-10;
// |d_y| below 1e-3·|d|: t = D(u)/d_y magnifies u's rounding, so Newton's method on (u, t) polishes it.
constexpr double kPolishSquared = 1e-6;
// Subdivision of a piece stops at intervals of 2^-40 of it (a double root, where the ray grazes the
// surface), or after this many intervals in one test (a counted failure: it never happens on a
// surface that is not degenerate).
constexpr int kMaxDepth = 40;
constexpr int kMaxIntervals = 2000;
constexpr int kMaxPolishSteps = 8;

// The profile at u on one piece: X, Y and their derivatives in u.
struct ProfilePoint {
    double x, dx, y, dy;
};

// A cubic's value and derivative by de Casteljau, written out: the course's pieces are all cubic,
// and the intersection evaluates them at every Newton step.
inline double eval_cubic(const double* c, double u, double& derivative) {
    const double a = c[0] + u * (c[1] - c[0]), b = c[1] + u * (c[2] - c[1]), e = c[2] + u * (c[3] - c[2]);
    const double f = a + u * (b - a), g = b + u * (e - b);
    derivative = 3 * (g - f);
    return f + u * (g - f);
}

ProfilePoint profile_at(const RevSurface& s, uint32_t piece, double u) {
    const size_t offset = static_cast<size_t>(piece) * static_cast<size_t>(s.degree + 1);
    ProfilePoint p;
    if (s.degree == 3) {
        p.x = eval_cubic(&s.x[offset], u, p.dx);
        p.y = eval_cubic(&s.y[offset], u, p.dy);
        return p;
    }
    p.x = eval_bernstein(&s.x[offset], s.degree, u, &p.dx);
    p.y = eval_bernstein(&s.y[offset], s.degree, u, &p.dy);
    return p;
}

// The ray in double precision, with its origin moved along it by `shift` (t = shift + τ), and what
// the tests need of it: a = |d_xz|², b = o_xz·d_xz, c = |o_xz|², the τ of its closest approach to
// the axis and its squared distance from the axis there.
struct RaySetup {
    double ox = 0, oy = 0, oz = 0, dx = 0, dy = 0, dz = 0;
    double a = 0, b = 0, c = 0, tc = 0, h2 = 0, length_squared = 0, shift = 0;
    double inverse_dy = 0, inverse_a = 0;  // 0 where d_y or a is 0

    void move_origin(double by) {
        ox += by * dx;
        oy += by * dy;
        oz += by * dz;
        shift += by;
        b = ox * dx + oz * dz;
        c = ox * ox + oz * oz;
        tc = -b * inverse_a;
        // h² as a square of the closest point, not c − b²/a, which cancels far from the axis.
        const double px = ox + tc * dx, pz = oz + tc * dz;
        h2 = px * px + pz * pz;
    }
    double radius_squared_at(double tau) const {
        const double px = ox + tau * dx, pz = oz + tau * dz;
        return px * px + pz * pz;
    }
    bool is_horizontal() const { return dy * dy < kHorizontalSquared * length_squared; }
};

bool make_ray_setup(const Ray& ray, RaySetup& r) {
    r.ox = ray.origin.x;
    r.oy = ray.origin.y;
    r.oz = ray.origin.z;
    r.dx = ray.direction.x;
    r.dy = ray.direction.y;
    r.dz = ray.direction.z;
    r.a = r.dx * r.dx + r.dz * r.dz;
    r.length_squared = r.a + r.dy * r.dy;
    if (!(r.length_squared > 0) || !std::isfinite(r.length_squared) || !std::isfinite(r.ox) || !std::isfinite(r.oy) ||
        !std::isfinite(r.oz))
        return false;
    r.inverse_dy = r.dy != 0 ? 1 / r.dy : 0;
    r.inverse_a = r.a > 0 ? 1 / r.a : 0;
    r.move_origin(0);
    return true;
}

// Narrows [lo, hi] to where the ray may be inside the ring: the y slab, then inside the outer
// cylinder, and not inside the inner one all along. False if nothing is left.
bool clip_to_ring(const ProfileNode& node, const RaySetup& r, double& lo, double& hi) {
    if (r.dy != 0) {
        double t0 = (node.y_min - r.oy) * r.inverse_dy, t1 = (node.y_max - r.oy) * r.inverse_dy;
        if (t0 > t1) std::swap(t0, t1);
        lo = std::max(lo, t0);
        hi = std::min(hi, t1);
    } else if (r.oy < node.y_min || r.oy > node.y_max) {
        return false;
    }
    if (!(lo <= hi)) return false;
    const double outer = node.radius_max * node.radius_max;
    if (r.a > 0) {
        const double reach = (outer - r.h2) * r.inverse_a;
        if (reach < 0) return false;
        const double half = std::sqrt(reach);
        lo = std::max(lo, r.tc - half);
        hi = std::min(hi, r.tc + half);
        if (!(lo <= hi)) return false;
    } else if (r.h2 > outer) {
        return false;
    }
    // The distance from the axis is convex along the ray: its largest value is at an end.
    const double inner = node.radius_min * node.radius_min;
    return inner == 0 || r.radius_squared_at(lo) >= inner || r.radius_squared_at(hi) >= inner;
}

// One intersection query against one surface, in the shifted frame (τ = t − shift).
class Query {
public:
    Query(const RevSurface& s, const RaySetup& r, double tau_min, double tau_max, bool any_hit)
        : s_(s), r_(r), tau_min_(tau_min), tau_max_(tau_max), any_hit_(any_hit) {}

    // Visits the rings nearest first and solves the pieces of the leaves that the ray may reach
    // before the best hit so far.
    void run(double lo, double hi, uint64_t* nodes_visited) {
        struct Pending {
            uint32_t node;
            double lo, hi;
        };
        Pending stack[64];
        int size = 0;
        Pending current{0, lo, hi};
        for (;;) {
            const ProfileNode& node = s_.nodes[current.node];
            if (node.count > 0) {
                for (uint32_t p = node.first; p < node.first + node.count && !done_; ++p)
                    solve_piece(p, current.lo, current.hi);
            } else {
                Pending near{node.first, tau_min_, tau_max_}, far{node.first + 1, tau_min_, tau_max_};
                const bool hit_near = clip_to_ring(s_.nodes[near.node], r_, near.lo, near.hi);
                const bool hit_far = clip_to_ring(s_.nodes[far.node], r_, far.lo, far.hi);
                if (nodes_visited) *nodes_visited += 2;
                if (hit_near && hit_far) {
                    if (far.lo < near.lo) std::swap(near, far);
                    if (size < 64) stack[size++] = far;
                    current = near;
                    continue;
                }
                if (hit_near || hit_far) {
                    current = hit_near ? near : far;
                    continue;
                }
            }
            for (;;) {
                if (size == 0 || done_) return;
                current = stack[--size];
                if (current.lo <= tau_max_) break;
            }
        }
    }

    bool found() const { return found_; }
    double tau() const { return tau_max_; }
    double u() const { return best_u_; }
    uint32_t piece() const { return best_piece_; }

    // Newton's method on (u, τ) for x(u)² = |o_xz + τ·d_xz|², y(u) = o_y + τ·d_y. Converged roots
    // replace u and τ; anything else (a singular Jacobian at a grazing hit, a step off the piece)
    // leaves them as they were.
    bool polish(uint32_t piece, double& u, double& tau) {
        const double tau_scale = s_.scale / std::sqrt(r_.length_squared);
        double nu = u, ntau = tau;
        for (int step = 0; step < kMaxPolishSteps; ++step) {
            const ProfilePoint p = profile_at(s_, piece, nu);
            const double px = r_.ox + ntau * r_.dx, pz = r_.oz + ntau * r_.dz;
            const double f1 = p.x * p.x - (px * px + pz * pz);
            const double f2 = p.y - (r_.oy + ntau * r_.dy);
            const double j00 = 2 * p.x * p.dx, j01 = -2 * (px * r_.dx + pz * r_.dz);
            const double j10 = p.dy, j11 = -r_.dy;
            const double det = j00 * j11 - j01 * j10;
            ++counters_.newton_iterations;
            if (!(std::fabs(det) > 0)) return false;
            const double du = (f1 * j11 - j01 * f2) / det;
            const double dtau = (j00 * f2 - j10 * f1) / det;
            if (!std::isfinite(du) || !std::isfinite(dtau)) return false;
            nu -= du;
            ntau -= dtau;
            if (std::fabs(nu - u) > 0.05 || nu < -1e-9 || nu > 1 + 1e-9) return false;
            if (std::fabs(du) <= 1e-13 && std::fabs(dtau) <= 1e-13 * (std::fabs(ntau) + tau_scale)) {
                u = std::clamp(nu, 0.0, 1.0);
                tau = ntau;
                return true;
            }
        }
        return false;
    }

    RevSurfaceCounters counters_;

private:
    void solve_piece(uint32_t piece, double lo, double hi) {
        if (r_.is_horizontal())
            solve_horizontal(piece);
        else if (s_.degree == 3)
            solve_general<6>(piece, lo, hi);
        else
            solve_general<2 * kMaxBezierControlPoints - 2>(piece, lo, hi);
    }

    // F(u) in Bernstein form (see the header): F_k = d_y²(X²_k − c) − Σ_i w_ki·D_i·(2·d_y·b + a·D_{k−i}).
    template <int kMaxF>
    void solve_general(uint32_t piece, double lo, double hi) {
        const int m = s_.degree;
        const double* ys = &s_.y[static_cast<size_t>(piece) * static_cast<size_t>(m + 1)];
        const double* xx = &s_.x_squared[static_cast<size_t>(piece) * static_cast<size_t>(2 * m + 1)];
        const double* w = s_.product_weights.data();
        double d[kMaxF / 2 + 1], f[kMaxF + 1];
        for (int i = 0; i <= m; ++i) d[i] = ys[i] - r_.oy;
        const double dy2 = r_.dy * r_.dy, cross = 2 * r_.dy * r_.b;
        for (int k = 0; k <= 2 * m; ++k) {
            const int first = k > m ? k - m : 0, last = k < m ? k : m;
            double sum = 0;
            for (int i = first; i <= last; ++i) sum += w[k * (m + 1) + i] * d[i] * (cross + r_.a * d[k - i]);
            f[k] = dy2 * (xx[k] - r_.c) - sum;
        }
        intervals_ = 0;
        lo_ = lo;
        hi_ = hi;
        // A ring is met twice, on the way in and out, on either side of the ray's closest approach
        // to the axis (τ = tc). The piece is monotone in y, so τ(u) = D(u)/d_y is too, and cutting
        // at the u where τ = tc parts the two at once: near-horizontal rays meet a ring at nearly
        // the same u, which halving would take many steps to tell apart.
        double cut = 0;
        if (sign_changes(f, 2 * m) >= 2 && split_at_closest_approach(piece, d, cut)) {
            double f_near[kMaxF + 1], f_far[kMaxF + 1], d_near[kMaxF / 2 + 1], d_far[kMaxF / 2 + 1];
            split_bernstein(f, 2 * m, cut, f_near, f_far);
            split_bernstein(d, m, cut, d_near, d_far);
            // The part before the cut holds the smaller τ when τ grows with u.
            const bool rising = (d[m] - d[0]) * r_.dy > 0;
            if (rising) {
                isolate<kMaxF>(piece, f_near, d_near, 0, cut, 1);
                isolate<kMaxF>(piece, f_far, d_far, cut, 1 - cut, 1);
            } else {
                isolate<kMaxF>(piece, f_far, d_far, cut, 1 - cut, 1);
                isolate<kMaxF>(piece, f_near, d_near, 0, cut, 1);
            }
            return;
        }
        isolate<kMaxF>(piece, f, d, 0, 1, 0);
    }

    // The u in (0, 1) where the piece reaches the height of the ray's closest approach to the axis,
    // D(u) = tc·d_y, if it does: Newton steps on the monotone D from the chord's estimate, kept
    // inside the bracket. It need not be exact: any cut between the two roots parts them.
    bool split_at_closest_approach(uint32_t piece, const double* d, double& cut) const {
        const int m = s_.degree;
        const double target = r_.tc * r_.dy;
        double lo = 0, hi = 1;
        const double g0 = d[0] - target, g1 = d[m] - target;
        if (!((g0 < 0 && g1 > 0) || (g0 > 0 && g1 < 0))) return false;
        const double* ys = &s_.y[static_cast<size_t>(piece) * static_cast<size_t>(m + 1)];
        double u = g0 / (g0 - g1);
        for (int step = 0; step < 4; ++step) {
            double slope;
            const double g = (m == 3 ? eval_cubic(ys, u, slope) : eval_bernstein(ys, m, u, &slope)) - r_.oy - target;
            if ((g < 0) == (g0 < 0))
                lo = u;
            else
                hi = u;
            const double next = u - g / slope;
            u = next > lo && next < hi ? next : 0.5 * (lo + hi);
        }
        cut = u;
        return cut > 0 && cut < 1;
    }

    // The τ range over an interval whose D coefficients are `d`: τ = D/d_y, and D lies in their hull.
    void tau_range(const double* d, int m, double& low, double& high) const {
        double d_min = d[0], d_max = d[0];
        for (int i = 1; i <= m; ++i) {
            d_min = std::min(d_min, d[i]);
            d_max = std::max(d_max, d[i]);
        }
        low = d_min / r_.dy;
        high = d_max / r_.dy;
        if (low > high) std::swap(low, high);
    }

    template <int kMaxF>
    void isolate(uint32_t piece, const double* f, const double* d, double start, double width, int depth) {
        if (done_) return;
        if (++intervals_ > kMaxIntervals) {
            if (intervals_ == kMaxIntervals + 1) ++counters_.newton_failures;
            return;
        }
        const int m = s_.degree, n = 2 * m;
        double low, high;
        tau_range(d, m, low, high);
        const double slack = 1e-12 * (std::fabs(low) + std::fabs(high)) + 1e-300;
        if (high < std::max(lo_, tau_min_) - slack || low > std::min(hi_, tau_max_) + slack) return;
        if (f[0] == 0) offer_root(piece, start);
        if (f[n] == 0) offer_root(piece, start + width);
        const RootsInside roots = roots_inside(f, n);
        if (roots == RootsInside::None) return;
        if (roots == RootsInside::OneBracketed) {
            refine(piece, start, start + width, start + width * control_polygon_crossing(f, n), f[0] > 0);
            return;
        }
        if (depth == kMaxDepth) {
            offer_root(piece, start + 0.5 * width);  // a grazing double root
            return;
        }
        double f_left[kMaxF + 1], f_right[kMaxF + 1], d_left[kMaxF / 2 + 1], d_right[kMaxF / 2 + 1];
        if (kMaxF == 6) {
            split_bernstein_half<6>(f, f_left, f_right);
            split_bernstein_half<3>(d, d_left, d_right);
        } else {
            split_bernstein(f, n, 0.5, f_left, f_right);
            split_bernstein(d, m, 0.5, d_left, d_right);
        }
        double left_low, right_low, unused;
        tau_range(d_left, m, left_low, unused);
        tau_range(d_right, m, right_low, unused);
        const double half = 0.5 * width;
        if (left_low <= right_low) {
            isolate<kMaxF>(piece, f_left, d_left, start, half, depth + 1);
            isolate<kMaxF>(piece, f_right, d_right, start + half, half, depth + 1);
        } else {
            isolate<kMaxF>(piece, f_right, d_right, start + half, half, depth + 1);
            isolate<kMaxF>(piece, f_left, d_left, start, half, depth + 1);
        }
    }

    // The one root of F in [lo, hi] (F's sign at lo is given): Newton steps on u, each replaced by
    // a bisection when it would leave the bracket, so it always converges.
    void refine(uint32_t piece, double lo, double hi, double u, bool positive_at_lo) {
        for (int step = 0; step < 100; ++step) {
            const ProfilePoint p = profile_at(s_, piece, u);
            const double d = p.y - r_.oy;
            const double value = r_.dy * r_.dy * (p.x * p.x - r_.c) - 2 * r_.dy * r_.b * d - r_.a * d * d;
            const double slope = 2 * (r_.dy * r_.dy * p.x * p.dx - r_.dy * r_.b * p.dy - r_.a * d * p.dy);
            ++counters_.newton_iterations;
            if (value == 0) break;
            if ((value > 0) == positive_at_lo)
                lo = u;
            else
                hi = u;
            double next = u - value / slope;
            if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
            // Newton's error squares at each step: after a step of 1e-7 it is about 1e-14·F''/F',
            // which moves the point far less than float precision.
            const bool converged = std::fabs(next - u) <= 1e-7 || hi - lo <= 1e-14;
            u = next;
            if (converged) break;
        }
        offer_root(piece, u);
    }

    // A root u of F: its τ from the y equation, polished where d_y is small.
    void offer_root(uint32_t piece, double u) {
        const ProfilePoint p = profile_at(s_, piece, u);
        double tau = (p.y - r_.oy) / r_.dy;
        if (r_.dy * r_.dy < kPolishSquared * r_.length_squared && !polish(piece, u, tau)) ++counters_.newton_failures;
        offer(piece, u, tau);
    }

    // Rays with d_y ≈ 0: y(u) = o_y gives u; the circle of radius |x(u)| at that height gives τ
    // (twice: in and out); Newton's method then corrects for the small d_y.
    void solve_horizontal(uint32_t piece) {
        const int m = s_.degree;
        const double* ys = &s_.y[static_cast<size_t>(piece) * static_cast<size_t>(m + 1)];
        double d[kMaxBernsteinDegree + 1], roots[kMaxBernsteinDegree];
        for (int i = 0; i <= m; ++i) d[i] = ys[i] - r_.oy;
        const int count = bernstein_roots(d, m, roots);
        for (int k = 0; k < count && !done_; ++k) {
            const double x = profile_at(s_, piece, roots[k]).x;
            const double reach = (x * x - r_.h2) / r_.a;
            if (reach < 0) continue;
            for (double sign : {-1.0, 1.0}) {
                double u = roots[k], tau = r_.tc + sign * std::sqrt(reach);
                if (!polish(piece, u, tau)) ++counters_.newton_failures;
                offer(piece, u, tau);
            }
        }
    }

    void offer(uint32_t piece, double u, double tau) {
        if (!(tau > tau_min_)) return;
        const bool better = tau < tau_max_ || (found_ && tau == tau_max_ && piece < best_piece_);
        if (!better) return;
        found_ = true;
        tau_max_ = tau;
        best_u_ = u;
        best_piece_ = piece;
        if (any_hit_) done_ = true;
    }

    const RevSurface& s_;
    const RaySetup& r_;
    double tau_min_, tau_max_;
    bool any_hit_;
    bool found_ = false, done_ = false;
    double best_u_ = 0;
    uint32_t best_piece_ = 0;
    int intervals_ = 0;
    double lo_ = 0, hi_ = 0;  // the ring's τ interval for the piece being solved
};

ProfileNode piece_ring(const std::vector<double>& x, const std::vector<double>& y, int degree, uint32_t piece,
                       double pad) {
    // Monotone in x and y (make_rev_surface cuts the profile where they turn): the ends bound it.
    const size_t first = static_cast<size_t>(piece) * static_cast<size_t>(degree + 1);
    const size_t last = first + static_cast<size_t>(degree);
    ProfileNode node;
    node.y_min = std::min(y[first], y[last]) - pad;
    node.y_max = std::max(y[first], y[last]) + pad;
    const double r0 = std::fabs(x[first]), r1 = std::fabs(x[last]);
    node.radius_max = std::max(r0, r1) + pad;
    const bool crosses_axis = (x[first] < 0) != (x[last] < 0);
    node.radius_min = crosses_axis ? 0 : std::max(0.0, std::min(r0, r1) - pad);
    node.first = piece;
    node.count = 1;
    return node;
}

void build_nodes(RevSurface& s, uint32_t index, uint32_t first, uint32_t count, double pad) {
    if (count == 1) {
        s.nodes[index] = piece_ring(s.x, s.y, s.degree, first, pad);
        return;
    }
    const uint32_t child = static_cast<uint32_t>(s.nodes.size());
    s.nodes.resize(s.nodes.size() + 2);
    const uint32_t half = count / 2;
    build_nodes(s, child, first, half, pad);
    build_nodes(s, child + 1, first + half, count - half, pad);
    const ProfileNode& a = s.nodes[child];
    const ProfileNode& b = s.nodes[child + 1];
    ProfileNode node;
    node.y_min = std::min(a.y_min, b.y_min);
    node.y_max = std::max(a.y_max, b.y_max);
    node.radius_min = std::min(a.radius_min, b.radius_min);
    node.radius_max = std::max(a.radius_max, b.radius_max);
    node.first = child;
    node.count = 0;
    s.nodes[index] = node;
}

// The parameters in (0, 1) where a piece's x or y turns (roots of the derivatives), ascending.
std::vector<double> turning_points(const std::vector<double>& x, const std::vector<double>& y) {
    const int m = static_cast<int>(x.size()) - 1;
    std::vector<double> cuts;
    if (m < 2) return cuts;
    for (const std::vector<double>* c : {&x, &y}) {
        double derivative[kMaxBernsteinDegree + 1], roots[kMaxBernsteinDegree];
        for (int i = 0; i < m; ++i) derivative[i] = m * ((*c)[static_cast<size_t>(i) + 1] - (*c)[static_cast<size_t>(i)]);
        const int count = bernstein_roots(derivative, m - 1, roots);
        for (int k = 0; k < count; ++k)
            if (roots[k] > 1e-9 && roots[k] < 1 - 1e-9) cuts.push_back(roots[k]);
    }
    std::sort(cuts.begin(), cuts.end());
    std::vector<double> distinct;
    for (double u : cuts)
        if (distinct.empty() || u - distinct.back() > 1e-9) distinct.push_back(u);
    return distinct;
}

}  // namespace

RevSurface make_rev_surface(const Curve& profile) {
    RevSurface s;
    s.degree = curve_degree(profile);
    RAYCAST_CHECK(s.degree >= 1 && s.degree < kMaxBezierControlPoints);
    const int m = s.degree;
    s.product_weights = bernstein_product_weights(m);
    s.scale = 0;
    for (const Vec3f& p : profile.controls) s.scale = std::max({s.scale, double(std::fabs(p.x)), double(std::fabs(p.y))});
    if (!(s.scale > 0)) s.scale = 1;
    for (const BezierPiece& piece : curve_bezier_pieces(profile)) {
        std::vector<double> x, y;
        for (const Vec3d& p : piece.points) {
            x.push_back(p.x);
            y.push_back(p.y);
        }
        const bool is_point = std::all_of(piece.points.begin(), piece.points.end(), [&](const Vec3d& p) {
            return p.x == piece.points[0].x && p.y == piece.points[0].y;
        });
        // A piece on the axis turns into a segment of it: no area, never seen, but a ray exactly
        // through the axis found it (every other column of a profile drawn on the axis).
        const bool on_axis =
            std::all_of(piece.points.begin(), piece.points.end(), [](const Vec3d& p) { return p.x == 0; });
        if (is_point || on_axis) continue;
        // Cut at every turn of x or y; the last part keeps the piece's own end point, so that
        // neighbouring pieces still share theirs exactly.
        double done = 0;
        const double span = piece.t_end - piece.t_begin;
        std::vector<double> cuts = turning_points(x, y);
        cuts.push_back(1);
        for (double cut : cuts) {
            std::vector<double> left_x(x.size()), left_y(y.size()), right_x(x.size()), right_y(y.size());
            if (cut < 1) {
                const double local = (cut - done) / (1 - done);
                split_bernstein(x.data(), m, local, left_x.data(), right_x.data());
                split_bernstein(y.data(), m, local, left_y.data(), right_y.data());
            } else {
                left_x = x;
                left_y = y;
            }
            s.x.insert(s.x.end(), left_x.begin(), left_x.end());
            s.y.insert(s.y.end(), left_y.begin(), left_y.end());
            s.t_begin.push_back(piece.t_begin + done * span);
            s.t_end.push_back(piece.t_begin + cut * span);
            x = right_x;
            y = right_y;
            done = cut;
        }
    }
    const uint32_t pieces = s.piece_count();
    s.x_squared.resize(static_cast<size_t>(pieces) * static_cast<size_t>(2 * m + 1));
    for (uint32_t p = 0; p < pieces; ++p) {
        const double* x = &s.x[static_cast<size_t>(p) * static_cast<size_t>(m + 1)];
        multiply_bernstein(x, x, m, s.product_weights.data(), &s.x_squared[static_cast<size_t>(p) * static_cast<size_t>(2 * m + 1)]);
    }
    if (pieces == 0) return s;
    s.nodes.resize(1);
    build_nodes(s, 0, 0, pieces, 1e-9 * s.scale);
    for (const ProfileNode& node : s.nodes) {
        if (node.count == 0) continue;
        const float r = static_cast<float>(node.radius_max), y0 = static_cast<float>(node.y_min),
                    y1 = static_cast<float>(node.y_max);
        s.bounds.grow(Vec3f{-r, y0, -r});
        s.bounds.grow(Vec3f{r, y1, r});
    }
    return s;
}

bool intersect_rev_surface(const RevSurface& surface, const Ray& ray, float t_min, float t_max, bool any_hit,
                           RevSurfaceHit& hit, uint64_t* nodes_visited) {
    ++tally.tests;
    if (surface.nodes.empty()) return false;
    RaySetup r;
    if (!make_ray_setup(ray, r)) return false;
    // The whole path through the surface's ring, then the origin moved to its middle: every
    // quantity below is then of the surface's size, whatever the ray's distance.
    double lo = -INFINITY, hi = INFINITY;
    if (nodes_visited) ++*nodes_visited;
    if (!clip_to_ring(surface.nodes[0], r, lo, hi)) return false;
    r.move_origin(0.5 * (lo + hi));
    lo -= r.shift;
    hi -= r.shift;
    const double tau_min = double(t_min) - r.shift, tau_max = double(t_max) - r.shift;
    lo = std::max(lo, tau_min);
    hi = std::min(hi, tau_max);
    if (!(lo <= hi)) return false;
    Query query(surface, r, tau_min, tau_max, any_hit);
    query.run(lo, hi, nodes_visited);
    tally += query.counters_;
    if (!query.found()) return false;
    const float t = static_cast<float>(r.shift + query.tau());
    if (!(t > t_min && t < t_max)) return false;
    hit = {t, static_cast<float>(query.u()), query.piece()};
    return true;
}

bool polish_rev_surface_hit(const RevSurface& surface, uint32_t piece, const Ray& ray, double& u, double& t,
                            int& iterations) {
    RaySetup r;
    if (!make_ray_setup(ray, r)) return false;
    Query query(surface, r, -INFINITY, INFINITY, false);
    const bool converged = query.polish(piece, u, t);
    iterations = static_cast<int>(query.counters_.newton_iterations);
    return converged;
}

Vec3f rev_surface_normal(const RevSurface& surface, uint32_t piece, float u, Vec3f point) {
    ProfilePoint p = profile_at(surface, piece, u);
    // Where the parametrisation stops (a repeated control point), the tangent's direction is the
    // limit of nearby chords.
    if (p.dx * p.dx + p.dy * p.dy < 1e-24 * surface.scale * surface.scale) {
        const double a = std::max(0.0, double(u) - 1e-4), b = std::min(1.0, double(u) + 1e-4);
        const ProfilePoint pa = profile_at(surface, piece, a), pb = profile_at(surface, piece, b);
        p.dx = pb.x - pa.x;
        p.dy = pb.y - pa.y;
    }
    // The point is (x cos θ, y, x sin θ): the angle comes from its direction about the axis.
    const double radial = std::sqrt(double(point.x) * point.x + double(point.z) * point.z);
    double cos_theta = 1, sin_theta = 0;
    if (radial > 0) {
        const double sign = p.x < 0 ? -1 : 1;
        cos_theta = sign * point.x / radial;
        sin_theta = sign * point.z / radial;
    }
    return normalize(Vec3f{static_cast<float>(p.dy * cos_theta), static_cast<float>(-p.dx),
                           static_cast<float>(p.dy * sin_theta)});
}

Bounds3f rev_surface_bounds(const RevSurface& surface, const Mat4& m) {
    // A cylinder is the convex hull of its end discs; the disc of radius r at height y reaches
    // r·√(M_i0² + M_i2²) along world axis i from M·(0, y, 0).
    Bounds3f bounds;
    for (const ProfileNode& node : surface.nodes) {
        if (node.count == 0) continue;
        for (double y : {node.y_min, node.y_max}) {
            const Vec3f center = transform_point(m, Vec3f{0, static_cast<float>(y), 0});
            for (int i = 0; i < 3; ++i) {
                const float reach = static_cast<float>(node.radius_max) *
                                    std::sqrt(m.m[i][0] * m.m[i][0] + m.m[i][2] * m.m[i][2]);
                Vec3f low = center, high = center;
                low[i] -= reach;
                high[i] += reach;
                bounds.grow(low);
                bounds.grow(high);
            }
        }
    }
    return bounds;
}

RevSurfaceCounters take_rev_surface_counters() {
    const RevSurfaceCounters result = tally;
    tally = RevSurfaceCounters{};
    return result;
}

TriangleMesh tessellate_rev_surface(const Curve& profile, int along, int around) {
    TriangleMesh mesh;
    const ParameterRange range = curve_parameter_range(profile);
    const double two_pi = 6.283185307179586;
    for (int i = 0; i <= along; ++i) {
        const double t = range.begin + (range.end - range.begin) * i / along;
        const CurveSample c = eval_curve(profile, t);
        for (int j = 0; j < around; ++j) {
            const double theta = two_pi * j / around, cos_theta = std::cos(theta), sin_theta = std::sin(theta);
            mesh.positions.push_back(Vec3f{static_cast<float>(c.position.x * cos_theta), static_cast<float>(c.position.y),
                                           static_cast<float>(c.position.x * sin_theta)});
            mesh.normals.push_back(normalize(Vec3f{static_cast<float>(c.derivative.y * cos_theta),
                                                   static_cast<float>(-c.derivative.x),
                                                   static_cast<float>(c.derivative.y * sin_theta)}));
        }
    }
    const auto vertex = [around](int i, int j) { return static_cast<uint32_t>(i * around + j % around); };
    for (int i = 0; i < along; ++i)
        for (int j = 0; j < around; ++j) {
            const uint32_t quad[4] = {vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1)};
            for (int half = 0; half < 2; ++half) {
                uint32_t corner[3] = {quad[0], quad[half + 1], quad[half + 2]};
                // Counter-clockwise about the analytic normal, as an OBJ without normals would be.
                const Vec3f p0 = mesh.positions[corner[0]], p1 = mesh.positions[corner[1]], p2 = mesh.positions[corner[2]];
                const Vec3f n = mesh.normals[corner[0]] + mesh.normals[corner[1]] + mesh.normals[corner[2]];
                if (dot(cross(p1 - p0, p2 - p0), n) < 0) std::swap(corner[1], corner[2]);
                mesh.indices.insert(mesh.indices.end(), corner, corner + 3);
                mesh.normal_indices.insert(mesh.normal_indices.end(), corner, corner + 3);
            }
        }
    return mesh;
}

}  // namespace raycast
