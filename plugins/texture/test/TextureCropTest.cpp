// SPDX-License-Identifier: Apache-2.0
// What the texture passes read from the crop of a view's image they need (the statistics from
// observedBounds, the charts from their clamped source rectangles) is what they read from the
// whole image: the whole-image computation is the oracle.
#include <catch2/catch.hpp>
#include <random>

#include "FaceStats.h"
#include "TextureAtlas.h"
#include "Vignetting.h"

using namespace vdbmap;
using namespace vdbmap::texture;

namespace {

cv::Mat randomImage(int width, int height, std::mt19937& rng) {
    cv::Mat image(height, width, CV_32FC3);
    std::uniform_real_distribution<float> value(0.0f, 255.0f);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) image.at<cv::Vec3f>(y, x) = {value(rng), value(rng), value(rng)};
    }
    return image;
}

/// Triangles of one view in a region of the image: large ones, sub-pixel ones and ones that
/// reach past the image border.
Visibility observations(int width, int height, const cv::Rect2f& region, std::mt19937& rng) {
    Visibility vis;
    std::uniform_real_distribution<float> x(region.x, region.x + region.width);
    std::uniform_real_distribution<float> y(region.y, region.y + region.height);
    std::uniform_real_distribution<float> small(-0.3f, 0.3f);
    for (int k = 0; k < 60; ++k) {
        FaceObservation obs;
        obs.area_px = 1.0f;
        const Eigen::Vector2f a(x(rng), y(rng));
        for (int c = 0; c < 3; ++c) {
            obs.pixels[static_cast<std::size_t>(c)] =
                (k % 3 == 0) ? Eigen::Vector2f(a + Eigen::Vector2f(small(rng), small(rng)))
                             : Eigen::Vector2f(x(rng), y(rng));
        }
        vis.obs.push_back(obs);
    }
    if (region.x + region.width <= width) {
        vis.offsets = {0, vis.obs.size()};
        return vis;
    }
    // One past the right and bottom borders.
    FaceObservation border;
    border.area_px = 1.0f;
    border.pixels = {Eigen::Vector2f(width - 3.0f, height - 2.0f),
                     Eigen::Vector2f(width + 9.0f, height - 1.5f),
                     Eigen::Vector2f(width - 1.0f, height + 7.0f)};
    vis.obs.push_back(border);
    vis.offsets = {0, vis.obs.size()};
    return vis;
}

}  // namespace

TEST_CASE("view statistics from the observed crop equal those from the whole image",
          "[texture]") {
    std::mt19937 rng(7);
    const int width = 96, height = 64;
    const cv::Mat image = randomImage(width, height, rng);
    const auto [region, name] = GENERATE(table<cv::Rect2f, const char*>(
        {{cv::Rect2f(30, 20, 25, 15), "interior"},
         {cv::Rect2f(-20, -10, 40, 30), "past the top-left corner"},
         {cv::Rect2f(60, 40, 50, 40), "past the bottom-right corner"}}));
    INFO(name);
    const Visibility vis = observations(width, height, region, rng);
    std::vector<std::uint64_t> indices(vis.obs.size());
    for (std::size_t i = 0; i < indices.size(); ++i) indices[i] = i;

    const cv::Size size(width, height);
    const cv::Rect crop = observedBounds(vis, indices, size, kStatsMarginPx);
    REQUIRE_FALSE(crop.empty());
    CHECK((crop & cv::Rect(0, 0, width, height)) == crop);
    if (std::string(name) == "interior") CHECK(crop.area() < width * height / 4);

    for (const bool with_quality : {false, true}) {
        std::vector<ObservationStats> whole(vis.obs.size()), cropped(vis.obs.size());
        computeObservationStats(image, {0, 0}, size, vis, indices, with_quality, whole);
        computeObservationStats(image(crop).clone(), crop.tl(), size, vis, indices, with_quality,
                                cropped);
        for (std::size_t i = 0; i < whole.size(); ++i) {
            INFO("observation " << i << (with_quality ? " with quality" : ""));
            CHECK(cropped[i].pixels == whole[i].pixels);
            for (int c = 0; c < 3; ++c) {
                CHECK(cropped[i].mean_bgr[c] == Approx(whole[i].mean_bgr[c]).margin(1e-3));
            }
            CHECK(cropped[i].quality == Approx(whole[i].quality).epsilon(1e-5).margin(1e-3));
        }
    }
}

TEST_CASE("vignetting correction of a crop equals the crop of the corrected image",
          "[texture]") {
    std::mt19937 rng(3);
    const int width = 80, height = 50;
    const cv::Mat image = randomImage(width, height, rng);
    const VignettingParams params{0.3, 0.1, 0.05};
    const double cu = (width - 1) / 2.0, cv_centre = (height - 1) / 2.0;
    cv::Mat whole = image.clone();
    correctVignetting(whole, params, cu, cv_centre);
    const cv::Rect crop(50, 7, 25, 30);
    cv::Mat part = image(crop).clone();
    correctVignetting(part, params, cu, cv_centre, crop.tl());
    CHECK(cv::norm(part, whole(crop), cv::NORM_INF) < 1e-4);
    // Without the origin the crop would be corrected as if it sat at the top-left corner.
    cv::Mat wrong = image(crop).clone();
    correctVignetting(wrong, params, cu, cv_centre);
    CHECK(cv::norm(wrong, whole(crop), cv::NORM_INF) > 1.0);
}

TEST_CASE("a chart cut from a crop equals the chart cut from the whole image", "[texture]") {
    std::mt19937 rng(5);
    const int width = 70, height = 40;
    const cv::Mat image = randomImage(width, height, rng);
    Chart chart;
    chart.size = {18, 12};
    chart.place = {0, 3, 2};
    const auto [x0, y0] = GENERATE(table<int, int>({{20, 10}, {-6, -4}, {60, 33}}));
    INFO("chart at " << x0 << ", " << y0);
    chart.x0 = x0;
    chart.y0 = y0;
    // The rectangle the chart reads, its coordinates clamped to the image.
    const int cx0 = std::clamp(x0, 0, width - 1), cy0 = std::clamp(y0, 0, height - 1);
    const int cx1 = std::clamp(x0 + chart.size.width - 1, 0, width - 1);
    const int cy1 = std::clamp(y0 + chart.size.height - 1, 0, height - 1);
    const cv::Rect crop(cx0, cy0, cx1 - cx0 + 1, cy1 - cy0 + 1);
    cv::Mat whole_page(20, 25, CV_8UC3, cv::Scalar::all(0));
    cv::Mat crop_page = whole_page.clone();
    cutChart(image, chart, whole_page);
    cutChart(image(crop).clone(), chart, crop_page, crop.tl(), image.size());
    CHECK(cv::norm(whole_page, crop_page, cv::NORM_INF) == 0);
    CHECK(cv::norm(whole_page, cv::NORM_INF) > 0);
}
