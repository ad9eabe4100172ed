// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/dynamic/DynamicDetector.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numeric>
#include <set>
#include <sstream>

#include "vdbmap/Error.h"
#include "vdbmap/core/Timer.h"
#include "vdbmap/dynamic/JoinedObjects.h"
#include "vdbmap/dynamic/StaticColumns.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/io/LidarLabels.h"

namespace vdbmap {

namespace {

[[noreturn]] void bad(const std::string& who, const std::string& key, const std::string& what,
                      double value) {
    std::ostringstream os;
    os << who << ": option 'dynamic_" << key << "' must be " << what << ", got " << value;
    throw ConfigError(os.str());
}

/// Whether `p` (W) lies in the box `b` grown by `grow_m`.
bool inBox(const Vec3d& p, const TrackBox& b, double grow_m) {
    return (p.array() >= b.min_W.array() - grow_m).all() && (p.array() <= b.max_W.array() + grow_m).all();
}

/// Static evidence for a point (docs/dynamic.md, step 5): at least `keep_hits` scans hit it
/// (thin votes stood behind it: no evidence for it) and none saw through it; 0 = never.
bool keptByVotes(const PointVotes& v, int keep_hits) {
    return keep_hits > 0 && v.free == 0 && v.hit - v.thin >= keep_hits;
}

/// A pole beside a mover's path, joined to the mover while it passes (StaticColumns.h), is no
/// part of its box: the box of an object moving by its own points is that of its points
/// outside thin static columns (at most kColumnFootprintM wide, kColumnMinHeightM tall), so
/// that the track's box does not grow to the pole and step 5 leaves it to static evidence.
constexpr float kColumnFootprintM = 0.4f;
constexpr float kColumnMinHeightM = 1.0f;
constexpr float kColumnVoxelM = 0.1f;  // finer than the objects' voxels: a pole 0.1 m off stays apart

void leaveOutColumns(const std::vector<Vec3f>& points_L, const Isometry3d& T_W_L,
                     const std::vector<std::uint8_t>& kept, ScanObjects& objects) {
    std::vector<std::vector<std::size_t>> members(objects.clusters.size());
    for (std::size_t i = 0; i < points_L.size(); ++i) {
        const std::int32_t c = objects.cluster[i];
        if (c < 0) continue;
        const ScanCluster& sc = objects.clusters[static_cast<std::size_t>(c)];
        if (sc.confirmed && sc.static_points > 0) members[static_cast<std::size_t>(c)].push_back(i);
    }
    for (std::size_t c = 0; c < members.size(); ++c) {
        if (members[c].empty()) continue;
        std::vector<std::uint8_t> member_kept(members[c].size());
        for (std::size_t m = 0; m < members[c].size(); ++m) member_kept[m] = kept[members[c][m]];
        const std::vector<std::uint8_t> column =
            staticColumns(points_L, members[c], member_kept, kColumnVoxelM, kColumnFootprintM, kColumnMinHeightM);
        if (std::find(column.begin(), column.end(), 1) == column.end()) continue;
        ScanCluster& sc = objects.clusters[c];
        bool first = true;
        Vec3d sum = Vec3d::Zero();
        std::size_t n = 0;
        for (std::size_t m = 0; m < members[c].size(); ++m) {
            if (column[m]) continue;
            const Vec3d p_W = T_W_L * points_L[members[c][m]].cast<double>();
            sc.min_W = first ? p_W : Vec3d(sc.min_W.cwiseMin(p_W));
            sc.max_W = first ? p_W : Vec3d(sc.max_W.cwiseMax(p_W));
            sum += p_W;
            ++n;
            first = false;
        }
        if (n > 0) sc.centroid_W = sum / static_cast<double>(n);
    }
}

/// Step 6 of the object level (docs/dynamic.md, "Joined objects"): in each object flagged in
/// `joined`, the points not `kept` connected through such points to a point inside a box of
/// `boxes` (grown by `voxel_m`) or to a point already `dynamic` become dynamic. Returns how many.
std::size_t takeJoinedMovers(const std::vector<Vec3f>& points_L, const ScanObjects& objects,
                             const std::vector<std::uint8_t>& joined, const std::vector<TrackBox>& boxes,
                             const Isometry3d& T_W_L, double voxel_m, const std::function<bool(std::size_t)>& kept,
                             std::vector<std::uint8_t>& dynamic) {
    if (std::find(joined.begin(), joined.end(), 1) == joined.end()) return 0;
    std::vector<std::vector<std::size_t>> members(objects.clusters.size());
    for (std::size_t i = 0; i < points_L.size(); ++i) {
        const std::int32_t c = objects.cluster[i];
        if (c >= 0 && joined[static_cast<std::size_t>(c)]) members[static_cast<std::size_t>(c)].push_back(i);
    }
    auto inABox = [&](std::size_t i) {
        const Vec3d p = T_W_L * points_L[i].cast<double>();
        return std::any_of(boxes.begin(), boxes.end(), [&](const TrackBox& b) { return inBox(p, b, voxel_m); });
    };
    std::size_t taken = 0;
    for (const std::vector<std::size_t>& object : members) {
        if (object.empty()) continue;
        std::vector<std::uint8_t> seed(object.size()), static_evidence(object.size());
        for (std::size_t m = 0; m < object.size(); ++m) {
            const std::size_t i = object[m];
            static_evidence[m] = !dynamic[i] && kept(i);
            seed[m] = dynamic[i] || (!static_evidence[m] && inABox(i));
        }
        const std::vector<std::uint8_t> mover =
            moverOfJoined(points_L, object, seed, static_evidence, static_cast<float>(voxel_m));
        for (std::size_t m = 0; m < object.size(); ++m) {
            const std::size_t i = object[m];
            if (!mover[m] || dynamic[i]) continue;
            dynamic[i] = 1;
            ++taken;
        }
    }
    return taken;
}

}  // namespace

void validateDynamicRemovalConfig(const DynamicRemovalConfig& c, const std::string& who) {
    if (c.window_frames < 0) bad(who, "window_frames", ">= 0", c.window_frames);
    if (c.window_stride < 1) bad(who, "window_stride", ">= 1", c.window_stride);
    for (const int f : c.far_frames) {
        if (f < 1) bad(who, "far_frames", "a list of frame offsets >= 1", f);
    }
    if (!(c.image.azimuth_res_deg > 0.0 && c.image.azimuth_res_deg <= 10.0)) {
        bad(who, "azimuth_res_deg", "in (0, 10]", c.image.azimuth_res_deg);
    }
    if (!(c.image.elevation_res_deg > 0.0 && c.image.elevation_res_deg <= 10.0)) {
        bad(who, "elevation_res_deg", "in (0, 10]", c.image.elevation_res_deg);
    }
    if (c.image.azimuth_radius_px < 0 || c.image.azimuth_radius_px > 100) {
        bad(who, "azimuth_radius_px", "in [0, 100]", c.image.azimuth_radius_px);
    }
    if (c.image.elevation_search_px < 0 || c.image.elevation_search_px > 1000) {
        bad(who, "elevation_search_px", "in [0, 1000]", c.image.elevation_search_px);
    }
    if (!(c.votes.margin_m >= 0.0) || !std::isfinite(c.votes.margin_m)) {
        bad(who, "margin_m", "finite and >= 0", c.votes.margin_m);
    }
    if (!(c.votes.margin_per_m >= 0.0) || !std::isfinite(c.votes.margin_per_m)) {
        bad(who, "margin_per_m", "finite and >= 0", c.votes.margin_per_m);
    }
    if (!(c.share_radius_m >= 0.0) || !std::isfinite(c.share_radius_m)) {
        bad(who, "share_radius_m", "finite and >= 0", c.share_radius_m);
    }
    if (!(c.votes.no_return_free_within_m >= 0.0) || !std::isfinite(c.votes.no_return_free_within_m)) {
        bad(who, "no_return_free_within_m", "finite and >= 0", c.votes.no_return_free_within_m);
    }
    const ScanObjectConfig& o = c.objects;
    if (!(o.ground_cell_m > 0.0 && o.ground_cell_m <= 100.0)) bad(who, "ground_cell_m", "in (0, 100]", o.ground_cell_m);
    if (o.ground_radius_cells < 0 || o.ground_radius_cells > 50) {
        bad(who, "ground_radius_cells", "in [0, 50]", o.ground_radius_cells);
    }
    if (!(o.ground_slope >= 0.0) || !std::isfinite(o.ground_slope)) bad(who, "ground_slope", "finite and >= 0", o.ground_slope);
    if (!(o.ground_band_m >= 0.0) || !std::isfinite(o.ground_band_m)) {
        bad(who, "ground_band_m", "finite and >= 0", o.ground_band_m);
    }
    if (!(o.voxel_m >= 0.01 && o.voxel_m <= 10.0)) bad(who, "object_voxel_m", "in [0.01, 10]", o.voxel_m);
    if (o.min_points < 1) bad(who, "object_min_points", ">= 1", o.min_points);
    if (!(o.min_fraction >= 0.0 && o.min_fraction <= 1.0)) bad(who, "object_min_fraction", "in [0, 1]", o.min_fraction);
    if (!(o.max_extent_m > 0.0) || !std::isfinite(o.max_extent_m)) {
        bad(who, "object_max_extent_m", "finite and > 0", o.max_extent_m);
    }
    if (c.tracks.frames < 0 || c.tracks.frames > 1000) bad(who, "track_frames", "in [0, 1000]", c.tracks.frames);
    if (!(c.tracks.gate_m > 0.0) || !std::isfinite(c.tracks.gate_m)) bad(who, "track_gate_m", "finite and > 0", c.tracks.gate_m);
    if (!(c.tracks.max_step_m > 0.0) || !std::isfinite(c.tracks.max_step_m)) {
        bad(who, "track_max_step_m", "finite and > 0", c.tracks.max_step_m);
    }
    if (!std::isfinite(c.tracks.part_gate_m)) bad(who, "track_part_gate_m", "finite", c.tracks.part_gate_m);
    if (!(c.tracks.part_max_extent_m >= 0.0) || !std::isfinite(c.tracks.part_max_extent_m)) {
        bad(who, "track_part_extent_m", "finite and >= 0", c.tracks.part_max_extent_m);
    }
    if (!(c.tracks.static_share >= 0.0) || !std::isfinite(c.tracks.static_share)) {
        bad(who, "track_static_share", "finite and >= 0", c.tracks.static_share);
    }
    if (c.tracks.min_confirmations < 1) bad(who, "track_min_confirmations", ">= 1", c.tracks.min_confirmations);
    if (c.object_keep_hits < 0) bad(who, "object_keep_hits", ">= 0", c.object_keep_hits);
    if (!(c.object_static_share >= 0.0 && c.object_static_share <= 1.0)) {
        bad(who, "object_static_share", "in [0, 1]", c.object_static_share);
    }
    if (c.grow_voxels < 0 || c.grow_voxels > 10) bad(who, "grow_voxels", "in [0, 10]", c.grow_voxels);
    if (c.grow_down_voxels < 0 || c.grow_down_voxels > 50) bad(who, "grow_down_voxels", "in [0, 50]", c.grow_down_voxels);
    if (c.votes.min_free_votes < 1) bad(who, "min_free_votes", ">= 1", c.votes.min_free_votes);
    if (!(c.votes.thin_margin_m >= 0.0) || !std::isfinite(c.votes.thin_margin_m)) {
        bad(who, "thin_margin_m", "finite and >= 0", c.votes.thin_margin_m);
    }
    if (!(c.votes.thin_margin_per_m >= 0.0) || !std::isfinite(c.votes.thin_margin_per_m)) {
        bad(who, "thin_margin_per_m", "finite and >= 0", c.votes.thin_margin_per_m);
    }
    if (c.votes.thin_min_votes < 1) bad(who, "thin_min_votes", ">= 1", c.votes.thin_min_votes);
    if (!(c.votes.thin_fraction >= 0.0 && c.votes.thin_fraction <= 1.0)) {
        bad(who, "thin_fraction", "in [0, 1]", c.votes.thin_fraction);
    }
    if (!(c.votes.free_fraction >= 0.0 && c.votes.free_fraction <= 1.0)) {
        bad(who, "free_fraction", "in [0, 1]", c.votes.free_fraction);
    }
}

DynamicDetector::DynamicDetector(const Dataset& dataset, DynamicRemovalConfig config)
    : dataset_(dataset), config_(std::move(config)) {
    const std::size_t n = dataset_.numFrames();
    order_.resize(n);
    std::iota(order_.begin(), order_.end(), std::size_t(0));
    // Time order from the timestamps when the dataset has them (not all equal); else the
    // frame order, which report.json says (issue 33: "uses the frame order and says so").
    bool stamped = false;
    for (std::size_t i = 1; i < n && !stamped; ++i) {
        stamped = dataset_.frame(i).timestamp_s != dataset_.frame(0).timestamp_s;
    }
    if (stamped) {
        std::stable_sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) {
            return dataset_.frame(a).timestamp_s < dataset_.frame(b).timestamp_s;
        });
        time_order_ = "timestamps";
    } else {
        time_order_ = "frame_order";
    }
    rank_.resize(n);
    for (std::size_t r = 0; r < n; ++r) rank_[order_[r]] = r;

    // Offsets, the largest first: a mover has moved most between far-apart scans. The first
    // pass asks the first kFirstPass of them that exist for a frame (a point none of them saw
    // through is static), the second pass the rest.
    std::set<int> all;
    for (int o = config_.window_stride; o <= config_.window_frames; o += config_.window_stride) all.insert(o);
    for (const int f : config_.far_frames) all.insert(f);
    for (auto it = all.rbegin(); it != all.rend(); ++it) {
        offsets_.push_back(-*it);
        offsets_.push_back(*it);
    }
}

