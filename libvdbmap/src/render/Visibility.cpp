// SPDX-License-Identifier: Apache-2.0
// Face x view visibility shared by the texture (paper Sec. 5) and semantic (Sec. 6) plugins.
#include "vdbmap/render/Visibility.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "vdbmap/Error.h"
#include "vdbmap/core/Progress.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/mesh/MeshArrays.h"
#include "vdbmap/render/Raycaster.h"

namespace vdbmap {

namespace {

/// Face geometry in the world frame, precomputed once for all views.
struct FaceGeometry {
    std::vector<std::array<Vec3f, 3>> corners_W;
    std::vector<Vec3f> centroid_W;
    std::vector<Vec3f> normal_W;  ///< unit; zero for deleted / degenerate faces
};

FaceGeometry faceGeometry(const TriMesh& mesh) {
    // Face f = triangle f; a deleted face is collapsed, so it gets a zero normal.
    const MeshArrays arrays = meshArrays(mesh, DeletedFaces::Collapse);
    const std::size_t num_faces = arrays.faces.size();
    FaceGeometry g;
    g.corners_W.resize(num_faces);
    g.centroid_W.resize(num_faces);
    g.normal_W.assign(num_faces, Vec3f::Zero());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, num_faces, 4096),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t f = r.begin(); f != r.end(); ++f) {
            auto& c = g.corners_W[f];
            for (int k = 0; k < 3; ++k) c[k] = arrays.vertices_W[arrays.faces[f][k]];
            g.centroid_W[f] = (c[0] + c[1] + c[2]) / 3.0f;
            const Vec3f n = (c[1] - c[0]).cross(c[2] - c[0]);
            const float len = n.norm();
            if (len > 0.0f && std::isfinite(len)) g.normal_W[f] = n / len;
        }
    });
    return g;
}

/// Faces binned into cubic cells (about 8 mean edge lengths wide) with tight boxes, for
/// culling whole cells against a view frustum.
struct CellGrid {
    std::vector<std::uint32_t> faces;     ///< grouped per cell, ascending inside a cell
    std::vector<std::uint64_t> offsets;   ///< per cell
    std::vector<Eigen::AlignedBox3f> boxes;
};

CellGrid cellGrid(const FaceGeometry& g) {
    CellGrid grid;
    std::vector<std::uint32_t> valid;
    double edge_sum = 0.0;
    Eigen::AlignedBox3f bounds;
    for (std::size_t f = 0; f < g.normal_W.size(); ++f) {
        if (g.normal_W[f].isZero()) continue;
        valid.push_back(static_cast<std::uint32_t>(f));
        edge_sum += (g.corners_W[f][1] - g.corners_W[f][0]).norm();
        bounds.extend(g.centroid_W[f]);
    }
    grid.offsets.push_back(0);
    if (valid.empty()) return grid;
    // 21 bits per axis: widen the cells if the scene is too large for that.
    const float extent = bounds.sizes().maxCoeff();
    const float cell_m = std::max({8.0f * static_cast<float>(edge_sum / valid.size()),
                                   extent / 1.0e6f, 1e-6f});
    auto key = [&](std::uint32_t f) {
        const Vec3f q = (g.centroid_W[f] - bounds.min()) / cell_m;
        const auto ix = static_cast<std::uint64_t>(std::max(0.0f, q.x()));
        const auto iy = static_cast<std::uint64_t>(std::max(0.0f, q.y()));
        const auto iz = static_cast<std::uint64_t>(std::max(0.0f, q.z()));
        return (ix << 42) | (iy << 21) | iz;
    };
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(valid.size());
    for (std::size_t k = 0; k < valid.size(); ++k) keyed[k] = {key(valid[k]), valid[k]};
    std::sort(keyed.begin(), keyed.end());
    grid.faces.resize(keyed.size());
    for (std::size_t k = 0; k < keyed.size(); ++k) {
        grid.faces[k] = keyed[k].second;
        if (k > 0 && keyed[k].first != keyed[k - 1].first) grid.offsets.push_back(k);
    }
    grid.offsets.push_back(keyed.size());
    grid.boxes.resize(grid.offsets.size() - 1);
    for (std::size_t c = 0; c + 1 < grid.offsets.size(); ++c) {
        for (std::uint64_t k = grid.offsets[c]; k < grid.offsets[c + 1]; ++k) {
            for (const Vec3f& p : g.corners_W[grid.faces[k]]) grid.boxes[c].extend(p);
        }
    }
    return grid;
}

