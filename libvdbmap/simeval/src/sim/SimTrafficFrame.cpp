// SPDX-License-Identifier: Apache-2.0
#include "sim/SimTrafficFrame.h"

#include "sim/SimLidarLabels.h"
#include "vdbmap/Error.h"

namespace vdbmap {

TrafficFrames::TrafficFrames(std::vector<Mover> movers, std::uint64_t seed)
    : movers_(std::move(movers)) {
    for (const Mover& m : movers_) textures_.push_back(moverTextures(m, seed));
}

TrafficFrame TrafficFrames::frame(const SimScene& static_scene, std::size_t f) const {
    TrafficFrame out;
    out.scene = static_scene;
    out.static_faces = static_scene.numTriangles();
    for (std::size_t i = 0; i < movers_.size(); ++i) {
        const Mover& m = movers_[i];
        if (f >= m.T_W_O.size()) {
            throw InvalidInput("TrafficFrames: " + m.name + " has no pose for frame " +
                               std::to_string(f));
        }
        addMoverToScene(out.scene, m, m.T_W_O[f], textures_[i]);
        out.instance_of_mover_face.resize(out.scene.numTriangles() - out.static_faces,
                                          m.instance_id);
    }
    out.raycaster =
        std::make_unique<Raycaster>(out.scene.mesh.positions, out.scene.triangleIndices());
    return out;
}

void markMovingPoints(LidarLabels& labels, const LidarScan& scan, const TrafficFrame& frame,
                      const std::vector<Mover>& movers, bool semantickitti_ids) {
    if (labels.raw.size() != scan.faces.size()) {
        throw InvalidInput("markMovingPoints: " + std::to_string(labels.raw.size()) +
                           " labels for " + std::to_string(scan.faces.size()) + " points");
    }
    for (std::size_t i = 0; i < labels.raw.size(); ++i) {
        const std::uint16_t instance = frame.instanceOf(scan.faces[i]);
        if (instance == 0) continue;
        const Mover& m = movers.at(instance - 1);
        std::uint32_t cls = LidarLabels::classOf(labels.raw[i]);
        const std::uint32_t own = semantickitti_ids ? semanticKittiId(m.class_id) : m.class_id;
        if (cls == own) cls = semantickitti_ids ? movingSemanticKittiId(m.class_id) : m.class_id;
        labels.raw[i] = (static_cast<std::uint32_t>(instance) << 16) | cls;
    }
}

}  // namespace vdbmap
