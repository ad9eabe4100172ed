// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/sim/MoversJson.h"

namespace vdbmap {

class Raycaster;

/// The volume the movers swept: the union over frames of each mover's bounding box at that
/// frame's pose T_W_O, inflated by `inflate_m` on every side.
class SweptVolume {
public:
    SweptVolume(const MoversFile& movers, double inflate_m);
    /// True if `p_W` lies in some inflated box.
    bool contains(const Vec3f& p_W) const;
    /// Area (m^2) of the volume's footprint on the ground: the union of the boxes' rectangles
    /// projected along the movers' up axis (z of O), rasterised on a grid of `cell_m` (a cell
    /// counts if its centre is covered). 0 without boxes.
    double groundArea(double cell_m) const;
    /// World-aligned bounds of all boxes (empty without boxes).
    const Eigen::AlignedBox3f& bounds() const { return bounds_W_; }
    std::size_t numBoxes() const { return boxes_.size(); }

private:
    struct Box {
        Eigen::Isometry3f T_O_W;    // world -> mover frame
        Eigen::AlignedBox3f box_O;  // inflated
        Eigen::AlignedBox3f bounds_W;
    };
    std::vector<Box> boxes_;
    Eigen::AlignedBox3f bounds_W_;
    Vec3f up_W_ = Vec3f::UnitZ();
};

/// Ghost area (m^2) of a mesh: the part of its surface farther than `ghost_distance_m` from
/// the static ground truth `static_gt` and inside `swept`. Each triangle is split into n^2
/// equal sub-triangles (n = ceil(longest edge / sample_spacing_m)) and a sub-triangle counts
/// whole where its centroid satisfies both conditions. Parallel; deterministic.
double ghostArea(const std::vector<Vec3f>& vertices,
                 const std::vector<std::array<std::uint32_t, 3>>& triangles,
                 const Raycaster& static_gt, const SweptVolume& swept, double ghost_distance_m,
                 double sample_spacing_m);

/// The same measure per triangle: entry t is triangle t's ghost area (m^2); ghostArea() is
/// their sum.
std::vector<double> ghostAreaPerFace(const std::vector<Vec3f>& vertices,
                                     const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                     const Raycaster& static_gt, const SweptVolume& swept,
                                     double ghost_distance_m, double sample_spacing_m);

/// A point that a run removed as dynamic: its frame number and its index in that frame's scan.
struct RemovedPoint {
    std::uint32_t frame = 0;
    std::uint32_t index = 0;
};

/// Reads `dynamic_points.ply` (binary little-endian PLY; vertex properties x y z float,
/// frame uint, index uint, in any order, other properties skipped). Throws IoError naming the
/// file for a missing file, another format or a missing property, or a truncated body.
std::vector<RemovedPoint> readRemovedPointsPly(const std::filesystem::path& path);

/// Per frame, per point: 1 if the ground-truth label marks a moving point (instance id != 0,
/// as vdbmap-sim --traffic writes it, or a SemanticKITTI moving class 252..259).
using MovingTruth = std::vector<std::vector<std::uint8_t>>;

/// The moving-point truth of a simulated sequence from its label files (NNNNNN.label, frame
/// number = file number) in `labels_dir`, for `frames` frames. Throws IoError naming a
/// missing or unreadable file.
MovingTruth readMovingTruth(const std::filesystem::path& labels_dir, std::size_t frames);

/// The labels folder of a simulated sequence whose gt/ is `gt_dir`, in every vdbmap-sim
/// layout: gt/labels (kitti360), gt/../labels (sequence), gt/../dataset/sequences/*/labels
/// (semantic-kitti). Empty if none exists.
std::filesystem::path findSimLabelsDir(const std::filesystem::path& gt_dir);

/// Removed points against the truth. recall = removed moving / all moving, precision =
/// removed moving / all removed, static retention = kept static / all static.
struct MovingPointScores {
    std::size_t moving_points = 0, static_points = 0;
    std::size_t removed = 0, removed_moving = 0, removed_static = 0;
    std::size_t removed_unmatched = 0;   ///< (frame, index) outside the truth; counted as wrong
    std::size_t removed_duplicates = 0;  ///< repeated (frame, index) pairs, counted once
    double recall = 0, precision = 0, static_retention = 1;
};
MovingPointScores scoreRemovedPoints(const MovingTruth& truth,
                                     const std::vector<RemovedPoint>& removed);

}  // namespace vdbmap
