// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "vdbmap/Error.h"
#include "vdbmap/eval/GeometryMetrics.h"
#include "vdbmap/render/Raycaster.h"

using namespace vdbmap;

namespace {

// n x n grid of quads covering [0, size]^2 at height z.
void gridPlane(int n, float size, float z, std::vector<Vec3f>& v,
               std::vector<std::array<std::uint32_t, 3>>& t) {
    v.clear();
    t.clear();
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) v.emplace_back(size * i / n, size * j / n, z);
    }
    auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            t.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            t.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    }
}

std::vector<Vec3f> observedGrid(float lo, float hi, float step) {
    std::vector<Vec3f> p;
    for (float y = lo; y <= hi; y += step) {
        for (float x = lo; x <= hi; x += step) p.emplace_back(x, y, 0.0f);
    }
    return p;
}

}  // namespace

TEST_CASE("distanceStats on a known set", "[eval]") {
    std::vector<float> d;
    for (int i = 1; i <= 100; ++i) d.push_back(0.01f * i);
    const DistanceStats s = distanceStats(d);
    CHECK(s.count == 100);
    CHECK(s.mean == Approx(0.505));
    CHECK(s.median == Approx(0.5).margin(0.011));
    CHECK(s.p90 == Approx(0.9).margin(0.011));
    CHECK(s.max == Approx(1.0));
    CHECK(distanceStats({}).count == 0);
}

TEST_CASE("Ground truth against itself: zero error, F = 1", "[eval]") {
    std::vector<Vec3f> v;
    std::vector<std::array<std::uint32_t, 3>> t;
    gridPlane(10, 10.0f, 0.0f, v, t);
    const Raycaster gt(v, t);
    const auto observed = observedGrid(0.5f, 9.5f, 0.25f);
    const GeometryMetrics m = evaluateGeometry(v, t, gt, observed);
    CHECK(m.accuracy.max == Approx(0.0).margin(1e-5));
    CHECK(m.completeness.max == Approx(0.0).margin(1e-5));
    CHECK(m.chamfer_l1 == Approx(0.0).margin(1e-5));
    REQUIRE(m.fscores.size() == 3);
    for (const auto& f : m.fscores) CHECK(f.fscore == Approx(1.0));
    // Samples: about area / spacing^2 = 100 / 0.0004.
    CHECK(m.pred_samples == Approx(250000).epsilon(0.02));
}

TEST_CASE("A mesh offset by d has mean error d", "[eval]") {
    std::vector<Vec3f> gv, pv;
    std::vector<std::array<std::uint32_t, 3>> gt_tris, pt;
    gridPlane(10, 10.0f, 0.0f, gv, gt_tris);
    const float d = 0.03f;
    gridPlane(8, 8.0f, d, pv, pt);
    for (auto& p : pv) p += Vec3f(1.0f, 1.0f, 0.0f);  // [1, 9]^2, inside the gt
    const Raycaster gt(gv, gt_tris);
    const auto observed = observedGrid(1.0f, 9.0f, 0.2f);
    GeometryEvalOptions o;
    o.tau_m = {0.02, 0.05};
    std::vector<float> vertex_error;
    const GeometryMetrics m = evaluateGeometry(pv, pt, gt, observed, o, &vertex_error);
    CHECK(m.accuracy.mean == Approx(d).epsilon(1e-4));
    CHECK(m.accuracy.max == Approx(d).epsilon(1e-4));
    CHECK(m.completeness.mean == Approx(d).epsilon(1e-4));
    CHECK(m.chamfer_l1 == Approx(d).epsilon(1e-4));
    CHECK(m.fscores[0].fscore == Approx(0.0));  // tau 2 cm < 3 cm
    CHECK(m.fscores[1].fscore == Approx(1.0));  // tau 5 cm > 3 cm
    REQUIRE(vertex_error.size() == pv.size());
    for (float e : vertex_error) CHECK(e == Approx(d).epsilon(1e-4));
}