/// True if the box lies entirely outside the view frustum (one separating plane among the
/// near / far depth planes and, without distortion, the four image-border planes).
bool cullBox(const Eigen::AlignedBox3f& box, const View& view, const VisibilityOptions& options) {
    const CameraIntrinsics& K = view.intrinsics;
    // Image borders as slopes x/z and y/z (pixel convention: borders at -0.5 and size-0.5).
    const double xl = (-0.5 - K.cx) / K.fx, xr = (K.width - 0.5 - K.cx) / K.fx;
    const double yt = (-0.5 - K.cy) / K.fy, yb = (K.height - 0.5 - K.cy) / K.fy;
    const bool sides = !K.hasDistortion();
    int near_out = 0, far_out = 0, left = 0, right = 0, top = 0, bottom = 0;
    for (int i = 0; i < 8; ++i) {
        const Vec3f corner = box.corner(static_cast<Eigen::AlignedBox3f::CornerType>(i));
        const Vec3d p = view.T_C_W * corner.cast<double>();
        near_out += p.z() < options.min_depth_m;
        far_out += p.z() > options.max_depth_m;
        left += p.x() < xl * p.z();
        right += p.x() > xr * p.z();
        top += p.y() < yt * p.z();
        bottom += p.y() > yb * p.z();
    }
    if (near_out == 8 || far_out == 8) return true;
    return sides && (left == 8 || right == 8 || top == 8 || bottom == 8);
}

void checkInputs(const std::vector<View>& views, const VisibilityOptions& options) {
    if (!(options.max_view_angle_deg > 0.0 && options.max_view_angle_deg <= 90.0)) {
        throw InvalidInput("computeVisibility: max_view_angle_deg must be in (0, 90], got " +
                           std::to_string(options.max_view_angle_deg));
    }
    if (!(options.min_depth_m >= 0.0) || !(options.max_depth_m > options.min_depth_m)) {
        throw InvalidInput("computeVisibility: need 0 <= min_depth_m < max_depth_m, got " +
                           std::to_string(options.min_depth_m) + " and " +
                           std::to_string(options.max_depth_m));
    }
    if (!(options.occlusion_tolerance_m >= 0.0)) {
        throw InvalidInput("computeVisibility: occlusion_tolerance_m must be >= 0, got " +
                           std::to_string(options.occlusion_tolerance_m));
    }
    for (std::size_t v = 0; v < views.size(); ++v) {
        const CameraIntrinsics& K = views[v].intrinsics;
        if (K.width <= 0 || K.height <= 0 || !(K.fx > 0.0) || !(K.fy > 0.0)) {
            throw InvalidInput("computeVisibility: view " + std::to_string(v) + " (frame " +
                               std::to_string(views[v].frame) + ", camera " +
                               std::to_string(views[v].camera) + ") has image size " +
                               std::to_string(K.width) + "x" + std::to_string(K.height) +
                               " and focal lengths " + std::to_string(K.fx) + ", " +
                               std::to_string(K.fy) + "; all must be > 0");
        }
    }
}

struct ViewHit {
    std::uint32_t face;
    FaceObservation obs;
};

/// All visible faces of one view, in cell order.
std::vector<ViewHit> visibleFaces(const FaceGeometry& g, const CellGrid& grid, const View& view,
                                  std::uint32_t view_index, const VisibilityOptions& options,
                                  const Raycaster* occluder) {
    std::vector<ViewHit> hits;
    const Isometry3d T_W_C = view.T_C_W.inverse();
    const Vec3f origin_W = T_W_C.translation().cast<float>();
    const double cos_max = std::cos(options.max_view_angle_deg * M_PI / 180.0);
    const float tolerance = static_cast<float>(options.occlusion_tolerance_m);
    for (std::size_t c = 0; c + 1 < grid.offsets.size(); ++c) {
        if (cullBox(grid.boxes[c], view, options)) continue;
        for (std::uint64_t k = grid.offsets[c]; k < grid.offsets[c + 1]; ++k) {
            const std::uint32_t f = grid.faces[k];
            const Vec3f to_camera = origin_W - g.centroid_W[f];
            const float dist = to_camera.norm();
            if (!(dist > 0.0f)) continue;
            const float cos_angle = g.normal_W[f].dot(to_camera) / dist;
            if (!(cos_angle > 0.0f) || cos_angle < cos_max) continue;  // back-facing / grazing
            FaceObservation obs;
            obs.view = view_index;
            obs.cos_angle = cos_angle;
            bool inside = true;
            for (int i = 0; i < 3 && inside; ++i) {
                const Vec3d p_C = view.T_C_W * g.corners_W[f][i].cast<double>();
                Vec2d px = Vec2d::Zero();  // read below even when a depth test fails
                inside = p_C.z() >= options.min_depth_m && p_C.z() <= options.max_depth_m &&
                         view.intrinsics.project(p_C, px) && view.intrinsics.inside(px);
                obs.pixels[i] = px.cast<float>();
            }
            if (!inside) continue;
            obs.depth_m = static_cast<float>((view.T_C_W * g.centroid_W[f].cast<double>()).z());
            const Eigen::Vector2f e1 = obs.pixels[1] - obs.pixels[0];
            const Eigen::Vector2f e2 = obs.pixels[2] - obs.pixels[0];
            obs.area_px = 0.5f * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
            if (occluder != nullptr && options.occlusion_test) {
                bool blocked = false;
                for (int s = 0; s < 4 && !blocked; ++s) {
                    const Vec3f sample =
                        s == 0 ? g.centroid_W[f]
                               : Vec3f(g.centroid_W[f] +
                                       0.95f * (g.corners_W[f][s - 1] - g.centroid_W[f]));
                    const Vec3f ray = sample - origin_W;
                    const float len = ray.norm();
                    if (len <= tolerance) continue;
                    blocked = occluder->occluded(origin_W, ray / len, 0.0f, len - tolerance);
                }
                if (blocked) continue;
            }
            hits.push_back({f, obs});
        }
    }
    return hits;
}

}  // namespace

