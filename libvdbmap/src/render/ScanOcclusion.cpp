// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/render/ScanOcclusion.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "vdbmap/Error.h"
#include "vdbmap/core/Progress.h"
#include "vdbmap/dynamic/MovingReturns.h"
#include "vdbmap/io/Dataset.h"

namespace vdbmap {

namespace {

/// Min filter of radius r along each row, in place (one row buffer).
void minFilterRows(std::vector<float>& image, int width, int height, int r) {
    std::vector<float> line(static_cast<std::size_t>(width));
    for (int y = 0; y < height; ++y) {
        float* row = image.data() + static_cast<std::size_t>(y) * width;
        std::copy(row, row + width, line.begin());
        for (int x = 0; x < width; ++x) {
            float m = line[static_cast<std::size_t>(x)];
            for (int j = std::max(0, x - r); j <= std::min(width - 1, x + r); ++j) {
                m = std::min(m, line[static_cast<std::size_t>(j)]);
            }
            row[x] = m;
        }
    }
}

/// Min filter of radius r down each column: each output row is the element-wise minimum of the
/// input rows within r, whole rows at a time (contiguous, so the compiler vectorises it).
void minFilterColumns(std::vector<float>& image, int width, int height, int r) {
    const std::vector<float> in = image;
    for (int y = 0; y < height; ++y) {
        float* out = image.data() + static_cast<std::size_t>(y) * width;
        for (int j = std::max(0, y - r); j <= std::min(height - 1, y + r); ++j) {
            const float* src = in.data() + static_cast<std::size_t>(j) * width;
            for (int x = 0; x < width; ++x) out[x] = std::min(out[x], src[x]);
        }
    }
}

/// Fills each empty pixel (+inf) between two returns of its column at most r empty rows apart
/// with the farther of the two: the gap between two rings.
void bracketFillColumns(std::vector<float>& image, int width, int height, int r) {
    const float inf = std::numeric_limits<float>::infinity();
    std::vector<float> above(static_cast<std::size_t>(height));
    std::vector<int> above_row(static_cast<std::size_t>(height));
    for (int x = 0; x < width; ++x) {
        auto at = [&](int y) -> float& { return image[static_cast<std::size_t>(y) * width + x]; };
        float last = inf;
        int last_row = -(1 << 20);
        for (int y = 0; y < height; ++y) {  // the nearest return above each pixel
            if (at(y) != inf) {
                last = at(y);
                last_row = y;
            }
            above[static_cast<std::size_t>(y)] = last;
            above_row[static_cast<std::size_t>(y)] = last_row;
        }
        last = inf;
        last_row = 1 << 20;
        for (int y = height - 1; y >= 0; --y) {  // and below, filling as we go up
            const float own = at(y);
            if (own != inf) {
                last = own;
                last_row = y;
                continue;
            }
            if (last_row - above_row[static_cast<std::size_t>(y)] - 1 <= r) {
                at(y) = std::max(above[static_cast<std::size_t>(y)], last);
            }
        }
    }
}

}  // namespace

ScanDepthImage bracketedScanDepthImage(const std::vector<Vec3f>& points_C,
                                       const CameraIntrinsics& intrinsics, int dilate_px,
                                       int gap_px) {
    if (gap_px < 0) {
        throw InvalidInput("bracketedScanDepthImage: gap_px " + std::to_string(gap_px) + " (need >= 0)");
    }
    ScanDepthImage depth = scanDepthImage(points_C, intrinsics, 0);
    if (dilate_px > 0 && !depth.empty()) minFilterRows(depth.depth_m, depth.width, depth.height, dilate_px);
    if (gap_px > 0) bracketFillColumns(depth.depth_m, depth.width, depth.height, gap_px);
    return depth;
}

ScanDepthImage scanDepthImage(const std::vector<Vec3f>& points_C,
                              const CameraIntrinsics& intrinsics, int dilate_px) {
    if (intrinsics.width <= 0 || intrinsics.height <= 0 || dilate_px < 0) {
        throw InvalidInput("scanDepthImage: image " + std::to_string(intrinsics.width) + "x" +
                           std::to_string(intrinsics.height) + ", dilate_px " +
                           std::to_string(dilate_px) + " (need a positive size, dilate_px >= 0)");
    }
    ScanDepthImage depth;
    depth.width = intrinsics.width;
    depth.height = intrinsics.height;
    depth.depth_m.assign(static_cast<std::size_t>(depth.width) * depth.height,
                         std::numeric_limits<float>::infinity());
    Vec2d pixel;
    for (const Vec3f& p : points_C) {
        if (!(p.z() > 0) || !intrinsics.project(p.cast<double>(), pixel)) continue;
        if (!intrinsics.inside(pixel)) continue;
        const int x = static_cast<int>(std::lround(pixel.x()));
        const int y = static_cast<int>(std::lround(pixel.y()));
        if (x < 0 || y < 0 || x >= depth.width || y >= depth.height) continue;
        float& d = depth.depth_m[static_cast<std::size_t>(y) * depth.width + x];
        d = std::min(d, p.z());
        depth.returns = true;
    }
    if (dilate_px > 0 && !depth.empty()) {
        // The square min filter is separable: rows, then columns.
        minFilterRows(depth.depth_m, depth.width, depth.height, dilate_px);
        minFilterColumns(depth.depth_m, depth.width, depth.height, dilate_px);
    }
    return depth;
}

bool faceHiddenByScan(const ScanDepthImage& depth, const std::array<Vec3d, 3>& corners_C,
                      const CameraIntrinsics& intrinsics, const ScanOcclusionOptions& options,
                      const ScanDepthImage* moving) {
    const Vec3d centroid = (corners_C[0] + corners_C[1] + corners_C[2]) / 3.0;
    const std::array<Vec3d, 4> samples = {centroid, centroid + 0.7 * (corners_C[0] - centroid),
                                          centroid + 0.7 * (corners_C[1] - centroid),
                                          centroid + 0.7 * (corners_C[2] - centroid)};
    int hidden = 0;
    Vec2d pixel;
    for (const Vec3d& s : samples) {
        if (!intrinsics.project(s, pixel)) continue;
        const int x = static_cast<int>(std::lround(pixel.x()));
        const int y = static_cast<int>(std::lround(pixel.y()));
        const double limit = s.z() * (1.0 - options.margin_rel) - options.margin_m;
        if (depth.at(x, y) < limit || (moving && moving->at(x, y) < s.z() - options.moving_margin_m)) {
            ++hidden;
        }
    }
    return hidden >= std::ceil(options.min_hidden_fraction * samples.size() - 1e-9) && hidden > 0;
}

std::size_t removeScanOccluded(Visibility& vis, const MeshArrays& mesh,
                               const std::vector<View>& views, const ViewScanFn& scan_of_view,
                               const ScanOcclusionOptions& options, Progress* progress,
                               const ViewScanFn& moving_of_view,
                               std::vector<float>* hidden_cos_angles) {
    if (vis.numFaces() != mesh.faces.size()) {
        throw InvalidInput("removeScanOccluded: visibility covers " +
                           std::to_string(vis.numFaces()) + " faces but the mesh has " +
                           std::to_string(mesh.faces.size()));
    }
    std::vector<std::vector<std::uint64_t>> per_view;
    try {
        per_view = observationsByView(vis, views.size());
    } catch (const InvalidInput& e) {
        throw InvalidInput(std::string("removeScanOccluded: ") + e.what());
    }
    std::vector<std::uint32_t> face_of(vis.obs.size());
    for (std::size_t f = 0; f < vis.numFaces(); ++f) {
        for (std::uint64_t i = vis.offsets[f]; i < vis.offsets[f + 1]; ++i) {
            face_of[i] = static_cast<std::uint32_t>(f);
        }
    }
    std::vector<char> hidden(vis.obs.size(), 0);
    tbb::parallel_for(std::size_t{0}, views.size(), [&](std::size_t v) {
        if (!per_view[v].empty()) {
            const View& view = views[v];
            const ScanDepthImage depth = bracketedScanDepthImage(
                scan_of_view(v), view.intrinsics, options.row_dilate_px, options.gap_px);
            ScanDepthImage moving;
            if (moving_of_view) {
                moving = scanDepthImage(moving_of_view(v), view.intrinsics, options.moving_dilate_px);
            }
            for (const std::uint64_t i : per_view[v]) {
                const auto& face = mesh.faces[face_of[i]];
                std::array<Vec3d, 3> corners_C;
                for (int k = 0; k < 3; ++k) {
                    corners_C[static_cast<std::size_t>(k)] =
                        view.T_C_W * mesh.vertices_W[face[static_cast<std::size_t>(k)]].cast<double>();
                }
                hidden[i] = faceHiddenByScan(depth, corners_C, view.intrinsics, options,
                                             moving_of_view ? &moving : nullptr);
            }
        }
        if (progress) progress->tick();
    });
    if (hidden_cos_angles) {
        for (std::size_t i = 0; i < hidden.size(); ++i) {
            if (hidden[i]) hidden_cos_angles->push_back(vis.obs[i].cos_angle);
        }
    }
    return dropObservations(vis, hidden);
}

std::size_t nearestScanFrame(const Dataset& dataset, std::size_t frame) {
    // The layouts give an image the timestamp of its frame (KITTI's synchronised camera and
    // LiDAR), so the frame's own scan is at dt = 0: no other scan can be nearer. Checked here so
    // that a bad frame index fails where it is asked for.
    (void)dataset.frame(frame);
    return frame;
}

ViewScanFn datasetViewScans(const Dataset& dataset, const std::vector<View>& views) {
    return [&dataset, &views](std::size_t v) {
        const View& view = views.at(v);
        const std::size_t frame = nearestScanFrame(dataset, view.frame);
        const PointCloud scan_L = dataset.loadScan(frame);
        const Eigen::Isometry3f T_C_L = (view.T_C_W * dataset.frame(frame).T_W_L).cast<float>();
        std::vector<Vec3f> points_C;
        points_C.reserve(scan_L.size());
        for (const Vec3f& p : scan_L.points) points_C.push_back(T_C_L * p);
        return points_C;
    };
}

ViewScanFn movingViewScans(const Dataset& dataset, const std::vector<View>& views,
                           const MovingReturns& moving) {
    return [&dataset, &views, &moving](std::size_t v) {
        const View& view = views.at(v);
        const std::vector<Vec3f> points_W = moving.frame(nearestScanFrame(dataset, view.frame));
        const Eigen::Isometry3f T_C_W = view.T_C_W.cast<float>();
        std::vector<Vec3f> points_C;
        points_C.reserve(points_W.size());
        for (const Vec3f& p : points_W) points_C.push_back(T_C_W * p);
        return points_C;
    };
}

}  // namespace vdbmap
