// SPDX-License-Identifier: Apache-2.0
// The pose-based tile plan of streamed and distributed runs (issue 13): which tiles a scan
// can reach, which frames each tile needs, when it can be finished, and the split over
// processes, against brute-force oracles.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <numeric>
#include <random>
#include <set>

#include "pipeline/PointRegion.h"
#include "support/CliRun.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/pipeline/TilePlan.h"
#include "vdbmap/render/ViewFrustum.h"

namespace fs = std::filesystem;
using namespace vdbmap;

namespace {

/// The largest part of a partition.
double largestPart(const std::vector<double>& costs, const std::vector<int>& parts, int n) {
    std::vector<double> sums(static_cast<std::size_t>(n), 0.0);
    for (std::size_t i = 0; i < costs.size(); ++i) sums[static_cast<std::size_t>(parts[i])] += costs[i];
    return *std::max_element(sums.begin(), sums.end());
}

/// Brute force: the smallest largest part over every way of cutting into <= n contiguous runs.
double bestLargestPart(const std::vector<double>& costs, int n) {
    const std::size_t m = costs.size();
    double best = std::numeric_limits<double>::max();
    // Each of the m - 1 gaps is a cut or not; at most n - 1 cuts.
    for (std::uint32_t cuts = 0; cuts < (1u << (m - 1)); ++cuts) {
        if (static_cast<int>(__builtin_popcount(cuts)) > n - 1) continue;
        double run = 0.0, largest = 0.0;
        for (std::size_t i = 0; i < m; ++i) {
            if (i > 0 && (cuts & (1u << (i - 1)))) run = 0.0;
            run += costs[i];
            largest = std::max(largest, run);
        }
        best = std::min(best, largest);
    }
    return best;
}

double groundDistance(double g0, double g1, double min0, double min1, double max0, double max1) {
    const double d0 = std::max({min0 - g0, 0.0, g0 - max0});
    const double d1 = std::max({min1 - g1, 0.0, g1 - max1});
    return std::sqrt(d0 * d0 + d1 * d1);
}

/// The simulated street `name` (frames, size) below test_scratch/tile_plan, written once, opened.
std::shared_ptr<Dataset> simStreet(const std::string& name, std::size_t frames, double size_m) {
    setLogLevel(LogLevel::Warn);
    const fs::path dir = fs::path(VDBMAP_BINARY_DIR) / "test_scratch" / "tile_plan" / name;
    test::writeSimStreet(dir, frames, size_m);
    DatasetConfig config;
    config.path = dir.string();
    return Dataset::open(config);
}

/// Tiles of `tile_size_m` with a 1 m halo and a 3 m occluder margin.
TilingConfig smallMargins(double tile_size_m) {
    TilingConfig tiling;
    tiling.tile_size_m = tile_size_m;
    tiling.halo_m = 1.0;
    tiling.occluder_margin_m = 3.0;
    return tiling;
}

}  // namespace

