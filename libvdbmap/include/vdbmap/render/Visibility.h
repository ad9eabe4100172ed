// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/io/Camera.h"
#include "vdbmap/mesh/TriMesh.h"

namespace vdbmap {

class Dataset;
class Progress;
class Raycaster;

/// One image of the sequence: camera `camera` at frame `frame`.
struct View {
    std::size_t frame = 0;
    std::size_t camera = 0;
    CameraIntrinsics intrinsics;
    Isometry3d T_C_W = Isometry3d::Identity();  ///< world -> camera
};

/// Every (frame, camera) of the dataset that has a colour image (if `need_images`) and a
/// semantic image (if `need_semantics`); views without the needed file are skipped (with
/// neither flag, every frame x camera). Ordered by frame, then camera.
std::vector<View> datasetViews(const Dataset& dataset, bool need_images, bool need_semantics);

/// The tests that make a face visible in a view.
struct VisibilityOptions {
    double max_view_angle_deg = 80.0;  ///< angle between face normal and direction to camera
    double min_depth_m = 0.1;          ///< in front of the camera by at least this
    double max_depth_m = 200.0;
    bool occlusion_test = true;        ///< BVH test of the centroid and the three corners
    double occlusion_tolerance_m = 0.02;  ///< a hit closer than this to the sample is no occluder
};

/// A face seen in a view, with its projection.
struct FaceObservation {
    std::uint32_t view = 0;
    float area_px = 0;    ///< projected area, pixels^2
    float cos_angle = 0;  ///< cosine between face normal and direction to the camera
    float depth_m = 0;    ///< camera-z of the centroid
    std::array<Eigen::Vector2f, 3> pixels;  ///< projected corners (docs/DATA.md pixel convention)
};

/// Face -> views in CSR form: the observations of face f are obs[offsets[f] .. offsets[f+1]),
/// sorted by view index.
struct Visibility {
    std::vector<std::uint64_t> offsets;  ///< size numFaces()+1
    std::vector<FaceObservation> obs;
    std::size_t numFaces() const { return offsets.empty() ? 0 : offsets.size() - 1; }
    std::size_t count(std::size_t face) const { return offsets[face + 1] - offsets[face]; }
    const FaceObservation* begin(std::size_t face) const { return obs.data() + offsets[face]; }
    const FaceObservation* end(std::size_t face) const { return obs.data() + offsets[face + 1]; }
};

/// The indices into vis.obs of each view's observations, for views 0 .. num_views-1, in
/// face order. Throws InvalidInput on an observation of a view >= num_views.
std::vector<std::vector<std::uint64_t>> observationsByView(const Visibility& vis,
                                                           std::size_t num_views);

/// Removes the observations i with drop[i] != 0 in place, keeping the order of the others (per
/// face sorted by view). Returns how many were removed. Throws InvalidInput unless drop has
/// one entry per observation.
std::size_t dropObservations(Visibility& vis, const std::vector<char>& drop);

/// Decides for every pair (face, view) whether the face is visible: all corners project
/// inside the image, in front of the camera within [min_depth_m, max_depth_m], front-facing,
/// within max_view_angle_deg, and not occluded (if `occluder` is non-null and
/// options.occlusion_test). Parallel over views with frustum culling first (faces are binned
/// into a coarse grid whose cell boxes are tested against each view's frustum). Deterministic:
/// the result does not depend on the thread count. Deleted and degenerate faces are never
/// visible. The occlusion rays go from the camera centre to the centroid and to the three
/// corners pulled 5 % towards the centroid (so that they do not graze the neighbours); a
/// sample is occluded by a hit closer than its distance minus occlusion_tolerance_m.
/// `progress` (optional) is ticked once per view. Throws InvalidInput on bad options
/// (max_view_angle_deg outside (0, 90], min_depth_m < 0, max_depth_m <= min_depth_m) or a
/// view with a non-positive image size or focal length. An empty mesh or no views is a no-op.
Visibility computeVisibility(const TriMesh& mesh, const std::vector<View>& views,
                             const VisibilityOptions& options, const Raycaster* occluder,
                             Progress* progress = nullptr);

}  // namespace vdbmap