void DynamicDetector::neighbours(std::size_t frame, std::vector<std::size_t>& first,
                                 std::vector<std::size_t>& others) const {
    first.clear();
    others.clear();
    const long r = static_cast<long>(rank_.at(frame));
    const long n = static_cast<long>(order_.size());
    // The window's scans that exist, in the order of the offsets (the furthest first), and
    // which side of this scan each lies on.
    std::vector<std::size_t> frames;
    std::vector<int> side_of;
    for (const int o : offsets_) {
        const long q = r + o;
        if (q < 0 || q >= n) continue;
        frames.push_back(order_[static_cast<std::size_t>(q)]);
        side_of.push_back(o > 0 ? 1 : 0);
    }
    // The first pass: the kFirstPass furthest, and the two furthest of a side none of them is
    // on. Near the start or the end of a drive the furthest scans all lie on one side, and a
    // car driving ahead of the sensor hides its own places from every earlier scan: only the
    // later ones see through them. The second pass: the rest, in the same order.
    std::vector<char> in_first(frames.size(), 0);
    int on_side[2] = {0, 0};
    for (std::size_t k = 0; k < std::min(kFirstPass, frames.size()); ++k) {
        in_first[k] = 1;
        ++on_side[side_of[k]];
    }
    for (int side = 0; side < 2; ++side) {
        for (std::size_t k = 0, added = 0; on_side[side] == 0 && added < 2 && k < frames.size(); ++k) {
            if (side_of[k] != side || in_first[k]) continue;
            in_first[k] = 1;
            ++added;
        }
    }
    for (std::size_t k = 0; k < frames.size(); ++k) (in_first[k] ? first : others).push_back(frames[k]);
}