TEST_CASE("partitionContiguous: the smallest largest part, every process busy", "[tiles]") {
    CHECK(partitionContiguous({1, 1, 1, 1}, 2) == std::vector<int>{0, 0, 1, 1});
    CHECK(partitionContiguous({5, 1, 1, 1, 1, 1}, 2) == std::vector<int>{0, 1, 1, 1, 1, 1});
    CHECK(partitionContiguous({1, 2, 3}, 5) == std::vector<int>{0, 1, 2});
    CHECK(partitionContiguous({}, 3).empty());
    CHECK(partitionContiguous({4, 4}, 1) == std::vector<int>{0, 0});
    CHECK_THROWS_AS(partitionContiguous({1.0}, 0), InvalidInput);
    // Four equal items on three processes: largest part 2, and no process idle.
    const std::vector<int> three = partitionContiguous({1, 1, 1, 1}, 3);
    CHECK(std::set<int>(three.begin(), three.end()).size() == 3);
    CHECK(largestPart({1, 1, 1, 1}, three, 3) == Approx(2.0));

    std::mt19937 rng(7);
    std::uniform_real_distribution<double> cost(0.1, 10.0);
    for (int trial = 0; trial < 300; ++trial) {
        const std::size_t m = 1 + rng() % 9;
        const int n = 1 + static_cast<int>(rng() % 4);
        std::vector<double> costs(m);
        for (double& c : costs) c = cost(rng);
        const std::vector<int> parts = partitionContiguous(costs, n);
        REQUIRE(parts.size() == m);
        CHECK(parts.front() == 0);
        for (std::size_t i = 1; i < m; ++i) {
            CHECK(parts[i] >= parts[i - 1]);  // contiguous runs in order
            CHECK(parts[i] <= parts[i - 1] + 1);
        }
        CHECK(parts.back() < n);
        // Every process gets an item when there are enough of them.
        CHECK(parts.back() + 1 == std::min<int>(n, static_cast<int>(m)));
        CHECK(largestPart(costs, parts, n) == Approx(bestLargestPart(costs, n)).epsilon(1e-6));
    }
}

