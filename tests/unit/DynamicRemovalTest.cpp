// SPDX-License-Identifier: Apache-2.0
// Moving objects out of the map (issue 33): free-space votes over time on a closed-form street
// (support/DynamicScene.h). A box driving along the street is removed; the ground seen at
// grazing incidence, a thin pole and a parked box are kept; moving labels are removed; the
// removed points round-trip through dynamic_points.ply.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <random>

#include "support/DynamicScene.h"
#include "vdbmap/Error.h"
#include "vdbmap/dynamic/DynamicDetector.h"
#include "vdbmap/dynamic/DynamicPoints.h"
#include "vdbmap/dynamic/RangeImage.h"
#include "vdbmap/io/Dataset.h"

namespace fs = std::filesystem;
using namespace vdbmap;
using test::Hit;

namespace {

fs::path scratch(const std::string& name) { return test::freshScratch("vdbmap_dynamic_", name); }

std::shared_ptr<Dataset> openGeneric(const fs::path& dir) { return test::openDynamicDataset(dir); }

/// Removed and total points per kind of surface over the frames `frames`.
struct Counts {
    std::size_t removed[4] = {0, 0, 0, 0};
    std::size_t total[4] = {0, 0, 0, 0};
    double recall() const { return static_cast<double>(removed[3]) / static_cast<double>(total[3]); }
    std::size_t staticRemoved() const { return removed[0] + removed[1] + removed[2]; }
    std::size_t staticTotal() const { return total[0] + total[1] + total[2]; }
};

Counts detectAll(const Dataset& dataset, const std::vector<test::DynamicScan>& scans,
                 const DynamicRemovalConfig& config, int first, int last) {
    DynamicDetector detector(dataset, config);
    Counts c;
    for (int f = first; f <= last; ++f) {
        PointCloud cloud;
        ScanReadStats stats;
        std::vector<std::uint32_t> index;
        dataset.loadScan(static_cast<std::size_t>(f), cloud, &stats, &index);
        const std::vector<std::uint8_t> dyn =
            detector.detect(static_cast<std::size_t>(f), cloud.points, index, stats.points_read);
        for (std::size_t i = 0; i < dyn.size(); ++i) {
            const int kind = static_cast<int>(scans[static_cast<std::size_t>(f)].hits[index[i]]);
            ++c.total[kind];
            c.removed[kind] += dyn[i];
        }
    }
    return c;
}

std::vector<test::DynamicScan> makeScans(const test::DynamicSceneOptions& o) {
    std::vector<test::DynamicScan> scans;
    for (int f = 0; f < o.frames; ++f) scans.push_back(test::dynamicScan(o, f));
    return scans;
}

}  // namespace

TEST_CASE("RangeImage: a point on the ground seen at grazing incidence is not seen through",
          "[dynamic]") {
    // One scan of the flat ground from (0, 0, 1.73); points of the ground and above it seen
    // from 10 m further along.
    test::DynamicSceneOptions o;
    o.pole_height_m = 0.0;
    o.parked = {{1000, 1000, 0}, {1001, 1001, 1}};
    o.mover_start = {1000.0, 1000.0, 0.0};
    const test::DynamicScan scan = test::dynamicScan(o, 0);
    const RangeImage image(scan.points_L, RangeImageConfig{});
    REQUIRE(image.rows() > 100);
    FreeSpaceVoteConfig votes;
    std::vector<VoteScan> scans{{&image, scan.T_W_L.inverse()}};
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int ground_free = 0, above_free = 0, tested = 0;
    for (int k = 0; k < 2000; ++k) {
        // A ground point 5 to 30 m from the scan, in any direction (the ray through a point
        // 1 m above it meets the ground within 2.4 r <= 71 m, inside the 80 m range).
        const double r = 5.0 + 12.5 * (u(rng) + 1.0), a = 3.14159 * u(rng);
        const Vec3f ground(static_cast<float>(r * std::cos(a)), static_cast<float>(r * std::sin(a)), 0.0f);
        const Vec3f above = ground + Vec3f(0.0f, 0.0f, 1.0f);
        ground_free += voteFreeSpace(ground, scans, votes).free;
        above_free += voteFreeSpace(above, scans, votes).free;
        ++tested;
    }
    CHECK(ground_free == 0);
    // 1 m above the ground the scan saw through: the ring below the point still reaches the
    // ground behind it by more than the margin.
    CHECK(above_free > tested * 99 / 100);
}