const RangeImage& DynamicDetector::image(std::size_t frame) {
    const std::size_t r = rank_[frame];
    auto it = images_.find(r);
    if (it != images_.end()) return *it->second;
    const PointCloud cloud = dataset_.loadScan(frame);
    auto img = std::make_unique<RangeImage>(cloud.points, config_.image);
    ++stats_.images_built;
    return *images_.emplace(r, std::move(img)).first->second;
}

void DynamicDetector::evictBefore(std::size_t rank) {
    images_.erase(images_.begin(), images_.lower_bound(rank));
}

void DynamicDetector::buildImages(const std::vector<std::size_t>& frames) {
    Timer images_timer;
    // Build the missing images in parallel (usually the one or two newly in the window).
    std::vector<std::size_t> missing;
    for (const std::size_t f : frames) {
        if (!images_.count(rank_[f])) missing.push_back(f);
    }
    std::vector<std::unique_ptr<RangeImage>> built(missing.size());
    tbb::parallel_for(std::size_t(0), missing.size(), [&](std::size_t i) {
        const PointCloud cloud = dataset_.loadScan(missing[i]);
        built[i] = std::make_unique<RangeImage>(cloud.points, config_.image);
    });
    for (std::size_t i = 0; i < missing.size(); ++i) {
        images_.emplace(rank_[missing[i]], std::move(built[i]));
        ++stats_.images_built;
    }
    stats_.images_s += images_timer.elapsedSeconds();
}

