// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/render/ImageMasks.h"

#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "vdbmap/Error.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/io/Image.h"

namespace vdbmap {
namespace {

constexpr int kMaxDilatePx = 32;

/// The four samples of an observation in pixels: the centroid of its projected corners and the
/// corners pulled 30 % towards it (faceHiddenByScan's samples, ScanOcclusion.cpp).
std::array<Eigen::Vector2f, 4> samplePixels(const FaceObservation& o) {
    const Eigen::Vector2f c = (o.pixels[0] + o.pixels[1] + o.pixels[2]) / 3.0f;
    return {c, c + 0.7f * (o.pixels[0] - c), c + 0.7f * (o.pixels[1] - c),
            c + 0.7f * (o.pixels[2] - c)};
}

bool touchesMask(const FaceObservation& o, const cv::Mat& mask) {
    for (const Eigen::Vector2f& p : samplePixels(o)) {
        const int x = static_cast<int>(std::lround(p.x()));
        const int y = static_cast<int>(std::lround(p.y()));
        if (x >= 0 && y >= 0 && x < mask.cols && y < mask.rows && mask.at<std::uint8_t>(y, x)) {
            return true;
        }
    }
    return false;
}

/// Phase: the view's mask grown by `dilate_px` (a square, i.e. Chebyshev, neighbourhood).
cv::Mat grownMask(const cv::Mat& mask, const View& view, int dilate_px, std::size_t v) {
    if (mask.type() != CV_8UC1 || mask.cols != view.intrinsics.width ||
        mask.rows != view.intrinsics.height) {
        throw InvalidInput("removeMaskedObservations: the mask of view " + std::to_string(v) +
                           " is " + std::to_string(mask.cols) + " x " + std::to_string(mask.rows) +
                           " (type " + std::to_string(mask.type()) + "), its image " +
                           std::to_string(view.intrinsics.width) + " x " +
                           std::to_string(view.intrinsics.height) + " 8-bit grey");
    }
    if (dilate_px == 0) return mask;
    cv::Mat grown;
    cv::dilate(mask, grown, cv::Mat::ones(2 * dilate_px + 1, 2 * dilate_px + 1, CV_8U));
    return grown;
}

}  // namespace

std::size_t removeMaskedObservations(Visibility& vis, const std::vector<View>& views,
                                     const ViewMaskFn& mask_of_view, int dilate_px) {
    if (dilate_px < 0 || dilate_px > kMaxDilatePx) {
        throw InvalidInput("removeMaskedObservations: dilate_px must be in [0, " +
                           std::to_string(kMaxDilatePx) + "], got " + std::to_string(dilate_px));
    }
    const std::vector<std::vector<std::uint64_t>> per_view = observationsByView(vis, views.size());
    std::vector<char> masked(vis.obs.size(), 0);
    tbb::parallel_for(std::size_t{0}, views.size(), [&](std::size_t v) {
        if (per_view[v].empty()) return;
        const cv::Mat mask = mask_of_view(v);
        if (mask.empty()) return;
        const cv::Mat grown = grownMask(mask, views[v], dilate_px, v);
        for (const std::uint64_t i : per_view[v]) masked[i] = touchesMask(vis.obs[i], grown);
    });
    return dropObservations(vis, masked);
}

ViewMaskFn directoryViewMasks(const Dataset& dataset, const std::vector<View>& views,
                              const std::filesystem::path& dir) {
    if (!std::filesystem::is_directory(dir)) {
        throw IoError("image masks: '" + dir.string() + "' is not a directory");
    }
    const bool one_camera = dataset.cameras().size() == 1;
    return [&dataset, views, dir, one_camera](std::size_t v) -> cv::Mat {
        const View& view = views.at(v);
        const auto image = dataset.imagePath(view.frame, view.camera);
        if (!image) return {};
        const std::filesystem::path path =
            (one_camera ? dir : dir / dataset.cameras()[view.camera].name) / image->filename();
        if (!std::filesystem::exists(path)) return {};
        cv::Mat mask = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
        if (mask.empty()) {
            throw IoError("unreadable image mask (not an image or corrupt): " + path.string());
        }
        requireImageSize(mask, path, {view.intrinsics.width, view.intrinsics.height},
                         "its image " + image->string());
        return mask;
    };
}

}  // namespace vdbmap
