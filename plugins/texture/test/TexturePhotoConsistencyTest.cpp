// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>
#include <random>

#include "PhotoConsistency.h"

using namespace vdbmap::texture;
using vdbmap::Vec3f;

TEST_CASE("HSV cone maps hue circularly and grey to the axis", "[texture]") {
    const Vec3f grey = bgrToHsvCone(Vec3f(128, 128, 128));
    CHECK(grey.x() == Approx(0.0f).margin(1e-6));
    CHECK(grey.y() == Approx(0.0f).margin(1e-6));
    CHECK(grey.z() == Approx(128.0f / 255.0f));
    // Hue 358 deg and 2 deg are neighbours in the cone, far apart as numbers.
    const Vec3f a = bgrToHsvCone(Vec3f(8, 0, 255));  // red, slightly blue: hue ~358
    const Vec3f b = bgrToHsvCone(Vec3f(0, 8, 255));  // red, slightly green: hue ~2
    CHECK((a - b).norm() < 0.1f);
    const Vec3f green = bgrToHsvCone(Vec3f(0, 255, 0));
    CHECK((a - green).norm() > 1.0f);
}

TEST_CASE("photo-consistency rejects a minority occluder", "[texture]") {
    std::mt19937 rng(3);
    std::normal_distribution<float> noise(0.0f, 3.0f);
    std::vector<Vec3f> colors;
    for (int v = 0; v < 6; ++v) {
        // The facade with exposure changes (+-10 %) and noise.
        const float gain = 0.9f + 0.04f * v;
        colors.push_back(gain * Vec3f(90, 110, 150) + Vec3f(noise(rng), noise(rng), noise(rng)));
    }
    colors.push_back(Vec3f(30, 30, 200));  // red pedestrian in two views
    colors.push_back(Vec3f(35, 25, 190));
    const auto keep = photoConsistentViews(colors, {});
    for (int v = 0; v < 6; ++v) CHECK(keep[v]);
    CHECK_FALSE(keep[6]);
    CHECK_FALSE(keep[7]);
}

TEST_CASE("photo-consistency keeps consistent views and small sets", "[texture]") {
    const std::vector<Vec3f> consistent = {
        {100, 100, 100}, {104, 101, 99}, {97, 99, 102}, {101, 103, 100}};
    const auto keep = photoConsistentViews(consistent, {});
    for (char k : keep) CHECK(k);
    // Two views cannot out-vote each other.
    const auto two = photoConsistentViews({{0, 0, 255}, {255, 0, 0}}, {});
    CHECK(two[0]);
    CHECK(two[1]);
}

TEST_CASE("photo-consistency over a visibility only clears flags", "[texture]") {
    vdbmap::Visibility vis;
    vis.offsets = {0, 4, 5};
    vis.obs.resize(5);
    for (std::uint32_t i = 0; i < 5; ++i) vis.obs[i].view = i;
    std::vector<ObservationStats> stats(5);
    stats[0].mean_bgr = {100, 100, 100};
    stats[1].mean_bgr = {102, 100, 99};
    stats[2].mean_bgr = {20, 200, 20};  // occluder
    stats[3].mean_bgr = {99, 101, 100};
    stats[4].mean_bgr = {10, 10, 10};  // alone on face 1
    std::vector<char> keep = {1, 1, 1, 1, 1};
    const std::size_t rejected = applyPhotoConsistency(vis, stats, {}, keep);
    CHECK(rejected == 1);
    CHECK(keep == std::vector<char>{1, 1, 0, 1, 1});
}
