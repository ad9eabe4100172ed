// SPDX-License-Identifier: Apache-2.0
// vdbmap-sim --traffic: the movers' points lie on their boxes at each frame's pose (closed
// form), the labels mark exactly them, gt/ stays the static world, and --traffic 0 writes
// what the simulator wrote before.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>

#include "vdbmap/Error.h"
#include "vdbmap/io/CalibIO.h"
#include "vdbmap/io/LidarLabels.h"
#include "vdbmap/io/PointCloudIO.h"
#include "vdbmap/io/PoseIO.h"
#include "vdbmap/sim/MoversJson.h"
#include "vdbmap/sim/SimLayout.h"
#include "vdbmap/sim/SimSequence.h"

using namespace vdbmap;
namespace fs = std::filesystem;

namespace {

std::string fileBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

SimOptions trafficOptions(std::size_t traffic) {
    SimOptions o;
    o.scene = "street";
    o.frames = 6;
    o.seed = 3;
    o.gt_views = 0;
    o.images = false;
    o.quiet = true;
    o.traffic = traffic;
    return o;
}

// Signed distance of p to the axis-aligned box (centre, half extents): < 0 inside.
float boxSignedDistance(const Vec3f& p, const Vec3f& centre, const Vec3f& half) {
    const Vec3f q = (p - centre).cwiseAbs() - half;
    const float outside = q.cwiseMax(0.0f).norm();
    const float inside = std::min(q.maxCoeff(), 0.0f);
    return outside + inside;
}

// Distance of p_O to the surface of the union of the mover's part boxes.
float distanceToParts(const Mover& m, const Vec3f& p_O) {
    float best = 1e9f;
    for (const MoverPart& part : m.parts) {
        best = std::min(best, std::abs(boxSignedDistance(p_O, part.centre_O, part.half_m)));
    }
    return best;
}

// Inside the mover's bounding box shrunk by 10 cm, and above its lowest 0.4 m (the ground and
// the kerb it may stand over are static and lie below).
bool insideCore(const Mover& m, const Vec3f& p_O) {
    Vec3f half = m.boxHalf_m() - Vec3f(0.1f, 0.1f, 0.0f);
    Vec3f centre = m.boxCentre_O();
    const float z0 = centre.z() - half.z() + 0.4f, z1 = centre.z() + half.z() - 0.1f;
    centre.z() = (z0 + z1) / 2;
    half.z() = (z1 - z0) / 2;
    return half.minCoeff() > 0 && boxSignedDistance(p_O, centre, half) < 0;
}

struct Sequence {
    std::vector<Isometry3d> T_W_L;
    MoversFile movers;
};

Sequence readSequence(const fs::path& dir) {
    Sequence s;
    const KittiCalib calib = readKittiCalib(dir / "calib.txt");
    for (const auto& T : readKittiPoses(dir / "poses.txt")) s.T_W_L.push_back(T * calib.Tr);
    s.movers = readMoversJson(dir / "gt" / "movers.json");
    return s;
}

// Footprints (x-y rectangles of the bounding boxes) of two movers overlap (separating axes).
bool footprintsOverlap(const Mover& a, const Isometry3d& Ta, const Mover& b, const Isometry3d& Tb) {
    const auto corners = [](const Mover& m, const Isometry3d& T) {
        std::vector<Eigen::Vector2d> out;
        const Vec3d c = m.boxCentre_O().cast<double>(), h = m.boxHalf_m().cast<double>();
        for (double sx : {-1.0, 1.0}) {
            for (double sy : {-1.0, 1.0}) {
                out.push_back((T * Vec3d(c.x() + sx * h.x(), c.y() + sy * h.y(), 0)).head<2>());
            }
        }
        return out;
    };
    const auto ca = corners(a, Ta), cb = corners(b, Tb);
    std::vector<Eigen::Vector2d> axes;
    for (const Isometry3d* T : {&Ta, &Tb}) {
        axes.push_back(T->linear().col(0).head<2>());
        axes.push_back(T->linear().col(1).head<2>());
    }
    for (const auto& axis : axes) {
        double a0 = 1e9, a1 = -1e9, b0 = 1e9, b1 = -1e9;
        for (const auto& p : ca) a0 = std::min(a0, p.dot(axis)), a1 = std::max(a1, p.dot(axis));
        for (const auto& p : cb) b0 = std::min(b0, p.dot(axis)), b1 = std::max(b1, p.dot(axis));
        if (a1 < b0 || b1 < a0) return false;
    }
    return true;
}

}  // namespace

