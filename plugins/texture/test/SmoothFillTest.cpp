// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "SmoothFill.h"
#include "vdbmap/Error.h"

using namespace vdbmap;
using namespace vdbmap::texture;

TEST_CASE("harmonic fill of a path is the linear interpolation of its ends", "[texture][fill]") {
    // Faces 0..10 in a chain (a triangle strip's adjacency is a path), plus faces 11-12 linked
    // to each other only: a component without any textured face.
    std::vector<std::array<std::uint32_t, 2>> adjacency;
    for (std::uint32_t f = 0; f < 10; ++f) adjacency.push_back({f, f + 1});
    adjacency.push_back({11, 12});
    std::vector<char> known(13, 0);
    std::vector<Vec3f> color(13, Vec3f(7, 7, 7));
    known[0] = known[10] = 1;
    color[0] = Vec3f(0, 200, 50);
    color[10] = Vec3f(100, 0, 50);
    std::vector<char> filled;
    const std::vector<Vec3f> out = harmonicFill(known, color, adjacency, filled);
    for (int f = 0; f <= 10; ++f) {
        CHECK(filled[f] == (f > 0 && f < 10 ? 1 : 0));
        CHECK(out[f].x() == Approx(10.0f * f).margin(1e-4));
        CHECK(out[f].y() == Approx(200.0f - 20.0f * f).margin(1e-4));
        CHECK(out[f].z() == Approx(50.0f).margin(1e-4));
    }
    CHECK(filled[11] == 0);
    CHECK(filled[12] == 0);
    CHECK(out[11] == Vec3f(7, 7, 7));
}

TEST_CASE("harmonic fill on a grid: the mean-value property, within the border's range",
          "[texture][fill]") {
    // 12 x 12 grid graph, 4-neighbours; left column black, right column white, rest unknown.
    const int n = 12;
    const auto id = [&](int x, int y) { return static_cast<std::uint32_t>(y * n + x); };
    std::vector<std::array<std::uint32_t, 2>> adjacency;
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            if (x + 1 < n) adjacency.push_back({id(x, y), id(x + 1, y)});
            if (y + 1 < n) adjacency.push_back({id(x, y), id(x, y + 1)});
        }
    }
    std::vector<char> known(n * n, 0);
    std::vector<Vec3f> color(n * n, Vec3f::Zero());
    for (int y = 0; y < n; ++y) {
        known[id(0, y)] = known[id(n - 1, y)] = 1;
        color[id(n - 1, y)] = Vec3f(255, 255, 255);
    }
    std::vector<char> filled;
    const std::vector<Vec3f> out = harmonicFill(known, color, adjacency, filled);
    for (int y = 0; y < n; ++y) {
        for (int x = 1; x + 1 < n; ++x) {
            // With insulated top and bottom rows the solution is linear in x.
            CHECK(out[id(x, y)].x() == Approx(255.0f * x / (n - 1)).margin(1e-3));
        }
    }
    CHECK_THROWS_AS(harmonicFill(known, std::vector<Vec3f>(3), adjacency, filled), InvalidInput);
    CHECK_THROWS_AS(harmonicFill(known, color, {{0, 999}}, filled), InvalidInput);
}

TEST_CASE("weighted harmonic fill and crease weights in closed form", "[texture][fill]") {
    // Path 0 - 1 - 2, ends fixed at 0 and 100, weights 1 and 3: x_1 = (1 * 0 + 3 * 100) / 4.
    const std::vector<std::array<std::uint32_t, 2>> path{{0, 1}, {1, 2}};
    const std::vector<char> known{1, 0, 1};
    const std::vector<Vec3f> color{Vec3f::Zero(), Vec3f::Zero(), Vec3f(100, 100, 100)};
    const std::vector<float> w{1.0f, 3.0f};
    std::vector<char> filled;
    const auto out = harmonicFill(known, color, path, filled, &w);
    CHECK(out[1].x() == Approx(75.0f).margin(1e-4));
    const std::vector<float> bad{1.0f};
    CHECK_THROWS_AS(harmonicFill(known, color, path, filled, &bad), InvalidInput);

    // Three triangles: 0 and 1 coplanar (z = 0), 2 folded up by 90 degrees along x = 1.
    const std::vector<Vec3f> v{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, 0, 1}};
    const std::vector<std::array<std::uint32_t, 3>> faces{{0, 1, 2}, {0, 2, 3}, {1, 4, 2}};
    const std::vector<std::array<std::uint32_t, 2>> adjacency{{0, 1}, {0, 2}};
    const auto cw = creaseWeights(v, faces, adjacency, 20.0, 0.01);
    CHECK(cw[0] == Approx(1.0f));
    CHECK(cw[1] == Approx(0.01f));  // exp(-(90/20)^2 / 2) = 4e-5, floored
    CHECK(creaseWeights(v, faces, {{0, 1}}, 90.0, 0.01)[0] == Approx(1.0f));
}
