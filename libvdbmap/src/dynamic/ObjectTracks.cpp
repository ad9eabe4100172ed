// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/dynamic/ObjectTracks.h"

#include <algorithm>
#include <tuple>

namespace vdbmap {

namespace {

struct Track {
    Vec3d last = Vec3d::Zero();      ///< centroid of its last object (W)
    Vec3d velocity = Vec3d::Zero();  ///< per scan
    bool has_velocity = false;
    int missed = 0;                  ///< scans since its last object
    int since_confirmed = 0;         ///< scans since its last confirmed object
    int confirmations = 0;
    float extent_m = 0.0f;
    /// The object's whole box: its last object's box when that object had the track's size,
    /// else the whole box before it moved by the velocity (a part of the object seen, or the
    /// object joined to a static one).
    Vec3d min_W = Vec3d::Zero(), max_W = Vec3d::Zero();
    Vec3d centre() const { return 0.5 * (min_W + max_W); }
};

/// True if an object of horizontal extent `a_m` can be the whole of one of extent `b_m`:
/// within 20 % of the larger, or 0.3 m.
bool sameSize(float a_m, float b_m) {
    return std::abs(a_m - b_m) <= std::max(0.2f * std::max(a_m, b_m), 0.3f);
}

/// Distance between two boxes (0 if they overlap).
double boxGap(const Vec3d& a_min, const Vec3d& a_max, const Vec3d& b_min, const Vec3d& b_max) {
    const Vec3d gap = (a_min - b_max).cwiseMax(b_min - a_max).cwiseMax(Vec3d::Zero());
    return gap.norm();
}

/// The step of an object's box between two scans, per axis: where both faces moved the same
/// way, the smaller of their two steps; else none. A whole object that moves moves both faces;
/// a face that moves alone is the view changing (more or less of the object seen, a part
/// joined or lost), which the step of the box centres would take for motion: on `--seed 4`'s
/// street the crossing van's near face grew 1.3 m toward the sensor in one scan and its track
/// then drifted 0.3 m per scan away from it.
Vec3d boxStep(const Vec3d& from_min, const Vec3d& from_max, const Vec3d& to_min, const Vec3d& to_max) {
    Vec3d step = Vec3d::Zero();
    for (int a = 0; a < 3; ++a) {
        const double lo = to_min[a] - from_min[a], hi = to_max[a] - from_max[a];
        if (lo * hi > 0.0) step[a] = std::abs(lo) < std::abs(hi) ? lo : hi;
    }
    return step;
}

/// Whether an object not moving by its own points is static by evidence: at least
/// static_share of its points were hit by scans and seen through by none. Such an object takes
/// no track and is no part (a parked car next to a van).
bool staticByEvidence(const ScanCluster& o, const ObjectTrackConfig& config) {
    return !o.confirmed && o.points > 0 && static_cast<double>(o.static_points) >= config.static_share * static_cast<double>(o.points);
}

/// Whether a track makes objects moving: confirmed often enough, recently enough.
bool isMoving(const Track& tr, const ObjectTrackConfig& config) {
    return tr.confirmations >= config.min_confirmations && tr.since_confirmed <= config.frames;
}

/// Parts (ObjectTrackConfig::part_gate_m): the objects of the last scan that no moving track
/// took, within part_gate_m of the box of a moving track where it is now (matched: its updated
/// box; coasting: moved on by its velocity), no larger than the track's object or than
/// part_max_extent_m, are moving. A part is never larger than the whole, so an object joined
/// to a static one (a car at the kerb) is not made moving here. An object a track that is not
/// moving took can be a part: that track says nothing of it (the body of `--seed 3`'s car ahead,
/// seen from behind, kept a track of its own that never confirmed, in the drive's last frames).
void markParts(const std::vector<ScanCluster>& objects, const std::vector<Track>& tracks,
               const std::vector<char>& track_used, const ObjectTrackConfig& config, std::vector<std::uint8_t>& moving) {
    if (config.part_gate_m < 0.0) return;
    for (std::size_t t = 0; t < tracks.size(); ++t) {
        const Track& tr = tracks[t];
        if (!tr.has_velocity || !isMoving(tr, config)) continue;
        if (!track_used[t] && tr.missed + 1 > config.max_missed) continue;
        const Vec3d shift = track_used[t] ? Vec3d::Zero() : Vec3d(static_cast<double>(tr.missed + 1) * tr.velocity);
        for (std::size_t i = 0; i < objects.size(); ++i) {
            const ScanCluster& o = objects[i];
            if (moving[i] || !o.compact || staticByEvidence(o, config)) continue;
            const bool part = o.extent_m <= tr.extent_m || sameSize(o.extent_m, tr.extent_m) ||
                              o.extent_m <= static_cast<float>(config.part_max_extent_m);
            if (!part) continue;
            if (boxGap(o.min_W, o.max_W, tr.min_W + shift, tr.max_W + shift) <= config.part_gate_m) moving[i] = 1;
        }
    }
}

}  // namespace

std::vector<std::uint8_t> movingObjects(const std::vector<const std::vector<ScanCluster>*>& window,
                                        const ObjectTrackConfig& config,
                                        std::vector<TrackBox>* boxes,
                                        std::vector<std::uint8_t>* joined) {
    if (boxes != nullptr) boxes->clear();
    if (window.empty()) return {};
    const std::vector<ScanCluster>& current = *window.back();
    std::vector<std::uint8_t> moving(current.size(), 0);
    if (joined != nullptr) joined->assign(current.size(), 0);
    for (std::size_t i = 0; i < current.size(); ++i) moving[i] = current[i].confirmed ? 1 : 0;
    if (config.frames <= 0) return moving;

    std::vector<Track> tracks;
    for (std::size_t w = 0; w < window.size(); ++w) {
        const std::vector<ScanCluster>& objects = *window[w];
        const bool last_scan = w + 1 == window.size();
        // Candidate pairs within the gate: the object's box within gate_m of the box the track
        // predicts (a part of the object seen has another centroid, but lies in that box),
        // nearest box first, then nearest predicted centroid (ties by track, then object: the
        // result does not depend on anything but the window).
        std::vector<std::tuple<double, double, std::size_t, std::size_t>> pairs;
        for (std::size_t t = 0; t < tracks.size(); ++t) {
            const Track& tr = tracks[t];
            const double steps = static_cast<double>(tr.missed + 1);
            const Vec3d shift = tr.has_velocity ? Vec3d(steps * tr.velocity) : Vec3d::Zero();
            const Vec3d predicted = tr.last + shift;
            const double gate = tr.has_velocity ? config.gate_m : config.max_step_m * steps;
            for (std::size_t i = 0; i < objects.size(); ++i) {
                const ScanCluster& o = objects[i];
                if (!o.confirmed && (!o.compact || o.extent_m > 2.0f * tr.extent_m + 1.0f)) continue;
                if (sameSize(o.extent_m, tr.extent_m) && staticByEvidence(o, config)) continue;
                const double gap = boxGap(o.min_W, o.max_W, tr.min_W + shift, tr.max_W + shift);
                if (gap <= gate) pairs.emplace_back(gap, (o.centroid_W - predicted).norm(), t, i);
            }
        }
        std::sort(pairs.begin(), pairs.end());
        std::vector<char> track_used(tracks.size(), 0), object_used(objects.size(), 0);
        for (const auto& [gap, d, t, i] : pairs) {
            if (track_used[t] || object_used[i]) continue;
            track_used[t] = object_used[i] = 1;
            Track& tr = tracks[t];
            const ScanCluster& o = objects[i];
            const double steps = static_cast<double>(tr.missed + 1);
            const bool same = sameSize(o.extent_m, tr.extent_m);
            const bool larger = !same && o.extent_m > tr.extent_m;
            if (same) {
                // The whole object again: its box moved by the step, and becomes the track's.
                const Vec3d step = boxStep(tr.min_W, tr.max_W, o.min_W, o.max_W) / steps;
                tr.velocity = tr.has_velocity ? Vec3d(0.5 * (tr.velocity + step)) : step;
                tr.has_velocity = true;
                tr.min_W = o.min_W;
                tr.max_W = o.max_W;
                tr.extent_m = o.extent_m;
            } else {
                // A part of it, or it joined a static object: the whole box moves on by the
                // velocity (by the centroid's step while the track has none).
                if (!tr.has_velocity) {
                    tr.velocity = (o.centroid_W - tr.last) / steps;
                    tr.has_velocity = true;
                }
                tr.min_W += steps * tr.velocity;
                tr.max_W += steps * tr.velocity;
                // A part that reaches out of the box (the van's end face once the sensor is
                // beside it, behind the long side the box was made of) grows the box, as far as
                // the box stays the object's size: it was a view of the object's near faces.
                if (!larger) {
                    const Vec3d grown_min = tr.min_W.cwiseMin(o.min_W), grown_max = tr.max_W.cwiseMax(o.max_W);
                    if (sameSize(static_cast<float>((grown_max - grown_min).norm()), static_cast<float>((tr.max_W - tr.min_W).norm()))) {
                        tr.min_W = grown_min;
                        tr.max_W = grown_max;
                    }
                }
            }
            tr.last = o.centroid_W;
            tr.missed = 0;
            if (o.confirmed) {
                tr.since_confirmed = 0;
                ++tr.confirmations;
            } else {
                ++tr.since_confirmed;
            }
            if (last_scan && isMoving(tr, config)) {
                moving[i] = 1;
                if (joined != nullptr && larger && !o.confirmed) (*joined)[i] = 1;
                if (boxes != nullptr) boxes->push_back({tr.min_W, tr.max_W});
            }
        }
        if (last_scan) markParts(objects, tracks, track_used, config, moving);
        // Unmatched tracks coast; those lost or no longer moving end.
        std::vector<Track> kept;
        for (std::size_t t = 0; t < tracks.size(); ++t) {
            Track tr = tracks[t];
            if (!track_used[t]) {
                ++tr.missed;
                ++tr.since_confirmed;
                if (last_scan && boxes != nullptr && tr.has_velocity && tr.missed <= config.max_missed &&
                    isMoving(tr, config)) {
                    const Vec3d shift = static_cast<double>(tr.missed) * tr.velocity;
                    boxes->push_back({tr.min_W + shift, tr.max_W + shift});
                }
            }
            if (tr.missed <= config.max_missed && tr.since_confirmed <= config.frames) kept.push_back(tr);
        }
        tracks = std::move(kept);
        // Confirmed objects no track took start tracks.
        for (std::size_t i = 0; i < objects.size(); ++i) {
            if (object_used[i] || !objects[i].confirmed) continue;
            Track tr;
            tr.last = objects[i].centroid_W;
            tr.confirmations = 1;
            tr.extent_m = objects[i].extent_m;
            tr.min_W = objects[i].min_W;
            tr.max_W = objects[i].max_W;
            tracks.push_back(tr);
        }
    }
    return moving;
}

}  // namespace vdbmap
