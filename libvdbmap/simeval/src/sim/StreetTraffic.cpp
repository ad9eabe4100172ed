// SPDX-License-Identifier: Apache-2.0
// The street's traffic (vdbmap-sim --traffic N): box-built cars, a van and pedestrians, each
// with a pose per frame, choreographed so that nobody meets the ego vehicle or one another.
#include <cmath>
#include <functional>
#include <random>

#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/render/Raycaster.h"
#include "vdbmap/sim/Scenes.h"
#include "vdbmap/sim/Traffic.h"

namespace vdbmap {

namespace {

// The street's layout (StreetScene.cpp): lanes at y = -+1.75 m, kerbs at |y| = 5 m, 15 cm up.
constexpr double kTrafficLaneY = 1.75;
constexpr double kTrafficKerbY = 5.0;
constexpr double kTrafficKerbHeight = 0.15;
constexpr double kTrafficSidewalkY = 7.2;  // pedestrians walk 0.8 m from the facades

constexpr std::uint8_t kTrafficPerson = 11, kTrafficCar = 13, kTrafficTruck = 14;

using PoseAt = std::function<Isometry3d(double)>;  // pose T_S_O at normalised time u

Isometry3d poseXYZYaw(double x, double y, double z, double yaw) {
    Isometry3d T = Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(yaw, Vec3d::UnitZ()).toRotationMatrix();
    T.translation() = Vec3d(x, y, z);
    return T;
}

MoverPart moverPart(float cx, float cy, float cz, float hx, float hy, float hz,
                    const char* texture) {
    return MoverPart{Vec3f(cx, cy, cz), Vec3f(hx, hy, hz), texture};
}

// 4.2 m x 1.92 m x 1.62 m: body, cabin, four wheels.
Mover makeCar(std::size_t i, const char* paint) {
    Mover m;
    m.name = "car_" + std::to_string(i);
    m.kind = "car";
    m.class_id = kTrafficCar;
    m.parts = {moverPart(0.0f, 0.0f, 0.7f, 2.1f, 0.88f, 0.4f, paint),
               moverPart(-0.2f, 0.0f, 1.36f, 1.1f, 0.78f, 0.26f, "window")};
    for (float x : {-1.35f, 1.35f}) {
        for (float y : {-0.85f, 0.85f})
            m.parts.push_back(moverPart(x, y, 0.33f, 0.33f, 0.11f, 0.33f, "tyre"));
    }
    return m;
}

// 4.84 m x 2.0 m x 2.6 m: body, windscreen, four wheels.
Mover makeVan() {
    Mover m;
    m.name = "van";
    m.kind = "van";
    m.class_id = kTrafficTruck;
    m.parts = {moverPart(0.0f, 0.0f, 1.475f, 2.4f, 0.95f, 1.125f, "van_white"),
               moverPart(2.41f, 0.0f, 1.9f, 0.01f, 0.8f, 0.4f, "window")};
    for (float x : {-1.6f, 1.6f}) {
        for (float y : {-0.88f, 0.88f})
            m.parts.push_back(moverPart(x, y, 0.36f, 0.36f, 0.12f, 0.36f, "tyre"));
    }
    return m;
}

// 0.26 m x 0.44 m x 1.72 m: legs, torso, head.
Mover makePedestrian(std::size_t i, const char* shirt) {
    Mover m;
    m.name = "pedestrian_" + std::to_string(i);
    m.kind = "pedestrian";
    m.class_id = kTrafficPerson;
    m.parts = {moverPart(0.0f, 0.0f, 0.4f, 0.12f, 0.17f, 0.4f, "trousers"),
               moverPart(0.0f, 0.0f, 1.12f, 0.13f, 0.22f, 0.32f, shirt),
               moverPart(0.0f, 0.0f, 1.6f, 0.1f, 0.09f, 0.12f, "skin")};
    return m;
}

// True if the static scene leaves the mover's box free along its path: rays cast down through
// the box footprint (10 cm grid, 41 instants) hit nothing higher than 0.2 m above the mover's
// ground (the kerb it steps over is lower).
bool pathClear(const Raycaster& static_S, const Mover& mover, const PoseAt& pose_at) {
    const Vec3f c = mover.boxCentre_O();
    const Vec3f h = mover.boxHalf_m();
    const float top_z = c.z() + h.z();
    const float max_hit_m = top_z - 0.2f;
    for (int s = 0; s <= 40; ++s) {
        const Eigen::Isometry3f T = pose_at(s / 40.0).cast<float>();
        for (float x = c.x() - h.x(); x <= c.x() + h.x() + 1e-4f; x += 0.1f) {
            for (float y = c.y() - h.y(); y <= c.y() + h.y() + 1e-4f; y += 0.1f) {
                const Vec3f origin = T * Vec3f(x, y, top_z);
                if (static_S.occluded(origin, Vec3f(0, 0, -1), 0.0f, max_hit_m)) return false;
            }
        }
    }
    return true;
}

// The first of `candidates` whose path is clear; the first candidate (with a warning) if none.
double firstClear(const Raycaster& static_S, const Mover& mover,
                  const std::vector<double>& candidates,
                  const std::function<PoseAt(double)>& path_for) {
    for (double c : candidates) {
        if (pathClear(static_S, mover, path_for(c))) return c;
    }
    logWarn("vdbmap-sim: no clear path for the traffic's " + mover.name +
            "; it passes through the static scene");
    return candidates.front();
}

std::vector<double> candidateSteps(double from, double to, double step) {
    std::vector<double> out;
    const int n = static_cast<int>(std::floor((to - from) / step + 1e-9));
    for (int k = 0; k <= std::max(0, n); ++k) out.push_back(from + k * step);
    return out;
}

void samplePoses(Mover& mover, const PoseAt& pose_at, std::size_t frames) {
    mover.T_W_O.clear();
    for (std::size_t f = 0; f < frames; ++f) {
        const double u =
            frames > 1 ? static_cast<double>(f) / static_cast<double>(frames - 1) : 0.0;
        mover.T_W_O.push_back(pose_at(u));
    }
}

}  // namespace

Vec3f Mover::boxCentre_O() const {
    Eigen::AlignedBox3f box;
    for (const auto& p : parts) box.extend(p.centre_O - p.half_m).extend(p.centre_O + p.half_m);
    return box.center();
}

Vec3f Mover::boxHalf_m() const {
    Eigen::AlignedBox3f box;
    for (const auto& p : parts) box.extend(p.centre_O - p.half_m).extend(p.centre_O + p.half_m);
    return box.sizes() / 2.0f;
}

std::uint16_t movingSemanticKittiId(std::uint8_t class_id) {
    switch (class_id) {
        case kTrafficCar:
            return 252;  // moving-car
        case kTrafficPerson:
            return 254;  // moving-person
        case kTrafficTruck:
            return 258;  // moving-truck
        default:
            return 259;  // moving-other-vehicle
    }
}

std::vector<Mover> buildStreetTraffic(const SceneSetup& setup, const Raycaster& static_S,
                                      std::size_t cars, std::uint64_t seed) {
    if (cars == 0) return {};
    if (setup.T_S_V.empty()) throw InvalidInput("buildStreetTraffic: the drive has no frames");
    const std::size_t frames = setup.T_S_V.size();
    // The ego vehicle drives the right lane (y = -1.75) from x_s, D metres, at constant speed.
    const double x_s = setup.T_S_V.front().translation().x();
    const double D = std::max(1.0, setup.T_S_V.back().translation().x() - x_s);
    std::mt19937_64 rng(seed * 0x9e3779b97f4a7c15ULL + 0x7aff1cULL);
    std::uniform_real_distribution<double> jitter(-1.0, 0.0);
    const char* paints[] = {"car_yellow", "car_green", "car_orange"};
    std::vector<Mover> movers;

    // car_0 creeps ahead in the ego lane: 15 m ahead at the start, 8 m at the end.
    const double lead_gap0 = 15.0, lead_gap1 = 8.0;
    const double k_lead = std::max(0.0, 1.0 - (lead_gap0 - lead_gap1) / D);
    Mover lead = makeCar(0, paints[0]);
    const PoseAt lead_at = [=](double u) {
        return poseXYZYaw(x_s + lead_gap0 + k_lead * D * u, -kTrafficLaneY, 0.0, 0.0);
    };
    samplePoses(lead, lead_at, frames);
    movers.push_back(std::move(lead));

    // The van crosses from the right kerb (y = -4) to the left one (y = 5.4) at x_c. It leaves
    // the right lane (rear at y >= -0.6) at u = 0.62, before car_0 gets there (u = 0.65) and
    // long before the ego vehicle, which stays behind car_0.
    Mover van = makeVan();
    const auto van_path = [](double x_c) -> PoseAt {
        return [=](double u) { return poseXYZYaw(x_c, -4.0 + 9.4 * u, 0.0, M_PI / 2); };
    };
    const double x_c0 = x_s + lead_gap0 + k_lead * D * 0.65 + 3.6;
    const double x_c = firstClear(static_S, van, candidateSteps(x_c0, x_c0 + 15.0, 0.25), van_path);
    samplePoses(van, van_path(x_c), frames);

    // The other cars come the other way in the left lane, all from behind the van's crossing
    // (x < x_c - 3.6), so they never meet it; they cover half the drive's length.
    const std::size_t n_oncoming = cars - 1;
    const double first_x = x_c - 5.6;
    const double spacing =
        n_oncoming > 1 ? std::max(8.0, (first_x - (x_s + 12.0)) / (n_oncoming - 1)) : 0.0;
    for (std::size_t i = 1; i < cars; ++i) {
        Mover car = makeCar(i, paints[i % 3]);
        const double x0 = first_x - (i - 1) * spacing + jitter(rng);
        samplePoses(
            car, [=](double u) { return poseXYZYaw(x0 - 0.5 * D * u, kTrafficLaneY, 0.0, M_PI); },
            frames);
        movers.push_back(std::move(car));
    }
    movers.push_back(std::move(van));

    // Pedestrians: one along each sidewalk, one crossing the right half behind the ego vehicle
    // (at y <= -5.1 while the ego vehicle passes, at most to the centre line at the end).
    Mover p1 = makePedestrian(1, "shirt_purple");
    const auto p1_path = [=](double x0) -> PoseAt {
        return [=](double u) {
            return poseXYZYaw(x0 + 0.08 * D * u, -kTrafficSidewalkY, kTrafficKerbHeight, 0.0);
        };
    };
    samplePoses(p1,
                p1_path(firstClear(static_S, p1,
                                   candidateSteps(x_s + 0.35 * D, x_s + 0.5 * D, 0.25), p1_path)),
                frames);
    Mover p2 = makePedestrian(2, "shirt_cyan");
    const auto p2_path = [=](double x0) -> PoseAt {
        return [=](double u) {
            return poseXYZYaw(x0 - 0.08 * D * u, kTrafficSidewalkY, kTrafficKerbHeight, M_PI);
        };
    };
    samplePoses(p2,
                p2_path(firstClear(static_S, p2,
                                   candidateSteps(x_s + 0.6 * D, x_s + 0.75 * D, 0.25), p2_path)),
                frames);
    Mover p3 = makePedestrian(3, "shirt_purple");
    const auto p3_path = [](double x_p) -> PoseAt {
        return [=](double u) {
            const double y = -6.2 + 6.0 * u;
            return poseXYZYaw(x_p, y, std::abs(y) > kTrafficKerbY ? kTrafficKerbHeight : 0.0,
                              M_PI / 2);
        };
    };
    // The ego vehicle passes x_p at u = (x_p - x_s) / D <= 0.45, when p3 is still at y <= -3.5.
    samplePoses(p3,
                p3_path(firstClear(static_S, p3,
                                   candidateSteps(x_s + 0.15 * D, x_s + 0.45 * D, 0.25), p3_path)),
                frames);
    for (Mover* p : {&p1, &p2, &p3}) movers.push_back(std::move(*p));

    for (std::size_t i = 0; i < movers.size(); ++i) {
        movers[i].instance_id = static_cast<std::uint16_t>(i + 1);
    }
    return movers;
}

std::vector<cv::Mat> moverTextures(const Mover& mover, std::uint64_t seed) {
    std::vector<cv::Mat> out;
    for (const auto& p : mover.parts) out.push_back(proceduralTexture(p.texture, seed));
    return out;
}

void addMoverToScene(SimScene& scene, const Mover& mover, const Isometry3d& T_W_O,
                     const std::vector<cv::Mat>& part_textures) {
    if (part_textures.size() != mover.parts.size()) {
        throw InvalidInput("addMoverToScene: " + mover.name + " has " +
                           std::to_string(mover.parts.size()) + " parts but " +
                           std::to_string(part_textures.size()) + " textures");
    }
    for (std::size_t k = 0; k < mover.parts.size(); ++k) {
        const MoverPart& p = mover.parts[k];
        const std::uint32_t material =
            scene.addMaterial(mover.name + "_" + p.texture, part_textures[k]);
        Isometry3d T_O_P = Isometry3d::Identity();
        T_O_P.translation() = p.centre_O.cast<double>();
        scene.addBox(T_W_O * T_O_P, p.half_m, 1.0f, material, mover.class_id);
    }
}

}  // namespace vdbmap
