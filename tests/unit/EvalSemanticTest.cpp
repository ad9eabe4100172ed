// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "vdbmap/Error.h"
#include "vdbmap/eval/SemanticMetrics.h"
#include "vdbmap/render/Raycaster.h"

using namespace vdbmap;

namespace {

// n x n unit quads (2 triangles each) in z = 0; left half class 0 (road), right half 2.
struct Grid {
    std::vector<Vec3f> v;
    std::vector<std::array<std::uint32_t, 3>> t;
    std::vector<std::uint8_t> labels;
};

Grid grid(int n) {
    Grid g;
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) g.v.emplace_back(i, j, 0.0f);
    }
    auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const std::uint8_t label = i < n / 2 ? 0 : 2;
            g.t.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            g.t.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
            g.labels.insert(g.labels.end(), {label, label});
        }
    }
    return g;
}

}  // namespace

TEST_CASE("Labels against themselves score 1", "[eval][semantic]") {
    const Grid g = grid(10);
    const Raycaster gt(g.v, g.t);
    const SemanticMetrics m = evaluateSemantics(g.v, g.t, g.labels, gt, g.labels);
    CHECK(m.overall_accuracy == Approx(1.0));
    CHECK(m.mean_class_accuracy == Approx(1.0));
    CHECK(m.miou == Approx(1.0));
    CHECK(m.unlabelled_fraction == Approx(0.0));
    CHECK(m.matched_area_m2 == Approx(100.0));
    REQUIRE(m.classes.size() == 2);
}

TEST_CASE("A known label swap gives accuracy 1 - swapped fraction", "[eval][semantic]") {
    const Grid g = grid(10);
    const Raycaster gt(g.v, g.t);
    // Swap classes 0 <-> 2 on the first 3 rows (30 % of the area).
    std::vector<std::uint8_t> pred = g.labels;
    for (std::size_t f = 0; f < 60; ++f) pred[f] = pred[f] == 0 ? 2 : 0;
    const SemanticMetrics m = evaluateSemantics(g.v, g.t, pred, gt, g.labels);
    CHECK(m.overall_accuracy == Approx(0.7));
    CHECK(m.mean_class_accuracy == Approx(0.7));
    // Per class: TP = 35, FN = 15, FP = 15: IoU = 35 / 65.
    CHECK(m.miou == Approx(35.0 / 65.0));
    // Unlabelled faces count as wrong and are reported.
    std::vector<std::uint8_t> partial = g.labels;
    for (std::size_t f = 0; f < 20; ++f) partial[f] = 255;
    const SemanticMetrics u = evaluateSemantics(g.v, g.t, partial, gt, g.labels);
    CHECK(u.unlabelled_fraction == Approx(0.1));
    CHECK(u.overall_accuracy == Approx(0.9));
}

TEST_CASE("Prediction far from the ground truth is unmatched", "[eval][semantic]") {
    const Grid g = grid(4);
    const Raycaster gt(g.v, g.t);
    Grid far = g;
    for (auto& p : far.v) p.z() += 2.0f;
    const SemanticMetrics m = evaluateSemantics(far.v, far.t, far.labels, gt, g.labels, 0.5);
    CHECK(m.matched_area_m2 == 0.0);
    CHECK(m.unmatched_area_m2 == Approx(16.0));
    std::vector<std::uint8_t> short_labels(3, 0);
    CHECK_THROWS_AS(evaluateSemantics(g.v, g.t, short_labels, gt, g.labels), InvalidInput);
}
