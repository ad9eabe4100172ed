// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "vdbmap/Error.h"
#include "vdbmap/eval/SemanticBoundary.h"
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
    // The confusion rows: 15 m^2 of each class went to the other one.
    REQUIRE(m.classes.size() == 2);
    REQUIRE(m.classes[0].confused_m2.size() == 1);
    CHECK(m.classes[0].confused_m2[0].first == 2);
    CHECK(m.classes[0].confused_m2[0].second == Approx(15.0));
    CHECK(m.classes[1].confused_m2[0].first == 0);
    // Unlabelled faces count as wrong and are reported.
    std::vector<std::uint8_t> partial = g.labels;
    for (std::size_t f = 0; f < 20; ++f) partial[f] = 255;
    const SemanticMetrics u = evaluateSemantics(g.v, g.t, partial, gt, g.labels);
    CHECK(u.unlabelled_fraction == Approx(0.1));
    CHECK(u.overall_accuracy == Approx(0.9));
    // The first row (10 m^2) is unlabelled: 5 m^2 of each class.
    REQUIRE(u.classes[0].confused_m2.size() == 1);
    CHECK(u.classes[0].confused_m2[0].first == 255);
    CHECK(u.classes[0].confused_m2[0].second == Approx(5.0));
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

TEST_CASE("A marking stacked on the asphalt labels the faces above it", "[eval][semantic]") {
    // Ground truth: asphalt (0) at z = 0 and a marking strip (19) 5 mm above it over x in
    // [4, 6]. The prediction is the plane z = 1 mm (a marking face whose centroid is nearer the
    // asphalt, as a reconstruction at 5 cm voxels gives), labelled right everywhere.
    Grid asphalt = grid(10);
    for (auto& l : asphalt.labels) l = 0;
    Grid gt = asphalt;
    const std::uint32_t base = static_cast<std::uint32_t>(gt.v.size());
    for (const Vec3f& p : {Vec3f(4, 0, 0.005f), Vec3f(6, 0, 0.005f), Vec3f(6, 10, 0.005f),
                           Vec3f(4, 10, 0.005f)}) {
        gt.v.push_back(p);
    }
    gt.t.push_back({base, base + 1, base + 2});
    gt.t.push_back({base, base + 2, base + 3});
    gt.labels.insert(gt.labels.end(), {19, 19});
    const Raycaster gt_rc(gt.v, gt.t);
    Grid pred = asphalt;
    for (auto& p : pred.v) p.z() = 0.001f;
    for (std::size_t f = 0; f < pred.t.size(); ++f) {
        const Vec3f c = (pred.v[pred.t[f][0]] + pred.v[pred.t[f][1]] + pred.v[pred.t[f][2]]) / 3;
        pred.labels[f] = c.x() > 4 && c.x() < 6 ? 19 : 0;
    }
    const GtLabelTransfer stacked = transferGtLabels(pred.v, pred.t, gt_rc, gt.labels, 0.5, 0.01);
    CHECK(stacked.stacked_resolved == 40);  // 2 columns x 10 rows x 2 triangles
    const SemanticMetrics m = scoreSemantics(stacked, pred.labels);
    CHECK(m.overall_accuracy == Approx(1.0));
    // The plain nearest-face transfer scores every marking face against the asphalt.
    const GtLabelTransfer nearest = transferGtLabels(pred.v, pred.t, gt_rc, gt.labels, 0.5, 0.0);
    CHECK(nearest.stacked_resolved == 0);
    CHECK(scoreSemantics(nearest, pred.labels).overall_accuracy == Approx(0.8));
    // A surface farther than the tolerance is not preferred: the plane 2 cm below the asphalt.
    Grid low = pred;
    for (auto& p : low.v) p.z() = -0.02f;
    const GtLabelTransfer deep = transferGtLabels(low.v, low.t, gt_rc, gt.labels, 0.5, 0.004);
    CHECK(deep.stacked_resolved == 0);
}

TEST_CASE("Scores on a face mask leave the other faces out", "[eval][semantic]") {
    const Grid g = grid(10);
    const Raycaster gt(g.v, g.t);
    const GtLabelTransfer t = transferGtLabels(g.v, g.t, gt, g.labels);
    std::vector<std::uint8_t> pred = g.labels;
    std::vector<std::uint8_t> mask(pred.size(), 1);
    // Rows 0-2 wrong (30 % of the area) and outside the mask; row 3 wrong inside it.
    for (std::size_t f = 0; f < 80; ++f) pred[f] = 255;
    for (std::size_t f = 0; f < 60; ++f) mask[f] = 0;
    const SemanticMetrics all = scoreSemantics(t, pred);
    const SemanticMetrics masked = scoreSemantics(t, pred, &mask);
    CHECK(all.overall_accuracy == Approx(0.6));
    CHECK(all.matched_area_m2 == Approx(100.0));
    CHECK(masked.matched_area_m2 == Approx(70.0));
    CHECK(masked.overall_accuracy == Approx(60.0 / 70.0));
    CHECK(masked.unlabelled_fraction == Approx(10.0 / 70.0));
    std::vector<std::uint8_t> short_mask(3, 1);
    CHECK_THROWS_AS(scoreSemantics(t, pred, &short_mask), InvalidInput);
}

TEST_CASE("Faces near a ground-truth class boundary are found", "[eval][semantic]") {
    // Classes 0 | 2 change at x = 5. Triangle centroids sit 1/3 and 2/3 into their unit
    // quad, so with a radius of 0.8 m (the 8 samples reach at least 0.8 cos(22.5 deg) = 0.74
    // along x) exactly the two quad columns next to x = 5 are near: 2 x 10 x 2 = 40 faces.
    const Grid g = grid(10);
    const Raycaster gt(g.v, g.t);
    const GtLabelTransfer transfer = transferGtLabels(g.v, g.t, gt, g.labels);
    const std::vector<std::uint8_t> near =
        nearGtClassBoundary(g.v, g.t, transfer, gt, g.labels, 0.8);
    REQUIRE(near.size() == g.t.size());
    std::size_t count = 0;
    for (std::size_t f = 0; f < near.size(); ++f) {
        const float x = (g.v[g.t[f][0]].x() + g.v[g.t[f][1]].x() + g.v[g.t[f][2]].x()) / 3.0f;
        INFO("face " << f << " centroid x " << x);
        CHECK(near[f] == ((x > 4.0f && x < 6.0f) ? 1 : 0));
        count += near[f];
    }
    CHECK(count == 40);
    // A mask on the near faces scores exactly them (20 m^2).
    const SemanticMetrics m = scoreSemantics(transfer, g.labels, &near);
    CHECK(m.matched_area_m2 == Approx(20.0));
    CHECK_THROWS_AS(nearGtClassBoundary(g.v, g.t, transfer, gt, g.labels, 0.0), InvalidInput);
}

TEST_CASE("Unlabelled faces with a labelled neighbour are counted", "[eval][semantic]") {
    const std::vector<std::uint8_t> labels{255, 3, 255, 255, 7};
    // 0-1: unknown next to known; 2-3: both unknown; 3-4: unknown next to known; 0-4 again 0.
    CHECK(unlabelledNextToLabelled(labels, {{0, 1}, {2, 3}, {3, 4}, {0, 4}}) == 2);
    CHECK(unlabelledNextToLabelled(labels, {{2, 3}}) == 0);
    CHECK_THROWS_AS(unlabelledNextToLabelled(labels, {{0, 5}}), InvalidInput);
}
