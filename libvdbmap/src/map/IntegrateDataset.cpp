// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/map/IntegrateDataset.h"

#include <tbb/global_control.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <future>
#include <numeric>
#include <utility>

#include "vdbmap/core/Timer.h"
#include "vdbmap/map/AtsdfIntegrator.h"

namespace vdbmap {

namespace {

struct LoadedScan {
    PointCloud cloud;
    std::vector<std::uint32_t> index;  ///< with a filter: each point's index in the file
    ScanReadStats stats;
    RingSpacing rings;  ///< estimated by the reader if the integrator uses them
};

/// The two filters of a scan: `filter` before its rings are estimated, `late` after.
struct Filters {
    const ScanFilter* filter = nullptr;
    const ScanFilter* late = nullptr;
    bool indexed() const { return (filter && *filter) || (late && *late); }
};

/// Scan i, read into `reuse`'s storage (the scan before last: no allocation per scan), and its
/// rings if `rings` (the reader's work rather than the integrating threads').
LoadedScan load(const Dataset& dataset, std::size_t i, bool rings, Filters filters,
                LoadedScan reuse) {
    reuse.stats = ScanReadStats{};
    if (filters.indexed()) {
        dataset.loadScan(i, reuse.cloud, &reuse.stats, &reuse.index);
        if (filters.filter && *filters.filter)
            (*filters.filter)(i, reuse.cloud, reuse.index, reuse.stats.points_read);
    } else {
        dataset.loadScan(i, reuse.cloud, &reuse.stats);
    }
    reuse.rings = rings ? RingSpacing::estimate(reuse.cloud.points) : RingSpacing{};
    // After the rings, so that the points it drops do not change them (`index` is as read).
    if (filters.late && *filters.late)
        (*filters.late)(i, reuse.cloud, reuse.index, reuse.stats.points_read);
    return reuse;
}

/// The read of the next scan while this one is integrated. With more than one integrating
/// thread it is one more task of theirs (tbb::task_group): a thread takes it when it runs out of
/// work, in the serial parts of a scan, and wait() runs it itself if none did. A thread of its
/// own (std::async) would preempt an integrating thread instead: on 2 threads the stage took
/// 3 % longer that way (docs/benchmarks/integration.md). With one integrating thread it does
/// get a thread of its own, so that reading still overlaps integration.
class ReadAhead {
public:
    ReadAhead(const Dataset& dataset, bool rings, Filters filters)
        : dataset_(dataset), rings_(rings), filters_(filters), as_task_(threads() > 1) {}
    /// A read still in flight here means the loop is unwinding from another exception (every
    /// read started is taken otherwise): wait for it, and drop its own error.
    ~ReadAhead() {
        if (!as_task_) return;  // std::future's destructor waits
        try {
            group_.wait();
        } catch (...) {
        }
    }
    ReadAhead(const ReadAhead&) = delete;
    ReadAhead& operator=(const ReadAhead&) = delete;

    /// Starts reading `frame` into `reuse`'s storage.
    void start(std::size_t frame, LoadedScan reuse) {
        if (as_task_) {
            slot_ = std::move(reuse);
            group_.run([this, frame] { slot_ = load(dataset_, frame, rings_, filters_, std::move(slot_)); });
        } else {
            thread_ = std::async(std::launch::async, load, std::cref(dataset_), frame, rings_, filters_,
                                 std::move(reuse));
        }
    }
    /// The scan started last; rethrows its read error.
    LoadedScan take() {
        if (!as_task_) return thread_.get();
        group_.wait();
        return std::move(slot_);
    }

private:
    /// The TBB threads that integrate: this arena's, within the process's limit (--threads).
    static std::size_t threads() {
        return std::min(static_cast<std::size_t>(tbb::this_task_arena::max_concurrency()),
                        tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
    }

    const Dataset& dataset_;
    const bool rings_;
    const Filters filters_;
    const bool as_task_;
    tbb::task_group group_;
    LoadedScan slot_;  ///< the task's scan
    std::future<LoadedScan> thread_;
};

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
    return integrateDataset(dataset, integrator, frames, on_scan, ScanFilter{}, read_ahead);
}

DatasetIntegration integrateDataset(const Dataset& dataset, AtsdfIntegrator& integrator,
                                    const std::vector<std::size_t>& frames,
                                    const std::function<void(std::size_t)>& on_scan,
                                    const ScanFilter& filter, bool read_ahead) {
    return integrateDataset(dataset, integrator, frames, on_scan, filter, ScanFilter{}, read_ahead);
}

DatasetIntegration integrateDataset(const Dataset& dataset, AtsdfIntegrator& integrator,
                                    const std::vector<std::size_t>& frames,
                                    const std::function<void(std::size_t)>& on_scan,
                                    const ScanFilter& filter, const ScanFilter& late_filter,
                                    bool read_ahead) {
    DatasetIntegration out;
    Timer total;
    const std::size_t n = frames.size();
    for (const std::size_t f : frames) (void)dataset.frame(f);  // out_of_range before reading
    const bool rings = integrator.usesRings();
    const Filters filters{&filter, &late_filter};
    ReadAhead next(dataset, rings, filters);
    if (read_ahead && n > 0) next.start(frames[0], LoadedScan{});
    LoadedScan scan;  // the scan being integrated
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t i = frames[k];
        if (read_ahead) {
            LoadedScan spare = std::move(scan);  // the last scan is done: the next read reuses it
            Timer wait;
            scan = next.take();
            out.read_wait_s += wait.elapsedSeconds();
            if (k + 1 < n) next.start(frames[k + 1], std::move(spare));
        } else {
            Timer wait;
            scan = load(dataset, i, rings, filters, std::move(scan));
            out.read_wait_s += wait.elapsedSeconds();
        }
        add(out.read, scan.stats);
        integrator.integrateScan(scan.cloud.points, dataset.frame(i).T_W_L, scan.rings);
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