TEST_CASE("planTiles: tiles and scan frames are those a scan's reach gives", "[tiles]") {
    const auto dataset = simStreet("seq", 12, 60.0);
    const TilingConfig tiling = smallMargins(6.4);
    const int up = TileGrid::resolveUpAxis(tiling, dataset.get());
    CHECK(up == 1);  // KITTI W: y is up-down
    const TileGrid grid(tiling, 0.1, up);
    TilePlanOptions options;
    options.scan_reach_m = 12.0;
    options.max_view_distance_m = 15.0;
    options.processes = 3;
    const TilePlan plan = planTiles(grid, *dataset, options);
    REQUIRE(plan.tiles.size() > 6);

    // Oracle: a tile exists iff some frame's sensor lies within the reach of its core; its
    // frames are those within the reach of the core grown by the occluder margin + 1 voxel.
    const double s = grid.tileSizeM();
    const double grow = (grid.occluderVoxels() + 1) * 0.1;
    const int a0 = grid.groundAxis(0), a1 = grid.groundAxis(1);
    std::size_t expected_tiles = 0;
    for (int iy = -20; iy <= 20; ++iy) {
        for (int ix = -20; ix <= 20; ++ix) {
            bool reached = false;
            std::vector<std::size_t> frames;
            for (std::size_t i = 0; i < dataset->numFrames(); ++i) {
                const Eigen::Vector3d o = dataset->frame(i).T_W_L.translation();
                if (groundDistance(o[a0], o[a1], ix * s, iy * s, (ix + 1) * s, (iy + 1) * s) <= 12.0)
                    reached = true;
                if (groundDistance(o[a0], o[a1], ix * s - grow, iy * s - grow, (ix + 1) * s + grow,
                                   (iy + 1) * s + grow) <= 12.0)
                    frames.push_back(i);
            }
            const PlannedTile* t = plan.find(ix, iy);
            INFO("tile " << ix << "_" << iy);
            CHECK((t != nullptr) == reached);
            if (!reached || t == nullptr) continue;
            ++expected_tiles;
            CHECK(t->scan_frames == frames);
            CHECK(t->finish_frame >= frames.back());
            CHECK(t->finish_frame < dataset->numFrames());
            // The cost features: the frames near the tile, weighted by their distance.
            double weighted = 0.0;
            for (std::size_t i = 0; i < dataset->numFrames(); ++i) {
                const Eigen::Vector3d o = dataset->frame(i).T_W_L.translation();
                if (groundDistance(o[a0], o[a1], ix * s - grow, iy * s - grow, (ix + 1) * s + grow,
                                   (iy + 1) * s + grow) > 12.0)
                    continue;
                const double d = groundDistance(o[a0], o[a1], ix * s, iy * s, (ix + 1) * s, (iy + 1) * s);
                weighted += std::exp(-d * d / (2.0 * 20.0 * 20.0));
            }
            CHECK(t->weighted_frames == Approx(weighted));
            CHECK(t->cost == Approx(tileCostEstimate(t->weighted_frames, t->views)));
            CHECK(t->cost > 0.0);
        }
    }
    CHECK(plan.tiles.size() == expected_tiles);

    // Finish order; processes in contiguous runs of it; each process's frames are the union
    // of its tiles' frames, and a stretch of the drive, not all of it (the middle process's
    // stretch may be all of this short drive).
    std::size_t total_tiles = 0, partial = 0;
    for (std::size_t i = 1; i < plan.tiles.size(); ++i) {
        CHECK(plan.tiles[i].finish_frame >= plan.tiles[i - 1].finish_frame);
        CHECK(plan.tiles[i].process >= plan.tiles[i - 1].process);
    }
    for (int p = 0; p < 3; ++p) {
        std::set<std::size_t> expected;
        for (const PlannedTile& t : plan.tiles)
            if (t.process == p) expected.insert(t.scan_frames.begin(), t.scan_frames.end());
        const std::vector<std::size_t> frames = plan.framesOf(p);
        CHECK(std::vector<std::size_t>(expected.begin(), expected.end()) == frames);
        CHECK(plan.tilesOf(p) > 0);
        partial += frames.size() < dataset->numFrames() ? 1 : 0;
        total_tiles += plan.tilesOf(p);
    }
    CHECK(partial >= 2);
    CHECK(total_tiles == plan.tiles.size());

    // The last view that may see a tile (frustum and distance against its halo box at every
    // height a scan reaches) is no later than its finish frame.
    const std::vector<View> views = datasetViews(*dataset, false, false);
    REQUIRE_FALSE(views.empty());
    double up_min = 1e9, up_max = -1e9;
    for (std::size_t i = 0; i < dataset->numFrames(); ++i) {
        up_min = std::min(up_min, dataset->frame(i).T_W_L.translation()[up]);
        up_max = std::max(up_max, dataset->frame(i).T_W_L.translation()[up]);
    }
    // Its views (a cost feature) are those.
    std::size_t with_views = 0;
    for (const PlannedTile& t : plan.tiles) {
        Tile tile = grid.tile(t.ix, t.iy);
        tile.halo_W.min_W[up] = up_min - 12.0;
        tile.halo_W.max_W[up] = up_max + 12.0;
        TileGrid::assignViews(tile, views, 15.0);
        for (const auto& [frame, camera] : tile.views) CHECK(frame <= t.finish_frame);
        CHECK(t.views == tile.views.size());
        with_views += t.views > 0 ? 1 : 0;
    }
    CHECK(with_views > 3);

    // Unstreamed: every tile waits for the last frame.
    options.stream = false;
    for (const PlannedTile& t : planTiles(grid, *dataset, options).tiles) {
        CHECK(t.finish_frame == dataset->numFrames() - 1);
    }
    options.scan_reach_m = -1.0;
    CHECK_THROWS_AS(planTiles(grid, *dataset, options), InvalidInput);
}

