// SPDX-License-Identifier: Apache-2.0
// The integrator's fast per-point kernel (map/RayUpdate.h: float, incremental sdf, offsets and
// leaf crossings) against the slow reference: the double-precision Amanatides-Woo walk
// (map/RayTraversal.h) with sdf = n . (c - p) and t = d . (c - p) recomputed per voxel and the
// weight from distanceFalloff and behindSurfaceFactor (vdbmap/map/MeasurementWeight.h).
#include <catch2/catch.hpp>
#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "map/RayTraversal.h"
#include "map/RayUpdate.h"
#include "vdbmap/map/MeasurementWeight.h"

using namespace vdbmap;
using openvdb::Coord;

namespace {

struct Update {
    Coord ijk;
    float sdf;
    float w;
};

/// Records the kernel's updates and checks its leaf bookkeeping on every one: the leaf it
/// announced last must be the voxel's leaf and the offset the voxel's offset in it.
struct RecordingSink {
    std::vector<Update> updates;
    Coord leaf = Coord::max();
    std::size_t leaf_changes = 0;
    std::size_t bad_bookkeeping = 0;
    bool enterLeaf(const Coord& origin) {
        if (origin != leaf) ++leaf_changes;
        leaf = origin;
        return true;
    }
    void update(int i, int j, int k, unsigned offset, float sdf, float w) {
        const Coord c(i, j, k);
        if ((c & ~7) != leaf || offset != openvdb::FloatTree::LeafNodeType::coordToOffset(c))
            ++bad_bookkeeping;
        updates.push_back({c, sdf, w});
    }
};

std::vector<Update> reference(const Vec3d& p, const Vec3d& dir, const Vec3d& n, double w_inc,
                              double eps, double vs, double inv_l2, double floor) {
    std::vector<Update> out;
    detail::traverseSegment(p - dir * eps, dir, 2.0 * eps, 1.0 / vs, [&](const Coord& v) {
        const Vec3d centre(v.x() * vs, v.y() * vs, v.z() * vs);
        const double sdf = std::clamp(n.dot(centre - p), -eps, eps);
        const double w = w_inc * distanceFalloff(dir.dot(centre - p), inv_l2, floor) *
                         behindSurfaceFactor(sdf, eps, vs);
        if (w > 0.0) out.push_back({v, static_cast<float>(sdf), static_cast<float>(w)});
    });
    return out;
}

}  // namespace

