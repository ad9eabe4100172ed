// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/dynamic/RangeImage.h"

namespace vdbmap {

/// When a point counts as seen through, and how many such scans make it dynamic
/// (docs/dynamic.md).
struct FreeSpaceVoteConfig {
    /// A scan j saw through point p if the bracket range of p's pixel in j's image exceeds
    /// |p - o_j| + margin_m + margin_per_m * |p - o_j| (range noise, pose error, the angular size
    /// of a pixel on a slanted surface).
    double margin_m = 0.3;
    double margin_per_m = 0.01;
    /// p is dynamic if at least min_free_votes scans saw through it and at least
    /// free_fraction of the scans that saw p's place (through it, or a return within the margin
    /// of p) saw through it. Occluded scans (a return in front of p) do not count either way.
    int min_free_votes = 2;
    /// A scan with no return at all around p's direction (the sky behind a tall vehicle) saw
    /// through p if p is closer to it than this (well within the sensor's range); 0 = never.
    double no_return_free_within_m = 40.0;
    double free_fraction = 0.0;
    /// The thin test (thin_margin_m 0 = off): a scan whose return lies behind p by more than
    /// thin_margin_m + thin_margin_per_m * |p - o|, but within the margin above, is a "thin"
    /// vote: p stood just in front of a surface that scan saw. A point with at least
    /// thin_min_votes thin or free votes, at least thin_fraction of its free and hit votes, is
    /// dynamic: a pedestrian 0.15 to 0.3 m in front of a parked car (docs/dynamic.md). The
    /// bracket takes the least range around p, so a static surface's own returns lie at or in
    /// front of it: a static point gets thin votes only from noise and pose error.
    double thin_margin_m = 0.12;
    double thin_margin_per_m = 0.005;
    int thin_min_votes = 5;
    double thin_fraction = 0.9;
};

/// One other scan to test against: its range image and its pose.
struct VoteScan {
    const RangeImage* image = nullptr;
    Isometry3d T_L_W = Isometry3d::Identity();  ///< world W into that scan's sensor frame L
};

/// The votes of the scans for one point.
struct PointVotes {
    std::uint16_t free = 0;  ///< saw through it
    std::uint16_t hit = 0;   ///< had a return within the margin of it
    std::uint16_t thin = 0;  ///< of the hits, those whose return lay behind it by the thin margin
};

/// The votes of `scans` for the point p_W: for each scan, "free" if its bracket range is beyond
/// |p - o| + margin (or it has no return around p's direction and p is within
/// no_return_free_within_m), "hit" if within the margin, nothing if in front (occluded) or
/// outside its image.
PointVotes voteFreeSpace(const Vec3f& p_W, const std::vector<VoteScan>& scans,
                         const FreeSpaceVoteConfig& config);

/// The decision rule on the votes (see FreeSpaceVoteConfig).
inline bool isDynamic(const PointVotes& v, const FreeSpaceVoteConfig& config) {
    const double seen = static_cast<double>(v.free + v.hit);
    if (v.free >= config.min_free_votes && static_cast<double>(v.free) >= config.free_fraction * seen) return true;
    const int thin = v.free + v.thin;
    return config.thin_margin_m > 0.0 && thin >= config.thin_min_votes &&
           static_cast<double>(thin) >= config.thin_fraction * seen;
}

/// Whether a point's first-pass votes send it to the second pass (some scan saw through it,
/// or, with the thin test, stood behind it).
inline bool needsSecondPass(const PointVotes& v, const FreeSpaceVoteConfig& config) {
    return v.free != 0 || (config.thin_margin_m > 0.0 && v.thin != 0);
}

/// Per point of `points_W` (one scan in W): 1 if dynamic by the free-space votes of `scans`,
/// else 0. Two passes: the `first` scans (a few spread over the window) first; a point none of
/// them saw through is static without asking the others (most points: the test's cost is
/// about first.size() look-ups per static point). The others are then asked only for the
/// remaining points, and the decision counts the votes of both; `second_pass` (may be null)
/// gets their number. `votes` (may be null) gets each point's votes: of the first scans, plus
/// of the others for the points asked again. Parallel over points (TBB).
std::vector<std::uint8_t> dynamicByFreeSpace(const std::vector<Vec3f>& points_W,
                                             const std::vector<VoteScan>& first,
                                             const std::vector<VoteScan>& others,
                                             const FreeSpaceVoteConfig& config,
                                             std::size_t* second_pass = nullptr,
                                             std::vector<PointVotes>* votes = nullptr);

}  // namespace vdbmap
