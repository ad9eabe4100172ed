// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/map/IntegrateDataset.h"

#include <future>
#include <numeric>
#include <utility>

#include "vdbmap/core/Timer.h"
#include "vdbmap/map/AtsdfIntegrator.h"

namespace vdbmap {

namespace {

struct LoadedScan {
    PointCloud cloud;
    ScanReadStats stats;
};

/// Scan i, read into `reuse`'s storage (the scan before last: no allocation per scan).
LoadedScan load(const Dataset& dataset, std::size_t i, LoadedScan reuse) {
    reuse.stats = ScanReadStats{};
    dataset.loadScan(i, reuse.cloud, &reuse.stats);
    return reuse;
}

void add(ScanReadStats& total, const ScanReadStats& s) {
    total.points_read += s.points_read;
    total.dropped_non_finite += s.dropped_non_finite;
    total.dropped_range += s.dropped_range;
}

}  // namespace

DatasetIntegration integrateDataset(const Dataset& dataset, AtsdfIntegrator& integrator,
                                    const std::vector<std::size_t>& frames,
                                    const std::function<void(std::size_t)>& on_scan,
                                    bool read_ahead) {
    DatasetIntegration out;
    Timer total;
    const std::size_t n = frames.size();
    for (const std::size_t f : frames) (void)dataset.frame(f);  // out_of_range before reading
    std::future<LoadedScan> next;
    if (read_ahead && n > 0)
        next = std::async(std::launch::async, load, std::cref(dataset), frames[0], LoadedScan{});
    LoadedScan scan;  // the scan being integrated
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t i = frames[k];
        if (read_ahead) {
            LoadedScan spare = std::move(scan);  // the last scan is done: the next read reuses it
            Timer wait;
            scan = next.get();
            out.read_wait_s += wait.elapsedSeconds();
            if (k + 1 < n)
                next = std::async(std::launch::async, load, std::cref(dataset), frames[k + 1], std::move(spare));
        } else {
            Timer wait;
            scan = load(dataset, i, std::move(scan));
            out.read_wait_s += wait.elapsedSeconds();
        }
        add(out.read, scan.stats);
        integrator.integrateScan(scan.cloud.points, dataset.frame(i).T_W_L);
        if (on_scan) {
            Timer callback;
            on_scan(i);
            out.on_scan_s += callback.elapsedSeconds();
        }
    }
    out.seconds = total.elapsedSeconds();
    return out;
}

DatasetIntegration integrateDataset(const Dataset& dataset, AtsdfIntegrator& integrator,
                                    const std::function<void()>& on_scan, bool read_ahead) {
    std::vector<std::size_t> frames(dataset.numFrames());
    std::iota(frames.begin(), frames.end(), std::size_t(0));
    return integrateDataset(
        dataset, integrator, frames,
        [&on_scan](std::size_t) {
            if (on_scan) on_scan();
        },
        read_ahead);
}

}  // namespace vdbmap