std::vector<std::uint8_t> DynamicDetector::freeSpace(std::size_t frame, const std::vector<Vec3f>& points_L,
                                                     std::vector<PointVotes>& votes) {
    std::vector<std::uint8_t> dynamic(points_L.size(), 0);
    votes.assign(points_L.size(), PointVotes{});
    std::vector<std::size_t> first_frames, other_frames;
    neighbours(frame, first_frames, other_frames);
    if (first_frames.empty() && other_frames.empty()) return dynamic;
    int max_offset = config_.window_frames;
    for (const int f : config_.far_frames) max_offset = std::max(max_offset, f);
    const std::size_t r = rank_.at(frame);
    evictBefore(r > static_cast<std::size_t>(max_offset) ? r - static_cast<std::size_t>(max_offset) : 0);
    std::vector<std::size_t> all = first_frames;
    all.insert(all.end(), other_frames.begin(), other_frames.end());
    buildImages(all);
    auto scans = [&](const std::vector<std::size_t>& frames) {
        std::vector<VoteScan> out;
        for (const std::size_t f : frames) {
            out.push_back({&image(f), dataset_.frame(f).T_W_L.inverse()});
        }
        return out;
    };
    Timer votes_timer;
    const Isometry3d& T_W_L = dataset_.frame(frame).T_W_L;
    const Eigen::Matrix3f R = T_W_L.linear().cast<float>();
    const Vec3f t = T_W_L.translation().cast<float>();
    // Representatives: a point near the last tested one shares its decision.
    const float share2 = static_cast<float>(config_.share_radius_m * config_.share_radius_m);
    std::vector<Vec3f> tested_W;
    std::vector<std::uint32_t> rep(points_L.size());
    tested_W.reserve(points_L.size());
    Vec3f last_L(1e30f, 1e30f, 1e30f);
    for (std::size_t i = 0; i < points_L.size(); ++i) {
        if ((points_L[i] - last_L).squaredNorm() > share2 || tested_W.empty()) {
            last_L = points_L[i];
            tested_W.push_back(R * points_L[i] + t);
        }
        rep[i] = static_cast<std::uint32_t>(tested_W.size() - 1);
    }
    std::size_t second = 0;
    std::vector<PointVotes> tested_votes;
    const std::vector<std::uint8_t> tested = dynamicByFreeSpace(
        tested_W, scans(first_frames), scans(other_frames), config_.votes, &second, &tested_votes);
    for (std::size_t i = 0; i < points_L.size(); ++i) {
        dynamic[i] = tested[rep[i]];
        votes[i] = tested_votes[rep[i]];
    }
    stats_.points_tested += tested_W.size();
    stats_.points_second_pass += second;
    stats_.votes_s += votes_timer.elapsedSeconds();
    return dynamic;
}

