// SPDX-License-Identifier: Apache-2.0
#include <cmath>
#include <random>

#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/io/Image.h"
#include "vdbmap/sim/Scenes.h"

namespace vdbmap {

namespace {

// Class ids of docs/DATA.md.
constexpr std::uint8_t kRoad = 0, kSidewalk = 1, kBuilding = 2, kPole = 5, kSign = 7,
                       kVegetation = 8, kCar = 13, kLaneMarking = 19, kOtherObject = 20;

constexpr float kRoadHalfWidth = 5.0f;   // kerb line, y = +-5 m
constexpr float kSidewalkWidth = 3.0f;   // sidewalk from |y| = 5 to 8 m
constexpr float kKerbHeight = 0.15f;
constexpr float kMarkingLift = 0.005f;   // markings sit 5 mm above the asphalt
constexpr float kLaneY = -1.75f;         // centre of the right lane (driving direction +x)

struct Materials {
    std::uint32_t asphalt, lane, sidewalk, curb, brick, glass, metal, sign, foliage, bark,
        car[3], tyre;
};

Isometry3d translation(double x, double y, double z) {
    Isometry3d T = Isometry3d::Identity();
    T.translation() = Vec3d(x, y, z);
    return T;
}

// Axis-aligned quad in a horizontal plane z, corners (x0,y0) - (x1,y1), facing up.
void addGroundQuad(SimScene& s, float x0, float y0, float x1, float y1, float z, float tile,
                   std::uint32_t m, std::uint8_t label) {
    s.addQuad({x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}, tile, m, label);
}

// Building facade at y = y_f facing the street (towards y = 0), from x0 to x1, height h, with
// a grid of windows recessed by `recess` m. side = +1: building on the left (y > 0).
void addBuilding(SimScene& s, const Materials& mat, float x0, float x1, float y_f, float depth,
                 float h, float side, std::mt19937& rng) {
    const float y_b = y_f + side * depth;  // back wall
    const float z0 = kKerbHeight;
    auto P = [&](float x, float y, float z) { return Vec3f(x, y, z); };
    // Facade normal points to -side*y. For a quad a-b-c-d counter-clockwise seen from the
    // street, walk x in the direction that makes (b-a) x (d-a) point towards the street.
    auto facadeQuad = [&](float xa, float xb, float za, float zb, float y, std::uint32_t m,
                          std::uint8_t label) {
        if (side > 0) {
            s.addQuad(P(xb, y, za), P(xa, y, za), P(xa, y, zb), P(xb, y, zb), 3.0f, m, label);
        } else {
            s.addQuad(P(xa, y, za), P(xb, y, za), P(xb, y, zb), P(xa, y, zb), 3.0f, m, label);
        }
    };
    // Window grid.
    const float floor_h = 3.0f;
    const int floors = std::max(1, static_cast<int>(std::floor((h - 0.5f) / floor_h)));
    const float win_w = 1.2f, win_h = 1.5f, win_sill = 1.0f;
    const int cols = std::max(1, static_cast<int>(std::floor((x1 - x0) / 3.0f)));
    const float pitch = (x1 - x0) / cols;
    std::uniform_real_distribution<float> recess_dist(0.15f, 0.3f);
    const float recess = recess_dist(rng);
    float z_cursor = z0;
    for (int f = 0; f < floors; ++f) {
        const float zf = z0 + f * floor_h;
        const float zw0 = zf + win_sill, zw1 = zw0 + win_h;
        facadeQuad(x0, x1, z_cursor, zw0, y_f, mat.brick, kBuilding);  // band below windows
        float x_cursor = x0;
        for (int c = 0; c < cols; ++c) {
            const float xc = x0 + (c + 0.5f) * pitch;
            const float xw0 = xc - win_w / 2, xw1 = xc + win_w / 2;
            facadeQuad(x_cursor, xw0, zw0, zw1, y_f, mat.brick, kBuilding);  // pier
            x_cursor = xw1;
            // Recessed window: glass at the back, four reveals.
            const float y_g = y_f + side * recess;
            facadeQuad(xw0, xw1, zw0, zw1, y_g, mat.glass, kBuilding);
            // Reveals (normals pointing into the opening).
            s.addQuad(P(xw0, y_f, zw0), P(xw1, y_f, zw0), P(xw1, y_g, zw0), P(xw0, y_g, zw0),
                      1.0f, mat.brick, kBuilding);
            s.addQuad(P(xw0, y_g, zw1), P(xw1, y_g, zw1), P(xw1, y_f, zw1), P(xw0, y_f, zw1),
                      1.0f, mat.brick, kBuilding);
            s.addQuad(P(xw0, y_g, zw0), P(xw0, y_g, zw1), P(xw0, y_f, zw1), P(xw0, y_f, zw0),
                      1.0f, mat.brick, kBuilding);
            s.addQuad(P(xw1, y_f, zw0), P(xw1, y_f, zw1), P(xw1, y_g, zw1), P(xw1, y_g, zw0),
                      1.0f, mat.brick, kBuilding);
        }
        facadeQuad(x_cursor, x1, zw0, zw1, y_f, mat.brick, kBuilding);
        z_cursor = zw1;
    }
    facadeQuad(x0, x1, z_cursor, z0 + h, y_f, mat.brick, kBuilding);  // top band
    // The other walls and the roof: a box without its street face.
    const float zt = z0 + h;
    const float ya = std::min(y_f, y_b), yb = std::max(y_f, y_b);
    s.addQuad(P(x0, ya, zt), P(x1, ya, zt), P(x1, yb, zt), P(x0, yb, zt), 3.0f, mat.brick,
              kBuilding);  // roof
    s.addQuad(P(x0, yb, z0), P(x0, ya, z0), P(x0, ya, zt), P(x0, yb, zt), 3.0f, mat.brick,
              kBuilding);  // -x end
    s.addQuad(P(x1, ya, z0), P(x1, yb, z0), P(x1, yb, zt), P(x1, ya, zt), 3.0f, mat.brick,
              kBuilding);  // +x end
    facadeQuad(x1, x0, z0, zt, y_b, mat.brick, kBuilding);  // back wall
}

// A parked car: body, cabin and four wheels, centred at (x, y), heading along x.
void addCar(SimScene& s, const Materials& mat, float x, float y, std::uint32_t paint) {
    s.addBox(translation(x, y, 0.7), Vec3f(2.1f, 0.88f, 0.4f), 2.0f, paint, kCar);
    s.addBox(translation(x - 0.2, y, 1.35), Vec3f(1.1f, 0.78f, 0.27f), 2.0f, mat.glass, kCar);
    for (float dx : {-1.35f, 1.35f}) {
        for (float y_centre : {-0.85f, 0.85f}) {
            // Rotated +90 deg about x, the cylinder axis runs along -y from its base.
            Isometry3d T = translation(x + dx, y + y_centre + 0.11, 0.33);
            T.linear() = Eigen::AngleAxisd(M_PI / 2, Vec3d::UnitX()).toRotationMatrix();
            s.addCylinder(T, 0.33f, 0.22f, 16, 1.0f, mat.tyre, kCar);
        }
    }
}

void addArrow(SimScene& s, const Materials& mat, float x, float y) {
    // Straight-ahead arrow pointing +x: shaft 3 m x 0.15 m, triangular head 1.2 m x 0.6 m.
    const float z = kMarkingLift;
    addGroundQuad(s, x, y - 0.075f, x + 3.0f, y + 0.075f, z, 1.0f, mat.lane, kLaneMarking);
    s.addTriangle({x + 3.0f, y - 0.3f, z}, {x + 4.2f, y, z}, {x + 3.0f, y + 0.3f, z}, {0, 0},
                  {1, 0.5f}, {0, 1}, mat.lane, kLaneMarking);
}

Materials addMaterials(SimScene& s, std::uint64_t seed) {
    Materials mat{};
    const auto add = [&](const char* name) { return s.addMaterial(name, proceduralTexture(name, seed)); };
    mat.asphalt = add("asphalt");
    mat.lane = add("lane");
    mat.sidewalk = add("sidewalk");
    mat.curb = add("curb");
    mat.brick = add("brick");
    mat.glass = add("glass");
    mat.metal = add("metal");
    mat.sign = add("sign");
    mat.foliage = add("foliage");
    mat.bark = add("bark");
    mat.car[0] = add("car_red");
    mat.car[1] = add("car_blue");
    mat.car[2] = add("car_silver");
    mat.tyre = add("tyre");
    return mat;
}

// Road, sidewalks with kerbs and solid edge lines, in 5 m pieces so that faces stay small.
void addRoad(SimScene& s, const Materials& mat, float L) {
    const float seg = 5.0f;
    const int n_seg = static_cast<int>(std::ceil(L / seg));
    for (int i = 0; i < n_seg; ++i) {
        const float xa = i * seg, xb = std::min(L, (i + 1) * seg);
        addGroundQuad(s, xa, -kRoadHalfWidth, xb, kRoadHalfWidth, 0.0f, 4.0f, mat.asphalt, kRoad);
        // Sidewalks (top), kerb faces towards the road.
        const float yo = kRoadHalfWidth + kSidewalkWidth;
        addGroundQuad(s, xa, kRoadHalfWidth, xb, yo, kKerbHeight, 2.0f, mat.sidewalk, kSidewalk);
        addGroundQuad(s, xa, -yo, xb, -kRoadHalfWidth, kKerbHeight, 2.0f, mat.sidewalk,
                      kSidewalk);
        s.addQuad({xb, kRoadHalfWidth, 0}, {xa, kRoadHalfWidth, 0},
                  {xa, kRoadHalfWidth, kKerbHeight}, {xb, kRoadHalfWidth, kKerbHeight}, 1.0f,
                  mat.curb, kSidewalk);
        s.addQuad({xa, -kRoadHalfWidth, 0}, {xb, -kRoadHalfWidth, 0},
                  {xb, -kRoadHalfWidth, kKerbHeight}, {xa, -kRoadHalfWidth, kKerbHeight}, 1.0f,
                  mat.curb, kSidewalk);
        for (float yc : {-4.7f, 4.7f}) {
            addGroundQuad(s, xa, yc - 0.075f, xb, yc + 0.075f, kMarkingLift, 1.0f, mat.lane,
                          kLaneMarking);
        }
    }
}

// Dashed centre line (3 m dash, 3 m gap) and arrows on both lanes every 25 m.
void addMarkings(SimScene& s, const Materials& mat, float L) {
    for (float x = 1.0f; x + 3.0f <= L; x += 6.0f) {
        addGroundQuad(s, x, -0.075f, x + 3.0f, 0.075f, kMarkingLift, 1.0f, mat.lane,
                      kLaneMarking);
    }
    for (float x = 12.0f; x + 5.0f <= L; x += 25.0f) {
        addArrow(s, mat, x, kLaneY);
        addArrow(s, mat, x + 8.0f, -kLaneY);
    }
}

// Buildings on both sides with gaps between them.
void addBuildings(SimScene& s, const Materials& mat, float L, std::mt19937& rng) {
    std::uniform_real_distribution<float> len_dist(10.0f, 18.0f), gap_dist(1.5f, 4.0f),
        height_dist(7.0f, 13.0f), depth_dist(6.0f, 10.0f);
    for (float side : {1.0f, -1.0f}) {
        float x = -2.0f;
        while (x < L) {
            const float len = std::min(len_dist(rng), L + 2.0f - x);
            if (len > 4.0f) {
                addBuilding(s, mat, x, x + len, side * (kRoadHalfWidth + kSidewalkWidth),
                            depth_dist(rng), height_dist(rng), side, rng);
            }
            x += len + gap_dist(rng);
        }
    }
}

// Poles with signs every 15 m, alternating sides; a tree and a bush between them.
void addPolesAndTrees(SimScene& s, const Materials& mat, float L, std::uint64_t seed) {
    int k = 0;
    for (float x = 6.0f; x < L - 2.0f; x += 15.0f, ++k) {
        const float side = (k % 2 == 0) ? -1.0f : 1.0f;
        const float y = side * (kRoadHalfWidth + 0.6f);
        s.addCylinder(translation(x, y, kKerbHeight), 0.08f, 4.5f, 12, 1.0f, mat.metal, kPole);
        Isometry3d sign_pose = translation(x, y - side * 0.15, kKerbHeight + 3.6);
        s.addBox(sign_pose, Vec3f(0.35f, 0.03f, 0.35f), 0.7f, mat.sign, kSign);
        const float xt = x + 7.5f;
        if (xt >= L - 2.0f) continue;
        const float yt = -side * (kRoadHalfWidth + 1.5f);
        s.addCylinder(translation(xt, yt, kKerbHeight), 0.15f, 2.2f, 10, 1.0f, mat.bark,
                      kVegetation);
        s.addBlob(Vec3f(xt, yt, kKerbHeight + 3.2f), 1.3f, 0.25f,
                  static_cast<std::uint32_t>(seed * 131 + k), 1.5f, mat.foliage, kVegetation);
        s.addBlob(Vec3f(xt + 2.5f, yt + side * 0.5f, kKerbHeight + 0.45f), 0.55f, 0.3f,
                  static_cast<std::uint32_t>(seed * 977 + k), 1.0f, mat.foliage, kVegetation);
    }
}

// Parked cars in the parking strips next to the kerbs.
void addParkedCars(SimScene& s, const Materials& mat, float L, std::mt19937& rng) {
    std::uniform_real_distribution<float> car_gap(6.0f, 14.0f);
    int c = 0;
    for (float side : {1.0f, -1.0f}) {
        for (float x = 8.0f + (side > 0 ? 0.0f : 5.0f); x < L - 6.0f; x += car_gap(rng), ++c) {
            addCar(s, mat, x, side * 3.9f, mat.car[c % 3]);
            x += 4.5f;
        }
    }
}

// Spot (Keenan Crane, public domain) on the right sidewalk: y-up OBJ, rotated to z-up.
void addSpot(SimScene& s, const std::filesystem::path& spot_dir, float L) {
    ObjMesh spot = readObj(spot_dir / "spot_triangulated.obj");
    std::vector<cv::Mat> spot_textures{readColorImage(spot_dir / "spot_texture.png")};
    spot.materials.assign(1, ObjMaterial{"spot", {1, 1, 1}, ""});
    for (auto& t : spot.triangles) t.material = 0;
    float min_y = 1e9f;
    for (const auto& p : spot.positions) min_y = std::min(min_y, p.y());
    Isometry3d pose = Isometry3d::Identity();
    pose.linear() = (Eigen::AngleAxisd(M_PI / 2, Vec3d::UnitZ()) *
                     Eigen::AngleAxisd(M_PI / 2, Vec3d::UnitX()))
                        .toRotationMatrix();
    pose.translation() =
        Vec3d(std::min(20.0, 0.4 * L), -(kRoadHalfWidth + 1.6), kKerbHeight - min_y);
    s.append(spot, spot_textures, pose, kOtherObject);
}

}  // namespace

SceneSetup buildStreetScene(const StreetSceneOptions& options) {
    if (!(options.length_m >= 20.0) || options.frames == 0) {
        throw InvalidInput("street scene: length must be >= 20 m and frames > 0 (got " +
                           std::to_string(options.length_m) + " m, " +
                           std::to_string(options.frames) + " frames)");
    }
    SceneSetup setup;
    SimScene& s = setup.scene;
    std::mt19937 rng(static_cast<std::uint32_t>(options.seed));
    const Materials mat = addMaterials(s, options.seed);
    const float L = static_cast<float>(options.length_m);
    addRoad(s, mat, L);
    addMarkings(s, mat, L);
    addBuildings(s, mat, L, rng);
    addPolesAndTrees(s, mat, L, options.seed);
    addParkedCars(s, mat, L, rng);
    if (!options.spot_dir.empty()) addSpot(s, options.spot_dir, L);
    // Trajectory: the right lane, from x = 3 m to L - 3 m at constant speed.
    const double x_start = 3.0, x_end = L - 3.0;
    for (std::size_t f = 0; f < options.frames; ++f) {
        const double t = options.frames > 1 ? static_cast<double>(f) / (options.frames - 1) : 0.0;
        setup.T_S_V.push_back(translation(x_start + t * (x_end - x_start), kLaneY, 0.0));
    }
    setup.lidar_height_m = 1.73;  // KITTI's HDL-64E mounting height
    return setup;
}

}  // namespace vdbmap