std::vector<View> datasetViews(const Dataset& dataset, bool need_images, bool need_semantics) {
    std::vector<View> views;
    for (std::size_t i = 0; i < dataset.numFrames(); ++i) {
        for (std::size_t c = 0; c < dataset.cameras().size(); ++c) {
            if (need_images && !dataset.imagePath(i, c)) continue;
            if (need_semantics && !dataset.semanticPath(i, c)) continue;
            View view;
            view.frame = i;
            view.camera = c;
            view.intrinsics = dataset.cameras()[c].intrinsics;
            view.T_C_W = dataset.T_W_C(i, c).inverse();
            views.push_back(view);
        }
    }
    return views;
}

Visibility computeVisibility(const TriMesh& mesh, const std::vector<View>& views,
                             const VisibilityOptions& options, const Raycaster* occluder,
                             Progress* progress) {
    checkInputs(views, options);
    const std::size_t num_faces = mesh.n_faces();
    Visibility vis;
    vis.offsets.assign(num_faces + 1, 0);
    if (num_faces == 0 || views.empty()) return vis;

    const FaceGeometry geometry = faceGeometry(mesh);
    const CellGrid grid = cellGrid(geometry);
    std::vector<std::vector<ViewHit>> per_view(views.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, views.size(), 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            per_view[v] = visibleFaces(geometry, grid, views[v], static_cast<std::uint32_t>(v),
                                       options, occluder);
            if (progress != nullptr) progress->tick();
        }
    });

    // Face-major CSR; filling view by view keeps each face's observations sorted by view.
    for (const auto& hits : per_view) {
        for (const ViewHit& h : hits) ++vis.offsets[h.face + 1];
    }
    std::partial_sum(vis.offsets.begin(), vis.offsets.end(), vis.offsets.begin());
    vis.obs.resize(vis.offsets.back());
    std::vector<std::uint64_t> cursor(vis.offsets.begin(), vis.offsets.end() - 1);
    for (auto& hits : per_view) {
        for (const ViewHit& h : hits) vis.obs[cursor[h.face]++] = h.obs;
        std::vector<ViewHit>().swap(hits);
    }
    return vis;
}

std::vector<std::vector<std::uint64_t>> observationsByView(const Visibility& vis,
                                                           std::size_t num_views) {
    std::vector<std::vector<std::uint64_t>> per_view(num_views);
    for (std::uint64_t i = 0; i < vis.obs.size(); ++i) {
        if (vis.obs[i].view >= num_views) {
            throw InvalidInput("observation of view " + std::to_string(vis.obs[i].view) + " of " +
                               std::to_string(num_views));
        }
        per_view[vis.obs[i].view].push_back(i);
    }
    return per_view;
}

std::size_t dropObservations(Visibility& vis, const std::vector<char>& drop) {
    if (drop.size() != vis.obs.size()) {
        throw InvalidInput("dropObservations: " + std::to_string(drop.size()) + " flags for " +
                           std::to_string(vis.obs.size()) + " observations");
    }
    std::size_t removed = 0, out = 0;
    std::uint64_t begin = 0;
    for (std::size_t f = 0; f < vis.numFaces(); ++f) {
        const std::uint64_t end = vis.offsets[f + 1];
        for (std::uint64_t i = begin; i < end; ++i) {
            if (drop[i]) {
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

}  // namespace vdbmap