void DynamicDetector::replayHistory(std::size_t rank) {
    const std::size_t history = static_cast<std::size_t>(trackHistory(config_.tracks));
    const std::size_t from = rank > history ? rank - history : 0;
    objects_.erase(objects_.begin(), objects_.lower_bound(from));
    for (std::size_t q = from; q < rank; ++q) {
        if (objects_.count(q)) continue;
        const std::size_t frame = order_[q];
        PointCloud cloud;
        std::vector<std::uint32_t> index;
        dataset_.loadScan(frame, cloud, nullptr, &index);
        std::vector<PointVotes> votes;
        const std::vector<std::uint8_t> free = freeSpace(frame, cloud.points, votes);
        objects_[q] = objectsOf(frame, cloud.points, free, votes).clusters;
        ++stats_.scans_replayed;
    }
}

std::vector<PointVotes> DynamicDetector::windowVotes(std::size_t frame,
                                                    const std::vector<Vec3f>& points_L,
                                                    const std::vector<std::size_t>& which) {
    std::vector<PointVotes> votes(which.size());
    if (which.empty()) return votes;
    Timer votes_timer;
    std::vector<std::size_t> first_frames, other_frames;
    neighbours(frame, first_frames, other_frames);
    first_frames.insert(first_frames.end(), other_frames.begin(), other_frames.end());
    std::vector<VoteScan> scans;
    for (const std::size_t f : first_frames) scans.push_back({&image(f), dataset_.frame(f).T_W_L.inverse()});
    const Isometry3d& T_W_L = dataset_.frame(frame).T_W_L;
    std::vector<Vec3f> points_W;
    points_W.reserve(which.size());
    for (const std::size_t i : which) points_W.push_back((T_W_L * points_L[i].cast<double>()).cast<float>());
    dynamicByFreeSpace(points_W, scans, {}, config_.votes, nullptr, &votes);
    stats_.votes_s += votes_timer.elapsedSeconds();
    return votes;
}

