// SPDX-License-Identifier: Apache-2.0
// integrateDataset: the scans of a dataset into the integrator, each read (and its rings
// estimated) while the one before is integrated, into the storage of the scan before that.
#include <catch2/catch.hpp>
#include <tbb/task_arena.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <utility>
#include <vector>

#include "support/MapTestUtil.h"
#include "support/PlainAtsdfConfig.h"
#include "unit/IoTestUtil.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/map/AtsdfIntegrator.h"
#include "vdbmap/map/IntegrateDataset.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/sim/SimSequence.h"

using namespace vdbmap;
using vdbmap::test::plainAtsdfConfig;
using openvdb::Coord;

namespace {

using test::voxelsOf;

/// A simulated street without images in `folder`, and its dataset.
std::shared_ptr<Dataset> simStreet(const std::filesystem::path& folder, std::size_t frames,
                                   double size_m, std::uint64_t seed, double max_range_m) {
    SimOptions o;
    o.scene = "street";
    o.frames = frames;
    o.size_m = size_m;
    o.seed = seed;
    o.gt_views = 0;
    o.images = false;
    o.quiet = true;
    REQUIRE(writeSimSequence(o, folder).frames == frames);
    DatasetConfig dc;
    dc.path = folder.string();
    dc.max_range_m = max_range_m;
    return Dataset::open(dc);
}

struct Run {
    std::vector<std::pair<Coord, std::uint32_t>> voxels;
    IntegrationStats totals;
    DatasetIntegration read;
    std::vector<std::size_t> order;  ///< frames in the order on_scan saw them
};

/// With `read_ahead` unset and `by_hand`, each scan goes through integrateScan(points_L, T_W_L)
/// (the integrator estimates the rings; integrateDataset's reader does it otherwise).
Run integrate(const Dataset& dataset, const std::vector<std::size_t>& frames, bool read_ahead,
              bool by_hand = false) {
    VoxelMap map(0.1, 0.3f);
    AtsdfConfig config = plainAtsdfConfig();
    config.truncation.min_m = 0.1;
    config.truncation.max_m = 0.3;
    config.truncation.grazing_band_to_next_ring = true;
    config.merge_divisions = 1;
    AtsdfIntegrator integrator(map, config);
    REQUIRE(integrator.usesRings());
    Run run;
    if (by_hand) {
        for (std::size_t f : frames) {
            const PointCloud scan = dataset.loadScan(f);
            integrator.integrateScan(scan.points, dataset.frame(f).T_W_L);
            run.order.push_back(f);
        }
    } else {
        run.read = integrateDataset(
            dataset, integrator, frames, [&](std::size_t f) { run.order.push_back(f); }, read_ahead);
    }
    run.totals = integrator.totals();
    integrator.finalize();
    run.voxels = voxelsOf(map);
    return run;
}

}  // namespace

TEST_CASE("integrateDataset reads ahead into reused storage and maps as reading in turn does",
          "[tsdf][io]") {
    // Scans of different sizes, in an order that goes back and forth: a scan read into the
    // storage of a bigger one must not keep its tail, and the map must be the one of reading
    // each scan in turn, voxel for voxel.
    test::TempDir dir;
    const auto dataset = simStreet(dir / "street", 5, 30, 5, 25.0);
    REQUIRE(dataset->numFrames() == 5);
    const std::vector<std::size_t> frames{4, 0, 3, 1, 2, 0};
    std::size_t points = 0;
    for (std::size_t f : frames) points += dataset->loadScan(f).size();

    // One TBB thread: the read has a thread of its own; two: it is a task of theirs.
    const int threads = GENERATE(1, 2);
    INFO(threads << " TBB threads");
    tbb::task_arena arena(threads);
    Run ahead, in_turn, by_hand;
    arena.execute([&] {
        ahead = integrate(*dataset, frames, true);
        in_turn = integrate(*dataset, frames, false);
        by_hand = integrate(*dataset, frames, false, true);
    });
    CHECK(ahead.order == frames);
    CHECK(in_turn.order == frames);
    CHECK(ahead.totals.scans == frames.size());
    CHECK(ahead.totals.points_in == points);
    CHECK(in_turn.totals.points_in == points);
    CHECK(ahead.read.read.points_read == in_turn.read.read.points_read);
    CHECK(ahead.read.read.dropped_range == in_turn.read.read.dropped_range);
    CHECK(ahead.read.read.dropped_range > 0);  // max_range_m cut some points
    CHECK(ahead.totals.voxel_updates == in_turn.totals.voxel_updates);
    REQUIRE(ahead.voxels.size() > 10000);
    CHECK(ahead.voxels == in_turn.voxels);
    CHECK(ahead.voxels == by_hand.voxels);  // the reader's rings are the integrator's
}

TEST_CASE("integrateDataset rethrows a read error after the scans before it", "[tsdf][io]") {
    test::TempDir dir;
    const std::filesystem::path scan = dir / "street" / "velodyne" / "000001.bin";
    auto dataset = simStreet(dir / "street", 3, 20, 2, 200.0);
    REQUIRE(std::filesystem::exists(scan));
    std::filesystem::resize_file(scan, std::filesystem::file_size(scan) - 5);
    for (const int threads : {1, 2}) {
        tbb::task_arena arena(threads);
        for (const bool read_ahead : {true, false}) {
            INFO(threads << " TBB threads, read ahead " << read_ahead);
            VoxelMap map(0.1, 0.3f);
            AtsdfIntegrator integrator(map, plainAtsdfConfig());
            std::vector<std::size_t> seen;
            arena.execute([&] {
                CHECK_THROWS_AS(integrateDataset(
                                    *dataset, integrator, {0, 1, 2},
                                    [&](std::size_t f) { seen.push_back(f); }, read_ahead),
                                IoError);
            });
            CHECK(seen == std::vector<std::size_t>{0});
            // on_scan throwing while the failing read is in flight: its exception comes out
            // (the read's own error is dropped, not a second exception while unwinding).
            arena.execute([&] {
                CHECK_THROWS_WITH(integrateDataset(
                                      *dataset, integrator, {0, 1, 2},
                                      [](std::size_t) { throw std::runtime_error("tile writer failed"); },
                                      read_ahead),
                                  "tile writer failed");
            });
        }
    }
}
