// SPDX-License-Identifier: Apache-2.0
// Exposure gains per image (ExposureGains.h): synthetic observations with known gains, and the
// whole texturing of a plane seen by views with different exposures.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "ExposureGains.h"
#include "TexturePipeline.h"
#include "TextureTestScenes.h"
#include "vdbmap/Error.h"

using namespace vdbmap::texture;
using namespace vdbmap::texture::test;
using vdbmap::Vec3f;

namespace {

/// Observations of `num_faces` faces by `gains.size()` views, view v seeing the `window`
/// consecutive faces from 20 v on (a drive: a face is seen by window / 20 views): observed
/// colour = gain_v * radiance_f. Returns the visibility; `stats` gets the colours.
vdbmap::Visibility chainObservations(std::size_t num_faces, const std::vector<double>& gains,
                                     std::vector<ObservationStats>& stats, std::mt19937& rng,
                                     std::size_t window = 40) {
    std::uniform_real_distribution<float> radiance(30.0f, 180.0f);
    std::vector<Vec3f> face_bgr(num_faces);
    for (auto& c : face_bgr) c = Vec3f(radiance(rng), radiance(rng), radiance(rng));
    vdbmap::Visibility vis;
    vis.offsets.push_back(0);
    for (std::size_t f = 0; f < num_faces; ++f) {
        for (std::uint32_t v = 0; v < gains.size(); ++v) {
            const std::size_t first = 20 * v;
            if (f < first || f >= first + window) continue;
            vdbmap::FaceObservation obs;
            obs.view = v;
            for (auto& p : obs.pixels) p.setZero();  // unused here
            vis.obs.push_back(obs);
            ObservationStats s;
            s.mean_bgr = static_cast<float>(gains[v]) * face_bgr[f];
            s.pixels = 50;
            s.quality = 10.0f * static_cast<float>(gains[v]);
            stats.push_back(s);
        }
        vis.offsets.push_back(vis.obs.size());
    }
    return vis;
}

/// Gains with geometric mean 1 (the gauge of the estimate).
std::vector<double> normalisedGains(std::vector<double> g) {
    double mean_log = 0;
    for (double x : g) mean_log += std::log(x);
    mean_log /= static_cast<double>(g.size());
    for (double& x : g) x /= std::exp(mean_log);
    return g;
}

}  // namespace

TEST_CASE("exposure gains from exact overlaps are the true gains", "[texture][exposure]") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> exposure(0.8, 1.2);
    std::vector<double> truth(12);
    for (double& g : truth) g = exposure(rng);
    truth = normalisedGains(truth);
    std::vector<ObservationStats> stats;
    const auto vis = chainObservations(20 * 12 + 20, truth, stats, rng);
    const ExposureResult result = estimateExposureGains(vis, stats, truth.size(), {});
    REQUIRE(result.gain.size() == truth.size());
    CHECK(result.faces_used > 200);
    double mean_log = 0;
    for (std::size_t v = 0; v < truth.size(); ++v) {
        CHECK(result.gain[v] == Approx(truth[v]).epsilon(1e-6));
        mean_log += std::log(result.gain[v]);
    }
    CHECK(std::abs(mean_log) < 1e-9);  // the gauge

    // The corrected statistics are those of one exposure: every view agrees on every face.
    applyExposureGains(vis, result.gain, stats);
    for (std::size_t f = 0; f < vis.numFaces(); ++f) {
        for (std::uint64_t i = vis.offsets[f] + 1; i < vis.offsets[f + 1]; ++i) {
            CHECK((stats[i].mean_bgr - stats[vis.offsets[f]].mean_bgr).norm() <
                  1e-3f * stats[i].mean_bgr.norm());
        }
    }
}