TEST_CASE("The vectorised look-ups give each point the votes of the one-point path", "[dynamic]") {
    // dynamicByFreeSpace works on blocks of points with branch-free, vectorised arithmetic
    // (RangeImage::pixelsOf); bracketRange and voteFreeSpace are the plain one-point code. The
    // votes must be the same integers for every point: points on and off the surfaces of three
    // scans of the street, around, above and below the images' rows, at the origin of a scan,
    // on the azimuth seam (+-180 deg), and straight above a sensor.
    test::DynamicSceneOptions o;
    o.frames = 3;
    std::vector<test::DynamicScan> raw;
    std::vector<RangeImage> images;
    for (int f = 0; f < 3; ++f) raw.push_back(test::dynamicScan(o, f * 2));
    for (const auto& r : raw) images.emplace_back(r.points_L, RangeImageConfig{});
    std::vector<VoteScan> first{{&images[0], raw[0].T_W_L.inverse()}, {&images[2], raw[2].T_W_L.inverse()}};
    std::vector<VoteScan> others{{&images[1], raw[1].T_W_L.inverse()}};
    std::vector<Vec3f> points_W;
    std::mt19937 rng(11);
    std::normal_distribution<float> jitter(0.0f, 0.5f);
    for (const auto& r : raw) {
        for (std::size_t i = 0; i < r.points_L.size(); i += 7) {
            const Vec3f p_W = (r.T_W_L * r.points_L[i].cast<double>()).cast<float>();
            points_W.push_back(p_W);
            points_W.push_back(p_W + Vec3f(jitter(rng), jitter(rng), jitter(rng)));
        }
    }
    const Vec3f o0 = raw[0].T_W_L.translation().cast<float>();
    points_W.push_back(o0);                                   // a sensor's origin: no direction
    points_W.push_back(o0 + Vec3f(0.0f, 0.0f, 5.0f));         // straight up: outside the rows
    points_W.push_back(o0 + Vec3f(0.0f, 0.0f, -1.0f));        // straight down
    points_W.push_back(o0 + Vec3f(-10.0f, 0.0f, -1.0f));      // on the azimuth seam
    points_W.push_back(o0 + Vec3f(-10.0f, -1e-6f, -1.0f));
    FreeSpaceVoteConfig config;
    config.min_free_votes = 1;
    std::vector<PointVotes> votes;
    const std::vector<std::uint8_t> dynamic = dynamicByFreeSpace(points_W, first, others, config, nullptr, &votes);
    REQUIRE(votes.size() == points_W.size());
    std::vector<VoteScan> all = first;
    all.insert(all.end(), others.begin(), others.end());
    std::size_t mismatches = 0, seen_free = 0, seen_hit = 0;
    for (std::size_t i = 0; i < points_W.size(); ++i) {
        PointVotes expected = voteFreeSpace(points_W[i], first, config);
        if (needsSecondPass(expected, config)) expected = voteFreeSpace(points_W[i], all, config);
        mismatches += expected.free != votes[i].free || expected.hit != votes[i].hit ||
                      expected.thin != votes[i].thin || dynamic[i] != (isDynamic(expected, config) ? 1 : 0);
        seen_free += expected.free != 0;
        seen_hit += expected.hit != 0;
    }
    CHECK(mismatches == 0);
    // The comparison covers both outcomes.
    CHECK(seen_free > 100);
    CHECK(seen_hit > 100);
    // And the block form of the look-up itself, against bracketRange.
    const RangeImage& image = images[0];
    std::vector<float> x, y, z;
    for (const Vec3f& p_W : points_W) {
        const Vec3f p_L = (raw[0].T_W_L.inverse() * p_W.cast<double>()).cast<float>();
        x.push_back(p_L.x()), y.push_back(p_L.y()), z.push_back(p_L.z());
    }
    std::vector<std::int32_t> pixel(x.size());
    std::vector<float> range(x.size());
    image.pixelsOf(x.data(), y.data(), z.data(), x.size(), pixel.data(), range.data());
    std::size_t differ = 0, outside = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        float d = 0.0f;
        const float b = image.bracketRange(Vec3f(x[i], y[i], z[i]), d);
        outside += b == RangeImage::kOutside;
        const bool same = b == RangeImage::kOutside ? pixel[i] < 0
                                                    : pixel[i] >= 0 && image.bracketAt(pixel[i]) == b;
        differ += !same || d != range[i];
    }
    CHECK(differ == 0);
    CHECK(outside >= 2);
}