TEST_CASE("planTiles: tiles cut into pieces until the work spreads over split_for_processes",
          "[tiles]") {
    // Issue 37: 8 processes on a 100 m street of 51.2 m tiles (a handful of tiles of uneven
    // work): the costliest tiles are cut into TileGrid::split's pieces, which take their
    // tile's place in the finish order and share its cost by the frames near their own core.
    const auto dataset = simStreet("seq_long", 50, 100.0);
    const TilingConfig tiling = smallMargins(51.2);
    const int up = TileGrid::resolveUpAxis(tiling, dataset.get());
    const TileGrid grid(tiling, 0.1, up);
    TilePlanOptions options;
    options.scan_reach_m = 30.0;
    options.max_view_distance_m = 40.0;
    options.processes = 8;
    const TilePlan whole = planTiles(grid, *dataset, options);  // split_for_processes 1: none
    CHECK(whole.pieces() == 0);
    for (const PlannedTile& t : whole.tiles) CHECK(t.piece.empty());
    std::vector<double> whole_costs;
    for (const PlannedTile& t : whole.tiles) whole_costs.push_back(t.cost);
    const double total = std::accumulate(whole_costs.begin(), whole_costs.end(), 0.0);
    const double even = total / 8.0;
    const double whole_largest = largestPart(whole_costs, partitionContiguous(whole_costs, 8), 8);
    INFO("tiles " << whole.tiles.size() << ", largest " << whole_largest << " s, even " << even << " s");
    REQUIRE(whole_largest > 1.25 * even);  // the tiles alone cannot be spread evenly

    options.split_for_processes = 8;
    const TilePlan cut = planTiles(grid, *dataset, options);
    REQUIRE(cut.pieces() > 0);
    std::vector<double> costs;
    for (const PlannedTile& t : cut.tiles) costs.push_back(t.cost);
    const double largest = largestPart(costs, partitionContiguous(costs, 8), 8);
    CHECK(largest < whole_largest);
    CHECK(std::accumulate(costs.begin(), costs.end(), 0.0) == Approx(total));
    // Every process has work now.
    for (int p = 0; p < 8; ++p) CHECK(cut.tilesOf(p) > 0);
    // Pieces are not cut again; each cut makes the grain finer (no piece keeps more than 0.8
    // of its tile's cost).
    for (const PlannedTile& t : cut.tiles) {
        CHECK(t.piece.find('.') == std::string::npos);
        if (t.piece.empty()) continue;
        const PlannedTile* w = whole.find(t.ix, t.iy);
        REQUIRE(w != nullptr);
        CHECK(t.cost <= 0.8 * w->cost * (1.0 + 1e-9));
    }

    // Each whole tile is there whole or as consecutive pieces whose cores partition its core,
    // with its frames, finish frame and cost (shared by the pieces' own weighted frames).
    const int a0 = grid.groundAxis(0), a1 = grid.groundAxis(1);
    std::size_t at = 0;
    for (const PlannedTile& w : whole.tiles) {
        REQUIRE(at < cut.tiles.size());
        double area = 0.0, cost = 0.0;
        const Tile wt = grid.tile(w.ix, w.iy);
        const std::size_t first = at;
        while (at < cut.tiles.size() && cut.tiles[at].ix == w.ix && cut.tiles[at].iy == w.iy) {
            const PlannedTile& p = cut.tiles[at++];
            INFO(p.name());
            CHECK(p.scan_frames == w.scan_frames);
            CHECK(p.finish_frame == w.finish_frame);
            const Tile pt = grid.piece(p.ix, p.iy, p.piece);
            CHECK(pt.name() == p.name());
            for (int k = 0; k < 2; ++k) {
                CHECK(pt.region.core_min[k] >= wt.region.core_min[k]);
                CHECK(pt.region.core_max[k] <= wt.region.core_max[k]);
                CHECK(pt.region.core_min[k] % 8 == 0);
            }
            area += double(pt.region.core_max[0] - pt.region.core_min[0]) *
                    double(pt.region.core_max[1] - pt.region.core_min[1]);
            cost += p.cost;
            // Oracle for the piece's weighted frames: the frames near its own core.
            double weighted = 0.0;
            for (std::size_t f : p.scan_frames) {
                const Eigen::Vector3d o = dataset->frame(f).T_W_L.translation();
                const double d = groundDistance(o[a0], o[a1], pt.core_W.min_W[a0], pt.core_W.min_W[a1],
                                                pt.core_W.max_W[a0], pt.core_W.max_W[a1]);
                weighted += std::exp(-d * d / (2.0 * 20.0 * 20.0));
            }
            CHECK(p.weighted_frames == Approx(weighted));
        }
        REQUIRE(at > first);
        CHECK(area == Approx(double(wt.region.core_max[0] - wt.region.core_min[0]) *
                             double(wt.region.core_max[1] - wt.region.core_min[1])));
        CHECK(cost == Approx(w.cost));
    }
    CHECK(at == cut.tiles.size());

    // The pieces depend on split_for_processes alone: a one-process plan makes the same ones.
    options.processes = 1;
    const TilePlan single = planTiles(grid, *dataset, options);
    REQUIRE(single.tiles.size() == cut.tiles.size());
    for (std::size_t i = 0; i < cut.tiles.size(); ++i) {
        CHECK(single.tiles[i].name() == cut.tiles[i].name());
        CHECK(single.tiles[i].process == 0);
    }
    // The first piece of a tile stands for it (its process owns the tile's map leaves).
    for (const PlannedTile& t : cut.tiles) CHECK(cut.find(t.ix, t.iy)->piece <= t.piece);

    // A path split() does not make.
    const PlannedTile& any = cut.tiles.front();
    CHECK_THROWS_AS(grid.piece(any.ix, any.iy, "4"), InvalidInput);
    CHECK_THROWS_AS(grid.piece(any.ix, any.iy, "x"), InvalidInput);
    CHECK_THROWS_AS(grid.piece(any.ix, any.iy, "0."), InvalidInput);
    CHECK(grid.piece(any.ix, any.iy, "").name() == grid.tile(any.ix, any.iy).name());
}

