// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <vector>

#include "vdbmap/dynamic/ScanObjects.h"

namespace vdbmap {

/// Tracking of moving objects over time (docs/dynamic.md, "Tracks"): an object seen moving
/// earlier stays moving when the free-space test cannot tell any more (the last frames of a
/// drive, where no later scan sees the places it leaves).
struct ObjectTrackConfig {
    /// A track stays moving this many scans after the last scan in which its object was
    /// confirmed moving by its own points; 0 = no tracking (each scan's objects alone).
    int frames = 10;
    /// Association: an object joins the track whose predicted centroid (last centroid + velocity
    /// per scan) is nearest, within gate_m; a track without a velocity yet (one object so far)
    /// takes objects within max_step_m of its last centroid (the fastest mover's step per scan).
    double gate_m = 1.5;
    double max_step_m = 4.0;
    /// A track makes objects moving only after this many confirmed objects.
    int min_confirmations = 2;
    /// A track not matched in more than this many consecutive scans ends.
    int max_missed = 3;
    /// Parts: an object of the scan being decided that no track took, within part_gate_m of
    /// the box of a moving track (where the track predicts its object) and no larger than
    /// that object (sameSize) or than part_max_extent_m, is a part of the mover: moving. A car
    /// seen from behind is several objects (its cabin, its body, a strip under it), and the one
    /// to one association continues one of them. part_gate_m < 0 = off.
    double part_gate_m = 0.5;
    double part_max_extent_m = 2.5;
    /// An object not moving by its own points, of the track's size, of which at least this share
    /// is static by evidence (ScanCluster::static_points) continues no track: a parked car that
    /// a van stopped beside is not the van (the nearer centroid took the van's track to it on
    /// `--seed 4`'s street). Above 1 = off.
    double static_share = 0.5;
};

/// Scans of history a decision needs: the tracker runs over the window of the scan and the
/// trackHistory() scans before it, so that the decision depends on those scans alone (tiled,
/// untiled and distributed runs decide the same).
inline int trackHistory(const ObjectTrackConfig& c) { return c.frames > 0 ? c.frames + 2 : 0; }

/// `window`: the objects of consecutive scans in time order, the scan being decided last. Runs
/// a fresh tracker over the window and returns, for each object of the last scan, 1 if it is
/// moving: confirmed itself, or (compact and at most twice the track's last extent + 1 m) the
/// continuation of a track with at least min_confirmations confirmed objects, the last of them
/// at most `frames` scans before.
/// - Association, greedy one to one: an object continues the track whose predicted box (the
///   track's box moved by its velocity) is nearest to the object's box, within gate_m (a track
///   without a velocity yet: max_step_m per scan), ties by the distance to the predicted
///   centroid. A part of an object lies in the whole object's box, though its centroid is
///   elsewhere.
/// - The track's box is the whole object's: an object of the track's size (sameSize) replaces
///   it and gives the velocity (the step of the box centres, averaged); a smaller object (a
///   part seen) or a larger one (joined to a static object) moves the old box by the velocity.
/// - Parts (part_gate_m): the other objects of the last scan near a moving track's box, no
///   larger than its object, are moving too.
/// `boxes` (may be null) gets the box (W) of each track moving at the last scan, continued or
/// not (its object joined a static one, or was not seen): what the track predicts the object
/// occupies. `joined` (may be null) gets, per object of the last scan, 1 for an object a moving
/// track continued that is larger than the track's object (the mover joined to a static one:
/// DynamicDetector splits it by the static evidence, moverOfJoined).
struct TrackBox {
    Vec3d min_W, max_W;
};
std::vector<std::uint8_t> movingObjects(const std::vector<const std::vector<ScanCluster>*>& window,
                                        const ObjectTrackConfig& config,
                                        std::vector<TrackBox>* boxes = nullptr,
                                        std::vector<std::uint8_t>* joined = nullptr);

}  // namespace vdbmap