TEST_CASE("A box driving along the street is removed; ground, pole and parked box are kept",
          "[dynamic]") {
    const test::DynamicSceneOptions o;
    const std::vector<test::DynamicScan> scans = makeScans(o);
    const fs::path dir = scratch("moving");
    test::writeDynamicDataset(dir, scans);
    const auto dataset = openGeneric(dir);
    DynamicRemovalConfig config;
    const Counts c = detectAll(*dataset, scans, config, 0, o.frames - 1);
    INFO("mover " << c.removed[3] << " / " << c.total[3] << ", ground " << c.removed[0] << " / "
                  << c.total[0] << ", pole " << c.removed[1] << " / " << c.total[1]
                  << ", parked " << c.removed[2] << " / " << c.total[2]);
    REQUIRE(c.total[3] > 1000);
    REQUIRE(c.total[1] > 100);
    WARN("moving box: recall " << c.recall() << " (" << c.removed[3] << " / " << c.total[3]
                               << "), static points removed " << c.staticRemoved() << " / "
                               << c.staticTotal());
    CHECK(c.recall() >= 0.95);
    CHECK(c.removed[0] == 0);
    CHECK(c.removed[1] == 0);
    CHECK(c.removed[2] == 0);
}

TEST_CASE("The thin test: a point 0.25 m in front of a wall that other scans saw is dynamic, the wall not",
          "[dynamic]") {
    // Five scans of a wall (the parked box's face, 5.2 m beside the path, 3 m tall) from
    // x = 28 to 32 m; no mover. A point 0.25 m in front of the wall, where a pedestrian walked at
    // another time, is inside the margin (0.3 m + 0.01 d): the plain test calls every scan a hit.
    // The wall lies behind it by 0.25 m / cos(incidence) >= the thin margin (0.12 m + 0.005 d)
    // for each scan: five thin votes of five, so it is dynamic. A point on the wall, or 0.05 m in
    // front of it (range noise), gets no thin vote.
    test::DynamicSceneOptions o;
    o.parked = {{20.0, -7.0, 0.0}, {45.0, -5.2, 3.0}};
    o.mover_start = {1000.0, 1000.0, 0.0};
    o.pole_height_m = 0.0;
    std::vector<test::DynamicScan> raw;
    std::vector<RangeImage> images;
    for (int f = 28; f <= 32; ++f) raw.push_back(test::dynamicScan(o, f));
    for (const auto& r : raw) images.emplace_back(r.points_L, RangeImageConfig{});
    std::vector<VoteScan> scans;
    for (std::size_t k = 0; k < raw.size(); ++k) scans.push_back({&images[k], raw[k].T_W_L.inverse()});
    FreeSpaceVoteConfig config;  // the defaults: thin test on
    FreeSpaceVoteConfig plain = config;
    plain.thin_margin_m = 0.0;
    int in_front = 0, thin_in_front = 0, on_wall_thin = 0, near_wall_thin = 0, tested = 0;
    for (double x = 29.0; x <= 31.0; x += 0.25) {
        for (double z = 0.5; z <= 1.5; z += 0.25) {
            const auto at = [&](double gap_m) { return Vec3f(static_cast<float>(x), static_cast<float>(-5.2 + gap_m), static_cast<float>(z)); };
            const PointVotes front = voteFreeSpace(at(0.25), scans, config);
            ++tested;
            CHECK(front.free == 0);
            CHECK(front.hit == 5);
            CHECK_FALSE(isDynamic(front, plain));
            in_front += isDynamic(front, config) ? 1 : 0;
            thin_in_front += front.thin;
            const PointVotes wall = voteFreeSpace(at(0.0), scans, config);
            on_wall_thin += wall.thin;
            CHECK_FALSE(isDynamic(wall, config));
            near_wall_thin += voteFreeSpace(at(0.05), scans, config).thin;
        }
    }
    CHECK(in_front == tested);
    CHECK(thin_in_front == 5 * tested);
    CHECK(on_wall_thin == 0);
    CHECK(near_wall_thin == 0);
}

TEST_CASE("The same box parked is kept", "[dynamic]") {
    test::DynamicSceneOptions o;
    o.mover_moves = false;
    const std::vector<test::DynamicScan> scans = makeScans(o);
    const fs::path dir = scratch("parked");
    test::writeDynamicDataset(dir, scans);
    const auto dataset = openGeneric(dir);
    const Counts c = detectAll(*dataset, scans, DynamicRemovalConfig{}, 0, o.frames - 1);
    INFO("box " << c.removed[3] << " / " << c.total[3] << ", static " << c.staticRemoved() << " / "
                << c.staticTotal());
    CHECK(c.removed[3] == 0);
    CHECK(c.staticRemoved() == 0);
}

