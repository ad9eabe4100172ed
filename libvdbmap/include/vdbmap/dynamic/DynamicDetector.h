// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/dynamic/FreeSpaceVotes.h"
#include "vdbmap/dynamic/ObjectTracks.h"
#include "vdbmap/dynamic/RangeImage.h"
#include "vdbmap/dynamic/ScanObjects.h"

namespace vdbmap {

class Dataset;

/// The options of moving-object removal (integrate.atsdf `dynamic_removal:`, docs/dynamic.md).
struct DynamicRemovalConfig {
    bool enabled = true;
    /// Scan k is tested against the scans k +- window_stride, k +- 2 window_stride, ... up to
    /// k +- window_frames (in time order), and k +- each of far_frames.
    int window_frames = 10;
    int window_stride = 2;
    std::vector<int> far_frames = {20, 30};
    /// Points whose SemanticKITTI class (lower 16 bits of the .label entry) is a moving class,
    /// 252..259, are dynamic too, when the dataset has LiDAR labels.
    bool use_labels = true;
    /// A point within this distance of the last tested point before it in the scan (the scan
    /// order follows the rings) takes that point's decision instead of its own test: near the
    /// sensor several returns fall in one voxel, and the map cannot tell them apart anyway.
    double share_radius_m = 0.25;
    RangeImageConfig image;
    FreeSpaceVoteConfig votes;
    /// The object level (`objects.enabled`): a scan's objects with enough points found moving
    /// are removed whole, and tracked so that they stay moving when the test cannot tell.
    ScanObjectConfig objects;
    ObjectTrackConfig tracks;
    /// A point of a moving object (not moving by its own test) that at least this many scans of
    /// the whole window hit (a return within the margin of it) and none saw through stays:
    /// static evidence beats the object's decision; 0 = never.
    int object_keep_hits = 1;
    /// An object moving by its track alone (not by its own points) whose candidate points are
    /// at least this share kept by static evidence stays whole: it is a static object the track
    /// wrongly continued (a parked car a moving one passed). 1 = only when all are kept.
    double object_static_share = 0.5;
    /// The points of an object not moving, within this many object voxels of a voxel with at
    /// least 4 points moving by their own test, go too unless static evidence keeps them: a
    /// mover joined to a static object in one object (a pedestrian passing a parked car).
    /// 0 = off.
    int grow_voxels = 1;
    /// ...and below such a voxel by up to this many more object voxels: the legs under a
    /// pedestrian's moving body, when the pedestrian walks by a parked car (one object).
    int grow_down_voxels = 6;
};

/// Throws ConfigError naming `who` and the option for a value out of range.
void validateDynamicRemovalConfig(const DynamicRemovalConfig& config, const std::string& who);

/// True for SemanticKITTI's moving classes 252..259 (moving car, bicyclist, person,
/// motorcyclist, on-rails, truck, other vehicle; docs/DATA.md).
inline bool isMovingClass(std::uint16_t semantic_kitti_class) {
    return semantic_kitti_class >= 252 && semantic_kitti_class <= 259;
}

/// Counts of the detection, summed over scans.
struct DynamicStats {
    std::size_t scans = 0;
    std::size_t points_in = 0;
    std::size_t points_dynamic = 0;      ///< removed: free space or label
    std::size_t points_free_space = 0;   ///< of which by the free-space votes
    std::size_t points_label = 0;        ///< of which by a moving label
    std::size_t scans_with_labels = 0;
    std::size_t points_tested = 0;       ///< representatives tested (the others share)
    std::size_t points_second_pass = 0;  ///< points some first-pass scan saw through
    std::size_t images_built = 0;        ///< range images made (each frame at most once per pass)
    std::size_t points_object = 0;       ///< removed by the object level (not by their own test)
    std::size_t points_kept_by_hits = 0; ///< of a moving object, kept by static evidence
    std::size_t points_grown = 0;        ///< removed next to a moving point, in a static object
    std::size_t objects_kept_static = 0; ///< moving by their track, kept whole by evidence
    std::size_t objects = 0;             ///< objects found (summed over the scans decided)
    std::size_t objects_moving = 0;      ///< of which moving
    std::size_t objects_tracked = 0;     ///< of which moving by their track alone
    std::size_t scans_replayed = 0;      ///< scans before a run's first ones, for the tracks
    double seconds = 0.0;                ///< wall time in detect(), images and label reads included
    double images_s = 0.0;               ///< of which reading neighbours and making their images
    double votes_s = 0.0;                ///< of which the free-space votes
};

/// Moving-object detection for the scans of one dataset, scan by scan, before integration.
/// The decision for a scan depends only on the dataset (its neighbours are read from it
/// whichever frames a run integrates), so tiled, untiled and distributed runs remove the same
/// points. Keeps the range images of the frames within reach of the window (frames asked for
/// in ascending time order reuse them; any order is correct). Not thread-safe: one scan at a
/// time (detect() itself is parallel).
class DynamicDetector {
public:
    DynamicDetector(const Dataset& dataset, DynamicRemovalConfig config);

