// SPDX-License-Identifier: Apache-2.0
// Moving objects out of the map, the tracks of objects (issue 33, docs/dynamic.md "Tracks" and
// "Joined objects"), on closed-form windows of objects: the velocity from the faces that moved
// together, a static object of the track's size that does not take a mover's track, a part
// that grows the box, parts taken by tracks that are not moving, and the split of a mover
// joined to a static object by the static evidence.
#include <catch2/catch.hpp>

#include <cmath>

#include "vdbmap/dynamic/JoinedObjects.h"
#include "vdbmap/dynamic/ObjectTracks.h"
#include "vdbmap/dynamic/StaticColumns.h"

using namespace vdbmap;

namespace {

/// An object with the box [lo, hi] (W, z up), its centroid the box's centre, its extent the
/// box's horizontal diagonal.
ScanCluster object(const Vec3d& lo, const Vec3d& hi, bool confirmed, std::uint32_t points = 100,
                   std::uint32_t static_points = 0) {
    ScanCluster c;
    c.min_W = lo;
    c.max_W = hi;
    c.centroid_W = 0.5 * (lo + hi);
    c.extent_m = static_cast<float>(std::hypot(hi.x() - lo.x(), hi.y() - lo.y()));
    c.compact = true;
    c.confirmed = confirmed;
    c.points = points;
    c.static_points = static_points;
    return c;
}

std::vector<const std::vector<ScanCluster>*> windowOf(const std::vector<std::vector<ScanCluster>>& scans) {
    std::vector<const std::vector<ScanCluster>*> window;
    for (const auto& scan : scans) window.push_back(&scan);
    return window;
}

/// The long side of a van 4.8 m long driving along -x 0.5 m per scan, seen from y < 10: a
/// slab at y 10..10.2, 2.2 m high.
ScanCluster vanSide(int s, bool confirmed) {
    const double x = -0.5 * s;
    return object({x - 2.4, 10.0, 0.0}, {x + 2.4, 10.2, 2.2}, confirmed);
}

}  // namespace

TEST_CASE("ObjectTracks: the velocity comes from the faces that moved together, not the box centres",
          "[dynamic][objects]") {
    // Scans 0..3: the van's side, moving by its own points. Scan 4: the side and 1.3 m of
    // something in front of it (the box grows toward the sensor; the far face stays). Scans
    // 5..10: the van joined to a parked car in front of it (larger than the track: the box moves
    // on by the velocity). Scan 11: the van's side alone, not moving by its own points. The
    // centre of the box stepped 0.65 m toward the sensor at scan 4; a velocity from it carries
    // the box 2 m off the van in 6 scans, beyond the 1.5 m gate, and the van is lost.
    std::vector<std::vector<ScanCluster>> scans;
    for (int s = 0; s <= 3; ++s) scans.push_back({vanSide(s, true)});
    ScanCluster grown = vanSide(4, true);
    grown.min_W.y() -= 1.3;
    grown.centroid_W = 0.5 * (grown.min_W + grown.max_W);
    grown.extent_m = static_cast<float>(std::hypot(4.8, 1.5));
    scans.push_back({grown});
    for (int s = 5; s <= 10; ++s) {
        ScanCluster joined = vanSide(s, false);
        joined.min_W.y() = 5.0;  // the parked car, 5 m deep in front of it
        joined.centroid_W = 0.5 * (joined.min_W + joined.max_W);
        joined.extent_m = static_cast<float>(std::hypot(4.8, 5.2));
        scans.push_back({joined});
    }
    scans.push_back({vanSide(11, false)});
    std::vector<TrackBox> boxes;
    CHECK(movingObjects(windowOf(scans), ObjectTrackConfig{}, &boxes) == std::vector<std::uint8_t>{1});
    REQUIRE(boxes.size() == 1);
    // The box is the van's side at scan 11, to the step of the faces (0.5 m per scan along -x).
    CHECK((boxes[0].min_W - vanSide(11, false).min_W).norm() < 1e-9);
    CHECK((boxes[0].max_W - vanSide(11, false).max_W).norm() < 1e-9);
}

