// SPDX-License-Identifier: Apache-2.0
// The returns removed as moving, per frame (dynamic/MovingReturns.h): the store, and
// integrate.atsdf's removal step filling the context with exactly the points it drops, which
// the texture and semantic stages' scan occlusion reads (Context::movingReturns()).
#include <catch2/catch.hpp>

#include <filesystem>
#include <thread>

#include "pipeline/ContextBuilder.h"
#include "stages/DynamicRemovalStep.h"
#include "support/DynamicScene.h"
#include "vdbmap/dynamic/MovingReturns.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/pipeline/Context.h"
#include "vdbmap/pipeline/Report.h"

namespace fs = std::filesystem;
using namespace vdbmap;

TEST_CASE("MovingReturns keeps each frame's returns, replaces them, and reads while written",
          "[dynamic]") {
    MovingReturns m;
    CHECK(m.frame(3).empty());
    m.set(3, {Vec3f(1, 2, 3), Vec3f(4, 5, 6)});
    m.set(7, {Vec3f(0, 0, 1)});
    CHECK(m.size() == 3);
    REQUIRE(m.frame(3).size() == 2);
    CHECK(m.frame(3)[1] == Vec3f(4, 5, 6));
    m.set(3, {Vec3f(9, 9, 9)});
    CHECK(m.size() == 2);
    CHECK(m.frame(3) == std::vector<Vec3f>{Vec3f(9, 9, 9)});
    // integrate.atsdf writes in its read-ahead task while a streamed tile's stages read.
    std::thread writer([&] {
        for (std::size_t f = 100; f < 2100; ++f) m.set(f, std::vector<Vec3f>(f % 7, Vec3f(1, 1, 1)));
    });
    std::size_t seen = 0;
    for (std::size_t f = 100; f < 2100; ++f) {
        const std::vector<Vec3f> r = m.frame(f);
        CHECK((r.empty() || r.size() == f % 7));
        seen += r.size();
    }
    writer.join();
    std::size_t total = 2;
    for (std::size_t f = 100; f < 2100; ++f) total += f % 7;
    CHECK(m.size() == total);
    CHECK(seen <= total);
}

TEST_CASE("The removal step puts exactly the points it drops into the context, in W", "[dynamic]") {
    const test::DynamicSceneOptions scene;
    const fs::path dir = test::freshScratch("vdbmap_moving_returns_", "seq");
    std::vector<test::DynamicScan> scans;
    for (int f = 0; f < scene.frames; ++f) scans.push_back(test::dynamicScan(scene, f));
    test::writeDynamicDataset(dir, scans);
    const std::shared_ptr<Dataset> dataset = test::openDynamicDataset(dir);

    Report report;
    Context off_ctx(dir, report, true);
    ContextBuilder::setDataset(off_ctx, dataset);
    DynamicRemovalConfig off;
    off.enabled = false;
    detail::DynamicRemovalStep off_step(off_ctx, off);
    CHECK(off_ctx.movingReturns() == nullptr);

    Context ctx(dir, report, true);
    ContextBuilder::setDataset(ctx, dataset);
    detail::DynamicRemovalStep step(ctx, DynamicRemovalConfig{});
    REQUIRE(ctx.movingReturns() != nullptr);
    const ScanFilter filter = step.filter();
    std::size_t dropped_total = 0, on_mover = 0;
    for (int f = 0; f < scene.frames; ++f) {
        const std::size_t frame = static_cast<std::size_t>(f);
        PointCloud cloud;
        ScanReadStats stats;
        std::vector<std::uint32_t> index;
        dataset->loadScan(frame, cloud, &stats, &index);
        const std::size_t before = cloud.size();
        filter(frame, cloud, index, stats.points_read);
        const std::vector<Vec3f> moving = ctx.movingReturns()->frame(frame);
        CHECK(moving.size() == before - cloud.size());
        dropped_total += moving.size();
        const test::AxisBox b = test::moverBox(scene, f);
        for (const Vec3f& p : moving) {
            on_mover += p.x() > b.min.x() - 1e-3 && p.x() < b.max.x() + 1e-3 && p.y() > b.min.y() - 1e-3 &&
                        p.y() < b.max.y() + 1e-3 && p.z() > b.min.z() - 1e-3 && p.z() < b.max.z() + 1e-3;
        }
    }
    CHECK(dropped_total > 10000);
    CHECK(on_mover == dropped_total);  // in W, at the mover's place in its own frame
    CHECK(ctx.movingReturns()->size() == dropped_total);
}
