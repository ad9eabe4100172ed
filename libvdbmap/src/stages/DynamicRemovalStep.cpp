// SPDX-License-Identifier: Apache-2.0
#include "stages/DynamicRemovalStep.h"
#include "stages/KeepPoints.h"


#include "vdbmap/core/Log.h"
#include "vdbmap/core/OptionSpec.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/Report.h"
#include "pipeline/ContextBuilder.h"

namespace vdbmap::detail {

void declareDynamicOptions(OptionSpec& spec, DynamicRemovalConfig& c) {
    spec.add("dynamic_removal",
             "Remove moving objects: a point that other scans saw through (free space, counted "
             "per point over the scans around it in time) or that carries a SemanticKITTI "
             "moving label (252-259) is not integrated; written to dynamic_points.ply",
             c.enabled, true);
    spec.add("dynamic_window_frames",
             "A scan is tested against the scans up to this many frames before and after it",
             c.window_frames, 10, "frames");
    spec.add("dynamic_window_stride", "Every this many frames within the window",
             c.window_stride, 2, "frames");
    spec.add("dynamic_far_frames",
             "Further frame offsets tested on both sides (slow and stopping movers)", c.far_frames,
             std::vector<int>{20, 30});
    spec.add("dynamic_margin_m",
             "A scan saw through a point if its return in the point's direction lies beyond the "
             "point by more than margin_m + margin_per_m * distance",
             c.votes.margin_m, 0.3, "m");
    spec.add("dynamic_margin_per_m", "The margin's growth with the distance from that scan's sensor",
             c.votes.margin_per_m, 0.01);
    spec.add("dynamic_min_free_votes", "Scans that must have seen through a point to remove it",
             c.votes.min_free_votes, 2);
    spec.add("dynamic_free_fraction",
             "And at least this fraction of the scans that saw the point's place (through it or "
             "at it; scans with something in front do not count)",
             c.votes.free_fraction, 0.0);
    spec.add("dynamic_thin_margin_m",
             "Thin test (0 = off): a scan whose return lies behind a point by more than this "
             "(plus thin_margin_per_m * distance), but within the margin, stood behind it; a point "
             "enough scans stood behind is moving (a pedestrian just in front of a parked car)",
             c.votes.thin_margin_m, 0.12, "m");
    spec.add("dynamic_thin_margin_per_m", "The thin margin's growth with the distance", c.votes.thin_margin_per_m,
             0.005);
    spec.add("dynamic_thin_min_votes", "Scans that must have stood behind or seen through a point (thin test)",
             c.votes.thin_min_votes, 5);
    spec.add("dynamic_thin_fraction",
             "And at least this fraction of the scans that saw the point's place (thin test)",
             c.votes.thin_fraction, 0.9);
    spec.add("dynamic_no_return_free_within_m",
             "A scan with no return at all around a point's direction (sky behind it) saw through "
             "it if the point is closer to that scan than this (0 = never)",
             c.votes.no_return_free_within_m, 40.0, "m");
    spec.add("dynamic_azimuth_res_deg", "Column width of the range images", c.image.azimuth_res_deg,
             0.2, "deg");
    spec.add("dynamic_elevation_res_deg",
             "Row height of the range images (finer than the ring spacing)",
             c.image.elevation_res_deg, 0.2, "deg");
    spec.add("dynamic_azimuth_radius_px",
             "Columns on each side whose nearest returns also bracket a point", c.image.azimuth_radius_px, 1,
             "pixels");
    spec.add("dynamic_elevation_search_px",
             "Rows searched below and above a point for the nearest ring", c.image.elevation_search_px,
             8, "pixels");
    spec.add("dynamic_share_radius_m",
             "A point this close to the last tested point before it in the scan shares its "
             "decision (0 = test every point)",
             c.share_radius_m, 0.25, "m");
    spec.add("dynamic_objects",
             "Object level: cut each scan into objects (connected non-ground points) and remove "
             "an object whole when enough of its points are moving; track moving objects so that "
             "they stay moving where the free-space test cannot tell (the end of a drive)",
             c.objects.enabled, true);
    spec.add("dynamic_object_min_points",
             "An object is moving when at least this many of its points are moving by the "
             "free-space test...",
             c.objects.min_points, 5);
    spec.add("dynamic_object_min_fraction", "...and at least this fraction of its points",
             c.objects.min_fraction, 0.2);
    spec.add("dynamic_object_max_extent_m",
             "Objects wider (horizontal diagonal) than this are never moving (facades, hedges)",
             c.objects.max_extent_m, 20.0, "m");
    spec.add("dynamic_object_voxel_m",
             "Objects are connected over voxels of this size (26-neighbourhood)", c.objects.voxel_m,
             0.2, "m");
    spec.add("dynamic_object_keep_hits",
             "A point of a moving object that at least this many scans hit and none saw through "
             "stays (0 = never)",
             c.object_keep_hits, 1);
    spec.add("dynamic_object_static_share",
             "An object moving by its track alone whose points are at least this share kept by "
             "static evidence stays whole (a parked car a moving one passed)",
             c.object_static_share, 0.5);
    spec.add("dynamic_grow_voxels",
             "Points of an object not moving within this many object voxels of a voxel with 4 points "
             "moving by their own test go too unless static evidence keeps them (a pedestrian "
             "passing a parked car); 0 = off",
             c.grow_voxels, 1, "voxels");
    spec.add("dynamic_grow_down_voxels",
             "...and the points below such a voxel by up to this many more voxels (the legs under a "
             "pedestrian's moving body next to a parked car)",
             c.grow_down_voxels, 6, "voxels");
    spec.add("dynamic_ground_band_m",
             "Points less than this above the local ground height (lowest points around, with a "
             "slope allowance) are ground and join no object",
             c.objects.ground_band_m, 0.2, "m");
    spec.add("dynamic_ground_cell_m", "Cell of the ground height grid", c.objects.ground_cell_m, 1.0, "m");
    spec.add("dynamic_ground_radius_cells", "Cells around a cell whose lowest points bound its ground",
             c.objects.ground_radius_cells, 2, "cells");
    spec.add("dynamic_ground_slope", "Ground rise allowed per metre to a neighbouring cell",
             c.objects.ground_slope, 0.1);
    spec.add("dynamic_track_frames",
             "A tracked object stays moving this many scans after it was last seen moving by its "
             "own points (0 = no tracking)",
             c.tracks.frames, 10, "frames");
    spec.add("dynamic_track_gate_m",
             "An object continues a track if its box is within this of the box the track predicts",
             c.tracks.gate_m, 1.5, "m");
    spec.add("dynamic_track_max_step_m",
             "...or, for a track without a velocity yet, within this of its last centroid per scan",
             c.tracks.max_step_m, 4.0, "m");
    spec.add("dynamic_track_min_confirmations",
             "Objects moving by their own points a track needs before it makes others moving",
             c.tracks.min_confirmations, 2);
    spec.add("dynamic_track_static_share",
             "An object not moving by its own points of which at least this share is static by "
             "evidence (hit, never seen through) does not continue a track as its whole object (a "
             "parked car a van stopped beside is not the van); > 1 = off",
             c.tracks.static_share, 0.5);
    spec.add("dynamic_track_part_gate_m",
             "An object no moving track took, within this of a moving track's box and no larger than its "
             "object (or than dynamic_track_part_extent_m), is a part of the mover (a car seen "
             "from behind is several objects); < 0 = off",
             c.tracks.part_gate_m, 0.5, "m");
    spec.add("dynamic_track_part_extent_m",
             "...a part may be this large even when the track's object was smaller",
             c.tracks.part_max_extent_m, 2.5, "m");
    spec.add("dynamic_use_labels",
             "Also remove points whose LiDAR label (when the dataset has them) is a moving class "
             "252-259",
             c.use_labels, true);
}

DynamicRemovalStep::DynamicRemovalStep(Context& ctx, const DynamicRemovalConfig& config) {
    if (!config.enabled) return;
    dataset_ = &ctx.dataset();
    detector_ = std::make_unique<DynamicDetector>(ctx.dataset(), config);
    moving_ = std::make_shared<MovingReturns>();
    ContextBuilder::setMovingReturns(ctx, moving_);
}

ScanFilter DynamicRemovalStep::filter() {
    if (!detector_) return {};
    return [this](std::size_t frame, PointCloud& cloud, const std::vector<std::uint32_t>& index,
                  std::size_t points_in_file) {
        std::vector<std::uint8_t> dynamic;
        if (!sharing_ || !shared_.flags(frame, index, dynamic)) {
            dynamic = detector_->detect(frame, cloud.points, index, points_in_file);
        }
        const Isometry3d& T_W_L = dataset_->frame(frame).T_W_L;
        const Eigen::Matrix3f R = T_W_L.linear().cast<float>();
        const Vec3f t = T_W_L.translation().cast<float>();
        std::vector<Vec3f> moving_W;
        keepPoints(cloud, [&](std::size_t i) {
            if (!dynamic[i]) return true;
            moving_W.push_back(R * cloud.points[i] + t);
            removed_.add(moving_W.back(), static_cast<std::uint32_t>(frame), index[i]);
            return false;
        });
        moving_->set(frame, std::move(moving_W));
    };
}

void DynamicRemovalStep::shareDecisions(
    const std::vector<std::size_t>& mine, const std::vector<std::size_t>& integrated,
    const std::function<std::vector<std::string>(const std::string&)>& all_gather) {
    if (!detector_) return;
    const std::string part = shared_.decide(*dataset_, *detector_, mine);
    const std::vector<std::string> parts = all_gather(part);
    sharing_ = true;
    shared_.adopt(parts, integrated);
}

void DynamicRemovalStep::finish(Context& ctx, const std::string& stage) const {
    Report& r = ctx.report();
    r.set({"stages", stage, "dynamic_removal", "enabled"}, detector_ != nullptr);
    if (!detector_) return;
    const DynamicStats& s = detector_->stats();
    const std::vector<std::string> at{"stages", stage, "dynamic_removal"};
    auto key = [&](const char* k) {
        std::vector<std::string> p = at;
        p.emplace_back(k);
        return p;
    };
    r.set(key("scans"), s.scans);
    r.set(key("points_in"), s.points_in);
    r.set(key("points_dynamic"), s.points_dynamic);
    r.set(key("points_free_space"), s.points_free_space);
    r.set(key("points_label"), s.points_label);
    r.set(key("scans_with_labels"), s.scans_with_labels);
    r.set(key("points_tested"), s.points_tested);
    r.set(key("points_second_pass"), s.points_second_pass);
    r.set(key("range_images"), s.images_built);
    r.set(key("points_object"), s.points_object);
    r.set(key("points_kept_by_hits"), s.points_kept_by_hits);
    r.set(key("points_grown"), s.points_grown);
    r.set(key("objects_kept_static"), s.objects_kept_static);
    r.set(key("objects"), s.objects);
    r.set(key("objects_moving"), s.objects_moving);
    r.set(key("objects_tracked"), s.objects_tracked);
    r.set(key("scans_replayed"), s.scans_replayed);
    if (sharing_) {
        // A distributed run: scans this process tested for every process, and scans whose
        // decision it took from another process (not tested here).
        r.set(key("scans_decided_for_all"), shared_.decidedHere());
        r.set(key("scans_adopted"), shared_.adopted());
    }
    r.set(key("seconds"), s.seconds);
    r.set(key("range_images_s"), s.images_s);
    r.set(key("votes_s"), s.votes_s);
    r.set(key("time_order"), detector_->timeOrder());
    if (detector_->timeOrder() == "frame_order") {
        r.set(key("time_order_note"), "the dataset has no timestamps: neighbours in time are "
                                      "taken in frame order");
    }
    const std::string file = ctx.processes() > 1 ? dynamicPointsPartName(ctx.process())
                                                 : std::string("dynamic_points.ply");
    ctx.writeOutput(file, dynamicPointsPly(removed_));
    if (ctx.processes() == 1) {
        r.set({"outputs", "dynamic_points"}, (ctx.outputDir() / file).string());
    }
    logInfo(stage + ": removed " + std::to_string(s.points_dynamic) + " of " +
            std::to_string(s.points_in) + " points as moving (" +
            std::to_string(s.points_label) + " by label) in " + std::to_string(s.seconds) + " s");
}

}  // namespace vdbmap::detail