TEST_CASE("ObjectTracks: a static object of the track's size does not take a mover's track",
          "[dynamic][objects]") {
    // The van's side in scans 0..5 (moving by its own points in 0..3). In scan 6 the sensor is
    // beside the van and sees its end face (x = its front, 2 m along y) apart from the side, and
    // a parked car in front of the van (4.4 m long, the van side's size) whose box touches the
    // track's box and whose centroid is nearer the track's than the end face's. Most of the
    // parked car's points were hit by earlier scans and never seen through.
    std::vector<std::vector<ScanCluster>> scans;
    for (int s = 0; s <= 5; ++s) scans.push_back({vanSide(s, s <= 3)});
    const double x6 = -0.5 * 6;
    const ScanCluster end_face = object({x6 - 2.4, 10.0, 0.0}, {x6 - 2.3, 12.0, 2.2}, false);
    const ScanCluster parked = object({x6 - 1.0, 8.2, 0.0}, {x6 + 3.4, 10.0, 1.5}, false, 1000, 900);
    scans.push_back({end_face, parked});
    REQUIRE(std::abs(parked.extent_m - vanSide(6, false).extent_m) < 0.2f * vanSide(6, false).extent_m);
    ObjectTrackConfig config;
    CHECK(movingObjects(windowOf(scans), config) == std::vector<std::uint8_t>{1, 0});
    // The static share off: the parked car, nearer, takes the track (and the van's end face is
    // then 1.4 m from the parked car's box: not a part).
    config.static_share = 2.0;
    CHECK(movingObjects(windowOf(scans), config) == std::vector<std::uint8_t>{0, 1});
    // Moving by its own points, an object takes a track whatever its static share.
    config.static_share = 0.5;
    scans[6][1].confirmed = true;
    CHECK(movingObjects(windowOf(scans), config)[1] == 1);
}

TEST_CASE("ObjectTracks: a part reaching out of the track's box grows it, as far as the object's size",
          "[dynamic][objects]") {
    // The van's side in scans 0..5; in scan 6 its end face alone (a part: smaller), which lies
    // 1.8 m behind the side the box was made of. The box grows to the van's footprint (4.8 x 2
    // m: the diagonal of the box grows from 5.28 to 5.65 m, within 20 %).
    std::vector<std::vector<ScanCluster>> scans;
    for (int s = 0; s <= 5; ++s) scans.push_back({vanSide(s, s <= 3)});
    const double x6 = -0.5 * 6;
    scans.push_back({object({x6 - 2.4, 10.0, 0.0}, {x6 - 2.3, 12.0, 2.2}, false)});
    std::vector<TrackBox> boxes;
    CHECK(movingObjects(windowOf(scans), ObjectTrackConfig{}, &boxes) == std::vector<std::uint8_t>{1});
    REQUIRE(boxes.size() == 1);
    CHECK(boxes[0].min_W.y() == Approx(10.0));
    CHECK(boxes[0].max_W.y() == Approx(12.0));
    CHECK(boxes[0].min_W.x() == Approx(x6 - 2.4));
    CHECK(boxes[0].max_W.x() == Approx(x6 + 2.4));

    // A pedestrian (0.4 x 0.4 x 1.7 m) walking 0.3 m per scan along +x; in scan 6 something
    // 0.1 m wide, 1 m beside it, continues its track (within the gate, smaller): the box would
    // grow from 1.79 to 2.30 m across, more than the pedestrian's size. It stays the
    // pedestrian's box, moved by the velocity.
    auto walker = [](int s) {
        const double x = 0.3 * s;
        return object({x, 0.0, 0.0}, {x + 0.4, 0.4, 1.7}, true);
    };
    scans.clear();
    for (int s = 0; s <= 5; ++s) scans.push_back({walker(s)});
    scans.push_back({object({0.3 * 6, 1.4, 0.0}, {0.3 * 6 + 0.1, 1.5, 1.7}, false)});
    boxes.clear();
    CHECK(movingObjects(windowOf(scans), ObjectTrackConfig{}, &boxes) == std::vector<std::uint8_t>{1});
    REQUIRE(boxes.size() == 1);
    CHECK((boxes[0].min_W - walker(6).min_W).norm() < 1e-9);
    CHECK((boxes[0].max_W - walker(6).max_W).norm() < 1e-9);
}

