// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/render/ScanOcclusion.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "vdbmap/Error.h"
#include "vdbmap/core/Progress.h"
#include "vdbmap/io/Dataset.h"

namespace vdbmap {

namespace {

/// In-place running minimum over a window of radius r along rows (step 1) or columns.
void minFilter1d(std::vector<float>& image, int width, int height, int r, bool along_rows) {
    const int lines = along_rows ? height : width;
    const int length = along_rows ? width : height;
    std::vector<float> line(static_cast<std::size_t>(length));
    for (int l = 0; l < lines; ++l) {
        auto at = [&](int k) -> float& {
            return along_rows ? image[static_cast<std::size_t>(l) * width + k]
                              : image[static_cast<std::size_t>(k) * width + l];
        };
        for (int k = 0; k < length; ++k) line[static_cast<std::size_t>(k)] = at(k);
        for (int k = 0; k < length; ++k) {
            float m = line[static_cast<std::size_t>(k)];
            for (int j = std::max(0, k - r); j <= std::min(length - 1, k + r); ++j) {
                m = std::min(m, line[static_cast<std::size_t>(j)]);
            }
            at(k) = m;
        }
    }
}

}  // namespace

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
    }
    if (dilate_px > 0) {
        // The square min filter is separable: rows, then columns.
        minFilter1d(depth.depth_m, depth.width, depth.height, dilate_px, true);
        minFilter1d(depth.depth_m, depth.width, depth.height, dilate_px, false);
    }
    return depth;
}

bool faceHiddenByScan(const ScanDepthImage& depth, const std::array<Vec3d, 3>& corners_C,
                      const CameraIntrinsics& intrinsics, const ScanOcclusionOptions& options) {
    const Vec3d centroid = (corners_C[0] + corners_C[1] + corners_C[2]) / 3.0;
    const std::array<Vec3d, 4> samples = {centroid, centroid + 0.7 * (corners_C[0] - centroid),
                                          centroid + 0.7 * (corners_C[1] - centroid),
                                          centroid + 0.7 * (corners_C[2] - centroid)};
    int hidden = 0;
    Vec2d pixel;
    for (const Vec3d& s : samples) {
        if (!intrinsics.project(s, pixel)) continue;
        const float scan_z = depth.at(static_cast<int>(std::lround(pixel.x())),
                                      static_cast<int>(std::lround(pixel.y())));
        const double limit = s.z() * (1.0 - options.margin_rel) - options.margin_m;
        if (scan_z < limit) ++hidden;
    }
    return hidden >= std::ceil(options.min_hidden_fraction * samples.size() - 1e-9) && hidden > 0;
}

std::size_t removeScanOccluded(Visibility& vis, const MeshArrays& mesh,
                               const std::vector<View>& views, const ViewScanFn& scan_of_view,
                               const ScanOcclusionOptions& options, Progress* progress) {
    if (vis.numFaces() != mesh.faces.size()) {
        throw InvalidInput("removeScanOccluded: visibility covers " +
                           std::to_string(vis.numFaces()) + " faces but the mesh has " +
                           std::to_string(mesh.faces.size()));
    }
    std::vector<std::vector<std::uint64_t>> per_view(views.size());
    for (std::size_t f = 0; f < vis.numFaces(); ++f) {
        for (std::uint64_t i = vis.offsets[f]; i < vis.offsets[f + 1]; ++i) {
            if (vis.obs[i].view >= views.size()) {
                throw InvalidInput("removeScanOccluded: observation of view " +
                                   std::to_string(vis.obs[i].view) + " of " +
                                   std::to_string(views.size()));
            }
            per_view[vis.obs[i].view].push_back(i);
        }
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
            const ScanDepthImage depth =
                scanDepthImage(scan_of_view(v), view.intrinsics, options.dilate_px);
            for (const std::uint64_t i : per_view[v]) {
                const auto& face = mesh.faces[face_of[i]];
                std::array<Vec3d, 3> corners_C;
                for (int k = 0; k < 3; ++k) {
                    corners_C[static_cast<std::size_t>(k)] =
                        view.T_C_W * mesh.vertices_W[face[static_cast<std::size_t>(k)]].cast<double>();
                }
                hidden[i] = faceHiddenByScan(depth, corners_C, view.intrinsics, options);
            }
        }
        if (progress) progress->tick();
    });
    // Compact the CSR arrays in place, keeping the per-face order (sorted by view).
    std::size_t removed = 0, out = 0;
    std::uint64_t begin = 0;
    for (std::size_t f = 0; f < vis.numFaces(); ++f) {
        const std::uint64_t end = vis.offsets[f + 1];
        for (std::uint64_t i = begin; i < end; ++i) {
            if (hidden[i]) {
                ++removed;
            } else {
                vis.obs[out++] = vis.obs[i];
            }
        }
        begin = end;
        vis.offsets[f + 1] = out;
    }
    vis.obs.resize(out);
    return removed;
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

}  // namespace vdbmap
