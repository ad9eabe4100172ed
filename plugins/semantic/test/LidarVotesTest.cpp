// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <random>

#include "LidarVotes.h"
#include "VoteCombination.h"
#include "vdbmap/Error.h"

using namespace vdbmap;
using namespace vdbmap::semantic;

namespace {

// An n x n grid of squares of side s on z = 0, each split into two triangles.
struct Grid {
    std::vector<Vec3f> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

Grid flatGrid(int n, float s) {
    Grid g;
    for (int y = 0; y <= n; ++y) {
        for (int x = 0; x <= n; ++x) g.vertices.emplace_back(x * s, y * s, 0.0f);
    }
    const auto at = [&](int x, int y) { return static_cast<std::uint32_t>(y * (n + 1) + x); };
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            g.triangles.push_back({at(x, y), at(x + 1, y), at(x + 1, y + 1)});
            g.triangles.push_back({at(x, y), at(x + 1, y + 1), at(x, y + 1)});
        }
    }
    return g;
}

FaceVotes votesOf(std::size_t faces, std::size_t classes,
                  const std::vector<std::vector<std::pair<std::uint32_t, float>>>& per_face) {
    FaceVotes v;
    v.num_classes = classes;
    v.offsets.push_back(0);
    for (std::size_t f = 0; f < faces; ++f) {
        for (const auto& [c, w] : per_face[f]) {
            v.classes.push_back(c);
            v.weights.push_back(w);
        }
        v.offsets.push_back(v.classes.size());
    }
    return v;
}

}  // namespace

TEST_CASE("point-triangle distance in closed form", "[semantic][lidar]") {
    const Vec3f a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    CHECK(pointTriangleDistance({0.25f, 0.25f, 0.3f}, a, b, c) == Approx(0.3f));   // face
    CHECK(pointTriangleDistance({-0.3f, -0.4f, 0.0f}, a, b, c) == Approx(0.5f));  // vertex a
    CHECK(pointTriangleDistance({0.5f, -0.2f, 0.0f}, a, b, c) == Approx(0.2f));   // edge ab
    CHECK(pointTriangleDistance({1.0f, 1.0f, 0.0f}, a, b, c) ==
          Approx(std::sqrt(0.5f)));                                               // edge bc
    CHECK(pointTriangleDistance({2.0f, -1.0f, 0.0f}, a, b, c) == Approx(std::sqrt(2.0f)));
}

TEST_CASE("LiDAR votes: each point adds 1 - (d/r)^2 to the faces within r", "[semantic][lidar]") {
    const Grid g = flatGrid(20, 0.05f);  // 1 m x 1 m, 800 faces
    const float r = 0.08f;
    LidarVoteAccumulator acc(g.vertices, g.triangles, 3, r);

    // One point 0.05 m above the centre of a lower triangle: that face at d = 0.05 exactly.
    const Vec3f p(0.5f + 0.0375f, 0.5f + 0.0125f, 0.05f);
    acc.add({p}, {2});
    // A void point and a point far above the mesh vote for nothing.
    acc.add({Vec3f(0.3f, 0.3f, 0.0f), Vec3f(0.5f, 0.5f, 1.0f)},
            {LidarVoteAccumulator::kNoClass, 1});
    const FaceVotes votes = acc.finish();
    REQUIRE(votes.numFaces() == g.triangles.size());
    CHECK(votes.votes == 1);
    CHECK(votes.void_votes == 1);
    CHECK(acc.pointsWithoutFace() == 1);
    std::size_t voted = 0;
    for (std::size_t f = 0; f < g.triangles.size(); ++f) {
        const auto& t = g.triangles[f];
        const float d = pointTriangleDistance(p, g.vertices[t[0]], g.vertices[t[1]], g.vertices[t[2]]);
        if (d < r) {
            ++voted;
            REQUIRE(votes.offsets[f + 1] - votes.offsets[f] == 1);
            CHECK(votes.classes[votes.offsets[f]] == 2);
            CHECK(votes.weights[votes.offsets[f]] == Approx(1.0f - d * d / (r * r)));
        } else {
            REQUIRE_FALSE(votes.observed(f));
        }
    }
    // Faces whose closest point is within sqrt(r^2 - h^2) = 0.0624 m in the plane.
    CHECK(voted > 8);
    const std::size_t centre = (10 * 20 + 10) * 2;  // lower triangle of square (10, 10)
    CHECK(votes.weights[votes.offsets[centre]] == Approx(1.0f - 0.05f * 0.05f / (r * r)));

    CHECK_THROWS_AS(acc.add({p}, {3}), InvalidInput);
    CHECK_THROWS_AS(acc.add({p, p}, {0}), InvalidInput);
    CHECK_THROWS_AS(LidarVoteAccumulator(g.vertices, g.triangles, 3, 0.0f), InvalidInput);
}