TEST_CASE("ObjectTracks: an object a track that is not moving took can be a part of a mover",
          "[dynamic][objects]") {
    // A car seen from behind drives 2.5 m per scan along +x: its cabin (z 0.8..1.5) moves by its
    // own points in scans 0..4, its body under it (z 0.2..0.8, 0.8 m nearer the sensor) only in
    // scan 3, which starts a track of its own that never confirms again. In scan 5 neither moves
    // by its own points; the cabin continues the moving track and the body its own track, 0.6 m
    // from the cabin's box: the body is a part of the mover (part_gate_m 1 m here).
    auto cabin = [](int s, bool confirmed) {
        const double x = 2.5 * s;
        return object({x, -0.85, 0.8}, {x + 0.2, 0.85, 1.5}, confirmed);
    };
    auto body = [](int s, bool confirmed) {
        const double x = 2.5 * s - 0.8;
        return object({x, -0.9, 0.2}, {x + 0.2, 0.9, 0.8}, confirmed);
    };
    std::vector<std::vector<ScanCluster>> scans;
    for (int s = 0; s <= 4; ++s) {
        if (s == 3) {
            scans.push_back({cabin(s, true), body(s, true)});
        } else {
            scans.push_back({cabin(s, true)});
        }
    }
    scans.push_back({cabin(5, false), body(5, false)});
    ObjectTrackConfig config;
    config.part_gate_m = 1.0;
    CHECK(movingObjects(windowOf(scans), config) == std::vector<std::uint8_t>{1, 1});
    config.part_gate_m = 0.5;  // 0.6 m away: not a part
    CHECK(movingObjects(windowOf(scans), config) == std::vector<std::uint8_t>{1, 0});
}

TEST_CASE("ObjectTracks: an object larger than the track's, continuing it, is marked joined",
          "[dynamic][objects]") {
    // The van's side in scans 0..5; in scan 6 joined to a parked car in front of it.
    std::vector<std::vector<ScanCluster>> scans;
    for (int s = 0; s <= 5; ++s) scans.push_back({vanSide(s, s <= 3)});
    ScanCluster joined = vanSide(6, false);
    joined.min_W.y() = 5.0;
    joined.centroid_W = 0.5 * (joined.min_W + joined.max_W);
    joined.extent_m = static_cast<float>(std::hypot(4.8, 5.2));
    scans.push_back({joined, vanSide(6, false)});
    scans[6][1].min_W.x() += 100.0;  // a second object far away: neither joined nor moving
    scans[6][1].max_W.x() += 100.0;
    scans[6][1].centroid_W.x() += 100.0;
    std::vector<std::uint8_t> flags;
    CHECK(movingObjects(windowOf(scans), ObjectTrackConfig{}, nullptr, &flags) == std::vector<std::uint8_t>{1, 0});
    CHECK(flags == std::vector<std::uint8_t>{1, 0});
    // The whole van again (the track's size): continued, not joined.
    scans[6][0] = vanSide(6, false);
    CHECK(movingObjects(windowOf(scans), ObjectTrackConfig{}, nullptr, &flags) == std::vector<std::uint8_t>{1, 0});
    CHECK(flags == std::vector<std::uint8_t>{0, 0});
}

TEST_CASE("moverOfJoined: the points not kept connected to a seed through points not kept",
          "[dynamic][objects]") {
    // Points on a line along x, 0.1 m apart, voxels of 0.2 m: x = 0.0 .. 0.9 the mover (not
    // kept), 1.0 .. 1.9 a parked car's bumper (kept), 2.0 .. 2.3 a part of the car no scan saw
    // before (not kept, but joined to the mover only through kept points), then a gap of
    // 0.6 m and 2.9 .. 3.0 not kept. The seed: the point at x = 0.4.
    std::vector<Vec3f> points;
    std::vector<std::size_t> members;
    std::vector<std::uint8_t> seed, kept;
    for (int k = 0; k <= 30; ++k) {
        if (k >= 24 && k <= 28) continue;
        const float x = 0.1f * static_cast<float>(k) + 0.05f;
        points.emplace_back(x, 0.05f, 0.05f);
        members.push_back(points.size() - 1);
        seed.push_back(k == 4);
        kept.push_back(k >= 10 && k <= 19);
    }
    const std::vector<std::uint8_t> mover = moverOfJoined(points, members, seed, kept, 0.2f);
    for (std::size_t m = 0; m < members.size(); ++m) {
        const double x = points[members[m]].x();
        INFO("x " << x);
        CHECK(mover[m] == (x < 1.0 ? 1 : 0));
    }
    // Static evidence for none of the bumper: the mover reaches through it to the far part, but
    // not over the 0.6 m gap (two empty voxels) to x = 2.9.
    for (std::size_t m = 0; m < members.size(); ++m) kept[m] = 0;
    const std::vector<std::uint8_t> bridged = moverOfJoined(points, members, seed, kept, 0.2f);
    for (std::size_t m = 0; m < members.size(); ++m) {
        const double x = points[members[m]].x();
        INFO("x " << x);
        CHECK(bridged[m] == (x < 2.4 ? 1 : 0));
    }
    // No seed: nothing.
    std::fill(seed.begin(), seed.end(), 0);
    const std::vector<std::uint8_t> none = moverOfJoined(points, members, seed, kept, 0.2f);
    CHECK(std::count(none.begin(), none.end(), 1) == 0);
}

