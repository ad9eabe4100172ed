// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>
#include <random>

#include "AtlasPacker.h"
#include "Patches.h"
#include "TextureAtlas.h"
#include "vdbmap/Error.h"
#include "vdbmap/mrf/PottsMrf.h"

using namespace vdbmap::texture;

namespace {

bool overlap(const RectSize& sa, const RectPlacement& a, const RectSize& sb,
             const RectPlacement& b) {
    if (a.page != b.page) return false;
    return a.x < b.x + sb.width && b.x < a.x + sa.width && a.y < b.y + sb.height &&
           b.y < a.y + sa.height;
}

}  // namespace

TEST_CASE("shelf packer places rectangles without overlap inside the pages", "[texture][atlas]") {
    std::mt19937 rng(4);
    std::uniform_int_distribution<int> side(1, 90);
    std::vector<RectSize> sizes(300);
    for (auto& s : sizes) s = {side(rng), side(rng)};
    for (int max_size : {128, 256, 8192}) {
        const PackResult packed = packRects(sizes, max_size);
        REQUIRE(packed.placements.size() == sizes.size());
        for (const auto& page : packed.pages) {
            CHECK(page.width <= max_size);
            CHECK(page.height <= max_size);
        }
        for (std::size_t i = 0; i < sizes.size(); ++i) {
            const auto& p = packed.placements[i];
            REQUIRE(p.page < static_cast<int>(packed.pages.size()));
            CHECK(p.x >= 0);
            CHECK(p.y >= 0);
            CHECK(p.x + sizes[i].width <= packed.pages[p.page].width);
            CHECK(p.y + sizes[i].height <= packed.pages[p.page].height);
            for (std::size_t j = i + 1; j < sizes.size(); ++j) {
                CHECK_FALSE(overlap(sizes[i], p, sizes[j], packed.placements[j]));
            }
        }
        if (max_size == 128) CHECK(packed.pages.size() > 1);
        if (max_size == 8192) CHECK(packed.pages.size() == 1);
    }
    CHECK_THROWS_AS(packRects({{10, 300}}, 256), vdbmap::InvalidInput);
    CHECK_THROWS_AS(packRects({{0, 3}}, 256), vdbmap::InvalidInput);
}

TEST_CASE("patches are connected faces with the same view", "[texture][atlas]") {
    // A strip of 6 faces 0-1-2-3-4-5; labels A A B B A none.
    const std::vector<std::array<std::uint32_t, 2>> adjacency = {
        {0, 1}, {1, 2}, {2, 3}, {3, 4}, {4, 5}};
    const std::vector<std::uint32_t> labels = {7, 7, 3, 3, 7, vdbmap::kNoLabel};
    std::vector<std::uint32_t> face_patch;
    const auto patches = buildPatches(labels, adjacency, &face_patch);
    REQUIRE(patches.size() == 3);
    CHECK(patches[0].view == 7);
    CHECK(patches[0].faces == std::vector<std::uint32_t>{0, 1});
    CHECK(patches[1].view == 3);
    CHECK(patches[1].faces == std::vector<std::uint32_t>{2, 3});
    CHECK(patches[2].faces == std::vector<std::uint32_t>{4});
    CHECK(face_patch == std::vector<std::uint32_t>{0, 0, 1, 1, 2, vdbmap::kNoLabel});
}

TEST_CASE("atlas layout pads charts, splits oversized patches and adds a fill block",
          "[texture][atlas]") {
    std::vector<std::array<Eigen::Vector2f, 3>> pixels = {
        {Eigen::Vector2f(10.2f, 20.5f), Eigen::Vector2f(30.7f, 20.5f),
         Eigen::Vector2f(10.2f, 40.1f)},
        {Eigen::Vector2f(30.7f, 20.5f), Eigen::Vector2f(30.7f, 40.1f),
         Eigen::Vector2f(10.2f, 40.1f)},
        {Eigen::Vector2f(0, 0), Eigen::Vector2f(1, 0), Eigen::Vector2f(0, 1)},
        {Eigen::Vector2f(60, 0), Eigen::Vector2f(110, 0), Eigen::Vector2f(60, 1)},
        {Eigen::Vector2f(0, 0), Eigen::Vector2f(0, 0), Eigen::Vector2f(0, 0)}};
    std::vector<Patch> patches = {{0, {0, 1}}, {1, {2, 3}}};
    const AtlasLayout layout = layoutAtlas(patches, pixels, 5, 2, 64);
    // Patch 1 spans 115 px > 64: one chart per face.
    REQUIRE(layout.charts.size() == 1 + 1 + 1);
    CHECK(layout.charts[0].x0 == 8);
    CHECK(layout.charts[0].y0 == 18);
    CHECK(layout.charts[0].size.width == 31 + 2 - 8 + 1);
    CHECK(layout.charts[0].size.height == 41 + 2 - 18 + 1);
    CHECK(layout.has_fill_block);
    CHECK(layout.face_chart[4] == vdbmap::kNoLabel);
    std::vector<std::array<Eigen::Vector2f, 3>> uvs;
    std::vector<std::uint32_t> pages;
    // A face 105 px wide is too big even alone.
    auto wide = pixels;
    wide[3][1] = Eigen::Vector2f(160, 0);
    CHECK_THROWS_AS(layoutAtlas({{1, {3}}}, wide, 5, 2, 64), vdbmap::InvalidInput);
    faceUvs(layout, pixels, uvs, pages);
    for (std::size_t f = 0; f < 3; ++f) {
        for (const auto& uv : uvs[f]) {
            CHECK(uv.x() > 0.0f);
            CHECK(uv.x() < 1.0f);
            CHECK(uv.y() > 0.0f);
            CHECK(uv.y() < 1.0f);
        }
    }
}