TEST_CASE("LiDAR votes equal a brute-force oracle on random points", "[semantic][lidar]") {
    const Grid g = flatGrid(16, 0.05f);
    const float r = 0.1f;
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> xy(-0.1f, 0.9f), z(-0.12f, 0.12f);
    std::uniform_int_distribution<std::uint32_t> cls(0, 3);
    std::vector<Vec3f> points;
    std::vector<std::uint32_t> classes;
    for (int i = 0; i < 300; ++i) {
        // Spread out so that no two points share a merge cell (r/2): each counts alone.
        points.emplace_back(xy(rng), xy(rng), z(rng));
        classes.push_back(cls(rng));
    }
    std::vector<float> oracle(g.triangles.size() * 4, 0.0f);
    LidarVoteAccumulator acc(g.vertices, g.triangles, 4, r, 1);  // flush every add
    for (std::size_t i = 0; i < points.size(); ++i) {
        acc.add({points[i]}, {classes[i]});  // batch of 1: no merging
        for (std::size_t f = 0; f < g.triangles.size(); ++f) {
            const auto& t = g.triangles[f];
            const float d = pointTriangleDistance(points[i], g.vertices[t[0]], g.vertices[t[1]],
                                                  g.vertices[t[2]]);
            if (d < r) oracle[f * 4 + classes[i]] += 1.0f - d * d / (r * r);
        }
    }
    const FaceVotes votes = acc.finish();
    for (std::size_t f = 0; f < g.triangles.size(); ++f) {
        std::vector<float> got(4, 0.0f);
        for (auto k = votes.offsets[f]; k < votes.offsets[f + 1]; ++k) {
            got[votes.classes[k]] = votes.weights[k];
        }
        for (int c = 0; c < 4; ++c) REQUIRE(got[c] == Approx(oracle[f * 4 + c]).margin(1e-5));
    }
}

TEST_CASE("points of one scan in one merge cell count as their mean, weighted by their number",
          "[semantic][lidar]") {
    const Grid g = flatGrid(10, 0.1f);
    const float r = 0.2f;
    LidarVoteAccumulator merged(g.vertices, g.triangles, 2, r), mean(g.vertices, g.triangles, 2, r);
    // Three points in the cell [0.4, 0.5)^2 x [0, 0.1) of size r/2 = 0.1 m.
    merged.add({Vec3f(0.41f, 0.42f, 0.01f), Vec3f(0.45f, 0.46f, 0.05f), Vec3f(0.49f, 0.41f, 0.03f)},
               {1, 1, 1});
    const Vec3f centre((0.41f + 0.45f + 0.49f) / 3, (0.42f + 0.46f + 0.41f) / 3, 0.03f);
    for (int k = 0; k < 3; ++k) mean.add({centre}, {1});
    const FaceVotes a = merged.finish(), b = mean.finish();
    CHECK(a.votes == 3);
    REQUIRE(a.classes == b.classes);
    for (std::size_t k = 0; k < a.weights.size(); ++k) CHECK(a.weights[k] == Approx(b.weights[k]));
}

TEST_CASE("the two sources combine as (a_I P_I + w_L a_L P_L) / (a_I + w_L a_L)", "[semantic]") {
    // Face 0: images only; face 1: LiDAR only; face 2: both; face 3: neither.
    const FaceVotes images = votesOf(4, 3, {{{0, 30.0f}, {1, 10.0f}}, {}, {{0, 50.0f}}, {}});
    const FaceVotes lidar = votesOf(4, 3, {{}, {{2, 2.0f}}, {{1, 1.5f}, {2, 0.5f}}, {}});
    std::vector<std::uint8_t> sources;
    const FaceVotes both = combineVotes(images, lidar, 2.0, &sources);
    CHECK(sources == std::vector<std::uint8_t>{kSourceImages, kSourceLidar,
                                               kSourceImages | kSourceLidar, kSourceNone});
    const auto p = [&](std::size_t f, std::uint32_t c) {
        for (auto k = both.offsets[f]; k < both.offsets[f + 1]; ++k) {
            if (both.classes[k] == c) return static_cast<double>(both.weights[k]);
        }
        return 0.0;
    };
    CHECK(p(0, 0) == Approx(0.75));
    CHECK(p(0, 1) == Approx(0.25));
    CHECK(p(1, 2) == Approx(1.0));
    // Face 2: P_I = (1, 0, 0), P_L = (0, 0.75, 0.25), w_L = 2: (1, 1.5, 0.5) / 3.
    CHECK(p(2, 0) == Approx(1.0 / 3.0));
    CHECK(p(2, 1) == Approx(0.5));
    CHECK(p(2, 2) == Approx(0.5 / 3.0));
    CHECK_FALSE(both.observed(3));

    // lidar_weight 0: the LiDAR is ignored where images voted, and a LiDAR-only face has no data.
    const FaceVotes images_only = combineVotes(images, lidar, 0.0);
    CHECK(images_only.offsets[3] - images_only.offsets[2] == 1);
    CHECK_FALSE(images_only.observed(1));
    // One source off (no faces): the other alone, normalised.
    const FaceVotes lidar_only = combineVotes(FaceVotes(), lidar, 1.0);
    CHECK(lidar_only.numFaces() == 4);
    CHECK_FALSE(lidar_only.observed(0));
    CHECK(lidar_only.weights[lidar_only.offsets[2]] == Approx(0.75));
    CHECK_THROWS_AS(combineVotes(images, votesOf(3, 3, {{}, {}, {}}), 1.0), InvalidInput);
    CHECK_THROWS_AS(combineVotes(images, lidar, -1.0), InvalidInput);
}
