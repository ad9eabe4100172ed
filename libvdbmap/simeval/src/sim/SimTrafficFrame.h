// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "vdbmap/io/LidarLabels.h"
#include "vdbmap/render/Raycaster.h"
#include "vdbmap/sim/LidarModel.h"
#include "vdbmap/sim/SimScene.h"
#include "vdbmap/sim/Traffic.h"

namespace vdbmap {

/// The scene of one frame: the static scene with the movers at their pose of that frame
/// (time-dependent geometry: every frame is ray cast against its own scene).
struct TrafficFrame {
    SimScene scene;                        ///< static faces first, then the movers'
    std::unique_ptr<Raycaster> raycaster;  ///< over `scene`
    std::size_t static_faces = 0;          ///< faces [0, static_faces) are the static scene's
    std::vector<std::uint16_t> instance_of_mover_face;  ///< face - static_faces -> instance id

    /// Instance id of the mover that `face` belongs to, 0 for a static face.
    std::uint16_t instanceOf(std::uint32_t face) const {
        return face < static_faces ? 0 : instance_of_mover_face[face - static_faces];
    }
};

/// The movers of a sequence with their textures, made once.
class TrafficFrames {
public:
    TrafficFrames(std::vector<Mover> movers, std::uint64_t seed);
    const std::vector<Mover>& movers() const { return movers_; }
    /// The scene of frame `f`: `static_scene` plus every mover at T_W_O[f].
    TrafficFrame frame(const SimScene& static_scene, std::size_t f) const;

private:
    std::vector<Mover> movers_;
    std::vector<std::vector<cv::Mat>> textures_;
};

/// Marks the moving points of `scan` (cast against `frame`) in `labels`: each gets its
/// mover's instance id in the upper 16 bits and, if its class is still the mover's (label
/// noise may have changed it), SemanticKITTI's moving class (252 moving-car, 254
/// moving-person, 258 moving-truck) when `semantickitti_ids`, else the mover's own class id
/// (the default label set has no moving classes).
void markMovingPoints(LidarLabels& labels, const LidarScan& scan, const TrafficFrame& frame,
                      const std::vector<Mover>& movers, bool semantickitti_ids);

}  // namespace vdbmap