TEST_CASE("Points labelled with a moving class 252-259 are removed", "[dynamic]") {
    test::DynamicSceneOptions o;
    o.frames = 3;
    const std::vector<test::DynamicScan> scans = makeScans(o);
    SECTION("labels alone (no free-space neighbours) remove exactly the moving-labelled points") {
        const fs::path dir = scratch("labels");
        test::writeDynamicDataset(dir, scans, true, true);
        const auto dataset = openGeneric(dir);
        DynamicRemovalConfig config;
        config.window_frames = 0;
        config.far_frames.clear();
        const Counts c = detectAll(*dataset, scans, config, 0, o.frames - 1);
        CHECK(c.removed[3] == c.total[3]);
        CHECK(c.staticRemoved() == 0);
        config.use_labels = false;
        CHECK(detectAll(*dataset, scans, config, 0, o.frames - 1).removed[3] == 0);
    }
    SECTION("labels without moving classes: nothing removed by label") {
        const fs::path dir = scratch("labels_static");
        test::writeDynamicDataset(dir, scans, true, false);
        const auto dataset = openGeneric(dir);
        DynamicRemovalConfig config;
        config.window_frames = 0;
        config.far_frames.clear();
        CHECK(detectAll(*dataset, scans, config, 0, o.frames - 1).removed[3] == 0);
    }
}

TEST_CASE("Neighbours: the window and the far frames, in frame order without timestamps",
          "[dynamic]") {
    test::DynamicSceneOptions o;
    o.frames = 40;
    o.beams = 4;
    const fs::path dir = scratch("neighbours");
    test::writeDynamicDataset(dir, makeScans(o));
    const auto dataset = openGeneric(dir);
    DynamicRemovalConfig config;  // window 10, stride 2, far 20 and 30
    DynamicDetector detector(*dataset, config);
    CHECK(detector.timeOrder() == "frame_order");
    std::vector<std::size_t> first, others;
    detector.neighbours(15, first, others);
    // Offsets furthest first (-o before +o), those inside the 40 frames: +20, -10, +10, -8 ...
    CHECK(first == std::vector<std::size_t>{35, 5, 25, 7});
    CHECK(others == std::vector<std::size_t>{23, 9, 21, 11, 19, 13, 17});
    // Near the end every one of the four furthest is earlier: the two furthest later ones join
    // the first pass (+4, +2), the others keep the order of the offsets.
    detector.neighbours(35, first, others);
    CHECK(first == std::vector<std::size_t>{5, 15, 25, 27, 39, 37});
    CHECK(others == std::vector<std::size_t>{29, 31, 33});
    CHECK_THROWS_AS(validateDynamicRemovalConfig(
                        [] {
                            DynamicRemovalConfig c;
                            c.window_stride = 0;
                            return c;
                        }(),
                        "integrate.atsdf"),
                    ConfigError);
}

TEST_CASE("dynamic_points.ply round-trips", "[dynamic][io]") {
    DynamicPoints p;
    p.add(Vec3f(1.5f, -2.25f, 3.0f), 7, 123456);
    p.add(Vec3f(-1e3f, 0.0f, 1e-3f), 4000000000u, 0);
    const fs::path dir = scratch("ply");
    writeDynamicPointsPly(dir / "dynamic_points.ply", p);
    const DynamicPoints q = readDynamicPointsPly(dir / "dynamic_points.ply");
    REQUIRE(q.size() == 2);
    CHECK(q.points_W == p.points_W);
    CHECK(q.frame == p.frame);
    CHECK(q.index == p.index);
    const std::string bytes = dynamicPointsPly(p);
    CHECK(bytes.find("format binary_little_endian 1.0\n") != std::string::npos);
    CHECK(bytes.find("property float x\nproperty float y\nproperty float z\nproperty uint frame\n"
                     "property uint index\nend_header\n") != std::string::npos);
    // Empty: a valid file with 0 vertices.
    writeDynamicPointsPly(dir / "empty.ply", DynamicPoints{});
    CHECK(readDynamicPointsPly(dir / "empty.ply").size() == 0);
    // Truncated: an IoError naming the file.
    {
        std::ofstream out(dir / "cut.ply", std::ios::binary);
        out << bytes.substr(0, bytes.size() - 3);
    }
    CHECK_THROWS_AS(readDynamicPointsPly(dir / "cut.ply"), IoError);
}