TEST_CASE("Traffic: moving points lie on their mover's boxes and only they are labelled",
          "[sim][traffic]") {
    const fs::path dir = fs::temp_directory_path() / "vdbmap_simtraffic_points";
    fs::remove_all(dir);
    writeSimSequence(trafficOptions(3), dir);
    const Sequence seq = readSequence(dir);
    const auto& movers = seq.movers.movers;
    REQUIRE(movers.size() == 3 + 1 + 3);  // 3 cars, the van, 3 pedestrians
    REQUIRE(seq.movers.times_s.size() == 6);
    std::map<std::string, std::size_t> moving_by_kind;
    std::size_t static_points = 0;
    for (std::size_t f = 0; f < 6; ++f) {
        const std::string name = std::string("00000") + std::to_string(f);
        const PointCloud scan = readBin(dir / "velodyne" / (name + ".bin"));
        const LidarLabels labels = readLidarLabels(dir / "labels" / (name + ".label"));
        REQUIRE(labels.size() == scan.size());
        for (std::size_t i = 0; i < scan.size(); ++i) {
            const Vec3f p_W = (seq.T_W_L[f] * scan.points[i].cast<double>()).cast<float>();
            const std::uint16_t instance = LidarLabels::instanceOf(labels.raw[i]);
            const std::uint16_t cls = LidarLabels::classOf(labels.raw[i]);
            if (instance != 0) {
                REQUIRE(instance <= movers.size());
                const Mover& m = movers[instance - 1];
                const Vec3f p_O = (m.T_W_O[f].inverse() * p_W.cast<double>()).cast<float>();
                // Range noise is 2 cm along the ray: 5 sigma off the surface at most.
                INFO(m.name << " frame " << f << " point " << i);
                REQUIRE(distanceToParts(m, p_O) < 0.1f);
                const std::uint16_t expected = m.kind == "car" ? 252 : m.kind == "van" ? 258 : 254;
                REQUIRE(cls == expected);
                ++moving_by_kind[m.kind];
            } else {
                REQUIRE((cls < 252 || cls > 259));
                ++static_points;
                if (i % 7 != 0) continue;  // the box test on a sample of the static points
                for (const Mover& m : movers) {
                    const Vec3f p_O = (m.T_W_O[f].inverse() * p_W.cast<double>()).cast<float>();
                    INFO(m.name << " frame " << f << " static point " << i);
                    REQUIRE_FALSE(insideCore(m, p_O));
                }
            }
        }
    }
    CHECK(moving_by_kind["car"] > 1000);
    CHECK(moving_by_kind["van"] > 500);
    CHECK(moving_by_kind["pedestrian"] > 50);
    CHECK(static_points > 100 * moving_by_kind["pedestrian"]);
    fs::remove_all(dir);
}

TEST_CASE("Traffic: nobody meets the ego vehicle or another mover", "[sim][traffic]") {
    const fs::path dir = fs::temp_directory_path() / "vdbmap_simtraffic_choreo";
    fs::remove_all(dir);
    SimOptions o = trafficOptions(5);
    o.frames = 25;
    o.lidar_labels = false;
    writeSimSequence(o, dir);
    const Sequence seq = readSequence(dir);
    const auto& movers = seq.movers.movers;
    REQUIRE(movers.size() == 5 + 1 + 3);
    for (std::size_t f = 0; f < 25; ++f) {
        for (std::size_t a = 0; a < movers.size(); ++a) {
            // The LiDAR (1.73 m up) keeps its 1 m minimum range from every mover's box.
            const Vec3f l_O =
                (movers[a].T_W_O[f].inverse() * seq.T_W_L[f].translation()).cast<float>();
            INFO(movers[a].name << " frame " << f);
            CHECK(boxSignedDistance(l_O, movers[a].boxCentre_O(), movers[a].boxHalf_m()) > 1.0f);
            for (std::size_t b = a + 1; b < movers.size(); ++b) {
                INFO(movers[b].name);
                CHECK_FALSE(footprintsOverlap(movers[a], movers[a].T_W_O[f], movers[b],
                                              movers[b].T_W_O[f]));
            }
        }
    }
    // Every mover moves: more than 0.5 m from the first frame to the last.
    for (const Mover& m : movers) {
        INFO(m.name);
        CHECK((m.T_W_O.back().translation() - m.T_W_O.front().translation()).norm() > 0.5);
    }
    fs::remove_all(dir);
}