TEST_CASE("Fast ray kernel equals the double-precision reference walk", "[tsdf][kernel]") {
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> pos(-60.0, 60.0), unit(-1.0, 1.0), eps_of(0.1, 0.3),
        w_of(0.1, 1.0);
    const double vs = 0.1;
    std::size_t rays = 0, same_walk = 0, updates = 0, leaf_changes = 0;
    double max_sdf_err = 0.0, max_w_excess = 0.0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3d p(pos(rng), pos(rng), 0.1 * pos(rng));
        Vec3d dir(unit(rng), unit(rng), unit(rng));
        if (i % 10 == 0) dir = Vec3d(unit(rng), 0.0, 0.0);  // axis-parallel rays: zero steps
        if (dir.norm() < 1e-3) continue;
        dir.normalize();
        Vec3d n(unit(rng), unit(rng), unit(rng));
        if (n.norm() < 1e-3) continue;
        n.normalize();
        if (n.dot(dir) > 0.0) n = -n;  // oriented towards the sensor
        const double eps = eps_of(rng), w_inc = w_of(rng);
        // Every other ray with the distance falloff (l in [0.05, 0.3] m, floor 0.1), the others
        // without (the paper mode).
        const double ell = i % 2 ? 0.05 + 0.25 * (0.5 + 0.5 * unit(rng)) : 0.0;
        const float inv_l2 = ell > 0.0 ? static_cast<float>(1.0 / (ell * ell)) : 0.0f;
        const float floor = ell > 0.0 ? 0.1f : 1.0f;
        // The integrator works on float points and directions.
        const Vec3f pf = p.cast<float>(), df = dir.cast<float>(), nf = n.cast<float>();
        const Vec3d pd = pf.cast<double>(), dd = df.cast<double>(), nd = nf.cast<double>();
        const float epsf = static_cast<float>(eps);
        const float inv_dropoff = epsf > vs ? 1.0f / (epsf - static_cast<float>(vs)) : 0.0f;
        RecordingSink sink;
        detail::RayWeight weight;
        weight.w_inc = static_cast<float>(w_inc);
        weight.inv_dropoff = inv_dropoff;
        weight.inv_falloff2 = inv_l2;
        weight.falloff_floor = floor;
        detail::integrateRay(detail::RaySegment::of(pf, df, epsf, static_cast<float>(1.0 / vs)), pf, df,
                             nf, epsf, static_cast<float>(vs), weight, sink);
        const auto ref = reference(pd, dd, nd, w_inc, static_cast<double>(epsf), vs,
                                   static_cast<double>(inv_l2), static_cast<double>(floor));
        ++rays;
        REQUIRE(sink.bad_bookkeeping == 0);
        updates += sink.updates.size();
        leaf_changes += sink.leaf_changes;
        bool same = sink.updates.size() == ref.size();
        for (std::size_t k = 0; same && k < ref.size(); ++k) same = sink.updates[k].ijk == ref[k].ijk;
        if (!same) continue;  // float vs double rounding at a voxel face: counted below
        ++same_walk;
        for (std::size_t k = 0; k < ref.size(); ++k) {
            max_sdf_err = std::max(max_sdf_err, static_cast<double>(std::abs(sink.updates[k].sdf - ref[k].sdf)));
            // The weight follows the sdf through the drop-off slope w_inc / (eps - voxel) and t
            // through the falloff's slope (at most 0.65 / l); the falloff itself is the SSE
            // reciprocal estimate, 1.5 * 2^-12 relative (FastReciprocal.h).
            const double w_err = std::abs(sink.updates[k].w - ref[k].w);
            const double estimate = ell > 0.0 ? 1.5 / 4096.0 * ref[k].w : 0.0;
            const double allowed =
                1e-6 + 2e-5 * w_inc * (inv_dropoff + 0.65 * std::sqrt(inv_l2)) + estimate;
            max_w_excess = std::max(max_w_excess, w_err - allowed);
        }
    }
    INFO(rays << " rays, " << same_walk << " identical walks, " << updates << " updates, "
              << leaf_changes << " leaf changes");
    REQUIRE(rays > 19000);
    // The walks differ only where float and double round a voxel-face crossing differently.
    CHECK(static_cast<double>(same_walk) >= 0.995 * static_cast<double>(rays));
    CHECK(leaf_changes > rays);  // the walks did cross leaves
    CHECK(max_sdf_err < 2e-5);   // float over at most ~10 incremental steps at |p| <= 60 m
    CHECK(max_w_excess <= 0.0);
}

TEST_CASE("Fast ray kernel skips the voxels of missing leaves", "[tsdf][kernel]") {
    // Only the leaf at the origin exists: a ray along +x from x = -0.35 m to +0.35 m updates
    // the voxels of that leaf only (x index 0..3), in order.
    struct OneLeafSink {
        std::vector<int> xs;
        bool enterLeaf(const Coord& origin) { return origin == Coord(0, 0, 0); }
        void update(int i, int, int, unsigned, float, float) { xs.push_back(i); }
    } sink;
    const Vec3f p(0.0f, 0.02f, 0.02f), dir(1.0f, 0.0f, 0.0f), n(-1.0f, 0.0f, 0.0f);
    detail::RayWeight weight;
    weight.inv_dropoff = 1.0f / 0.25f;
    detail::integrateRay(detail::RaySegment::of(p, dir, 0.35f, 10.0f), p, dir, n, 0.35f, 0.1f, weight,
                         sink);
    CHECK(sink.xs == std::vector<int>{0, 1, 2, 3});
}
