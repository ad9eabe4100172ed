// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/sim/SimScene.h"

namespace vdbmap {

class Raycaster;
struct SceneSetup;

/// One box of a mover's body, in the mover frame O (x forward, y left, z up, origin on the
/// ground under the mover's centre).
struct MoverPart {
    Vec3f centre_O = Vec3f::Zero();
    Vec3f half_m = Vec3f::Zero();  ///< half extents along x, y, z of O
    std::string texture;           ///< proceduralTexture() kind
};

/// A moving object of the simulated traffic: rigid boxes moved by a pose per frame.
struct Mover {
    std::string name;               ///< "car_0", "van", "pedestrian_1"
    std::string kind;               ///< "car", "van" or "pedestrian"
    std::uint8_t class_id = 13;     ///< docs/DATA.md id: 13 car, 14 truck (the van), 11 person
    std::uint16_t instance_id = 0;  ///< 1 + the mover's index: its LiDAR points' instance id
    std::vector<MoverPart> parts;
    std::vector<Isometry3d> T_W_O;  ///< per frame; in the scene frame S until moved into W

    /// The axis-aligned bounding box of the parts in O: centre and half extents.
    Vec3f boxCentre_O() const;
    Vec3f boxHalf_m() const;
};

/// SemanticKITTI's moving class of our class id: car 13 -> 252 moving-car, person 11 -> 254
/// moving-person, truck 14 -> 258 moving-truck, anything else -> 259 moving-other-vehicle.
std::uint16_t movingSemanticKittiId(std::uint8_t class_id);

/// The traffic of the street scene (scene frame S, before the sequence moves it into W), one
/// pose per vehicle pose of `setup`: `cars` cars (car_0 creeps ahead of the ego vehicle in its
/// lane, the others come the other way in the left lane), a van that crosses the street ahead
/// and three pedestrians (one walking along each sidewalk, one crossing the right half of the
/// road behind the ego vehicle). The motion is laid out in the drive's normalised time
/// u = f / (frames - 1), so that no mover meets the ego vehicle or another mover whatever
/// the frame count; `static_S` (the static scene in S) moves the van and the pedestrians
/// along the street until their paths are clear of parked cars, poles and trees. Laid out
/// for the street's default length (60 m) and longer. Deterministic for `seed`.
/// `cars` = 0 returns no movers.
std::vector<Mover> buildStreetTraffic(const SceneSetup& setup, const Raycaster& static_S,
                                      std::size_t cars, std::uint64_t seed);

/// The textures of `mover`'s parts (proceduralTexture of each part's kind for `seed`).
std::vector<cv::Mat> moverTextures(const Mover& mover, std::uint64_t seed);

/// Appends `mover` at pose `T_W_O` to `scene`: its parts as closed boxes, a material per part
/// with `part_textures[k]` (moverTextures), every face with the mover's class id. Throws
/// InvalidInput if there is not one texture per part.
void addMoverToScene(SimScene& scene, const Mover& mover, const Isometry3d& T_W_O,
                     const std::vector<cv::Mat>& part_textures);

}  // namespace vdbmap