TEST_CASE("exposure gains are within 1 % despite noise and a moving object", "[texture][exposure]") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> exposure(0.8, 1.2);
    std::vector<double> truth(10);
    for (double& g : truth) g = exposure(rng);
    truth = normalisedGains(truth);
    std::vector<ObservationStats> stats;
    // A face seen by 4 views (as on a drive, where a facade stays in view for several frames).
    const auto vis = chainObservations(20 * 10 + 60, truth, stats, rng, 80);
    // 2 % multiplicative noise, and 5 % of the observations show something else (a car that
    // crossed in front): a colour unrelated to the face.
    std::normal_distribution<float> noise(0.0f, 0.02f);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (auto& s : stats) {
        s.mean_bgr *= 1.0f + noise(rng);
        if (unit(rng) < 0.05f) s.mean_bgr = Vec3f(40, 40, 200) * (0.5f + unit(rng));
    }
    const ExposureResult result = estimateExposureGains(vis, stats, truth.size(), {});
    for (std::size_t v = 0; v < truth.size(); ++v) {
        CHECK(std::abs(result.gain[v] / truth[v] - 1.0) < 0.01);
    }
}

TEST_CASE("views without overlap keep gain 1; bad sizes throw", "[texture][exposure]") {
    vdbmap::Visibility vis;
    vis.offsets = {0, 1, 2};  // two faces, each seen by one view
    vis.obs.resize(2);
    vis.obs[1].view = 1;
    std::vector<ObservationStats> stats(2);
    stats[0].mean_bgr = Vec3f::Constant(100);
    stats[1].mean_bgr = Vec3f::Constant(150);
    stats[0].pixels = stats[1].pixels = 50;
    const ExposureResult result = estimateExposureGains(vis, stats, 3, {});
    CHECK(result.faces_used == 0);
    CHECK(result.gain == std::vector<double>{1.0, 1.0, 1.0});
    stats.pop_back();
    CHECK_THROWS_AS(estimateExposureGains(vis, stats, 3, {}), vdbmap::InvalidInput);
}

namespace {

constexpr float kDepth = 5.0f;

Vec3f wallColor(double x, double y) {
    return Vec3f(static_cast<float>(90 + 40 * std::sin(3 * x)),
                 static_cast<float>(110 + 30 * std::cos(4 * y)),
                 static_cast<float>(80 + 20 * std::sin(2 * x + y)));
}

/// The wall z = kDepth seen by a view, times an exposure gain.
cv::Mat renderWall(const vdbmap::View& view, double gain) {
    const auto& in = view.intrinsics;
    cv::Mat image(in.height, in.width, CV_8UC3);
    const double centre_x = -view.T_C_W.translation().x();
    for (int v = 0; v < in.height; ++v) {
        for (int u = 0; u < in.width; ++u) {
            const double x = (u - in.cx) / in.fx * kDepth + centre_x;
            const double y = (v - in.cy) / in.fy * kDepth;
            const Vec3f c = static_cast<float>(gain) * wallColor(x, y);
            image.at<cv::Vec3b>(v, u) =
                cv::Vec3b(cv::saturate_cast<uchar>(c[0]), cv::saturate_cast<uchar>(c[1]),
                          cv::saturate_cast<uchar>(c[2]));
        }
    }
    return image;
}

}  // namespace

TEST_CASE("texturing estimates the gains of rendered images within 1 %", "[texture][exposure]") {
    const MeshArrays mesh = planeGrid(16, 8, 2.0f, 1.0f, kDepth);
    const std::vector<vdbmap::View> views = {makeView(0, -0.3), makeView(1, 0.0),
                                             makeView(2, 0.3)};
    const std::vector<double> truth = normalisedGains({0.85, 1.15, 1.0});
    std::vector<cv::Mat> images;
    for (std::size_t v = 0; v < views.size(); ++v) images.push_back(renderWall(views[v], truth[v]));
    const auto vis = makeVisibility(mesh, views, [](std::size_t, std::uint32_t) { return true; });
    TextureOptions options;
    options.global_adjustment = false;
    const TextureResult result = textureMesh(mesh, views, vis, bruteAdjacency(mesh),
                                             [&](std::size_t v) { return images[v]; }, options);
    REQUIRE(result.stats.exposure_gains.size() == 3);
    for (std::size_t v = 0; v < 3; ++v) {
        CHECK(std::abs(result.stats.exposure_gains[v] / truth[v] - 1.0) < 0.01);
    }
}