ScanObjects DynamicDetector::objectsOf(std::size_t frame, const std::vector<Vec3f>& points_L,
                                       const std::vector<std::uint8_t>& dynamic,
                                       const std::vector<PointVotes>& votes) const {
    const Isometry3d& T_W_L = dataset_.frame(frame).T_W_L;
    ScanObjects objects = findScanObjects(points_L, dynamic, T_W_L, config_.objects);
    std::vector<std::uint8_t> kept(points_L.size(), 0);
    for (std::size_t i = 0; i < points_L.size(); ++i) {
        const std::int32_t c = objects.cluster[i];
        if (c >= 0 && !dynamic[i] && keptByVotes(votes[i], config_.object_keep_hits)) {
            kept[i] = 1;
            ++objects.clusters[static_cast<std::size_t>(c)].static_points;
        }
    }
    leaveOutColumns(points_L, T_W_L, kept, objects);
    return objects;
}

void DynamicDetector::objectLevel(std::size_t frame, const std::vector<Vec3f>& points_L,
                                  const std::vector<PointVotes>& point_votes, std::vector<std::uint8_t>& dynamic) {
    // 1. This scan's objects, and which are moving: by their own points, or as the
    //    continuation of a moving track over the scans before.
    const std::size_t r = rank_.at(frame);
    replayHistory(r);
    const ScanObjects objects = objectsOf(frame, points_L, dynamic, point_votes);
    objects_[r] = objects.clusters;
    std::vector<const std::vector<ScanCluster>*> window;
    for (auto it = objects_.begin(); it != objects_.end() && it->first <= r; ++it) window.push_back(&it->second);
    std::vector<TrackBox> boxes;
    std::vector<std::uint8_t> joined;
    const std::vector<std::uint8_t> moving = movingObjects(window, config_.tracks, &boxes, &joined);
    stats_.objects += objects.clusters.size();
    stats_.objects_moving += static_cast<std::size_t>(std::count(moving.begin(), moving.end(), 1));

    // 2. Candidates, points not moving by their own test that may go with a mover: the other
    //    points of moving objects, the ground band under them (wheels), and the points of any
    //    other object next to a point moving by its own test (a mover that joined a static
    //    object, such as a pedestrian passing a parked car).
    const auto voxel_m = static_cast<float>(config_.objects.voxel_m);
    const std::vector<std::uint8_t> low = lowPointsUnder(points_L, objects, moving, voxel_m);
    const std::vector<std::uint8_t> near =
        config_.grow_voxels > 0 ? pointsNearDynamic(points_L, dynamic, objects, moving, voxel_m, config_.grow_voxels,
                                            kGrowSeedPoints, config_.grow_down_voxels)
                                : std::vector<std::uint8_t>(points_L.size(), 0);
    std::vector<std::size_t> candidates;
    for (std::size_t i = 0; i < points_L.size(); ++i) {
        const std::int32_t c = objects.cluster[i];
        if (!dynamic[i] && (low[i] || near[i] || (c >= 0 && moving[static_cast<std::size_t>(c)]))) {
            candidates.push_back(i);
        }
    }

    // 3. Static evidence over every scan of the window: a point that scans hit and none saw
    //    through stays. Votes are asked once per point (vote_of: its index in `votes`).
    const int keep_hits = config_.object_keep_hits;
    std::vector<PointVotes> votes;
    std::vector<std::int32_t> vote_of(points_L.size(), -1);
    auto askVotes = [&](const std::vector<std::size_t>& which) {
        std::vector<std::size_t> fresh;
        for (const std::size_t i : which) {
            if (vote_of[i] < 0) fresh.push_back(i);
        }
        if (keep_hits <= 0 || fresh.empty()) return;
        const std::vector<PointVotes> more = windowVotes(frame, points_L, fresh);
        for (std::size_t k = 0; k < fresh.size(); ++k) vote_of[fresh[k]] = static_cast<std::int32_t>(votes.size() + k);
        votes.insert(votes.end(), more.begin(), more.end());
    };
    auto kept = [&](std::size_t i) {
        if (vote_of[i] < 0) return false;
        return keptByVotes(votes[static_cast<std::size_t>(vote_of[i])], keep_hits);
    };
    // Objects whose points among `which` are mostly kept (object_static_share).
    auto mostlyKept = [&](const std::vector<std::size_t>& which) {
        std::vector<std::array<std::size_t, 2>> share(objects.clusters.size(), {0, 0});  // kept, all
        for (const std::size_t i : which) {
            auto& sh = share[static_cast<std::size_t>(objects.cluster[i])];
            sh[0] += kept(i) ? 1 : 0;
            ++sh[1];
        }
        std::vector<std::uint8_t> out(share.size(), 0);
        for (std::size_t c = 0; c < share.size(); ++c) {
            out[c] = keep_hits > 0 && share[c][1] > 0 &&
                     static_cast<double>(share[c][0]) >= config_.object_static_share * static_cast<double>(share[c][1]);
        }
        return out;
    };
    askVotes(candidates);

    // 4. An object moving by its track alone whose candidates are mostly kept is a static
    //    object the track wrongly continued: it stays whole.
    std::vector<std::size_t> continued;
    for (const std::size_t i : candidates) {
        const std::int32_t c = objects.cluster[i];
        if (c >= 0 && moving[static_cast<std::size_t>(c)] && !objects.clusters[static_cast<std::size_t>(c)].confirmed &&
            !joined[static_cast<std::size_t>(c)]) {
            continued.push_back(i);
        }
    }
    const std::vector<std::uint8_t> stays = mostlyKept(continued);
    stats_.objects_kept_static += static_cast<std::size_t>(std::count(stays.begin(), stays.end(), 1));
    auto staysWhole = [&](std::size_t i) {
        const std::int32_t c = objects.cluster[i];
        return c >= 0 && stays[static_cast<std::size_t>(c)];
    };

    // 5. The objects' points inside the box of a moving track (the whole object where the
    //    track predicts it, continued or not: an object seen in part, or joined to a static
    //    one at a kerb) go, without a check per point: the sides of a vehicle slide along their
    //    own planes, so the scans just before hit some of them. But an object whose points in
    //    the boxes are mostly kept by static evidence is a static one the box's margin brushes
    //    (a parked car a moving one passes): those stay. Unless the object moves by its own
    //    points: then its points inside a box go, and those in the margin unless kept (a van
    //    crossing sideways is its long side, which slides along itself: most of it is hit).
    if (!boxes.empty()) {
        const Isometry3d& T_W_L = dataset_.frame(frame).T_W_L;
        const double grow = config_.objects.voxel_m;
        stats_.objects_tracked += boxes.size();
        // A point can be in a box only if its object's world box meets the box: per object,
        // the boxes to ask (most objects meet none, and their points are not transformed).
        std::vector<std::vector<std::uint32_t>> boxes_of(objects.clusters.size());
        for (std::size_t c = 0; c < objects.clusters.size(); ++c) {
            const ScanCluster& sc = objects.clusters[c];
            for (std::size_t k = 0; k < boxes.size(); ++k) {
                const TrackBox& b = boxes[k];
                if ((sc.max_W.array() >= b.min_W.array() - grow).all() && (sc.min_W.array() <= b.max_W.array() + grow).all()) {
                    boxes_of[c].push_back(static_cast<std::uint32_t>(k));
                }
            }
        }
        std::vector<std::size_t> in_box;
        std::vector<std::uint8_t> inner(points_L.size(), 0);
        for (std::size_t i = 0; i < points_L.size(); ++i) {
            if (dynamic[i] || objects.cluster[i] < 0 || staysWhole(i)) continue;
            if (joined[static_cast<std::size_t>(objects.cluster[i])]) continue;
            const std::vector<std::uint32_t>& near_boxes = boxes_of[static_cast<std::size_t>(objects.cluster[i])];
            if (near_boxes.empty()) continue;
            const Vec3d p = T_W_L * points_L[i].cast<double>();
            bool in_grown = false;
            for (const std::uint32_t k : near_boxes) {
                in_grown = in_grown || inBox(p, boxes[k], grow);
                inner[i] = inner[i] || inBox(p, boxes[k], 0.0);
            }
            if (in_grown) in_box.push_back(i);
        }
        askVotes(in_box);
        const std::vector<std::uint8_t> brushed = mostlyKept(in_box);
        for (const std::size_t i : in_box) {
            const auto c = static_cast<std::size_t>(objects.cluster[i]);
            const bool confirmed_goes = objects.clusters[c].confirmed && (inner[i] || !kept(i));
            if (brushed[c] && !confirmed_goes) continue;
            dynamic[i] = 1;
            ++stats_.points_object;
        }
    }

    // 6. Joined objects (a mover joined to a static one, larger than its track's object): the
    //    points not kept that connect, through points not kept, to the track's box or to points
    //    moving by their own test are the mover's; the rest is the static object's.
    stats_.points_object += takeJoinedMovers(points_L, objects, joined, boxes, dataset_.frame(frame).T_W_L,
                                             config_.objects.voxel_m, kept, dynamic);

    // 7. The other candidates that static evidence does not keep go.
    for (const std::size_t i : candidates) {
        if (dynamic[i] || staysWhole(i)) continue;  // in a track's box, or a static object
        const std::int32_t cj = objects.cluster[i];
        if (cj >= 0 && joined[static_cast<std::size_t>(cj)]) continue;  // split in 6
        if (kept(i)) {
            ++stats_.points_kept_by_hits;
            continue;
        }
        dynamic[i] = 1;
        const std::int32_t c = objects.cluster[i];
        const bool with_mover = low[i] || (c >= 0 && moving[static_cast<std::size_t>(c)]);
        ++(with_mover ? stats_.points_object : stats_.points_grown);
    }
}

