// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>
#include <random>

#include "Vignetting.h"
#include "vdbmap/Error.h"

using namespace vdbmap::texture;

TEST_CASE("vignetting radius is normalised by the centre's distance to the corner", "[texture]") {
    CHECK(vignettingRadius(50, 20, 50, 20) == Approx(0.0));
    CHECK(vignettingRadius(0, 0, 50, 20) == Approx(1.0));
    CHECK(vignettingRadius(100, 40, 50, 20) == Approx(1.0));
    CHECK(vignettingGain({0.3, 0.1, 0.05}, 1.0) == Approx(1.45));
    CHECK(vignettingGain({0.3, 0.1, 0.05}, 0.0) == Approx(1.0));
}

TEST_CASE("vignetting correction inverts a known vignette", "[texture]") {
    const VignettingParams params{0.35, -0.1, 0.2};
    const int width = 120, height = 60;
    const double cu = (width - 1) / 2.0, cv = (height - 1) / 2.0;
    cv::Mat truth(height, width, CV_32FC3), observed(height, width, CV_32FC3);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const cv::Vec3f c(40.0f + x, 80.0f + y, 150.0f);
            truth.at<cv::Vec3f>(y, x) = c;
            // The camera darkens the border: I_observed = I / g(r).
            observed.at<cv::Vec3f>(y, x) =
                c / static_cast<float>(vignettingGain(params, vignettingRadius(x, y, cu, cv)));
        }
    }
    CHECK(observed.at<cv::Vec3f>(0, 0)[2] < 0.8f * 150.0f);
    correctVignetting(observed, params, cu, cv);
    double max_error = 0;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const cv::Vec3f d = observed.at<cv::Vec3f>(y, x) - truth.at<cv::Vec3f>(y, x);
            max_error = std::max({max_error, double(std::abs(d[0])), double(std::abs(d[1])),
                                  double(std::abs(d[2]))});
        }
    }
    CHECK(max_error < 1e-3);
}

TEST_CASE("vignetting correction rejects a non-float image", "[texture]") {
    cv::Mat image(4, 4, CV_8UC3);
    CHECK_THROWS_AS(correctVignetting(image, {0.1, 0, 0}, 1.5, 1.5), vdbmap::InvalidInput);
}

namespace {

/// Faces of random albedo seen by several views at random radii, each view with its own
/// exposure; `outlier_fraction` of the observations get a random wrong colour (occluders).
std::vector<VignettingSample> simulateSamples(const VignettingParams& truth, int num_views,
                                              int num_faces, double outlier_fraction,
                                              unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    std::vector<double> exposure(num_views);
    for (auto& e : exposure) e = 0.7 + 0.6 * uni(rng);
    std::vector<VignettingSample> samples;
    for (int f = 0; f < num_faces; ++f) {
        const double albedo = 40.0 + 150.0 * uni(rng);
        const int first = static_cast<int>(uni(rng) * (num_views - 4));
        for (int v = first; v < first + 4; ++v) {
            const double r = uni(rng);
            double luminance = albedo * exposure[v] / vignettingGain(truth, r);
            if (uni(rng) < outlier_fraction) luminance = 20.0 + 200.0 * uni(rng);
            samples.push_back({static_cast<std::uint32_t>(f), static_cast<std::uint32_t>(v),
                               static_cast<float>(luminance), static_cast<float>(r)});
        }
    }
    return samples;
}

double maxGainError(const VignettingParams& a, const VignettingParams& b) {
    double worst = 0;
    for (int k = 0; k <= 20; ++k) {
        const double r = k / 20.0;
        worst = std::max(worst, std::abs(vignettingGain(a, r) - vignettingGain(b, r)));
    }
    return worst;
}

}  // namespace

TEST_CASE("vignetting estimation recovers the gain curve despite exposures", "[texture]") {
    const VignettingParams truth{0.3, 0.1, 0.05};
    const auto samples = simulateSamples(truth, 30, 3000, 0.0, 7);
    const std::vector<std::uint32_t> view_camera(30, 0);
    const auto estimate = estimateVignetting(samples, view_camera, 1);
    REQUIRE(estimate.size() == 1);
    CHECK(estimate[0].pairs_used > 1000);
    // The gain curve matters, not the individual coefficients (they trade off).
    CHECK(maxGainError(estimate[0].params, truth) < 0.01);
}

TEST_CASE("vignetting estimation survives occluded observations", "[texture]") {
    const VignettingParams truth{0.4, -0.05, 0.1};
    const auto samples = simulateSamples(truth, 30, 3000, 0.1, 11);
    const std::vector<std::uint32_t> view_camera(30, 0);
    const auto estimate = estimateVignetting(samples, view_camera, 1);
    CHECK(maxGainError(estimate[0].params, truth) < 0.03);
}

TEST_CASE("vignetting estimation without overlaps gives the identity", "[texture]") {
    std::vector<VignettingSample> samples = {{0, 0, 100.0f, 0.5f}, {1, 1, 90.0f, 0.2f}};
    const auto estimate = estimateVignetting(samples, {0, 0}, 1);
    CHECK(estimate[0].params.isIdentity());
    CHECK_THROWS_AS(estimateVignetting(samples, {0}, 1), vdbmap::InvalidInput);
}