TEST_CASE("Traffic: gt/ is the static world, the same as without traffic", "[sim][traffic]") {
    const fs::path with = fs::temp_directory_path() / "vdbmap_simtraffic_with";
    const fs::path without = fs::temp_directory_path() / "vdbmap_simtraffic_without";
    fs::remove_all(with);
    fs::remove_all(without);
    writeSimSequence(trafficOptions(2), with);
    writeSimSequence(trafficOptions(0), without);
    // The static mesh and the calibration are the same files, byte for byte.
    for (const char* f :
         {"gt/mesh.ply", "gt/textured/mesh.obj", "calib.txt", "poses.txt", "times.txt"}) {
        INFO(f);
        CHECK(fileBytes(with / f) == fileBytes(without / f));
    }
    // Traffic 0 writes no movers and no traffic key.
    CHECK_FALSE(fs::exists(without / "gt" / "movers.json"));
    const auto info0 = nlohmann::json::parse(fileBytes(without / "gt" / "sim.json"));
    CHECK_FALSE(info0.contains("traffic"));
    const auto info2 = nlohmann::json::parse(fileBytes(with / "gt" / "sim.json"));
    CHECK(info2.at("traffic") == 2);
    // The observed points are static: none inside a mover at any frame.
    const Sequence seq = readSequence(with);
    const PointCloud observed = readPlyPoints(with / "gt" / "observed_points.ply");
    REQUIRE(observed.size() > 10000);
    for (std::size_t i = 0; i < observed.size(); i += 5) {
        for (const Mover& m : seq.movers.movers) {
            for (const Isometry3d& T : m.T_W_O) {
                const Vec3f p_O = (T.inverse() * observed.points[i].cast<double>()).cast<float>();
                REQUIRE_FALSE(insideCore(m, p_O));
            }
        }
    }
    fs::remove_all(with);
    fs::remove_all(without);
}

TEST_CASE("Traffic: deterministic, our ids, the semantic-kitti layout, bad values",
          "[sim][traffic]") {
    const fs::path a = fs::temp_directory_path() / "vdbmap_simtraffic_a";
    const fs::path b = fs::temp_directory_path() / "vdbmap_simtraffic_b";
    fs::remove_all(a);
    fs::remove_all(b);
    SimOptions o = trafficOptions(2);
    o.frames = 3;
    o.lidar_label_semantickitti_ids = false;
    writeSimSequence(o, a);
    writeSimSequence(o, b);
    CHECK(fileBytes(a / "gt" / "movers.json") == fileBytes(b / "gt" / "movers.json"));
    CHECK(fileBytes(a / "labels" / "000002.label") == fileBytes(b / "labels" / "000002.label"));
    // Our ids: a moving point carries its class (13 car, 14 truck, 11 person) and its instance.
    const LidarLabels labels = readLidarLabels(a / "labels" / "000001.label");
    std::size_t moving = 0;
    for (std::uint32_t v : labels.raw) {
        if (LidarLabels::instanceOf(v) == 0) continue;
        ++moving;
        const auto cls = LidarLabels::classOf(v);
        CHECK((cls == 13 || cls == 14 || cls == 11));
    }
    CHECK(moving > 100);

    // semantic-kitti layout: labels with 252 in dataset/sequences/00/labels, movers in gt/.
    fs::remove_all(a);
    SimLayoutOptions layout;
    layout.layout = "semantic-kitti";
    o.lidar_label_semantickitti_ids = true;
    writeSimLayout(o, layout, a);
    CHECK(fs::exists(a / "gt" / "movers.json"));
    const LidarLabels sk =
        readLidarLabels(a / "dataset" / "sequences" / "00" / "labels" / "000001.label");
    CHECK(std::count_if(sk.raw.begin(), sk.raw.end(),
                        [](std::uint32_t v) { return LidarLabels::classOf(v) == 252; }) > 100);

    SimOptions bad = trafficOptions(2);
    bad.scene = "suv";
    CHECK_THROWS_AS(writeSimSequence(bad, b / "suv"), ConfigError);
    bad = trafficOptions(21);
    CHECK_THROWS_AS(writeSimSequence(bad, b / "many"), ConfigError);
    fs::remove_all(a);
    fs::remove_all(b);
}