std::vector<std::uint8_t> DynamicDetector::detect(std::size_t frame,
                                                  const std::vector<Vec3f>& points_L,
                                                  const std::vector<std::uint32_t>& index,
                                                  std::size_t points_in_file) {
    Timer timer;
    ++stats_.scans;
    stats_.points_in += points_L.size();

    // Free space: the scans around this one in time.
    std::vector<PointVotes> votes;
    std::vector<std::uint8_t> dynamic = freeSpace(frame, points_L, votes);
    for (const std::uint8_t d : dynamic) stats_.points_free_space += d;

    // Objects: whole objects enough of whose points are moving, and the continuations of the
    // tracks of such objects over the scans before.
    if (config_.objects.enabled) objectLevel(frame, points_L, votes, dynamic);

    // Labels: SemanticKITTI's moving classes.
    if (config_.use_labels) {
        if (const auto label_path = dataset_.lidarLabelPath(frame)) {
            const LidarLabels labels = readLidarLabels(*label_path);
            checkLabelCount(labels.size(), *label_path, points_in_file, dataset_.frame(frame).scan_path);
            ++stats_.scans_with_labels;
            for (std::size_t i = 0; i < points_L.size(); ++i) {
                if (!dynamic[i] && isMovingClass(LidarLabels::classOf(labels.raw[index[i]]))) {
                    dynamic[i] = 1;
                    ++stats_.points_label;
                }
            }
        }
    }
    for (const std::uint8_t d : dynamic) stats_.points_dynamic += d;
    stats_.seconds += timer.elapsedSeconds();
    return dynamic;
}

}  // namespace vdbmap