TEST_CASE("staticColumns: a thin, tall part of the kept points, apart from the rest", "[dynamic]") {
    // A van's long side (the plane y = 0, 4 m long, 2 m tall, sampled every 0.05 m) and a pole
    // (0.12 m square, 1.8 m tall) 0.15 m in front of it, in the sensor frame (z up). The pole's
    // points are kept; of the side, a 1 m stretch is kept too (a side sliding along itself),
    // the rest not. Only the pole is a column: the kept stretch is 1 m long, the side's other
    // points are not kept, and the pole stands apart from the kept stretch (0.15 m: more than
    // a 0.1 m voxel's neighbourhood).
    std::vector<Vec3f> points;
    std::vector<std::uint8_t> kept, pole;
    for (int i = 0; i <= 80; ++i) {
        for (int k = 0; k <= 40; ++k) {
            const float x = 0.05f * static_cast<float>(i), z = 0.05f * static_cast<float>(k);
            points.emplace_back(x, 0.0f, z);
            kept.push_back(x >= 1.0f && x <= 2.0f);
            pole.push_back(0);
        }
    }
    for (int i = 0; i <= 3; ++i) {
        for (int j = 0; j <= 3; ++j) {
            for (int k = 0; k <= 36; ++k) {
                points.emplace_back(1.5f + 0.04f * static_cast<float>(i), -0.15f - 0.04f * static_cast<float>(j),
                                    0.05f * static_cast<float>(k));
                kept.push_back(1);
                pole.push_back(1);
            }
        }
    }
    std::vector<std::size_t> members(points.size());
    for (std::size_t m = 0; m < members.size(); ++m) members[m] = m;
    const std::vector<std::uint8_t> column = staticColumns(points, members, kept, 0.1f, 0.4f, 1.0f);
    REQUIRE(column.size() == points.size());
    std::size_t pole_columns = 0, other_columns = 0;
    for (std::size_t m = 0; m < points.size(); ++m) (pole[m] ? pole_columns : other_columns) += column[m];
    CHECK(pole_columns == 4u * 4u * 37u);
    CHECK(other_columns == 0);

    // With 0.2 m voxels the pole touches the kept stretch: one part, 1 m long, no column.
    const std::vector<std::uint8_t> coarse = staticColumns(points, members, kept, 0.2f, 0.4f, 1.0f);
    CHECK(std::count(coarse.begin(), coarse.end(), 1) == 0);
    // A pole shorter than the least height is no column.
    const std::vector<std::uint8_t> tall = staticColumns(points, members, kept, 0.1f, 0.4f, 2.0f);
    CHECK(std::count(tall.begin(), tall.end(), 1) == 0);
    // Only members count: without the pole among them, nothing.
    std::vector<std::size_t> side;
    std::vector<std::uint8_t> side_kept;
    for (std::size_t m = 0; m < points.size(); ++m) {
        if (pole[m]) continue;
        side.push_back(m);
        side_kept.push_back(kept[m]);
    }
    const std::vector<std::uint8_t> none = staticColumns(points, side, side_kept, 0.1f, 0.4f, 1.0f);
    CHECK(std::count(none.begin(), none.end(), 1) == 0);
}