TEST_CASE("PointRegion: a process keeps the points within reach of its tiles' regions", "[tiles]") {
    // 64 m tiles at 0.1 m, occluder margin 30 m: a tile needs its core grown by 30.1 m (the
    // occluder voxels and one); the region adds the update reach (5 m) and one leaf (0.8 m).
    TilingConfig config;
    config.tile_size_m = 64.0;
    config.halo_m = 4.0;
    config.occluder_margin_m = 30.0;
    const TileGrid grid(config, 0.1, 2);
    TilePlan plan;
    for (int ix = 0; ix < 4; ++ix) {
        PlannedTile t;
        t.ix = ix;
        t.process = ix < 2 ? 0 : 1;  // process 0: x in [0, 128), process 1: x in [128, 256)
        plan.tiles.push_back(t);
    }
    const double grow = 30.1 + 5.0 + 0.8;
    const detail::PointRegion p0(grid, plan, 0, 5.0), p1(grid, plan, 1, 5.0);
    CHECK(p0.rectangles() == 2);
    CHECK(p1.rectangles() == 2);
    const auto at = [](double x, double y) { return Vec3f(float(x), float(y), 123.f); };
    CHECK(p0.contains(at(10, 10)));
    CHECK_FALSE(p1.contains(at(10, 10)));
    // Either side of each rectangle's edge, on both ground axes; the up coordinate is free.
    CHECK(p0.contains(at(128 + grow - 0.01, 32)));
    CHECK_FALSE(p0.contains(at(128 + grow + 0.01, 32)));
    CHECK(p0.contains(at(-grow + 0.01, 32)));
    CHECK_FALSE(p0.contains(at(-grow - 0.01, 32)));
    CHECK(p0.contains(at(32, 64 + grow - 0.01)));
    CHECK_FALSE(p0.contains(at(32, 64 + grow + 0.01)));
    CHECK(p1.contains(at(128 - grow + 0.01, -grow + 0.01)));
    CHECK_FALSE(p1.contains(at(128 - grow - 0.01, 0)));
    // Both processes keep the points between their tiles that both need.
    CHECK(p0.contains(at(128, 0)));
    CHECK(p1.contains(at(128, 0)));
    // A process without tiles keeps nothing.
    const detail::PointRegion p2(grid, plan, 2, 5.0);
    CHECK(p2.rectangles() == 0);
    CHECK_FALSE(p2.contains(at(10, 10)));
}
