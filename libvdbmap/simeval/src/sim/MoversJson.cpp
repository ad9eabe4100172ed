// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/sim/MoversJson.h"

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "vdbmap/Error.h"
#include "vdbmap/io/AtomicFile.h"

namespace vdbmap {

namespace {

nlohmann::json moverVec3(const Vec3f& v) { return {v.x(), v.y(), v.z()}; }

Vec3f readMoverVec3(const nlohmann::json& j) {
    if (!j.is_array() || j.size() != 3) throw std::invalid_argument("expected 3 numbers");
    return Vec3f(j[0].get<float>(), j[1].get<float>(), j[2].get<float>());
}

nlohmann::json moverPose12(const Isometry3d& T) {
    nlohmann::json out = nlohmann::json::array();
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 4; ++c) out.push_back(T.matrix()(r, c));
    }
    return out;
}

Isometry3d readMoverPose12(const nlohmann::json& j) {
    if (!j.is_array() || j.size() != 12) throw std::invalid_argument("a pose needs 12 numbers");
    Isometry3d T = Isometry3d::Identity();
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 4; ++c) T.matrix()(r, c) = j[4 * r + c].get<double>();
    }
    return T;
}

}  // namespace

void writeMoversJson(const std::filesystem::path& path, const MoversFile& file) {
    nlohmann::json j;
    j["frames"] = file.times_s.size();
    j["times_s"] = file.times_s;
    j["pose_format"] = "T_W_O row-major 3x4 [R | t]; O: x forward, y left, z up, on the ground";
    j["movers"] = nlohmann::json::array();
    for (const Mover& m : file.movers) {
        nlohmann::json jm;
        jm["name"] = m.name;
        jm["kind"] = m.kind;
        jm["class_id"] = m.class_id;
        jm["semantickitti_id"] = movingSemanticKittiId(m.class_id);
        jm["instance_id"] = m.instance_id;
        jm["box_centre_O"] = moverVec3(m.boxCentre_O());
        jm["box_size_m"] = moverVec3(2.0f * m.boxHalf_m());
        jm["parts"] = nlohmann::json::array();
        for (const MoverPart& p : m.parts) {
            jm["parts"].push_back({{"centre_O", moverVec3(p.centre_O)},
                                   {"size_m", moverVec3(2.0f * p.half_m)},
                                   {"texture", p.texture}});
        }
        jm["T_W_O"] = nlohmann::json::array();
        for (const Isometry3d& T : m.T_W_O) jm["T_W_O"].push_back(moverPose12(T));
        j["movers"].push_back(jm);
    }
    writeFileAtomically(path, j.dump(1) + "\n");
}

MoversFile readMoversJson(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) throw IoError(path.string() + ": cannot open");
    MoversFile out;
    std::string key = "(file)";
    try {
        const nlohmann::json j = nlohmann::json::parse(in);
        key = "times_s";
        out.times_s = j.at("times_s").get<std::vector<double>>();
        key = "movers";
        for (const auto& jm : j.at("movers")) {
            Mover m;
            key = "movers[].name";
            m.name = jm.at("name").get<std::string>();
            key = "movers[" + m.name + "]";
            m.kind = jm.at("kind").get<std::string>();
            m.class_id = jm.at("class_id").get<std::uint8_t>();
            m.instance_id = jm.at("instance_id").get<std::uint16_t>();
            for (const auto& jp : jm.at("parts")) {
                m.parts.push_back(MoverPart{readMoverVec3(jp.at("centre_O")),
                                            readMoverVec3(jp.at("size_m")) / 2.0f,
                                            jp.value("texture", std::string())});
            }
            for (const auto& jt : jm.at("T_W_O")) m.T_W_O.push_back(readMoverPose12(jt));
            if (m.T_W_O.size() != out.times_s.size()) {
                throw std::invalid_argument(std::to_string(m.T_W_O.size()) + " poses but " +
                                            std::to_string(out.times_s.size()) + " frames");
            }
            out.movers.push_back(std::move(m));
        }
    } catch (const std::exception& e) {
        throw IoError(path.string() + ": bad key '" + key + "': " + e.what());
    }
    return out;
}

}  // namespace vdbmap
