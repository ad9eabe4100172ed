// SPDX-License-Identifier: Apache-2.0
#include <cmath>

#include "vdbmap/Error.h"
#include "vdbmap/sim/Scenes.h"

namespace vdbmap {

namespace {

constexpr std::uint8_t kSuvGroundClass = 0, kSuvClass = 13;

Isometry3d suvOffset(double x, double y, double z) {
    Isometry3d T = Isometry3d::Identity();
    T.translation() = Vec3d(x, y, z);
    return T;
}

}  // namespace

SceneSetup buildSuvScene(const SuvSceneOptions& options) {
    if (options.frames == 0 || !(options.circle_radius_m > 4.0) || !(options.speed_mps > 0.0)) {
        throw InvalidInput("suv scene: frames > 0, circle radius > 4 m and speed > 0 required");
    }
    SceneSetup setup;
    SimScene& s = setup.scene;
    const std::uint32_t ground = s.addMaterial("asphalt", proceduralTexture("asphalt", options.seed));
    const std::uint32_t paint = s.addMaterial("suv", proceduralTexture("suv", options.seed));
    const std::uint32_t glass = s.addMaterial("glass", proceduralTexture("glass", options.seed));
    const std::uint32_t tyre = s.addMaterial("tyre", proceduralTexture("tyre", options.seed));
    // Ground: 40 m x 40 m in 4 m tiles.
    for (int i = -5; i < 5; ++i) {
        for (int j = -5; j < 5; ++j) {
            const float x0 = 4.0f * i, y0 = 4.0f * j;
            s.addQuad({x0, y0, 0}, {x0 + 4, y0, 0}, {x0 + 4, y0 + 4, 0}, {x0, y0 + 4, 0}, 4.0f,
                      ground, kSuvGroundClass);
        }
    }
    // SUV (about 4.8 m x 1.95 m x 1.85 m): body, cabin, bumpers, tilted bonnet, four wheels.
    s.addBox(suvOffset(0, 0, 0.8), Vec3f(2.4f, 0.975f, 0.45f), 2.0f, paint, kSuvClass);
    s.addBox(suvOffset(-0.35, 0, 1.55), Vec3f(1.6f, 0.9f, 0.3f), 2.0f, glass, kSuvClass);
    s.addBox(suvOffset(2.45, 0, 0.55), Vec3f(0.1f, 0.9f, 0.15f), 1.0f, paint, kSuvClass);
    s.addBox(suvOffset(-2.45, 0, 0.55), Vec3f(0.1f, 0.9f, 0.15f), 1.0f, paint, kSuvClass);
    Isometry3d roof_rack = suvOffset(-0.35, 0, 1.88);
    s.addBox(roof_rack, Vec3f(1.2f, 0.7f, 0.03f), 1.0f, paint, kSuvClass);
    for (float dx : {-1.5f, 1.5f}) {
        for (float y_centre : {-0.98f, 0.98f}) {
            // Rotated +90 deg about x, the cylinder axis runs along -y from its base.
            Isometry3d T = suvOffset(dx, y_centre + 0.14, 0.38);
            T.linear() = Eigen::AngleAxisd(M_PI / 2, Vec3d::UnitX()).toRotationMatrix();
            s.addCylinder(T, 0.38f, 0.28f, 20, 1.0f, tyre, kSuvClass);
        }
    }
    // Counter-clockwise circle, heading along the tangent: 10 Hz.
    const double dtheta = options.speed_mps / 10.0 / options.circle_radius_m;
    for (std::size_t f = 0; f < options.frames; ++f) {
        const double th = dtheta * static_cast<double>(f);
        Isometry3d T = suvOffset(options.circle_radius_m * std::cos(th),
                                   options.circle_radius_m * std::sin(th), 0.0);
        T.linear() = Eigen::AngleAxisd(th + M_PI / 2, Vec3d::UnitZ()).toRotationMatrix();
        setup.T_S_V.push_back(T);
    }
    setup.lidar_height_m = 2.3;  // the paper: top-mounted, 2.3 m above the ground
    setup.frame_rate_hz = 10.0;
    return setup;
}

}  // namespace vdbmap
