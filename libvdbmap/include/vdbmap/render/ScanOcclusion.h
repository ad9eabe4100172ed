// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/io/Camera.h"
#include "vdbmap/mesh/MeshArrays.h"
#include "vdbmap/render/Visibility.h"

namespace vdbmap {

class Dataset;
class MovingReturns;
class Progress;

/// When a LiDAR return hides a face from a view: the scan nearest in time to the image,
/// projected into it as a sparse depth image whose gaps between the beams are closed
/// (bracketedScanDepthImage), is compared with the depth of the face.
struct ScanOcclusionOptions {
    /// Along rows, a min filter of this radius (pixels) closes the gaps between a ring's
    /// returns (an HDL-64's 0.09 degrees are 1.1 px at KITTI's 721 px focal length).
    int row_dilate_px = 2;
    /// Down columns, the empty pixels between two returns at most this many empty rows apart
    /// take the farther of the two: the gap between two rings (an HDL-64's lower rings, 0.5
    /// degrees apart, are 6.3 px apart at KITTI's focal length, 7.1 px at 20 degrees below the
    /// optical axis). The farther ring, not the
    /// nearer: on the ground the nearer ring lies in front of the ground between the rings,
    /// which would hide itself at range; inside a car both rings are the car. (Before issue
    /// 33's traffic runs a 2 px square min filter left the ring gaps open, and a passing car's
    /// colours reached the road through them: docs/results/traffic.md.)
    int gap_px = 8;
    /// A return hides a face sample at camera depth z when its depth is below
    /// z * (1 - margin_rel) - margin_m. The relative part absorbs the spread of the min filter
    /// over slanted surfaces (ground at depth z: about z^2 / (f h) metres per pixel).
    double margin_m = 0.3;
    double margin_rel = 0.1;
    /// Returns known to be moving (MovingReturns: removed from the map as moving objects) cannot
    /// be the face's own surface, so they hide a sample at depth z by a tighter rule, when
    /// nearer than z - moving_margin_m, over a min filter of radius moving_dilate_px: the road
    /// under a passing car's tyres (a few tens of centimetres behind them) is hidden too.
    double moving_margin_m = 0.1;
    int moving_dilate_px = 6;
    /// The face is hidden when at least this fraction of its 4 samples (the centroid and the
    /// corners pulled 30 % towards it) is.
    double min_hidden_fraction = 0.5;
};

/// Camera depth (metres, along z) of the nearest scan return per pixel, +inf where none.
struct ScanDepthImage {
    int width = 0, height = 0;
    std::vector<float> depth_m;  ///< row-major
    bool returns = false;        ///< some return fell inside the image (else all +inf)
    bool empty() const { return !returns; }
    float at(int x, int y) const {
        if (x < 0 || y < 0 || x >= width || y >= height) {
            return std::numeric_limits<float>::infinity();
        }
        return depth_m[static_cast<std::size_t>(y) * width + x];
    }
};

/// The depth image of ScanOcclusionOptions: projected as scanDepthImage, min-filtered along rows
/// with radius dilate_px, then the ring gaps of each column closed (gaps of at most gap_px
/// empty rows take the farther of the returns around them). Throws
/// InvalidInput as scanDepthImage, and for gap_px < 0.
ScanDepthImage bracketedScanDepthImage(const std::vector<Vec3f>& points_C,
                                       const CameraIntrinsics& intrinsics, int dilate_px,
                                       int gap_px);

/// Projects points given in the camera frame C into the image (nearest pixel, z-buffered
/// minimum depth) and min-filters the result with a square window of radius dilate_px.
/// Points behind the camera or outside the image are skipped. Empty input gives an all-+inf
/// image. Throws InvalidInput for a non-positive image size or dilate_px < 0.
ScanDepthImage scanDepthImage(const std::vector<Vec3f>& points_C,
                              const CameraIntrinsics& intrinsics, int dilate_px);

/// True if the depth image hides the triangle (corners in the camera frame C) by the test of
/// ScanOcclusionOptions; `moving` (optional) is the depth image of the moving returns alone
/// (filtered with moving_dilate_px), which hides a sample by the moving rule.
bool faceHiddenByScan(const ScanDepthImage& depth, const std::array<Vec3d, 3>& corners_C,
                      const CameraIntrinsics& intrinsics, const ScanOcclusionOptions& options,
                      const ScanDepthImage* moving = nullptr);

/// The scan points of the scan nearest in time to view v, in v's camera frame C. Called once per
/// view, from TBB tasks: must be thread-safe.
using ViewScanFn = std::function<std::vector<Vec3f>(std::size_t view)>;

/// Removes from `vis` every observation whose face the scan of its view hides (faceHiddenByScan).
/// `mesh` must index faces as `vis` does (meshArrays(..., DeletedFaces::Collapse) of the mesh
/// the visibility was computed on). Parallel over views; `progress` (optional) is ticked per
/// view. `moving_of_view` (optional: empty function) gives the moving returns of the same scan
/// (a subset of its points), which also hide by the moving rule. `hidden_cos_angles` (optional)
/// receives the cos_angle of each observation removed. Returns the number of observations
/// removed. Throws InvalidInput on size mismatch and what the functions throw.
std::size_t removeScanOccluded(Visibility& vis, const MeshArrays& mesh,
                               const std::vector<View>& views, const ViewScanFn& scan_of_view,
                               const ScanOcclusionOptions& options, Progress* progress = nullptr,
                               const ViewScanFn& moving_of_view = {},
                               std::vector<float>* hidden_cos_angles = nullptr);

/// The frame whose scan is nearest in time to the images of frame `frame`. Every layout gives an
/// image the timestamp of its frame (docs/DATA.md: camera and LiDAR are synchronised, KITTI
/// triggers the cameras on the LiDAR sweep), so this is `frame` itself (dt = 0); the one place
/// to change if images ever carry their own times. Throws std::out_of_range past numFrames().
std::size_t nearestScanFrame(const Dataset& dataset, std::size_t frame);

/// ViewScanFn of a dataset: reads the nearest scan of each view's frame (nearestScanFrame) and
/// maps it into the view's camera frame, T_C_L = T_C_W * T_W_L.
ViewScanFn datasetViewScans(const Dataset& dataset, const std::vector<View>& views);

/// ViewScanFn of the moving returns of each view's nearest scan (MovingReturns, in W), mapped
/// into the view's camera frame. `moving` must outlive the function.
ViewScanFn movingViewScans(const Dataset& dataset, const std::vector<View>& views,
                           const MovingReturns& moving);

}  // namespace vdbmap