TEST_CASE("Unobserved prediction is not scored; missing prediction hurts completeness",
          "[eval]") {
    std::vector<Vec3f> gv, pv;
    std::vector<std::array<std::uint32_t, 3>> gt_tris, pt;
    gridPlane(10, 10.0f, 0.0f, gv, gt_tris);
    const Raycaster gt(gv, gt_tris);
    // Prediction: the gt plane plus a wall 2 m above it far from any observed point.
    gridPlane(10, 10.0f, 0.0f, pv, pt);
    const auto n0 = static_cast<std::uint32_t>(pv.size());
    pv.insert(pv.end(), {{20, 0, 2}, {21, 0, 2}, {21, 1, 2}});
    pt.push_back({n0, n0 + 1, n0 + 2});
    const auto observed = observedGrid(0.0f, 10.0f, 0.25f);
    const GeometryMetrics m = evaluateGeometry(pv, pt, gt, observed);
    CHECK(m.pred_samples_used < m.pred_samples);
    CHECK(m.accuracy.max == Approx(0.0).margin(1e-5));
    // A quarter of the prediction only: recall at 0.2 m counts the observed points within
    // 0.2 m of [0, 5]^2, i.e. 21 of 41 grid columns and rows.
    std::vector<Vec3f> hv;
    std::vector<std::array<std::uint32_t, 3>> ht;
    gridPlane(5, 5.0f, 0.0f, hv, ht);  // [0, 5]^2
    const GeometryMetrics h = evaluateGeometry(hv, ht, gt, observed);
    CHECK(h.fscores[2].recall == Approx((21.0 / 41.0) * (21.0 / 41.0)).margin(1e-6));
    CHECK(h.accuracy.mean == Approx(0.0).margin(1e-5));
    const GeometryMetrics empty = evaluateGeometry({}, {}, gt, observed);
    CHECK(empty.accuracy.count == 0);
    CHECK(empty.fscores[0].recall == 0.0);
    GeometryEvalOptions bad;
    bad.tau_m = {};
    CHECK_THROWS_AS(evaluateGeometry(hv, ht, gt, observed, bad), InvalidInput);
}

TEST_CASE("A ground-truth face mask scores only the selected surface", "[eval]") {
    // Ground truth: plane A = [0, 10]^2 (selected) and plane B = [20, 30] x [0, 10] (not).
    std::vector<Vec3f> gv, bv, pv;
    std::vector<std::array<std::uint32_t, 3>> gt_tris, bt;
    gridPlane(10, 10.0f, 0.0f, gv, gt_tris);
    gridPlane(10, 10.0f, 0.0f, bv, bt);
    const auto nA = static_cast<std::uint32_t>(gv.size());
    const std::size_t tA = gt_tris.size();
    for (auto& p : bv) gv.push_back(p + Vec3f(20, 0, 0));
    for (auto t : bt) gt_tris.push_back({t[0] + nA, t[1] + nA, t[2] + nA});
    const Raycaster gt(gv, gt_tris);
    // Prediction: A lifted by 3 cm, B lifted by 10 cm.
    std::vector<std::array<std::uint32_t, 3>> pt = gt_tris;
    pv = gv;
    for (std::size_t i = 0; i < pv.size(); ++i) pv[i].z() += i < nA ? 0.03f : 0.10f;
    std::vector<Vec3f> observed = observedGrid(0.0f, 10.0f, 0.5f);
    for (const auto& p : observedGrid(0.0f, 10.0f, 0.5f)) observed.push_back(p + Vec3f(20, 0, 0));
    GeometryEvalOptions o;
    const GeometryMetrics all = evaluateGeometry(pv, pt, gt, observed, o);
    CHECK(all.accuracy.max == Approx(0.10).epsilon(1e-3));
    o.gt_face_mask.assign(gt_tris.size(), 0);
    std::fill(o.gt_face_mask.begin(), o.gt_face_mask.begin() + static_cast<std::ptrdiff_t>(tA), 1);
    const GeometryMetrics a = evaluateGeometry(pv, pt, gt, observed, o);
    CHECK(a.accuracy.max == Approx(0.03).epsilon(1e-3));
    CHECK(a.completeness.mean == Approx(0.03).epsilon(1e-3));
    CHECK(a.gt_points_used == observed.size() / 2);
    o.gt_face_mask.resize(3);
    CHECK_THROWS_AS(evaluateGeometry(pv, pt, gt, observed, o), InvalidInput);
}