    /// Flags (1 = dynamic) for the points of frame `frame` as the dataset reads them
    /// (`points_L`, in the LiDAR frame), `index` their indices in the scan file and
    /// `points_in_file` the file's point count (for the label check). Throws IoError for a
    /// label file that does not match its scan, what Dataset::loadScan throws for a neighbour.
    std::vector<std::uint8_t> detect(std::size_t frame, const std::vector<Vec3f>& points_L,
                                     const std::vector<std::uint32_t>& index,
                                     std::size_t points_in_file);

    /// The frames scan `frame` is tested against, the furthest in time first: the first 4 that
    /// exist are the first pass, the rest the second (tests, docs).
    void neighbours(std::size_t frame, std::vector<std::size_t>& first,
                    std::vector<std::size_t>& others) const;
    /// "timestamps" or "frame_order" (the dataset has no increasing timestamps).
    const std::string& timeOrder() const { return time_order_; }
    const DynamicStats& stats() const { return stats_; }
    const DynamicRemovalConfig& config() const { return config_; }

private:
    const RangeImage& image(std::size_t frame);
    void evictBefore(std::size_t rank);
    void buildImages(const std::vector<std::size_t>& frames);
    /// The free-space flags of the points of `frame` (and each point's votes).
    std::vector<std::uint8_t> freeSpace(std::size_t frame, const std::vector<Vec3f>& points_L,
                                        std::vector<PointVotes>& votes);
    /// The objects of the scans within trackHistory() before time rank `rank`, found now for
    /// those not seen yet (a run that starts mid-sequence).
    void replayHistory(std::size_t rank);
    /// The object level (docs/dynamic.md, "Objects"): adds to `dynamic` the points of moving
    /// objects and of their surroundings that static evidence does not keep.
    void objectLevel(std::size_t frame, const std::vector<Vec3f>& points_L, const std::vector<PointVotes>& votes,
                     std::vector<std::uint8_t>& dynamic);
    /// The objects of a scan, each with its points static by evidence (`votes`).
    ScanObjects objectsOf(std::size_t frame, const std::vector<Vec3f>& points_L, const std::vector<std::uint8_t>& dynamic,
                          const std::vector<PointVotes>& votes) const;
    /// Free and hit votes of the scans of the whole window for the points `points_L[i]`, i in
    /// `which`, of `frame`.
    std::vector<PointVotes> windowVotes(std::size_t frame, const std::vector<Vec3f>& points_L,
                                        const std::vector<std::size_t>& which);

    const Dataset& dataset_;
    DynamicRemovalConfig config_;
    std::vector<std::size_t> order_;  ///< frames in time order
    std::vector<std::size_t> rank_;   ///< position of each frame in order_
    std::string time_order_;
    static constexpr std::size_t kFirstPass = 4;
    /// An object voxel seeds grow_voxels with at least this many points moving by their own
    /// test (a lone wrong vote grows nothing).
    static constexpr int kGrowSeedPoints = 4;
    std::vector<int> offsets_;  ///< -o, +o for each offset o, largest first
    std::map<std::size_t, std::unique_ptr<RangeImage>> images_;  ///< by time rank
    std::map<std::size_t, std::vector<ScanCluster>> objects_;     ///< by time rank
    DynamicStats stats_;
};

}  // namespace vdbmap
