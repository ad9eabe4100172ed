// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>

#include "vdbmap/io/Camera.h"
#include "vdbmap/sim/SimRig.h"

namespace vdbmap {

/// Everything `vdbmap-sim` can vary.
struct SimOptions {
    std::string scene = "street";  ///< "street" or "suv"
    std::size_t frames = 20;       ///< 0 = the scene's default (street 20, suv 126)
    std::uint64_t seed = 1;
    std::string lidar;     ///< preset name; "" = scene default (street hdl64, suv vls128)
    double size_m = 60.0;  ///< street length
    int cameras = 1;       ///< kitti rig: 1 (image_2) or 2 (image_2 + image_3)
    /// "kitti": KITTI layout (forward camera(s) image_2 / image_3); "surround": generic layout
    /// with the four cameras of surroundRig(rig_options) and a ready-to-use dataset.yaml.
    std::string rig = "kitti";
    SurroundRigOptions rig_options;  ///< image size, field of view, mounting of "surround"
    bool occluders = false;   ///< moving "pedestrian" boxes in some frames, images only
    /// Street traffic (buildStreetTraffic): this many cars, plus a van and three pedestrians,
    /// in the LiDAR and the images alike; 0 = none. gt/ stays the static world, the labels
    /// mark the moving points, gt/movers.json has every mover's pose per frame.
    std::size_t traffic = 0;
    int label_noise_px = 0;   ///< boundary jitter of semantic_2/3, pixels
    /// Per-point LiDAR labels (SemanticKITTI .label): KITTI layout labels/, surround layout
    /// labels/ with `labels_dir: labels` in dataset.yaml.
    bool lidar_labels = true;
    bool lidar_label_semantickitti_ids = true;  ///< raw SemanticKITTI ids, else our ids
    double lidar_label_flip_rate = 0.0;  ///< probability that a point gets another scene class
    int lidar_label_boundary_px = 0;     ///< boundary jitter in range-image pixels
    bool images = true;       ///< render image_k / semantic_k
    std::size_t gt_views = 4; ///< held-out views in gt/views (0 = none)
    std::filesystem::path spot_dir;  ///< folder with the Spot mesh ("" = street without Spot)
    /// The paper's vignetting model g(r) = 1 + a r^2 + b r^4 + c r^6 (Rohlfing 2012); the
    /// simulated image is I / g(r), so the correction g(r) * I recovers I.
    std::array<double, 3> vignetting_abc{0.3, 0.1, 0.05};
    double exposure_spread = 0.2;  ///< per-frame gain uniform in [1 - s, 1 + s]
    bool quiet = false;
};

/// What was written.
struct SimSummary {
    std::size_t frames = 0;
    std::size_t points = 0;            ///< LiDAR returns over all frames
    std::size_t gt_faces = 0;
    std::size_t observed_points = 0;   ///< gt/observed_points.ply
    double seconds = 0;
};

/// KITTI camera intrinsics used for image_2/image_3 (1242x375, fx = fy = 721.5377).
CameraIntrinsics kittiLikeIntrinsics();

/// Simulates a sequence and writes it into `out_dir`, plus vignetting.txt, exposure.txt and
/// gt/ (mesh.ply with face labels, textured/mesh.obj, observed_points.ply, views/).
/// rig "kitti": the KITTI layout of docs/DATA.md (velodyne/, calib.txt, poses.txt, times.txt,
/// image_k/, semantic_k/). rig "surround": the generic layout (scans/*.bin, poses.txt with
/// the LiDAR poses T_W_L as KITTI 3x4 lines, times.txt, image_<name>/, semantic_<name>/,
/// calib_<name>.txt with K:, D:, T: lines, and dataset.yaml: the `dataset:` section that
/// reads it, paths relative to the sequence). Both write labels/NNNNNN.label (per-point LiDAR
/// labels, SemanticKITTI format) unless lidar_labels is false. Both put the world W at KITTI camera 0 of frame
/// 0, so the scans and gt/ of a seed are the same for both rigs. Deterministic for a seed.
/// Throws ConfigError for bad options and IoError for write failures.
SimSummary writeSimSequence(const SimOptions& options, const std::filesystem::path& out_dir);

}  // namespace vdbmap
