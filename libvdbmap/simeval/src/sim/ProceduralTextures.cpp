// SPDX-License-Identifier: Apache-2.0
// Procedural textures, so that texture scoring has structure to compare (edges, patterns).
#include <opencv2/imgproc.hpp>

#include "vdbmap/Error.h"
#include "vdbmap/sim/Scenes.h"

namespace vdbmap {

namespace {

constexpr int kSize = 256;

cv::Mat noiseField(cv::RNG& rng, double sigma, int blur_px) {
    cv::Mat noise(kSize, kSize, CV_32FC1);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, sigma);
    if (blur_px > 0) {
        // Blur a wrapped copy and crop, so the texture tiles without seams.
        const int pad = 4 * blur_px;
        cv::Mat padded;
        cv::copyMakeBorder(noise, padded, pad, pad, pad, pad, cv::BORDER_WRAP);
        cv::GaussianBlur(padded, padded, cv::Size(0, 0), blur_px, blur_px);
        noise = padded(cv::Rect(pad, pad, kSize, kSize)).clone();
        double min_v = 0, max_v = 0;
        cv::minMaxLoc(noise, &min_v, &max_v);
        const double range = std::max(1e-6, max_v - min_v);
        noise = (noise - (min_v + max_v) / 2.0) * (2.0 * sigma / range);
    }
    return noise;
}

cv::Mat colored(const cv::Scalar& bgr, const cv::Mat& noise) {
    cv::Mat out(kSize, kSize, CV_8UC3);
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
            const float n = noise.at<float>(y, x);
            for (int c = 0; c < 3; ++c) {
                out.at<cv::Vec3b>(y, x)[c] = cv::saturate_cast<std::uint8_t>(bgr[c] + n);
            }
        }
    }
    return out;
}

}  // namespace

cv::Mat proceduralTexture(const std::string& kind, std::uint64_t seed) {
    cv::RNG rng(seed * 7919u + std::hash<std::string>{}(kind));
    if (kind == "asphalt") return colored({75, 75, 80}, noiseField(rng, 14, 1));
    if (kind == "lane") return colored({225, 230, 230}, noiseField(rng, 6, 1));
    if (kind == "grass") return colored({60, 140, 90}, noiseField(rng, 25, 2));
    if (kind == "foliage") return colored({40, 120, 60}, noiseField(rng, 35, 3));
    if (kind == "bark") return colored({40, 60, 90}, noiseField(rng, 15, 1));
    if (kind == "metal") return colored({150, 150, 150}, noiseField(rng, 8, 4));
    if (kind == "tyre") return colored({30, 30, 30}, noiseField(rng, 5, 1));
    if (kind == "glass" || kind == "window") return colored({110, 80, 50}, noiseField(rng, 12, 8));
    if (kind == "car_red") return colored({40, 40, 170}, noiseField(rng, 6, 6));
    if (kind == "car_blue") return colored({150, 70, 30}, noiseField(rng, 6, 6));
    if (kind == "car_silver") return colored({180, 180, 175}, noiseField(rng, 6, 6));
    if (kind == "suv") return colored({60, 70, 120}, noiseField(rng, 6, 6));
    if (kind == "skin") return colored({120, 150, 200}, noiseField(rng, 10, 4));
    // The traffic of --traffic (sim/StreetTraffic.cpp): colours no static surface has.
    if (kind == "car_yellow") return colored({30, 200, 230}, noiseField(rng, 6, 6));
    if (kind == "car_green") return colored({60, 150, 40}, noiseField(rng, 6, 6));
    if (kind == "car_orange") return colored({20, 120, 240}, noiseField(rng, 6, 6));
    if (kind == "van_white") return colored({235, 235, 230}, noiseField(rng, 8, 3));
    if (kind == "shirt_purple") return colored({150, 40, 120}, noiseField(rng, 10, 2));
    if (kind == "shirt_cyan") return colored({200, 200, 40}, noiseField(rng, 10, 2));
    if (kind == "trousers") return colored({90, 50, 30}, noiseField(rng, 8, 2));
    if (kind == "curb") return colored({170, 170, 165}, noiseField(rng, 10, 1));
    if (kind == "sidewalk") {
        // Square paving slabs, 4 per tile, with dark joints.
        cv::Mat out = colored({165, 170, 175}, noiseField(rng, 10, 1));
        for (int k = 0; k <= 4; ++k) {
            const int p = k * kSize / 4;
            cv::line(out, {p, 0}, {p, kSize - 1}, cv::Scalar(95, 95, 100), 3);
            cv::line(out, {0, p}, {kSize - 1, p}, cv::Scalar(95, 95, 100), 3);
        }
        return out;
    }
    if (kind == "brick") {
        // Running-bond bricks (8 courses per tile) with light mortar.
        cv::Mat out(kSize, kSize, CV_8UC3, cv::Scalar(200, 205, 210));
        const int course = kSize / 8;
        const int brick = kSize / 4;
        for (int r = 0; r < 8; ++r) {
            const int offset = (r % 2) * brick / 2;
            for (int b = -1; b < 5; ++b) {
                const int x0 = b * brick + offset;
                const double shade = rng.uniform(-25.0, 25.0);
                cv::rectangle(out, {x0 + 2, r * course + 2},
                              {x0 + brick - 3, (r + 1) * course - 3},
                              cv::Scalar(50 + shade, 70 + shade, 150 + shade), cv::FILLED);
            }
        }
        return out;
    }
    if (kind == "sign") {
        // Blue sign with a white border and a white arrow.
        cv::Mat out(kSize, kSize, CV_8UC3, cv::Scalar(160, 80, 20));
        cv::rectangle(out, {8, 8}, {kSize - 9, kSize - 9}, cv::Scalar(240, 240, 240), 12);
        const std::vector<cv::Point> arrow{{60, 150}, {130, 150}, {130, 190}, {200, 128},
                                           {130, 66},  {130, 106}, {60, 106}};
        cv::fillConvexPoly(out, std::vector<cv::Point>(arrow.begin(), arrow.begin() + 3),
                           cv::Scalar(240, 240, 240));
        cv::fillPoly(out, std::vector<std::vector<cv::Point>>{arrow}, cv::Scalar(240, 240, 240));
        return out;
    }
    throw InvalidInput("proceduralTexture: unknown texture kind '" + kind + "'");
}

}  // namespace vdbmap
